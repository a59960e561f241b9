"""Test problems (right-hand sides and event functions) shared by the integrators' tests and
``benchmarks/bench_integrator.py``.

Not a test module (pytest collects ``test_*.py`` only); the benchmark puts this folder on
``sys.path`` to import it.
"""

import numpy as np
from numba import njit


@njit(cache=True)
def forced_pendulum(t, y, p, dydt):
    """Damped pendulum under a sampled horizontal base acceleration.

    p = (consts, acc): consts = [omega0^2 [1/s^2], 2 zeta omega0 [1/s], 1/L [1/m], dt [s]],
    acc = ground acceleration [m/s^2] sampled every dt from t = 0, linearly interpolated
    (as the physics will interpolate a record). y = [angle [rad], angular velocity [rad/s]].
    """
    consts, acc = p
    s = t / consts[3]
    i = int(s)
    if i >= acc.shape[0] - 1:
        a = acc[acc.shape[0] - 1]
    else:
        w = s - i
        a = (1.0 - w) * acc[i] + w * acc[i + 1]
    dydt[0] = y[1]
    dydt[1] = -consts[0] * np.sin(y[0]) - consts[1] * y[1] - consts[2] * a * np.cos(y[0])


@njit(cache=True)
def van_der_pol(t, y, p, dydt):
    """Van der Pol oscillator, p = [mu]."""
    dydt[0] = y[1]
    dydt[1] = p[0] * (1.0 - y[0] * y[0]) * y[1] - y[0]


@njit(cache=True)
def arenstorf(t, y, p, dydt):
    """Restricted three-body problem (Arenstorf orbit), y = [x, y, x', y'], p = [mu]."""
    mu = p[0]
    mup = 1.0 - mu
    d1 = ((y[0] + mu) ** 2 + y[1] ** 2) ** 1.5
    d2 = ((y[0] - mup) ** 2 + y[1] ** 2) ** 1.5
    dydt[0] = y[2]
    dydt[1] = y[3]
    dydt[2] = y[0] + 2.0 * y[3] - mup * (y[0] + mu) / d1 - mu * (y[0] - mup) / d2
    dydt[3] = y[1] - 2.0 * y[2] - mup * y[1] / d1 - mu * y[1] / d2


@njit(cache=True)
def oscillator(t, y, p, dydt):
    """x'' = -omega^2 x - f, p = [omega^2, f]: a harmonic oscillator, or with omega = 0 a
    falling ball (f = g)."""
    dydt[0] = y[1]
    dydt[1] = -p[0] * y[0] - p[1]


@njit(cache=True)
def oscillator_events(t, y, p, g):
    """g0 = position, g1 = velocity (only g0 when the caller asks for one event)."""
    g[0] = y[0]
    if g.shape[0] > 1:
        g[1] = y[1]
