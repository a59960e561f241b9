"""The step loop both adaptive Runge-Kutta integrators share: step control, break points,
the restart window, output grid, terminal events and the step monitor.

:func:`integrate` is parametrised by a method, that is its step, error norm and continuous
extension (functions) and a few numbers (stage rows, evaluations per step, the order of
its error estimate); :mod:`~pipeline.dynamics.integrators.dop853` and
:mod:`~pipeline.dynamics.integrators.dopri5` pass theirs. The step size controller, the
initial-step rule and the event rule are scipy's (``scipy.integrate._ivp.rk``), so that at
equal ``rtol``/``atol`` the step counts match scipy's ``DOP853`` and ``RK45``.

Calling convention
------------------
``rhs(t, y, params, dydt_out)``
    numba-jitted; writes dy/dt into ``dydt_out`` (length n) and returns nothing. It must not
    allocate if speed matters: it is called once per stage of every attempted step.
``events(t, y, params, g_out)``
    numba-jitted; writes the values of the event functions g_k into ``g_out`` (length
    ``len(event_direction)``). Use :func:`~pipeline.dynamics.integrators.events.no_events`
    when there are none.
``params``
    anything numba can type and both functions accept: a float64 array, a tuple of arrays
    (e.g. column constants and a sampled ground-acceleration record), ...

How to call it (compilation and caching)
----------------------------------------
The integrators are specialised by numba for each (rhs, events, params-type). Findings with
numba 0.68 (``benchmarks/bench_integrator.py`` measures the compile times):

* A function passed as an *argument* to an ``@njit(cache=True)`` function is typed by its
  identity (``type(CPUDispatcher(<function f at 0x...>))``), so the on-disk cache never hits
  in a new process, and every process appends one more entry to ``__pycache__``
  (numba issues #6251, #9237, #6972). A factory that closes over the functions fails the
  same way (the closure variables pickle with the dispatcher's UUID, numba #6264), and a
  cached caller that passes a global jitted function as a value is refused outright
  ("uses dynamic globals").
* What works: the public integrators and :func:`integrate` are declared ``inline="always"``,
  so numba splices their IR into the caller, where ``rhs`` and ``events`` (and the method's
  step functions, passed down by the method's module) become direct calls to globals. The
  caller writes one small ``@njit(cache=True)`` wrapper in its own module per problem; that
  wrapper caches (its key is its own argument types only) and its calls to ``rhs`` can be
  inlined by LLVM::

      @njit(cache=True)
      def integrate_rocking(params, t0, y0, t_end, t_out, y_out, out_start, t_samples, h0):
          return dop853(rocking_rhs, rocking_events, params, t0, y0, t_end,
                        t_out, y_out, out_start, ROCKING_EVENT_DIRECTION, t_samples,
                        1e-9, 1e-12, np.inf, h0, 1_000_000)

  Trade-offs: the integrator is compiled once per wrapper (cold: ~5-9 s; a fresh process
  that loads it from the cache starts in ~0.8 s, imports included); the integrators
  themselves carry no ``cache=True`` because called directly from Python they could never
  hit the cache and would only grow ``__pycache__``. As with every numba cache, the
  wrapper's cache is keyed on *its own* file: editing this module or the rhs module does
  not invalidate it (:mod:`pipeline.dynamics` points ``NUMBA_CACHE_DIR`` at a directory
  named after a digest of the kernels' sources). The alternative, first-class function
  types (``cfunc`` rhs with a fixed signature), caches the integrator itself but makes
  every rhs call an indirect, non-inlinable call and fixes the type of ``params`` in the
  signature.

Sampled forcing: pass the sample times as ``t_breaks``
-----------------------------------------------------
A record interpolated linearly has a kink at every sample; the error estimate assumes a
smooth rhs, so steps across kinks are accepted with errors ~1e3 rtol after cascades of
rejections. With the sample times as break points no step crosses one: on the benchmark's
30 s pendulum at rtol 1e-9 (DOP853) that is 14x fewer rhs calls and a 1e4x smaller error.
Without break points the steps are exactly scipy's.

Restarting (hybrid simulations)
-------------------------------
One call integrates one smooth phase. It fills ``y_out[i]`` for the grid times
``t_out[i] <= t`` reached, starting at ``out_start``, and returns ``out_next``, the first
index not filled. At a terminal event it stops at the event time with the interpolated
state; the caller applies its impact map and calls again from ``(t_event, y_new)`` with
``out_start=out_next``, so the grid is filled continuously with no point written twice.
The start state usually *is* the previous event's state (g ~ 0, its sign rounding noise),
so the event functions' signs are first taken at the end of a restart window,
``t0 + 1e-7 h`` on the interpolant, with h the first step the controller wanted: the
restart is not reported again, and a return to zero after the window still is. Roots
closer than that to ``t0`` are therefore not reported. When a break point cuts the first
step short (a record sample 1e-9 after ``t0``, say), the window still has the wanted
step's length: steps inside it report nothing, and the first step that leaves it reads
the signs at its end. (Scaling the window by the cut step instead put the reading within
rounding of ``t0``, where a noisy sign could report the restart again and again.)

Limitations
-----------
Forward integration only (``t_end >= t0``). Every event is terminal; if several events
change sign in one step the earliest root wins. As in scipy, only sign changes between the
ends of accepted steps are seen: an event function that goes out and back within one step
is missed (bound ``max_step`` if that matters).

References
----------
.. [1] E. Hairer, S. P. Nørsett, G. Wanner, "Solving Ordinary Differential Equations I:
       Nonstiff Problems", 2nd ed., Springer, 1993, Sec. II.4 (step size control, the
       initial step).
.. [2] scipy.integrate._ivp.rk and scipy.integrate._ivp.common (BSD licence): the step
       controller and ``select_initial_step``.
"""

