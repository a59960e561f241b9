"""The compliant kernel's dimensionless tables of a structure, with the joint law's parameters.

:func:`assemble` turns a structure's :class:`pipeline.compliant.parts.Layout` into the tables of
:mod:`pipeline.dynamics.compliant.layout` (lengths per L, the first column's base radius; masses
per the total M; forces per M g; time per sqrt(L/g)), each joint with the settings' stiffness,
friction and damping:

* the base of a column on the ground: ``normal_stiffness``, ``friction``;
* every joint between stones (bed joints, a capital on its shaft, an epistyle block on a
  capital, two blocks end to end): ``joint_stiffness`` (default the base's) and
  ``joint_friction`` (one value, or one per bed joint of a single column; default the base's);
* the dashpots keep the base's damping ratio: ``c_n sqrt(k_joint / k_n)`` per unit area;
* imperfect drums with a friction range (``settings.friction_range``): every joint of a column,
  its base too, takes its drawn friction (:mod:`pipeline.structures.imperfections`); the
  epistyle's bearings and head joints keep ``joint_friction``.
"""

import math
from dataclasses import dataclass

import numpy as np

from pipeline.compliant.layouts import layout_of
from pipeline.compliant.parts import per_joint
from pipeline.dynamics.compliant import assembly as sk
from pipeline.dynamics.compliant import linear_system as ls
from pipeline.dynamics.compliant.layout import (
    B_COS_LIE, B_HEIGHT, B_HOLD, B_IX, B_IY, B_IZ, B_MASS, B_SUPPORT, B_ZC, B_Z_FALL, GROUND, J_AREA, J_BAND, J_CN,
    J_DELTA, J_F, J_FA, J_FB, J_G, J_IMPLICIT, J_KN, J_KS, J_LAND, J_LOWER, J_MU, J_OX, J_RIM, J_SHAPE, J_TAU,
    J_UFLOOR, J_UPPER, J_UX, N_BODY_COLS, N_JOINT_COLS, N_POINT_COLS, SHAPE_DISC,
)
from pipeline.errors import InputError
from pipeline.units import G

__all__ = ["Assembly", "assemble", "numerics"]


@dataclass(frozen=True)
class Assembly:
    """Dimensionless tables of one structure for the kernel, and the reference scales.

    Attributes
    ----------
    layout : pipeline.compliant.parts.Layout
        The bodies and joints it was made from (SI).
    bodies, points, joint_start, joints : numpy.ndarray
        Tables of :mod:`pipeline.dynamics.compliant.layout` (holding loads not yet set).
    length : float
        Reference length L [m].
    mass : float
        Total mass M [kg].
    time : float
        sqrt(L/g) [s].
    barrier : float
        The lowest overturning barrier [M g L] (:mod:`pipeline.compliant.barriers`).
    critical : numpy.ndarray
        Critical tilt of the part that tips with each body [rad].
    pattern : tuple
        The fixed-step solve's elimination pattern
        (:func:`pipeline.dynamics.compliant.linear_system.elimination`).
    """

    layout: object
    bodies: np.ndarray
    points: np.ndarray
    joint_start: np.ndarray
    joints: np.ndarray
    length: float
    mass: float
    time: float
    barrier: float
    critical: np.ndarray
    pattern: tuple

    @property
    def n_bodies(self):
        return self.bodies.shape[0]

    @property
    def n_joints(self):
        return self.joints.shape[0]

    def params(self, record=None, dt=1.0):
        """Kernel parameters with a record (n, 3) [g] sampled every dt [tau]."""
        record = np.zeros((0, 3)) if record is None else record
        return sk.make_params(self.bodies.copy(), self.points, self.joint_start, self.joints.copy(), record, dt,
                              np.array(self.layout.watched))


def numerics(settings):
    """The compliant model's numerical choices: the defaults of its registry entry
    (:data:`pipeline.models.compliant.COMPLIANT_DRUMS`), the settings' overrides."""
    from pipeline.models.compliant import COMPLIANT_DRUMS

    return {**COMPLIANT_DRUMS.numerics, **dict(settings.numerics)}


