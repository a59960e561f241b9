"""The three-dimensional frustum's phases: rolling, rim slip, flat sliding and flight (compiled).

Right-hand sides, event functions (``EV_*`` of
:mod:`pipeline.dynamics.rigid.layout`) and step monitor of the phase that
``OPT_PHASE`` of the options array names, as the compiled DOP853 integrates it
(:func:`integrate3d`); the contact patch's couples
(:mod:`pipeline.dynamics.rigid.patch`) in rolling and slip; the slip
direction, a state, or slaved to the consistent one in a thin layer at slow
slip (:func:`consistent_direction`, :func:`layer_edge`); the mechanical
energy of a state in each phase (:func:`energy3d`). What happens at the
events is :mod:`pipeline.dynamics.rigid.run3d`'s.
"""

import math

from numba import njit

from pipeline.dynamics.rigid import frustum as fk
from pipeline.dynamics.integrators.dop853 import dop853_monitored
from pipeline.dynamics.rigid import patch
from pipeline.dynamics.rigid import rim
from pipeline.dynamics.rigid.layout import (
    EVENT_DIRECTIONS, EV_LAND, EV_LIE, EV_LIFT, EV_MODE, EV_PIVOT, EV_SLIP, EV_STICK, EV_TURN, MAX_STEPS,
    PHASE_FLIGHT, PHASE_REST, PHASE_ROLLING, PHASE_SLIDING, PHASE_SLIPPING
)
from pipeline.dynamics.rigid.loop import watch_contact


_TWO_PI = 2.0 * math.pi


@njit(cache=True)
def _slip_friction(chi, sp_, cp, mu):
    """Friction per unit normal force (xi, n) opposing the slip direction chi, and (cos, sin) of chi."""
    sx, cx = fk.sincos(chi)
    s_xi = cx * cp + sx * sp_
    s_n = -cx * sp_ + sx * cp
    return -mu * s_xi, -mu * s_n, cx, sx


@njit(cache=True)
def horizontal_spin(theta, dphi, dtheta, omega):
    """Angular velocity in the contact point's frame: (xi, n) horizontal and vertical [1/tau]."""
    s = math.sin(theta)
    co = math.cos(theta)
    w_eta = dphi * s
    return dtheta, w_eta * co - omega * s, w_eta * s + omega * co


@njit(cache=True)
def rolling_state(t, y, params):
    """Accelerations and contact of rolling, with the contact patch's couples.

    Rolling on P (the paper's equations, the optional viscous couple nu), plus
    the patch of :mod:`pipeline.dynamics.rigid.patch` when ``theta_k > 0``: its
    dashpots' rolling damping, and drilling friction about the vertical through
    P, either holding the pivot (the couple that keeps omega_Z constant, while
    it stays below the patch's capacity mu N r_d) or sliding against the turning
    sense ``OPT_DRILL_SIGN`` with the full capacity.

    Returns
    -------
    tuple
        ``(ddphi, ddtheta, domega, f_xi, f_n, f_z, ax, ay, az, a_xi, a_n, damped, drill, capacity,
        omega_z)``: accelerations [1/tau^2], contact force [m g], ground
        acceleration [g] (plane and contact frames), the power of damping
        [m g sqrt(g R)], the drilling couple and its limit [m g R], the
        vertical angular velocity [1/tau].
    """
    c, record, dt, opts = params[0], params[1], params[2], params[3]
    ax, ay, az = fk.ground_acceleration(t, record, dt)
    sp_, cp = fk.sincos(y[fk.PHI])
    a_xi = ax * cp + ay * sp_
    a_n = -ax * sp_ + ay * cp
    theta, dphi, dtheta, omega = y[fk.THETA], y[fk.DPHI], y[fk.DTHETA], y[fk.OMEGA]
    zc = c[fk.C_ZC]
    ddphi, ddtheta, domega = fk.accelerations(theta, dphi, dtheta, omega, a_xi, a_n, az, c)
    d1, d2, d3, damped = fk.damping_accelerations(theta, dphi, dtheta, omega, opts[fk.OPT_NU], c)
    ddphi += d1
    ddtheta += d2
    domega += d3
    om_xi, om_n, om_z = horizontal_spin(theta, dphi, dtheta, omega)
    drill = 0.0
    capacity = 0.0
    theta_k = opts[fk.OPT_THETA_K]
    if theta_k > 0.0:
        # _patch_load, from the accelerations at hand (the same arithmetic, so the same bits)
        f_z = fk.contact_force(theta, dphi, dtheta, omega, ddphi, ddtheta, domega, a_xi, a_n, az, zc)[2]
        m_xi, m_n, capacity = patch.couples(f_z, theta, theta_k, opts[fk.OPT_PATCH_DAMPING], opts[fk.OPT_MU],
                                            om_xi, om_n)
        s = math.sin(theta)
        co = math.cos(theta)
        e1, e2, e3 = fk.couple_accelerations(theta, m_xi, m_n * co, -m_n * s, c)
        ddphi += e1
        ddtheta += e2
        domega += e3
        damped -= m_xi * om_xi + m_n * om_n
        # a couple T about the vertical: body components (0, T s, T cos)
        b1, _b2, b3 = fk.couple_accelerations(theta, 0.0, s, co, c)
        if opts[fk.OPT_PIVOT_HELD] != 0.0:
            # keep omega_Z = phi' s^2 + omega cos: its rate without T, over its rate per unit T
            free = ddphi * s * s + domega * co + dtheta * (2.0 * dphi * s * co - omega * s)
            drill = -free / (b1 * s * s + b3 * co)
        else:
            drill = -capacity * opts[fk.OPT_DRILL_SIGN]
        ddphi += drill * b1
        domega += drill * b3
    f_xi, f_n, f_z = fk.contact_force(theta, dphi, dtheta, omega, ddphi, ddtheta, domega, a_xi, a_n, az, zc)
    return ddphi, ddtheta, domega, f_xi, f_n, f_z, ax, ay, az, a_xi, a_n, damped, drill, capacity, om_z


