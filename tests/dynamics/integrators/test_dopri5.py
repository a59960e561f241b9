"""Tests of the compiled DOPRI5 integrator (pipeline/dynamics/integrators/dopri5.py).

DOPRI5 is its tableau, error estimate and interpolant on the driver DOP853 uses
(:mod:`pipeline.dynamics.integrators.driver`), whose events, restarts and bookkeeping
``test_dop853.py`` tests in depth; here: the method against scipy's ``RK45`` (same tableau,
controller and initial step), and the driver's events and grid through DOPRI5's interpolant.
"""

import numpy as np
from numba import njit
from scipy.integrate import solve_ivp

from integrator_problems import oscillator, oscillator_events, van_der_pol
from pipeline.dynamics.integrators.dop853 import STATUS_END, STATUS_EVENT, no_events
from pipeline.dynamics.integrators.dopri5 import dopri5

EMPTY = np.zeros(0)
G = 9.80665  # [m/s^2]


@njit(cache=True)
def run_van_der_pol(p, y0, t_end, t_out, y_out, rtol, atol):
    return dopri5(van_der_pol, no_events, p, 0.0, y0, t_end, t_out, y_out, 0, EMPTY, EMPTY,
                  rtol, atol, np.inf, 0.0, 1_000_000)


@njit(cache=True)
def run_oscillator(p, t0, y0, t_end, t_out, y_out, out_start, direction, rtol, atol, first_step):
    return dopri5(oscillator, oscillator_events, p, t0, y0, t_end, t_out, y_out, out_start,
                  direction, EMPTY, rtol, atol, np.inf, first_step, 1_000_000)


def test_van_der_pol_matches_scipy_rk45():
    mu, rtol, atol = 2.0, 1e-8, 1e-11
    y0 = np.array([2.0, 0.0])
    t_end = 10.0
    t_out = np.linspace(0.0, t_end, 201)
    y_out = np.full((t_out.size, 2), np.nan)
    r = run_van_der_pol(np.array([mu]), y0, t_end, t_out, y_out, rtol, atol)
    assert r.status == STATUS_END and r.t == t_end and r.out_next == t_out.size
    sol = solve_ivp(lambda t, y: [y[1], mu * (1 - y[0] ** 2) * y[1] - y[0]], (0.0, t_end), y0,
                    method="RK45", rtol=rtol, atol=atol, t_eval=t_out)
    # the interpolant is free: f(t0), the initial-step probe and 6 per attempted step, as scipy
    assert r.nfev == 2 + 6 * (r.n_accepted + r.n_rejected)
    # same tableau, controller and initial step: the same steps up to rounding-dependent
    # decisions (10 %, as for DOP853), and the same solution to well below its own error
    # (~1e-6 at rtol 1e-8 over the relaxation jumps): 1e3 rtol of |y| ~ 3
    assert abs(r.nfev - sol.nfev) <= 0.1 * sol.nfev, (r.nfev, sol.nfev)
    scale = np.abs(sol.y).max()
    np.testing.assert_allclose(y_out, sol.y.T, rtol=0, atol=1e3 * rtol * scale)


def test_bouncing_ball_events_and_restarts_on_the_quartic_interpolant():
    """Phase by phase as the hybrid models run: impacts at the exact times, grid filled once."""
    h0, e, t_end = 1.0, 0.8, 2.5
    params = np.array([0.0, G])  # x'' = -g
    t_out = np.linspace(0.0, t_end, 1001)
    y_out = np.full((t_out.size, 2), np.nan)
    t, y, out_i, h_next = 0.0, np.array([h0, 0.0]), 0, 0.0
    impacts = []
    for _ in range(50):
        r = run_oscillator(params, t, y, t_end, t_out, y_out, out_i, np.array([0.0]), 1e-10, 1e-12, h_next)
        assert r.out_next == out_i + r.n_out
        out_i = r.out_next
        if r.status == STATUS_END:
            break
        assert r.status == STATUS_EVENT and r.event_index == 0
        impacts.append(r.t)
        t, y = r.t, np.array([0.0, -e * r.y[1]])  # the restart on x = 0 is not reported again
        h_next = r.h_next
    assert r.t == t_end and out_i == t_out.size
    v1 = np.sqrt(2 * G * h0)
    t_imp = [np.sqrt(2 * h0 / G)]
    while t_imp[-1] < t_end:
        t_imp.append(t_imp[-1] + 2 * e ** len(t_imp) * v1 / G)
    # quadratics: the 5th-order step and the quartic interpolant reproduce them exactly, so
    # only rounding remains (1e-12 s, as for DOP853)
    np.testing.assert_allclose(impacts, t_imp[:-1], rtol=0, atol=1e-12)
    k = np.searchsorted(t_imp[:-1], t_out, side="left")
    t_start = np.concatenate([[0.0], t_imp[:-1]])[k]
    v_start = np.where(k == 0, 0.0, e**k * v1)
    tau = t_out - t_start
    exact = np.stack([np.where(k == 0, h0, 0.0) + v_start * tau - 0.5 * G * tau**2, v_start - G * tau], axis=-1)
    np.testing.assert_allclose(y_out, exact, rtol=0, atol=1e-11)
