"""Compiled Dormand–Prince 5(4) integrator, with the calling convention of
:func:`~pipeline.dynamics.integrators.dop853.dop853`.

A numba kernel of DOPRI5 with the coefficients, error norm and step controller of
:class:`scipy.integrate.RK45` (error estimate of order 4, exponent -1/5) and its free
4th-order continuous extension (no extra stages) for the output grid and the event roots.
This module holds the method (its tableau, error estimate and interpolant); everything
else is the driver DOP853 uses too (:mod:`pipeline.dynamics.integrators.driver`): break
points no step crosses, terminal events located by Brent's method on the interpolant, the
restart window, the step monitor, the returned tuple
(:data:`pipeline.dynamics.integrators.driver.Dop853Result`). Call it the same way, from an
``@njit(cache=True)`` wrapper in the caller's module.

Why a second integrator: on a right-hand side with many kinks, DOP853's 8th order is
wasted. The compliant multi-drum model (:mod:`pipeline.dynamics.compliant.assembly`) has dozens of
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

from pipeline.dynamics.integrators.driver import integrate
from pipeline.dynamics.integrators.events import N_DENSE, no_monitor

__all__ = ["dopri5", "dopri5_monitored"]

_ERROR_ORDER = 4  # the embedded estimate is of order 4
_ERROR_EXPONENT = -1.0 / 5.0  # -1/(error estimator order + 1), the step controller's

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
    """The quartic interpolant of the step in the nested form of ``events.dense_eval``.

    scipy's ``y_old + sum_k q_k x^k`` (k = 1..4, ``q = h K^T P``) rewritten on the basis
    x, x(1-x), x^2(1-x), x^2(1-x)^2 that ``dense_eval`` evaluates, so that the event
    root finder and the output grid serve both integrators; the higher rows are zero.
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
        for r in range(4, N_DENSE):
            F[r, i] = 0.0


@njit(inline="always")
def _dense(rhs, params, t_old, h, y_old, y_new, K, F, y_stage):
    """:func:`_dense_coefficients` with the driver's arguments (it needs only h, K and F)."""
    _dense_coefficients(h, K, F)


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
    return integrate(_A, _B, _C, _N_STAGES, _N_STAGES + 1, _error_norm, _dense, 0, _ERROR_ORDER, _ERROR_EXPONENT,
                     rhs, events, monitor, params, t0, y0, t_end, t_out, y_out, out_start, event_direction,
                     t_breaks, rtol, atol, max_step, first_step, max_steps)
