"""Compiled Dormand–Prince 5(4) integrator, with the calling convention of
:func:`~pipeline.dynamics.integrators.dop853.dop853`.

A numba kernel of DOPRI5 with the coefficients, error norm and step controller of
:class:`scipy.integrate.RK45` (error estimate of order 4, exponent -1/5), its free
4th-order continuous extension (no extra stages) for the output grid and the event roots,
and everything else of :func:`pipeline.dynamics.integrators.dop853.dop853_monitored` unchanged:
break points no step crosses, terminal events located by Brent's method on the
interpolant, the restart window, the step monitor, the returned tuple
(:data:`pipeline.dynamics.integrators.dop853.Dop853Result`). Call it the same way, from an
``@njit(cache=True)`` wrapper in the caller's module.

Why a second integrator: on a right-hand side with many kinks, DOP853's 8th order is
wasted. The compliant multi-drum model (:mod:`pipeline.dynamics.compliant.stack`) has dozens of
contact points per joint entering and leaving compression and switching between stick
and slip; across each such kink the local error behaves as a low power of the step
(the shear state's rate jumps when a point touches), so DOP853's controller, which
expects h^8, rejects about as many steps as it accepts and pays 12 stages for each.
Measured on a three-drum stack under FEMA-FF-01 at the same tolerances (rtol 1e-9,
atol 1e-12): DOPRI5 takes 2.9x fewer right-hand sides with the same energy balance
(``benchmarks/bench_compliant.py drums``, docs/model.md). On a smooth right-hand side at
tight tolerances DOP853 remains the better choice (the rigid kernels keep it).

References
----------
.. [1] J. R. Dormand, P. J. Prince, "A family of embedded Runge-Kutta formulae",
       J. Comput. Appl. Math. 6 (1980) 19-26.
.. [2] L. F. Shampine, "Some practical Runge-Kutta formulas", Math. Comp. 46 (1986)
       135-150 (the continuous extension).
.. [3] scipy.integrate.RK45 (scipy/integrate/_ivp/rk.py, BSD licence): the coefficient
       table, error estimate and dense-output matrix reproduced below.
"""

import numpy as np
from numba import njit

from pipeline.dynamics.integrators.dop853 import (
    _START_WINDOW,
    STATUS_BAD_INPUT,
    STATUS_END,
    STATUS_EVENT,
    STATUS_MAX_STEPS,
    STATUS_STEP_TOO_SMALL,
    Dop853Result,
    _dense_eval,
    _earliest_event,
    _outputs_until,
    _read_event_signs,
    _select_initial_step,
    no_monitor,
)

__all__ = ["dopri5", "dopri5_monitored"]

# Step size controller of scipy's RungeKutta solvers, with the exponent of a 4th-order estimate.
_SAFETY = 0.9
_MIN_FACTOR = 0.2
_MAX_FACTOR = 10.0
_ERROR_EXPONENT = -1.0 / 5.0

_N_STAGES = 6
_C = np.array([0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0])
_A = np.array([
    [0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0],
    [19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0],
    [9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0],
])
_B = np.array([35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0])
# 5th minus 4th order weights; the 7th entry weighs f(t + h, y_new) (FSAL)
_E = np.array([-71.0 / 57600.0, 0.0, 71.0 / 16695.0, -71.0 / 1920.0, 17253.0 / 339200.0, -22.0 / 525.0,
               1.0 / 40.0])
# y(t + x h) = y + h sum_k (K^T P)[:, k] x^(k+1): scipy's RK45 dense output
_P = np.array([
    [1.0, -8048581381.0 / 2820520608.0, 8663915743.0 / 2820520608.0, -12715105075.0 / 11282082432.0],
    [0.0, 0.0, 0.0, 0.0],
    [0.0, 131558114200.0 / 32700410799.0, -68118460800.0 / 10900136933.0, 87487479700.0 / 32700410799.0],
    [0.0, -1754552775.0 / 470086768.0, 14199869525.0 / 1410260304.0, -10690763975.0 / 1880347072.0],
    [0.0, 127303824393.0 / 49829197408.0, -318862633887.0 / 49829197408.0, 701980252875.0 / 199316789632.0],
    [0.0, -282668133.0 / 205662961.0, 2019193451.0 / 616988883.0, -1453857185.0 / 822651844.0],
    [0.0, 40617522.0 / 29380423.0, -110615467.0 / 29380423.0, 69997945.0 / 29380423.0],
])
_N_DENSE = 7  # rows of the interpolant in the nested form of integrator._dense_eval (4 used)


