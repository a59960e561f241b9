"""Hybrid simulation of a column under ground motion: rest, rolling, overturned.

Kernel layer (dimensionless arrays in, arrays out), compiled with numba. One
call runs one column under one ground-acceleration record, for the
three-dimensional frustum (:func:`run_frustum`) or for planar rocking
(:func:`run_rocking`). The phases and events (docs/model.md):

* **rest** (full base contact): the column moves with the ground; the uplift
  time is found exactly on the piecewise-linear record
  (:func:`pipeline.dynamics.contact.first_uplift`).
* **rolling** on the rim, from ``theta_c`` upwards, integrated by the compiled
  DOP853 (:mod:`pipeline.dynamics.integrator`), with three terminal events:
  landing (theta falls to ``theta_c``), overturning (theta rises to
  ``theta_lie``, where the side of the frustum touches the ground: it lies
  down) and every turning point of theta (theta' = 0), where the peaks are
  taken exactly.
* **landing**: the impact map of :func:`pipeline.dynamics.contact.landing_impact`
  (or a given coefficient of restitution); if the column cannot rise again
  (kinetic energy below what lifting from theta_c to 2 theta_c needs) it
  settles to rest, and the spin is stopped by the base's friction.
* **overturned**: the run ends.

Every jump of mechanical energy at a contact transition (uplift into
``theta_c``, impacts, settling) is added to ``summary[S_TRANSITION]``, so that
``E_end - E_0 = work + transitions - dissipated`` holds to the integration
error.

The entry points (:func:`run_frustum`, :func:`run_rocking`,
:func:`diagnostics_rows`) release the GIL (``nogil=True``): a Dask worker's
own threads (heartbeats, result transfers) then run beside a simulation instead
of waiting for it, and threads may run simulations side by side.
"""

import math

import numpy as np
from numba import njit

from pipeline.dynamics import contact
from pipeline.dynamics import frustum as fk
from pipeline.dynamics import rocking as rk
from pipeline.dynamics.integrator import dop853

PHASE_REST, PHASE_ROLLING, PHASE_OVERTURNED = 0, 1, 2

# Indices of the summary array filled by the runs.
(
    S_STATUS,  # 0 done, < 0 integration failure (integrator status)
    S_PEAK_THETA,  # [rad]
    S_PEAK_TIME,  # [tau]
    S_OVERTURN_TIME,  # [tau], nan if it stands
    S_UPLIFT_TIME,  # first uplift [tau], nan if never
    S_N_IMPACTS,
    S_PEAK_MU,  # at turning points of theta [1]
    S_MIN_NORMAL,  # at turning points [m g]
    S_TRANSITION,  # energy jumps at contact transitions [m g R]
    S_NFEV,
    S_STEPS,
    S_END_TIME,  # [tau]
    S_ROTATION,  # body rotation about the vertical at the end, phi + psi [rad]
    S_BASE_X,  # base centre at the end [R]
    S_BASE_Y,
) = range(15)
N_SUMMARY = 15

# Safety net against a Zeno cascade of landings and uplifts.
MAX_TRANSITIONS = 1_000_000
MAX_STEPS = 50_000_000
# Consecutive event stops without advancing time that end a run (status -11)
# instead of looping: a safety net, never reached in the tests.
MAX_STALLS = 100
STATUS_STALLED = -11

EVENT_DIRECTIONS = np.array([-1.0, 1.0, 0.0])  # landing, lying down, turning point

# Rolling starts at theta_c; the landing surface lies a hair below it, so a
# column that uplifts on the verge of the threshold (theta'' ~ 0) does not
# start on the landing surface, where round-off would trip the event at once
# and the uplift-landing-settle cycle could repeat without time advancing.
LANDING_MARGIN = 1e-3
EV_LANDING, EV_LIE, EV_TURN = 0, 1, 2


@njit(cache=True)
def _events_frustum(t, y, params, g):
    opts = params[3]
    g[EV_LANDING] = y[fk.THETA] - (1.0 - LANDING_MARGIN) * opts[fk.OPT_THETA_C]
    g[EV_LIE] = y[fk.THETA] - opts[fk.OPT_THETA_LIE]
    g[EV_TURN] = y[fk.DTHETA]


