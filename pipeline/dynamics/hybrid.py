"""Hybrid simulation of a rigid column under ground motion: phases, events, impacts.

Kernel layer (dimensionless arrays in, arrays out), compiled with numba. One
call runs one column under one ground-acceleration record, for the
three-dimensional frustum (:func:`run_frustum`) or for planar rocking
(:func:`run_rocking`). The base is a flat face of stone on stone; the phases
(docs/model.md):

* **rest** (full base contact): the column moves with the ground. It leaves
  rest when the ground's push beats what the base can hold: it *uplifts* at
  ``|a_h| z_cm = (g + a_Z) R``, it *slides* at ``|a_h| = mu (g + a_Z)``,
  whichever threshold is lower (a column with ``mu < R / z_cm`` slides first),
  or it *flies* when ``g + a_Z`` reaches 0. The record is linear between
  samples, so the time is found exactly
  (:func:`pipeline.dynamics.contact.first_uplift`).
* **sliding** flat on the base (Coulomb friction, ``mu N`` against the
  sliding velocity), until the velocity vanishes (then rest, or sliding the
  other way).
* **rolling** on the rim (the paper's equations, :mod:`pipeline.dynamics.frustum`),
  while the normal force stays positive and the friction it needs stays
  below ``mu N``.
* **slipping** on the rim (:mod:`pipeline.dynamics.rim`): the rim point
  slides with Coulomb friction; back to rolling when the slip velocity
  vanishes and sticking holds.
* **flight**: the normal force would turn negative; the column flies until
  its lowest rim point (or its flat base) comes down, with a plastic impact
  that sticks or slides as Coulomb allows.
* **landing** near full contact (``theta`` down to ``theta_c``): the
  angular-momentum impact about the opposite rim point, or settling to rest.
* **overturned**: the side of the frustum touches the ground,
  ``theta_lie = pi/2 + atan((R - r)/h)``; the run ends.

Every phase is integrated by the compiled DOP853 (one wrapper per model; the
phase is read from the options array) with the terminal events of
``EV_*``; the record's samples are break points. A step monitor updates the
peak mobilized friction and the lowest normal force at every accepted step,
so those peaks, like the sliding and lift-off flags (phases entered), do not
depend on the output grid. Every jump of mechanical energy at a transition is
added to ``summary[S_TRANSITION]``, so that
``E_end - E_0 = work + transitions - dissipated - friction`` holds to the
integration error.

The entry points release the GIL (``nogil=True``).
"""

import math

import numpy as np
from numba import njit

from pipeline.dynamics import contact
from pipeline.dynamics import frustum as fk
from pipeline.dynamics import patch
from pipeline.dynamics import rim
from pipeline.dynamics import rocking as rk
from pipeline.dynamics.integrator import dop853_monitored

PHASE_REST, PHASE_ROLLING, PHASE_OVERTURNED, PHASE_SLIDING, PHASE_SLIPPING, PHASE_FLIGHT = range(6)

# Indices of the summary array filled by the runs.
(
    S_STATUS,  # 0 done, < 0 integration failure (integrator status)
    S_PEAK_THETA,  # [rad]
    S_PEAK_TIME,  # [tau]
    S_OVERTURN_TIME,  # [tau], nan if it stands
    S_UPLIFT_TIME,  # first uplift [tau], nan if never
    S_N_IMPACTS,
    S_PEAK_MU,  # largest mobilized friction |F_t|/N while in contact [1]
    S_MIN_NORMAL,  # lowest normal force while in contact [m g]
    S_TRANSITION,  # energy jumps at contact transitions [m g R]
    S_NFEV,
    S_STEPS,
    S_END_TIME,  # [tau]
    S_ROTATION,  # body rotation about the vertical at the end, phi + psi [rad]
    S_BASE_X,  # base centre at the end [R]
    S_BASE_Y,
    S_SLIDE_TIME,  # first slip of the base or of the rim [tau], nan if never
    S_FLIGHT_TIME,  # first lift-off [tau], nan if never
    S_FINAL_PHASE,  # phase at the end (PHASE_OVERTURNED if it lay down)
    S_ENERGY_START,  # mechanical energy at the start [m g R]
    S_ENERGY_END,  # at the end (when it lies down: then) [m g R]
    S_WORK,  # work done by the ground motion [m g R]
    S_DISSIPATED,  # removed by the contact couples [m g R]
    S_FRICTION,  # removed by sliding friction [m g R]
) = range(23)
N_SUMMARY = 23

# Safety net against a Zeno cascade of transitions.
MAX_TRANSITIONS = 1_000_000
MAX_STEPS = 50_000_000
# Consecutive event stops without advancing time that end a run (status -11)
# instead of looping: a safety net, never reached in the tests.
MAX_STALLS = 100
STATUS_STALLED = -11

EV_LAND, EV_LIE, EV_TURN, EV_LIFT, EV_SLIP, EV_STICK, EV_MODE, EV_PIVOT = range(8)
# landing/touch-down falling, lying down rising, turning point of theta both
# ways, normal force falling to 0, friction margin falling to 0, slip velocity
# falling to 0, slip speed crossing the slaved-direction layer, the drilling
# friction letting the pivot go (or its turning stopping)
EVENT_DIRECTIONS = np.array([-1.0, 1.0, 0.0, -1.0, -1.0, -1.0, -1.0, -1.0])

# Numerical thresholds (defaults; carried in the options array, OPT_*, so that
# studies/thresholds can vary them). No physical result may depend on them:
# studies/thresholds/results.md shows that none does.
#
# slave_time [tau]: the direction of a two-dimensional Coulomb slip relaxes
# towards the consistent one (slip acceleration along the slip) at the rate
# k / s, k of order mu N: at slip onset and stop (s -> 0) that is infinitely
# fast, and no explicit step survives it. Below s = slave_time mu N the
# direction is therefore slaved: taken as the consistent direction, solved at
# every evaluation (an error of the order of the lag slave_time x the turning
# rate of that direction); above it the direction is a state. The layer is
# left at slave_time mu N and entered again below half of it.
#
# look_ahead [tau]: a phase that starts on a bound (stick after a slip stops,
# say) is checked a little ahead as well: the integrator reads the event signs
# only after a restart window of 1e-7 of its first step, and a bound left
# within it would not be seen (the phase would then violate it until the next
# crossing).
#
# landing_margin [1]: rolling starts at theta_c; the landing surface lies a
# hair below it, (1 - landing_margin) theta_c, so a column that uplifts on the
# verge of the threshold (theta'' ~ 0) does not start on the landing surface,
# where round-off would trip the event at once.
#
# min_rebound [rad]: a rebound that would rise less than this above theta_c is
# a settling: shorter excursions than an integration step could slip past the
# landing event (and with theta_c = 0 the column would never settle otherwise).
#
# slaved_turn [rad]: where the contact frame turns fast (phi' ~ 1e6 near the
# vertical) a lag of slave_time would let it turn far; the layer's edge shrinks
# so that the frame turns at most about slaved_turn within the lag (_layer_edge).
NUMERICS = {"landing_margin": 1e-3, "min_rebound": 1e-8, "slave_time": 1e-6, "look_ahead": 1e-7,
            "slaved_turn": 1e-3}

_TWO_PI = 2.0 * math.pi


# --- the three-dimensional frustum ----------------------------------------------------------


@njit(cache=True)
def _slip_friction(chi, sp_, cp, mu):
    """Friction per unit normal force (xi, n) opposing the slip direction chi, and (cos, sin) of chi."""
    sx, cx = fk.sincos(chi)
    s_xi = cx * cp + sx * sp_
    s_n = -cx * sp_ + sx * cp
    return -mu * s_xi, -mu * s_n, cx, sx


@njit(cache=True)
def _horizontal_spin(theta, dphi, dtheta, omega):
    """Angular velocity in the contact point's frame: (xi, n) horizontal and vertical [1/tau]."""
    s = math.sin(theta)
    co = math.cos(theta)
    w_eta = dphi * s
    return dtheta, w_eta * co - omega * s, w_eta * s + omega * co


@njit(cache=True)
def _rolling_state(t, y, params):
    """Accelerations and contact of rolling, with the contact patch's couples.

    Rolling on P (the paper's equations, the optional viscous couple nu), plus
    the patch of :mod:`pipeline.dynamics.patch` when ``theta_k > 0``: its
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
    om_xi, om_n, om_z = _horizontal_spin(theta, dphi, dtheta, omega)
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
def _rolling_contact(t, y, params):
    """Contact force of rolling (xi, n, N) [m g] and the ground acceleration [g]."""
    r = _rolling_state(t, y, params)
    return r[3], r[4], r[5], r[6], r[7], r[8]


@njit(cache=True)
def _slip_patch(y, params, theta, a_xi, a_n, az):
    """Couples of the contact while P slides (body components), their power and the drilling capacity.

    The patch's rolling damping and the optional viscous couple ``-nu omega``
    (rolling has both, :func:`_rolling_state`; so slip must, or the two sets of
    equations would differ at slip onset). Returns ``(m_xi, m_eta, m_zeta,
    damped, capacity)``: the couple [m g R], the power it removes
    [m g sqrt(g R)] and the largest drilling couple ``mu N r_d`` [m g R]
    (:func:`pipeline.dynamics.patch.couples`).
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
    om_xi, om_n, _om_z = _horizontal_spin(theta, dphi, dtheta, omega)
    p_xi, p_n, capacity = patch.couples(load, theta, theta_k, opts[fk.OPT_PATCH_DAMPING], opts[fk.OPT_MU],
                                        om_xi, om_n)
    return (m_xi + p_xi, m_eta + p_n * co, m_zeta - p_n * s, damped - (p_xi * om_xi + p_n * om_n), capacity)


@njit(cache=True)
def _slip_drill(opts, theta, dphi, dtheta, omega, ddphi, domega, capacity, c):
    """Drilling couple of the patch about the vertical through a sliding P [m g R].

    The patch's friction limit is the same in every phase: a tangential force
    up to mu N and, independently, a drilling couple up to ``mu N r_d``
    (:func:`_rolling_state`). So a pivot held while rolling stays held when P
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
def _slip_setting(t, y, params):
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
def _slip_with(t, y, params, chi):
    """:func:`_slip_in` with its setting computed here."""
    return _slip_in(t, y, params, chi, _slip_setting(t, y, params))


@njit(cache=True)
def _slip_in(t, y, params, chi, setting):
    """Normal force and accelerations of rim slip in the direction chi (``setting``: :func:`_slip_setting`).

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
def _along(t, y, params, chi, setting):
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
    setting = _slip_setting(t, y, params)
    if (_misalignment(t, y, params, guess, setting) == 0.0
            and not (starting and _along(t, y, params, guess, setting) < 0.0)):
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
            if gap < best_gap and not (starting and _along(t, y, params, root, setting) < 0.0):
                best, best_gap = root, gap
        a, fa = b, fb
    return best if best_gap < math.inf else best_any


@njit(cache=True)
def _slip_direction(t, y, params):
    """The slip direction in use: the state's, or the slaved consistent one."""
    opts = params[3]
    if opts[fk.OPT_SLAVED] == 0.0:
        return y[fk.SLIP_DIR]
    guess = y[fk.SLIP_DIR] + (y[fk.PHI] - opts[fk.OPT_PHI_REF])
    return consistent_direction(t, y, params, guess, y[fk.SLIP_SPEED] <= 0.0)


@njit(cache=True)
def _slip_state(t, y, params):
    """:func:`_slip_with` in the direction in use."""
    return _slip_with(t, y, params, _slip_direction(t, y, params))


