"""The frustum on its rim when it slips, and in free flight (compiled, dimensionless).

Kernel layer, units of :mod:`pipeline.dynamics.rigid.frustum` (lengths per R, time per
sqrt(R/g), forces per m g). Rolling without slip (:func:`pipeline.dynamics.rigid.frustum.accelerations`)
ties the velocity of the centre of mass to the rotation; here it is free:

* **rim slip**: the lowest point P of the base rim stays on the plane (the
  height of the centre of mass is ``lever(theta) = zc cos(theta) + sin(theta)``),
  the material point at P slides with velocity ``v_s`` and the plane pushes
  with ``F = N (e_Z + f)``, ``f = -mu v_s / |v_s|`` (Coulomb). The normal force
  N follows from the height constraint in closed form.
* **flight**: no contact, ``F = 0``: the centre of mass falls in the field
  ``-a_g - g e_Z`` and the rotation is torque-free.

Both are the Newton-Euler equations of an axisymmetric body in the frame
``(xi, eta, zeta)`` of :mod:`pipeline.dynamics.derivation` (line of nodes,
tilted transverse axis, symmetry axis), which turns with
``Omega = phi' e_Z + theta' e_xi``; the body turns with ``omega = Omega + psi' e_zeta``.
``tests/dynamics/test_rim.py`` checks them against invariants (the power of the
contact force and of a couple, the angular momentum of flight, the symmetric
impulse response) and the material point's kinematics by finite differences;
``tests/dynamics/test_contact_physics.py`` against rolling (the friction that
rolling needs gives back the rolling accelerations at slip onset).

Horizontal vectors are given in the frame of the contact point: ``xi`` (line of
nodes, ``(cos phi, sin phi)``) and ``n`` (``(-sin phi, cos phi)``, from P
towards the centre of the base).
"""

import math

from numba import njit

from pipeline.dynamics.rigid import frustum as fk


@njit(cache=True)
def lever(theta, zc):
    """Height of the centre of mass above the lowest rim point [R]."""
    return zc * math.cos(theta) + math.sin(theta)


@njit(cache=True)
def reach(theta, zc):
    """Horizontal distance from the lowest rim point to the centre of mass, along n [R]."""
    return math.cos(theta) - zc * math.sin(theta)


@njit(cache=True)
def _cross(a1, a2, a3, b1, b2, b3):
    return a2 * b3 - a3 * b2, a3 * b1 - a1 * b3, a1 * b2 - a2 * b1


@njit(cache=True)
def _to_horizontal(u_eta, u_zeta, s, co):
    """(n, Z) components of a vector given by its eta and zeta components."""
    return u_eta * co - u_zeta * s, u_eta * s + u_zeta * co


@njit(cache=True)
def rotation_accelerations(theta, dphi, dtheta, omega, f_xi, f_n, normal, c, m_xi=0.0, m_eta=0.0, m_zeta=0.0):
    """Euler angle accelerations under a force at P (any N and friction) and a couple.

    Parameters
    ----------
    theta, dphi, dtheta, omega : float
        Inclination [rad], precession and inclination rates and spin [1/tau].
    f_xi, f_n : float
        Horizontal force of the plane per unit normal force, along xi and n [1].
    normal : float
        Normal force N [m g].
    c : numpy.ndarray
        Column constants (:func:`pipeline.dynamics.rigid.frustum.column_constants`).
    m_xi, m_eta, m_zeta : float
        A couple on the body, body components [m g R] (the contact patch's).

    Returns
    -------
    tuple of float
        ``(phi'', theta'', omega_zeta', omega_eta')`` [1/tau^2]; ``omega_eta'`` is
        the rate of the eta component in the turning frame.
    """
    A = c[fk.C_A]
    C = c[fk.C_IZ1]
    zc = c[fk.C_ZC]
    s = math.sin(theta)
    co = math.cos(theta)
    # the force of the plane in body components; its moment about C is
    # M = -r_PC x F with r_PC = (0, 1, zc): M_xi = zc F_eta - F_zeta,
    # M_eta = -zc F_xi, M_zeta = F_xi
    F_xi = normal * f_xi
    F_eta = normal * (f_n * co + s)
    F_zeta = normal * (-f_n * s + co)
    m_xi = zc * F_eta - F_zeta + m_xi
    m_eta = -zc * F_xi + m_eta
    w_eta = dphi * s
    # A theta'' + (Omega_eta C w_zeta - Omega_zeta A w_eta) = M_xi, ...
    ddtheta = (m_xi - w_eta * C * omega + dphi * co * A * w_eta) / A
    dw_eta = (m_eta - dphi * co * A * dtheta + dtheta * C * omega) / A
    domega = (F_xi + m_zeta) / C
    if s != 0.0:
        ddphi = (dw_eta - dphi * dtheta * co) / s
    elif dw_eta == 0.0 and dphi * dtheta == 0.0:
        ddphi = 0.0  # planar through theta = 0 (see frustum.accelerations)
    else:
        ddphi = math.nan
    return ddphi, ddtheta, domega, dw_eta