@njit(inline="always")
def _rk_step(rhs, params, t, y, h, K, y_stage, y_new):
    """One DOPRI5 step: stages 1..5 into ``K``, ``y_new``, and f(t+h, y_new) into ``K[6]``.

    ``K[0]`` must hold f(t, y). Costs 6 rhs evaluations.
    """
    n = y.shape[0]
    for s in range(1, _N_STAGES):
        for i in range(n):
            acc = 0.0
            for j in range(s):
                acc += _A[s, j] * K[j, i]
            y_stage[i] = y[i] + h * acc
        rhs(t + _C[s] * h, y_stage, params, K[s])
    for i in range(n):
        acc = 0.0
        for j in range(_N_STAGES):
            acc += _B[j] * K[j, i]
        y_new[i] = y[i] + h * acc
    rhs(t + h, y_new, params, K[_N_STAGES])


@njit(cache=True)
def _error_norm(K, h, y, y_new, rtol, atol):
    """Scaled RMS error of a step (scipy's ``RK45``): accepted when < 1."""
    n = y.shape[0]
    s = 0.0
    for i in range(n):
        scale = atol[i] + max(abs(y[i]), abs(y_new[i])) * rtol
        e = 0.0
        for j in range(_N_STAGES + 1):
            e += _E[j] * K[j, i]
        e *= h / scale
        s += e * e
    return np.sqrt(s / n)


@njit(cache=True)
def _dense_coefficients(h, K, F):
    """The quartic interpolant of the step in the nested form of ``integrator._dense_eval``.

    scipy's ``y_old + sum_k q_k x^k`` (k = 1..4, ``q = h K^T P``) rewritten on the basis
    x, x(1-x), x^2(1-x), x^2(1-x)^2 that ``_dense_eval`` evaluates, so that the event
    root finder and the output grid of the DOP853 module serve both integrators.
    No rhs evaluations.
    """
    n = K.shape[1]
    for i in range(n):
        q1 = 0.0
        q2 = 0.0
        q3 = 0.0
        q4 = 0.0
        for j in range(_N_STAGES + 1):
            k = K[j, i]
            q1 += _P[j, 0] * k
            q2 += _P[j, 1] * k
            q3 += _P[j, 2] * k
            q4 += _P[j, 3] * k
        f3 = h * q4
        f2 = -h * q3 - 2.0 * f3
        f1 = f2 + f3 - h * q2
        F[0, i] = h * q1 - f1
        F[1, i] = f1
        F[2, i] = f2
        F[3, i] = f3
        for r in range(4, _N_DENSE):
            F[r, i] = 0.0


@njit(inline="always")
def dopri5(rhs, events, params, t0, y0, t_end, t_out, y_out, out_start, event_direction, t_breaks,
           rtol, atol, max_step, first_step, max_steps):
    """Integrate dy/dt = rhs(t, y) from t0 to t_end with DOPRI5, dense output and events.

    :func:`dopri5_monitored` without a step monitor.
    """
    return dopri5_monitored(rhs, events, no_monitor, params, t0, y0, t_end, t_out, y_out, out_start,
                            event_direction, t_breaks, rtol, atol, max_step, first_step, max_steps)