@njit(cache=True)
def _flat_direction(t, y, params):
    """Direction of flat sliding: the state's, or slaved, against the ground's push."""
    if params[3][fk.OPT_SLAVED] == 0.0:
        return y[fk.SLIP_DIR]
    ax, ay, _az = fk.ground_acceleration(t, params[1], params[2])
    if ax == 0.0 and ay == 0.0:
        return y[fk.SLIP_DIR]
    return math.atan2(-ay, -ax)


@njit(cache=True)
def _rhs_slipping(t, y, params, dydt):
    c, opts = params[0], params[3]
    zc = c[fk.C_ZC]
    mu = opts[fk.OPT_MU]
    (normal, den, ddphi, ddtheta, domega, dw_eta, f_xi, f_n, cx, sx, ax, ay, az, a_xi, a_n,
     vx, vy, damped, drill, _cap, om_z) = _slip_state(t, y, params)
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
def _rhs_sliding(t, y, params, dydt):
    record, dt, opts = params[1], params[2], params[3]
    ax, ay, az = fk.ground_acceleration(t, record, dt)
    mu = opts[fk.OPT_MU]
    speed = y[fk.SLIP_SPEED]
    chi = _flat_direction(t, y, params)
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
def _rhs_rolling(t, y, params, dydt):
    (ddphi, ddtheta, domega, _f_xi, _f_n, _f_z, _ax, _ay, az, a_xi, a_n, damped, drill, _cap,
     om_z) = _rolling_state(t, y, params)
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
        _rhs_rolling(t, y, params, dydt)
    elif phase == PHASE_SLIPPING:
        _rhs_slipping(t, y, params, dydt)
    elif phase == PHASE_FLIGHT:
        _rhs_flight(t, y, params, dydt)
    else:
        _rhs_sliding(t, y, params, dydt)


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
    if phase == PHASE_ROLLING:
        r = _rolling_state(t, y, params)
        f_xi, f_n, f_z = r[3], r[4], r[5]
        if opts[fk.OPT_RIM_HELD] != 0.0:  # falls through 0 when N pushes again or the flight would rise
            g[EV_LIFT] = min(-f_z, -flight_gap_acceleration(theta, y[fk.DPHI], y[fk.DTHETA], y[fk.OMEGA],
                                                            r[8], c))
        elif opts[fk.OPT_UNILATERAL] != 0.0:
            g[EV_LIFT] = f_z
        if opts[fk.OPT_MU] < math.inf:  # inf: rolling without slip, whatever the force
            g[EV_SLIP] = opts[fk.OPT_MU] * f_z - math.sqrt(f_xi * f_xi + f_n * f_n) + opts[fk.OPT_FRICTION_EXCESS]
            if opts[fk.OPT_THETA_K] > 0.0:
                g[EV_PIVOT] = _pivot_event(opts, r[12], r[13], r[14])
    else:
        r = _slip_state(t, y, params)
        normal = r[0]
        if opts[fk.OPT_UNILATERAL] != 0.0:
            g[EV_LIFT] = normal
        if opts[fk.OPT_THETA_K] > 0.0:
            g[EV_PIVOT] = _pivot_event(opts, r[18], r[19], r[20])
        g[EV_STICK] = y[fk.SLIP_SPEED]
        g[EV_MODE] = _layer_event(y, opts, normal)


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
def _layer_edge(y, opts, normal):
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
    edge = _layer_edge(y, opts, normal)
    if opts[fk.OPT_SLAVED] != 0.0:
        return _layer_exit(edge, opts) - speed
    return speed - 0.5 * edge


@njit(cache=True)
def _layer_exit(edge, opts):
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
def _watch(summary, mu, normal):
    if mu > summary[S_PEAK_MU]:
        summary[S_PEAK_MU] = mu
    if normal < summary[S_MIN_NORMAL]:
        summary[S_MIN_NORMAL] = normal


@njit(cache=True)
def monitor3d(t, y, params, g):
    """Peak mobilized friction and lowest normal force, at every accepted step.

    The event functions there (``g``) already hold N and ``mu N - |F_t|``.
    """
    opts, summary = params[3], params[4]
    phase = opts[fk.OPT_PHASE]
    mu = opts[fk.OPT_MU]
    fast = opts[fk.OPT_UNILATERAL] != 0.0 and mu < math.inf
    if phase == PHASE_ROLLING:
        if fast:
            normal = g[EV_LIFT]
            f_t = mu * normal - (g[EV_SLIP] - opts[fk.OPT_FRICTION_EXCESS])
        else:
            f_xi, f_n, normal, _ax, _ay, _az = _rolling_contact(t, y, params)
            f_t = math.sqrt(f_xi * f_xi + f_n * f_n)
        _watch(summary, f_t / normal if normal > 0.0 else 0.0, normal)
    elif phase == PHASE_SLIPPING:
        _watch(summary, mu, g[EV_LIFT] if fast else _slip_state(t, y, params)[0])
    elif phase == PHASE_SLIDING:
        _watch(summary, mu, g[EV_LIFT])
    elif phase == PHASE_FLIGHT:
        _watch(summary, 0.0, 0.0)


@njit(cache=True)
def _integrate3d(params, t0, y0, t_end, t_out, y_out, out_start, t_breaks, rtol, atol, h0):
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
def _init_summary(summary):
    summary[:] = 0.0
    summary[S_OVERTURN_TIME] = math.nan
    summary[S_UPLIFT_TIME] = math.nan
    summary[S_SLIDE_TIME] = math.nan
    summary[S_FLIGHT_TIME] = math.nan
    summary[S_MIN_NORMAL] = math.inf


@njit(cache=True)
def _close_budget(summary, energy_end, work, dissipated, friction):
    summary[S_ENERGY_END] = energy_end
    summary[S_WORK] = work
    summary[S_DISSIPATED] = dissipated
    summary[S_FRICTION] = friction


@njit(cache=True)
def _first(summary, k, t):
    if math.isnan(summary[k]):
        summary[k] = t


@njit(cache=True)
def _settle_kinetic(theta_c, zc, min_rebound):
    """Kinetic energy [m g R] below which a landing column settles to rest."""
    top = theta_c + max(theta_c, min_rebound)
    return (math.sin(top) + zc * math.cos(top)) - (math.sin(theta_c) + zc * math.cos(theta_c))


@njit(cache=True)
def departure_ratio(zc, mu):
    """Ratio |a_h| / (g + a_z) at which a column at rest starts to move [1].

    ``R / z_cm`` if it uplifts first, ``mu`` if it slides first.
    """
    return min(1.0 / zc, mu)


@njit(cache=True)
def _rest_until_departure(record, dt, ratio, t, t_end, t_out, y_out, phase_out, out_i, y_rest, summary):
    """Stay at rest from ``t`` until the column starts to move (or ``t_end``), filling the outputs.

    Also updates the peak mobilized friction at rest, ``|a_h| / (1 + a_z)``,
    which on the piecewise-linear record peaks at samples or at the ends.
    Returns the departure time (``inf`` if none before the record ends) and
    the next output row.
    """
    t_dep = contact.first_uplift(record, dt, 1.0 / ratio, t)
    stop = min(t_dep, t_end)
    inclusive = t_dep >= t_end
    n = t_out.shape[0]
    while out_i < n and (t_out[out_i] < stop or (inclusive and t_out[out_i] <= stop)):
        y_out[out_i, :] = y_rest
        phase_out[out_i] = PHASE_REST
        out_i += 1
    n_rec = record.shape[0]
    # a column that comes to rest where the ground already asks more than it can hold leaves
    # at once: no rest, no friction at rest (the phase it leaves in carries the friction)
    if n_rec > 0 and stop > t:
        last = min(stop, (n_rec - 1) * dt)
        k_lo = int(math.ceil(t / dt)) if t > 0.0 else 0
        k_hi = int(math.floor(last / dt))
        _rest_friction(summary, *fk.ground_acceleration(t, record, dt))
        for k in range(k_lo, min(k_hi, n_rec - 1) + 1):
            _rest_friction(summary, record[k, 0], record[k, 1], record[k, 2])
        if last >= t:
            _rest_friction(summary, *fk.ground_acceleration(last, record, dt))
    return t_dep, out_i


@njit(cache=True)
def _rest_friction(summary, ax, ay, az):
    normal = 1.0 + az
    if normal > 0.0:
        _watch(summary, math.sqrt(ax * ax + ay * ay) / normal, normal)


@njit(cache=True)
def _log_impact(impacts, summary, t, rate_before, rate_after, energy_jump):
    """Record a landing in the log (the first ``len(impacts)`` only)."""
    k = int(summary[S_N_IMPACTS]) - 1
    if 0 <= k < impacts.shape[0]:
        impacts[k, 0] = t
        impacts[k, 1] = rate_before
        impacts[k, 2] = rate_after
        impacts[k, 3] = energy_jump


@njit(cache=True)
def _book_phase(res, phase, phase_out, out_i, summary, y, t_start, stalls):
    """Record a phase's outputs and cost; copy its final state into y.

    Returns the next output row and the count of consecutive calls that
    stopped without advancing time (``STATUS_STALLED`` past ``MAX_STALLS``).
    """
    phase_out[out_i:res.out_next] = phase
    summary[S_NFEV] += res.nfev
    summary[S_STEPS] += res.n_accepted
    if res.status < 0:
        summary[S_STATUS] = res.status
    y[:] = res.y
    stalls = stalls + 1 if res.t == t_start else 0
    if stalls > MAX_STALLS:
        summary[S_STATUS] = STATUS_STALLED
    return res.out_next, stalls


@njit(cache=True)
def _lie_down(summary, t, theta, y, y_out, phase_out, out_i):
    """The column lies on its side: record it and freeze the remaining outputs."""
    summary[S_PEAK_THETA] = theta
    summary[S_PEAK_TIME] = t
    summary[S_OVERTURN_TIME] = t
    for i in range(out_i, y_out.shape[0]):
        y_out[i, :] = y
        phase_out[i] = PHASE_OVERTURNED
    return y_out.shape[0]


@njit(cache=True)
def _peak(summary, t, theta):
    if theta > summary[S_PEAK_THETA]:
        summary[S_PEAK_THETA] = theta
        summary[S_PEAK_TIME] = t


@njit(cache=True)
def _clear_free_slots(y):
    """Zero the slots that the contact phases do not integrate (slip, flight)."""
    y[fk.SLIP_SPEED] = 0.0
    y[fk.SLIP_DIR] = 0.0
    y[fk.ZC] = 0.0
    y[fk.VX] = 0.0
    y[fk.VY] = 0.0
    y[fk.VZ] = 0.0


@njit(cache=True)
def _to_flight(y, c, slipping):
    """Rim contact (rolling or slipping) -> flight: centre of mass position and velocity."""
    zc = c[fk.C_ZC]
    theta = y[fk.THETA]
    sp_, cp = fk.sincos(y[fk.PHI])
    v_xi, v_n, v_z = rim.cm_velocity_rolling(theta, y[fk.DPHI], y[fk.DTHETA], y[fk.OMEGA], zc)
    vx = v_xi * cp - v_n * sp_
    vy = v_xi * sp_ + v_n * cp
    if slipping:
        vx += y[fk.SLIP_SPEED] * math.cos(y[fk.SLIP_DIR])
        vy += y[fk.SLIP_SPEED] * math.sin(y[fk.SLIP_DIR])
    reach = rim.reach(theta, zc)
    x, yy = y[fk.XP] - sp_ * reach, y[fk.YP] + cp * reach
    _clear_free_slots(y)
    y[fk.XP], y[fk.YP] = x, yy
    y[fk.ZC] = rim.lever(theta, zc)
    y[fk.VX], y[fk.VY], y[fk.VZ] = vx, vy, v_z