@njit(cache=True)
def _patch_load(theta, dphi, dtheta, omega, a_xi, a_n, az, opts, c):
    """Normal force that sizes the contact patch [m g]: rolling's at this state, without the patch's couples.

    The same in every phase (rolling, slipping): the patch's couples are then
    a function of the state alone, and a switch of phase does not jump them, so
    that the slip equations at onset continue the rolling ones exactly. While P
    slides the actual N differs (the friction is mu N, not what rolling asks);
    the patch's size follows the rolling value, the couples' cap and the
    sliding drilling capacity too. A couple about the line of nodes would
    change it by a part in J / I_y.
    """
    ddphi, ddtheta, domega = fk.accelerations(theta, dphi, dtheta, omega, a_xi, a_n, az, c)
    d1, d2, d3, _damped = fk.damping_accelerations(theta, dphi, dtheta, omega, opts[fk.OPT_NU], c)
    return fk.contact_force(theta, dphi, dtheta, omega, ddphi + d1, ddtheta + d2, domega + d3, a_xi, a_n, az,
                            c[fk.C_ZC])[2]


@njit(cache=True)
def rolling_contact(t, y, params):
    """Contact force of rolling (xi, n, N) [m g] and the ground acceleration [g]."""
    r = rolling_state(t, y, params)
    return r[3], r[4], r[5], r[6], r[7], r[8]


@njit(cache=True)
def _slip_patch(y, params, theta, a_xi, a_n, az):
    """Couples of the contact while P slides (body components), their power and the drilling capacity.

    The patch's rolling damping and the optional viscous couple ``-nu omega``
    (rolling has both, :func:`rolling_state`; so slip must, or the two sets of
    equations would differ at slip onset). Returns ``(m_xi, m_eta, m_zeta,
    damped, capacity)``: the couple [m g R], the power it removes
    [m g sqrt(g R)] and the largest drilling couple ``mu N r_d`` [m g R]
    (:func:`pipeline.dynamics.rigid.patch.couples`).
    """
    c, opts = params[0], params[3]
    dphi, dtheta, omega = y[fk.DPHI], y[fk.DTHETA], y[fk.OMEGA]
    s = math.sin(theta)
    co = math.cos(theta)
    # the viscous couple; body angular velocity (theta', phi' sin theta, omega)
    nu = opts[fk.OPT_NU]
    w_eta = dphi * s
    m_xi, m_eta, m_zeta = -nu * dtheta, -nu * w_eta, -nu * omega
    damped = nu * (dtheta * dtheta + w_eta * w_eta + omega * omega)
    theta_k = opts[fk.OPT_THETA_K]
    if theta_k <= 0.0:
        return m_xi, m_eta, m_zeta, damped, 0.0
    load = _patch_load(theta, dphi, dtheta, omega, a_xi, a_n, az, opts, c)
    om_xi, om_n, _om_z = horizontal_spin(theta, dphi, dtheta, omega)
    p_xi, p_n, capacity = patch.couples(load, theta, theta_k, opts[fk.OPT_PATCH_DAMPING], opts[fk.OPT_MU],
                                        om_xi, om_n)
    return (m_xi + p_xi, m_eta + p_n * co, m_zeta - p_n * s, damped - (p_xi * om_xi + p_n * om_n), capacity)


