"""One column, one motion, one set of settings -> one response.

:func:`simulate` is the facade: it asks the model registry (:mod:`pipeline.models`) for the
model of ``settings.model`` and runs it; every model returns a
:class:`pipeline.response.Response`: a summary (peaks, overturning, energy budget, ...) and, on
request, an ``xarray.Dataset`` of time histories named as in :mod:`pipeline.dataset`.

The rest of the module runs the rigid models of a monolith (:func:`simulate_rigid`): it
converts SI quantities to the kernels' dimensionless variables and runs the compiled
event-driven kernels of :mod:`pipeline.dynamics.rigid`:

* the rolling frustum of the paper (not ``planar``). The column is axisymmetric, so
  its response to a record turned by the incidence angle is its response to
  the record as recorded, turned by that angle. The kernel is run on the
  record in its own frame and the horizontal outputs are turned afterwards:
  the angle changes no number but the directions, exactly, and a
  one-directional record stays planar by construction.
* classical planar rocking (Housner) of the same column (``planar``) in the
  vertical plane of the X axis, driven by the X component of the turned
  record.

The compliant model (drums on joints of contact points) runs in :mod:`pipeline.compliant`.
"""

import math
from dataclasses import dataclass, replace

import numpy as np
import xarray as xr

from pipeline import models
from pipeline.dataset import annotate, append_history
from pipeline.dynamics.rigid import frustum as fk
from pipeline.dynamics.rigid import diagnostics as rd
from pipeline.dynamics.rigid import layout as hy  # the rigid runs' layouts: S_*, PHASE_*
from pipeline.dynamics.rigid import rocking as rk
from pipeline.dynamics.rigid.run2d import run_rocking
from pipeline.dynamics.rigid.run3d import run_frustum
from pipeline.errors import InputError
from pipeline.structures.description import history_attributes, whole_label
from pipeline.structures.kinds import RUNS, describe_kind, kind_of
from pipeline.models.rigid import ROLLING_FRUSTUM
from pipeline.response import Response
from pipeline.settings import FREE_MOTION, Excitation, ModelSettings, check_column
from pipeline.units import MARBLE_DENSITY, G, deg_to_rad, time_scale

# The contact tilt of a rigid base (no compliance to set it): small enough to
# change nothing measurable (studies/contact_tilt), large enough for the
# integrator to resolve the landing.
RIGID_CONTACT_TILT = 1e-7  # [rad]

# Landings logged individually (time, theta' before/after, energy jump).
MAX_LOGGED_IMPACTS = 10_000


def lying_tilt(column):
    """Inclination at which the side of the frustum touches the ground [rad].

    The generator of the side through the pivot runs from the base rim
    inwards by R - r over the height h, so it makes the angle
    atan((R - r)/h) with the axis, leaning towards the axis. It lies on the
    ground when the axis has turned past the horizontal by that angle:
    ``theta_lie = pi/2 + atan((R - r)/h)`` (91.43 deg for R = 0.5, r = 0.4,
    h = 4 m; below 90 deg for a column wider at the top). Reaching it is the
    overturning event.
    """
    return 0.5 * math.pi + math.atan((column.R - column.r) / column.h)


def _options(column, settings):
    theta_k, patch_damping = patch_parameters(column, settings)
    return kernel_options(settings, lying_tilt(column), settings.damping, theta_k, patch_damping,
                          contact_tilt(column, settings))