@njit(cache=True)
def _start_slip(y, opts, chi, normal):
    """Begin a slip with speed ``y[SLIP_SPEED]`` in direction chi, slaved if it is slow."""
    y[fk.SLIP_DIR] = chi
    opts[fk.OPT_PHI_REF] = y[fk.PHI]
    opts[fk.OPT_SLAVED] = 1.0 if y[fk.SLIP_SPEED] < _layer_edge(y, opts, normal) else 0.0
    opts[fk.OPT_SLAVED_SPEED] = y[fk.SLIP_SPEED]


@njit(cache=True)
def _slip_reading(t, y, params, phase):
    """Normal force [m g] and the slip speed's rate [g] of a slip phase (rim or flat) in the direction in use."""
    if phase == PHASE_SLIPPING:
        r = _slip_state(t, y, params)
        return r[0], r[15] * r[8] + r[16] * r[9]  # _rhs_slipping's SLIP_SPEED rate
    rate = np.empty(y.shape[0])
    _rhs_sliding(t, y, params, rate)
    return 1.0 + fk.ground_acceleration(t, params[1], params[2])[2], rate[fk.SLIP_SPEED]


@njit(cache=True)
def _leave_layer_if_past(t, y, params, phase):
    """A call that would start slaved with the speed past the layer's exit starts free instead.

    The exit's event would start past zero and never fire (N, and so the
    edge, can drop at a transition). The slaved direction in use was written
    into the state at the end of the last call (:func:`_sync_direction`).
    """
    opts = params[3]
    if opts[fk.OPT_SLAVED] == 0.0:
        return
    normal = _slip_reading(t, y, params, phase)[0]
    if y[fk.SLIP_SPEED] > _layer_exit(_layer_edge(y, opts, normal), opts):
        opts[fk.OPT_SLAVED] = 0.0


@njit(cache=True)
def _slaved_step(t, y, params, phase):
    """Longest step of a call that starts with a slaved slip direction [tau] (inf otherwise).

    Events are read at the ends of steps, and a slaved slip is smooth enough
    for steps much longer than its layer: a speed that rose past the edge and
    fell back to a stick within one step stayed slaved at 50 x the edge
    (FEMA-FF-05 x 0.8 g, R 0.5 r 0.3 h 4: 1.7e-7 m of the budget). Half the
    time the speed, at its rate now, takes to cross the layer's width.
    """
    opts = params[3]
    if opts[fk.OPT_SLAVED] == 0.0 or (phase != PHASE_SLIPPING and phase != PHASE_SLIDING):
        return math.inf
    normal, speed_rate = _slip_reading(t, y, params, phase)
    exit_speed = _layer_exit(_layer_edge(y, opts, normal), opts)
    if speed_rate == 0.0 or exit_speed <= 0.0:
        return math.inf
    return 0.5 * exit_speed / abs(speed_rate)


@njit(cache=True)
def _book_slaved_turn(t, y, params, phase):
    """Turn a slaved slip direction to the one the next call uses, and book the energy it takes.

    A handler that changes the contact's law (the pivot's mode, the layer
    entered) can move the consistent direction to another root: the slip
    velocity (below the layer's edge, ``slave_time mu N``) turns at once.
    Its kinetic energy then changes by the momentum times that small
    velocity change; unbooked, it read as an error of the budget of up to
    2e-5 m (model_2d_vs_3d, 3D, 16 of 4840 runs).
    """
    if params[3][fk.OPT_SLAVED] == 0.0:
        return
    c, summary = params[0], params[4]
    e_before = energy3d(phase, y, c)
    _sync_direction(t, y, params, phase)
    summary[S_TRANSITION] += energy3d(phase, y, c) - e_before


@njit(cache=True)
def _sync_direction(t, y, params, phase):
    """Write the slip direction in use into the state (it is only a guess while slaved)."""
    opts = params[3]
    if opts[fk.OPT_SLAVED] != 0.0:
        if phase == PHASE_SLIPPING:
            y[fk.SLIP_DIR] = _slip_direction(t, y, params)
        elif phase == PHASE_SLIDING:
            y[fk.SLIP_DIR] = _flat_direction(t, y, params)
    # the slaved direction is sought near the stored one, turned with the precession since
    opts[fk.OPT_PHI_REF] = y[fk.PHI]


@njit(cache=True)
def _ahead(t, y, params, phase=PHASE_ROLLING):
    """The state a look-ahead later (one Euler step, ``OPT_LOOK_AHEAD``), rolling or slipping."""
    ahead = y.copy()
    rate = np.empty(y.shape[0])
    if phase == PHASE_SLIPPING:
        _rhs_slipping(t, y, params, rate)
    else:
        _rhs_rolling(t, y, params, rate)
    step = params[3][fk.OPT_LOOK_AHEAD]
    for i in range(rate.shape[0]):
        ahead[i] += step * rate[i]
    return ahead


@njit(cache=True)
def _drill_demand(t, y, params, phase):
    """The drilling couple and its limit [m g R] of the phase (rolling or slipping) at t."""
    if phase == PHASE_SLIPPING:
        r = _slip_state(t, y, params)
        return r[18], r[19]
    r = _rolling_state(t, y, params)
    return r[12], r[13]


@njit(cache=True)
def _pivot_mode(t, y, params, phase=PHASE_ROLLING):
    """Whether the patch's drilling friction holds the pivot, or in which sense it turns.

    A column turning about the vertical through P keeps turning (friction
    against it) until the turning stops; then the pivot is held while the
    couple that holds it stays within ``mu N r_d``, now and a moment later.
    A patch that carries no load a moment later gives no drilling couple
    (neither held nor turning, ``OPT_DRILL_SIGN`` 0) until it loads again.
    The same law whether P rolls or slides (``phase``).
    """
    opts = params[3]
    opts[fk.OPT_PIVOT_HELD] = 0.0
    opts[fk.OPT_DRILL_SIGN] = 0.0
    if opts[fk.OPT_THETA_K] <= 0.0:
        return  # a point contact: no drilling friction (the paper's model)
    om_z = _horizontal_spin(y[fk.THETA], y[fk.DPHI], y[fk.DTHETA], y[fk.OMEGA])[2]
    scale = abs(y[fk.DPHI]) + abs(y[fk.OMEGA]) + abs(y[fk.DTHETA])
    if abs(om_z) > 1e-12 * scale:
        opts[fk.OPT_DRILL_SIGN] = math.copysign(1.0, om_z)
        return
    opts[fk.OPT_PIVOT_HELD] = 1.0
    if opts[fk.OPT_MU] == math.inf:
        return
    drill, capacity = _drill_demand(t, y, params, phase)
    drill_ahead, capacity_ahead = _drill_demand(t + opts[fk.OPT_LOOK_AHEAD], _ahead(t, y, params, phase), params,
                                                phase)
    if capacity_ahead <= 0.0:
        # the patch is unloaded: no drilling friction, the column turns freely (until it loads again)
        opts[fk.OPT_PIVOT_HELD] = 0.0
        return
    if abs(drill) <= capacity and abs(drill_ahead) <= capacity_ahead:
        return
    # too strong a twist for the patch: it turns, against the couple that would hold it
    opts[fk.OPT_PIVOT_HELD] = 0.0
    opts[fk.OPT_DRILL_SIGN] = -math.copysign(1.0, drill_ahead)


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


@njit(cache=True)
def _holds_rim(opts, gap_acceleration):
    """Infinite friction, a pulling normal force and a sinking flight: hold the rim (OPT_RIM_HELD).

    Without slip (mu = inf) the contact force is whatever rolling needs; when
    that would pull while the free column would fall into the ground
    (``gap_acceleration`` < 0, :func:`flight_gap_acceleration`), neither
    rolling nor flight is consistent (an infinite-friction paradox that any
    finite mu avoids by slipping first). The rim is then held, as the paper
    holds it, until the normal force pushes again or the flight would rise.
    Both kernels use it.
    """
    if opts[fk.OPT_MU] != math.inf or opts[fk.OPT_UNILATERAL] == 0.0 or gap_acceleration >= 0.0:
        return False
    opts[fk.OPT_RIM_HELD] = 1.0
    return True


@njit(cache=True)
def _gap_acceleration(t, y, params):
    """:func:`flight_gap_acceleration` of a 3D state at time t."""
    az = fk.ground_acceleration(t, params[1], params[2])[2]
    return flight_gap_acceleration(y[fk.THETA], y[fk.DPHI], y[fk.DTHETA], y[fk.OMEGA], az, params[0])


@njit(cache=True)
def _slip_starts(t, y, params, ahead, chi):
    """Whether a slip from rest in (about) the direction chi accelerates, now or a look-ahead later.

    At slip onset the rolling and slip equations agree, so the slip
    acceleration starts at 0 (round-off either side) and grows with the
    friction demand: the look-ahead state ``ahead`` (rolling, one Euler step
    on) settles the sign.
    """
    if _along(t, y, params, _slip_direction(t, y, params), _slip_setting(t, y, params)) >= 0.0:
        return True
    later = t + params[3][fk.OPT_LOOK_AHEAD]
    guess = chi + (ahead[fk.PHI] - y[fk.PHI])
    return _along(later, ahead, params, consistent_direction(later, ahead, params, guess, True),
                  _slip_setting(later, ahead, params)) >= 0.0


@njit(cache=True)
def _enter_contact(t, y, params):
    """Phase that a state in rim contact (P not sliding) continues in: rolling, slipping or flight.

    Sets the slip direction against the friction that sticking would need
    when that exceeds ``mu N``.
    """
    c, opts = params[0], params[3]
    mu = opts[fk.OPT_MU]
    opts[fk.OPT_RIM_HELD] = 0.0
    opts[fk.OPT_FRICTION_EXCESS] = 0.0
    _pivot_mode(t, y, params)
    f_xi, f_n, f_z, _ax, _ay, _az = _rolling_contact(t, y, params)
    # a bound that holds now but is being left (N or the margin falling
    # through 0 within the integrator's restart window) would go unseen
    ahead = _ahead(t, y, params)
    g_xi, g_n, g_z, _ax, _ay, _az = _rolling_contact(t + opts[fk.OPT_LOOK_AHEAD], ahead, params)
    unilateral = opts[fk.OPT_UNILATERAL] != 0.0
    pushes = (f_z >= 0.0 and g_z >= 0.0) or not unilateral
    if pushes and (mu == math.inf or (math.sqrt(f_xi * f_xi + f_n * f_n) <= mu * f_z
                                      and math.sqrt(g_xi * g_xi + g_n * g_n) <= mu * g_z)):
        return PHASE_ROLLING
    if mu < math.inf:
        # sticking fails (friction or a pulling normal force): slipping against
        # the friction it would need, if the plane then pushes
        sp_, cp = fk.sincos(y[fk.PHI])
        chi = math.atan2(-(f_xi * sp_ + f_n * cp), -(f_xi * cp - f_n * sp_))
        normal = _slip_with(t, y, params, chi)[0]
        y[fk.SLIP_SPEED] = 0.0
        if normal >= 0.0 or not unilateral:
            _start_slip(y, opts, chi, normal)
            if pushes and opts[fk.OPT_SLAVED] != 0.0 and not _slip_starts(t, y, params, ahead, chi):
                # no slip direction accelerates from rest, now or a moment later: the
                # slip equations hold it though the rolling ones ask a little more than
                # mu N. It rolls on with that excess, which peak_mu_mob shows; the slip
                # event fires as soon as the friction asked grows beyond it. Both sets
                # of equations carry the same patch couples, so this is a safety net
                y[fk.SLIP_SPEED] = 0.0
                opts[fk.OPT_SLAVED] = 0.0
                # twice the deficit: a demand that keeps growing re-arms it a few times, not
                # at every look-ahead (1e6 transitions on FEMA-FF-18 at 3 g otherwise)
                opts[fk.OPT_FRICTION_EXCESS] = 2.0 * max(0.0, math.sqrt(f_xi * f_xi + f_n * f_n) - mu * f_z,
                                                         math.sqrt(g_xi * g_xi + g_n * g_n) - mu * g_z) + 1e-12
                return PHASE_ROLLING
            return PHASE_SLIPPING
    if not unilateral or _holds_rim(opts, _gap_acceleration(t, y, params)):
        return PHASE_ROLLING
    _to_flight(y, c, False)
    return PHASE_FLIGHT


