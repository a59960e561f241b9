"""The three-dimensional frustum's event-driven run: transitions, impacts and the loop (compiled).

:func:`run_frustum` runs one column through one record and its tail: at rest
until the column departs, then each phase of
:mod:`pipeline.dynamics.rigid.phases3d` integrated up to its first event, and
at each event the map to the next phase: a slip against the friction that
sticking would need (:func:`_enter_contact`), a lift-off, a plastic
touch-down on the rim with Coulomb friction, a landing near full contact (the
angular-momentum impact of :mod:`pipeline.dynamics.rigid.contact`), a partial
slap at a passage near full contact, the drilling pivot held or let go, the
slaved slip direction's layer entered or left. Every jump of mechanical energy
is booked in ``summary[S_TRANSITION]``. The loop itself is
:func:`pipeline.dynamics.rigid.loop.run_events`, shared with planar rocking;
this module gives it the 3D parts: the departure from rest, the phase's
integration, the maps at events and the summary's end.
"""

import math

import numpy as np
from numba import njit

from pipeline.dynamics.rigid import frustum as fk
from pipeline.dynamics.rigid import contact
from pipeline.dynamics.rigid import rim
from pipeline.dynamics.rigid.layout import (
    EV_LIFT, EV_MODE, EV_PIVOT, EV_SLIP, EV_STICK, EV_TURN, PHASE_FLIGHT, PHASE_REST, PHASE_ROLLING, PHASE_SLIDING,
    PHASE_SLIPPING, S_BASE_X, S_BASE_Y, S_FLIGHT_TIME, S_N_IMPACTS, S_ROTATION, S_SLIDE_TIME, S_TRANSITION,
    S_UPLIFT_TIME
)
from pipeline.dynamics.rigid.loop import book_peak, first_time, holds_rim, log_impact, note_entry, run_events
from pipeline.dynamics.rigid.phases3d import (
    along_slip, consistent_direction, contact_margins, energy3d, flat_direction, flight_gap_acceleration,
    horizontal_spin, integrate3d, layer_edge, layer_exit, rhs_rolling, rhs_sliding, rhs_slipping, rolling_contact,
    rolling_state, slip_direction, slip_setting, slip_state, slip_with, sticking_slip_direction
)


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
    opts[fk.OPT_SLAVED] = 1.0 if y[fk.SLIP_SPEED] < layer_edge(y, opts, normal) else 0.0
    opts[fk.OPT_SLAVED_SPEED] = y[fk.SLIP_SPEED]


@njit(cache=True)
def _slip_reading(t, y, params, phase):
    """Normal force [m g] and the slip speed's rate [g] of a slip phase (rim or flat) in the direction in use."""
    if phase == PHASE_SLIPPING:
        r = slip_state(t, y, params)
        return r[0], r[15] * r[8] + r[16] * r[9]  # rhs_slipping's SLIP_SPEED rate
    rate = np.empty(y.shape[0])
    rhs_sliding(t, y, params, rate)
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
    if y[fk.SLIP_SPEED] > layer_exit(layer_edge(y, opts, normal), opts):
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
    exit_speed = layer_exit(layer_edge(y, opts, normal), opts)
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
            y[fk.SLIP_DIR] = slip_direction(t, y, params)
        elif phase == PHASE_SLIDING:
            y[fk.SLIP_DIR] = flat_direction(t, y, params)
    # the slaved direction is sought near the stored one, turned with the precession since
    opts[fk.OPT_PHI_REF] = y[fk.PHI]


@njit(cache=True)
def _ahead(t, y, params, phase=PHASE_ROLLING):
    """The state a look-ahead later (one Euler step, ``OPT_LOOK_AHEAD``), rolling or slipping."""
    ahead = y.copy()
    rate = np.empty(y.shape[0])
    if phase == PHASE_SLIPPING:
        rhs_slipping(t, y, params, rate)
    else:
        rhs_rolling(t, y, params, rate)
    step = params[3][fk.OPT_LOOK_AHEAD]
    for i in range(rate.shape[0]):
        ahead[i] += step * rate[i]
    return ahead


