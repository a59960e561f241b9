"""Planar rocking's event-driven run: transitions, impacts and the loop (compiled).

:func:`run_rocking` runs classical planar rocking (Housner's, with the
frustum's own inertia about its rim), with sliding and flight, through one
record and its tail. Its phases are :mod:`pipeline.dynamics.rigid.phases2d`'s,
its events those of the three-dimensional run; its impacts are planar: the
pivot moves to the other rim point with the restitution ``e``, and a flying
column comes down on its lowest base corner with Coulomb friction. The loop is
:func:`pipeline.dynamics.rigid.loop.run_events`, shared with the
three-dimensional run; this module gives it the planar parts.
"""

import math

from numba import njit

from pipeline.dynamics.rigid import frustum as fk
from pipeline.dynamics.rigid import rocking as rk
from pipeline.dynamics.rigid.layout import (
    EV_LIFT, EV_SLIP, EV_STICK, EV_TURN, PHASE_FLIGHT, PHASE_REST, PHASE_ROLLING, PHASE_SLIDING,
    PHASE_SLIPPING, S_BASE_X, S_FLIGHT_TIME, S_N_IMPACTS, S_SLIDE_TIME, S_TRANSITION, S_UPLIFT_TIME
)
from pipeline.dynamics.rigid.loop import book_peak, first_time, holds_rim, log_impact, note_entry, run_events
from pipeline.dynamics.rigid.phases2d import (
    contact_margins2d, energy2d, flight_gap_acceleration2d, integrate2d, rocking_contact, rocking_slip
)


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
def _enter_contact2d(t, y, params):
    """Rolling, slipping (direction in OPT_SIGN) or flight for a planar state whose pivot sticks.

    The pivot side is ``OPT_PIVOT``, set by the caller (theta may be a signed zero).
    """
    c, record, dt, opts = params[0], params[1], params[2], params[3]
    a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
    f_u, f_z, ddtheta, _p = rocking_contact(y[rk.THETA2], y[rk.DTHETA2], a_u, a_z, c, opts)
    step = opts[fk.OPT_LOOK_AHEAD]
    b_u, _unused, b_z = fk.ground_acceleration(t + step, record, dt)
    theta_ahead = y[rk.THETA2] + step * y[rk.DTHETA2]
    rate_ahead = y[rk.DTHETA2] + step * ddtheta
    g_u, g_z, _dd, _p = rocking_contact(theta_ahead, rate_ahead, b_u, b_z, c, opts)
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
        normal = rocking_slip(y[rk.THETA2], y[rk.DTHETA2], sigma, a_u, a_z, c, opts)[2]
        if normal >= 0.0 or not unilateral:
            opts[fk.OPT_SIGN] = sigma
            return PHASE_SLIPPING
    if not unilateral:
        return PHASE_ROLLING
    # no contact the model allows: a flight if it rises, else the rim held (loop.holds_rim); a
    # flight that started sinking would never see its landing (the gap starts at 0, falling)
    free = flight_gap_acceleration2d(y[rk.THETA2], y[rk.DTHETA2], a_z, c)
    if free < 0.0 and mu < math.inf:
        # one the model allows a look-ahead later (sticking's margin or the slip's N rising
        # through 0, as where a hold ends) is entered now: a hold started there would start on
        # its own end, which its event (falling through 0) would then never see
        if min(g_z, mu * g_z - abs(g_u)) >= 0.0:
            return PHASE_ROLLING
        sigma = -1.0 if g_u > 0.0 else 1.0
        if rocking_slip(theta_ahead, rate_ahead, sigma, b_u, b_z, c, opts)[2] >= 0.0:
            opts[fk.OPT_SIGN] = sigma
            return PHASE_SLIPPING
    if holds_rim(opts, free):
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


@njit(cache=True)
def _tilt2d(y):
    return abs(y[rk.THETA2])


@njit(cache=True)
def _tilt_rate2d(y):
    """Rate of |theta| [1/tau]."""
    return math.copysign(1.0, y[rk.THETA2]) * y[rk.DTHETA2]


