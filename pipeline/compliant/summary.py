"""What a compliant run reports: the rigid models' summary keys, per body and per joint, named.

A column's base is the joint the rigid models' keys describe (uplift, landings, friction,
sliding, lift-off, residual displacement); a colonnade has one base per column, and each key
then tells the worst of them (the earliest time, the largest peak, the lowest force). Every
body's peak tilt and residual rotation, every joint's residual slip, twist, tilt and opening
come per body and per joint, in the structure's order, named by ``body_label`` and
``joint_label``; a colonnade also tells which body fell first and how far its epistyle moved
on its capitals and opened between its blocks.
"""

import math

import numpy as np

from pipeline.dynamics.compliant import assembly as sk
from pipeline.dynamics.compliant.layout import (
    A_DAMPING, A_FRICTION, A_WORK, BS_PEAK, BS_ROTATION, JS_FLIGHT_TIME, JS_MIN_AREA, JS_MIN_NORMAL, JS_PEAK_MU,
    JS_RETURNS, JS_SLIDE_TIME, JS_UPLIFT_TIME, NB, N_ACC, QW, QZ, STATUS_COLLAPSED, S_ENERGY_END, S_ENERGY_START,
    S_NFEV, S_OVERTURN_BODY, S_OVERTURN_TIME, S_PEAK_THETA, S_PEAK_TIME, S_REJECTED, S_STATUS, S_STEPS,
    S_UNDECIDED,
)

__all__ = ["summary", "joint_dislocations", "dislocation_ratio", "joint_diameters"]


