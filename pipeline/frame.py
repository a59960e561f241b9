"""The rigid planar frame (``2d-frame``): a colonnade rocking in its own plane as one block, run by the 2D kernel.

Makris & Vassiliou (2013): the columns of a row capped by a freely supported rigid beam rock in
unison about their base rims, and the beam, resting on the capitals' top edges opposite the
pivots, translates with them. Potential and kinetic energy are those of one rocking block
(:class:`pipeline.structures.colonnade.FrameBlock`, derived in docs/model.md, "The rigid planar
frame"), which :func:`simulate_frame` runs through the planar kernel
(:func:`pipeline.dynamics.rigid.run2d.run_rocking`) unchanged:

* the kernel's unit of length is the equivalent block's horizontal lever ``b_e`` (its pivots are
  ``+-b_e`` from its base centre), its unit of mass the frame's ``m_tot``, its time
  ``sqrt(b_e/g)``; its constants ``Iy = I_e/(m_tot b_e^2)``, ``zc = z_e/b_e`` and the central
  inertia ``A = Iy - 1 - zc^2`` (:func:`frame_constants`; the 3D slots are NaN: unused);
* landings switch every column's pivot across its base; the default restitution is the frame's
  (``FrameBlock.restitution``), not the column's;
* the outputs map back to the frame: theta is every column's tilt, the positions (the pivot,
  the base centre, the epistyle's translation) are each column's displacement from where it
  stood (:func:`_histories`).

The options read as the ``2d`` model reads them, each on the frame's terms (:func:`frame_options`).
"""

import math

import numpy as np
import xarray as xr

from pipeline import models
from pipeline.dataset import annotate, append_history
from pipeline.dynamics.rigid import diagnostics as rd
from pipeline.dynamics.rigid import frustum as fk
from pipeline.dynamics.rigid import layout as hy
from pipeline.dynamics.rigid import rocking as rk
from pipeline.dynamics.rigid.run2d import run_rocking
from pipeline.errors import InputError
from pipeline.response import Response
from pipeline.settings import check_column
from pipeline.simulate import (
    RIGID_CONTACT_TILT, kernel_diagnostics, kernel_options, kernel_record, kernel_summary, output_instants, run_kernel,
)
from pipeline.structures.colonnade import Colonnade
from pipeline.structures.description import history_attributes, whole_label
from pipeline.units import G, deg_to_rad, time_scale

__all__ = ["simulate_frame", "check_frame", "frame_constants", "frame_options", "frame_lying_tilt", "frame_restitution",
           "frame_patch"]


def frame_constants(frame):
    """The planar kernel's constants array (``fk.C_*``) of a :class:`FrameBlock`, per ``m_tot`` and ``b_e``.

    ``Iy``, ``zc`` and ``A`` (:meth:`FrameBlock.kernel_constants`); the 3D slots (axial inertia,
    Delta, K) have no meaning for a planar frame and are NaN, so that any use would show.
    """
    c = np.full(fk.N_CONST, np.nan)
    c[fk.C_IY], c[fk.C_ZC], c[fk.C_A] = frame.kernel_constants()
    return c


def frame_lying_tilt(colonnade):
    """Tilt at which the columns lie down, the frame's overturning event [rad].

    The first point of a column's outline in the plane (the shaft's top rim, the capital's
    lower and upper corners) to reach the ground as the column turns about its pivot: for a
    point at (u, z) from the pivot (u > 0 towards the lean) that is ``atan2(z, u)``. Without a
    capital it is the ``2d`` model's :func:`pipeline.simulate.lying_tilt`.
    """
    col = colonnade.column.column
    points = [(col.r - col.R, col.h)]
    if colonnade.capital is not None:
        u = colonnade.half_abacus - col.R
        points += [(u, col.h), (u, colonnade.abacus_top)]
    return min(math.atan2(z, u) for u, z in points)


def frame_restitution(colonnade, settings):
    """theta' after / before a landing: ``settings.restitution``, or the frame's from angular momentum
    (:attr:`FrameBlock.restitution`), clipped at 0."""
    if settings.restitution is not None:
        return float(settings.restitution)
    return max(0.0, colonnade.frame.restitution)


