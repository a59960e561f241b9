"""Compiled equations of motion of a rigid conical frustum rolling on its rim.

Everything here is dimensionless (the paper's Eq. 9): lengths in units of the
base radius R, time in units of sqrt(R/g), accelerations in units of g, forces
in units of m g, energies in units of m g R. The expressions are those derived
in :mod:`pipeline.dynamics.derivation`; ``tests/dynamics/test_derivation.py``
checks them against the symbolic result to round-off.

The state vector (length ``N_STATE``) is, in this order::

    phi, theta, psi, phi', theta', omega_zeta, x_p, y_p, work, dissipated,
    friction, slip_speed, slip_direction, z_c, v_x, v_y, v_z

with ``omega_zeta = phi' cos(theta) + psi'`` the spin (paper Eq. 3), ``x_p,
y_p`` the contact point on the plane (relative to the plane, which may move),
``work`` the work done on the column by the ground motion, ``dissipated``
the energy removed by the contact couples and ``friction`` the energy removed
by sliding. Rolling (this module) uses the first ten. The other phases of
:mod:`pipeline.dynamics.rigid` use the rest: the slip velocity (speed and
direction angle) of the base or of the rim point that slides, and in flight
the centre of mass (its horizontal position in the ``x_p, y_p`` slots, its
height and velocity).

Why the spin and not psi' as third speed: near small theta, phi' and psi'
grow like 1/theta^2 and nearly cancel in omega_zeta; in the paper's form of
theta'' (Eq. 12) the terms phi'^2 and phi' psi' cancel the same way and lose
digits. With omega_zeta the equations read (docs/model.md)::

    theta'' = [s (Iy-1) c + zc s) phi'^2 - (Iz s + zc c) phi' omega_zeta
               + (zc s - c)(1 + a_z) + (zc c + s) a_eta] / Iy
    omega_zeta' = [A omega_eta theta' + (Iz-1) zc omega_zeta theta' + A a_xi] / Delta
    phi'' = -(2 cot(theta) + zc (Iz-1)/Delta) phi' theta'
            + (Iz-1) (Iz omega_zeta theta' - zc a_xi) / (Delta sin(theta))

(s = sin theta, c = cos theta, omega_eta = phi' s): the spin equation is
regular at theta = 0 and no large terms cancel.

The column enters through a small constants array built by
:func:`column_constants`; the kernels never allocate.
"""

import math

import numpy as np
from numba import njit

from pipeline.dynamics.excitation import ground_acceleration

# State indices.
PHI, THETA, PSI, DPHI, DTHETA, OMEGA, XP, YP, WORK, DISSIPATED = range(10)
FRICTION, SLIP_SPEED, SLIP_DIR, ZC, VX, VY, VZ = range(10, 17)
N_STATE = 17

# Indices into the options array (the fourth element of ``params``): the
# contact transition tilt, the tilt at which the column lies down, the viscous
# contact couple, the friction coefficient, the phase being integrated, the
# pivot side and slip direction of planar rocking, the rolling resistance.
# Slipping phases also keep: whether the slip direction is slaved (see
# pipeline.dynamics.rigid.phases3d) and the precession angle when it was last set.
# OPT_UNILATERAL is 1 when the ground can only push (the column flies when
# the normal force would pull), 0 to hold the rim on the ground as the paper does.
# OPT_FRICTION_EXCESS [m g]: friction beyond mu N that a rolling phase started
# with because no slip could start from rest (pipeline.dynamics.rigid.run3d._enter_contact).
# OPT_SLAVED_SPEED [sqrt(g R)]: the slip speed at which the direction was last
# slaved; the layer is left above max(edge, 2 x it) (pipeline.dynamics.rigid.run3d).
# OPT_MAX_STEP [tau]: the longest step of the phase being integrated (inf but
# while a slip direction is slaved, so that its speed cannot cross the layer's
# edge and come back within one step unseen; pipeline.dynamics.rigid.run3d).
# OPT_RIM_HELD is 1 while the contact's equations and lift-off contradict each
# other (no contact the model allows: the rim would have to pull or to stick
# beyond mu N, yet the column in free flight would sink into the ground): the
# rim is held, rolling or slipping, until either stops (pipeline.dynamics.rigid.loop.holds_rim).
# The contact patch (pipeline.dynamics.rigid.patch): the tilt theta_k of lost full
# contact (0: a point contact, the paper's) and the dashpots per unit area,
# c_n R^3 / (m sqrt(g R)); whether the patch's drilling friction holds the
# pivot (no turning about the vertical through P) and, if not, the sense it
# turns in.
# OPT_LANDING_MARGIN, OPT_MIN_REBOUND, OPT_SLAVE_TIME, OPT_LOOK_AHEAD and
# OPT_SLAVED_TURN are the numerical thresholds of the rigid runs
# (declared with their defaults in pipeline.models.rigid.NUMERICS), carried at run time so that a study can vary
# them without recompiling.
(OPT_THETA_C, OPT_THETA_LIE, OPT_NU, OPT_MU, OPT_PHASE, OPT_PIVOT, OPT_SIGN, OPT_RIM_HELD,
 OPT_SLAVED, OPT_PHI_REF, OPT_UNILATERAL, OPT_THETA_K, OPT_PATCH_DAMPING, OPT_PIVOT_HELD,
 OPT_DRILL_SIGN, OPT_LANDING_MARGIN, OPT_MIN_REBOUND, OPT_SLAVE_TIME, OPT_LOOK_AHEAD,
 OPT_FRICTION_EXCESS, OPT_SLAVED_SPEED, OPT_MAX_STEP, OPT_SLAVED_TURN) = range(23)
