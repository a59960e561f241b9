"""Planar rocking's event-driven run: transitions, impacts and the loop (compiled).

:func:`run_rocking` runs classical planar rocking (Housner's, with the
frustum's own inertia about its rim), with sliding and flight, through one
record and its tail. Its phases are :mod:`pipeline.dynamics.rigid.phases2d`'s,
its events those of the three-dimensional run; its impacts are planar: the
pivot moves to the other rim point with the restitution ``e``, and a flying
column comes down on its lowest base corner with Coulomb friction.
"""

import math

from numba import njit

from pipeline.dynamics.rigid import frustum as fk
from pipeline.dynamics.rigid import rocking as rk
from pipeline.dynamics.rigid.layout import (
    EV_LIE, EV_LIFT, EV_SLIP, EV_STICK, EV_TURN, MAX_STALLS, MAX_TRANSITIONS, PHASE_FLIGHT, PHASE_OVERTURNED,
    PHASE_REST, PHASE_ROLLING, PHASE_SLIDING, PHASE_SLIPPING, S_BASE_X, S_END_TIME, S_ENERGY_START, S_FINAL_PHASE,
    S_FLIGHT_TIME, S_MIN_NORMAL, S_N_IMPACTS, S_SLIDE_TIME, S_STATUS, S_TRANSITION, S_UPLIFT_TIME
)
from pipeline.dynamics.rigid.loop import (
    book_peak, book_phase, close_budget, departure_ratio, first_time, holds_rim, init_summary, lie_down,
    log_impact, rest_until_departure, settling_kinetic_energy
)
from pipeline.dynamics.rigid.phases2d import (
    energy2d, flight_gap_acceleration2d, integrate2d, rocking_contact, rocking_slip
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
    if not unilateral or holds_rim(opts, flight_gap_acceleration2d(y[rk.THETA2], y[rk.DTHETA2], a_z, c)):
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
    """Run classical planar rocking, with sliding and flight.

    Arguments as :func:`pipeline.dynamics.rigid.run3d.run_frustum`.

    The record's column 0 is the acceleration along the plane's direction u;
    ``y_out`` has ``N_STATE2`` columns (:mod:`pipeline.dynamics.rigid.rocking`). A
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
    init_summary(summary)
    y = y0.copy()
    rest_energy = zc
    settle_kinetic = settling_kinetic_energy(theta_c, zc, opts[fk.OPT_MIN_REBOUND])
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
            t_dep, out_i = rest_until_departure(record, dt, ratio, t, t_end, t_out, y_out, phase_out, out_i,
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
                first_time(summary, S_FLIGHT_TIME, t)
                phase = PHASE_FLIGHT
                continue
            # the inertial force -a_u pushes towards -u
            toward = -1.0 if a_u > 0.0 else 1.0
            if mu < 1.0 / zc:
                opts[fk.OPT_SIGN] = toward
                first_time(summary, S_SLIDE_TIME, t)
                phase = PHASE_SLIDING
                continue
            y[rk.THETA2] = toward * theta_c  # a signed zero when theta_c = 0
            y[rk.X2] += toward * math.cos(theta_c)  # the pivot on that side of the base
            opts[fk.OPT_PIVOT] = toward
            summary[S_TRANSITION] += rk.energy(theta_c, 0.0, c) - rest_energy
            first_time(summary, S_UPLIFT_TIME, t)
            phase = _enter_contact2d(t, y, p)
            if phase == PHASE_SLIPPING:
                first_time(summary, S_SLIDE_TIME, t)
            continue
        opts[fk.OPT_PHASE] = phase
        res = integrate2d(p, t, y, t_end, t_out, y_out, out_i, t_breaks, rtol, atol, h)
        out_i, stalls = book_phase(res, phase, phase_out, out_i, summary, y, t, stalls)
        t, h = res.t, res.h_next
        if res.status <= 0 or stalls > MAX_STALLS:
            break
        ev = res.event_index
        theta = abs(y[rk.THETA2])
        if ev == EV_TURN:
            y[rk.DTHETA2] = 0.0  # exactly a turning point (see run3d.run_frustum)
            book_peak(summary, t, theta)
            if phase == PHASE_ROLLING and theta < (1.0 - opts[fk.OPT_LANDING_MARGIN]) * theta_c:
                # at rest below the tilt of full contact (reached without a landing, e.g.
                # tipped from sliding at mu = R / z_cm): the base is down. Rocking on there
                # turned every 2.5e-5 s at 1e-11 rad and never ended (FEMA-FF-13, squat cylinder)
                summary[S_TRANSITION] += rest_energy - energy2d(phase, y, c)
                _down_on_base2d(y, opts[fk.OPT_PIVOT])
                phase = PHASE_REST
            continue
        if ev == EV_LIE:
            out_i = lie_down(summary, t, theta, y, y_out, phase_out, out_i)
            moving = phase
            phase = PHASE_OVERTURNED
            break
        h = 0.0
        n_transitions += 1
        if ev == EV_SLIP:
            phase = _enter_contact2d(t, y, p)
            first_time(summary, S_SLIDE_TIME, t)
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
                    if (rocking_contact(y[rk.THETA2], y[rk.DTHETA2], a_u, a_z, c, opts)[1]
                            >= flight_gap_acceleration2d(y[rk.THETA2], y[rk.DTHETA2], a_z, c)):
                        continue
                elif holds_rim(opts, flight_gap_acceleration2d(
                        y[rk.THETA2], y[rk.DTHETA2], fk.ground_acceleration(t, record, dt)[2], c)):
                    continue
            first_time(summary, S_FLIGHT_TIME, t)
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
            log_impact(impacts, summary, t, 0.0, y[rk.DTHETA2], e_after - e_before)
            continue
        # landing near full contact: pivot to the other rim point, theta' scaled by e
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
                first_time(summary, S_SLIDE_TIME, t)
            elif phase == PHASE_FLIGHT:
                first_time(summary, S_FLIGHT_TIME, t)
    if n_transitions >= MAX_TRANSITIONS:
        summary[S_STATUS] = -10
    summary[S_END_TIME] = t
    summary[S_FINAL_PHASE] = phase
    close_budget(summary, energy2d(phase if phase != PHASE_OVERTURNED else moving, y, c),
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