@njit(cache=True)
def _events_rocking(t, y, params, g):
    opts = params[3]
    th = abs(y[rk.THETA2])
    g[EV_LANDING] = th - (1.0 - LANDING_MARGIN) * opts[fk.OPT_THETA_C]
    g[EV_LIE] = th - opts[fk.OPT_THETA_LIE]
    g[EV_TURN] = y[rk.DTHETA2]


@njit(cache=True)
def _roll_frustum(params, t0, y0, t_end, t_out, y_out, out_start, t_breaks, rtol, atol, h0):
    return dop853(fk.rhs, _events_frustum, params, t0, y0, t_end, t_out, y_out, out_start,
                  EVENT_DIRECTIONS, t_breaks, rtol, atol, np.inf, h0, MAX_STEPS)


@njit(cache=True)
def _roll_rocking(params, t0, y0, t_end, t_out, y_out, out_start, t_breaks, rtol, atol, h0):
    return dop853(rk.rhs, _events_rocking, params, t0, y0, t_end, t_out, y_out, out_start,
                  EVENT_DIRECTIONS, t_breaks, rtol, atol, np.inf, h0, MAX_STEPS)


@njit(cache=True)
def _rest_until_uplift(record, dt, zc, t, t_end, t_out, y_out, phase_out, out_i, y_rest):
    """Stay at rest from ``t`` until the next uplift (or ``t_end``), filling the outputs.

    Returns the uplift time (``inf`` if none before the record ends) and the
    next output row.
    """
    t_up = contact.first_uplift(record, dt, zc, t)
    stop = min(t_up, t_end)
    inclusive = t_up >= t_end
    n = t_out.shape[0]
    while out_i < n and (t_out[out_i] < stop or (inclusive and t_out[out_i] <= stop)):
        y_out[out_i, :] = y_rest
        phase_out[out_i] = PHASE_REST
        out_i += 1
    return t_up, out_i


@njit(cache=True)
def _init_summary(summary):
    summary[:] = 0.0
    summary[S_OVERTURN_TIME] = math.nan
    summary[S_UPLIFT_TIME] = math.nan
    summary[S_MIN_NORMAL] = math.inf


# A rebound that would rise less than this above theta_c is a settling:
# shorter excursions than an integration step could slip past the landing
# event (and with theta_c = 0 the column would never settle otherwise).
MIN_REBOUND_TILT = 1e-8  # [rad]


@njit(cache=True)
def _settle_kinetic(theta_c, zc):
    """Kinetic energy [m g R] below which a landing column settles to rest."""
    top = theta_c + max(theta_c, MIN_REBOUND_TILT)
    return (math.sin(top) + zc * math.cos(top)) - (math.sin(theta_c) + zc * math.cos(theta_c))


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
def _book_phase(res, phase_out, out_i, summary, y, t_start, stalls):
    """Record a rolling phase's outputs and cost; copy its final state into y.

    Returns the next output row and the count of consecutive calls that
    stopped without advancing time (``STATUS_STALLED`` past ``MAX_STALLS``).
    """
    phase_out[out_i:res.out_next] = PHASE_ROLLING
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
def _turning_point(summary, t, theta, mu, normal):
    """Update the peaks at a turning point of theta."""
    if theta > summary[S_PEAK_THETA]:
        summary[S_PEAK_THETA] = theta
        summary[S_PEAK_TIME] = t
    if normal > 0.0 and mu > summary[S_PEAK_MU]:
        summary[S_PEAK_MU] = mu
    if normal < summary[S_MIN_NORMAL]:
        summary[S_MIN_NORMAL] = normal