@njit(cache=True)
def _slip_drill(opts, theta, dphi, dtheta, omega, ddphi, domega, capacity, c):
    """Drilling couple of the patch about the vertical through a sliding P [m g R].

    The patch's friction limit is the same in every phase: a tangential force
    up to mu N and, independently, a drilling couple up to ``mu N r_d``
    (:func:`rolling_state`). So a pivot held while rolling stays held when P
    starts to slide, and the slip starts with the rolling accelerations (the
    two sets of equations agree at slip onset). Held: the couple that keeps
    omega_Z; turning: the capacity against the turning sense. A vertical
    couple T on the free body (P's force given) changes phi'' by T / A,
    omega' by T cos(theta) / C and leaves theta'' and N alone.
    """
    if opts[fk.OPT_THETA_K] <= 0.0:
        return 0.0
    if opts[fk.OPT_PIVOT_HELD] == 0.0:
        return -capacity * opts[fk.OPT_DRILL_SIGN]
    s = math.sin(theta)
    co = math.cos(theta)
    free = ddphi * s * s + domega * co + dtheta * (2.0 * dphi * s * co - omega * s)
    return -free / (s * s / c[fk.C_A] + co * co / c[fk.C_IZ1])


@njit(cache=True)
def slip_setting(t, y, params):
    """What the slip equations at (t, y) share for every slip direction: the ground and the patch.

    Returns ``(ax, ay, az, sp_, cp, a_xi, a_n, m_xi, m_eta, m_zeta, damped, capacity)``: the
    ground acceleration [g] (plane and contact frames), sin and cos of phi, and the patch's
    couple, power and drilling limit (:func:`_slip_patch`). The search for a consistent
    direction evaluates the equations at many directions: computed once for all of them.
    """
    ax, ay, az = fk.ground_acceleration(t, params[1], params[2])
    sp_, cp = fk.sincos(y[fk.PHI])
    a_xi = ax * cp + ay * sp_
    a_n = -ax * sp_ + ay * cp
    m_xi, m_eta, m_zeta, damped, capacity = _slip_patch(y, params, y[fk.THETA], a_xi, a_n, az)
    return ax, ay, az, sp_, cp, a_xi, a_n, m_xi, m_eta, m_zeta, damped, capacity


@njit(cache=True)
def slip_with(t, y, params, chi):
    """:func:`_slip_in` with its setting computed here."""
    return _slip_in(t, y, params, chi, slip_setting(t, y, params))


@njit(cache=True)
def _slip_in(t, y, params, chi, setting):
    """Normal force and accelerations of rim slip in the direction chi (``setting``: :func:`slip_setting`).

    Returns ``(N, den, ddphi, ddtheta, domega, dw_eta, f_xi, f_n, cx, sx, ax, ay, az, a_xi, a_n,
    vx, vy, damped, drill, capacity, omega_z)`` with ``(vx, vy)`` the rate of the slip velocity
    (horizontal, plane frame), ``damped`` the power of the patch's rolling damping, the drilling
    couple and its limit [m g R] and the vertical angular velocity [1/tau].
    """
    c, opts = params[0], params[3]
    ax, ay, az, sp_, cp, a_xi, a_n, m_xi, m_eta, m_zeta, damped, capacity = setting
    f_xi, f_n, cx, sx = _slip_friction(chi, sp_, cp, opts[fk.OPT_MU])
    theta, dphi, dtheta, omega = y[fk.THETA], y[fk.DPHI], y[fk.DTHETA], y[fk.OMEGA]
    normal, den = rim.slip_normal_force(theta, dphi, dtheta, omega, f_xi, f_n, az, c, m_xi)
    ddphi, ddtheta, domega, dw_eta = rim.rotation_accelerations(theta, dphi, dtheta, omega, f_xi, f_n, normal, c,
                                                                m_xi, m_eta, m_zeta)
    drill = _slip_drill(opts, theta, dphi, dtheta, omega, ddphi, domega, capacity, c)
    s = math.sin(theta)
    co = math.cos(theta)
    ddphi += drill / c[fk.C_A]
    domega += drill * co / c[fk.C_IZ1]
    dw_eta += drill * s / c[fk.C_A]
    v_xi, v_n, _v_z = rim.material_point_acceleration(
        theta, dphi, dtheta, omega, ddtheta, dw_eta, domega,
        normal * f_xi - a_xi, normal * f_n - a_n, normal - 1.0 - az, c[fk.C_ZC])
    vx = v_xi * cp - v_n * sp_
    vy = v_xi * sp_ + v_n * cp
    om_z = dphi * s * s + omega * co
    return (normal, den, ddphi, ddtheta, domega, dw_eta, f_xi, f_n, cx, sx, ax, ay, az, a_xi, a_n, vx, vy, damped,
            drill, capacity, om_z)


