"""The same hybrid model, rolling phases integrated by scipy's ``solve_ivp``.

A reference for benchmarks and cross-checks: :func:`run_frustum_scipy` runs
the Python source of :func:`pipeline.dynamics.hybrid.run_frustum` (the same
phases, events, impact maps) with each rolling phase integrated by
``scipy.integrate.solve_ivp(method="DOP853")`` instead of the compiled
integrator. Under ``NUMBA_DISABLE_JIT=1`` every kernel, the right-hand side
included, is then plain Python: "the same model, solve_ivp, Python
right-hand side" of ``benchmarks/bench_response.py``.
"""

import contextlib
import math

import numpy as np
from scipy.integrate import solve_ivp

from pipeline.dynamics import frustum as fk
from pipeline.dynamics import hybrid as hy
from pipeline.dynamics.integrator import Dop853Result

_TINY = 1e-300


def roll_scipy(params, t0, y0, t_end, t_out, y_out, out_start, t_breaks, rtol, atol, h0):
    """One rolling phase with solve_ivp; same contract as the compiled ``_roll_frustum``.

    ``t_breaks`` is ignored (scipy has no such option: a plain implementation
    lets the error control deal with the record's kinks).
    """
    rhs = fk.rhs

    def fun(t, y):
        out = np.empty_like(y)
        rhs(t, y, params, out)
        return out

    g = np.empty(3)

    def make_event(k, direction):
        def event(t, y):
            hy._events_frustum(t, y, params, g)
            value = g[k]
            if t == t0:
                # The start is the previous event's state, where g is zero up
                # to round-off (1e-17, of either sign): give g the sign of its
                # slope so that scipy sees no crossing there, as the compiled
                # integrator ignores roots at the start.
                slope = fun(t, y)[fk.DTHETA] if k == hy.EV_TURN else fun(t, y)[fk.THETA]
                if abs(value) < 1e-12:
                    value = math.copysign(max(abs(value), _TINY), slope)
            return value

        event.terminal = True
        event.direction = direction
        return event

    events = [make_event(k, d) for k, d in enumerate(hy.EVENT_DIRECTIONS)]
    sol = solve_ivp(fun, (t0, t_end), y0, method="DOP853", rtol=rtol, atol=atol, events=events,
                    dense_output=True, first_step=h0 if h0 > 0 else None)
    t_stop = sol.t[-1]
    stop = int(np.searchsorted(t_out, t_stop, side="right"))
    if stop > out_start:
        y_out[out_start:stop] = sol.sol(t_out[out_start:stop]).T
    event_index = -1
    if sol.status == 1:
        event_index = min((k for k in range(3) if len(sol.t_events[k])), key=lambda k: sol.t_events[k][0])
    status = {0: 0, 1: 1}.get(sol.status, -1)
    n_steps = max(len(sol.t) - 1, 0)
    return Dop853Result(status, t_stop, sol.y[:, -1].copy(), event_index, sol.nfev, n_steps, 0,
                        max(stop, out_start), max(stop - out_start, 0), 0.0)


@contextlib.contextmanager
def _scipy_rolling():
    original = hy._roll_frustum
    hy._roll_frustum = roll_scipy
    try:
        yield
    finally:
        hy._roll_frustum = original


def run_frustum_scipy(*args):
    """:func:`pipeline.dynamics.hybrid.run_frustum` with scipy rolling phases (same arguments)."""
    source = getattr(hy.run_frustum, "py_func", hy.run_frustum)
    with _scipy_rolling():
        return source(*args)