@njit(inline="always")
def dopri5_monitored(rhs, events, monitor, params, t0, y0, t_end, t_out, y_out, out_start, event_direction,
                     t_breaks, rtol, atol, max_step, first_step, max_steps):
    """Integrate dy/dt = rhs(t, y) from t0 to t_end with DOPRI5, dense output and events.

    Arguments, results and behaviour (break points, events, restart window, monitor) as
    :func:`pipeline.dynamics.integrators.dop853.dop853_monitored`, except: 6 rhs evaluations per
    attempted step (the last stage is the next step's first), the output grid and the
    event roots are read on the 4th-order interpolant, which costs no evaluations, and
    ``rtol``, ``atol`` control a 4th-order error estimate.
    """
    n = y0.shape[0]
    n_ev = event_direction.shape[0]
    m = t_out.shape[0]

    y = np.empty(n)
    y[:] = y0
    y_new = np.empty(n)
    y_stage = np.empty(n)
    K = np.empty((_N_STAGES + 1, n))
    F = np.zeros((_N_DENSE, n))
    atol_v = np.empty(n)
    atol_v[:] = atol
    g_old = np.full(n_ev, np.nan)
    g_new = np.empty(n_ev)
    g_buf = np.empty(n_ev)

    t = t0
    out_i = out_start
    bad = (
        not (t_end >= t0)
        or y_out.shape[0] != m
        or y_out.shape[1] != n
        or out_start < 0
        or out_start > m
        or not (rtol > 0.0)
        or not (max_step > 0.0)
    )
    for i in range(n):
        if not (atol_v[i] >= 0.0):
            bad = True
    if bad:
        return Dop853Result(STATUS_BAD_INPUT, t, y, -1, 0, 0, 0, out_i, 0, 0.0)

    while out_i < m and t_out[out_i] <= t0:
        y_out[out_i, :] = y
        out_i += 1
    if t_end == t0:
        return Dop853Result(STATUS_END, t, y, -1, 0, 0, 0, out_i, out_i - out_start, 0.0)

    rhs(t, y, params, K[0])
    nfev = 1
    if first_step > 0.0:
        h_abs = first_step
    else:
        h_abs = _select_initial_step(rhs, params, t, y, K[0], t_end, max_step, rtol, atol_v, y_stage, K[1], 4)
        nfev += 1

    n_acc = 0
    n_rej = 0
    restart_end = t0
    status = STATUS_END
    event_index = -1
    n_breaks = t_breaks.shape[0]
    i_break = 0
    while t < t_end:
        if n_acc >= max_steps:
            status = STATUS_MAX_STEPS
            break
        while i_break < n_breaks and t_breaks[i_break] <= t:
            i_break += 1
        t_stop = t_end
        if i_break < n_breaks and t_breaks[i_break] < t_end:
            t_stop = t_breaks[i_break]
        min_step = 10.0 * abs(np.nextafter(t, np.inf) - t)
        if h_abs > max_step:
            h_abs = max_step
        elif h_abs < min_step:
            h_abs = min_step
        rejected = False
        accepted = False
        t_new = t
        h = 0.0
        h_wanted = h_abs
        while not accepted:
            if not (h_abs >= min_step):
                break
            h_wanted = h_abs
            t_new = t + h_abs
            if t_new > t_stop:
                t_new = t_stop
            h = t_new - t
            h_abs = abs(h)
            _rk_step(rhs, params, t, y, h, K, y_stage, y_new)
            nfev += 6
            err = _error_norm(K, h, y, y_new, rtol, atol_v)
            if err < 1.0:
                if err == 0.0:
                    factor = _MAX_FACTOR
                else:
                    factor = min(_MAX_FACTOR, _SAFETY * err**_ERROR_EXPONENT)
                if rejected:
                    factor = min(1.0, factor)
                h_abs *= factor
                accepted = True
            else:
                factor = _SAFETY * err**_ERROR_EXPONENT
                if not (factor > _MIN_FACTOR):
                    factor = _MIN_FACTOR
                h_abs *= factor
                rejected = True
                n_rej += 1
        if not accepted:
            status = STATUS_STEP_TOO_SMALL
            break
        if t_stop < t_end and t_new == t_stop and not rejected and h_abs < h_wanted:
            h_abs = h_wanted
        n_acc += 1
        t_old = t

        # the interpolant is free: build it for output points and event roots alike
        need_dense = out_i < m and t_out[out_i] < t_new
        first_step_of_call = n_acc == 1
        if n_ev > 0 and first_step_of_call:
            restart_end = max(t_old + _START_WINDOW * max(h, h_wanted), np.nextafter(t_old, np.inf))
        in_window = n_ev > 0 and t_old < restart_end
        read_in_step = in_window and t_new > restart_end
        if need_dense or read_in_step:
            _dense_coefficients(h, K, F)
        frac = 0.0
        if read_in_step:
            frac = _START_WINDOW if (first_step_of_call and h_wanted <= h) else (restart_end - t_old) / h
        t_a, any_event = _read_event_signs(events, params, event_direction, n_ev, t_old, t_new, h, y, y_new, F,
                                           y_stage, g_old, g_new, in_window, read_in_step, frac)
        if any_event and not (need_dense or read_in_step):
            _dense_coefficients(h, K, F)

        if any_event:
            event_index, t_ev = _earliest_event(events, params, event_direction, n_ev, t_a, t_new, t_old, h, F, y,
                                                y_stage, g_old, g_new, g_buf)
            if event_index >= 0:
                _dense_eval(F, y, (t_ev - t_old) / h, y_new)
                out_i = _outputs_until(F, y, t_old, h, t_ev, y_new, t_out, y_out, out_i, m)
                t = t_ev
                y[:] = y_new
                events(t, y, params, g_buf)
                monitor(t, y, params, g_buf)
                status = STATUS_EVENT
                break
        if n_ev > 0:
            g_old[:] = g_new

        out_i = _outputs_until(F, y, t_old, h, t_new, y_new, t_out, y_out, out_i, m)

        t = t_new
        y[:] = y_new
        monitor(t, y, params, g_new)
        K[0, :] = K[_N_STAGES]  # FSAL

    return Dop853Result(status, t, y, event_index, nfev, n_acc, n_rej, out_i, out_i - out_start, h_abs)

