"""One column, one motion, one set of settings -> one response.

This module is the friendly layer over :mod:`pipeline.dynamics`: it checks
inputs, converts SI quantities to the kernels' dimensionless variables, runs
the compiled hybrid simulation (:mod:`pipeline.dynamics.hybrid`) and returns
a :class:`Response`: a summary (peaks, overturning, energy budget, ...) and,
on request, an ``xarray.Dataset`` of time histories named as in
:mod:`pipeline.dataset`.

Three models share this interface (``ModelSettings.model``); the third,
``"3d-compliant"`` (rigid drums on joints of contact points, monolith or
multi-drum, :mod:`pipeline.compliant`), is dispatched to its own module:

* ``"3d"``: the rolling frustum of the paper. The column is axisymmetric, so
  its response to a record turned by the incidence angle is its response to
  the record as recorded, turned by that angle. The kernel is run on the
  record in its own frame and the horizontal outputs are turned afterwards:
  the angle changes no number but the directions, exactly, and a
  one-directional record stays planar by construction.
* ``"2d"``: classical planar rocking (Housner) of the same column in the
  vertical plane of the X axis, driven by the X component of the turned
  record.
"""

import math
from dataclasses import dataclass, field, replace

import numpy as np
import xarray as xr

from pipeline.dataset import annotate, append_history
from pipeline.dynamics import frustum as fk
from pipeline.dynamics import hybrid as hy
from pipeline.dynamics import rocking as rk
from pipeline.errors import InputError
from pipeline.geometry import Column
from pipeline.units import G, time_scale

MODELS = ("3d", "2d", "3d-compliant")
COMPLIANT_MODELS = ("3d-compliant",)  # pipeline.compliant: rigid drums on compliant joints

# Geometry the model is meant for: free-standing columns and drums, from
# squat drums to slender monoliths, from pebbles to the largest monoliths.
RADIUS_RANGE = (1e-3, 50.0)  # [m]
SLENDERNESS_RANGE = (0.05, 200.0)  # h/R [1]
BETA_RANGE = (0.05, 20.0)  # r/R [1]