N_OPT = 23

# Indices into the constants array.
C_IY, C_IZ, C_ZC, C_DELTA, C_K, C_IZ1, C_A = range(7)
N_CONST = 7


def column_constants(Iy, Iz, zc):
    """Pack the dimensionless inertia constants for the kernels.

    Parameters
    ----------
    Iy : float
        Transverse moment of inertia about the rim point, I_y^P / (m R^2) [1].
    Iz : float
        Axial moment of inertia about the rim point, I_z^P / (m R^2) [1].
    zc : float
        Height of the centre of mass over R, h_hat k1 / 2 [1].

    Returns
    -------
    numpy.ndarray
        Float64 array of length ``N_CONST``: Iy, Iz, zc, Delta, K, Iz - 1, A,
        where ``Delta = (Iy - 1) Iz - zc^2`` (a quarter of the paper's
        ``4 (I_y - 1) I_z - h^2 k1^2``; positive for every frustum),
        ``K = 2 Iy Iz - Iz^2 - Iz - 2 zc^2`` and ``A = Iy - 1 - zc^2`` (the
        central transverse inertia).
    """
    delta = (Iy - 1.0) * Iz - zc * zc
    if not delta > 0.0:
        raise ValueError(f"inertia constants give a singular mass matrix (Delta = {delta})")
    k = 2.0 * Iy * Iz - Iz * Iz - Iz - 2.0 * zc * zc
    return np.array([Iy, Iz, zc, delta, k, Iz - 1.0, Iy - 1.0 - zc * zc], dtype=np.float64)


@njit(cache=True)
def accelerations(theta, dphi, dtheta, omega, a_xi, a_eta, a_z, c):
    """Accelerations (phi'', theta'', omega_zeta') of rolling on the rim, theta != 0.

    Parameters
    ----------
    theta : float
        Inclination [rad], 0 < theta < pi/2.
    dphi, dtheta : float
        Precession and inclination rates [1/tau].
    omega : float
        Spin omega_zeta = phi' cos(theta) + psi' [1/tau].
    a_xi, a_eta : float
        Horizontal ground acceleration [g] along the line of nodes
        ``(cos phi, sin phi)`` and along ``(-sin phi, cos phi)``, the horizontal
        direction from the contact point to the centre of the base.
    a_z : float
        Vertical ground acceleration [g], positive upwards.
    c : numpy.ndarray
        Constants from :func:`column_constants`.

    Returns
    -------
    tuple of float
        phi'' [1/tau^2], theta'' [1/tau^2], omega_zeta' [1/tau^2]: the paper's
        Eq. 12 (with g23 and g34 corrected, docs/misprints.md) in the speeds
        (phi', theta', omega_zeta).
    """
    Iy = c[C_IY]
    Iz = c[C_IZ]
    zc = c[C_ZC]
    delta = c[C_DELTA]
    iz1 = c[C_IZ1]
    s = math.sin(theta)
    co = math.cos(theta)
    pt = dphi * dtheta
    if s != 0.0:
        csc = 1.0 / s
    elif pt == 0.0 and omega * dtheta == 0.0 and a_xi == 0.0:
        # Planar motion through full contact: every csc term is multiplied by
        # an exact zero, so its limit is zero (planar by construction).
        csc = 0.0
    else:
        csc = math.nan  # genuinely singular: out-of-plane motion at theta = 0
    lever = zc * co + s  # height of the centre of mass above P
    rest = zc * s - co  # minus its horizontal distance from P
    ddtheta = (
        s * ((Iy - 1.0) * co + zc * s) * dphi * dphi
        - (Iz * s + zc * co) * dphi * omega
        + rest * (1.0 + a_z)
        + lever * a_eta
    ) / Iy
    domega = (c[C_A] * (dphi * s * dtheta + a_xi) + iz1 * zc * omega * dtheta) / delta
    ddphi = -(2.0 * co * csc + zc * iz1 / delta) * pt + iz1 * (Iz * omega * dtheta - zc * a_xi) * csc / delta
    return ddphi, ddtheta, domega


