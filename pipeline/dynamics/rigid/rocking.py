"""Classical two-dimensional rocking (Housner 1963) of the frustum's outline.

Kernel layer, dimensionless like :mod:`pipeline.dynamics.rigid.frustum`. The column
rocks in one vertical plane, the plane of a horizontal direction u, about one
of the two rim points of its base that lie in that plane. The signed angle
theta > 0 means it pivots on the rim point on the +u side (leaning towards
+u); theta < 0 the other one. With ``p^2 = zc_l / I_y`` (``zc_l`` the
distance pivot-centre of mass over R) this is Housner's
``theta'' = -p^2 [sin(alpha sgn(theta) - theta) (1 + a_z) + a_u cos(alpha sgn(theta) - theta)]``
written with the frustum's own inertia ``I_y`` about the rim.

State (``N_STATE2`` slots): ``theta, theta', work, dissipated, friction,
x, v, z, v_z``: the signed tilt and its rate, the work done by the ground, the
energy removed by the contact couples and by friction [m g R], and a position
and velocity along u whose meaning depends on the phase (the pivot and its slip
velocity on the rim, the base centre and its sliding velocity flat on the
ground, the centre of mass in flight, with its height ``z`` and vertical
velocity ``v_z``).

Besides rocking on a pivot that sticks (:func:`rhs`), the pivot may slip
(:func:`slip_accelerations`, Coulomb friction) and the column may fly
(:func:`flight_rhs`). In the pivot's frame the centre of mass sits at
``(C_u, C_z) = (-sgn cos(theta) + zc sin(theta), sin|theta| + zc cos(theta))``
and turns about the pivot with ``dC/dtheta = (C_z, -C_u)``.
"""

import math

from numba import njit

from pipeline.dynamics.rigid import frustum as fk

THETA2, DTHETA2, WORK2, DISSIPATED2, FRICTION2, X2, V2, Z2, VZ2 = range(9)
N_STATE2 = 9


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
        Constants from :func:`pipeline.dynamics.rigid.frustum.column_constants`.
    """
    zc = c[fk.C_ZC]
    sgn = math.copysign(1.0, theta)  # -0.0: pivot on the -u side
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
    c, record, dt, opts = params[0], params[1], params[2], params[3]
    a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
    theta = y[THETA2]
    nu = opts[fk.OPT_NU]
    dydt[THETA2] = y[DTHETA2]
    dydt[DTHETA2] = angular_acceleration(theta, a_u, a_z, c) - nu * y[DTHETA2] / c[fk.C_IY]
    dydt[DISSIPATED2] = nu * y[DTHETA2] * y[DTHETA2]
    zc = c[fk.C_ZC]
    th = abs(theta)
    sgn = math.copysign(1.0, theta)  # -0.0: pivot on the -u side
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


@njit(cache=True)
def cm_offset(theta, zc):
    """Centre of mass relative to the pivot, ``(C_u, C_z)`` [R], for signed theta."""
    sgn = math.copysign(1.0, theta)  # -0.0: pivot on the -u side
    th = abs(theta)
    return -sgn * math.cos(th) + zc * math.sin(theta), math.sin(th) + zc * math.cos(th)


@njit(cache=True)
def slip_accelerations(theta, dtheta, sigma, mu, a_u, a_z, c, couple=0.0):
    """Rocking on a pivot that slips in the direction ``sigma`` (+1 or -1) along u.

    Lagrange's equations in (x_P, theta) with the friction ``F_u = -mu sigma N``
    on x_P and ``N = Z_C'' + 1 + a_z``:
    ``theta'' (A + C_u^2 + mu sigma C_z C_u) = (C_u + mu sigma C_z)(1 + a_z - C_z theta'^2)``
    (A the central inertia; a denominator <= 0 would be Painleve's paradox);
    a ``couple`` [m g R] on theta adds to the right-hand side.

    Returns
    -------
    tuple of float
        ``(theta'', x_P'', N, denominator)``.
    """
    cu, cz = cm_offset(theta, c[fk.C_ZC])
    ms = mu * sigma
    den = c[fk.C_A] + cu * cu + ms * cz * cu
    w2 = dtheta * dtheta
    ddtheta = ((cu + ms * cz) * (1.0 + a_z - cz * w2) + couple) / den
    normal = 1.0 + a_z - cu * ddtheta - cz * w2
    ddx = -ms * normal - a_u - cz * ddtheta + cu * w2
    return ddtheta, ddx, normal, den


@njit(cache=True)
def cm_velocity(theta, dtheta, v_pivot, zc):
    """Velocity of the centre of mass ``(V_u, V_z)`` for a pivot moving at ``v_pivot``."""
    cu, cz = cm_offset(theta, zc)
    return v_pivot + cz * dtheta, -cu * dtheta


@njit(cache=True)
def energy_moving(theta, dtheta, v_u, v_z, height, c):
    """Mechanical energy [m g R] for a centre of mass moving at (v_u, v_z), at ``height``."""
    return 0.5 * (v_u * v_u + v_z * v_z + c[fk.C_A] * dtheta * dtheta) + height


@njit(cache=True)
def pivot_impulse_response(theta, j_u, j_z, c):
    """Change of the pivot's velocity for an impulse (j_u, j_z) applied there [sqrt(g R)].

    Returns ``(dv_u, dv_z, dtheta')``: the rotation changes by
    ``A dtheta' = C_u j_z - C_z j_u`` and the pivot moves with
    ``v_P = V_C - theta' (C_z, -C_u)``.
    """
    cu, cz = cm_offset(theta, c[fk.C_ZC])
    dw = (cu * j_z - cz * j_u) / c[fk.C_A]
    return j_u - dw * cz, j_z + dw * cu, dw
