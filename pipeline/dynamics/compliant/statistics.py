"""Statistics of a compliant run that every integrator shares: peaks, joints' events, history rows, the end.

Per monitor sample (the adaptive integrators) or per step (the fixed-step one): each body's
peak tilt and rotation, the watched bodies' largest tilt (the run's peak theta), each joint's
lowest normal force, peak mobilised friction, sliding, lift-off, uplift onto a rim and landings;
the history rows; and whether a structure on still ground stands for good
(:func:`stands_for_good`, docs/model.md "The end of a run"). Kernel layer, as
:mod:`pipeline.dynamics.compliant.assembly`.
"""

import math

from numba import njit

from pipeline.dynamics.compliant.assembly import _contacts, _kinematics, energy, tilt_and_rotation
from pipeline.dynamics.compliant.layout import (
    BS_PEAK, BS_PEAK_TIME, BS_ROTATION, D_AREA, D_AX, D_AY, D_AZ, D_COP_X, D_COP_Y, D_ENERGY, D_MU, D_NORMAL,
    D_ON_RIM, D_TANGENTIAL, H_DX, H_DY, H_ROT, H_TILT, JS_FLIGHT_TIME, JS_MIN_AREA, JS_MIN_NORMAL, JS_ON_RIM,
    JS_PEAK_MU, JS_RETURNS, JS_SLIDE_TIME, JS_UPLIFT_TIME, J_LAND, J_MU, J_RIM, M_AREA, M_COP_BX, M_COP_BY,
    M_COP_X, M_COP_Y, M_NORMAL, M_NORMAL_EL, M_TX, M_TY, NB, RISE_FLOOR, SLIDE_FRACTION, S_ENERGY_START,
    S_OVERTURN_BODY, S_OVERTURN_TIME, S_PEAK_THETA, S_PEAK_TIME, W_OM, X, Y,
)
from pipeline.dynamics.excitation import ground_acceleration


@njit(cache=True)
def can_fall(y, params, energy_rest, barrier, critical):
    """Whether a structure on still ground could still fall: a body past the tilt over which its part
    tips, or the energy above the rest state at or above ``barrier``.

    With the ground still the energy (kinetic, weights, joints' springs) can only fall; every body
    below ``critical[b]`` and the energy below the lowest rise over which any part tips, none can
    ever tip. Leaves each body's rotation and angular velocity in the scratch when it says False
    (:func:`stands_for_good` reads the watched bodies' there).

    Parameters
    ----------
    y : float64[n]
        State.
    params : tuple
        :func:`make_params` (its scratch is overwritten).
    energy_rest : float
        Energy of the rest state [M g L] (``S_ENERGY_START`` of a run from rest).
    barrier : float
        The lowest overturning barrier [M g L].
    critical : float64[n_bodies]
        Critical tilt of the part that tips with each body [rad].
    """
    n_bodies = params[0].shape[0]
    for b in range(n_bodies):
        if tilt_and_rotation(y, b)[0] >= critical[b]:
            return True
    return energy(y, params) - energy_rest >= barrier


@njit(cache=True)
def stands_for_good(y, params, energy_rest, barrier, critical, peaked):
    """Whether a structure on still ground can no longer fall, each watched body's swing past its peak.

    The compliant counterpart of :func:`pipeline.dynamics.rigid.loop.stands_for_good`, called at
    checks along a run's end. The structure must not be able to fall (:func:`can_fall`), and each
    watched body (a column's top) must have been seen with its tilt not rising at some check since
    it last could: the swing each was in has then peaked, and the peak is booked (the statistics
    run at every step or sample). The watched bodies need not fall at the same check: two columns
    under an epistyle, dislocated by a record, may swing on in antiphase for minutes on still
    ground, one top always rising (docs/model.md, "The end of a run").

    Parameters
    ----------
    y, params, energy_rest, barrier, critical
        As :func:`can_fall`.
    peaked : bool[n_watched]
        Whether each watched body has been seen not rising since the structure last could fall:
        all False at a run's start, updated here.
    """
    if can_fall(y, params, energy_rest, barrier, critical):
        peaked[:] = False
        return False
    # a watched body's axis a = R e_z turns at omega x a (ground frame): its tilt rises while a_z
    # falls, a_z' = -sin(theta) theta', sin(theta) = |(a_x, a_y)|; rising: theta' above the floor
    work, watched = params[6], params[9]
    done = True
    for w in range(watched.shape[0]):
        R = work[watched[w]]  # the rotation and angular velocity energy() left in the scratch
        falls = R[W_OM] * R[5] - R[W_OM + 1] * R[2]
        if falls >= -RISE_FLOOR * math.sqrt(R[2] * R[2] + R[5] * R[5]):
            peaked[w] = True
        done = done and peaked[w]
    return done