# Passages whose lowest tilt stays above PASSAGE_REACH theta_c lose nothing to
# a slap (exp(1 - 40) ~ 1e-17 of it).
PASSAGE_REACH = 40.0


@njit(cache=True)
def passage_weight(ratio):
    """Share of a full slap lost in a passage whose lowest tilt is ``ratio`` theta_c [1].

    1 at theta_c, where the passage would land; ``exp(1 - ratio)`` above it:
    the far side of the base comes within the compliance theta_k R of the
    ground only when the lowest tilt is of that order, so the slap fades over
    one theta_k. Continuous, so no threshold switches between a lossless
    roll-through and a full impact.
    """
    if ratio <= 1.0:
        return 1.0
    return math.exp(1.0 - ratio) if ratio < PASSAGE_REACH else 0.0


@njit(cache=True)
def _near_contact_passage(t, y, params, phase, planar_e):
    """A passage through a minimum of theta near full contact: a partial slap.

    The base slaps the ground in part (:func:`passage_weight`): the rates are
    scaled by ``1 - w (1 - e)``, e the planar restitution, so that a passage
    that nearly lands loses what the planar impact would, and one that stays
    well above theta_c loses nothing. Booked in the transitions' energy.
    """
    c, opts, summary = params[0], params[3], params[4]
    if phase == PHASE_ROLLING:
        ddtheta = _rolling_state(t, y, params)[1]
    else:
        ddtheta = _slip_state(t, y, params)[3]
    if not ddtheta > 0.0:
        return  # a maximum
    w = passage_weight(y[fk.THETA] / opts[fk.OPT_THETA_C])
    if w == 0.0:
        return
    scale = 1.0 - w * (1.0 - planar_e)
    e_before = energy3d(phase, y, c)
    y[fk.DPHI] *= scale
    y[fk.OMEGA] *= scale
    y[fk.SLIP_SPEED] *= scale
    summary[S_TRANSITION] += energy3d(phase, y, c) - e_before


@njit(cache=True)
def _solve3(a, b):
    """Solve the 3x3 system a x = b (Cramer's rule)."""
    det = (a[0, 0] * (a[1, 1] * a[2, 2] - a[1, 2] * a[2, 1])
           - a[0, 1] * (a[1, 0] * a[2, 2] - a[1, 2] * a[2, 0])
           + a[0, 2] * (a[1, 0] * a[2, 1] - a[1, 1] * a[2, 0]))
    x = np.empty(3)
    for k in range(3):
        m = a.copy()
        for i in range(3):
            m[i, k] = b[i]
        x[k] = (m[0, 0] * (m[1, 1] * m[2, 2] - m[1, 2] * m[2, 1])
                - m[0, 1] * (m[1, 0] * m[2, 2] - m[1, 2] * m[2, 0])
                + m[0, 2] * (m[1, 0] * m[2, 1] - m[1, 1] * m[2, 0])) / det
    return x


@njit(cache=True)
def _touch_down_rim(y, c, mu):
    """Plastic impact of a flying column on its lowest rim point, with Coulomb friction.

    Writes the state after the impact (rim contact: P rolling, or slipping with
    its velocity) and returns True if P slides after it.
    """
    zc = c[fk.C_ZC]
    theta = y[fk.THETA]
    sp_, cp = fk.sincos(y[fk.PHI])
    r_xi, r_n, r_z = rim.cm_velocity_rolling(theta, y[fk.DPHI], y[fk.DTHETA], y[fk.OMEGA], zc)
    v_xi_c = y[fk.VX] * cp + y[fk.VY] * sp_
    v_n_c = -y[fk.VX] * sp_ + y[fk.VY] * cp
    # velocity of the material point at P: V_C - omega x r_PC
    vp = np.array([v_xi_c - r_xi, v_n_c - r_n, y[fk.VZ] - r_z])
    w = np.empty((3, 3))
    for k in range(3):
        j = np.zeros(3)
        j[k] = 1.0
        w[0, k], w[1, k], w[2, k] = rim.impulse_response(theta, j[0], j[1], j[2], c)
    impulse = _solve3(w, -vp)
    sliding = mu < math.inf and math.hypot(impulse[0], impulse[1]) > mu * impulse[2]
    if sliding:
        speed = math.hypot(vp[0], vp[1])
        d_xi = vp[0] / speed if speed > 0.0 else 0.0
        d_n = vp[1] / speed if speed > 0.0 else 0.0
        u = rim.impulse_response(theta, -mu * d_xi, -mu * d_n, 1.0, c)
        jn = -vp[2] / u[2]
        impulse[0], impulse[1], impulse[2] = -mu * d_xi * jn, -mu * d_n * jn, jn
    dphi, dtheta, omega = rim.apply_impulse(theta, y[fk.DPHI], y[fk.DTHETA], y[fk.OMEGA],
                                            impulse[0], impulse[1], impulse[2], c)
    dv = rim.impulse_response(theta, impulse[0], impulse[1], impulse[2], c)
    post_xi, post_n = vp[0] + dv[0], vp[1] + dv[1]
    reach = rim.reach(theta, zc)
    x_p, y_p = y[fk.XP] + sp_ * reach, y[fk.YP] - cp * reach
    _clear_free_slots(y)
    y[fk.DPHI], y[fk.DTHETA], y[fk.OMEGA] = dphi, dtheta, omega
    y[fk.XP], y[fk.YP] = x_p, y_p
    if sliding:
        vx = post_xi * cp - post_n * sp_
        vy = post_xi * sp_ + post_n * cp
        y[fk.SLIP_SPEED] = math.hypot(vx, vy)
        y[fk.SLIP_DIR] = math.atan2(vy, vx)
    return sliding


@njit(cache=True)
def _tip_onto_rim(y, theta_c):
    """A column sliding flat with mu z_cm >= R tips onto its leading rim point (and slips)."""
    cx, sx = math.cos(y[fk.SLIP_DIR]), math.sin(y[fk.SLIP_DIR])
    # the pivot lies ahead: the direction from P to the base centre is -slip
    phi = math.atan2(cx, -sx)
    sp_, cp = fk.sincos(phi)
    bx, by = y[fk.XP], y[fk.YP]
    y[fk.PHI] = phi
    y[fk.PSI] = -phi
    y[fk.THETA] = theta_c
    y[fk.DPHI] = 0.0
    y[fk.DTHETA] = 0.0
    y[fk.OMEGA] = 0.0
    y[fk.XP] = bx + sp_ * math.cos(theta_c)
    y[fk.YP] = by - cp * math.cos(theta_c)