@njit(cache=True)
def slip_normal_force(theta, dphi, dtheta, omega, f_xi, f_n, a_z, c, m_xi=0.0):
    """Normal force [m g] while P slides with friction ``N (f_xi, f_n)`` (and a couple's m_xi).

    From the height constraint ``Z_C = lever(theta)``: ``N - 1 - a_z = Z_C''``
    with ``theta''`` linear in N. Returns ``(N, denominator)``; a denominator
    ``<= 0`` is Painleve's paradox (no consistent N), which no frustum with
    mu < 1 meets (docs/model.md).
    """
    A = c[fk.C_A]
    C = c[fk.C_IZ1]
    zc = c[fk.C_ZC]
    s = math.sin(theta)
    co = math.cos(theta)
    lv = zc * co + s
    dh = co - zc * s
    # theta'' = (N (f_n lv - dh) + G) / A
    G = dphi * dphi * s * co * A - dphi * s * C * omega + m_xi
    den = 1.0 + dh * (dh - f_n * lv) / A
    num = 1.0 + a_z + dh * G / A - lv * dtheta * dtheta
    return num / den, den


@njit(cache=True)
def material_point_acceleration(theta, dphi, dtheta, omega, ddtheta, dw_eta, domega, acc_xi, acc_n, acc_z, zc):
    """Rate of the velocity of the material point at P, in (xi, n, Z) [g].

    ``v_P = V_C + omega x r_CP`` with ``r_CP`` the vector from the centre of
    mass to the current contact point (fixed in the turning frame); its rate is
    ``A_C + omega_dot x r_CP + omega x (Omega x r_CP)``.

    Parameters
    ----------
    ddtheta, dw_eta, domega : float
        Frame-component rates of omega (:func:`rotation_accelerations`).
    acc_xi, acc_n, acc_z : float
        Acceleration of the centre of mass relative to the plane [g].
    """
    s = math.sin(theta)
    co = math.cos(theta)
    w1 = dtheta
    w2 = dphi * s
    w3 = omega
    # omega_dot (world) = frame rates + Omega x omega, Omega x omega = (w3 - phi' cos)(phi' s, -theta', 0)
    k = w3 - dphi * co
    al1 = ddtheta + k * dphi * s
    al2 = dw_eta - k * dtheta
    al3 = domega
    # alpha x r_CP with r_CP = (0, -1, -zc)
    u1, u2, u3 = -zc * al2 + al3, zc * al1, -al1
    # omega x (Omega x r_CP), Omega x r_CP = (phi' reach, zc theta', -theta')
    q1 = dphi * (co - zc * s)
    q2 = zc * dtheta
    q3 = -dtheta
    x1, x2, x3 = _cross(w1, w2, w3, q1, q2, q3)
    u1 += x1
    u2 += x2
    u3 += x3
    un, uz = _to_horizontal(u2, u3, s, co)
    return acc_xi + u1, acc_n + un, acc_z + uz


@njit(cache=True)
def cm_velocity_rolling(theta, dphi, dtheta, omega, zc):
    """Velocity of the centre of mass when P does not slip, ``omega x r_PC``, in (xi, n, Z)."""
    s = math.sin(theta)
    co = math.cos(theta)
    return dphi * s * zc - omega, -dtheta * (zc * co + s), dtheta * (co - zc * s)


@njit(cache=True)
def energy(theta, dphi, dtheta, omega, v_xi, v_n, v_z, height, c):
    """Mechanical energy [m g R] for any velocity of the centre of mass.

    Parameters
    ----------
    v_xi, v_n, v_z : float
        Velocity of the centre of mass relative to the plane, (xi, n, Z).
    height : float
        Height of the centre of mass above the plane [R].
    """
    w_eta = dphi * math.sin(theta)
    rot = c[fk.C_A] * (dtheta * dtheta + w_eta * w_eta) + c[fk.C_IZ1] * omega * omega
    return 0.5 * (v_xi * v_xi + v_n * v_n + v_z * v_z + rot) + height


@njit(cache=True)
def impulse_response(theta, j_xi, j_n, j_z, c):
    """Change of the velocity of the material point at P for an impulse J at P [sqrt(g R)].

    ``dv_P = J / m + (I_C^-1 (r_CP x J)) x r_CP``, all in (xi, n, Z).
    """
    A = c[fk.C_A]
    C = c[fk.C_IZ1]
    zc = c[fk.C_ZC]
    s = math.sin(theta)
    co = math.cos(theta)
    # J in body components
    jx = j_xi
    je = j_n * co + j_z * s
    jz = -j_n * s + j_z * co
    m1, m2, m3 = _cross(0.0, -1.0, -zc, jx, je, jz)  # r_CP x J
    d1, d2, d3 = m1 / A, m2 / A, m3 / C
    u1, u2, u3 = _cross(d1, d2, d3, 0.0, -1.0, -zc)
    un, uz = _to_horizontal(u2, u3, s, co)
    return j_xi + u1, j_n + un, j_z + uz


@njit(cache=True)
def apply_impulse(theta, dphi, dtheta, omega, j_xi, j_n, j_z, c):
    """Rates after an impulse J at P: ``(phi', theta', omega_zeta)`` and the change of V_C."""
    A = c[fk.C_A]
    C = c[fk.C_IZ1]
    zc = c[fk.C_ZC]
    s = math.sin(theta)
    co = math.cos(theta)
    je = j_n * co + j_z * s
    jz = -j_n * s + j_z * co
    m1, m2, m3 = _cross(0.0, -1.0, -zc, j_xi, je, jz)
    w_eta = dphi * s + m2 / A
    new_dtheta = dtheta + m1 / A
    new_omega = omega + m3 / C
    new_dphi = w_eta / s if s != 0.0 else (0.0 if w_eta == 0.0 else math.nan)
    return new_dphi, new_dtheta, new_omega


__all__ = [
    "lever",
    "reach",
    "rotation_accelerations",
    "slip_normal_force",
    "material_point_acceleration",
    "cm_velocity_rolling",
    "energy",
    "impulse_response",
    "apply_impulse",
]