@njit(cache=True)
def _unwrap(previous, angle):
    """``angle`` shifted by a multiple of 2 pi to lie within pi of ``previous``."""
    return angle + 2.0 * math.pi * round((previous - angle) / (2.0 * math.pi))


# inlined (with _cop_radius): called for every joint at every step, and a call that passes tables
# takes and drops their reference counts, atomic operations that cost more than the test itself
@njit(cache=True, inline="always")
def _on_rim(mon, joints, j):
    """Joint j rocks on its rim: its centre of pressure lies beyond ``J_RIM`` from the axis
    (only a rim point and its neighbours carry it), or it carries nothing (flight)."""
    if mon[j, M_NORMAL] <= 0.0:
        return True
    return _cop_radius(mon, j) >= joints[j, J_RIM]


@njit(cache=True, inline="always")
def _cop_radius(mon, j):
    """Distance of joint j's centre of pressure from the centre of its upper body's bearing face."""
    return math.sqrt(mon[j, M_COP_BX] ** 2 + mon[j, M_COP_BY] ** 2)


@njit(cache=True)
def _monitor(t, y, params, theta_commit, summary, body_stats, joint_stats, joint_committed, update):
    """Statistics of one monitor sample (if ``update``); returns the watched bodies' largest tilt.

    Leaves the per-joint monitor of ``params`` filled for the history row.
    """
    _kinematics(y, params)
    _contacts(y, params, y, False, True)
    return update_statistics(t, y, params, theta_commit, summary, body_stats, joint_stats, joint_committed,
                             update)


@njit(cache=True)
def update_statistics(t, y, params, theta_commit, summary, body_stats, joint_stats, joint_committed, update):
    """The statistics of :func:`_monitor` from the per-joint monitor of ``params`` as filled.

    Reads the monitor's normal forces (whole and elastic), tangential resultant, centre of
    pressure on the upper body's face and area in contact; returns the largest tilt of the
    watched bodies (a column's top: ``params[9]``), which is the run's peak theta. The
    fixed-step integrator fills the monitor from its own step and calls this every step.
    """
    bodies, joints, mon, watched = params[0], params[3], params[7], params[9]
    n_bodies = bodies.shape[0]
    for b in range(n_bodies):
        tilt, rot = tilt_and_rotation(y, b)
        if update:
            body_stats[b, BS_ROTATION] = _unwrap(body_stats[b, BS_ROTATION], rot)
            if tilt > body_stats[b, BS_PEAK]:
                body_stats[b, BS_PEAK] = tilt
                body_stats[b, BS_PEAK_TIME] = t
    top = 0.0
    for w in range(watched.shape[0]):
        tilt = tilt_and_rotation(y, watched[w])[0]
        if tilt > top:
            top = tilt
    if not update:
        return top
    if top > summary[S_PEAK_THETA]:
        summary[S_PEAK_THETA] = top
        summary[S_PEAK_TIME] = t
    for j in range(joints.shape[0]):
        normal = mon[j, M_NORMAL]
        tangential = math.sqrt(mon[j, M_TX] ** 2 + mon[j, M_TY] ** 2)
        if normal < joint_stats[j, JS_MIN_NORMAL]:
            joint_stats[j, JS_MIN_NORMAL] = normal
        if normal <= 0.0 and math.isnan(joint_stats[j, JS_FLIGHT_TIME]):
            joint_stats[j, JS_FLIGHT_TIME] = t
        if mon[j, M_AREA] < joint_stats[j, JS_MIN_AREA]:
            joint_stats[j, JS_MIN_AREA] = mon[j, M_AREA]
        if normal > 0.0 and mon[j, M_NORMAL_EL] > 0.0:
            mu_mob = tangential / mon[j, M_NORMAL_EL]
            if mu_mob > joint_stats[j, JS_PEAK_MU]:
                joint_stats[j, JS_PEAK_MU] = mu_mob
            if mu_mob >= SLIDE_FRACTION * joints[j, J_MU] and math.isnan(joint_stats[j, JS_SLIDE_TIME]):
                joint_stats[j, JS_SLIDE_TIME] = t
        if joints[j, J_RIM] < 0.0:
            continue  # no rim: a rectangle, a head joint
        if _on_rim(mon, joints, j):
            joint_stats[j, JS_ON_RIM] = 1.0
            if math.isnan(joint_stats[j, JS_UPLIFT_TIME]):
                joint_stats[j, JS_UPLIFT_TIME] = t
        elif joint_stats[j, JS_ON_RIM] > 0.0 and _cop_radius(mon, j) < joints[j, J_LAND]:
            # back from the rim well into the base: a landing (the hysteresis keeps a column
            # rolling from one rim point to the next, whose centre of pressure grazes the
            # rim threshold between them, from counting landings)
            joint_stats[j, JS_RETURNS] += 1.0
            joint_stats[j, JS_ON_RIM] = 0.0
    if top <= theta_commit:
        # peaks before any final fall past theta_crit (the summary uses these if it overturns)
        joint_committed[:, :] = joint_stats
    return top


