"""The same rigid 3D model, every phase integrated by scipy's ``solve_ivp``.

A reference for benchmarks and cross-checks: :func:`run_frustum_scipy` runs
the Python source of :func:`pipeline.dynamics.rigid.run3d.run_frustum` (the same
phases, events, impact maps) with each phase integrated by
``scipy.integrate.solve_ivp(method="DOP853")`` instead of the compiled
integrator. Under ``NUMBA_DISABLE_JIT=1`` every kernel, the right-hand side
included, is then plain Python: "the same model, solve_ivp, Python
right-hand side" of ``benchmarks/bench_response.py``.
"""

import contextlib

import numpy as np
from scipy.integrate import solve_ivp

from pipeline.dynamics.rigid import frustum as fk
from pipeline.dynamics.rigid import phases3d, run3d
from pipeline.dynamics.rigid.layout import EVENT_DIRECTIONS
from pipeline.dynamics.integrators.dop853 import Dop853Result

# The compiled integrator reads the event signs first at the end of a
# restart window of 1e-7 of its first step; scipy reads them at the start.
# A start that sits on an event's surface (the previous event) gets the
# sign the function takes just after it, as the compiled code sees it.
_RESTART = 1e-9  # [tau]


def integrate_scipy(params, t0, y0, t_end, t_out, y_out, out_start, t_breaks, rtol, atol, h0):
    """One phase with solve_ivp; same contract as the compiled ``phases3d.integrate3d``.

    ``t_breaks`` is ignored (scipy has no such option: a plain implementation
    lets the error control deal with the record's kinks). The step monitor is
    called at every accepted step, as the compiled integrator does.
    """
    n_ev = len(EVENT_DIRECTIONS)

    def fun(t, y):
        out = np.empty_like(y)
        phases3d.rhs3d(t, y, params, out)
        return out

    g = np.empty(n_ev)
    nudged = y0 + _RESTART * fun(t0, y0)
    start = np.empty(n_ev)
    phases3d.events3d(t0 + _RESTART, nudged, params, start)

    def make_event(k, direction):
        def event(t, y):
            phases3d.events3d(t, y, params, g)
            if t == t0:
                return start[k]
            return g[k]

        event.terminal = True
        event.direction = direction
        return event

    events = [make_event(k, d) for k, d in enumerate(EVENT_DIRECTIONS)]
    sol = solve_ivp(fun, (t0, t_end), y0, method="DOP853", rtol=rtol, atol=atol, events=events,
                    dense_output=True, first_step=h0 if h0 > 0 else None,
                    max_step=params[3][fk.OPT_MAX_STEP])
    for t_step, y_step in zip(sol.t[1:], sol.y.T[1:]):
        phases3d.events3d(t_step, y_step, params, g)
        phases3d.monitor3d(t_step, y_step, params, g)
    t_stop = sol.t[-1]
    stop = int(np.searchsorted(t_out, t_stop, side="right"))
    if stop > out_start:
        y_out[out_start:stop] = sol.sol(t_out[out_start:stop]).T
    event_index = -1
    if sol.status == 1:
        event_index = min((k for k in range(n_ev) if len(sol.t_events[k])), key=lambda k: sol.t_events[k][0])
    status = {0: 0, 1: 1}.get(sol.status, -1)
    n_steps = max(len(sol.t) - 1, 0)
    return Dop853Result(status, t_stop, sol.y[:, -1].copy(), event_index, sol.nfev, n_steps, 0,
                        max(stop, out_start), max(stop - out_start, 0), 0.0)


@contextlib.contextmanager
def _scipy_phases():
    # run_frustum's Python source looks the name up in its own module
    original = run3d.integrate3d
    run3d.integrate3d = integrate_scipy
    try:
        yield
    finally:
        run3d.integrate3d = original


def run_frustum_scipy(*args):
    """:func:`pipeline.dynamics.rigid.run3d.run_frustum` with scipy phases (same arguments)."""
    source = getattr(run3d.run_frustum, "py_func", run3d.run_frustum)
    with _scipy_phases():
        return source(*args)
