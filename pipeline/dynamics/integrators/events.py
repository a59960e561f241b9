"""Dense output and terminal events of the adaptive integrators, written once for both methods.

What :func:`pipeline.dynamics.integrators.driver.integrate` does with a step's interpolant,
whichever Runge-Kutta method built it: evaluate it (:func:`dense_eval`), fill the output grid
(:func:`outputs_until`), read the event functions' signs at the end of a step and at the end
of a call's restart window (:func:`read_event_signs`), and find the earliest root among the
events that changed sign (:func:`earliest_event`, Brent's method on the interpolant).

The interpolant is held in DOP853's nested form: ``N_DENSE`` rows ``F`` such that
``y(t_old + x h) = y_old + x (F0 + (1 - x) (F1 + x (F2 + (1 - x) (F3 + ...))))``. DOP853's
7th-order extension fills all rows; DOPRI5's quartic fills four and zeroes the rest
(:mod:`pipeline.dynamics.integrators.dopri5`).

References
----------
.. [1] R. P. Brent, "Algorithms for Minimization without Derivatives", 1973, ch. 4
       (the root finder, in the form of scipy's ``brentq``).
.. [2] scipy.integrate.solve_ivp (BSD licence): the rule of which sign changes trigger an
       event (``find_active_events``) and the root tolerances.
"""

import numpy as np
from numba import njit

__all__ = [
    "N_DENSE",
    "no_events",
    "no_monitor",
    "dense_eval",
    "outputs_until",
    "read_event_signs",
    "earliest_event",
]

N_DENSE = 7  #: rows of the interpolant's nested form (DOP853's 7th-order extension)

# Root finder tolerance on the event time, as scipy's solve_ivp (xtol = rtol = 4 eps): the
# interpolant is cheap to evaluate, so the root is taken to the precision of t itself.
_EPS = np.finfo(np.float64).eps
_ROOT_XTOL = 4.0 * _EPS
_ROOT_RTOL = 4.0 * _EPS
_ROOT_MAXITER = 100


@njit(cache=True)
def no_events(t, y, params, g_out):
    """Event function for problems without events (writes nothing).

    Parameters
    ----------
    t : float
        Time [s] (unused).
    y, params, g_out
        Unused; ``g_out`` has length 0 when ``event_direction`` is empty.
    """


@njit(cache=True)
def no_monitor(t, y, params, g):
    """Step monitor for problems that watch nothing (does nothing)."""


@njit(cache=True)
def dense_eval(F, y_old, x, out):
    """Interpolated state at ``x = (t - t_old) / h`` in [0, 1] (scipy's nested form).

    Parameters
    ----------
    F : float64[N_DENSE, n]
        The step's interpolant (units of the state).
    y_old : float64[n]
        State at the start of the step.
    x : float
        Fraction of the step [1].
    out : float64[n]
        Filled with the state at ``t_old + x h``.
    """
    n = y_old.shape[0]
    for i in range(n):
        v = 0.0
        for r in range(N_DENSE - 1, -1, -1):
            v += F[r, i]
            # alternating factors x, 1-x, x, ... from the highest coefficient down
            if (N_DENSE - 1 - r) % 2 == 0:
                v *= x
            else:
                v *= 1.0 - x
        out[i] = y_old[i] + v


@njit(inline="always")
def outputs_until(F, y, t_old, h, t_stop, y_stop, t_out, y_out, out_i, m):
    """Output rows of the step up to ``t_stop`` [s] (inclusive) on the interpolant; a row
    exactly at ``t_stop`` is ``y_stop`` itself. Returns the next output index."""
    while out_i < m and t_out[out_i] <= t_stop:
        if t_out[out_i] == t_stop:
            y_out[out_i, :] = y_stop
        else:
            dense_eval(F, y, (t_out[out_i] - t_old) / h, y_out[out_i])
        out_i += 1
    return out_i


@njit(inline="always")
def _event_value(events, params, k, t, t_old, h, F, y_old, y_buf, g_buf):
    """g_k at time t on the interpolant of the current step."""
    dense_eval(F, y_old, (t - t_old) / h, y_buf)
    events(t, y_buf, params, g_buf)
    return g_buf[k]