def _joint_law(contacts, settings, imperfect=None):
    """Per joint: (stiffness [Pa/m], friction [1]) from the settings, by the joint's kind; with ``imperfect``
    (the imperfections drawn, :class:`pipeline.structures.imperfections.JointDraw`) and a friction
    range, the drawn friction of the columns' joints (the first joints, in the draw's order)."""
    beds = [c for c in contacts if c.kind in ("bed", "capital")]
    columns = len({c.column for c in contacts if c.column >= 0})  # an epistyle's joints are of no column
    per_bed = iter(per_joint(settings.joint_friction, len(beds), "joint_friction", settings.friction, columns))
    # a list is refused above for a colonnade, the only structure with joints between stones that are no bed joints
    stones = settings.friction if settings.joint_friction is None else settings.joint_friction
    law = []
    for c in contacts:
        if c.kind == "base":
            law.append((settings.normal_stiffness, settings.friction))
            continue
        stiffness = settings.joint_stiffness or settings.normal_stiffness
        law.append((stiffness, float(next(per_bed)) if c.kind in ("bed", "capital") else float(stones)))
    if imperfect is not None and imperfect.imperfections.friction_range is not None:
        for j, mu in enumerate(imperfect.friction):
            law[j] = (law[j][0], float(mu))
    return law


def _check_tilts(layout, law):
    """Refuse a bed that leans past its joint's friction angle: its drum would slide off at rest, not stand
    imperfect (the static solve holds the lean on the shear springs, sticking)."""
    beds = layout.imperfections
    if beds is None:
        return
    from pipeline.compliant.summary import joint_labels

    labels = joint_labels(layout)
    for j in range(beds.n_joints):
        mu = law[j][1]
        if math.tan(beds.tilt[j]) >= mu:
            raise InputError(f"imperfections = {beds.imperfections.tolerance:g} m: the {labels[j]} leans "
                             f"{math.degrees(beds.tilt[j]):.3g} deg (seed {beds.imperfections.seed}), at or past its "
                             f"friction angle atan({mu:g}) = {math.degrees(math.atan(mu)):.3g} deg: the body on it "
                             "would slide at rest; give a smaller tolerance or a higher friction")


