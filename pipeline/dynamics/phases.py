"""Run the rolling phase between events: landing (theta -> 0) and falling over.

Kernel layer: arrays in, arrays out. The output grid ``tau_out`` is filled in
``states`` as the integration proceeds; after a terminal event the caller
(or this module, for planar landings) changes the state and continues.
"""

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from pipeline.dynamics import frustum as fk

REACHED_END = "reached_end"
LANDED = "landed_out_of_plane"
OVERTURNED = "overturned"


@dataclass
class Outcome:
    """How an integration ended."""

    status: str
    tau_end: float
    n_landings: int = 0
    n_rhs: int = 0

    def describe(self):
        return f"{self.status} at tau = {self.tau_end:.6g} after {self.n_landings} planar landings"


def _planar_landing(y, restitution):
    """Switch the pivot to the opposite rim point at a planar landing.

    The body does not rotate at the instant of impact, so with the new line
    of nodes (phi + pi) the spin angle becomes psi - pi; the contact point
    jumps across the base by 2R; theta' changes sign and is scaled by the
    coefficient of restitution.
    """
    y = y.copy()
    s, c = fk.sincos(y[fk.PHI])
    y[fk.XP] -= 2.0 * s
    y[fk.YP] += 2.0 * c
    # keep phi in (-pi, pi] so that multiples of pi stay exact
    y[fk.PHI] = y[fk.PHI] - math.pi if y[fk.PHI] > 0.0 else y[fk.PHI] + math.pi
    y[fk.PSI] -= math.pi
    y[fk.THETA] = 0.0
    y[fk.DTHETA] = -restitution * y[fk.DTHETA]
    return y


def integrate_rolling(params, y0, tau_out, states, rtol, atol, restitution, max_landings=100000):
    """Integrate rolling on the rim over the output grid, handling landings.

    Parameters
    ----------
    params : tuple
        ``(constants, record, dt)`` as :func:`pipeline.dynamics.frustum.rhs` takes.
    y0 : numpy.ndarray
        Initial state (theta > 0).
    tau_out : numpy.ndarray
        Increasing output times [tau], starting at the initial time.
    states : numpy.ndarray, shape (len(tau_out), N_STATE)
        Filled with the state at each output time reached (NaN after a stop).
    rtol, atol : float
        Tolerances.
    restitution : float
        theta'_after / theta'_before at a planar landing.

    Returns
    -------
    Outcome
    """

    def fun(t, y):
        out = np.empty_like(y)
        fk.rhs(t, y, params, out)
        return out

    def landing(t, y):
        return y[fk.THETA]

    landing.terminal = True
    landing.direction = -1

    def falling(t, y):
        return y[fk.THETA] - 0.5 * math.pi

    falling.terminal = True
    falling.direction = 1

    tau = float(tau_out[0])
    y = np.array(y0, dtype=np.float64)
    states[0] = y
    next_index = 1
    n_landings = 0
    n_rhs = 0
    while True:
        sol = solve_ivp(
            fun, (tau, float(tau_out[-1])), y, method="DOP853", rtol=rtol, atol=atol,
            events=(landing, falling), dense_output=True,
        )
        n_rhs += sol.nfev
        t_stop = sol.t[-1]
        stop = np.searchsorted(tau_out, t_stop, side="right")
        if stop > next_index:
            states[next_index:stop] = sol.sol(tau_out[next_index:stop]).T
            next_index = stop
        if sol.status == 0:
            return Outcome(REACHED_END, t_stop, n_landings, n_rhs)
        if sol.status < 0:
            raise RuntimeError(f"integration failed at tau = {t_stop}: {sol.message}")
        y = sol.y[:, -1].copy()
        tau = t_stop
        if len(sol.t_events[1]):
            return Outcome(OVERTURNED, tau, n_landings, n_rhs)
        planar = y[fk.DPHI] == 0.0 and y[fk.OMEGA] == 0.0
        if not planar or n_landings >= max_landings:
            return Outcome(LANDED, tau, n_landings, n_rhs)
        y = _planar_landing(y, restitution)
        n_landings += 1
