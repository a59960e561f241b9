"""The adaptive run of the compliant models: DOPRI5 (the reference) or DOP853 on the assembly's rhs.

The right-hand side, events and energy are :mod:`pipeline.dynamics.compliant.assembly`'s, the
statistics and history rows :mod:`pipeline.dynamics.compliant.statistics`', the integrators
:mod:`pipeline.dynamics.integrators.dopri5` and :mod:`pipeline.dynamics.integrators.dop853`.
Kernel layer, as :mod:`pipeline.dynamics.compliant.assembly`.
"""

import math

import numpy as np
from numba import njit

from pipeline.dynamics.compliant.assembly import _events, energy, rhs
from pipeline.dynamics.compliant.layout import (
    STATUS_COLLAPSED, S_CALLS, S_END_TIME, S_ENERGY_END, S_ENERGY_START, S_NFEV, S_OVERTURN_BODY, S_OVERTURN_TIME,
    S_REJECTED, S_STATUS, S_STEPS, S_UNDECIDED,
)
from pipeline.dynamics.compliant.statistics import _history_row, _monitor, stands_for_good, start_statistics
from pipeline.dynamics.integrators.dop853 import dop853
from pipeline.dynamics.integrators.dopri5 import dopri5

MAX_STEPS = 50_000_000
CHUNK = 64  # monitor samples per integrator call
# Integrators of :func:`run`: the joint law's kinks waste DOP853's order (pipeline.dynamics.integrators.dopri5)
METHOD_DOPRI5, METHOD_DOP853 = 0, 1
METHODS = {"dopri5": METHOD_DOPRI5, "dop853": METHOD_DOP853}


@njit(cache=True)
def _integrate(params, t0, y0, t_end, t_out, y_out, event_direction, t_breaks, rtol, atol, max_step, h0):
    return dop853(rhs, _events, params, t0, y0, t_end, t_out, y_out, 0, event_direction,
                  t_breaks, rtol, atol, max_step, h0, MAX_STEPS)


@njit(cache=True)
def _integrate5(params, t0, y0, t_end, t_out, y_out, event_direction, t_breaks, rtol, atol, max_step, h0):
    return dopri5(rhs, _events, params, t0, y0, t_end, t_out, y_out, 0, event_direction,
                  t_breaks, rtol, atol, max_step, h0, MAX_STEPS)