@njit(cache=True)
def _misalignment(t, y, params, chi, setting):
    """Component of the slip acceleration across the slip direction chi (zero when consistent)."""
    r = _slip_in(t, y, params, chi, setting)
    return -r[15] * r[9] + r[16] * r[8]


@njit(cache=True)
def along_slip(t, y, params, chi, setting):
    """Component of the slip acceleration along the slip direction chi."""
    r = _slip_in(t, y, params, chi, setting)
    return r[15] * r[8] + r[16] * r[9]


@njit(cache=True)
def consistent_direction(t, y, params, guess, starting=False):
    """Slip direction chi* in which the slip acceleration lies along the slip.

    The root of the misalignment closest to ``guess`` among those where the
    direction is stable (misalignment decreasing in chi: a nearby direction
    turns towards it). Found by a scan of the circle and bisection.
    ``starting`` (a slip from rest, speed 0): only roots where the slip
    accelerates along chi count (an antiparallel root would drive the speed
    below 0, where no event can see it), unless there is none.
    """
    setting = slip_setting(t, y, params)
    if (_misalignment(t, y, params, guess, setting) == 0.0
            and not (starting and along_slip(t, y, params, guess, setting) < 0.0)):
        return guess  # exactly consistent (planar motion stays planar)
    best_any = guess
    gap_any = math.inf
    n_scan = 16
    best = guess
    best_gap = math.inf
    a = guess - math.pi
    fa = _misalignment(t, y, params, a, setting)
    for k in range(1, n_scan + 1):
        b = guess - math.pi + _TWO_PI * k / n_scan
        fb = _misalignment(t, y, params, b, setting)
        if fa > 0.0 and fb <= 0.0:
            lo, hi, flo = a, b, fa
            for _i in range(60):
                mid = 0.5 * (lo + hi)
                fm = _misalignment(t, y, params, mid, setting)
                if (fm > 0.0) == (flo > 0.0):
                    lo, flo = mid, fm
                else:
                    hi = mid
                if hi - lo < 1e-13:
                    break
            root = 0.5 * (lo + hi)
            gap = abs(root - guess)
            if gap < gap_any:
                best_any, gap_any = root, gap
            if gap < best_gap and not (starting and along_slip(t, y, params, root, setting) < 0.0):
                best, best_gap = root, gap
        a, fa = b, fb
    return best if best_gap < math.inf else best_any


@njit(cache=True)
def slip_direction(t, y, params):
    """The slip direction in use: the state's, or the slaved consistent one."""
    opts = params[3]
    if opts[fk.OPT_SLAVED] == 0.0:
        return y[fk.SLIP_DIR]
    guess = y[fk.SLIP_DIR] + (y[fk.PHI] - opts[fk.OPT_PHI_REF])
    return consistent_direction(t, y, params, guess, y[fk.SLIP_SPEED] <= 0.0)


@njit(cache=True)
def slip_state(t, y, params):
    """:func:`slip_with` in the direction in use."""
    return slip_with(t, y, params, slip_direction(t, y, params))


@njit(cache=True)
def flat_direction(t, y, params):
    """Direction of flat sliding: the state's, or slaved, against the ground's push."""
    if params[3][fk.OPT_SLAVED] == 0.0:
        return y[fk.SLIP_DIR]
    ax, ay, _az = fk.ground_acceleration(t, params[1], params[2])
    if ax == 0.0 and ay == 0.0:
        return y[fk.SLIP_DIR]
    return math.atan2(-ay, -ax)