def summary(structure_column, asm, params, settings, raw, damping, restitution):
    """The run's summary (SI, energies per unit weight [m]).

    Parameters
    ----------
    structure_column : pipeline.structures.drums.DrumColumn
        The column (a colonnade's every column): its theta_crit makes ``peak_theta_ratio``.
    asm : pipeline.compliant.tables.Assembly
    params : tuple
        Its kernel parameters (scratch overwritten).
    settings : pipeline.settings.ModelSettings
    raw : pipeline.compliant.integrate.Raw
    damping, restitution : float
        The joints' damping [Pa s/m] and the restitution it was calibrated to [1] (NaN if given).
    """
    s, L, T = raw.summary, asm.length, asm.time
    layout = asm.layout
    overturned = not math.isnan(s[S_OVERTURN_TIME])
    # peaks of friction and contact before any final fall past theta_crit
    stats = raw.joint_committed if overturned else raw.joint_stats
    n_b, n_p, n_j = asm.n_bodies, asm.points.shape[0], asm.n_joints
    acc = raw.y_end[NB * n_b + 2 * n_p:]
    work, friction, damping_loss = acc[A_WORK], acc[A_FRICTION], acc[A_DAMPING]
    slip_paths = acc[N_ACC:N_ACC + n_j]
    e0, e1 = s[S_ENERGY_START], s[S_ENERGY_END]
    bases = [j for j, c in enumerate(layout.contacts) if c.kind == "base"]
    rims = [j for j, c in enumerate(layout.contacts) if c.rim]
    uplift_times = raw.joint_stats[rims, JS_UPLIFT_TIME]
    uplift = float(np.nanmin(uplift_times)) if np.any(np.isfinite(uplift_times)) else math.nan
    # imperfect drums stand offset at rest: their dislocations are measured from there
    joints = joint_dislocations(asm, params, raw.y_end, None if layout.imperfections is None else raw.y0)
    diameters = joint_diameters(asm)
    body = int(s[S_OVERTURN_BODY]) if overturned else -1
    out = {
        "model": settings.model,
        "peak_theta": float(s[S_PEAK_THETA]),
        "peak_theta_ratio": float(s[S_PEAK_THETA] / structure_column.column.critical_tilt),
        "peak_time": float(s[S_PEAK_TIME] * T),
        "overturned": overturned,
        "undecided": bool(s[S_UNDECIDED]),
        "overturn_time": float(s[S_OVERTURN_TIME] * T),
        "collapsed": bool(s[S_STATUS] == STATUS_COLLAPSED),
        "uplifted": bool(math.isfinite(uplift)),
        "uplift_time": uplift * T,
        "n_impacts": int(np.max(raw.joint_stats[bases, JS_RETURNS])),
        "peak_mu_mob": float(np.max(stats[bases, JS_PEAK_MU])),
        "sliding_onset": bool(np.any(np.isfinite(stats[bases, JS_SLIDE_TIME]))),
        "sliding_time": _earliest(raw.joint_stats[bases, JS_SLIDE_TIME]) * T,
        "min_normal_force_hat": float(np.min(stats[bases, JS_MIN_NORMAL])),
        "lift_off": bool(np.any(np.isfinite(stats[bases, JS_FLIGHT_TIME]))),
        "lift_off_time": _earliest(stats[bases, JS_FLIGHT_TIME]) * T,
        "residual_rotation": float(_largest(raw.body_stats[[asm.layout.contacts[j].upper for j in bases],
                                                           BS_ROTATION])),
        "residual_displacement": float(np.max(joints["joint_slip"][bases])),
        "slip": float(np.max(slip_paths[bases]) * L),
        "contact_area_fraction": float(np.min(stats[bases, JS_MIN_AREA])),
        "energy_initial": float(e0 * L),
        "work_ground": float(work * L),
        "energy_transitions": 0.0,
        "energy_dissipated": float((friction + damping_loss) * L),
        "energy_friction": float(friction * L),
        "energy_damping": float(damping_loss * L),
        "energy_final": float(e1 * L),
        "energy_balance_error": float(((e1 - e0) - (work - friction - damping_loss)) * L),
        "rhs_evaluations": int(s[S_NFEV]),
        "steps": int(s[S_STEPS]),
        "rejected_steps": int(s[S_REJECTED]),
        "restitution": float(restitution),
        "contact_damping": float(damping),
        "n_drums": structure_column.n_drums,
        "n_bodies": n_b,
        "body_label": tuple(p.label for p in layout.parts),
        "joint_label": joint_labels(layout),
        # each joint's kind (base, bed, capital, bearing, head) and each body's column (-1: an epistyle block)
        "joint_kind": tuple(c.kind for c in layout.contacts),
        "body_column": np.array([p.column for p in layout.parts]),
        "drum_peak_theta": raw.body_stats[:, BS_PEAK].copy(),
        "drum_residual_rotation": raw.body_stats[:, BS_ROTATION].copy(),
        "overturn_drum": body,
        "overturn_body": layout.parts[body].label if overturned else "",
        **joints,
        "joint_diameter": diameters,
        "dislocation_ratio": dislocation_ratio(joints["joint_slip"], diameters, _bed_joints(layout)),
        "joint_uplifted": np.isfinite(raw.joint_stats[:, JS_UPLIFT_TIME]),
        "joint_uplift_time": raw.joint_stats[:, JS_UPLIFT_TIME] * T,
        "joint_peak_mu_mob": stats[:, JS_PEAK_MU].copy(),
    }
    # a colonnade: how far its epistyle moved on its capitals and opened between its blocks (NaN: a column)
    bearings = [j for j, c in enumerate(layout.contacts) if c.kind == "bearing"]
    heads = [j for j, c in enumerate(layout.contacts) if c.kind == "head"]
    out["epistyle_slip"] = float(np.max(joints["joint_slip"][bearings])) if bearings else math.nan
    out["epistyle_opening"] = float(np.max(joints["joint_opening"][heads])) if heads else \
        (0.0 if bearings else math.nan)
    if layout.imperfections is not None:  # what was drawn, per joint (pipeline.structures.imperfections)
        out.update(layout.imperfections.recorded(n_j))
    return out


def _earliest(times):
    finite = times[np.isfinite(times)]
    return float(finite.min()) if finite.size else math.nan


def _largest(values):
    return values[int(np.argmax(np.abs(values)))]


def _bed_joints(layout):
    return [j for j, c in enumerate(layout.contacts) if c.kind in ("bed", "capital")]


def joint_labels(layout):
    """Each joint in words, as the structure names it (:mod:`pipeline.structures.description`): "base of
    column 2", "bed joint under drum 3", "capital 2 / epistyle block 1", "head joint blocks 1-2"; a joint
    of a layout made by hand without labels by its kind and index ("bearing joint 3")."""
    return tuple(c.label or f"{c.kind} joint {j}" for j, c in enumerate(layout.contacts))