@njit(cache=True, nogil=True)
def run_frustum(params, restitution, y0, t_end, t_out, y_out, phase_out, t_breaks, rtol, atol, summary, impacts):
    """Run the three-dimensional frustum through the record and its tail.

    Parameters
    ----------
    params : tuple
        ``(c, record, dt, opts)`` as :func:`pipeline.dynamics.frustum.rhs`.
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
        Filled with the states; at rest the XP, YP slots hold the base centre.
    phase_out : int8[m]
        Filled with the phase of each output row.
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
    zc = c[fk.C_ZC]
    theta_c = opts[fk.OPT_THETA_C]
    _init_summary(summary)
    y = y0.copy()  # at rest: XP, YP hold the base centre
    y_new = y0.copy()
    rotation = y0[fk.PHI] + y0[fk.PSI]  # body rotation about the vertical while at rest
    rest_energy = zc  # V at theta = 0
    settle_kinetic = _settle_kinetic(theta_c, zc)
    phase = PHASE_ROLLING if y0[fk.THETA] > 0.0 else PHASE_REST
    t = 0.0
    out_i = 0
    h = 0.0
    n_transitions = 0
    stalls = 0
    while n_transitions < MAX_TRANSITIONS:
        if phase == PHASE_REST:
            t_up, out_i = _rest_until_uplift(record, dt, zc, t, t_end, t_out, y_out, phase_out, out_i, y)
            if t_up >= t_end:
                t = t_end
                break
            ax, ay, az = fk.ground_acceleration(t_up, record, dt)
            phi = contact.uplift_azimuth(ax, ay)
            s_phi, c_phi = fk.sincos(phi)
            bx, by = y[fk.XP], y[fk.YP]
            y[:] = 0.0 * y
            y[fk.WORK] = y_new[fk.WORK]
            y[fk.DISSIPATED] = y_new[fk.DISSIPATED]
            y[fk.PHI] = phi
            y[fk.PSI] = rotation - phi
            y[fk.THETA] = theta_c
            y[fk.XP] = bx + s_phi * math.cos(theta_c)  # pivot: opposite the acceleration
            y[fk.YP] = by - c_phi * math.cos(theta_c)
            summary[S_TRANSITION] += fk.energy(theta_c, 0.0, 0.0, 0.0, c) - rest_energy
            if math.isnan(summary[S_UPLIFT_TIME]):
                summary[S_UPLIFT_TIME] = t_up
            t = t_up
            h = 0.0
            phase = PHASE_ROLLING
            n_transitions += 1
            continue
        res = _roll_frustum(params, t, y, t_end, t_out, y_out, out_i, t_breaks, rtol, atol, h)
        out_i, stalls = _book_phase(res, phase_out, out_i, summary, y, t, stalls)
        t, h = res.t, res.h_next
        if res.status <= 0 or stalls > MAX_STALLS:  # end, failure or stall (status in the summary)
            break
        ev = res.event_index
        if ev == EV_TURN:
            # a turning point: theta' is zero there, its 1e-17 residue is
            # round-off that could make the next call find this root again
            y[fk.DTHETA] = 0.0
            diag = np.empty(fk.N_DIAGNOSTICS)
            fk.diagnostics(t, y, params, diag)
            _turning_point(summary, t, y[fk.THETA], diag[4], diag[2])
            continue
        if ev == EV_LIE:
            out_i = _lie_down(summary, t, y[fk.THETA], y, y_out, phase_out, out_i)
            break
        # landing
        e_before = fk.energy(y[fk.THETA], y[fk.DPHI], y[fk.DTHETA], y[fk.OMEGA], c)
        theta_land = y[fk.THETA]
        contact.landing_impact(y, theta_land, c, y_new)
        if restitution >= 0.0 and y_new[fk.DTHETA] != 0.0:
            ratio = restitution * abs(y[fk.DTHETA]) / y_new[fk.DTHETA]
            y_new[fk.DTHETA] *= ratio
            y_new[fk.DPHI] *= ratio
            y_new[fk.OMEGA] *= ratio
        summary[S_N_IMPACTS] += 1
        n_transitions += 1
        e_after = fk.energy(y_new[fk.THETA], y_new[fk.DPHI], y_new[fk.DTHETA], y_new[fk.OMEGA], c)
        kinetic = e_after - fk.energy(theta_land, 0.0, 0.0, 0.0, c)
        h = 0.0
        settles = y_new[fk.DTHETA] <= 0.0 or kinetic < settle_kinetic
        _log_impact(impacts, summary, t, y[fk.DTHETA], 0.0 if settles else y_new[fk.DTHETA],
                    (rest_energy if settles else e_after) - e_before)
        if settles:
            # full base contact, at rest on the ground
            s_phi, c_phi = fk.sincos(y[fk.PHI])
            rotation = y[fk.PHI] + y[fk.PSI]
            bx = y[fk.XP] - s_phi * math.cos(theta_land)
            by = y[fk.YP] + c_phi * math.cos(theta_land)
            work, dissipated = y[fk.WORK], y[fk.DISSIPATED]
            y[:] = 0.0 * y
            y[fk.XP], y[fk.YP] = bx, by
            y[fk.WORK], y[fk.DISSIPATED] = work, dissipated
            y_new[fk.WORK], y_new[fk.DISSIPATED] = work, dissipated
            summary[S_TRANSITION] += rest_energy - e_before
            phase = PHASE_REST
        else:
            summary[S_TRANSITION] += e_after - e_before
            y[:] = y_new
    if n_transitions >= MAX_TRANSITIONS:
        summary[S_STATUS] = -10
    summary[S_END_TIME] = t
    if phase == PHASE_REST:
        summary[S_ROTATION] = rotation
        summary[S_BASE_X], summary[S_BASE_Y] = y[fk.XP], y[fk.YP]
    else:
        s_phi, c_phi = fk.sincos(y[fk.PHI])
        summary[S_ROTATION] = y[fk.PHI] + y[fk.PSI]
        summary[S_BASE_X] = y[fk.XP] - s_phi * math.cos(y[fk.THETA])
        summary[S_BASE_Y] = y[fk.YP] + c_phi * math.cos(y[fk.THETA])
    if summary[S_MIN_NORMAL] == math.inf:
        summary[S_MIN_NORMAL] = math.nan
    return out_i


@njit(cache=True, nogil=True)
def run_rocking(params, restitution, y0, t_end, t_out, y_out, phase_out, t_breaks, rtol, atol, summary, impacts):
    """Run classical planar rocking; arguments as :func:`run_frustum`.

    The record's column 0 is the acceleration along the plane's direction u;
    ``y_out`` has ``N_STATE2`` columns (signed theta, theta', work,
    dissipated). A negative ``restitution`` selects the angular-momentum
    value ``1 - 2 / Iy`` (clipped at 0).
    """
    c, record, dt, opts = params
    zc = c[fk.C_ZC]
    theta_c = opts[fk.OPT_THETA_C]
    e = restitution if restitution >= 0.0 else max(0.0, 1.0 - 2.0 / c[fk.C_IY])
    _init_summary(summary)
    y = y0.copy()
    rest_energy = zc
    lift_energy = rk.energy(theta_c, 0.0, c)
    settle_kinetic = _settle_kinetic(theta_c, zc)
    phase = PHASE_ROLLING if y0[rk.THETA2] != 0.0 else PHASE_REST
    t = 0.0
    out_i = 0
    h = 0.0
    n_transitions = 0
    stalls = 0
    while n_transitions < MAX_TRANSITIONS:
        if phase == PHASE_REST:
            t_up, out_i = _rest_until_uplift(record, dt, zc, t, t_end, t_out, y_out, phase_out, out_i, y)
            if t_up >= t_end:
                t = t_end
                break
            a_u, _unused, az = fk.ground_acceleration(t_up, record, dt)
            # the inertial force -a_u tips the column towards -u: pivot on the -u side
            y[rk.THETA2] = -theta_c if a_u > 0.0 else theta_c
            y[rk.DTHETA2] = 0.0
            summary[S_TRANSITION] += lift_energy - rest_energy
            if math.isnan(summary[S_UPLIFT_TIME]):
                summary[S_UPLIFT_TIME] = t_up
            t = t_up
            h = 0.0
            phase = PHASE_ROLLING
            n_transitions += 1
            continue
        res = _roll_rocking(params, t, y, t_end, t_out, y_out, out_i, t_breaks, rtol, atol, h)
        out_i, stalls = _book_phase(res, phase_out, out_i, summary, y, t, stalls)
        t, h = res.t, res.h_next
        if res.status <= 0 or stalls > MAX_STALLS:  # end, failure or stall (status in the summary)
            break
        ev = res.event_index
        theta = abs(y[rk.THETA2])
        if ev == EV_TURN:
            y[rk.DTHETA2] = 0.0  # exactly a turning point (see run_frustum)
            a_u, _unused, az = fk.ground_acceleration(t, record, dt)
            mu, normal = _rocking_contact(y[rk.THETA2], y[rk.DTHETA2], a_u, az, c, opts[fk.OPT_NU])
            _turning_point(summary, t, theta, mu, normal)
            continue
        if ev == EV_LIE:
            out_i = _lie_down(summary, t, theta, y, y_out, phase_out, out_i)
            break
        # landing: pivot to the other rim point, theta' scaled by e
        e_before = rk.energy(theta, y[rk.DTHETA2], c)
        summary[S_N_IMPACTS] += 1
        n_transitions += 1
        h = 0.0
        new_rate = e * y[rk.DTHETA2]
        kinetic = 0.5 * c[fk.C_IY] * new_rate * new_rate
        settles = kinetic < settle_kinetic
        e_after = rk.energy(theta, new_rate, c)
        _log_impact(impacts, summary, t, y[rk.DTHETA2], 0.0 if settles else new_rate,
                    (rest_energy if settles else e_after) - e_before)
        if settles:
            summary[S_TRANSITION] += rest_energy - e_before
            y[rk.THETA2] = 0.0
            y[rk.DTHETA2] = 0.0
            phase = PHASE_REST
        else:
            summary[S_TRANSITION] += e_after - e_before
            y[rk.THETA2] = -y[rk.THETA2]
            y[rk.DTHETA2] = new_rate
    if n_transitions >= MAX_TRANSITIONS:
        summary[S_STATUS] = -10
    summary[S_END_TIME] = t
    if summary[S_MIN_NORMAL] == math.inf:
        summary[S_MIN_NORMAL] = math.nan
    return out_i


@njit(cache=True)
def _rocking_contact(theta, dtheta, a_u, a_z, c, nu):
    """Mobilized friction and normal force (per m g) of planar rocking.

    The centre of mass relative to the pivot, for signed theta, is
    ``C_u = -sgn cos(theta) + zc sin(theta)``, ``C_z = sgn sin(theta) + zc cos(theta)``;
    the contact force is ``F = m (C'' + a_g + g e_z)``.
    """
    zc = c[fk.C_ZC]
    sgn = 1.0 if theta >= 0.0 else -1.0
    s, co = math.sin(theta), math.cos(theta)
    ddtheta = rk.angular_acceleration(theta, a_u, a_z, c) - nu * dtheta / c[fk.C_IY]
    w2 = dtheta * dtheta
    f_u = (sgn * s + zc * co) * ddtheta + (sgn * co - zc * s) * w2 + a_u
    f_z = (sgn * co - zc * s) * ddtheta - (sgn * s + zc * co) * w2 + 1.0 + a_z
    mu = abs(f_u) / f_z if f_z > 0.0 else math.inf
    return mu, f_z


@njit(cache=True, nogil=True)
def diagnostics_rows(tau, states, phase, params, model_3d, out):
    """Diagnostics of every output row (compiled loop), written to ``out``.

    Columns as :func:`pipeline.dynamics.frustum.diagnostics`: omega_zeta,
    energy, normal force, |F_t|, mu_mob, a_X, a_Y, a_Z (dimensionless). At
    rest (or on rows never reached) the base carries the weight and the
    ground's push: N = 1 + a_z, |F_t| = |a_h|.
    """
    c, record, dt, opts = params
    buf = np.empty(fk.N_DIAGNOSTICS)
    for i in range(tau.shape[0]):
        t = tau[i]
        ax, ay, az = fk.ground_acceleration(t, record, dt)
        if phase[i] == PHASE_REST or math.isnan(states[i, 0]):
            normal = 1.0 + az
            tangential = math.sqrt(ax * ax + ay * ay)
            out[i, 0] = 0.0
            out[i, 1] = c[fk.C_ZC]
            out[i, 2] = normal
            out[i, 3] = tangential
            out[i, 4] = tangential / normal if normal > 0.0 else math.inf
            out[i, 5] = ax
            out[i, 6] = ay
            out[i, 7] = az
        elif model_3d:
            fk.diagnostics(t, states[i], params, buf)
            out[i, :] = buf
        else:
            theta, dtheta = states[i, rk.THETA2], states[i, rk.DTHETA2]
            mu, normal = _rocking_contact(theta, dtheta, ax, az, c, opts[fk.OPT_NU])
            out[i, 0] = 0.0
            out[i, 1] = rk.energy(theta, dtheta, c)
            out[i, 2] = normal
            out[i, 3] = mu * normal
            out[i, 4] = mu
            out[i, 5] = ax
            out[i, 6] = ay
            out[i, 7] = az