@njit(cache=True, nogil=True)
def run_frustum(params, restitution, y0, t_end, t_out, y_out, phase_out, t_breaks, rtol, atol, summary, impacts):
    """Run the three-dimensional frustum through the record and its tail.

    Parameters
    ----------
    params : tuple
        ``(c, record, dt, opts)`` as :func:`pipeline.dynamics.frustum.rhs`; the
        options array is used as scratch for the phase (``OPT_PHASE``).
    y0 : float64[N_STATE]
        Initial state: theta = 0 (and zero rates) starts at rest with the
        base centre at (XP, YP); theta > 0 starts rolling on the rim.
    restitution : float
        < 0: the angular-momentum impact law; otherwise theta' after a
        landing is ``restitution`` times theta' before it (the other rates
        scaled alike).
    t_end : float
        End of the run [tau] (record plus free tail).
    t_out : float64[m]
        Output times [tau], increasing, from 0.
    y_out : float64[m, N_STATE]
        Filled with the states; at rest and sliding the XP, YP slots hold the
        base centre, in flight the centre of mass.
    phase_out : int8[m]
        Filled with the phase of each output row (``PHASE_*``).
    t_breaks : float64[b]
        Sample times of the record (kinks of the forcing), no step crosses them.
    rtol, atol : float
        Integration tolerances.
    summary : float64[N_SUMMARY]
        Filled with the summary quantities (``S_*`` indices).
    impacts : float64[k, 4]
        Filled with the first k landings: time [tau], theta' before and
        after [1/tau], energy jump [m g R] (after settling, theta' after is 0).
    """
    c, record, dt, opts = params
    p = (c, record, dt, opts, summary)
    zc = c[fk.C_ZC]
    mu = opts[fk.OPT_MU]
    theta_c = opts[fk.OPT_THETA_C]
    opts[fk.OPT_RIM_HELD] = 0.0
    opts[fk.OPT_FRICTION_EXCESS] = 0.0
    ratio = departure_ratio(zc, mu)
    planar_e = restitution if restitution >= 0.0 else max(0.0, 1.0 - 2.0 / c[fk.C_IY])
    _init_summary(summary)
    y = y0.copy()  # at rest: XP, YP hold the base centre
    y_new = y0.copy()
    rotation = y0[fk.PHI] + y0[fk.PSI]  # body rotation about the vertical while at rest
    rest_energy = zc  # V at theta = 0
    settle_kinetic = _settle_kinetic(theta_c, zc, opts[fk.OPT_MIN_REBOUND])
    phase = PHASE_ROLLING if y0[fk.THETA] > 0.0 else PHASE_REST
    summary[S_ENERGY_START] = energy3d(phase, y, c)
    moving = phase  # the phase the column lies down from
    t = 0.0
    out_i = 0
    h = 0.0
    n_transitions = 0
    stalls = 0
    while n_transitions < MAX_TRANSITIONS:
        if phase == PHASE_REST:
            t_dep, out_i = _rest_until_departure(record, dt, ratio, t, t_end, t_out, y_out, phase_out, out_i,
                                                 y, summary)
            if t_dep >= t_end:
                t = t_end
                break
            t = t_dep
            h = 0.0
            n_transitions += 1
            ax, ay, az = fk.ground_acceleration(t_dep, record, dt)
            bx, by = y[fk.XP], y[fk.YP]
            work, dissipated, friction = y[fk.WORK], y[fk.DISSIPATED], y[fk.FRICTION]
            y[:] = 0.0
            y[fk.WORK], y[fk.DISSIPATED], y[fk.FRICTION] = work, dissipated, friction
            if 1.0 + az <= 0.0:  # the ground falls faster than gravity: flat flight
                y[fk.XP], y[fk.YP], y[fk.ZC] = bx, by, zc
                _first(summary, S_FLIGHT_TIME, t)
                phase = PHASE_FLIGHT
                continue
            if mu < 1.0 / zc:  # slides before it can uplift
                y[fk.XP], y[fk.YP] = bx, by
                _start_slip(y, opts, math.atan2(-ay, -ax), 1.0 + az)
                _first(summary, S_SLIDE_TIME, t)
                phase = PHASE_SLIDING
                continue
            phi = contact.uplift_azimuth(ax, ay)
            s_phi, c_phi = fk.sincos(phi)
            y[fk.PHI] = phi
            y[fk.PSI] = rotation - phi
            y[fk.THETA] = theta_c
            y[fk.XP] = bx + s_phi * math.cos(theta_c)  # pivot: opposite the acceleration
            y[fk.YP] = by - c_phi * math.cos(theta_c)
            summary[S_TRANSITION] += fk.energy(theta_c, 0.0, 0.0, 0.0, c) - rest_energy
            _first(summary, S_UPLIFT_TIME, t)
            phase = _enter_contact(t, y, p)
            if phase == PHASE_SLIPPING:
                _first(summary, S_SLIDE_TIME, t)
            continue
        opts[fk.OPT_PHASE] = phase
        if phase == PHASE_SLIPPING or phase == PHASE_SLIDING:
            _leave_layer_if_past(t, y, p, phase)
            _book_slaved_turn(t, y, p, phase)
        opts[fk.OPT_MAX_STEP] = _slaved_step(t, y, p, phase)
        res = _integrate3d(p, t, y, t_end, t_out, y_out, out_i, t_breaks, rtol, atol, h)
        out_i, stalls = _book_phase(res, phase, phase_out, out_i, summary, y, t, stalls)
        t, h = res.t, res.h_next
        _sync_direction(t, y, p, phase)
        if res.status <= 0 or stalls > MAX_STALLS:  # end, failure or stall (status in the summary)
            break
        ev = res.event_index
        if ev == EV_TURN:
            # a turning point: theta' is zero there, its 1e-17 residue is
            # round-off that could make the next call find this root again
            y[fk.DTHETA] = 0.0
            _peak(summary, t, y[fk.THETA])
            if phase != PHASE_FLIGHT and opts[fk.OPT_THETA_K] > 0.0:
                _near_contact_passage(t, y, p, phase, planar_e)
            continue
        if ev == EV_MODE:  # in or out of the slaved-direction layer (direction synced above)
            opts[fk.OPT_SLAVED] = 1.0 - opts[fk.OPT_SLAVED]
            if opts[fk.OPT_SLAVED] != 0.0:
                opts[fk.OPT_SLAVED_SPEED] = y[fk.SLIP_SPEED]
                opts[fk.OPT_PHI_REF] = y[fk.PHI]
            continue
        if ev == EV_PIVOT:  # the pivot's turning stopped, its hold gave way, or the unloaded patch loads
            if opts[fk.OPT_PIVOT_HELD] == 0.0 and opts[fk.OPT_DRILL_SIGN] != 0.0:
                # stopped: make it exact (the spin that cancels omega_Z at this tilt)
                e_before = energy3d(phase, y, c)
                y[fk.OMEGA] = -y[fk.DPHI] * math.sin(y[fk.THETA]) ** 2 / math.cos(y[fk.THETA])
                summary[S_TRANSITION] += energy3d(phase, y, c) - e_before
            if phase == PHASE_ROLLING and mu < math.inf:
                # a new drilling couple changes the friction rolling asks (a stopped pivot that
                # turns back flips it): sticking is checked again, which sets the pivot's mode
                phase = _enter_contact(t, y, p)
                if phase == PHASE_SLIPPING:
                    _first(summary, S_SLIDE_TIME, t)
                elif phase == PHASE_FLIGHT:
                    _first(summary, S_FLIGHT_TIME, t)
            else:
                _pivot_mode(t, y, p, phase)
            continue
        if ev == EV_SLIP and phase == PHASE_FLIGHT:
            # the axis passes the vertical: the same orientation is (phi + pi, -theta, psi - pi)
            y[fk.PHI] = y[fk.PHI] - math.pi if y[fk.PHI] > 0.0 else y[fk.PHI] + math.pi
            y[fk.PSI] -= math.pi
            y[fk.THETA] = -y[fk.THETA]
            y[fk.DTHETA] = -y[fk.DTHETA]
            continue
        if ev == EV_LIE:
            out_i = _lie_down(summary, t, y[fk.THETA], y, y_out, phase_out, out_i)
            moving = phase
            phase = PHASE_OVERTURNED
            break
        h = 0.0
        n_transitions += 1
        if ev == EV_SLIP:  # rolling -> slipping: against the friction sticking would need
            phase = _enter_contact(t, y, p)
            _first(summary, S_SLIDE_TIME, t)
            continue
        if ev == EV_STICK:
            if phase == PHASE_SLIPPING:
                y[fk.SLIP_SPEED] = 0.0
                phase = _enter_contact(t, y, p)
                continue
            # flat sliding stopped: rest, or sliding on in the new direction
            ax, ay, az = fk.ground_acceleration(t, record, dt)
            y[fk.SLIP_SPEED] = 0.0
            if math.hypot(ax, ay) > mu * (1.0 + az):
                _start_slip(y, opts, math.atan2(-ay, -ax), 1.0 + az)
            else:
                phase = PHASE_REST
            continue
        if ev == EV_LIFT:
            if phase == PHASE_ROLLING:
                if opts[fk.OPT_RIM_HELD] != 0.0:
                    # the hold ends: N pushes again (rolling on), or the flight now rises
                    # (whichever of -N and -gap'' reached 0, the minimum in the event function)
                    opts[fk.OPT_RIM_HELD] = 0.0
                    if _rolling_state(t, y, p)[5] >= _gap_acceleration(t, y, p):
                        continue
                elif _holds_rim(opts, _gap_acceleration(t, y, p)):
                    continue
            _first(summary, S_FLIGHT_TIME, t)
            if phase == PHASE_SLIDING:
                speed, cx, sx = y[fk.SLIP_SPEED], math.cos(y[fk.SLIP_DIR]), math.sin(y[fk.SLIP_DIR])
                y[fk.ZC] = zc
                y[fk.VX], y[fk.VY], y[fk.VZ] = speed * cx, speed * sx, 0.0
                y[fk.SLIP_SPEED] = 0.0
            else:
                _to_flight(y, c, phase == PHASE_SLIPPING)
            phase = PHASE_FLIGHT
            continue
        # EV_LAND
        if phase == PHASE_FLIGHT:
            e_before = energy3d(phase, y, c)
            if y[fk.THETA] < theta_c:
                # flat on the ground: the base stops the fall and the rotation;
                # friction takes at most mu times the vertical impulse
                speed = math.hypot(y[fk.VX], y[fk.VY])
                cx = y[fk.VX] / speed if speed > 0.0 else 1.0
                sx = y[fk.VY] / speed if speed > 0.0 else 0.0
                left = speed - mu * abs(y[fk.VZ])
                s_phi, c_phi = fk.sincos(y[fk.PHI])
                lean = zc * math.sin(y[fk.THETA])
                x, yy = y[fk.XP] - s_phi * lean, y[fk.YP] + c_phi * lean
                rotation = y[fk.PHI] + y[fk.PSI]
                work, dissipated, friction = y[fk.WORK], y[fk.DISSIPATED], y[fk.FRICTION]
                y[:] = 0.0
                y[fk.WORK], y[fk.DISSIPATED], y[fk.FRICTION] = work, dissipated, friction
                y[fk.XP], y[fk.YP] = x, yy
                if left > 0.0:
                    y[fk.SLIP_SPEED] = left
                    _az = fk.ground_acceleration(t, record, dt)[2]
                    _start_slip(y, opts, math.atan2(sx, cx), 1.0 + _az)
                    phase = PHASE_SLIDING
                    if mu * zc >= 1.0:
                        _tip_onto_rim(y, theta_c)
                        opts[fk.OPT_PHI_REF] = y[fk.PHI]
                        phase = PHASE_SLIPPING
                else:
                    phase = PHASE_REST
            else:
                slides = _touch_down_rim(y, c, mu)
                if slides:
                    _pivot_mode(t, y, p, PHASE_SLIPPING)
                    _start_slip(y, opts, y[fk.SLIP_DIR], _slip_with(t, y, p, y[fk.SLIP_DIR])[0])
                    phase = PHASE_SLIPPING
                else:
                    phase = _enter_contact(t, y, p)
            summary[S_N_IMPACTS] += 1
            e_after = energy3d(phase, y, c)
            summary[S_TRANSITION] += e_after - e_before
            _log_impact(impacts, summary, t, 0.0, y[fk.DTHETA], e_after - e_before)
            continue
        # landing near full contact
        e_before = energy3d(phase, y, c)
        theta_land = y[fk.THETA]
        slip_xi = 0.0
        slip_n = 0.0
        if phase == PHASE_SLIPPING:
            sp_, cp = fk.sincos(y[fk.PHI])
            speed, cx, sx = y[fk.SLIP_SPEED], math.cos(y[fk.SLIP_DIR]), math.sin(y[fk.SLIP_DIR])
            slip_xi = speed * (cx * cp + sx * sp_)
            slip_n = speed * (-cx * sp_ + sx * cp)
        contact.landing_impact(y, theta_land, c, y_new, slip_xi, slip_n)
        _clear_free_slots(y_new)
        if restitution >= 0.0 and y_new[fk.DTHETA] != 0.0:
            scale = restitution * abs(y[fk.DTHETA]) / y_new[fk.DTHETA]
            y_new[fk.DTHETA] *= scale
            y_new[fk.DPHI] *= scale
            y_new[fk.OMEGA] *= scale
        e_after = energy3d(PHASE_ROLLING, y_new, c)
        kinetic = e_after - fk.energy(theta_land, 0.0, 0.0, 0.0, c)
        settles = y_new[fk.DTHETA] <= 0.0 or kinetic < settle_kinetic
        if y[fk.DTHETA] != 0.0:  # touching back down with no speed at all is no impact
            summary[S_N_IMPACTS] += 1
            _log_impact(impacts, summary, t, y[fk.DTHETA], 0.0 if settles else y_new[fk.DTHETA],
                        (rest_energy if settles else e_after) - e_before)
        if settles:
            # full base contact, at rest on the ground
            s_phi, c_phi = fk.sincos(y[fk.PHI])
            rotation = y[fk.PHI] + y[fk.PSI]
            bx = y[fk.XP] - s_phi * math.cos(theta_land)
            by = y[fk.YP] + c_phi * math.cos(theta_land)
            work, dissipated, friction = y[fk.WORK], y[fk.DISSIPATED], y[fk.FRICTION]
            y[:] = 0.0
            y[fk.XP], y[fk.YP] = bx, by
            y[fk.WORK], y[fk.DISSIPATED], y[fk.FRICTION] = work, dissipated, friction
            summary[S_TRANSITION] += rest_energy - e_before
            phase = PHASE_REST
        else:
            summary[S_TRANSITION] += e_after - e_before
            y[:] = y_new
            phase = _enter_contact(t, y, p)
            if phase == PHASE_SLIPPING:
                _first(summary, S_SLIDE_TIME, t)
            elif phase == PHASE_FLIGHT:
                _first(summary, S_FLIGHT_TIME, t)
    if n_transitions >= MAX_TRANSITIONS:
        summary[S_STATUS] = -10
    summary[S_END_TIME] = t
    summary[S_FINAL_PHASE] = phase
    _close_budget(summary, energy3d(phase if phase != PHASE_OVERTURNED else moving, y, c),
                  y[fk.WORK], y[fk.DISSIPATED], y[fk.FRICTION])
    if phase == PHASE_REST or phase == PHASE_SLIDING:
        summary[S_ROTATION] = rotation
        summary[S_BASE_X], summary[S_BASE_Y] = y[fk.XP], y[fk.YP]
    else:
        s_phi, c_phi = fk.sincos(y[fk.PHI])
        summary[S_ROTATION] = y[fk.PHI] + y[fk.PSI]
        if phase == PHASE_FLIGHT:
            lean = zc * math.sin(y[fk.THETA])  # the centre of mass leans away from the base centre
            summary[S_BASE_X] = y[fk.XP] - s_phi * lean
            summary[S_BASE_Y] = y[fk.YP] + c_phi * lean
        else:
            summary[S_BASE_X] = y[fk.XP] - s_phi * math.cos(y[fk.THETA])
            summary[S_BASE_Y] = y[fk.YP] + c_phi * math.cos(y[fk.THETA])
    if summary[S_MIN_NORMAL] == math.inf:
        summary[S_MIN_NORMAL] = math.nan
    return out_i