@njit(cache=True)
def rhs_slipping(t, y, params, dydt):
    c, opts = params[0], params[3]
    zc = c[fk.C_ZC]
    mu = opts[fk.OPT_MU]
    (normal, den, ddphi, ddtheta, domega, dw_eta, f_xi, f_n, cx, sx, ax, ay, az, a_xi, a_n,
     vx, vy, damped, drill, _cap, om_z) = slip_state(t, y, params)
    theta = y[fk.THETA]
    dphi, dtheta, omega = y[fk.DPHI], y[fk.DTHETA], y[fk.OMEGA]
    speed = y[fk.SLIP_SPEED]
    sp_, cp = fk.sincos(y[fk.PHI])
    dpsi = omega - dphi * math.cos(theta)
    for i in range(dydt.shape[0]):
        dydt[i] = 0.0
    dydt[fk.PHI] = dphi
    dydt[fk.THETA] = dtheta
    dydt[fk.PSI] = dpsi
    dydt[fk.DPHI] = ddphi
    dydt[fk.DTHETA] = ddtheta
    dydt[fk.OMEGA] = domega
    dydt[fk.XP] = speed * cx - dpsi * cp
    dydt[fk.YP] = speed * sx - dpsi * sp_
    dydt[fk.SLIP_SPEED] = vx * cx + vy * sx
    if opts[fk.OPT_SLAVED] == 0.0 and speed > 0.0:
        dydt[fk.SLIP_DIR] = (-vx * sx + vy * cx) / speed
    # velocity of the centre of mass: slip of P plus rotation about P
    r_xi, r_n, r_z = rim.cm_velocity_rolling(theta, dphi, dtheta, omega, zc)
    s_xi = -f_xi / mu if mu > 0.0 else 0.0
    s_n = -f_n / mu if mu > 0.0 else 0.0
    dydt[fk.WORK] = -(a_xi * (r_xi + speed * s_xi) + a_n * (r_n + speed * s_n) + az * r_z)
    dydt[fk.FRICTION] = mu * normal * speed - drill * om_z  # sliding and drilling friction
    dydt[fk.DISSIPATED] = damped


@njit(cache=True)
def _rhs_flight(t, y, params, dydt):
    c, record, dt = params[0], params[1], params[2]
    ax, ay, az = fk.ground_acceleration(t, record, dt)
    theta = y[fk.THETA]
    dphi, dtheta, omega = y[fk.DPHI], y[fk.DTHETA], y[fk.OMEGA]
    ddphi, ddtheta, domega, _dw = rim.rotation_accelerations(theta, dphi, dtheta, omega, 0.0, 0.0, 0.0, c)
    for i in range(dydt.shape[0]):
        dydt[i] = 0.0
    dydt[fk.PHI] = dphi
    dydt[fk.THETA] = dtheta
    dydt[fk.PSI] = omega - dphi * math.cos(theta)
    dydt[fk.DPHI] = ddphi
    dydt[fk.DTHETA] = ddtheta
    dydt[fk.OMEGA] = domega
    dydt[fk.XP] = y[fk.VX]
    dydt[fk.YP] = y[fk.VY]
    dydt[fk.ZC] = y[fk.VZ]
    dydt[fk.VX] = -ax
    dydt[fk.VY] = -ay
    dydt[fk.VZ] = -1.0 - az
    dydt[fk.WORK] = -(ax * y[fk.VX] + ay * y[fk.VY] + az * y[fk.VZ])


@njit(cache=True)
def rhs_sliding(t, y, params, dydt):
    record, dt, opts = params[1], params[2], params[3]
    ax, ay, az = fk.ground_acceleration(t, record, dt)
    mu = opts[fk.OPT_MU]
    speed = y[fk.SLIP_SPEED]
    chi = flat_direction(t, y, params)
    cx = math.cos(chi)
    sx = math.sin(chi)
    for i in range(dydt.shape[0]):
        dydt[i] = 0.0
    along = ax * cx + ay * sx
    dydt[fk.SLIP_SPEED] = -along - mu * (1.0 + az)
    if opts[fk.OPT_SLAVED] == 0.0 and speed > 0.0:
        dydt[fk.SLIP_DIR] = (ax * sx - ay * cx) / speed
    dydt[fk.XP] = speed * cx
    dydt[fk.YP] = speed * sx
    dydt[fk.WORK] = -along * speed
    dydt[fk.FRICTION] = mu * (1.0 + az) * speed