def kernel_options(settings, theta_lie, nu, theta_k, patch_damping, theta_c):
    """The rigid kernels' options array (``fk.OPT_*``) of a body, in the kernel's dimensionless units.

    Parameters
    ----------
    settings : ModelSettings
        Its friction, lift-off and the model's numerical thresholds are read here.
    theta_lie : float
        Tilt at which the body lies down (the overturning event) [rad].
    nu : float
        Viscous couple, per m g L sqrt(L/g) of the kernel's mass m and length L [1].
    theta_k, patch_damping : float
        The contact patch (:func:`patch_parameters`): the tilt of lost full contact [rad] and the
        dashpots per unit area in the kernel's units [1]; 0, 0 for a point contact.
    theta_c : float
        The contact tilt [rad] (:func:`contact_tilt`).
    """
    opts = np.zeros(fk.N_OPT)
    opts[fk.OPT_THETA_LIE] = theta_lie
    opts[fk.OPT_NU] = nu
    opts[fk.OPT_MU] = settings.friction
    opts[fk.OPT_UNILATERAL] = 1.0 if settings.lift_off else 0.0
    opts[fk.OPT_THETA_K], opts[fk.OPT_PATCH_DAMPING] = theta_k, patch_damping
    opts[fk.OPT_THETA_C] = theta_c
    numerics = {**models.get(settings.model).numerics, **dict(settings.numerics)}
    opts[fk.OPT_LANDING_MARGIN] = numerics["landing_margin"]
    opts[fk.OPT_MIN_REBOUND] = numerics["min_rebound"]
    opts[fk.OPT_SLAVE_TIME] = numerics["slave_time"]
    opts[fk.OPT_LOOK_AHEAD] = numerics["look_ahead"]
    opts[fk.OPT_SLAVED_TURN] = numerics["slaved_turn"]
    opts[fk.OPT_MAX_STEP] = np.inf  # set per call by the 3D kernel
    return opts


def contact_tilt(column, settings):
    """Tilt theta_c [rad] below which the base is in full contact (landing, uplift).

    ``settings.contact_tilt`` [deg] if given; otherwise theta_k, the tilt at which
    the compliant bed under the column's weight loses full contact
    (:func:`patch_parameters`), or for a rigid base (``normal_stiffness`` inf,
    the paper's point contact) a numerical 1e-7 rad.
    """
    if settings.contact_tilt is not None:
        return deg_to_rad(settings.contact_tilt)
    theta_k = patch_parameters(column, settings)[0]
    return theta_k if theta_k > 0.0 else RIGID_CONTACT_TILT


def patch_parameters(column, settings):
    """Contact patch of the rigid models: (theta_k [rad], dashpots c_n R^3 / (m sqrt(g R)) [1]).

    theta_k = m g / (k_n A R) is the tilt at which the base under the
    column's weight just loses full contact (:mod:`pipeline.dynamics.rigid.patch`);
    0 for a rigid base (``normal_stiffness`` inf), the paper's point contact.
    """
    kn = settings.normal_stiffness
    if kn == math.inf:
        return 0.0, 0.0
    mass = _mass(column)
    area = math.pi * column.R**2
    theta_k = mass * G / (kn * area * column.R)
    return theta_k, patch_dashpots(column, settings) * column.R**3 / (mass * math.sqrt(G * column.R))


def _mass(column):
    """The column's mass [kg] (marble if it has no density)."""
    return (column.density if column.density is not None else MARBLE_DENSITY) * column.volume


def patch_dashpots(column, settings):
    """Normal dashpots of the rigid models' contact patch per unit area, c_n [Pa s/m]: ``contact_damping``,
    or critical damping of the column bouncing on its base, 2 sqrt(k_n m / A); 0 for the point contact."""
    kn = settings.normal_stiffness
    if kn == math.inf:
        return 0.0
    if settings.contact_damping is not None:
        return settings.contact_damping
    return 2.0 * math.sqrt(kn * _mass(column) / (math.pi * column.R**2))


def simulate(column, motion, excitation=Excitation(), settings=ModelSettings(), histories=True, progress=None):
    """Response of a column at rest to a ground motion.

    Parameters
    ----------
    column : pipeline.structures.column.Column, pipeline.structures.drums.DrumColumn or \
pipeline.structures.colonnade.Colonnade
        A structure of a kind the model runs (``Model.bodies`` of the registry): a multi-drum
        column needs a model that runs drums, a colonnade one that runs colonnades.
    motion : pipeline.groundmotion.GroundMotion
    excitation : Excitation
        Incidence angle, scale and whether to use the vertical component.
    settings : ModelSettings
    histories : bool
        Also return the time histories (a Dataset); False is faster for studies.
    progress : callable, optional
        ``progress(done, total)`` [s of motion], called about every simulated second by the
        compliant model's fixed-step integrator (a progress line for long drum stacks).

    Returns
    -------
    Response
    """
    model = models.get(settings.model)
    kind = kind_of(column)  # refuses what is no structure
    if not model.runs(kind):
        runners = ", ".join(name for name, m in models.REGISTRY.items() if m.runs(kind))
        raise InputError(f"model = {settings.model!r} runs {' or '.join(RUNS[b] for b in model.bodies)}: "
                         f"{describe_kind(column)} needs one of {runners}")
    return model.run(column, motion, excitation, settings, histories, progress)