# --- planar rocking -------------------------------------------------------------------------


@njit(cache=True)
def _rocking_couple(theta, dtheta, load, opts):
    """Rolling-damping couple of the contact patch on planar rocking [m g R], and its power."""
    theta_k = opts[fk.OPT_THETA_K]
    if theta_k <= 0.0:
        return 0.0, 0.0
    m = patch.couples(load, abs(theta), theta_k, opts[fk.OPT_PATCH_DAMPING], opts[fk.OPT_MU], dtheta, 0.0)[0]
    return m, -m * dtheta


@njit(cache=True)
def _rocking_contact(theta, dtheta, a_u, a_z, c, opts):
    """Planar rocking on a pivot that sticks: ``(F_u, N, theta'', damped)``.

    Forces per m g; the centre of mass relative to the pivot is ``(C_u, C_z)``
    (:func:`pipeline.dynamics.rocking.cm_offset`) and the contact force is
    ``F = m (C'' + a_g + g e_z)``. theta'' includes the viscous couple nu and
    the contact patch's rolling damping, whose power (with nu's) is ``damped``.
    """
    cu, cz = rk.cm_offset(theta, c[fk.C_ZC])
    nu = opts[fk.OPT_NU]
    ddtheta = rk.angular_acceleration(theta, a_u, a_z, c) - nu * dtheta / c[fk.C_IY]
    damped = nu * dtheta * dtheta
    w2 = dtheta * dtheta
    if opts[fk.OPT_THETA_K] > 0.0:
        m, power = _rocking_couple(theta, dtheta, -cu * ddtheta - cz * w2 + 1.0 + a_z, opts)
        ddtheta += m / c[fk.C_IY]
        damped += power
    f_u = cz * ddtheta - cu * w2 + a_u
    f_z = -cu * ddtheta - cz * w2 + 1.0 + a_z
    return f_u, f_z, ddtheta, damped


@njit(cache=True)
def _rocking_slip(theta, dtheta, sigma, a_u, a_z, c, opts):
    """Planar rocking on a slipping pivot with the patch's couple: ``(theta'', x'', N, damped)``."""
    mu = opts[fk.OPT_MU]
    nu = opts[fk.OPT_NU]  # the viscous couple, as rolling has it
    viscous = -nu * dtheta
    ddtheta, ddx, normal, _den = rk.slip_accelerations(theta, dtheta, sigma, mu, a_u, a_z, c, viscous)
    if opts[fk.OPT_THETA_K] <= 0.0:
        return ddtheta, ddx, normal, nu * dtheta * dtheta
    m, power = _rocking_couple(theta, dtheta, normal, opts)
    ddtheta, ddx, normal, _den = rk.slip_accelerations(theta, dtheta, sigma, mu, a_u, a_z, c, m + viscous)
    return ddtheta, ddx, normal, power + nu * dtheta * dtheta


@njit(cache=True)
def _rhs2d_slipping(t, y, params, dydt):
    c, record, dt, opts = params[0], params[1], params[2], params[3]
    a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
    mu = opts[fk.OPT_MU]
    theta, dtheta = y[rk.THETA2], y[rk.DTHETA2]
    ddtheta, ddx, normal, damped = _rocking_slip(theta, dtheta, opts[fk.OPT_SIGN], a_u, a_z, c, opts)
    v_u, v_z = rk.cm_velocity(theta, dtheta, y[rk.V2], c[fk.C_ZC])
    for i in range(dydt.shape[0]):
        dydt[i] = 0.0
    dydt[rk.THETA2] = dtheta
    dydt[rk.DTHETA2] = ddtheta
    dydt[rk.X2] = y[rk.V2]
    dydt[rk.V2] = ddx
    dydt[rk.WORK2] = -a_u * v_u - a_z * v_z
    dydt[rk.DISSIPATED2] = damped
    # sigma v, not |v|: the same while slipping, and smooth through the stick, which
    # the last step crosses before the event is located on its interpolant (|v| put a
    # kink there: up to 1.5e-5 of the work lost in 34 of 38720 2D runs)
    dydt[rk.FRICTION2] = mu * normal * opts[fk.OPT_SIGN] * y[rk.V2]


@njit(cache=True)
def _rhs2d_rolling(t, y, params, dydt):
    c, record, dt, opts = params[0], params[1], params[2], params[3]
    a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
    theta, dtheta = y[rk.THETA2], y[rk.DTHETA2]
    _f_u, _f_z, ddtheta, damped = _rocking_contact(theta, dtheta, a_u, a_z, c, opts)
    v_u, v_z = rk.cm_velocity(theta, dtheta, 0.0, c[fk.C_ZC])
    for i in range(dydt.shape[0]):
        dydt[i] = 0.0
    dydt[rk.THETA2] = dtheta
    dydt[rk.DTHETA2] = ddtheta
    dydt[rk.WORK2] = -a_u * v_u - a_z * v_z
    dydt[rk.DISSIPATED2] = damped


@njit(cache=True)
def rhs2d(t, y, params, dydt):
    """Right-hand side of the phase ``params[3][OPT_PHASE]`` (planar rocking)."""
    record, dt, opts = params[1], params[2], params[3]
    phase = opts[fk.OPT_PHASE]
    if phase == PHASE_ROLLING:
        _rhs2d_rolling(t, y, params, dydt)
        return
    if phase == PHASE_SLIPPING:
        _rhs2d_slipping(t, y, params, dydt)
        return
    a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
    for i in range(dydt.shape[0]):
        dydt[i] = 0.0
    dydt[rk.X2] = y[rk.V2]
    if phase == PHASE_FLIGHT:
        dydt[rk.THETA2] = y[rk.DTHETA2]
        dydt[rk.V2] = -a_u
        dydt[rk.Z2] = y[rk.VZ2]
        dydt[rk.VZ2] = -1.0 - a_z
        dydt[rk.WORK2] = -a_u * y[rk.V2] - a_z * y[rk.VZ2]
    else:  # sliding flat
        mu = opts[fk.OPT_MU]
        dydt[rk.V2] = -a_u - mu * (1.0 + a_z) * opts[fk.OPT_SIGN]
        dydt[rk.WORK2] = -a_u * y[rk.V2]
        dydt[rk.FRICTION2] = mu * (1.0 + a_z) * opts[fk.OPT_SIGN] * y[rk.V2]  # smooth at the stop


@njit(cache=True)
def events2d(t, y, params, g):
    """Event functions of the current phase, planar rocking (``EV_*``)."""
    c, record, dt, opts = params[0], params[1], params[2], params[3]
    phase = opts[fk.OPT_PHASE]
    for i in range(g.shape[0]):
        g[i] = 1.0
    a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
    if phase == PHASE_SLIDING:
        g[EV_LIFT] = 1.0 + a_z
        g[EV_STICK] = opts[fk.OPT_SIGN] * y[rk.V2]
        return
    theta = y[rk.THETA2]
    g[EV_LIE] = abs(theta) - opts[fk.OPT_THETA_LIE]
    g[EV_TURN] = y[rk.DTHETA2]
    if phase == PHASE_FLIGHT:
        g[EV_LAND] = y[rk.Z2] - rk.cm_offset(theta, c[fk.C_ZC])[1]
        return
    # signed with the pivot side, so that theta_c = 0 is a crossing too
    g[EV_LAND] = opts[fk.OPT_PIVOT] * theta - (1.0 - opts[fk.OPT_LANDING_MARGIN]) * opts[fk.OPT_THETA_C]
    unilateral = opts[fk.OPT_UNILATERAL] != 0.0
    if phase == PHASE_ROLLING:
        f_u, f_z, _dd, _p = _rocking_contact(theta, y[rk.DTHETA2], a_u, a_z, c, opts)
        if opts[fk.OPT_RIM_HELD] != 0.0:  # falls through 0 when N pushes again or the flight would rise
            g[EV_LIFT] = min(-f_z, -flight_gap_acceleration2d(theta, y[rk.DTHETA2], a_z, c))
        elif unilateral:
            g[EV_LIFT] = f_z
        if opts[fk.OPT_MU] < math.inf:
            g[EV_SLIP] = opts[fk.OPT_MU] * f_z - abs(f_u)
    else:
        if unilateral:
            g[EV_LIFT] = _rocking_slip(theta, y[rk.DTHETA2], opts[fk.OPT_SIGN], a_u, a_z, c, opts)[2]
        g[EV_STICK] = opts[fk.OPT_SIGN] * y[rk.V2]


@njit(cache=True)
def monitor2d(t, y, params, g):
    """Peak mobilized friction and lowest normal force at every accepted step (planar).

    The event functions there (``g``) already hold N and ``mu N - |F_u|``.
    """
    c, record, dt, opts, summary = params[0], params[1], params[2], params[3], params[4]
    phase = opts[fk.OPT_PHASE]
    mu = opts[fk.OPT_MU]
    fast = opts[fk.OPT_UNILATERAL] != 0.0 and mu < math.inf
    if phase == PHASE_ROLLING:
        if fast:
            normal = g[EV_LIFT]
            f_t = mu * normal - g[EV_SLIP]
        else:
            a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
            f_u, normal, _dd, _p = _rocking_contact(y[rk.THETA2], y[rk.DTHETA2], a_u, a_z, c, opts)
            f_t = abs(f_u)
        _watch(summary, f_t / normal if normal > 0.0 else 0.0, normal)
    elif phase == PHASE_SLIPPING:
        if fast:
            normal = g[EV_LIFT]
        else:
            a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
            normal = _rocking_slip(y[rk.THETA2], y[rk.DTHETA2], opts[fk.OPT_SIGN], a_u, a_z, c, opts)[2]
        _watch(summary, mu, normal)
    elif phase == PHASE_SLIDING:
        _watch(summary, mu, g[EV_LIFT])
    elif phase == PHASE_FLIGHT:
        _watch(summary, 0.0, 0.0)


@njit(cache=True)
def _integrate2d(params, t0, y0, t_end, t_out, y_out, out_start, t_breaks, rtol, atol, h0):
    return dop853_monitored(rhs2d, events2d, monitor2d, params, t0, y0, t_end, t_out, y_out, out_start,
                            EVENT_DIRECTIONS, t_breaks, rtol, atol, np.inf, h0, MAX_STEPS)


@njit(cache=True)
def energy2d(phase, y, c):
    """Mechanical energy [m g R] of a planar state in a given phase."""
    zc = c[fk.C_ZC]
    if phase == PHASE_REST:
        return zc
    if phase == PHASE_SLIDING:
        return zc + 0.5 * y[rk.V2] * y[rk.V2]
    theta, dtheta = y[rk.THETA2], y[rk.DTHETA2]
    if phase == PHASE_FLIGHT:
        return rk.energy_moving(theta, dtheta, y[rk.V2], y[rk.VZ2], y[rk.Z2], c)
    if phase == PHASE_SLIPPING:
        v_u, v_z = rk.cm_velocity(theta, dtheta, y[rk.V2], zc)
        return rk.energy_moving(theta, dtheta, v_u, v_z, rk.cm_offset(theta, zc)[1], c)
    return rk.energy(theta, dtheta, c)