@njit(cache=True)
def rhs_rolling(t, y, params, dydt):
    (ddphi, ddtheta, domega, _f_xi, _f_n, _f_z, _ax, _ay, az, a_xi, a_n, damped, drill, _cap,
     om_z) = rolling_state(t, y, params)
    theta, dphi, omega = y[fk.THETA], y[fk.DPHI], y[fk.OMEGA]
    sp_, cp = fk.sincos(y[fk.PHI])
    dpsi = omega - dphi * math.cos(theta)
    for i in range(dydt.shape[0]):
        dydt[i] = 0.0
    dydt[fk.PHI] = dphi
    dydt[fk.THETA] = y[fk.DTHETA]
    dydt[fk.PSI] = dpsi
    dydt[fk.DPHI] = ddphi
    dydt[fk.DTHETA] = ddtheta
    dydt[fk.OMEGA] = domega
    # rolling without slip: the contact point moves along -xi at speed R psi'
    dydt[fk.XP] = -dpsi * cp
    dydt[fk.YP] = -dpsi * sp_
    dydt[fk.WORK] = fk.ground_power(theta, dphi, y[fk.DTHETA], omega, a_xi, a_n, az, params[0][fk.C_ZC])
    dydt[fk.DISSIPATED] = damped
    dydt[fk.FRICTION] = -drill * om_z  # the drilling couple's work (0 while it holds the pivot)


@njit(cache=True)
def rhs3d(t, y, params, dydt):
    """Right-hand side of the phase ``params[3][OPT_PHASE]`` (3D frustum)."""
    phase = params[3][fk.OPT_PHASE]
    if phase == PHASE_ROLLING:
        rhs_rolling(t, y, params, dydt)
    elif phase == PHASE_SLIPPING:
        rhs_slipping(t, y, params, dydt)
    elif phase == PHASE_FLIGHT:
        _rhs_flight(t, y, params, dydt)
    else:
        rhs_sliding(t, y, params, dydt)


@njit(cache=True)
def events3d(t, y, params, g):
    """Event functions of the current phase (``EV_*``); +1 where an event does not apply."""
    c, record, dt, opts = params[0], params[1], params[2], params[3]
    phase = opts[fk.OPT_PHASE]
    for i in range(g.shape[0]):
        g[i] = 1.0
    if phase == PHASE_SLIDING:
        _ax, _ay, az = fk.ground_acceleration(t, record, dt)
        g[EV_LIFT] = 1.0 + az
        g[EV_STICK] = y[fk.SLIP_SPEED]
        g[EV_MODE] = _layer_event(y, opts, 1.0 + az)
        return
    theta = y[fk.THETA]
    g[EV_LIE] = theta - opts[fk.OPT_THETA_LIE]
    g[EV_TURN] = y[fk.DTHETA]
    if phase == PHASE_FLIGHT:
        g[EV_LAND] = y[fk.ZC] - rim.lever(theta, c[fk.C_ZC])
        g[EV_SLIP] = theta  # the axis passes the vertical (planar flight): Euler angles flip
        return
    g[EV_LAND] = theta - (1.0 - opts[fk.OPT_LANDING_MARGIN]) * opts[fk.OPT_THETA_C]
    held = opts[fk.OPT_RIM_HELD] != 0.0  # (loop.holds_rim)
    if phase == PHASE_ROLLING:
        r = rolling_state(t, y, params)
        f_xi, f_n, f_z = r[3], r[4], r[5]
        if held:
            # falls through 0 when a contact the model allows exists again (N pushes, for
            # mu = inf) or the flight would rise; no slip event while held
            contact = f_z
            if opts[fk.OPT_MU] < math.inf:
                stick, slip = _contact_margins(t, y, params, f_xi, f_n, f_z)
                contact = max(stick, slip)
            g[EV_LIFT] = min(-contact, -flight_gap_acceleration(theta, y[fk.DPHI], y[fk.DTHETA], y[fk.OMEGA],
                                                               r[8], c))
        elif opts[fk.OPT_UNILATERAL] != 0.0:
            g[EV_LIFT] = f_z
        if opts[fk.OPT_MU] < math.inf:  # inf: rolling without slip, whatever the force
            if not held:
                g[EV_SLIP] = (opts[fk.OPT_MU] * f_z - math.sqrt(f_xi * f_xi + f_n * f_n)
                              + opts[fk.OPT_FRICTION_EXCESS])
            if opts[fk.OPT_THETA_K] > 0.0:
                g[EV_PIVOT] = _pivot_event(opts, r[12], r[13], r[14])
    else:
        r = slip_state(t, y, params)
        normal = r[0]
        if opts[fk.OPT_UNILATERAL] != 0.0:
            g[EV_LIFT] = normal
            if held:  # falls through 0 when N pushes again or the flight would rise
                g[EV_LIFT] = min(-normal, -flight_gap_acceleration(theta, y[fk.DPHI], y[fk.DTHETA], y[fk.OMEGA],
                                                                   r[12], c))
        if opts[fk.OPT_THETA_K] > 0.0:
            g[EV_PIVOT] = _pivot_event(opts, r[18], r[19], r[20])
        g[EV_STICK] = y[fk.SLIP_SPEED]
        g[EV_MODE] = _layer_event(y, opts, normal)