@njit(cache=True)
def _depart2d(t, y, params, scratch):
    """Rest -> flat flight, flat sliding or uplift onto a base corner at the departure time t; returns the phase."""
    c, record, dt, opts, summary = params
    zc = c[fk.C_ZC]
    mu = opts[fk.OPT_MU]
    theta_c = opts[fk.OPT_THETA_C]
    a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
    _clear_free_slots2d(y)
    y[rk.THETA2] = 0.0
    y[rk.DTHETA2] = 0.0
    if 1.0 + a_z <= 0.0:
        y[rk.Z2] = zc
        first_time(summary, S_FLIGHT_TIME, t)
        return PHASE_FLIGHT
    # the inertial force -a_u pushes towards -u
    toward = -1.0 if a_u > 0.0 else 1.0
    if mu < 1.0 / zc:
        opts[fk.OPT_SIGN] = toward
        first_time(summary, S_SLIDE_TIME, t)
        return PHASE_SLIDING
    y[rk.THETA2] = toward * theta_c  # a signed zero when theta_c = 0
    y[rk.X2] += toward * math.cos(theta_c)  # the pivot on that side of the base
    opts[fk.OPT_PIVOT] = toward
    summary[S_TRANSITION] += rk.energy(theta_c, 0.0, c) - zc
    first_time(summary, S_UPLIFT_TIME, t)
    phase = _enter_contact2d(t, y, params)
    note_entry(summary, t, phase)  # the first slip (or flight), as every transition notes it
    return phase


@njit(cache=True)
def _advance2d(params, phase, t, y, t_end, t_out, y_out, out_i, t_breaks, rtol, atol, h):
    return integrate2d(params, t, y, t_end, t_out, y_out, out_i, t_breaks, rtol, atol, h)


@njit(cache=True)
def _on_event2d(ev, t, y, params, phase, impacts, restitution, e, settle_kinetic, scratch):
    """The map at an event of a planar phase; returns the next phase and whether the integration restarts."""
    c, record, dt, opts, summary = params
    zc = c[fk.C_ZC]
    mu = opts[fk.OPT_MU]
    theta_c = opts[fk.OPT_THETA_C]
    rest_energy = zc
    theta = abs(y[rk.THETA2])
    if ev == EV_TURN:
        y[rk.DTHETA2] = 0.0  # exactly a turning point (see run3d._on_event3d)
        book_peak(summary, t, theta)
        if phase == PHASE_ROLLING and theta < (1.0 - opts[fk.OPT_LANDING_MARGIN]) * theta_c:
            # at rest below the tilt of full contact (reached without a landing, e.g.
            # tipped from sliding at mu = R / z_cm): the base is down. Rocking on there
            # turned every 2.5e-5 s at 1e-11 rad and never ended (FEMA-FF-13, squat cylinder)
            summary[S_TRANSITION] += rest_energy - energy2d(phase, y, c)
            _down_on_base2d(y, opts[fk.OPT_PIVOT])
            return PHASE_REST, False
        return phase, False
    # the events below restart the integration; a rim hold ends with them (or is set again)
    held = opts[fk.OPT_RIM_HELD] != 0.0
    opts[fk.OPT_RIM_HELD] = 0.0
    if ev == EV_SLIP:
        phase = _enter_contact2d(t, y, params)
        first_time(summary, S_SLIDE_TIME, t)
        return phase, True
    if ev == EV_STICK:
        y[rk.V2] = 0.0
        if phase == PHASE_SLIPPING:
            return _enter_contact2d(t, y, params), True
        a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
        if abs(a_u) > mu * (1.0 + a_z):
            opts[fk.OPT_SIGN] = -1.0 if a_u > 0.0 else 1.0
            return phase, True
        return PHASE_REST, True
    if ev == EV_LIFT:
        a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
        free = flight_gap_acceleration2d(y[rk.THETA2], y[rk.DTHETA2], a_z, c)
        if phase == PHASE_ROLLING:
            if held:
                # the hold ends: a contact the model allows exists again (rolling on, or
                # entered anew with finite friction), or the flight now rises (whichever of
                # -contact and -gap'' reached 0, the minimum in the event function)
                if mu == math.inf:
                    if rocking_contact(y[rk.THETA2], y[rk.DTHETA2], a_u, a_z, c, opts)[1] >= free:
                        return phase, True
                else:
                    stick, slip = contact_margins2d(y[rk.THETA2], y[rk.DTHETA2], a_u, a_z, c, opts)
                    if stick >= slip and stick >= free:
                        return phase, True  # sticking holds again (its margin rising through 0)
                    if slip >= free:  # the slip's N rises through 0
                        phase = _enter_contact2d(t, y, params)
                        note_entry(summary, t, phase)
                        return phase, True
            elif mu < math.inf:
                if free < 0.0:  # the free column would sink: slip if it pushes, else hold the rim
                    phase = _enter_contact2d(t, y, params)
                    note_entry(summary, t, phase)
                    return phase, True
            elif holds_rim(opts, free):
                return phase, True
        elif phase == PHASE_SLIPPING:
            if held:
                if rocking_slip(y[rk.THETA2], y[rk.DTHETA2], opts[fk.OPT_SIGN], a_u, a_z, c, opts)[2] >= free:
                    return phase, True  # N pushes again: slipping on
            elif holds_rim(opts, free):
                return phase, True  # slipping on, held
        first_time(summary, S_FLIGHT_TIME, t)
        if phase == PHASE_SLIDING:
            y[rk.Z2] = zc
            y[rk.VZ2] = 0.0
        else:
            _to_flight2d(y, c)
        return PHASE_FLIGHT, True
    # EV_LAND
    if phase == PHASE_FLIGHT:
        return _touch_down2d(t, y, params, impacts, theta), True
    return _land2d(t, y, params, phase, impacts, e, settle_kinetic, theta), True