@njit(cache=True)
def contact_force(theta, dphi, dtheta, omega, ddphi, ddtheta, domega, a_xi, a_eta, a_z, zc):
    """Contact force on the column at P, per m g.

    Returns
    -------
    tuple of float
        ``(F_xi, F_n, F_z)``: components along the line of nodes, along the
        horizontal direction from P towards the base centre, and vertical
        (the normal force N).
    """
    s = math.sin(theta)
    co = math.cos(theta)
    lever = zc * co + s
    rest = zc * s - co
    f_xi = a_xi - domega + zc * s * ddphi + dphi * dtheta * (2.0 * zc * co + s)
    f_n = a_eta - ddtheta * lever + zc * s * dphi * dphi + rest * dtheta * dtheta - dphi * omega
    f_z = 1.0 + a_z - ddtheta * rest - dtheta * dtheta * lever
    return f_xi, f_n, f_z


@njit(cache=True)
def energy(theta, dphi, dtheta, omega, c):
    """Total mechanical energy relative to the plane, E / (m g R) (paper Eq. 13).

    Evaluated in body components (its second form), which stay accurate when
    phi' is large; the potential energy is measured from the plane, V = Z_C / R.
    """
    Iy = c[C_IY]
    zc = c[C_ZC]
    s = math.sin(theta)
    w_eta = dphi * s
    kinetic = 0.5 * (Iy * dtheta * dtheta + (Iy - 1.0) * w_eta * w_eta + c[C_IZ] * omega * omega) - zc * w_eta * omega
    return kinetic + s + zc * math.cos(theta)


@njit(cache=True)
def ground_power(theta, dphi, dtheta, omega, a_xi, a_eta, a_z, zc):
    """Power delivered by the ground motion, P / (m g sqrt(g R)).

    In the plane's frame the ground acceleration acts as a uniform field
    ``-a_g``; its power on the centre of mass is ``-a_g . v_C``, and
    ``dE/dtau`` equals it along every solution.
    """
    s = math.sin(theta)
    co = math.cos(theta)
    return a_xi * (omega - zc * s * dphi) + (a_eta * (zc * co + s) - a_z * (co - zc * s)) * dtheta


@njit(cache=True)
def damping_accelerations(theta, dphi, dtheta, omega, nu, c):
    """Accelerations caused by a viscous contact couple ``M = -nu omega``.

    The optional dissipation model (docs/model.md): the contact transmits,
    besides the force, a couple opposing the body's angular velocity, a
    viscous form of the contact moment of Kessler and O'Reilly (2002) for a
    contact patch that is not a point. Its generalized forces
    ``(M.e_Z, M.e_xi, M.e_zeta)`` through the inverse mass matrix give

    * ``d theta'' = -nu theta' / Iy``
    * ``d phi'' = -nu (Iz omega_eta + zc omega_zeta) / (Delta sin theta)``
    * ``d omega_zeta' = -nu ((Iy - 1) omega_zeta + zc omega_eta) / Delta``

    Parameters
    ----------
    nu : float
        Couple per unit angular velocity, per (m g R sqrt(R/g)) [1].

    Returns
    -------
    tuple of float
        (d phi'', d theta'', d omega_zeta', dissipated power nu |omega|^2).
    """
    if nu == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    s = math.sin(theta)
    w_eta = dphi * s
    delta = c[C_DELTA]
    zc = c[C_ZC]
    ddtheta = -nu * dtheta / c[C_IY]
    ddphi = -nu * (c[C_IZ] * dphi + zc * omega / s) / delta if s != 0.0 else 0.0
    domega = -nu * ((c[C_IY] - 1.0) * omega + zc * w_eta) / delta
    power = nu * (dtheta * dtheta + w_eta * w_eta + omega * omega)
    return ddphi, ddtheta, domega, power


@njit(cache=True)
def couple_accelerations(theta, m_xi, m_eta, m_zeta, c):
    """Accelerations caused by a couple on the rolling body (any couple).

    The couple's generalized forces ``(M.e_Z, M.e_xi, M.e_zeta)`` through the
    inverse mass matrix of rolling (:func:`pipeline.dynamics.derivation.couple_accelerations`
    gives the viscous case, ``M = -nu omega``, from which these follow by
    linearity; ``tests/dynamics/test_derivation.py`` checks the general one).

    Parameters
    ----------
    theta : float
        Inclination [rad], != 0 unless ``m_eta = m_zeta = 0``.
    m_xi, m_eta, m_zeta : float
        The couple's body components [m g R].

    Returns
    -------
    tuple of float
        (d phi'', d theta'', d omega_zeta') [1/tau^2].
    """
    s = math.sin(theta)
    delta = c[C_DELTA]
    zc = c[C_ZC]
    ddtheta = m_xi / c[C_IY]
    top = c[C_IZ] * m_eta + zc * m_zeta
    ddphi = top / (delta * s) if s != 0.0 else (0.0 if top == 0.0 else math.nan)
    domega = ((c[C_IY] - 1.0) * m_zeta + zc * m_eta) / delta
    return ddphi, ddtheta, domega