@njit(cache=True)
def sticking_slip_direction(phi, f_xi, f_n):
    """Slip direction [rad] (plane frame) against the friction ``(f_xi, f_n)`` that rolling needs."""
    sp_, cp = fk.sincos(phi)
    return math.atan2(-(f_xi * sp_ + f_n * cp), -(f_xi * cp - f_n * sp_))


@njit(cache=True)
def _contact_margins(t, y, params, f_xi, f_n, f_z):
    """How near the contacts the model allows the rim point is [m g]: ``(stick, slip)``, each >= 0 if allowed.

    Rolling (contact force ``f_xi, f_n, f_z``) within friction on a pushing N:
    ``min(N, mu N - |F_t|)``; the slip against the friction rolling would need (the choice of
    ``run3d._enter_contact``): its N.
    """
    normal = slip_with(t, y, params, sticking_slip_direction(y[fk.PHI], f_xi, f_n))[0]
    return min(f_z, params[3][fk.OPT_MU] * f_z - math.sqrt(f_xi * f_xi + f_n * f_n)), normal


@njit(cache=True)
def contact_margins(t, y, params):
    """:func:`_contact_margins` of a 3D state in rim contact at t [m g]."""
    f_xi, f_n, f_z, _ax, _ay, _az = rolling_contact(t, y, params)
    return _contact_margins(t, y, params, f_xi, f_n, f_z)


@njit(cache=True)
def _pivot_event(opts, drill, capacity, omega_z):
    """Falls through 0 when the held pivot's couple reaches its limit, the pivot's turning stops,
    or (patch unloaded, no drilling friction) the patch takes load again."""
    if opts[fk.OPT_PIVOT_HELD] != 0.0:
        return capacity - abs(drill)
    if opts[fk.OPT_DRILL_SIGN] != 0.0:
        return opts[fk.OPT_DRILL_SIGN] * omega_z
    return 1.0 if capacity <= 0.0 else -1.0


@njit(cache=True)
def layer_edge(y, opts, normal):
    """Slip speed below which the slip direction is slaved [sqrt(g R)].

    ``slave_time mu N``: the direction's lag behind the consistent one is
    at most slave_time. Where the contact frame turns fast (the precession
    rate phi' reaches 1e6 near the vertical) that lag would turn it by
    slave_time phi'; the edge shrinks so that the turn within the lag stays
    below ``slaved_turn`` (a call slaved at a speed of 1.3e-3, so with N above
    3600, at theta 3e-5 put 1.7e-6 m g R into the budget's error, FEMA-FF-15
    x 2 g on R = r = 0.5, h = 2).
    """
    lag = opts[fk.OPT_SLAVE_TIME]
    return lag * opts[fk.OPT_MU] * max(normal, 0.0) / (1.0 + lag * abs(y[fk.DPHI]) / opts[fk.OPT_SLAVED_TURN])


@njit(cache=True)
def _layer_event(y, opts, normal):
    """Leaving (slaved) or entering (free) the slaved-direction layer: falls through 0."""
    speed = y[fk.SLIP_SPEED]
    edge = layer_edge(y, opts, normal)
    if opts[fk.OPT_SLAVED] != 0.0:
        return layer_exit(edge, opts) - speed
    return speed - 0.5 * edge


@njit(cache=True)
def layer_exit(edge, opts):
    """Slip speed above which a slaved direction becomes a state again.

    The edge moves with N, and N moves with the slaved direction: entering
    the layer at half the edge can land on a root whose N puts the edge below
    the speed already, and a layer event that starts past zero never fires
    (the direction then stayed slaved at any speed, and a slaved direction
    jumping between roots at speed jumps the kinetic energy). Twice the speed
    of entry keeps the exit ahead of it.
    """
    return max(edge, 2.0 * opts[fk.OPT_SLAVED_SPEED])