from collections import namedtuple

import numpy as np
from numba import njit

from pipeline.dynamics.integrators.events import N_DENSE, dense_eval, earliest_event, outputs_until, read_event_signs

__all__ = [
    "integrate",
    "rk_stages",
    "rk_step",
    "select_initial_step",
    "Dop853Result",
    "STATUS_END",
    "STATUS_EVENT",
    "STATUS_STEP_TOO_SMALL",
    "STATUS_MAX_STEPS",
    "STATUS_BAD_INPUT",
]

STATUS_END = 0  #: reached t_end
STATUS_EVENT = 1  #: stopped at a terminal event
STATUS_STEP_TOO_SMALL = -1  #: step size underflow (stiffness, singularity or NaN in rhs)
STATUS_MAX_STEPS = -2  #: max_steps accepted steps taken before t_end
STATUS_BAD_INPUT = -3  #: inconsistent arguments (t_end < t0, shapes, out_start, tolerances)

# What every integrator returns (named after the first one; DOPRI5 returns it too).
Dop853Result = namedtuple(
    "Dop853Result",
    [
        "status",  # int: one of the STATUS_* codes
        "t",  # float [s]: time reached (t_end, the event time, or where it failed)
        "y",  # float64[n]: state at t (a new array)
        "event_index",  # int: index of the event that stopped the run, -1 if none
        "nfev",  # int: rhs evaluations in this call
        "n_accepted",  # int: accepted steps
        "n_rejected",  # int: rejected steps
        "out_next",  # int: first index of t_out not filled; pass as out_start to continue
        "n_out",  # int: output samples filled by this call (out_next - out_start)
        "h_next",  # float [s]: the step size the controller proposes next (first_step to resume)
    ],
)

# Step size controller of scipy's RungeKutta solvers (scipy/integrate/_ivp/rk.py); the
# exponent, -1/(order of the error estimate + 1), is the method's.
_SAFETY = 0.9  # multiply steps predicted from the asymptotic error by this
_MIN_FACTOR = 0.2  # largest decrease of the step size after a rejection
_MAX_FACTOR = 10.0  # largest increase after an acceptance

# Event roots within this fraction of the first step of a call are the restart itself
# (the caller starts on the previous event) and are not reported.
_START_WINDOW = 1e-7


@njit(inline="always")
def select_initial_step(rhs, params, t0, y0, f0, t_end, max_step, rtol, atol, y1, f1, error_order=7):
    """First step size by Hairer's rule, as scipy's ``select_initial_step``.

    ``error_order``: the order of the method's error estimate (7 for DOP853, 4 for
    DOPRI5). Returns the step size [s]; costs one rhs evaluation (``y1``, ``f1`` are work
    arrays).
    """
    n = y0.shape[0]
    interval = t_end - t0
    if interval == 0.0:
        return 0.0
    d0 = 0.0
    d1 = 0.0
    for i in range(n):
        scale = atol[i] + abs(y0[i]) * rtol
        d0 += (y0[i] / scale) ** 2
        d1 += (f0[i] / scale) ** 2
    d0 = np.sqrt(d0 / n)
    d1 = np.sqrt(d1 / n)
    if d0 < 1e-5 or d1 < 1e-5:
        h0 = 1e-6
    else:
        h0 = 0.01 * d0 / d1
    h0 = min(h0, interval)
    for i in range(n):
        y1[i] = y0[i] + h0 * f0[i]
    rhs(t0 + h0, y1, params, f1)
    d2 = 0.0
    for i in range(n):
        scale = atol[i] + abs(y0[i]) * rtol
        d2 += ((f1[i] - f0[i]) / scale) ** 2
    d2 = np.sqrt(d2 / n) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / (error_order + 1))
    return min(100.0 * h0, h1, interval, max_step)