@njit(inline="always")
def _locate_root(events, params, k, t_a, t_b, g_a, g_b, t_old, h, F, y_old, y_buf, g_buf):
    """Root of g_k on [t_a, t_b] (g_a, g_b of opposite signs or zero) by Brent's method.

    A transcription of scipy's ``brentq`` (scipy/optimize/Zeros/brentq.c) working on the
    dense output, with xtol = rtol = 4 eps.
    """
    x_pre = t_a
    x_cur = t_b
    f_pre = g_a
    f_cur = g_b
    if f_pre == 0.0:
        return x_pre
    if f_cur == 0.0:
        return x_cur
    x_blk = 0.0
    f_blk = 0.0
    s_pre = 0.0
    s_cur = 0.0
    for _ in range(_ROOT_MAXITER):
        if f_pre != 0.0 and f_cur != 0.0 and (f_pre < 0.0) != (f_cur < 0.0):
            x_blk = x_pre
            f_blk = f_pre
            s_pre = x_cur - x_pre
            s_cur = s_pre
        if abs(f_blk) < abs(f_cur):
            x_pre = x_cur
            x_cur = x_blk
            x_blk = x_pre
            f_pre = f_cur
            f_cur = f_blk
            f_blk = f_pre
        delta = 0.5 * (_ROOT_XTOL + _ROOT_RTOL * abs(x_cur))
        s_bis = 0.5 * (x_blk - x_cur)
        if f_cur == 0.0 or abs(s_bis) < delta:
            return x_cur
        if abs(s_pre) > delta and abs(f_cur) < abs(f_pre):
            if x_pre == x_blk:
                s_try = -f_cur * (x_cur - x_pre) / (f_cur - f_pre)  # secant
            else:
                d_pre = (f_pre - f_cur) / (x_pre - x_cur)
                d_blk = (f_blk - f_cur) / (x_blk - x_cur)
                s_try = -f_cur * (f_blk * d_blk - f_pre * d_pre) / (
                    d_blk * d_pre * (f_blk - f_pre)
                )  # inverse quadratic interpolation
            if 2.0 * abs(s_try) < min(abs(s_pre), 3.0 * abs(s_bis) - delta):
                s_pre = s_cur
                s_cur = s_try
            else:
                s_pre = s_bis
                s_cur = s_bis
        else:
            s_pre = s_bis
            s_cur = s_bis
        x_pre = x_cur
        f_pre = f_cur
        if abs(s_cur) > delta:
            x_cur += s_cur
        elif s_bis > 0.0:
            x_cur += delta
        else:
            x_cur -= delta
        f_cur = _event_value(events, params, k, x_cur, t_old, h, F, y_old, y_buf, g_buf)
    return x_cur


@njit(cache=True)
def _event_triggered(g_old, g_new, direction):
    """scipy's ``find_active_events`` rule for one event: a sign change allowed by direction."""
    up = g_old <= 0.0 and g_new >= 0.0
    down = g_old >= 0.0 and g_new <= 0.0
    if direction > 0:
        return up
    if direction < 0:
        return down
    return up or down


@njit(inline="always")
def read_event_signs(events, params, event_direction, n_ev, t_old, t_new, h, y, y_new, F, y_stage, g_old, g_new,
                     in_window, read_in_step, frac):
    """Event functions at the end of an accepted step, and where the step's signs start.

    Inside a call's restart window (see :mod:`pipeline.dynamics.integrators.driver`) the
    signs are read at its end, ``t_old + frac h`` on the interpolant ``F`` (built by the
    caller when ``read_in_step``); a step wholly inside it reports nothing. Returns ``(t_a,
    any_event)``: where the signs were read [s] and whether an event changed sign.
    """
    t_a = t_old
    any_event = False
    if n_ev > 0:
        events(t_new, y_new, params, g_new)
        if read_in_step:
            t_a = t_old + frac * h
            dense_eval(F, y, frac, y_stage)
            events(t_a, y_stage, params, g_old)
        elif in_window:
            g_old[:] = g_new  # the whole step is inside the restart window
        for k in range(n_ev):
            if _event_triggered(g_old[k], g_new[k], event_direction[k]):
                any_event = True
    return t_a, any_event


@njit(inline="always")
def earliest_event(events, params, event_direction, n_ev, t_a, t_new, t_old, h, F, y, y_stage, g_old, g_new,
                   g_buf):
    """Roots of the triggered events on the interpolant; the earliest wins: ``(index or -1, time [s])``."""
    event_index = -1
    t_ev = np.inf
    for k in range(n_ev):
        if not _event_triggered(g_old[k], g_new[k], event_direction[k]):
            continue
        t_root = _locate_root(
            events, params, k, t_a, t_new, g_old[k], g_new[k],
            t_old, h, F, y, y_stage, g_buf,
        )
        if t_root < t_ev:
            t_ev = t_root
            event_index = k
    return event_index, t_ev