@njit(cache=True)
def _drill_demand(t, y, params, phase):
    """The drilling couple and its limit [m g R] of the phase (rolling or slipping) at t."""
    if phase == PHASE_SLIPPING:
        r = slip_state(t, y, params)
        return r[18], r[19]
    r = rolling_state(t, y, params)
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
    om_z = horizontal_spin(y[fk.THETA], y[fk.DPHI], y[fk.DTHETA], y[fk.OMEGA])[2]
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
    if along_slip(t, y, params, slip_direction(t, y, params), slip_setting(t, y, params)) >= 0.0:
        return True
    later = t + params[3][fk.OPT_LOOK_AHEAD]
    guess = chi + (ahead[fk.PHI] - y[fk.PHI])
    return along_slip(later, ahead, params, consistent_direction(later, ahead, params, guess, True),
                  slip_setting(later, ahead, params)) >= 0.0


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
    f_xi, f_n, f_z, _ax, _ay, _az = rolling_contact(t, y, params)
    # a bound that holds now but is being left (N or the margin falling
    # through 0 within the integrator's restart window) would go unseen
    ahead = _ahead(t, y, params)
    g_xi, g_n, g_z, _ax, _ay, _az = rolling_contact(t + opts[fk.OPT_LOOK_AHEAD], ahead, params)
    unilateral = opts[fk.OPT_UNILATERAL] != 0.0
    pushes = (f_z >= 0.0 and g_z >= 0.0) or not unilateral
    if pushes and (mu == math.inf or (math.sqrt(f_xi * f_xi + f_n * f_n) <= mu * f_z
                                      and math.sqrt(g_xi * g_xi + g_n * g_n) <= mu * g_z)):
        return PHASE_ROLLING
    if mu < math.inf:
        # sticking fails (friction or a pulling normal force): slipping against
        # the friction it would need, if the plane then pushes
        chi = sticking_slip_direction(y[fk.PHI], f_xi, f_n)
        normal = slip_with(t, y, params, chi)[0]
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
    if not unilateral:
        return PHASE_ROLLING
    # no contact the model allows: a flight if it rises, else the rim held (loop.holds_rim); a
    # flight that started sinking would never see its landing (the gap starts at 0, falling)
    gap = _gap_acceleration(t, y, params)
    if gap < 0.0 and mu < math.inf:
        # one the model allows a look-ahead later (sticking's margin or the slip's N rising
        # through 0, as where a hold ends) is entered now: a hold started there would start on
        # its own end, which its event (falling through 0) would then never see
        if min(g_z, mu * g_z - math.sqrt(g_xi * g_xi + g_n * g_n)) >= 0.0:
            return PHASE_ROLLING
        later = t + opts[fk.OPT_LOOK_AHEAD]
        normal_ahead = slip_with(later, ahead, params, sticking_slip_direction(ahead[fk.PHI], g_xi, g_n))[0]
        if normal_ahead >= 0.0:
            # slaved from rest on the N it pushes with a moment later (the direction that accelerates)
            y[fk.SLIP_SPEED] = 0.0
            _start_slip(y, opts, sticking_slip_direction(y[fk.PHI], f_xi, f_n), normal_ahead)
            return PHASE_SLIPPING
    if holds_rim(opts, gap):
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
        ddtheta = rolling_state(t, y, params)[1]
    else:
        ddtheta = slip_state(t, y, params)[3]
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


@njit(cache=True)
def _clear_but_budget(y):
    """Zero the state but its energy budget (WORK, DISSIPATED, FRICTION): the column is down flat."""
    work, dissipated, friction = y[fk.WORK], y[fk.DISSIPATED], y[fk.FRICTION]
    y[:] = 0.0
    y[fk.WORK], y[fk.DISSIPATED], y[fk.FRICTION] = work, dissipated, friction


@njit(cache=True)
def _tilt3d(y):
    return y[fk.THETA]


@njit(cache=True)
def _tilt_rate3d(y):
    return y[fk.DTHETA]