@njit(cache=True)
def _clear_free_slots2d(y):
    y[rk.V2] = 0.0
    y[rk.Z2] = 0.0
    y[rk.VZ2] = 0.0


@njit(cache=True)
def _down_on_base2d(y, side):
    """A planar state on its pivot (side ``side``) laid flat: the base centre in X2, no tilt, no rates."""
    _clear_free_slots2d(y)
    y[rk.X2] -= side * math.cos(y[rk.THETA2])  # pivot -> base centre
    y[rk.THETA2] = 0.0
    y[rk.DTHETA2] = 0.0


@njit(cache=True)
def flight_gap_acceleration2d(theta, dtheta, a_z, c):
    """Planar :func:`flight_gap_acceleration`: the free column does not turn (theta'' = 0)."""
    return -1.0 - a_z + rk.cm_offset(theta, c[fk.C_ZC])[1] * dtheta * dtheta


@njit(cache=True)
def _enter_contact2d(t, y, params):
    """Rolling, slipping (direction in OPT_SIGN) or flight for a planar state whose pivot sticks.

    The pivot side is ``OPT_PIVOT``, set by the caller (theta may be a signed zero).
    """
    c, record, dt, opts = params[0], params[1], params[2], params[3]
    a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
    f_u, f_z, ddtheta, _p = _rocking_contact(y[rk.THETA2], y[rk.DTHETA2], a_u, a_z, c, opts)
    step = opts[fk.OPT_LOOK_AHEAD]
    b_u, _unused, b_z = fk.ground_acceleration(t + step, record, dt)
    theta_ahead = y[rk.THETA2] + step * y[rk.DTHETA2]
    rate_ahead = y[rk.DTHETA2] + step * ddtheta
    g_u, g_z, _dd, _p = _rocking_contact(theta_ahead, rate_ahead, b_u, b_z, c, opts)
    unilateral = opts[fk.OPT_UNILATERAL] != 0.0
    mu = opts[fk.OPT_MU]
    opts[fk.OPT_RIM_HELD] = 0.0
    y[rk.V2] = 0.0
    pushes = (f_z >= 0.0 and g_z >= 0.0) or not unilateral
    if pushes and (mu == math.inf or (abs(f_u) <= mu * f_z and abs(g_u) <= mu * g_z)):
        return PHASE_ROLLING
    if mu < math.inf:
        # sticking fails: slipping against the friction it would need, if the plane then pushes
        sigma = -1.0 if f_u > 0.0 else 1.0
        normal = _rocking_slip(y[rk.THETA2], y[rk.DTHETA2], sigma, a_u, a_z, c, opts)[2]
        if normal >= 0.0 or not unilateral:
            opts[fk.OPT_SIGN] = sigma
            return PHASE_SLIPPING
    if not unilateral or _holds_rim(opts, flight_gap_acceleration2d(y[rk.THETA2], y[rk.DTHETA2], a_z, c)):
        return PHASE_ROLLING
    _to_flight2d(y, c)
    return PHASE_FLIGHT


@njit(cache=True)
def _to_flight2d(y, c):
    """Pivot contact -> flight: the centre of mass, its height and velocity."""
    cu, cz = rk.cm_offset(y[rk.THETA2], c[fk.C_ZC])
    v_u, v_z = rk.cm_velocity(y[rk.THETA2], y[rk.DTHETA2], y[rk.V2], c[fk.C_ZC])
    y[rk.X2] += cu
    y[rk.V2] = v_u
    y[rk.Z2] = cz
    y[rk.VZ2] = v_z


@njit(cache=True)
def _touch_down_corner(y, c, mu):
    """Plastic impact of a flying column on its lowest base corner, with Coulomb friction.

    Writes the pivot state after the impact; returns the slip velocity of the
    pivot (0 if it sticks).
    """
    theta = y[rk.THETA2]
    cu, cz = rk.cm_offset(theta, c[fk.C_ZC])
    dtheta = y[rk.DTHETA2]
    vp_u = y[rk.V2] - dtheta * cz
    vp_z = y[rk.VZ2] + dtheta * cu
    a11, a21, _w = rk.pivot_impulse_response(theta, 1.0, 0.0, c)
    a12, a22, _w = rk.pivot_impulse_response(theta, 0.0, 1.0, c)
    det = a11 * a22 - a12 * a21
    j_u = (-vp_u * a22 + vp_z * a12) / det
    j_z = (-vp_z * a11 + vp_u * a21) / det
    if mu < math.inf and abs(j_u) > mu * j_z:
        sense = 1.0 if vp_u > 0.0 else -1.0
        u_u, u_z, _w = rk.pivot_impulse_response(theta, -mu * sense, 1.0, c)
        j_z = -vp_z / u_z
        j_u = -mu * sense * j_z
    du, _dz, dw = rk.pivot_impulse_response(theta, j_u, j_z, c)
    slip = vp_u + du
    if mu == math.inf or abs(j_u) < mu * j_z:
        slip = 0.0
    x_c = y[rk.X2]
    _clear_free_slots2d(y)
    y[rk.DTHETA2] = dtheta + dw
    y[rk.X2] = x_c - cu
    y[rk.V2] = slip
    return slip


@njit(cache=True, nogil=True)
def run_rocking(params, restitution, y0, t_end, t_out, y_out, phase_out, t_breaks, rtol, atol, summary, impacts):
    """Run classical planar rocking, with sliding and flight; arguments as :func:`run_frustum`.

    The record's column 0 is the acceleration along the plane's direction u;
    ``y_out`` has ``N_STATE2`` columns (:mod:`pipeline.dynamics.rocking`). A
    negative ``restitution`` selects the angular-momentum value
    ``1 - 2 / Iy`` (clipped at 0).
    """
    c, record, dt, opts = params
    p = (c, record, dt, opts, summary)
    zc = c[fk.C_ZC]
    mu = opts[fk.OPT_MU]
    theta_c = opts[fk.OPT_THETA_C]
    opts[fk.OPT_RIM_HELD] = 0.0
    ratio = departure_ratio(zc, mu)
    e = restitution if restitution >= 0.0 else max(0.0, 1.0 - 2.0 / c[fk.C_IY])
    _init_summary(summary)
    y = y0.copy()
    rest_energy = zc
    settle_kinetic = _settle_kinetic(theta_c, zc, opts[fk.OPT_MIN_REBOUND])
    phase = PHASE_REST
    if y0[rk.THETA2] != 0.0:
        phase = PHASE_ROLLING
        opts[fk.OPT_PIVOT] = math.copysign(1.0, y0[rk.THETA2])
    summary[S_ENERGY_START] = energy2d(phase, y, c)
    moving = phase
    t = 0.0
    out_i = 0
    h = 0.0
    n_transitions = 0
    stalls = 0
    while n_transitions < MAX_TRANSITIONS:
        if phase == PHASE_REST:
            t_dep, out_i = _rest_until_departure(record, dt, ratio, t, t_end, t_out, y_out, phase_out, out_i,
                                                 y, summary)
            if t_dep >= t_end:
                t = t_end
                break
            t = t_dep
            h = 0.0
            n_transitions += 1
            a_u, _unused, a_z = fk.ground_acceleration(t_dep, record, dt)
            _clear_free_slots2d(y)
            y[rk.THETA2] = 0.0
            y[rk.DTHETA2] = 0.0
            if 1.0 + a_z <= 0.0:
                y[rk.Z2] = zc
                _first(summary, S_FLIGHT_TIME, t)
                phase = PHASE_FLIGHT
                continue
            # the inertial force -a_u pushes towards -u
            toward = -1.0 if a_u > 0.0 else 1.0
            if mu < 1.0 / zc:
                opts[fk.OPT_SIGN] = toward
                _first(summary, S_SLIDE_TIME, t)
                phase = PHASE_SLIDING
                continue
            y[rk.THETA2] = toward * theta_c  # a signed zero when theta_c = 0
            y[rk.X2] += toward * math.cos(theta_c)  # the pivot on that side of the base
            opts[fk.OPT_PIVOT] = toward
            summary[S_TRANSITION] += rk.energy(theta_c, 0.0, c) - rest_energy
            _first(summary, S_UPLIFT_TIME, t)
            phase = _enter_contact2d(t, y, p)
            if phase == PHASE_SLIPPING:
                _first(summary, S_SLIDE_TIME, t)
            continue
        opts[fk.OPT_PHASE] = phase
        res = _integrate2d(p, t, y, t_end, t_out, y_out, out_i, t_breaks, rtol, atol, h)
        out_i, stalls = _book_phase(res, phase, phase_out, out_i, summary, y, t, stalls)
        t, h = res.t, res.h_next
        if res.status <= 0 or stalls > MAX_STALLS:
            break
        ev = res.event_index
        theta = abs(y[rk.THETA2])
        if ev == EV_TURN:
            y[rk.DTHETA2] = 0.0  # exactly a turning point (see run_frustum)
            _peak(summary, t, theta)
            if phase == PHASE_ROLLING and theta < (1.0 - opts[fk.OPT_LANDING_MARGIN]) * theta_c:
                # at rest below the tilt of full contact (reached without a landing, e.g.
                # tipped from sliding at mu = R / z_cm): the base is down. Rocking on there
                # turned every 2.5e-5 s at 1e-11 rad and never ended (FEMA-FF-13, squat cylinder)
                summary[S_TRANSITION] += rest_energy - energy2d(phase, y, c)
                _down_on_base2d(y, opts[fk.OPT_PIVOT])
                phase = PHASE_REST
            continue
        if ev == EV_LIE:
            out_i = _lie_down(summary, t, theta, y, y_out, phase_out, out_i)
            moving = phase
            phase = PHASE_OVERTURNED
            break
        h = 0.0
        n_transitions += 1
        if ev == EV_SLIP:
            phase = _enter_contact2d(t, y, p)
            _first(summary, S_SLIDE_TIME, t)
            continue
        if ev == EV_STICK:
            y[rk.V2] = 0.0
            if phase == PHASE_SLIPPING:
                phase = _enter_contact2d(t, y, p)
                continue
            a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
            if abs(a_u) > mu * (1.0 + a_z):
                opts[fk.OPT_SIGN] = -1.0 if a_u > 0.0 else 1.0
            else:
                phase = PHASE_REST
            continue
        if ev == EV_LIFT:
            if phase == PHASE_ROLLING:
                if opts[fk.OPT_RIM_HELD] != 0.0:
                    # the hold ends: N pushes again (rolling on), or the flight now rises
                    # (whichever of -N and -gap'' reached 0, the minimum in the event function)
                    opts[fk.OPT_RIM_HELD] = 0.0
                    a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
                    if (_rocking_contact(y[rk.THETA2], y[rk.DTHETA2], a_u, a_z, c, opts)[1]
                            >= flight_gap_acceleration2d(y[rk.THETA2], y[rk.DTHETA2], a_z, c)):
                        continue
                elif _holds_rim(opts, flight_gap_acceleration2d(
                        y[rk.THETA2], y[rk.DTHETA2], fk.ground_acceleration(t, record, dt)[2], c)):
                    continue
            _first(summary, S_FLIGHT_TIME, t)
            if phase == PHASE_SLIDING:
                y[rk.Z2] = zc
                y[rk.VZ2] = 0.0
            else:
                _to_flight2d(y, c)
            phase = PHASE_FLIGHT
            continue
        # EV_LAND
        e_before = energy2d(phase, y, c)
        if phase == PHASE_FLIGHT:
            summary[S_N_IMPACTS] += 1
            if theta < theta_c:
                left = abs(y[rk.V2]) - mu * abs(y[rk.VZ2])
                sense = 1.0 if y[rk.V2] > 0.0 else -1.0
                y[rk.X2] -= zc * math.sin(y[rk.THETA2])  # centre of mass -> base centre
                y[rk.THETA2] = 0.0
                y[rk.DTHETA2] = 0.0
                _clear_free_slots2d(y)
                if left > 0.0:
                    y[rk.V2] = sense * left
                    opts[fk.OPT_SIGN] = sense
                    phase = PHASE_SLIDING
                    if mu * zc >= 1.0:  # tips onto the leading corner
                        y[rk.THETA2] = sense * theta_c
                        y[rk.X2] += sense * math.cos(theta_c)
                        opts[fk.OPT_PIVOT] = sense
                        phase = PHASE_SLIPPING
                else:
                    phase = PHASE_REST
            else:
                opts[fk.OPT_PIVOT] = math.copysign(1.0, y[rk.THETA2])
                slip = _touch_down_corner(y, c, mu)
                if slip != 0.0:
                    opts[fk.OPT_SIGN] = 1.0 if slip > 0.0 else -1.0
                    phase = PHASE_SLIPPING
                else:
                    phase = _enter_contact2d(t, y, p)
            e_after = energy2d(phase, y, c)
            summary[S_TRANSITION] += e_after - e_before
            _log_impact(impacts, summary, t, 0.0, y[rk.DTHETA2], e_after - e_before)
            continue
        # landing near full contact: pivot to the other rim point, theta' scaled by e
        new_rate = e * y[rk.DTHETA2]
        kinetic = 0.5 * c[fk.C_IY] * new_rate * new_rate
        settles = kinetic < settle_kinetic
        e_after = rk.energy(theta, new_rate, c)
        if y[rk.DTHETA2] != 0.0:  # touching back down with no speed at all is no impact
            summary[S_N_IMPACTS] += 1
            _log_impact(impacts, summary, t, y[rk.DTHETA2], 0.0 if settles else new_rate,
                        (rest_energy if settles else e_after) - e_before)
        side = opts[fk.OPT_PIVOT]
        if settles:
            summary[S_TRANSITION] += rest_energy - e_before
            _down_on_base2d(y, side)
            phase = PHASE_REST
        else:
            summary[S_TRANSITION] += e_after - e_before
            _clear_free_slots2d(y)
            y[rk.X2] -= 2.0 * side * math.cos(y[rk.THETA2])  # to the other rim point, across the base
            # the other rim point: its side explicitly (theta ~ 0 has no reliable sign)
            opts[fk.OPT_PIVOT] = -side
            y[rk.THETA2] = math.copysign(abs(y[rk.THETA2]), -side)
            y[rk.DTHETA2] = new_rate
            phase = _enter_contact2d(t, y, p)
            if phase == PHASE_SLIPPING:
                _first(summary, S_SLIDE_TIME, t)
            elif phase == PHASE_FLIGHT:
                _first(summary, S_FLIGHT_TIME, t)
    if n_transitions >= MAX_TRANSITIONS:
        summary[S_STATUS] = -10
    summary[S_END_TIME] = t
    summary[S_FINAL_PHASE] = phase
    _close_budget(summary, energy2d(phase if phase != PHASE_OVERTURNED else moving, y, c),
                  y[rk.WORK2], y[rk.DISSIPATED2], y[rk.FRICTION2])
    if phase == PHASE_REST or phase == PHASE_SLIDING:
        summary[S_BASE_X] = y[rk.X2]
    elif phase == PHASE_FLIGHT:
        summary[S_BASE_X] = y[rk.X2] - zc * math.sin(y[rk.THETA2])
    else:
        summary[S_BASE_X] = y[rk.X2] - opts[fk.OPT_PIVOT] * math.cos(y[rk.THETA2])
    if summary[S_MIN_NORMAL] == math.inf:
        summary[S_MIN_NORMAL] = math.nan
    return out_i