def _base_share(colonnade):
    """Weight carried by one column's base at rest [N]: its column and an equal share of the epistyle."""
    frame = colonnade.frame
    return (frame.m + frame.M / frame.n) * G


def frame_patch(colonnade, settings):
    """The contact patch of the frame's column bases, in the kernel's terms: (theta_k [rad], dashpots [1], c_n [Pa s/m]).

    Every base carries an equal share of the frame's normal force (the epistyle a rigid beam on
    equal beds): ``theta_k = (m + M/N) g / (k_n pi R^3)``, the tilt at which a base under its share
    just loses full contact, and the kernel's segment depth and second moments are then every
    base's (docs/model.md). The dashpots ``c_n`` per unit area (``contact_damping``, or the
    critical damping of one column with its share bouncing on its base,
    ``2 sqrt(k_n (m + M/N) / (pi R^2))``) damp rolling with N times one base's couple:
    ``N c_n R^4 / (m_tot sqrt(g b_e) b_e)`` in the kernel's units. (0, 0, 0) for the point contact.
    """
    kn = settings.normal_stiffness
    if kn == math.inf:
        return 0.0, 0.0, 0.0
    frame = colonnade.frame
    R, area = frame.R, math.pi * frame.R**2
    share = _base_share(colonnade)
    theta_k = share / (kn * area * R)
    c_n = settings.contact_damping if settings.contact_damping is not None else \
        2.0 * math.sqrt(kn * share / G / area)
    damping = frame.n * c_n * R**4 / (frame.m_tot * math.sqrt(G * frame.b_e) * frame.b_e)
    return theta_k, damping, c_n


def frame_options(colonnade, settings):
    """The planar kernel's options array of the frame (``fk.OPT_*``), every option on the frame's terms.

    * ``friction``, ``lift_off``: the whole frame's, on its column bases together (Coulomb's law on
      the sum of the bases' forces, flight when their sum would pull);
    * ``damping`` nu: at each base the couple the ``2d`` model puts under one column,
      ``nu m g R sqrt(R/g) theta'`` (m the column's mass with its capital), N of them:
      ``nu N m R^1.5 / (m_tot b_e^1.5)`` per the kernel's unit;
    * ``normal_stiffness``, ``contact_damping``: :func:`frame_patch`; ``contact_tilt`` [deg] as given,
      else the patch's theta_k, else the rigid models' 1e-7 rad.
    """
    frame = colonnade.frame
    theta_k, patch_damping, _c_n = frame_patch(colonnade, settings)
    if settings.contact_tilt is not None:
        theta_c = deg_to_rad(settings.contact_tilt)
    else:
        theta_c = theta_k if theta_k > 0.0 else RIGID_CONTACT_TILT
    nu = settings.damping * frame.n * frame.m * frame.R**1.5 / (frame.m_tot * frame.b_e**1.5)
    return kernel_options(settings, frame_lying_tilt(colonnade), nu, theta_k, patch_damping, theta_c)


def check_frame(colonnade, settings):
    """Refuse, before anything is computed, a colonnade the frame cannot run (the registry's ``Model.checker``
    of ``2d-frame``, called by :func:`simulate_frame` too): one that is no colonnade, a column out of range,
    or columns that would lie on the ground before the frame tips over."""
    if not isinstance(colonnade, Colonnade):
        raise InputError(f"model = {settings.model!r} runs a colonnade, got {type(colonnade).__name__}")
    check_column(colonnade.column.column)
    theta_lie, alpha = frame_lying_tilt(colonnade), colonnade.frame.alpha
    if not theta_lie > alpha:
        raise InputError(f"{colonnade.name or 'colonnade'}: its columns would lie on the ground (at "
                         f"{math.degrees(theta_lie):.1f} deg) before the frame tips over (at "
                         f"{math.degrees(alpha):.1f} deg); a capital this wide on a column this squat is "
                         "outside the frame model: give a narrower capital or a more slender column")


