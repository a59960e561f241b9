"""Steps that both rigid event-driven runs take, the 3D frustum's and planar rocking's (compiled).

Helpers of :func:`pipeline.dynamics.rigid.run3d.run_frustum` and
:func:`pipeline.dynamics.rigid.run2d.run_rocking`: the summary's start and
close, the first times of uplift, sliding and flight, the peak tilt, the step
monitor's peak mobilized friction and lowest normal force, the rest phase up
to the column's departure (found exactly on the piecewise-linear record), the
booking of an integrated phase with its stall count, lying down, the landing
log, and the rim hold of a contact that can neither push nor fly; and the run itself,
:func:`run_events`, into which each model passes its own parts.
"""

import math

from numba import njit

from pipeline.dynamics.rigid import frustum as fk
from pipeline.dynamics.rigid import contact
from pipeline.dynamics.rigid.layout import (
    EV_LIE, MAX_STALLS, MAX_TRANSITIONS, PHASE_FLIGHT, PHASE_OVERTURNED, PHASE_REST, PHASE_SLIPPING,
    SETTLE_CHUNK, STATUS_STALLED, S_DISSIPATED, S_END_TIME, S_ENERGY_END, S_ENERGY_START, S_FINAL_PHASE, S_FLIGHT_TIME,
    S_FRICTION, S_MIN_NORMAL, S_NFEV, S_N_IMPACTS, S_OVERTURN_TIME, S_PEAK_MU, S_PEAK_THETA, S_PEAK_TIME,
    S_SLIDE_TIME, S_STATUS, S_STEPS, S_UNDECIDED, S_UPLIFT_TIME, S_WORK
)


@njit(cache=True)
def watch_contact(summary, mu, normal):
    if mu > summary[S_PEAK_MU]:
        summary[S_PEAK_MU] = mu
    if normal < summary[S_MIN_NORMAL]:
        summary[S_MIN_NORMAL] = normal


@njit(cache=True)
def init_summary(summary):
    summary[:] = 0.0
    summary[S_OVERTURN_TIME] = math.nan
    summary[S_UPLIFT_TIME] = math.nan
    summary[S_SLIDE_TIME] = math.nan
    summary[S_FLIGHT_TIME] = math.nan
    summary[S_MIN_NORMAL] = math.inf


@njit(cache=True)
def close_budget(summary, energy_end, work, dissipated, friction):
    summary[S_ENERGY_END] = energy_end
    summary[S_WORK] = work
    summary[S_DISSIPATED] = dissipated
    summary[S_FRICTION] = friction


@njit(cache=True)
def first_time(summary, k, t):
    if math.isnan(summary[k]):
        summary[k] = t


@njit(cache=True)
def settling_kinetic_energy(theta_c, zc, min_rebound):
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
def rest_until_departure(record, dt, ratio, t, t_end, t_out, y_out, phase_out, out_i, y_rest, summary):
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
        watch_contact(summary, math.sqrt(ax * ax + ay * ay) / normal, normal)


@njit(cache=True)
def log_impact(impacts, summary, t, rate_before, rate_after, energy_jump):
    """Record a landing in the log (the first ``len(impacts)`` only)."""
    k = int(summary[S_N_IMPACTS]) - 1
    if 0 <= k < impacts.shape[0]:
        impacts[k, 0] = t
        impacts[k, 1] = rate_before
        impacts[k, 2] = rate_after
        impacts[k, 3] = energy_jump


@njit(cache=True)
def book_phase(res, phase, phase_out, out_i, summary, y, t_start, stalls):
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
def lie_down(summary, t, theta, y, y_out, phase_out, out_i):
    """The column lies on its side: record it and freeze the remaining outputs."""
    summary[S_PEAK_THETA] = theta
    summary[S_PEAK_TIME] = t
    summary[S_OVERTURN_TIME] = t
    for i in range(out_i, y_out.shape[0]):
        y_out[i, :] = y
        phase_out[i] = PHASE_OVERTURNED
    return y_out.shape[0]


@njit(cache=True)
def note_entry(summary, t, phase):
    """The first slip or flight, if ``phase``, entered at t, is one."""
    if phase == PHASE_SLIPPING:
        first_time(summary, S_SLIDE_TIME, t)
    elif phase == PHASE_FLIGHT:
        first_time(summary, S_FLIGHT_TIME, t)