@njit(inline="always")
def rk_stages(A, C, first, last, rhs, params, t, y, h, K, y_stage):
    """Stages ``first`` to ``last - 1`` of an explicit Runge-Kutta step into ``K``.

    Stage s is f(t + C[s] h, y + h sum_{j<s} A[s, j] K[j]); ``K[:first]`` must hold the
    earlier ones. ``h`` [s]; costs ``last - first`` rhs evaluations (``y_stage`` is a work
    array).
    """
    n = y.shape[0]
    for s in range(first, last):
        for i in range(n):
            acc = 0.0
            for j in range(s):
                acc += A[s, j] * K[j, i]
            y_stage[i] = y[i] + h * acc
        rhs(t + C[s] * h, y_stage, params, K[s])


@njit(inline="always")
def rk_step(A, B, C, n_stages, rhs, params, t, y, h, K, y_stage, y_new):
    """One step of length ``h`` [s]: stages 1.. into ``K``, the new state into ``y_new``, and
    f(t + h, y_new) into ``K[n_stages]``.

    ``K[0]`` must hold f(t, y). Costs ``n_stages`` rhs evaluations.
    """
    rk_stages(A, C, 1, n_stages, rhs, params, t, y, h, K, y_stage)
    n = y.shape[0]
    for i in range(n):
        acc = 0.0
        for j in range(n_stages):
            acc += B[j] * K[j, i]
        y_new[i] = y[i] + h * acc
    rhs(t + h, y_new, params, K[n_stages])