# --- per-row diagnostics --------------------------------------------------------------------

(
    D_OMEGA,  # spin omega_zeta [1/tau]
    D_ENERGY,  # [m g R]
    D_NORMAL,  # normal force [m g]
    D_TANGENTIAL,  # |F_t| [m g]
    D_MU,  # |F_t| / N, nan in flight
    D_AX,  # ground acceleration [g]
    D_AY,
    D_AZ,
    D_BASE_X,  # base centre relative to the ground [R]
    D_BASE_Y,
    D_CONTACT_X,  # contact point on the rim, nan unless on the rim [R]
    D_CONTACT_Y,
    D_SLIP,  # speed of the sliding base or rim point [sqrt(g R)]
) = range(13)
N_DIAGNOSTICS = 13


@njit(cache=True, nogil=True)
def diagnostics_rows(tau, states, phase, params, model_3d, out):
    """Derived quantities of every output row (compiled loop), written to ``out`` (``D_*`` columns).

    Rows after the column lies down, or never reached, get NaN forces.
    """
    c, record, dt, opts = params
    zc = c[fk.C_ZC]
    mu = opts[fk.OPT_MU]
    for i in range(tau.shape[0]):
        t = tau[i]
        ax, ay, az = fk.ground_acceleration(t, record, dt)
        y = states[i]
        ph = phase[i]
        for k in range(N_DIAGNOSTICS):
            out[i, k] = math.nan
        out[i, D_AX], out[i, D_AY], out[i, D_AZ] = ax, ay, az
        out[i, D_SLIP] = 0.0
        if math.isnan(y[0]):
            continue
        if ph == PHASE_REST or ph == PHASE_SLIDING:
            normal = 1.0 + az
            out[i, D_OMEGA] = 0.0
            out[i, D_NORMAL] = normal
            out[i, D_BASE_X] = y[fk.XP] if model_3d else y[rk.X2]
            out[i, D_BASE_Y] = y[fk.YP] if model_3d else 0.0
            if ph == PHASE_REST:
                out[i, D_ENERGY] = zc
                out[i, D_TANGENTIAL] = math.sqrt(ax * ax + ay * ay)
            else:
                out[i, D_ENERGY] = energy3d(ph, y, c) if model_3d else energy2d(ph, y, c)
                out[i, D_TANGENTIAL] = mu * normal
                out[i, D_SLIP] = y[fk.SLIP_SPEED] if model_3d else abs(y[rk.V2])
            out[i, D_MU] = out[i, D_TANGENTIAL] / normal if normal > 0.0 else math.nan
            continue
        if ph == PHASE_OVERTURNED:
            continue
        if model_3d:
            _diagnose3d(t, y, ph, (c, record, dt, opts), out[i])
        else:
            _diagnose2d(t, y, ph, (c, record, dt, opts), out[i])


@njit(cache=True)
def _pivot_from_row(y, opts):
    """The drilling state of an output row, from its turning about the vertical through P."""
    om_z = _horizontal_spin(y[fk.THETA], y[fk.DPHI], y[fk.DTHETA], y[fk.OMEGA])[2]
    scale = abs(y[fk.DPHI]) + abs(y[fk.OMEGA]) + abs(y[fk.DTHETA])
    held = opts[fk.OPT_THETA_K] > 0.0 and abs(om_z) <= 1e-9 * scale
    opts[fk.OPT_PIVOT_HELD] = 1.0 if held else 0.0
    opts[fk.OPT_DRILL_SIGN] = 0.0 if held or opts[fk.OPT_THETA_K] <= 0.0 else math.copysign(1.0, om_z)


@njit(cache=True)
def _row_direction(t, y, params):
    """Slip direction of an output row: stored, or slaved (consistent) inside the slow layer."""
    normal = _slip_with(t, y, params, y[fk.SLIP_DIR])[0]
    if y[fk.SLIP_SPEED] >= _layer_edge(y, params[3], normal):
        return y[fk.SLIP_DIR]
    return consistent_direction(t, y, params, y[fk.SLIP_DIR])


@njit(cache=True)
def _diagnose3d(t, y, ph, params, row):
    c = params[0]
    zc = c[fk.C_ZC]
    theta = y[fk.THETA]
    sp_, cp = fk.sincos(y[fk.PHI])
    row[D_OMEGA] = y[fk.OMEGA]
    if ph == PHASE_SLIPPING:
        synced = y.copy()
        synced[fk.SLIP_DIR] = _row_direction(t, y, params)
        row[D_ENERGY] = energy3d(ph, synced, c)
    else:
        row[D_ENERGY] = energy3d(ph, y, c)
    if ph == PHASE_FLIGHT:
        lean = zc * math.sin(theta)
        row[D_BASE_X] = y[fk.XP] - sp_ * lean
        row[D_BASE_Y] = y[fk.YP] + cp * lean
        row[D_NORMAL] = 0.0
        row[D_TANGENTIAL] = 0.0
        return
    row[D_BASE_X] = y[fk.XP] - sp_ * math.cos(theta)
    row[D_BASE_Y] = y[fk.YP] + cp * math.cos(theta)
    row[D_CONTACT_X] = y[fk.XP]
    row[D_CONTACT_Y] = y[fk.YP]
    if ph == PHASE_ROLLING:
        # the pivot was held where the column does not turn about the vertical through P
        _pivot_from_row(y, params[3])
        f_xi, f_n, f_z, _ax, _ay, _az = _rolling_contact(t, y, params)
        f_t = math.sqrt(f_xi * f_xi + f_n * f_n)
    else:
        f_z = _slip_with(t, y, params, synced[fk.SLIP_DIR])[0]
        f_t = params[3][fk.OPT_MU] * f_z
        row[D_SLIP] = y[fk.SLIP_SPEED]
    row[D_NORMAL] = f_z
    row[D_TANGENTIAL] = f_t
    row[D_MU] = f_t / f_z if f_z > 0.0 else math.nan


@njit(cache=True)
def _diagnose2d(t, y, ph, params, row):
    c, record, dt, opts = params
    zc = c[fk.C_ZC]
    theta = y[rk.THETA2]
    row[D_OMEGA] = 0.0
    row[D_ENERGY] = energy2d(ph, y, c)
    row[D_BASE_Y] = 0.0
    if ph == PHASE_FLIGHT:
        row[D_BASE_X] = y[rk.X2] - zc * math.sin(theta)
        row[D_NORMAL] = 0.0
        row[D_TANGENTIAL] = 0.0
        return
    side = math.copysign(1.0, theta)
    row[D_BASE_X] = y[rk.X2] - side * math.cos(theta)
    row[D_CONTACT_X] = y[rk.X2]
    row[D_CONTACT_Y] = 0.0
    a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
    if ph == PHASE_ROLLING:
        f_u, f_z, _dd, _p = _rocking_contact(theta, y[rk.DTHETA2], a_u, a_z, c, opts)
        f_t = abs(f_u)
    else:
        f_z = _rocking_slip(theta, y[rk.DTHETA2], math.copysign(1.0, y[rk.V2]), a_u, a_z, c, opts)[2]
        f_t = opts[fk.OPT_MU] * f_z
        row[D_SLIP] = abs(y[rk.V2])
    row[D_NORMAL] = f_z
    row[D_TANGENTIAL] = f_t
    row[D_MU] = f_t / f_z if f_z > 0.0 else math.nan
