"""Column geometry: a homogeneous rigid conical frustum.

A column of bottom radius R, top radius r and height h (the paper's Figure 1).
Every derived quantity follows the paper's definitions (Section 2.1-2.2) with
the misprint in its inertia tensor corrected (``docs/misprints.md``: the
parallel-axis term is ``k1^2 m h^2 / 4``, not ``k1 m h^2 / 4``).
"""

import math
from dataclasses import dataclass

from pipeline.errors import InputError
from pipeline.units import G


def _check_length(name, value):
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise InputError(f"column {name} = {value!r} is not a number; give it in metres") from None
    if not math.isfinite(value) or value <= 0.0:
        raise InputError(f"column {name} = {value!r} m must be a positive finite length in metres")
    return value


def k1_coefficient(beta):
    """k1 = 2 z_cm / h, the centre-of-mass height over half the height [1]."""
    return (3.0 * beta**2 + 2.0 * beta + 1.0) / (2.0 * (beta**2 + beta + 1.0))


def k2_coefficient(beta):
    """k2 of the paper (Section 2.2): central transverse inertia shape factor [1]."""
    return 0.45 * (beta**4 + 4.0 * beta**3 + 10.0 * beta**2 + 4.0 * beta + 1.0) / (beta**2 + beta + 1.0) ** 2


def k3_coefficient(beta):
    """k3 of the paper (Section 2.2): axial inertia shape factor, C = k3 m R^2 / 2 [1]."""
    return 0.6 * (beta**4 + beta**3 + beta**2 + beta + 1.0) / (beta**2 + beta + 1.0)


def transverse_inertia_hat(slenderness, beta):
    """I_y^P / (m R^2), transverse inertia about a rim point (the paper's I_x^P = I_y^P) [1].

    ``(k3 + 4)/4 + (k2 + 3 k1^2) (h/R)^2 / 12``: the parallel-axis term uses k1^2
    (docs/misprints.md). Works on floats and numpy arrays.
    """
    k1 = k1_coefficient(beta)
    return 0.25 * (k3_coefficient(beta) + 4.0) + (k2_coefficient(beta) + 3.0 * k1**2) * slenderness**2 / 12.0


def axial_inertia_hat(beta):
    """I_z^P / (m R^2) = C/(m R^2) + 1, axial inertia about a rim point [1]."""
    return 0.5 * (k3_coefficient(beta) + 2.0)