# Landings logged individually (time, theta' before/after, energy jump).
MAX_LOGGED_IMPACTS = 10_000


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
class ModelSettings:
    """The model and its options.

    Parameters
    ----------
    model : {"3d", "2d"}
        Rolling frustum (the paper) or planar rocking (Housner).
    restitution : float, optional
        theta' after / before a landing [1]. Default (None): the impact
        conserves angular momentum about the new pivot (for planar rocking
        ``1 - 2 m R^2 / I_P``).
    contact_tilt : float
        theta_c [rad]: below this inclination the base is in full contact;
        rolling starts there after uplift and a landing happens there
        (docs/model.md). 0 is allowed for planar motion only.
    damping : float
        Viscous contact couple nu, per m g R sqrt(R/g) [1]; 0 is the paper's
        model without dissipation other than impacts.
    friction : float
        Friction coefficient [1] against which the mobilized friction is
        compared (``sliding_onset``).
    tail : float
        Free motion after the record ends [s].
    rtol, atol : float
        Integration tolerances (dimensionless state).
    output_step : float
        Sampling interval of the time histories [s].
    normal_stiffness, joint_stiffness, stiffness_ratio, contact_damping, contact_rings, \
contact_sectors, joint_friction, anathyrosis, base_anathyrosis, monitor_step
        Options of the compliant-contact model ``"3d-compliant"`` (there
        ``friction`` is the base's friction coefficient and ``restitution`` the
        target of the damping calibration); see :mod:`pipeline.compliant`.
    """

    model: str = "3d"
    restitution: float | None = None
    contact_tilt: float = 1e-5
    damping: float = 0.0
    friction: float = 0.7
    tail: float = 5.0
    rtol: float = 1e-9
    atol: float = 1e-12
    output_step: float = 0.01
    normal_stiffness: float = 1.0e10
    joint_stiffness: float | None = None
    stiffness_ratio: float = 0.5
    contact_damping: float | None = None
    contact_rings: int = 3
    contact_sectors: int = 24
    joint_friction: float | tuple | None = None
    anathyrosis: float | tuple = 0.0
    base_anathyrosis: float = 0.0
    monitor_step: float = 0.001

    def __post_init__(self):
        if self.model not in MODELS:
            raise InputError(f"model = {self.model!r} is unknown; choose one of {', '.join(MODELS)}")
        checks = {
            "contact_tilt": (0.0, 0.01, "rad"),
            "damping": (0.0, 100.0, "(per m g R sqrt(R/g))"),
            "friction": (0.0, 10.0, ""),
            "tail": (0.0, 3600.0, "s"),
        }
        for name, (lo, hi, unit) in checks.items():
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and lo <= value <= hi):
                raise InputError(f"{name} = {value!r} {unit} must be a number in [{lo:g}, {hi:g}]")
        for name in ("rtol", "atol", "output_step"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise InputError(f"{name} = {value!r} must be a positive number")
        if self.restitution is not None and not (0.0 <= self.restitution <= 1.0):
            raise InputError(f"restitution = {self.restitution!r} must be between 0 and 1 (or omitted)")
        from pipeline.compliant import check_settings

        check_settings(self)


@dataclass(frozen=True)
class Excitation:
    """How a record drives the column.

    Parameters
    ----------
    angle : float
        Incidence angle [rad]: the horizontal pair is turned counter-clockwise
        by it (:meth:`pipeline.groundmotion.GroundMotion.rotated`).
    scale : float
        Factor on every component [1], > 0.
    vertical : bool
        Use the record's vertical component if it has one.
    """

    angle: float = 0.0
    scale: float = 1.0
    vertical: bool = True

    def __post_init__(self):
        if not (isinstance(self.scale, (int, float)) and math.isfinite(self.scale) and self.scale > 0):
            raise InputError(f"scale = {self.scale!r} must be a positive number")
        if not math.isfinite(self.angle):
            raise InputError(f"angle = {self.angle!r} must be a finite number of radians")


@dataclass
class Response:
    """What one simulation returns.

    Attributes
    ----------
    summary : dict
        Scalar results (names of docs/variables.md), SI units.
    histories : xarray.Dataset or None
        Time histories, if asked for.
    """

    summary: dict
    histories: xr.Dataset | None = field(default=None, repr=False)
    impacts: np.ndarray | None = field(default=None, repr=False)


def housner_restitution(column):
    """Coefficient of restitution of planar rocking from angular momentum conservation.

    Conserving the angular momentum about the new contact point, opposite
    the old one across the base, gives ``theta'_after / theta'_before =
    1 - 2 m R^2 / I_P = 1 - 2 / I_y_hat`` (docs/model.md). For a slender
    column this tends to Housner's ``1 - 1.5 sin^2(alpha)`` of the block with
    the same outline. Clipped at 0 for squat columns (I_y_hat < 2).
    """
    return max(0.0, 1.0 - 2.0 / column.inertia_transverse_hat)


def lying_tilt(column):
    """Inclination at which the side of the frustum touches the ground [rad].

    The generator of the side through the pivot makes the angle
    atan((R - r)/h) with the axis; it reaches the ground at
    ``theta = pi/2 - atan((R - r)/h)``. Reaching it is the overturning event.
    """
    return 0.5 * math.pi - math.atan((column.R - column.r) / column.h)


def check_column(column):
    """Reject geometry outside the range the model is meant for, naming the value."""
    lo, hi = RADIUS_RANGE
    if not lo <= column.R <= hi:
        raise InputError(f"column R = {column.R:g} m is out of range [{lo:g}, {hi:g}] m")
    lo, hi = SLENDERNESS_RANGE
    if not lo <= column.slenderness <= hi:
        raise InputError(f"column slenderness h/R = {column.slenderness:g} is out of range [{lo:g}, {hi:g}]")
    lo, hi = BETA_RANGE
    if not lo <= column.beta <= hi:
        raise InputError(f"column conicity r/R = {column.beta:g} is out of range [{lo:g}, {hi:g}]")


def _options(column, settings):
    return np.array([settings.contact_tilt, lying_tilt(column), settings.damping], dtype=np.float64)


def simulate(column, motion, excitation=Excitation(), settings=ModelSettings(), histories=True):
    """Response of a column at rest to a ground motion.

    Parameters
    ----------
    column : pipeline.geometry.Column or pipeline.drums.DrumColumn
        A multi-drum column needs the model ``"3d-compliant"``.
    motion : pipeline.groundmotion.GroundMotion
    excitation : Excitation
        Incidence angle, scale and whether to use the vertical component.
    settings : ModelSettings
    histories : bool
        Also return the time histories (a Dataset); False is faster for studies.

    Returns
    -------
    Response
    """
    if settings.model in COMPLIANT_MODELS or not isinstance(column, Column):
        from pipeline.compliant import simulate_compliant

        return simulate_compliant(column, motion, excitation, settings, histories)
    check_column(column)
    if not isinstance(excitation, Excitation):
        raise InputError(f"excitation must be an Excitation, got {type(excitation).__name__}")
    t_scale = time_scale(column.R)
    ax = np.asarray(motion.acc_x, dtype=np.float64) * excitation.scale
    ay = np.asarray(motion.acc_y, dtype=np.float64) * excitation.scale
    az = motion.acc_z
    az = np.zeros_like(ax) if (az is None or not excitation.vertical) else np.asarray(az) * excitation.scale
    gamma = excitation.angle
    if settings.model == "3d":
        record = np.stack([ax, ay, az], axis=1) / G  # turned after, by axisymmetry
    else:
        a_u = ax * math.cos(gamma) - ay * math.sin(gamma)  # X component of the turned pair
        record = np.stack([a_u, np.zeros_like(a_u), az], axis=1) / G
    record = np.ascontiguousarray(record)
    dt = motion.dt / t_scale
    duration = motion.duration + settings.tail
    y0 = np.zeros(fk.N_STATE if settings.model == "3d" else rk.N_STATE2)
    raw = _run(column, settings, record, dt, y0, duration)
    diag = _diagnostics(raw, settings)
    summary = _summary(column, settings, raw, diag, motion, excitation)
    ds = _histories(column, settings, raw, diag, excitation, motion) if histories else None
    return Response(summary, ds, _impact_table(raw, column))


def simulate_free(column, initial, duration, settings=ModelSettings(rtol=1e-12, atol=1e-14, contact_tilt=0.0),
                  restitution=None):
    """Free motion (no ground motion) of the 3D column released on its rim.

    Parameters
    ----------
    column : pipeline.geometry.Column
    initial : InitialState
    duration : float
        Length of the simulation [s].
    settings : ModelSettings
        ``contact_tilt`` 0 by default: free motion lands at theta = 0, which
        only planar motion reaches.
    restitution : float, optional
        Overrides ``settings.restitution``.

    Returns
    -------
    xarray.Dataset
        Time histories named as in the project's architecture.
    """
    if not (math.isfinite(duration) and duration > 0):
        raise InputError(f"duration = {duration!r} s must be a positive number of seconds")
    if restitution is not None:
        settings = replace(settings, restitution=float(restitution))
    settings = replace(settings, model="3d")
    rate = time_scale(column.R)  # (rad/s) * rate = rad per tau
    y0 = np.zeros(fk.N_STATE)
    y0[fk.PHI], y0[fk.THETA], y0[fk.PSI] = initial.phi, initial.theta, initial.psi
    y0[fk.DPHI] = initial.phi_dot * rate
    y0[fk.DTHETA] = initial.theta_dot * rate
    y0[fk.OMEGA] = (initial.phi_dot * math.cos(initial.theta) + initial.psi_dot) * rate
    raw = _run(column, settings, np.zeros((0, 3)), 1.0, y0, duration)
    ds = _histories(column, settings, raw, _diagnostics(raw, settings), Excitation(), None)
    ds.attrs["title"] = "Free motion of a conical frustum rolling on its rim"
    return ds


@dataclass
class _Raw:
    """Dimensionless arrays from one kernel run."""

    tau: np.ndarray
    states: np.ndarray
    phase: np.ndarray
    summary: np.ndarray
    impacts: np.ndarray
    params: tuple
    n_filled: int
    t_scale: float
    y0: np.ndarray


def _run(column, settings, record, dt, y0, duration):
    t_scale = time_scale(column.R)
    c = column.kernel_constants()
    params = (c, record, dt, _options(column, settings))
    tau_end = duration / t_scale
    n_out = int(math.floor(duration / settings.output_step + 1e-9)) + 1
    tau = np.arange(n_out) * (settings.output_step / t_scale)
    states = np.full((n_out, y0.shape[0]), np.nan)
    phase = np.zeros(n_out, dtype=np.int8)
    breaks = np.arange(record.shape[0]) * dt  # kinks of the linearly interpolated record
    summary = np.zeros(hy.N_SUMMARY)
    restitution = -1.0 if settings.restitution is None else float(settings.restitution)
    runner = hy.run_frustum if settings.model == "3d" else hy.run_rocking
    impacts = np.empty((MAX_LOGGED_IMPACTS, 4))  # the kernel fills every logged row; only those are read
    n = runner(params, restitution, y0, tau_end, tau, states, phase, breaks, settings.rtol, settings.atol,
               summary, impacts)
    if summary[hy.S_STATUS] < 0:
        raise RuntimeError(
            f"integration failed at t = {summary[hy.S_END_TIME] * t_scale:.6g} s "
            f"(status {summary[hy.S_STATUS]:.0f}); try other tolerances or a larger contact_tilt"
        )
    n_logged = min(int(summary[hy.S_N_IMPACTS]), MAX_LOGGED_IMPACTS)
    return _Raw(tau, states, phase, summary, impacts[:n_logged], params, n, t_scale, y0)


def _impact_table(raw, column):
    """Landings in SI: time [s], theta' before and after [rad/s], energy jump per weight [m]."""
    table = raw.impacts.copy()
    table[:, 0] *= raw.t_scale
    table[:, 1:3] /= raw.t_scale
    table[:, 3] *= column.R
    return table


def _diagnostics(raw, settings):
    """Per-row omega_zeta, energy, normal force, |F_t|, mu_mob, ground acceleration (dimensionless)."""
    out = np.full((raw.tau.shape[0], fk.N_DIAGNOSTICS), np.nan)
    hy.diagnostics_rows(raw.tau, raw.states, raw.phase, raw.params, settings.model == "3d", out)
    return out


def _summary(column, settings, raw, diag, motion, excitation):
    s = raw.summary
    ts = raw.t_scale
    # Peaks, sliding and lift-off are taken before the final fall: once the
    # column passes theta_crit for the last time it is going over (and the
    # rows after it lies down hold a frozen state under a moving ground).
    moving = raw.phase != hy.PHASE_OVERTURNED
    if not math.isnan(s[hy.S_OVERTURN_TIME]):
        tilt = np.abs(raw.states[:, fk.THETA if settings.model == "3d" else rk.THETA2])
        upright = np.flatnonzero(moving & ~(tilt > column.critical_tilt))
        moving = np.arange(len(moving)) <= (upright[-1] if len(upright) else -1)
    rolling = moving & (raw.phase == hy.PHASE_ROLLING)
    peak_mu = max(float(np.nanmax(diag[moving, 4])) if moving.any() else 0.0, s[hy.S_PEAK_MU])
    min_normal = np.fmin(np.nanmin(diag[rolling, 2]) if rolling.any() else np.inf, s[hy.S_MIN_NORMAL])
    weight_energy = column.R  # energies per m g: multiply dimensionless by R -> per (m g) [m]
    last = raw.states[raw.n_filled - 1]
    c = raw.params[0]
    if settings.model == "3d":
        work, dissipated = last[fk.WORK], last[fk.DISSIPATED]
        e_end = c[fk.C_ZC] if raw.phase[raw.n_filled - 1] == hy.PHASE_REST else fk.energy(
            last[fk.THETA], last[fk.DPHI], last[fk.DTHETA], last[fk.OMEGA], c)
        e_start = fk.energy(raw.y0[fk.THETA], raw.y0[fk.DPHI], raw.y0[fk.DTHETA], raw.y0[fk.OMEGA], c) \
            if raw.y0[fk.THETA] > 0 else c[fk.C_ZC]
        residual_rotation = s[hy.S_ROTATION]
        residual_displacement = math.hypot(s[hy.S_BASE_X], s[hy.S_BASE_Y]) * column.R
    else:
        work, dissipated = last[rk.WORK2], last[rk.DISSIPATED2]
        e_end = c[fk.C_ZC] if raw.phase[raw.n_filled - 1] == hy.PHASE_REST else rk.energy(
            last[rk.THETA2], last[rk.DTHETA2], c)
        e_start = c[fk.C_ZC]
        residual_rotation = 0.0
        residual_displacement = 0.0
    overturned = not math.isnan(s[hy.S_OVERTURN_TIME])
    balance = (e_end - e_start) - (work + s[hy.S_TRANSITION] - dissipated)
    out = {
        "model": settings.model,
        "peak_theta": float(s[hy.S_PEAK_THETA]),
        "peak_theta_ratio": float(s[hy.S_PEAK_THETA] / column.critical_tilt),
        "peak_time": float(s[hy.S_PEAK_TIME] * ts),
        "overturned": overturned,
        "overturn_time": float(s[hy.S_OVERTURN_TIME] * ts),
        "uplifted": not math.isnan(s[hy.S_UPLIFT_TIME]),
        "uplift_time": float(s[hy.S_UPLIFT_TIME] * ts),
        "n_impacts": int(s[hy.S_N_IMPACTS]),
        "peak_mu_mob": float(peak_mu),
        "sliding_onset": bool(peak_mu > settings.friction),
        "lift_off": bool(min_normal < 0.0),
        "residual_rotation": float(residual_rotation),
        "residual_displacement": float(residual_displacement),
        # energy budget per unit weight [m]: E / (m g)
        "energy_initial": float(e_start * weight_energy),
        "work_ground": float(work * weight_energy),
        "energy_transitions": float(s[hy.S_TRANSITION] * weight_energy),
        "energy_dissipated": float(dissipated * weight_energy),
        "energy_final": float(e_end * weight_energy),
        "energy_balance_error": float(balance * weight_energy),
        "rhs_evaluations": int(s[hy.S_NFEV]),
        "steps": int(s[hy.S_STEPS]),
    }
    if motion is not None:
        out.update(record_id=motion.record_id, angle=float(excitation.angle), scale=float(excitation.scale))
    return out


def _histories(column, settings, raw, diag, excitation, motion):
    ts = raw.t_scale
    R = column.R
    per_s = 1.0 / ts
    st = raw.states
    rest = raw.phase == hy.PHASE_REST
    if settings.model == "3d":
        phi = st[:, fk.PHI] + excitation.angle
        theta = np.where(rest, 0.0, st[:, fk.THETA])
        cg, sg = math.cos(excitation.angle), math.sin(excitation.angle)
        # the kernel stores the base centre in the contact-point slots at rest
        px, py = st[:, fk.XP] * R, st[:, fk.YP] * R
        bx = np.where(rest, px, px - np.sin(st[:, fk.PHI]) * np.cos(theta) * R)
        by = np.where(rest, py, py + np.cos(st[:, fk.PHI]) * np.cos(theta) * R)
        x_p = np.where(rest, np.nan, cg * px - sg * py)
        y_p = np.where(rest, np.nan, sg * px + cg * py)
        data = {
            "phi": np.where(rest, np.nan, phi),
            "theta": theta,
            "psi": np.where(rest, np.nan, st[:, fk.PSI]),
            "x_p": x_p,
            "y_p": y_p,
            "x_b": cg * bx - sg * by,
            "y_b": sg * bx + cg * by,
            "phi_dot": np.where(rest, 0.0, st[:, fk.DPHI]) * per_s,
            "theta_dot": np.where(rest, 0.0, st[:, fk.DTHETA]) * per_s,
            "psi_dot": np.where(rest, 0.0, st[:, fk.OMEGA] - st[:, fk.DPHI] * np.cos(st[:, fk.THETA])) * per_s,
            "work_ground_hat": st[:, fk.WORK],
        }
        gx, gy = diag[:, 5], diag[:, 6]
        ground_x, ground_y = cg * gx - sg * gy, sg * gx + cg * gy
    else:
        signed = st[:, rk.THETA2]
        theta = np.abs(signed)
        data = {
            "phi": np.where(rest, np.nan, np.where(signed >= 0, 0.5 * math.pi, -0.5 * math.pi)),
            "theta": theta,
            "x_p": np.where(rest, np.nan, np.sign(signed) * R),
            "y_p": np.where(rest, np.nan, 0.0),
            "theta_dot": np.where(rest, 0.0, np.sign(signed) * st[:, rk.DTHETA2]) * per_s,
            "work_ground_hat": st[:, rk.WORK2],
        }
        ground_x, ground_y = diag[:, 5], np.zeros_like(diag[:, 5])
    data.update({
        "omega_zeta": diag[:, 0] * per_s,
        "energy_hat": diag[:, 1],
        "normal_force_hat": diag[:, 2],
        "tangential_force_hat": diag[:, 3],
        "mu_mob": diag[:, 4],
        "ground_acc_x": ground_x * G,
        "ground_acc_y": ground_y * G,
        "ground_acc_z": diag[:, 7] * G,
    })
    if column.density is not None:
        weight = column.mass * G
        data["normal_force"] = data["normal_force_hat"] * weight
        data["tangential_force"] = data["tangential_force_hat"] * weight
        data["energy"] = data["energy_hat"] * weight * R
    time = raw.tau * ts
    variables = {k: ("time", np.asarray(v, dtype=np.float64)) for k, v in data.items()}
    variables["phase"] = ("time", raw.phase.astype(np.int8))
    ds = xr.Dataset(variables, coords={"time": time, "tau": ("time", raw.tau)})
    ds.attrs.update(
        title="Response of a free-standing column (conical frustum) to ground motion",
        model=settings.model,
        column_R_m=column.R,
        column_r_m=column.r,
        column_h_m=column.h,
        theta_crit_rad=column.critical_tilt,
        contact_tilt_rad=settings.contact_tilt,
        restitution="angular momentum" if settings.restitution is None else settings.restitution,
        damping=settings.damping,
        rtol=settings.rtol,
        atol=settings.atol,
    )
    if motion is not None:
        ds.attrs.update(record_id=motion.record_id, record_sha256=motion.sha256(),
                        incidence_angle_rad=excitation.angle, scale=excitation.scale)
    annotate(ds)
    append_history(ds, f"pipeline.simulate ({settings.model})")
    return ds


__all__ = [
    "InitialState",
    "ModelSettings",
    "Excitation",
    "Response",
    "simulate",
    "simulate_free",
    "housner_restitution",
    "lying_tilt",
    "check_column",
]