@njit(cache=True)
def _depart3d(t, y, params, scratch):
    """Rest -> flat flight, flat sliding or uplift onto the rim at the departure time t; returns the phase."""
    c, record, dt, opts, summary = params
    zc = c[fk.C_ZC]
    mu = opts[fk.OPT_MU]
    theta_c = opts[fk.OPT_THETA_C]
    ax, ay, az = fk.ground_acceleration(t, record, dt)
    bx, by = y[fk.XP], y[fk.YP]
    _clear_but_budget(y)
    if 1.0 + az <= 0.0:  # the ground falls faster than gravity: flat flight
        y[fk.XP], y[fk.YP], y[fk.ZC] = bx, by, zc
        first_time(summary, S_FLIGHT_TIME, t)
        return PHASE_FLIGHT
    if mu < 1.0 / zc:  # slides before it can uplift
        y[fk.XP], y[fk.YP] = bx, by
        _start_slip(y, opts, math.atan2(-ay, -ax), 1.0 + az)
        first_time(summary, S_SLIDE_TIME, t)
        return PHASE_SLIDING
    phi = contact.uplift_azimuth(ax, ay)
    s_phi, c_phi = fk.sincos(phi)
    y[fk.PHI] = phi
    y[fk.PSI] = scratch[1][0] - phi  # the rotation it rested with
    y[fk.THETA] = theta_c
    y[fk.XP] = bx + s_phi * math.cos(theta_c)  # pivot: opposite the acceleration
    y[fk.YP] = by - c_phi * math.cos(theta_c)
    summary[S_TRANSITION] += fk.energy(theta_c, 0.0, 0.0, 0.0, c) - zc
    first_time(summary, S_UPLIFT_TIME, t)
    phase = _enter_contact(t, y, params)
    note_entry(summary, t, phase)  # the first slip (or flight), as every transition notes it
    return phase


@njit(cache=True)
def _advance3d(params, phase, t, y, t_end, t_out, y_out, out_i, t_breaks, rtol, atol, h):
    """Integrate a phase up to its first event, the slaved slip direction set before and synced after."""
    opts = params[3]
    if phase == PHASE_SLIPPING or phase == PHASE_SLIDING:
        _leave_layer_if_past(t, y, params, phase)
        _book_slaved_turn(t, y, params, phase)
    opts[fk.OPT_MAX_STEP] = _slaved_step(t, y, params, phase)
    res = integrate3d(params, t, y, t_end, t_out, y_out, out_i, t_breaks, rtol, atol, h)
    _sync_direction(res.t, res.y, params, phase)  # the state the run goes on from (book_phase copies it)
    return res