@njit(cache=True)
def _history_row(t, y, params, k, hist_y, hist_diag, hist_body, body_stats, y0):
    """Write history row k from the state y and the filled per-joint monitor (joint 0: a base)."""
    bodies, points, joint_start, joints, record, dt, work, mon = params[:8]
    n_bodies = bodies.shape[0]
    nb = NB * n_bodies
    tail = nb + 2 * points.shape[0]
    hist_y[k, :nb] = y[:nb]
    hist_y[k, nb:] = y[tail:]
    normal = mon[0, M_NORMAL]
    tangential = math.sqrt(mon[0, M_TX] ** 2 + mon[0, M_TY] ** 2)
    ax, ay, az = ground_acceleration(t, record, dt)
    hist_diag[k, D_NORMAL] = normal
    hist_diag[k, D_TANGENTIAL] = tangential
    elastic = mon[0, M_NORMAL_EL]
    hist_diag[k, D_MU] = tangential / elastic if normal > 0.0 and elastic > 0.0 else math.nan
    hist_diag[k, D_COP_X] = mon[0, M_COP_X] if normal > 0.0 else math.nan
    hist_diag[k, D_COP_Y] = mon[0, M_COP_Y] if normal > 0.0 else math.nan
    hist_diag[k, D_AREA] = mon[0, M_AREA]
    hist_diag[k, D_AX] = ax
    hist_diag[k, D_AY] = ay
    hist_diag[k, D_AZ] = az
    hist_diag[k, D_ON_RIM] = 1.0 if _on_rim(mon, joints, 0) else 0.0
    for b in range(n_bodies):
        o = NB * b
        tilt, rot = tilt_and_rotation(y, b)
        hist_body[k, b, H_DX] = y[o + X] - y0[o + X]
        hist_body[k, b, H_DY] = y[o + Y] - y0[o + Y]
        hist_body[k, b, H_TILT] = tilt
        hist_body[k, b, H_ROT] = _unwrap(body_stats[b, BS_ROTATION], rot)
    hist_diag[k, D_ENERGY] = energy(y, params)  # last: it reuses the monitor


@njit(cache=True)
def start_statistics(t0, y0, params, theta_commit, hist_y, hist_diag, hist_body, summary, body_stats, joint_stats,
                     joint_committed):
    """Initialise the summary and statistics of a run from its initial state y0 at t0, and its
    first history row (if any): what every integrator of this state layout does first."""
    summary[:] = 0.0
    summary[S_OVERTURN_TIME] = math.nan
    summary[S_OVERTURN_BODY] = -1.0
    body_stats[:, :] = 0.0
    joint_stats[:, :] = 0.0
    joint_stats[:, JS_UPLIFT_TIME] = math.nan
    joint_stats[:, JS_SLIDE_TIME] = math.nan
    joint_stats[:, JS_FLIGHT_TIME] = math.nan
    joint_stats[:, JS_MIN_NORMAL] = math.inf
    joint_stats[:, JS_MIN_AREA] = math.inf
    for b in range(params[0].shape[0]):
        body_stats[b, BS_ROTATION] = tilt_and_rotation(y0, b)[1]
    summary[S_ENERGY_START] = energy(y0, params)
    _monitor(t0, y0, params, theta_commit, summary, body_stats, joint_stats, joint_committed, True)
    joint_committed[:, :] = joint_stats
    if hist_y.shape[0] > 0:
        _history_row(t0, y0, params, 0, hist_y, hist_diag, hist_body, body_stats, y0)