@njit(cache=True)
def book_peak(summary, t, theta):
    if theta > summary[S_PEAK_THETA]:
        summary[S_PEAK_THETA] = theta
        summary[S_PEAK_TIME] = t


@njit(cache=True)
def stands_for_good(phase, energy, theta, theta_rate, zc):
    """Whether a column on still ground can no longer overturn, its swing under way past its peak.

    With the ground still its mechanical energy can only fall (landings, friction, the contact
    couples take; nothing gives). To overturn it must pass the critical tilt theta_crit =
    atan(R / z_cm), where the potential energy on the rim, ``sin(theta) + z_cm cos(theta)``
    [m g R], peaks at ``sqrt(1 + z_cm^2)``: below it and on the near side the column stands
    for good (in flight its centre is higher than on the rim at the same tilt, so the bound
    holds there too). A tilt still rising has not yet reached the peak the run must report, so
    the run goes on until it falls (``theta_rate <= 0``). At rest it has stood.

    Parameters
    ----------
    phase : int
    energy : float
        Mechanical energy [m g R] (of the phase's state).
    theta, theta_rate : float
        Tilt [rad] and its rate [1/tau].
    zc : float
        Height of the centre of mass per R [1].
    """
    if phase == PHASE_REST:
        return True
    return theta < math.atan(1.0 / zc) and energy < math.sqrt(1.0 + zc * zc) and theta_rate <= 0.0


@njit(cache=True)
def holds_rim(opts, gap_acceleration):
    """A contact whose force the model cannot make push while the free column would sink: hold the rim.

    Flight is consistent only if the lowest rim point, free, would not sink into the ground
    (``gap_acceleration`` >= 0, :func:`flight_gap_acceleration`): its height and rate are 0
    when a contact ends, so a flight that starts with a negative gap acceleration is below
    the ground at once, its landing event (gap falling through 0) never fires and the column
    flies through the ground. A rigid body whose contact point would accelerate into the
    ground gets a compressive normal force; when the contact's equations give none, they
    are at fault, not the ground:

    - with infinite friction, rolling can need a finite tangential force while N reaches
      0 (mobilized friction tends to infinity; any finite mu slips first), the paper's
      paradox;
    - with finite friction, the contact patch's rolling damping (sized by the normal force
      rolling would carry without the patch's couples, :mod:`pipeline.dynamics.rigid.patch`,
      docs/model.md) can ask a couple that the actual normal force cannot carry: near full
      contact, where the dashpots reach the couple's cap N w with w up to the base's 2 R,
      it drives sticking beyond mu N and the slip's N below 0 (after every near-flat landing
      of a rocking column on still ground, and mid-slip under strong vertical shaking).

    Neither rolling, slipping nor flight is then consistent; the contact is kept (the rim
    held, as the paper holds it) with the model's forces, until a contact the model allows
    exists again or the free flight would rise (the event functions of the held phase).
    Returns whether it holds (``OPT_RIM_HELD`` set); never with a two-sided ground.
    Both kernels use it.
    """
    if opts[fk.OPT_UNILATERAL] == 0.0 or gap_acceleration >= 0.0:
        return False
    opts[fk.OPT_RIM_HELD] = 1.0
    return True