@njit(cache=True)
def monitor3d(t, y, params, g):
    """Peak mobilized friction and lowest normal force, at every accepted step.

    The event functions there (``g``) already hold N and ``mu N - |F_t|``.
    """
    opts, summary = params[3], params[4]
    phase = opts[fk.OPT_PHASE]
    mu = opts[fk.OPT_MU]
    # the event functions hold N unless the rim is held (then they hold the hold's end)
    fast = opts[fk.OPT_UNILATERAL] != 0.0 and mu < math.inf and opts[fk.OPT_RIM_HELD] == 0.0
    if phase == PHASE_ROLLING:
        if fast:
            normal = g[EV_LIFT]
            f_t = mu * normal - (g[EV_SLIP] - opts[fk.OPT_FRICTION_EXCESS])
        else:
            f_xi, f_n, normal, _ax, _ay, _az = rolling_contact(t, y, params)
            f_t = math.sqrt(f_xi * f_xi + f_n * f_n)
            if opts[fk.OPT_RIM_HELD] != 0.0 and mu < math.inf:
                # a held rim is at its friction limit: what it asks beyond is the patch
                # couple's overreach (loop.holds_rim), not friction the ground gives
                f_t = min(f_t, mu * max(normal, 0.0))
        watch_contact(summary, f_t / normal if normal > 0.0 else 0.0, normal)
    elif phase == PHASE_SLIPPING:
        watch_contact(summary, mu, g[EV_LIFT] if fast else slip_state(t, y, params)[0])
    elif phase == PHASE_SLIDING:
        watch_contact(summary, mu, g[EV_LIFT])
    elif phase == PHASE_FLIGHT:
        watch_contact(summary, 0.0, 0.0)


@njit(cache=True)
def integrate3d(params, t0, y0, t_end, t_out, y_out, out_start, t_breaks, rtol, atol, h0):
    return dop853_monitored(rhs3d, events3d, monitor3d, params, t0, y0, t_end, t_out, y_out, out_start,
                            EVENT_DIRECTIONS, t_breaks, rtol, atol, params[3][fk.OPT_MAX_STEP], h0, MAX_STEPS)


@njit(cache=True)
def energy3d(phase, y, c):
    """Mechanical energy [m g R] of a 3D state in a given phase."""
    zc = c[fk.C_ZC]
    if phase == PHASE_REST:
        return zc
    if phase == PHASE_SLIDING:
        return zc + 0.5 * y[fk.SLIP_SPEED] * y[fk.SLIP_SPEED]
    theta, dphi, dtheta, omega = y[fk.THETA], y[fk.DPHI], y[fk.DTHETA], y[fk.OMEGA]
    if phase == PHASE_FLIGHT:
        return rim.energy(theta, dphi, dtheta, omega, y[fk.VX], y[fk.VY], y[fk.VZ], y[fk.ZC], c)
    r_xi, r_n, r_z = rim.cm_velocity_rolling(theta, dphi, dtheta, omega, zc)
    if phase == PHASE_SLIPPING:
        sp_, cp = fk.sincos(y[fk.PHI])
        speed = y[fk.SLIP_SPEED]
        cx, sx = math.cos(y[fk.SLIP_DIR]), math.sin(y[fk.SLIP_DIR])
        r_xi += speed * (cx * cp + sx * sp_)
        r_n += speed * (-cx * sp_ + sx * cp)
    return rim.energy(theta, dphi, dtheta, omega, r_xi, r_n, r_z, rim.lever(theta, zc), c)


@njit(cache=True)
def flight_gap_acceleration(theta, dphi, dtheta, omega, az, c):
    """Second derivative of the lowest rim point's height if the column flew now [g].

    The gap is ``z_C - lever(theta)`` and its rate is 0 when a rim contact
    ends; free flight (no contact force) gives ``z_C'' = -(1 + a_Z)`` and the
    torque-free theta''. Negative: the free column would sink into the ground.
    """
    ddtheta = rim.rotation_accelerations(theta, dphi, dtheta, omega, 0.0, 0.0, 0.0, c)[1]
    zc = c[fk.C_ZC]
    return -1.0 - az + rim.lever(theta, zc) * dtheta * dtheta - rim.reach(theta, zc) * ddtheta