def simulate_frame(colonnade, motion, excitation, settings, histories=True, progress=None):
    """The response of a colonnade as the rigid planar frame (``2d-frame``), rocking in the row's plane.

    Same arguments and result as :func:`pipeline.simulate.simulate`, with a
    :class:`pipeline.structures.colonnade.Colonnade`: it rocks in the vertical plane of its row (x),
    driven by the X component of the pair turned by the incidence angle. ``progress`` is not called.
    """
    check_frame(colonnade, settings)
    frame = colonnade.frame
    theta_lie = frame_lying_tilt(colonnade)
    length = frame.b_e  # the kernel's unit of length: the equivalent block's pivot to base centre
    t_scale = time_scale(length)
    record = kernel_record(motion, excitation, planar=True)
    params = (frame_constants(frame), record, motion.dt / t_scale, frame_options(colonnade, settings))
    raw = run_kernel(run_rocking, params, t_scale, frame_restitution(colonnade, settings), settings,
                     np.zeros(rk.N_STATE2), motion.duration + settings.tail, settings.settle_limit)
    diag = kernel_diagnostics(raw, settings)
    summary = kernel_summary(raw, length, frame.alpha, settings, motion, excitation)
    # the kernel's base centre is the equivalent block's; a column's base is off it while tilted
    last = raw.states[raw.n_filled - 1] if raw.n_filled else np.zeros(rk.N_STATE2)
    theta = last[rk.THETA2] if raw.summary[hy.S_FINAL_PHASE] not in (hy.PHASE_REST, hy.PHASE_SLIDING) else 0.0
    base = raw.summary[hy.S_BASE_X] * length + _base_offset(frame, theta)
    summary["residual_displacement"] = float(abs(base))
    summary["overturn_body"] = whole_label(colonnade) if summary["overturned"] else ""  # it falls as one
    ds = _histories(colonnade, settings, raw, diag, excitation, motion) if histories else None
    return Response(summary, ds, _impact_table(raw, length))


def _base_offset(frame, theta):
    """A column's base centre minus the equivalent block's, at signed tilt theta [m]: ``s (b_e - R)(cos theta - 1)``.

    Both bases move alike when the bases slide or slip and stay put while the frame rocks; only
    their distances to the pivot differ (R and b_e), so the offset vanishes flat (docs/model.md).
    """
    s = np.copysign(1.0, theta)
    return s * (frame.b_e - frame.R) * (np.cos(theta) - 1.0)


def _impact_table(raw, length):
    """Landings in SI: time [s], theta' before and after [rad/s], energy jump per the frame's weight [m]."""
    table = raw.impacts.copy()
    table[:, 0] *= raw.t_scale
    table[:, 1:3] /= raw.t_scale
    table[:, 3] *= length
    return table


