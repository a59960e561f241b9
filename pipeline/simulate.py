"""One column, one motion, one set of settings -> one response Dataset.

This module is the friendly layer over :mod:`pipeline.dynamics`: it converts
SI inputs to the kernels' dimensionless variables, runs the phases of motion
and returns an ``xarray.Dataset`` named and annotated as in
:mod:`pipeline.dataset`.
"""

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from pipeline.dataset import annotate, append_history
from pipeline.dynamics import frustum as fk
from pipeline.dynamics.phases import LANDED, OVERTURNED, REACHED_END, integrate_rolling
from pipeline.errors import InputError
from pipeline.units import G


@dataclass(frozen=True)
class InitialState:
    """Euler angles [rad] and their rates [rad/s] at t = 0 (the paper's Figure 2)."""

    phi: float = 0.0
    theta: float = 0.0
    psi: float = 0.0
    phi_dot: float = 0.0
    theta_dot: float = 0.0
    psi_dot: float = 0.0

    def __post_init__(self):
        for name in ("phi", "theta", "psi", "phi_dot", "theta_dot", "psi_dot"):
            value = getattr(self, name)
            if not math.isfinite(value):
                raise InputError(f"initial {name} = {value!r} must be a finite number")
        if not 0.0 < self.theta < math.pi / 2:
            raise InputError(
                f"initial theta = {math.degrees(self.theta):g} deg: a free motion starts tilted on its rim, "
                "0 < theta < 90 deg"
            )

    @classmethod
    def from_dimensionless(cls, radius, phi, theta, psi, dphi, dtheta, dpsi):
        """Build from rates in the paper's dimensionless time (per tau), for a base radius [m]."""
        rate = math.sqrt(G / radius)
        return cls(phi, theta, psi, dphi * rate, dtheta * rate, dpsi * rate)


@dataclass(frozen=True)
class SolverSettings:
    """Accuracy and output sampling of the integration.

    Parameters
    ----------
    rtol, atol : float
        Relative and absolute tolerances of the adaptive integrator (on the
        dimensionless state).
    output_step : float
        Sampling interval of the returned histories [s].
    """

    rtol: float = 1e-10
    atol: float = 1e-12
    output_step: float = 0.01

    def __post_init__(self):
        for name in ("rtol", "atol", "output_step"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise InputError(f"solver {name} = {value!r} must be a positive number")


def housner_restitution(column):
    """Coefficient of restitution of planar rocking from angular momentum conservation.

    Conserving the angular momentum about the new contact point, opposite
    the old one across the base, gives ``theta'_after / theta'_before =
    1 - 2 m R^2 / I_P = 1 - 2 / I_y_hat`` (docs/model.md). For a slender
    column this tends to Housner's ``1 - 1.5 sin^2(alpha)`` of the block with
    the same outline. Clipped at 0 for squat columns (I_y_hat < 2).
    """
    # A squat body (I_y_hat < 2) would come out with a negative ratio: it
    # does not rebound at all, so the ratio is 0 and it settles.
    return max(0.0, 1.0 - 2.0 / column.inertia_transverse_hat)


def simulate_free(column, initial, duration, settings=SolverSettings(), restitution=None):
    """Free motion (no ground motion) of a column released on its rim.

    Parameters
    ----------
    column : pipeline.geometry.Column
    initial : InitialState
    duration : float
        Length of the simulation [s].
    settings : SolverSettings
    restitution : float, optional
        Ratio of theta' after to before a planar landing; defaults to the
        angular-momentum value :func:`housner_restitution`. A landing with
        out-of-plane motion ends the simulation (phase ``landed``): it needs
        the impact model of the earthquake response.

    Returns
    -------
    xarray.Dataset
        Time histories named as in the project's architecture.
    """
    if not (math.isfinite(duration) and duration > 0):
        raise InputError(f"duration = {duration!r} s must be a positive number of seconds")
    e = housner_restitution(column) if restitution is None else float(restitution)
    if not 0.0 <= e <= 1.0:
        raise InputError(f"restitution = {restitution!r} must be between 0 and 1")
    t_scale = math.sqrt(column.R / G)  # seconds per unit tau
    rate = t_scale  # (rad/s) * t_scale = rad per tau
    y0 = np.zeros(fk.N_STATE)
    y0[fk.PHI], y0[fk.THETA], y0[fk.PSI] = initial.phi, initial.theta, initial.psi
    y0[fk.DPHI] = initial.phi_dot * rate
    y0[fk.DTHETA] = initial.theta_dot * rate
    y0[fk.OMEGA] = (initial.phi_dot * math.cos(initial.theta) + initial.psi_dot) * rate
    n_out = int(math.floor(duration / settings.output_step + 1e-9)) + 1
    time = np.arange(n_out) * settings.output_step
    tau_out = time / t_scale
    params = (column.kernel_constants(), np.zeros((0, 3)), 1.0)
    states = np.full((n_out, fk.N_STATE), np.nan)
    outcome = integrate_rolling(params, y0, tau_out, states, settings.rtol, settings.atol, e)
    return _response_dataset(column, time, tau_out, states, params, outcome, e)


def _response_dataset(column, time, tau_out, states, params, outcome, restitution):
    """Assemble the Dataset of histories from integrated dimensionless states."""
    t_scale = math.sqrt(column.R / G)
    n = len(time)
    diag = np.full((n, fk.N_DIAGNOSTICS), np.nan)
    valid = ~np.isnan(states[:, fk.THETA])
    buf = np.empty(fk.N_DIAGNOSTICS)
    for i in np.flatnonzero(valid):
        fk.diagnostics(tau_out[i], states[i], params, buf)
        diag[i] = buf
    per_s = 1.0 / t_scale
    data = {
        "phi": states[:, fk.PHI],
        "theta": states[:, fk.THETA],
        "psi": states[:, fk.PSI],
        "x_p": states[:, fk.XP] * column.R,
        "y_p": states[:, fk.YP] * column.R,
        "phi_dot": states[:, fk.DPHI] * per_s,
        "theta_dot": states[:, fk.DTHETA] * per_s,
        "psi_dot": (states[:, fk.OMEGA] - states[:, fk.DPHI] * np.cos(states[:, fk.THETA])) * per_s,
        "omega_zeta": diag[:, 0] * per_s,
        "energy_hat": diag[:, 1],
        "normal_force_hat": diag[:, 2],
        "tangential_force_hat": diag[:, 3],
        "mu_mob": diag[:, 4],
    }
    if column.density is not None:
        weight = column.mass * G
        data["normal_force"] = data["normal_force_hat"] * weight
        data["tangential_force"] = data["tangential_force_hat"] * weight
        data["energy"] = data["energy_hat"] * weight * column.R
    ds = xr.Dataset(
        {k: ("time", np.asarray(v, dtype=np.float64)) for k, v in data.items()},
        coords={"time": time, "tau": ("time", tau_out)},
    )
    ds.attrs.update(
        title="Free motion of a conical frustum rolling on its rim",
        column_R_m=column.R,
        column_r_m=column.r,
        column_h_m=column.h,
        theta_crit_rad=column.critical_tilt,
        restitution=restitution,
        outcome=outcome.describe(),
        n_landings=outcome.n_landings,
    )
    annotate(ds)
    append_history(ds, "simulate_free")
    return ds


__all__ = [
    "InitialState",
    "SolverSettings",
    "simulate_free",
    "housner_restitution",
    "LANDED",
    "OVERTURNED",
    "REACHED_END",
]