@njit(inline="always")
def integrate(
    A,
    B,
    C,
    n_stages,
    n_rows,
    error_norm,
    dense_coefficients,
    dense_evals,
    error_order,
    error_exponent,
    rhs,
    events,
    monitor,
    params,
    t0,
    y0,
    t_end,
    t_out,
    y_out,
    out_start,
    event_direction,
    t_breaks,
    rtol,
    atol,
    max_step,
    first_step,
    max_steps,
):
    """Integrate dy/dt = rhs(t, y) from t0 to t_end with one Runge-Kutta method.

    Called by the methods' integrators (:func:`~pipeline.dynamics.integrators.dop853.dop853_monitored`,
    :func:`~pipeline.dynamics.integrators.dopri5.dopri5_monitored`), which pass the first
    ten arguments; the rest are theirs, documented there. Inlined at numba's IR level, so
    that the method's functions, passed as arguments, become direct calls, and its
    tableau's arrays constants.

    Parameters
    ----------
    A, B, C : float64 arrays
        The method's Butcher tableau: stage coefficients ``A[s, j]`` (j < s), weights
        ``B[j]`` of the solution, nodes ``C[s]`` [1] (see :func:`rk_step`).
    n_stages : int
        Stages of a step; ``K[n_stages]`` then holds f(t + h, y_new), the next step's
        first stage (FSAL). A step costs ``n_stages`` rhs evaluations.
    n_rows : int
        Rows of the stage array ``K``: the stages, f at the new point and any extra
        stages of the continuous extension.
    error_norm : numba-jitted function
        ``error_norm(K, h, y, y_new, rtol, atol) -> float``: the step's scaled error [1];
        accepted when < 1.
    dense_coefficients : numba-jitted function
        ``dense_coefficients(rhs, params, t_old, h, y_old, y_new, K, F, y_stage)``: the
        step's interpolant into ``F`` (``N_DENSE`` rows, the nested form of
        :func:`~pipeline.dynamics.integrators.events.dense_eval`), after the step's
        stages; it may evaluate extra stages into ``K``.
    dense_evals : int
        rhs evaluations of ``dense_coefficients``.
    error_order : int
        Order of the error estimate (the initial-step rule's exponent).
    error_exponent : float
        The controller's exponent, -1 / (``error_order`` + 1).

    Returns
    -------
    Dop853Result
        ``(status, t, y, event_index, nfev, n_accepted, n_rejected, out_next, n_out,
        h_next)``; see :data:`Dop853Result` and the ``STATUS_*`` codes.
    """
    n = y0.shape[0]
    n_ev = event_direction.shape[0]
    m = t_out.shape[0]

    # All work arrays of the call, allocated once here.
    y = np.empty(n)
    y[:] = y0
    y_new = np.empty(n)
    y_stage = np.empty(n)
    K = np.empty((n_rows, n))
    F = np.empty((N_DENSE, n))  # every row is written before it is read
    atol_v = np.empty(n)
    atol_v[:] = atol  # a scalar broadcasts; an array is copied
    g_old = np.full(n_ev, np.nan)  # NaN triggers nothing: no sign is ever read before it is set
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
        h_abs = select_initial_step(rhs, params, t, y, K[0], t_end, max_step, rtol, atol_v, y_stage, K[1],
                                    error_order)
        nfev += 1

    n_acc = 0
    n_rej = 0
    restart_end = t0  # end of the restart window, set by the first step (events only)
    status = STATUS_END
    event_index = -1
    n_breaks = t_breaks.shape[0]
    i_break = 0
    while t < t_end:
        if n_acc >= max_steps:
            status = STATUS_MAX_STEPS
            break
        # no step crosses a break point: the rhs may have a kink there
        while i_break < n_breaks and t_breaks[i_break] <= t:
            i_break += 1
        t_stop = t_end
        if i_break < n_breaks and t_breaks[i_break] < t_end:
            t_stop = t_breaks[i_break]
        # --- one accepted step, as scipy's RungeKutta._step_impl -------------------------
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
            if not (h_abs >= min_step):  # also a NaN step (NaN in rhs or tolerances)
                break
            h_wanted = h_abs
            t_new = t + h_abs
            if t_new > t_stop:
                t_new = t_stop
            h = t_new - t
            h_abs = abs(h)
            rk_step(A, B, C, n_stages, rhs, params, t, y, h, K, y_stage, y_new)
            nfev += n_stages
            err = error_norm(K, h, y, y_new, rtol, atol_v)
            if err < 1.0:
                if err == 0.0:
                    factor = _MAX_FACTOR
                else:
                    factor = min(_MAX_FACTOR, _SAFETY * err**error_exponent)
                if rejected:
                    factor = min(1.0, factor)
                h_abs *= factor
                accepted = True
            else:
                factor = _SAFETY * err**error_exponent
                if not (factor > _MIN_FACTOR):  # also when err is NaN: shrink, never NaN h
                    factor = _MIN_FACTOR
                h_abs *= factor
                rejected = True
                n_rej += 1
        if not accepted:
            status = STATUS_STEP_TOO_SMALL
            break
        if t_stop < t_end and t_new == t_stop and not rejected and h_abs < h_wanted:
            # A step shortened to end on a break says little about the step size the
            # solution allows; keep the step that was wanted (scipy has no breaks).
            h_abs = h_wanted
        n_acc += 1
        t_old = t

        # The interpolant may cost rhs evaluations (DOP853: 3): build it only for a step
        # that holds an output point before its end or a sign change of an event function.
        need_dense = out_i < m and t_out[out_i] < t_new
        # A call starts on the previous phase's event (the restart state, g ~ 0, its sign
        # rounding noise). The signs are first taken at the end of the restart window,
        # 1e-7 of the step the controller wanted (not of a first step cut short by a
        # break, which may be ~1e-9 long): the restart is not reported again while a
        # return to zero after the window still is. Steps inside the window report nothing.
        first_step_of_call = n_acc == 1
        if n_ev > 0 and first_step_of_call:
            # at a late time a tiny first step's window can round away (t + 1e-16 == t):
            # it still ends at least one float after the start, so the first step reads signs
            restart_end = max(t_old + _START_WINDOW * max(h, h_wanted), np.nextafter(t_old, np.inf))
        in_window = n_ev > 0 and t_old < restart_end
        read_in_step = in_window and t_new > restart_end
        if need_dense or read_in_step:
            dense_coefficients(rhs, params, t_old, h, y, y_new, K, F, y_stage)
            nfev += dense_evals
        # an uncut first step reads at exactly t_old + 1e-7 h
        frac = 0.0
        if read_in_step:
            frac = _START_WINDOW if (first_step_of_call and h_wanted <= h) else (restart_end - t_old) / h
        t_a, any_event = read_event_signs(events, params, event_direction, n_ev, t_old, t_new, h, y, y_new, F,
                                          y_stage, g_old, g_new, in_window, read_in_step, frac)
        if any_event and not (need_dense or read_in_step):
            dense_coefficients(rhs, params, t_old, h, y, y_new, K, F, y_stage)
            nfev += dense_evals

        if any_event:
            event_index, t_ev = earliest_event(events, params, event_direction, n_ev, t_a, t_new, t_old, h, F, y,
                                               y_stage, g_old, g_new, g_buf)
            if event_index >= 0:
                dense_eval(F, y, (t_ev - t_old) / h, y_new)
                out_i = outputs_until(F, y, t_old, h, t_ev, y_new, t_out, y_out, out_i, m)
                t = t_ev
                y[:] = y_new
                events(t, y, params, g_buf)
                monitor(t, y, params, g_buf)
                status = STATUS_EVENT
                break
        if n_ev > 0:
            g_old[:] = g_new

        # output grid points inside the step (the end point is y_new itself)
        out_i = outputs_until(F, y, t_old, h, t_new, y_new, t_out, y_out, out_i, m)

        t = t_new
        y[:] = y_new
        monitor(t, y, params, g_new)
        K[0, :] = K[n_stages]  # FSAL: f at the new point starts the next step

    return Dop853Result(
        status, t, y, event_index, nfev, n_acc, n_rej, out_i, out_i - out_start, h_abs
    )