def _histories(colonnade, settings, raw, diag, excitation, motion):
    """The frame's histories: every column's tilt and positions, the epistyle's translation, the bases' forces."""
    frame = colonnade.frame
    b, R, c, H_t = frame.b_e, frame.R, frame.c, frame.H_t
    ts = raw.t_scale
    per_s = 1.0 / ts
    st, phase = raw.states, raw.phase
    flat = (phase == hy.PHASE_REST) | (phase == hy.PHASE_SLIDING)
    signed = np.where(flat, 0.0, st[:, rk.THETA2])  # a flat frame's state holds no tilt
    theta = np.abs(signed)
    side = np.copysign(1.0, signed)  # the pivots' side; every term it multiplies vanishes flat
    x_b = diag[:, rd.D_BASE_X] * b + _base_offset(frame, signed)
    on_rim = ~np.isnan(diag[:, rd.D_CONTACT_X])
    x_p = np.where(on_rim, x_b + side * R * np.cos(theta), np.nan)
    # the pivots' height: 0 on the ground, in flight the kernel's centre height less its lever's
    flight = phase == hy.PHASE_FLIGHT
    lift = np.where(flight, st[:, rk.Z2] - np.sin(theta) - (frame.z_e / b) * np.cos(theta), 0.0) * b
    data = {
        "phi": np.where(flat, np.nan, np.copysign(0.5 * math.pi, signed)),
        "theta": theta,
        "x_p": x_p,
        "y_p": np.where(on_rim, 0.0, np.nan),
        "x_b": x_b,
        "y_b": np.zeros_like(x_b),
        "theta_dot": np.where(flat, 0.0, side * st[:, rk.DTHETA2]) * per_s,
        # the epistyle translates with the capitals' top edges opposite the pivots (-side c from each axis)
        "epistyle_dx": x_b + side * c * (1.0 - np.cos(theta)) + H_t * np.sin(signed),
        "epistyle_dz": lift + (R + c) * np.sin(theta) + H_t * (np.cos(theta) - 1.0),
        "omega_zeta": diag[:, rd.D_OMEGA] * per_s,
        # energies per m_tot g R, R the column's base radius (the kernel's are per m_tot g b_e)
        "energy_hat": diag[:, rd.D_ENERGY] * b / R,
        "normal_force_hat": diag[:, rd.D_NORMAL],
        "tangential_force_hat": diag[:, rd.D_TANGENTIAL],
        "mu_mob": diag[:, rd.D_MU],
        "slip_velocity": diag[:, rd.D_SLIP] * math.sqrt(G * b),
        "ground_acc_x": diag[:, rd.D_AX] * G,
        "ground_acc_y": np.zeros_like(diag[:, rd.D_AX]),
        "ground_acc_z": diag[:, rd.D_AZ] * G,
    }
    weight = frame.m_tot * G
    data["normal_force"] = data["normal_force_hat"] * weight
    data["tangential_force"] = data["tangential_force_hat"] * weight
    data["energy"] = diag[:, rd.D_ENERGY] * weight * b
    # the output instants as the column's run (unit sqrt(R/g), pipeline.simulate.run_kernel) has them, to the
    # bit: the models of one simulate file share one time axis (the kernel's rows are the same instants to
    # round-off)
    t_column = time_scale(R)
    tau = output_instants(raw.tau.shape[0], motion.duration + settings.tail, settings.settle_limit,
                          settings.output_step, t_column)
    variables = {k: ("time", np.asarray(v, dtype=np.float64)) for k, v in data.items()}
    variables["phase"] = ("time", phase.astype(np.int8))
    ds = xr.Dataset(variables, coords={"time": tau * t_column, "tau": ("time", tau)})
    theta_k, _damping, c_n = frame_patch(colonnade, settings)
    col = colonnade.column.column
    ds.attrs.update(history_attributes(colonnade, models.get(settings.model)))
    ds.attrs.update(
        comment=f"{settings.model}, the colonnade as a rigid planar frame: theta is the common tilt of its columns, "
        "x_b and x_p every column's base centre and pivot from where it stood, epistyle_dx and epistyle_dz the "
        "epistyle's translation; forces and energies the whole frame's",
        model=settings.model,
        column_R_m=col.R,
        column_r_m=col.r,
        column_h_m=col.h,
        theta_crit_rad=frame.alpha,
        column_mass_kg=frame.m,
        epistyle_mass_kg=frame.M,
        frame_mass_kg=frame.m_tot,
        frame_lever_m=frame.b_e,
        frame_height_m=frame.z_e,
        frame_inertia_kg_m2=frame.I_e,
        frame_frequency_parameter_rad_s=frame.frequency_parameter,
        contact_tilt_rad=frame_options(colonnade, settings)[fk.OPT_THETA_C],
        friction=settings.friction,
        restitution=frame_restitution(colonnade, settings),
        damping=settings.damping,
        lift_off="true" if settings.lift_off else "false",
        normal_stiffness_Pa_m=settings.normal_stiffness,
        contact_damping_Pa_s_m=c_n,
        base_theta_k_rad=theta_k,
        rtol=settings.rtol,
        atol=settings.atol,
    )
    if motion is not None:
        ds.attrs.update(record_id=motion.record_id, record_sha256=motion.sha256(),
                        incidence_angle_rad=excitation.angle_rad, scale=excitation.scale)
    annotate(ds)
    append_history(ds, f"pipeline.frame ({settings.model})")
    return ds