@njit(cache=True)
def _on_event3d(ev, t, y, params, phase, impacts, restitution, planar_e, settle_kinetic, scratch):
    """The map at an event of a 3D phase; returns the next phase and whether the integration restarts."""
    c, record, dt, opts, summary = params
    zc = c[fk.C_ZC]
    mu = opts[fk.OPT_MU]
    if ev == EV_TURN:
        # a turning point: theta' is zero there, its 1e-17 residue is
        # round-off that could make the next call find this root again
        y[fk.DTHETA] = 0.0
        book_peak(summary, t, y[fk.THETA])
        if phase != PHASE_FLIGHT and opts[fk.OPT_THETA_K] > 0.0:
            _near_contact_passage(t, y, params, phase, planar_e)
        return phase, False
    if ev == EV_MODE:  # in or out of the slaved-direction layer (direction synced after the call)
        opts[fk.OPT_SLAVED] = 1.0 - opts[fk.OPT_SLAVED]
        if opts[fk.OPT_SLAVED] != 0.0:
            opts[fk.OPT_SLAVED_SPEED] = y[fk.SLIP_SPEED]
            opts[fk.OPT_PHI_REF] = y[fk.PHI]
        return phase, False
    if ev == EV_PIVOT:  # the pivot's turning stopped, its hold gave way, or the unloaded patch loads
        if opts[fk.OPT_PIVOT_HELD] == 0.0 and opts[fk.OPT_DRILL_SIGN] != 0.0:
            # stopped: make it exact (the spin that cancels omega_Z at this tilt)
            e_before = energy3d(phase, y, c)
            y[fk.OMEGA] = -y[fk.DPHI] * math.sin(y[fk.THETA]) ** 2 / math.cos(y[fk.THETA])
            summary[S_TRANSITION] += energy3d(phase, y, c) - e_before
        if phase == PHASE_ROLLING and mu < math.inf:
            # a new drilling couple changes the friction rolling asks (a stopped pivot that
            # turns back flips it): sticking is checked again, which sets the pivot's mode
            phase = _enter_contact(t, y, params)
            note_entry(summary, t, phase)
        else:
            _pivot_mode(t, y, params, phase)
        return phase, False
    if ev == EV_SLIP and phase == PHASE_FLIGHT:
        # the axis passes the vertical: the same orientation is (phi + pi, -theta, psi - pi)
        y[fk.PHI] = y[fk.PHI] - math.pi if y[fk.PHI] > 0.0 else y[fk.PHI] + math.pi
        y[fk.PSI] -= math.pi
        y[fk.THETA] = -y[fk.THETA]
        y[fk.DTHETA] = -y[fk.DTHETA]
        return phase, False
    # the events below restart the integration; a rim hold ends with them (or is set again)
    held = opts[fk.OPT_RIM_HELD] != 0.0
    opts[fk.OPT_RIM_HELD] = 0.0
    if ev == EV_SLIP:  # rolling -> slipping: against the friction sticking would need
        phase = _enter_contact(t, y, params)
        first_time(summary, S_SLIDE_TIME, t)
        return phase, True
    if ev == EV_STICK:
        if phase == PHASE_SLIPPING:
            y[fk.SLIP_SPEED] = 0.0
            return _enter_contact(t, y, params), True
        # flat sliding stopped: rest, or sliding on in the new direction
        ax, ay, az = fk.ground_acceleration(t, record, dt)
        y[fk.SLIP_SPEED] = 0.0
        if math.hypot(ax, ay) > mu * (1.0 + az):
            _start_slip(y, opts, math.atan2(-ay, -ax), 1.0 + az)
            return phase, True
        return PHASE_REST, True
    if ev == EV_LIFT:
        if phase == PHASE_ROLLING:
            if held:
                # the hold ends: a contact the model allows exists again (rolling on, or
                # entered anew with finite friction), or the flight now rises (whichever of
                # -contact and -gap'' reached 0, the minimum in the event function)
                if mu == math.inf:
                    if rolling_state(t, y, params)[5] >= _gap_acceleration(t, y, params):
                        return phase, True
                else:
                    gap = _gap_acceleration(t, y, params)
                    stick, slip = contact_margins(t, y, params)
                    if stick >= slip and stick >= gap:
                        return phase, True  # sticking holds again (its margin rising through 0)
                    if slip >= gap:  # the slip's N rises through 0
                        phase = _enter_contact(t, y, params)
                        note_entry(summary, t, phase)
                        return phase, True
            elif mu < math.inf:
                if _gap_acceleration(t, y, params) < 0.0:
                    # the free column would sink: slip if it pushes, else hold the rim
                    phase = _enter_contact(t, y, params)
                    note_entry(summary, t, phase)
                    return phase, True
            elif holds_rim(opts, _gap_acceleration(t, y, params)):
                return phase, True
        elif phase == PHASE_SLIPPING:
            if held:
                if slip_state(t, y, params)[0] >= _gap_acceleration(t, y, params):
                    return phase, True  # N pushes again: slipping on
            elif holds_rim(opts, _gap_acceleration(t, y, params)):
                return phase, True  # slipping on, held
        first_time(summary, S_FLIGHT_TIME, t)
        if phase == PHASE_SLIDING:
            speed, cx, sx = y[fk.SLIP_SPEED], math.cos(y[fk.SLIP_DIR]), math.sin(y[fk.SLIP_DIR])
            y[fk.ZC] = zc
            y[fk.VX], y[fk.VY], y[fk.VZ] = speed * cx, speed * sx, 0.0
            y[fk.SLIP_SPEED] = 0.0
        else:
            _to_flight(y, c, phase == PHASE_SLIPPING)
        return PHASE_FLIGHT, True
    # EV_LAND
    if phase == PHASE_FLIGHT:
        return _touch_down3d(t, y, params, impacts, scratch[1]), True
    return _land3d(t, y, params, phase, impacts, restitution, settle_kinetic, scratch), True


@njit(cache=True)
def _touch_down3d(t, y, params, impacts, rest_rotation):
    """A flying column comes down: flat on its base (sliding, tipping or at rest), or on its rim.

    Returns the phase after the impact; a column down flat keeps its rotation in ``rest_rotation[0]``.
    """
    c, record, dt, opts, summary = params
    zc = c[fk.C_ZC]
    mu = opts[fk.OPT_MU]
    theta_c = opts[fk.OPT_THETA_C]
    phase = PHASE_FLIGHT
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
        rest_rotation[0] = y[fk.PHI] + y[fk.PSI]
        _clear_but_budget(y)
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
            _pivot_mode(t, y, params, PHASE_SLIPPING)
            _start_slip(y, opts, y[fk.SLIP_DIR], slip_with(t, y, params, y[fk.SLIP_DIR])[0])
            phase = PHASE_SLIPPING
        else:
            phase = _enter_contact(t, y, params)
    summary[S_N_IMPACTS] += 1
    e_after = energy3d(phase, y, c)
    summary[S_TRANSITION] += e_after - e_before
    log_impact(impacts, summary, t, 0.0, y[fk.DTHETA], e_after - e_before)
    return phase