_HALF_PI = 0.5 * math.pi


@njit(cache=True)
def sincos(phi):
    """(sin phi, cos phi), exact at multiples of pi/2.

    In floating point cos(pi/2) is 6e-17, not 0; through the csc(theta)
    terms such a residue would turn a planar motion into an out-of-plane one.
    Angles within 1e-14 (relative) of a multiple of pi/2 are snapped to it,
    so that planar motions stay planar by construction.
    """
    q = phi / _HALF_PI
    k = round(q)
    if abs(q - k) <= 1e-14 * max(1.0, abs(q)):
        m = int(k) % 4
        if m == 0:
            return 0.0, 1.0
        if m == 1:
            return 1.0, 0.0
        if m == 2:
            return 0.0, -1.0
        return -1.0, 0.0
    return math.sin(phi), math.cos(phi)


@njit(cache=True)
def rhs(t, y, params, dydt):
    """Right-hand side of the rolling phase, for the compiled integrator.

    Parameters
    ----------
    t : float
        Time [tau].
    y : numpy.ndarray
        State (see module docstring).
    params : tuple
        ``(c, record, dt, opts)``: constants from :func:`column_constants`,
        the ground acceleration record (n, 3) [g] (n may be 0 for free
        motion), its sampling interval [tau], and the options array
        (``OPT_THETA_C``, ``OPT_THETA_LIE``, ``OPT_NU``).
    dydt : numpy.ndarray
        Output, same layout as y.
    """
    c, record, dt, opts = params[0], params[1], params[2], params[3]
    ax, ay, az = ground_acceleration(t, record, dt)
    sp_, cp = sincos(y[PHI])
    a_xi = ax * cp + ay * sp_
    a_eta = -ax * sp_ + ay * cp
    theta = y[THETA]
    ddphi, ddtheta, domega = accelerations(theta, y[DPHI], y[DTHETA], y[OMEGA], a_xi, a_eta, az, c)
    d1, d2, d3, power = damping_accelerations(theta, y[DPHI], y[DTHETA], y[OMEGA], opts[OPT_NU], c)
    dpsi = y[OMEGA] - y[DPHI] * math.cos(theta)
    dydt[PHI] = y[DPHI]
    dydt[THETA] = y[DTHETA]
    dydt[PSI] = dpsi
    dydt[DPHI] = ddphi + d1
    dydt[DTHETA] = ddtheta + d2
    dydt[OMEGA] = domega + d3
    # Rolling without slip: the contact point moves along -xi at speed R psi'.
    dydt[XP] = -dpsi * cp
    dydt[YP] = -dpsi * sp_
    dydt[WORK] = ground_power(theta, y[DPHI], y[DTHETA], y[OMEGA], a_xi, a_eta, az, c[C_ZC])
    dydt[DISSIPATED] = power


@njit(cache=True)
def diagnostics(t, y, params, out):
    """Derived quantities at one state, written into ``out``.

    ``out`` receives: omega_zeta [1/tau], energy [m g R], normal force N
    [m g], tangential force |F_t| [m g], mobilized friction |F_t|/N [1],
    and the ground acceleration a_X, a_Y, a_Z [g].
    """
    c, record, dt, opts = params[0], params[1], params[2], params[3]
    ax, ay, az = ground_acceleration(t, record, dt)
    theta = y[THETA]
    sp_, cp = sincos(y[PHI])
    a_xi = ax * cp + ay * sp_
    a_eta = -ax * sp_ + ay * cp
    ddphi, ddtheta, domega = accelerations(theta, y[DPHI], y[DTHETA], y[OMEGA], a_xi, a_eta, az, c)
    d1, d2, d3, _power = damping_accelerations(theta, y[DPHI], y[DTHETA], y[OMEGA], opts[OPT_NU], c)
    ddphi += d1
    ddtheta += d2
    domega += d3
    f_xi, f_n, f_z = contact_force(
        theta, y[DPHI], y[DTHETA], y[OMEGA], ddphi, ddtheta, domega, a_xi, a_eta, az, c[C_ZC]
    )
    f_t = math.sqrt(f_xi * f_xi + f_n * f_n)
    out[0] = y[OMEGA]
    out[1] = energy(theta, y[DPHI], y[DTHETA], y[OMEGA], c)
    out[2] = f_z
    out[3] = f_t
    out[4] = f_t / f_z if f_z > 0.0 else math.inf
    out[5] = ax
    out[6] = ay
    out[7] = az


N_DIAGNOSTICS = 8