@njit(inline="always")
def run_events(energy, tilt, tilt_rate, depart, advance, handle, finish, params, restitution, phase, y, ledger, scratch,
               t_end, t_settle, t_out, y_out, phase_out, t_breaks, rtol, atol, summary, impacts):
    """The event-driven run both rigid models share: rest, phases up to their events, the summary.

    At rest until the column departs (:func:`rest_until_departure`), then
    each phase integrated up to its first event and booked
    (:func:`book_phase`), lying down ending the run (:func:`lie_down`), every
    other event mapped to the phase that follows, until the record and its
    tail end, an integration fails or stalls, or ``MAX_TRANSITIONS`` events
    that restart the integration have passed (status -10).

    The model's parts are compiled functions passed in, which numba
    specialises this loop for; it is inlined into each model's run (numba's
    IR), because a compiled function that passes functions on as values
    cannot be cached ("dynamic globals") and an inlined one can. The state
    layouts are the parts' own:

    - ``energy(phase, y, c)``: mechanical energy [m g R] of a state;
    - ``tilt(y)``: theta [rad], how far the column leans;
    - ``tilt_rate(y)``: its rate [1/tau];
    - ``depart(t, y, p, scratch)``: the map out of rest at the departure time
      t, returning the phase it departs in;
    - ``advance(p, phase, t, y, t_end, t_out, y_out, out_i, t_breaks, rtol, atol, h)``:
      integrate the phase from t up to its first event or ``t_end``
      (:data:`pipeline.dynamics.integrators.dop853.Dop853Result`);
    - ``handle(ev, t, y, p, phase, impacts, restitution, planar_e, settle_kinetic, scratch)``:
      the map at event ``ev`` (any but ``EV_LIE``), returning the phase that
      follows and whether the event restarts the integration (a transition);
    - ``finish(y, c, opts, summary, phase, scratch)``: the base's position at
      the end.

    ``p`` is ``(c, record, dt, opts, summary)``, ``phase`` the starting
    phase, ``y`` the state (changed in place), ``ledger`` the state's slots
    of the work done by the ground, the energy dissipated by the contact
    couples and by friction, ``scratch`` whatever else the model keeps
    through the run; the other arguments as
    :func:`pipeline.dynamics.rigid.run3d.run_frustum`'s. Returns the next
    output row.
    """
    c, record, dt, opts = params
    p = (c, record, dt, opts, summary)
    zc = c[fk.C_ZC]
    opts[fk.OPT_RIM_HELD] = 0.0
    ratio = departure_ratio(zc, opts[fk.OPT_MU])
    planar_e = restitution if restitution >= 0.0 else max(0.0, 1.0 - 2.0 / c[fk.C_IY])
    settle_kinetic = settling_kinetic_energy(opts[fk.OPT_THETA_C], zc, opts[fk.OPT_MIN_REBOUND])
    init_summary(summary)
    summary[S_ENERGY_START] = energy(phase, y, c)
    moving = phase  # the phase the column lies down from
    t = 0.0
    out_i = 0
    h = 0.0
    n_transitions = 0
    stalls = 0
    t_stop = t_end
    while n_transitions < MAX_TRANSITIONS:
        if phase == PHASE_REST:
            t_dep, out_i = rest_until_departure(record, dt, ratio, t, t_stop, t_out, y_out, phase_out, out_i,
                                                 y, summary)
            if t_dep >= t_stop:  # at rest through the record and its tail: it stands
                t = t_stop
                break
            t = t_dep
            h = 0.0
            n_transitions += 1
            phase = depart(t, y, p, scratch)
            continue
        opts[fk.OPT_PHASE] = phase
        res = advance(p, phase, t, y, t_stop, t_out, y_out, out_i, t_breaks, rtol, atol, h)
        out_i, stalls = book_phase(res, phase, phase_out, out_i, summary, y, t, stalls)
        t, h = res.t, res.h_next
        book_peak(summary, t, tilt(y))  # where a phase (or the run) ends, mid-swing or not
        if res.status < 0 or stalls > MAX_STALLS:  # failure or stall (status in the summary)
            break
        if res.status == 0:  # the record and its tail, or the last chunk after them, have passed
            if stands_for_good(phase, energy(phase, y, c), tilt(y), tilt_rate(y), zc):
                break
            if t_stop >= t_settle:
                summary[S_UNDECIDED] = 1.0
                break
            t_stop = min(t_stop + SETTLE_CHUNK, t_settle)  # the ground is still from here on
            continue
        ev = res.event_index
        if ev == EV_LIE:
            out_i = lie_down(summary, t, tilt(y), y, y_out, phase_out, out_i)
            moving = phase
            phase = PHASE_OVERTURNED
            break
        phase, restarts = handle(ev, t, y, p, phase, impacts, restitution, planar_e, settle_kinetic, scratch)
        if restarts:
            h = 0.0
            n_transitions += 1
    if n_transitions >= MAX_TRANSITIONS:
        summary[S_STATUS] = -10
    summary[S_END_TIME] = t
    summary[S_FINAL_PHASE] = phase
    close_budget(summary, energy(phase if phase != PHASE_OVERTURNED else moving, y, c),
                 y[ledger[0]], y[ledger[1]], y[ledger[2]])
    finish(y, c, opts, summary, phase, scratch)
    if summary[S_MIN_NORMAL] == math.inf:
        summary[S_MIN_NORMAL] = math.nan
    return out_i