def joint_diameters(asm):
    """Each joint's face across [m]: a disc's diameter (a base: its body's), a rectangle's longer side."""
    out = []
    for c in asm.layout.contacts:
        half = c.half[0] if math.isfinite(c.half[0]) else float(np.max(np.hypot(c.points[:, 3], c.points[:, 4])))
        out.append(2.0 * (half if c.shape == 0 else max(c.half)))
    return np.array(out)


def joint_dislocations(asm, params, y, rest=None):
    """Dislocation of every joint of a structure in the state y (the residual one at the end of a run).

    Measured in the frame of each joint's face, from the state the run started in for a joint
    on the ground (where the column stood), and for every joint with ``rest`` (imperfect drums,
    which stand offset at rest: the slip and twist from those of the state ``rest``):

    Parameters
    ----------
    asm : pipeline.compliant.tables.Assembly
    params : tuple
        The kernel parameters of ``asm`` (its scratch is overwritten).
    y : numpy.ndarray
        A state of :mod:`pipeline.dynamics.compliant.assembly` (dimensionless).

    Returns
    -------
    dict of numpy.ndarray, one value per joint
        ``joint_slip`` [m]: offset of the upper body's bearing face from the face's centre
        (a base: from where it stood); ``joint_twist`` [rad]: rotation of the upper face about
        the face's normal, in (-pi, pi]; ``joint_tilt`` [rad]: angle between the two faces'
        normals (a base: the tilt of its body); ``joint_opening`` [m]: the widest gap between a
        contact point and the face (0 while every point presses in).
    """
    n_j, L = asm.n_joints, asm.length
    out = np.zeros((n_j, 4))
    sk.dislocations(y, params, out)  # a base's face is centred where its column stood
    if rest is not None:
        start = np.zeros((n_j, 4))
        sk.dislocations(rest, params, start)
        out[:, :2] -= start[:, :2]
        out[:, 2] = (out[:, 2] - start[:, 2] + math.pi) % (2.0 * math.pi) - math.pi
    rot = np.empty((asm.n_bodies, 9))
    for b in range(asm.n_bodies):
        sk.rotation_matrix(*y[NB * b + QW:NB * b + QZ + 1], rot[b])
    rot = rot.reshape(-1, 3, 3)
    tilt = np.empty(n_j)
    for j, c in enumerate(asm.layout.contacts):
        lower = np.eye(3) if c.lower < 0 else rot[c.lower]
        normal_face = lower @ np.asarray(c.axes)[:, 2]
        normal_upper = rot[c.upper] @ np.asarray(c.upper_axes)[:, 2]
        tilt[j] = math.atan2(np.linalg.norm(np.cross(normal_face, normal_upper)), normal_face @ normal_upper)
    return {
        "joint_slip": np.hypot(out[:, 0], out[:, 1]) * L,
        "joint_twist": out[:, 2].copy(),
        "joint_tilt": tilt,
        "joint_opening": out[:, 3] * L,
    }


def dislocation_ratio(joint_slip, joint_diameter, beds=None):
    """Largest residual slip of a bed joint over that joint's diameter [1]; 0 without bed joints.

    The damage measure of :data:`pipeline.fragility.DISLOCATION_STATES`. The base is left out:
    the ground is an unbounded plane here, so a column's slide on it changes nothing of its
    stability, while a drum slid by s on the one below stands on a lever arm shortened from D/2
    to D/2 - s towards the side it slid to (see the fragility module).

    Parameters
    ----------
    joint_slip, joint_diameter : array_like
        Per joint [m] (:func:`joint_dislocations`).
    beds : sequence of int, optional
        The bed joints (drum on drum, capital on shaft); default every joint but the first (a
        single column's base).
    """
    slip = np.asarray(joint_slip, dtype=np.float64)
    diameter = np.asarray(joint_diameter, dtype=np.float64)
    beds = list(range(1, len(slip))) if beds is None else list(beds)
    return float(np.max(slip[beds] / diameter[beds])) if beds else 0.0