@njit(cache=True)
def _touch_down2d(t, y, params, impacts, theta):
    """A flying column comes down: flat on its base (sliding, tipping or at rest), or on a base corner."""
    c, summary, opts = params[0], params[4], params[3]
    zc = c[fk.C_ZC]
    mu = opts[fk.OPT_MU]
    theta_c = opts[fk.OPT_THETA_C]
    phase = PHASE_FLIGHT
    e_before = energy2d(phase, y, c)
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
            phase = _enter_contact2d(t, y, params)
    e_after = energy2d(phase, y, c)
    summary[S_TRANSITION] += e_after - e_before
    log_impact(impacts, summary, t, 0.0, y[rk.DTHETA2], e_after - e_before)
    return phase


@njit(cache=True)
def _land2d(t, y, params, phase, impacts, e, settle_kinetic, theta):
    """A landing near full contact: the pivot moves to the other rim point with theta' scaled by e, or it settles."""
    c, opts, summary = params[0], params[3], params[4]
    rest_energy = c[fk.C_ZC]
    e_before = energy2d(phase, y, c)
    new_rate = e * y[rk.DTHETA2]
    kinetic = 0.5 * c[fk.C_IY] * new_rate * new_rate
    settles = kinetic < settle_kinetic
    e_after = rk.energy(theta, new_rate, c)
    if y[rk.DTHETA2] != 0.0:  # touching back down with no speed at all is no impact
        summary[S_N_IMPACTS] += 1
        log_impact(impacts, summary, t, y[rk.DTHETA2], 0.0 if settles else new_rate,
                   (rest_energy if settles else e_after) - e_before)
    side = opts[fk.OPT_PIVOT]
    if settles:
        summary[S_TRANSITION] += rest_energy - e_before
        _down_on_base2d(y, side)
        return PHASE_REST
    summary[S_TRANSITION] += e_after - e_before
    _clear_free_slots2d(y)
    y[rk.X2] -= 2.0 * side * math.cos(y[rk.THETA2])  # to the other rim point, across the base
    # the other rim point: its side explicitly (theta ~ 0 has no reliable sign)
    opts[fk.OPT_PIVOT] = -side
    y[rk.THETA2] = math.copysign(abs(y[rk.THETA2]), -side)
    y[rk.DTHETA2] = new_rate
    phase = _enter_contact2d(t, y, params)
    note_entry(summary, t, phase)
    return phase


@njit(cache=True)
def _finish2d(y, c, opts, summary, phase, scratch):
    """The base centre at the end of a planar run."""
    if phase == PHASE_REST or phase == PHASE_SLIDING:
        summary[S_BASE_X] = y[rk.X2]
    elif phase == PHASE_FLIGHT:
        summary[S_BASE_X] = y[rk.X2] - c[fk.C_ZC] * math.sin(y[rk.THETA2])
    else:
        summary[S_BASE_X] = y[rk.X2] - opts[fk.OPT_PIVOT] * math.cos(y[rk.THETA2])


@njit(cache=True, nogil=True)
def run_rocking(params, restitution, y0, t_end, t_settle, t_out, y_out, phase_out, t_breaks, rtol, atol, summary,
                impacts):
    """Run classical planar rocking, with sliding and flight.

    Arguments as :func:`pipeline.dynamics.rigid.run3d.run_frustum`.

    The record's column 0 is the acceleration along the plane's direction u;
    ``y_out`` has ``N_STATE2`` columns (:mod:`pipeline.dynamics.rigid.rocking`). A
    negative ``restitution`` selects the angular-momentum value
    ``1 - 2 / Iy`` (clipped at 0).
    """
    y = y0.copy()
    phase = PHASE_REST
    if y0[rk.THETA2] != 0.0:
        phase = PHASE_ROLLING
        params[3][fk.OPT_PIVOT] = math.copysign(1.0, y0[rk.THETA2])
    return run_events(energy2d, _tilt2d, _tilt_rate2d, _depart2d, _advance2d, _on_event2d, _finish2d, params,
                      restitution, phase, y, (rk.WORK2, rk.DISSIPATED2, rk.FRICTION2), None, t_end, t_settle, t_out,
                      y_out, phase_out, t_breaks, rtol, atol, summary, impacts)
