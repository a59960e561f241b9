"""Classical two-dimensional rocking (Housner 1963) of the frustum's outline.

Kernel layer, dimensionless like :mod:`pipeline.dynamics.frustum`. The column
rocks in one vertical plane, the plane of a horizontal direction u, about one
of the two rim points of its base that lie in that plane. The signed angle
theta > 0 means it pivots on the rim point on the +u side (leaning towards
+u); theta < 0 the other one. With ``p^2 = zc_l / I_y`` (``zc_l`` the
distance pivot-centre of mass over R) this is Housner's
``theta'' = -p^2 [sin(alpha sgn(theta) - theta) (1 + a_z) + a_u cos(alpha sgn(theta) - theta)]``
written with the frustum's own inertia ``I_y`` about the rim.

State: ``theta, theta', work, dissipated`` (work done by the ground and
energy removed by the optional viscous contact couple, both [m g R]).
"""

import math

from numba import njit

from pipeline.dynamics import frustum as fk

THETA2, DTHETA2, WORK2, DISSIPATED2 = range(4)
N_STATE2 = 4


@njit(cache=True)
def angular_acceleration(theta, a_u, a_z, c):
    """theta'' of planar rocking [1/tau^2].

    Parameters
    ----------
    theta : float
        Signed inclination [rad].
    a_u : float
        Ground acceleration along u [g].
    a_z : float
        Vertical ground acceleration [g], upwards.
    c : numpy.ndarray
        Constants from :func:`pipeline.dynamics.frustum.column_constants`.
    """
    zc = c[fk.C_ZC]
    sgn = 1.0 if theta >= 0.0 else -1.0
    th = abs(theta)
    s = math.sin(th)
    co = math.cos(th)
    # gravity restores towards theta = 0; the inertial force -a_u pushes towards -u
    return (sgn * (zc * s - co) * (1.0 + a_z) - (zc * co + s) * a_u) / c[fk.C_IY]


@njit(cache=True)
def rhs(t, y, params, dydt):
    """Right-hand side for the compiled integrator.

    ``params = (c, record, dt, opts)`` as for the frustum, with
    ``record[:, 0]`` the acceleration along u [g] and ``record[:, 2]`` the
    vertical one (column 1 is unused), sampled at ``dt`` [tau].
    """
    c, record, dt, opts = params
    a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
    theta = y[THETA2]
    nu = opts[fk.OPT_NU]
    dydt[THETA2] = y[DTHETA2]
    dydt[DTHETA2] = angular_acceleration(theta, a_u, a_z, c) - nu * y[DTHETA2] / c[fk.C_IY]
    dydt[DISSIPATED2] = nu * y[DTHETA2] * y[DTHETA2]
    zc = c[fk.C_ZC]
    th = abs(theta)
    sgn = 1.0 if theta >= 0.0 else -1.0
    # power of the field -a_g on the centre of mass (horizontal and vertical
    # velocity of C for rotation theta' about the pivot)
    vx = (zc * math.cos(th) + math.sin(th)) * y[DTHETA2]
    vz = sgn * (math.cos(th) - zc * math.sin(th)) * y[DTHETA2]
    dydt[WORK2] = -a_u * vx - a_z * vz


@njit(cache=True)
def energy(theta, dtheta, c):
    """Mechanical energy per m g R relative to the base plane."""
    th = abs(theta)
    return 0.5 * c[fk.C_IY] * dtheta * dtheta + math.sin(th) + c[fk.C_ZC] * math.cos(th)