def simulate_rigid(column, motion, excitation, settings, histories=True, progress=None):
    """The run of the registry's rigid models of a monolith (:mod:`pipeline.models.rigid`).

    Same arguments and result as :func:`simulate`; ``progress`` is not called (a rigid run
    takes a fraction of a second to seconds).
    """
    planar = models.get(settings.model).planar
    check_column(column)
    if not isinstance(excitation, Excitation):
        raise InputError(f"excitation must be an Excitation, got {type(excitation).__name__}")
    t_scale = time_scale(column.R)
    record = kernel_record(motion, excitation, planar)
    dt = motion.dt / t_scale
    duration = motion.duration + settings.tail
    y0 = np.zeros(rk.N_STATE2 if planar else fk.N_STATE)
    raw = _run(column, settings, record, dt, y0, duration, settings.settle_limit)
    diag = kernel_diagnostics(raw, settings)
    summary = _summary(column, settings, raw, diag, motion, excitation)
    summary["overturn_body"] = whole_label(column) if summary["overturned"] else ""  # one body
    ds = _histories(column, settings, raw, diag, excitation, motion) if histories else None
    return Response(summary, ds, _impact_table(raw, column))


def kernel_record(motion, excitation, planar):
    """The record as the rigid kernels take it: (n, 3) samples in g, contiguous.

    3D (not ``planar``): the record as recorded (the outputs are turned afterwards, by
    axisymmetry); planar: the X component of the pair turned by the incidence angle,
    ``a_X cos(gamma) - a_Y sin(gamma)``, in column 0, column 1 zero. The vertical component is
    column 2 (zero without one, or when ``excitation.vertical`` is off).
    """
    if not isinstance(excitation, Excitation):
        raise InputError(f"excitation must be an Excitation, got {type(excitation).__name__}")
    ax = np.asarray(motion.acc_x, dtype=np.float64) * excitation.scale
    ay = np.asarray(motion.acc_y, dtype=np.float64) * excitation.scale
    az = motion.acc_z
    az = np.zeros_like(ax) if (az is None or not excitation.vertical) else np.asarray(az) * excitation.scale
    gamma = excitation.angle_rad
    if not planar:
        record = np.stack([ax, ay, az], axis=1) / G  # turned after, by axisymmetry
    else:
        a_u = ax * math.cos(gamma) - ay * math.sin(gamma)  # X component of the turned pair
        record = np.stack([a_u, np.zeros_like(a_u), az], axis=1) / G
    return np.ascontiguousarray(record)


def simulate_free(column, initial, duration, settings=FREE_MOTION,
                  restitution=None, friction=math.inf, lift_off=False, normal_stiffness=math.inf):
    """Free motion (no ground motion) of the 3D column released on its rim.

    Parameters
    ----------
    column : pipeline.structures.column.Column
    initial : InitialState
    duration : float
        Length of the simulation [s].
    settings : ModelSettings
        ``contact_tilt`` 0 by default: free motion lands at theta = 0, which
        only planar motion reaches.
    restitution : float, optional
        Overrides ``settings.restitution``.
    friction, lift_off, normal_stiffness : float, bool, float
        Override ``settings``; the defaults (inf, False, inf) are the paper's
        free motion: rolling without slip on a point, the rim held on the ground.

    Returns
    -------
    xarray.Dataset
        Time histories named as in the project's architecture.
    """
    if not (math.isfinite(duration) and duration > 0):
        raise InputError(f"duration = {duration!r} s must be a positive number of seconds")
    if restitution is not None:
        settings = replace(settings, restitution=float(restitution))
    settings = replace(settings, model=ROLLING_FRUSTUM.name, friction=friction, lift_off=lift_off,
                       normal_stiffness=normal_stiffness)
    rate = time_scale(column.R)  # (rad/s) * rate = rad per tau
    y0 = np.zeros(fk.N_STATE)
    phi, theta, psi = initial.angles_rad
    y0[fk.PHI], y0[fk.THETA], y0[fk.PSI] = phi, theta, psi
    y0[fk.DPHI] = initial.phi_dot * rate
    y0[fk.DTHETA] = initial.theta_dot * rate
    y0[fk.OMEGA] = (initial.phi_dot * math.cos(theta) + initial.psi_dot) * rate
    raw = _run(column, settings, np.zeros((0, 3)), 1.0, y0, duration)
    ds = _histories(column, settings, raw, kernel_diagnostics(raw, settings), Excitation(), None)
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