@njit(cache=True, nogil=True)
def run(params, y0, t_mon, stride, t_breaks, rtol, atol, max_step, event_direction, theta_commit,
        hist_y, hist_diag, hist_body, summary, body_stats, joint_stats, joint_committed, y_end,
        k_decide, barrier, critical, method=METHOD_DOPRI5):
    """Integrate from rest (or y0) up to ``t_mon[-1]``, monitoring every sample of ``t_mon``.

    From sample ``k_decide`` on (the end of the record and its tail) the run stops as soon as
    the structure stands for good (:func:`stands_for_good`, checked after every integrator
    call); if it has not by ``t_mon[-1]`` (the settle limit) it is undecided (``S_UNDECIDED``).

    Parameters
    ----------
    params : tuple
        From :func:`make_params` (dimensionless).
    y0 : float64[n]
        Initial state.
    t_mon : float64[m]
        Monitor times from 0 [tau]; the peaks, landings, uplift and friction statistics
        are taken on them (the steps follow the contact dynamics, the monitor only reads
        the dense output).
    stride : int
        Every ``stride``-th monitor sample is a history row.
    t_breaks : float64[b]
        Sample times of the record (no step crosses them).
    rtol : float
    atol : float64[n]
    event_direction : float64[2 N]
        +1 for every event (lying down, falling off).
    theta_commit : float
        Tilt of the watched bodies below which the joint statistics are committed (the values
        kept if it overturns) [rad].
    hist_y, hist_diag, hist_body : arrays
        History rows (filled for the rows reached; the rows after overturning hold the
        last state): states without shear (:func:`pipeline.dynamics.compliant.layout.kept_size`),
        first-joint diagnostics (``D_*``), per-body displacement, tilt and rotation (``H_*``).
    summary, body_stats, joint_stats, joint_committed : arrays
        Filled (``S_*``, ``BS_*``, ``JS_*``).
    y_end : float64[n]
        The final state.
    k_decide : int
        Sample at which the record and its tail end.
    barrier, critical : float, float64[n_bodies]
        Of :func:`stands_for_good` [M g L], [rad].
    method : int
        ``METHOD_DOPRI5`` (default: 2.9x fewer right-hand sides on a three-drum stack at
        equal tolerances, :mod:`pipeline.dynamics.integrators.dopri5`) or ``METHOD_DOP853`` (the
        reference it was measured against).
    """
    bodies = params[0]
    n_bodies = bodies.shape[0]
    n = y0.shape[0]
    m = t_mon.shape[0]
    n_hist = hist_y.shape[0]
    y = y0.copy()
    start_statistics(t_mon[0], y, params, theta_commit, hist_y, hist_diag, hist_body, summary, body_stats,
                     joint_stats, joint_committed)
    scratch = np.empty((CHUNK, n))
    peaked = np.zeros(params[9].shape[0], dtype=np.bool_)  # stands_for_good's watched bodies past a peak
    decided = False
    t = t_mon[0]
    h = 0.0
    i = 1
    ib = 0
    nb = t_breaks.shape[0]
    while i < m:
        stop = min(i + CHUNK, m)
        while ib < nb and t_breaks[ib] <= t:
            ib += 1
        if method == METHOD_DOP853:
            res = _integrate(params, t, y, t_mon[stop - 1], t_mon[i:stop], scratch[:stop - i],
                             event_direction, t_breaks[ib:], rtol, atol, max_step, h)
        else:
            res = _integrate5(params, t, y, t_mon[stop - 1], t_mon[i:stop], scratch[:stop - i],
                              event_direction, t_breaks[ib:], rtol, atol, max_step, h)
        summary[S_NFEV] += res.nfev
        summary[S_STEPS] += res.n_accepted
        summary[S_REJECTED] += res.n_rejected
        summary[S_CALLS] += 1
        for r in range(res.out_next):
            k = i + r
            _monitor(t_mon[k], scratch[r], params, theta_commit, summary, body_stats, joint_stats,
                     joint_committed, True)
            if k % stride == 0 and k // stride < n_hist:
                _history_row(t_mon[k], scratch[r], params, k // stride, hist_y, hist_diag, hist_body,
                             body_stats, y0)
        i += res.out_next
        y[:] = res.y
        t = res.t
        h = res.h_next
        if res.status < 0:
            summary[S_STATUS] = res.status
            break
        if res.status == 1:  # a body lies down or falls off: the structure is down
            b = res.event_index % n_bodies
            summary[S_OVERTURN_TIME] = t
            summary[S_OVERTURN_BODY] = b
            if res.event_index >= n_bodies:
                summary[S_STATUS] = STATUS_COLLAPSED
            _monitor(t, y, params, theta_commit, summary, body_stats, joint_stats, joint_committed, True)
            for k in range(i, m):  # frozen from here on
                if k % stride == 0 and k // stride < n_hist:
                    _monitor(t_mon[k], y, params, theta_commit, summary, body_stats, joint_stats,
                             joint_committed, False)
                    _history_row(t_mon[k], y, params, k // stride, hist_y, hist_diag, hist_body,
                                 body_stats, y0)
            break
        if i > k_decide and stands_for_good(y, params, summary[S_ENERGY_START], barrier, critical, peaked):
            decided = True
            break
    if (summary[S_STATUS] >= 0 and math.isnan(summary[S_OVERTURN_TIME]) and not decided
            and not stands_for_good(y, params, summary[S_ENERGY_START], barrier, critical, peaked)):
        summary[S_UNDECIDED] = 1.0
    summary[S_END_TIME] = t
    summary[S_ENERGY_END] = energy(y, params)
    y_end[:] = y