@njit(cache=True)
def _land3d(t, y, params, phase, impacts, restitution, settle_kinetic, scratch):
    """A landing near full contact (:func:`contact.landing_impact`): on the other rim point, or settled flat.

    Returns the phase after it; ``scratch`` is the run's (the new state's
    array, the rotation kept at rest).
    """
    c, summary = params[0], params[4]
    y_new, rest_rotation = scratch
    rest_energy = c[fk.C_ZC]  # V at theta = 0
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
        log_impact(impacts, summary, t, y[fk.DTHETA], 0.0 if settles else y_new[fk.DTHETA],
                   (rest_energy if settles else e_after) - e_before)
    if settles:
        # full base contact, at rest on the ground
        s_phi, c_phi = fk.sincos(y[fk.PHI])
        rest_rotation[0] = y[fk.PHI] + y[fk.PSI]
        bx = y[fk.XP] - s_phi * math.cos(theta_land)
        by = y[fk.YP] + c_phi * math.cos(theta_land)
        _clear_but_budget(y)
        y[fk.XP], y[fk.YP] = bx, by
        summary[S_TRANSITION] += rest_energy - e_before
        return PHASE_REST
    summary[S_TRANSITION] += e_after - e_before
    y[:] = y_new
    phase = _enter_contact(t, y, params)
    note_entry(summary, t, phase)
    return phase


@njit(cache=True)
def _finish3d(y, c, opts, summary, phase, scratch):
    """The rotation and the base centre at the end of a 3D run."""
    if phase == PHASE_REST or phase == PHASE_SLIDING:
        summary[S_ROTATION] = scratch[1][0]
        summary[S_BASE_X], summary[S_BASE_Y] = y[fk.XP], y[fk.YP]
    else:
        s_phi, c_phi = fk.sincos(y[fk.PHI])
        summary[S_ROTATION] = y[fk.PHI] + y[fk.PSI]
        if phase == PHASE_FLIGHT:
            lean = c[fk.C_ZC] * math.sin(y[fk.THETA])  # the centre of mass leans away from the base centre
            summary[S_BASE_X] = y[fk.XP] - s_phi * lean
            summary[S_BASE_Y] = y[fk.YP] + c_phi * lean
        else:
            summary[S_BASE_X] = y[fk.XP] - s_phi * math.cos(y[fk.THETA])
            summary[S_BASE_Y] = y[fk.YP] + c_phi * math.cos(y[fk.THETA])


@njit(cache=True, nogil=True)
def run_frustum(params, restitution, y0, t_end, t_settle, t_out, y_out, phase_out, t_breaks, rtol, atol, summary,
                impacts):
    """Run the three-dimensional frustum through the record and its tail.

    Parameters
    ----------
    params : tuple
        ``(c, record, dt, opts)`` as :func:`pipeline.dynamics.rigid.frustum.rhs`; the
        options array is used as scratch for the phase (``OPT_PHASE``).
    y0 : float64[N_STATE]
        Initial state: theta = 0 (and zero rates) starts at rest with the
        base centre at (XP, YP); theta > 0 starts rolling on the rim.
    restitution : float
        < 0: the angular-momentum impact law; otherwise theta' after a
        landing is ``restitution`` times theta' before it (the other rates
        scaled alike).
    t_end : float
        End of the record plus its free tail [tau].
    t_settle : float
        Latest end of the run [tau], >= ``t_end``: if at ``t_end`` the column could still
        overturn, it runs on with the ground still until it cannot, comes to rest or lies
        down, at most until then (``S_UNDECIDED``; :func:`pipeline.dynamics.rigid.loop.run_events`).
    t_out : float64[m]
        Output times [tau], increasing, from 0 (up to ``t_settle``: rows after the run's end
        are left as they were).
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
    params[3][fk.OPT_FRICTION_EXCESS] = 0.0
    # kept through the run: the state after a landing's impact, and the body's rotation about the
    # vertical while it rests (at rest and sliding the state holds no angles)
    scratch = (y0.copy(), np.array([y0[fk.PHI] + y0[fk.PSI]]))
    phase = PHASE_ROLLING if y0[fk.THETA] > 0.0 else PHASE_REST
    return run_events(energy3d, _tilt3d, _tilt_rate3d, _depart3d, _advance3d, _on_event3d, _finish3d, params,
                      restitution, phase, y0.copy(), (fk.WORK, fk.DISSIPATED, fk.FRICTION), scratch, t_end, t_settle,
                      t_out, y_out, phase_out, t_breaks, rtol, atol, summary, impacts)