def _run(column, settings, record, dt, y0, duration, settle_limit=0.0):
    runner = run_rocking if models.get(settings.model).planar else run_frustum
    restitution = -1.0 if settings.restitution is None else float(settings.restitution)
    params = (column.kernel_constants(), record, dt, _options(column, settings))
    return run_kernel(runner, params, time_scale(column.R), restitution, settings, y0, duration, settle_limit)


def output_instants(n_rows, duration, settle_limit, output_step, t_scale):
    """The output rows' instants [tau]: every ``output_step`` [s] in units of ``t_scale`` [s].

    The rows at the record's end (``duration``, the tail included) and the grid's last are where the
    integration may stop: k step / t_scale may round past them, and such a row was left unfilled (at
    rest, no position), so they are clamped there. A model that reports in another time unit than
    its kernel's (the frame) builds its rows with this too, to the bit.
    """
    tau = np.minimum(np.arange(n_rows) * (output_step / t_scale), (duration + settle_limit) / t_scale)
    k_end = int(math.floor(duration / output_step + 1e-9))
    if k_end < n_rows:
        tau[k_end] = min(tau[k_end], duration / t_scale)
    return tau


def run_kernel(runner, params, t_scale, restitution, settings, y0, duration, settle_limit=0.0):
    """One run of a rigid event-driven kernel (``run_rocking`` or ``run_frustum``): the dimensionless arrays.

    Parameters
    ----------
    runner : numba function
    params : tuple
        ``(constants, record [g], dt [tau], options)`` as the kernels take them.
    t_scale : float
        The kernel's time unit sqrt(L/g) [s] of its length L.
    restitution : float
        Planar landings' theta' after / before; negative: the kernel's own, ``1 - 2 / Iy``.
    settings : ModelSettings
        Its output step and tolerances.
    y0 : numpy.ndarray
    duration : float
        The record and its tail [s].
    settle_limit : float
        Up to this much more [s], with the ground still, if the outcome is not decided at
        ``duration`` (docs/model.md, "The end of a run"); the output rows end where the run
        does (not before ``duration``).
    """
    record, dt = params[1], params[2]
    tau_end = duration / t_scale
    tau_settle = (duration + settle_limit) / t_scale
    n_out = int(math.floor((duration + settle_limit) / settings.output_step + 1e-9)) + 1
    tau = output_instants(n_out, duration, settle_limit, settings.output_step, t_scale)
    states = np.full((n_out, y0.shape[0]), np.nan)
    phase = np.zeros(n_out, dtype=np.int8)
    breaks = np.arange(record.shape[0]) * dt  # kinks of the linearly interpolated record
    summary = np.zeros(hy.N_SUMMARY)
    impacts = np.empty((MAX_LOGGED_IMPACTS, 4))  # the kernel fills every logged row; only those are read
    n = runner(params, restitution, y0, tau_end, tau_settle, tau, states, phase, breaks, settings.rtol,
               settings.atol, summary, impacts)
    if summary[hy.S_STATUS] < 0:
        raise RuntimeError(
            f"integration failed at t = {summary[hy.S_END_TIME] * t_scale:.6g} s "
            f"(status {summary[hy.S_STATUS]:.0f}); try other tolerances or a larger contact_tilt"
        )
    n_logged = min(int(summary[hy.S_N_IMPACTS]), MAX_LOGGED_IMPACTS)
    # the rows up to the run's end (a column lying down fills them all), at least the record and its tail
    keep = np.searchsorted(tau, max(tau_end, summary[hy.S_END_TIME]) * (1.0 + 1e-12), side="right")
    return _Raw(tau[:keep], states[:keep], phase[:keep], summary, impacts[:n_logged], params, min(n, keep),
                t_scale, y0)