@dataclass(frozen=True)
class Column:
    """A free-standing column modelled as a homogeneous conical frustum.

    Parameters
    ----------
    R : float
        Radius of the base [m].
    r : float
        Radius of the top [m].
    h : float
        Height [m].
    density : float, optional
        Mass density [kg/m^3]; only needed for forces and energies in SI units.
    name : str, optional
        A label for outputs.
    """

    R: float
    r: float
    h: float
    density: float | None = None
    name: str = ""

    def __post_init__(self):
        for field in ("R", "r", "h"):
            object.__setattr__(self, field, _check_length(field, getattr(self, field)))
        if self.density is not None:
            d = self.density
            if not (isinstance(d, (int, float)) and math.isfinite(d) and d > 0):
                raise InputError(f"column density = {d!r} must be a positive number in kg/m^3")
            object.__setattr__(self, "density", float(d))

    # Shape ---------------------------------------------------------------
    @property
    def beta(self):
        """Conicity r/R [1]."""
        return self.r / self.R

    @property
    def slenderness(self):
        """h/R, the paper's h_hat [1]."""
        return self.h / self.R

    @property
    def k1(self):
        """2 z_cm / h [1]."""
        return k1_coefficient(self.beta)

    @property
    def k2(self):
        """Paper's k2 [1]."""
        return k2_coefficient(self.beta)

    @property
    def k3(self):
        """Paper's k3 [1]."""
        return k3_coefficient(self.beta)

    @property
    def z_cm(self):
        """Height of the centre of mass above the base [m]."""
        return 0.5 * self.k1 * self.h

    @property
    def volume(self):
        """Volume [m^3]."""
        return math.pi * self.h * (self.R**2 + self.R * self.r + self.r**2) / 3.0

    @property
    def mass(self):
        """Mass [kg]; needs a density."""
        if self.density is None:
            raise InputError("this column has no density: give one (kg/m^3) to get its mass")
        return self.density * self.volume

    # Inertia (dimensionless, per m R^2) -------------------------------------
    @property
    def inertia_transverse_hat(self):
        """I_y^P / (m R^2): transverse inertia about the rim point, principal directions [1].

        Equals A/(m R^2) + (z_cm/R)^2 + 1 with A the central transverse moment
        (the paper's I_x^P = I_y^P).
        """
        return transverse_inertia_hat(self.slenderness, self.beta)

    @property
    def inertia_axial_hat(self):
        """I_z^P / (m R^2) = C/(m R^2) + 1 [1]."""
        return axial_inertia_hat(self.beta)

    @property
    def central_inertia_hat(self):
        """(A, C) / (m R^2): central transverse and axial moments of inertia [1]."""
        zc = self.z_cm / self.R
        return self.inertia_transverse_hat - 1.0 - zc**2, self.inertia_axial_hat - 1.0

    @property
    def inertia_contact(self):
        """Inertia tensor about the contact point in (xi, eta, zeta) axes [kg m^2].

        Returns a 3x3 nested tuple; the off-diagonal eta-zeta term is
        ``-m R z_cm``. Needs a density.
        """
        m, R, z = self.mass, self.R, self.z_cm
        A, C = (v * m * R**2 for v in self.central_inertia_hat)
        return (
            (A + m * (R**2 + z**2), 0.0, 0.0),
            (0.0, A + m * z**2, -m * R * z),
            (0.0, -m * R * z, C + m * R**2),
        )

    # Statics ----------------------------------------------------------------
    @property
    def contact_to_cm_distance(self):
        """Distance from a rim point of the base to the centre of mass, the paper's l [m]."""
        return math.hypot(self.R, self.z_cm)

    @property
    def contact_to_cm_angle(self):
        """Angle of the line rim point -> centre of mass above the base plane, the paper's a [rad]."""
        return math.atan2(self.z_cm, self.R)

    @property
    def critical_tilt(self):
        """Static overturning inclination theta_crit = atan(R / z_cm) [rad].

        At this inclination the centre of mass is above the contact point.
        """
        return math.atan2(self.R, self.z_cm)

    def uplift_acceleration(self, vertical_acceleration=0.0):
        """Horizontal ground acceleration that tips the column off its full base [m/s^2].

        The column starts to pivot on its rim when the moment of the inertial
        force about the rim exceeds that of gravity:
        ``a_h z_cm = (g + a_z) R``.

        Parameters
        ----------
        vertical_acceleration : float
            Upward ground acceleration a_z [m/s^2].
        """
        return (G + vertical_acceleration) * self.R / self.z_cm

    def frequency_parameter(self):
        """Housner's p = sqrt(m g l / I_0) [rad/s] for planar rocking about a rim point."""
        return math.sqrt(G * self.contact_to_cm_distance / (self.inertia_transverse_hat * self.R**2))

    def kernel_constants(self):
        """Dimensionless constants for :mod:`pipeline.dynamics.rigid.frustum`."""
        from pipeline.dynamics.rigid.frustum import column_constants

        return column_constants(self.inertia_transverse_hat, self.inertia_axial_hat, self.z_cm / self.R)

    @classmethod
    def parse(cls, text, **kwargs):
        """Build a column from ``"R,r,h"`` (metres), as the command line gives it."""
        parts = [p.strip() for p in str(text).split(",")]
        if len(parts) != 3:
            raise InputError(f"--column {text!r}: give three lengths in metres as R,r,h (e.g. 0.5,0.4,4)")
        return cls(*parts, **kwargs)

    def describe(self):
        """A one-line human description."""
        label = f"{self.name}: " if self.name else ""
        return (
            f"{label}R = {self.R:g} m, r = {self.r:g} m, h = {self.h:g} m "
            f"(h/R = {self.slenderness:.3g}, beta = {self.beta:.3g}, "
            f"theta_crit = {math.degrees(self.critical_tilt):.2f} deg)"
        )
