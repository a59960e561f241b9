"""The one place for units and physical constants.

Everything inside the package is SI (metres, seconds, kilograms, radians).
Degrees and fractions of g appear only at the edges (study files, the command
line, plots), converted there with ``math.radians``/``deg_to_rad`` and ``G``.
"""

import math

#: Standard acceleration of gravity [m/s^2] (CGPM 1901, exact).
G = 9.80665

#: Density of marble [kg/m^3], a typical value used when a column carries none.
MARBLE_DENSITY = 2700.0


def deg_to_rad(value_deg):
    """Convert degrees to radians (works on floats and numpy arrays)."""
    return value_deg * (math.pi / 180.0)


def time_scale(radius_m):
    """Time unit of the dimensionless equations, sqrt(R/g) [s].

    The paper's dimensionless time is tau = t * sqrt(g/R) (its Eq. 9), so
    t = tau * time_scale(R).
    """
    return math.sqrt(radius_m / G)