def _impact_table(raw, column):
    """Landings in SI: time [s], theta' before and after [rad/s], energy jump per weight [m]."""
    table = raw.impacts.copy()
    table[:, 0] *= raw.t_scale
    table[:, 1:3] /= raw.t_scale
    table[:, 3] *= column.R
    return table


def kernel_diagnostics(raw, settings):
    """Per-row derived quantities of a rigid kernel's run (``rd.D_*`` columns, in its dimensionless units)."""
    out = np.full((raw.tau.shape[0], rd.N_DIAGNOSTICS), np.nan)
    rd.diagnostics_rows(raw.tau, raw.states, raw.phase, raw.params, not models.get(settings.model).planar, out)
    return out


def _summary(column, settings, raw, diag, motion, excitation):
    """Scalar results, all read from the kernel's own summary (none from the output grid)."""
    return kernel_summary(raw, column.R, column.critical_tilt, settings, motion, excitation)


def kernel_summary(raw, length, theta_crit, settings, motion, excitation):
    """Scalar results of a rigid kernel's run, all read from its own summary (none from the output grid).

    ``length`` [m] is the kernel's unit of length (energies per weight and the base's position
    are in it), ``theta_crit`` [rad] the critical tilt ``peak_theta_ratio`` divides by.
    """
    s = raw.summary
    ts = raw.t_scale
    R = length  # energies per m g: dimensionless times R [m]
    e_start, e_end = s[hy.S_ENERGY_START], s[hy.S_ENERGY_END]
    work, dissipated, friction = s[hy.S_WORK], s[hy.S_DISSIPATED], s[hy.S_FRICTION]
    balance = (e_end - e_start) - (work + s[hy.S_TRANSITION] - dissipated - friction)
    residual_rotation = 0.0 if models.get(settings.model).planar else s[hy.S_ROTATION]
    out = {
        "model": settings.model,
        "peak_theta": float(s[hy.S_PEAK_THETA]),
        "peak_theta_ratio": float(s[hy.S_PEAK_THETA] / theta_crit),
        "peak_time": float(s[hy.S_PEAK_TIME] * ts),
        "overturned": not math.isnan(s[hy.S_OVERTURN_TIME]),
        "undecided": bool(s[hy.S_UNDECIDED]),
        "overturn_time": float(s[hy.S_OVERTURN_TIME] * ts),
        "uplifted": not math.isnan(s[hy.S_UPLIFT_TIME]),
        "uplift_time": float(s[hy.S_UPLIFT_TIME] * ts),
        "n_impacts": int(s[hy.S_N_IMPACTS]),
        "peak_mu_mob": float(s[hy.S_PEAK_MU]),
        "min_normal_force_hat": float(s[hy.S_MIN_NORMAL]),
        "sliding_onset": not math.isnan(s[hy.S_SLIDE_TIME]),
        "sliding_time": float(s[hy.S_SLIDE_TIME] * ts),
        "lift_off": not math.isnan(s[hy.S_FLIGHT_TIME]),
        "lift_off_time": float(s[hy.S_FLIGHT_TIME] * ts),
        "residual_rotation": float(residual_rotation),
        "residual_displacement": float(math.hypot(s[hy.S_BASE_X], s[hy.S_BASE_Y]) * R),
        # energy budget per unit weight [m]: E / (m g)
        "energy_initial": float(e_start * R),
        "work_ground": float(work * R),
        "energy_transitions": float(s[hy.S_TRANSITION] * R),
        "energy_dissipated": float(dissipated * R),
        "energy_friction": float(friction * R),
        "energy_final": float(e_end * R),
        "energy_balance_error": float(balance * R),
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
    phase = raw.phase
    flat = (phase == hy.PHASE_REST) | (phase == hy.PHASE_SLIDING)
    cg, sg = math.cos(excitation.angle_rad), math.sin(excitation.angle_rad)
    bx, by = diag[:, rd.D_BASE_X] * R, diag[:, rd.D_BASE_Y] * R
    px, py = diag[:, rd.D_CONTACT_X] * R, diag[:, rd.D_CONTACT_Y] * R
    if not models.get(settings.model).planar:
        theta = np.where(flat, 0.0, st[:, fk.THETA])
        data = {
            "phi": np.where(flat, np.nan, st[:, fk.PHI] + excitation.angle_rad),
            "theta": theta,
            "psi": np.where(flat, np.nan, st[:, fk.PSI]),
            "phi_dot": np.where(flat, 0.0, st[:, fk.DPHI]) * per_s,
            "theta_dot": np.where(flat, 0.0, st[:, fk.DTHETA]) * per_s,
            "psi_dot": np.where(flat, 0.0, st[:, fk.OMEGA] - st[:, fk.DPHI] * np.cos(st[:, fk.THETA])) * per_s,
        }
        # the kernel runs in the record's frame: turn the horizontal outputs by the angle
        data.update({"x_p": cg * px - sg * py, "y_p": sg * px + cg * py,
                     "x_b": cg * bx - sg * by, "y_b": sg * bx + cg * by})
        gx, gy = diag[:, rd.D_AX], diag[:, rd.D_AY]
        ground_x, ground_y = cg * gx - sg * gy, sg * gx + cg * gy
    else:
        signed = st[:, rk.THETA2]
        data = {
            "phi": np.where(flat, np.nan, np.copysign(0.5 * math.pi, signed)),
            "theta": np.where(flat, 0.0, np.abs(signed)),
            "x_p": px,
            "y_p": np.where(np.isnan(px), np.nan, 0.0),
            "x_b": bx,
            "y_b": by,
            "theta_dot": np.where(flat, 0.0, np.copysign(1.0, signed) * st[:, rk.DTHETA2]) * per_s,
        }
        ground_x, ground_y = diag[:, rd.D_AX], np.zeros_like(diag[:, rd.D_AX])
    data.update({
        "omega_zeta": diag[:, rd.D_OMEGA] * per_s,
        "energy_hat": diag[:, rd.D_ENERGY],
        "normal_force_hat": diag[:, rd.D_NORMAL],
        "tangential_force_hat": diag[:, rd.D_TANGENTIAL],
        "mu_mob": diag[:, rd.D_MU],
        "slip_velocity": diag[:, rd.D_SLIP] * math.sqrt(G * R),
        "ground_acc_x": ground_x * G,
        "ground_acc_y": ground_y * G,
        "ground_acc_z": diag[:, rd.D_AZ] * G,
    })
    if column.density is not None:
        weight = column.mass * G
        data["normal_force"] = data["normal_force_hat"] * weight
        data["tangential_force"] = data["tangential_force_hat"] * weight
        data["energy"] = data["energy_hat"] * weight * R
    time = raw.tau * ts
    variables = {k: ("time", np.asarray(v, dtype=np.float64)) for k, v in data.items()}
    variables["phase"] = ("time", phase.astype(np.int8))
    ds = xr.Dataset(variables, coords={"time": time, "tau": ("time", raw.tau)})
    ds.attrs.update(history_attributes(column, models.get(settings.model)))
    ds.attrs.update(
        model=settings.model,
        column_R_m=column.R,
        column_r_m=column.r,
        column_h_m=column.h,
        theta_crit_rad=column.critical_tilt,
        contact_tilt_rad=contact_tilt(column, settings),
        friction=settings.friction,
        restitution="angular momentum" if settings.restitution is None else settings.restitution,
        damping=settings.damping,
        lift_off="true" if settings.lift_off else "false",
        normal_stiffness_Pa_m=settings.normal_stiffness,
        contact_damping_Pa_s_m=patch_dashpots(column, settings),
        rtol=settings.rtol,
        atol=settings.atol,
    )
    if motion is not None:
        ds.attrs.update(record_id=motion.record_id, record_sha256=motion.sha256(),
                        incidence_angle_rad=excitation.angle_rad, scale=excitation.scale)
    annotate(ds)
    append_history(ds, f"pipeline.simulate ({settings.model})")
    return ds


__all__ = [
    "simulate",
    "simulate_free",
    "lying_tilt",
]