def assemble(structure, settings, damping):
    """Dimensionless tables of a structure for :mod:`pipeline.dynamics.compliant.assembly`.

    Parameters
    ----------
    structure : Column, DrumColumn or Colonnade
    settings : pipeline.settings.ModelSettings
        Joint stiffness, ratio, friction, contact points, anathyrosis.
    damping : float
        Normal damping per unit area c_n [Pa s/m] of the base; a joint of another stiffness
        gets the same damping ratio, c_n sqrt(k_joint / k_n).

    Returns
    -------
    Assembly
    """
    from pipeline.compliant.barriers import overturning_barriers

    layout = layout_of(structure, settings)
    edge_band = numerics(settings)["edge_band"]
    implicit = numerics(settings)["springs"] == "implicit"
    parts, contacts = layout.parts, layout.contacts
    L = layout.length
    M = sum(p.mass for p in parts)
    T = math.sqrt(L / G)
    force = M * G  # force unit
    bodies = np.zeros((len(parts), N_BODY_COLS))
    for b, p in enumerate(parts):
        bodies[b, B_MASS] = p.mass / M
        bodies[b, B_IX], bodies[b, B_IY], bodies[b, B_IZ] = (i / (M * L * L) for i in p.inertia)
        bodies[b, B_ZC] = p.zc / L
        bodies[b, B_HEIGHT] = p.height / L
        bodies[b, B_COS_LIE] = math.cos(p.lie)
        bodies[b, B_SUPPORT], bodies[b, B_Z_FALL] = _support(b, parts, contacts, L)
        bodies[b, B_HOLD + 2] = p.mass / M  # the weight until the rest state sets it
    points, starts = [], [0]
    joints = np.zeros((len(contacts), N_JOINT_COLS))
    law = _joint_law(contacts, settings, layout.imperfections)
    _check_tilts(layout, law)
    for j, (c, (stiffness, mu)) in enumerate(zip(contacts, law)):
        table = np.zeros((len(c.points), N_POINT_COLS))
        table[:, :5] = c.points[:, :5] / L
        table[:, 5] = c.points[:, 5] / L ** 2
        points.append(table)
        starts.append(starts[-1] + len(table))
        kn = stiffness * L ** 3 / force
        ks = settings.stiffness_ratio * kn
        cn = damping * math.sqrt(stiffness / settings.normal_stiffness) * L ** 3 / (force * T)
        area = sum(table[:, 5].tolist())  # summed in the kernel's order: a full face is exactly its area
        load = c.load / M
        row = joints[j]
        row[J_LOWER], row[J_UPPER] = c.lower, c.upper
        row[J_OX:J_OX + 3] = np.asarray(c.origin) / L
        row[J_F:J_F + 9] = np.asarray(c.axes, dtype=float).ravel()
        row[J_UX:J_UX + 3] = np.asarray(c.upper_centre) / L
        row[J_G:J_G + 9] = np.asarray(c.upper_axes, dtype=float).ravel()
        row[J_SHAPE] = c.shape
        row[J_FA], row[J_FB] = c.half[0] / L, c.half[1] / L
        row[J_KN], row[J_KS], row[J_MU], row[J_CN] = kn, ks, mu, cn
        row[J_IMPLICIT] = 1.0 if implicit else 0.0
        # returns to the friction cone on the time scale of the joint's own shear vibration
        row[J_TAU] = math.sqrt(load / (ks * area))
        # the rim patch runs off the face below over edge_band spacings of the outer rings (or rows)
        row[J_BAND] = edge_band * _spacing(table, c.shape)
        row[J_AREA] = area
        row[J_DELTA] = load / (kn * area)  # the static penetration (a head joint's: its block's weight)
        # the elastic shear displacement at the cap under the joint's mean pressure
        row[J_UFLOOR] = mu * row[J_DELTA] / settings.stiffness_ratio
        if c.rim:
            radius = float(np.max(np.hypot(table[:, 3], table[:, 4])))
            # rocking on the rim: the centre of pressure beyond the chord joining the neighbours
            # of a rim point (any share of the load among a pivot point and its two neighbours,
            # which a compliant pivot presses in too); landed again: back inside half the radius
            row[J_RIM] = radius * math.cos(2.0 * math.pi / settings.contact_sectors)
            row[J_LAND] = 0.5 * radius
        else:
            row[J_RIM] = row[J_LAND] = -1.0
    barrier, critical = overturning_barriers(layout, contacts, law, M, L)
    pattern = ls.elimination(len(parts), [c.lower for c in contacts], [c.upper for c in contacts], layout.order)
    return Assembly(layout, bodies, np.concatenate(points), np.array(starts, dtype=np.int64), joints, L, M, T,
                    barrier, critical, pattern)


def _support(b, parts, contacts, L):
    """(joint, fall distance [L]) of body b: the first joint with a level face it rests on, and the
    distance of its centre from that face below which it has fallen off (its rest distance less its
    own height). A body on the ground: (-1, 0), fallen when its centre is below the ground.

    Measured on the supporting body, so that a capital or an epistyle carried down by a tilting
    column has not fallen off it (measured on the ground, the capital of a top drum rocking on the
    drum below counted as fallen before the drum passed twice its critical tilt).
    """
    part = parts[b]
    if part.on_ground:
        return -1.0, 0.0
    for j, c in enumerate(contacts):
        normal = np.asarray(c.axes, dtype=float)[:, 2]  # in the lower body's axes, upright at rest
        if c.upper != b or abs(normal[2]) < 0.5:
            continue  # another body's joint, or a head joint (its face stands upright)
        below = np.zeros(3) if c.lower == GROUND else np.asarray(parts[c.lower].centre, dtype=float)
        rest = float(normal @ (np.asarray(part.centre, dtype=float) - below - np.asarray(c.origin, dtype=float)))
        return float(j), (rest - part.height) / L
    raise ValueError(f"{part.label} rests on no level face")  # a layout's bug, not the user's


def _spacing(table, shape):
    """The spacing of the outermost points of a face: the outer rings' (a disc) or rows' (a rectangle)."""
    if shape == SHAPE_DISC:
        radii = np.unique(np.round(np.hypot(table[:, 3], table[:, 4]), 9))  # one radius per ring
        return radii[-1] - radii[-2] if len(radii) > 1 else radii[-1]
    u = np.unique(np.round(np.abs(table[:, 3]), 9))
    return u[-1] - u[-2] if len(u) > 1 else u[-1]


def ground_joints(asm):
    """Indices of the joints on the ground (the columns' bases)."""
    return [j for j in range(asm.n_joints) if asm.joints[j, J_LOWER] == GROUND]
