"""The motion of a column or a colonnade, animated: solid bodies in 3D moving with the ground.

:func:`animate_file` reads a histories file of ``frustum simulate`` (one
column, one record, one or both models) and writes a GIF (matplotlib's
Pillow writer) or an MP4 (matplotlib's ffmpeg writer with the ffmpeg of the
``imageio-ffmpeg`` package: ``pip install -e '.[video]'``). Each model gets a
3D view, side by side when the file holds both: the column as a shaded
solid with a stripe along one generator (so that its spin shows), the ground
as a plate that moves with the ground displacement, the path of the contact
point on that plate, an arrow for the horizontal ground acceleration, and the
time and tilt in the title. By default one second of animation is one second
of motion (``speed`` 1).

The drawing is per body: :func:`frustum_faces` turns one frustum
(:class:`Shape`) at one :class:`Pose` into shaded polygons, and
:class:`ModelView` draws a list of bodies per frame. A rigid column is one
body (:func:`rigid_bodies`); a column of drums or a colonnade (the compliant
model's histories, with a ``drum`` dimension) is one body per drum, a square
block for a capital and a box for an epistyle block, each placed by its own
displacement, tilt and rotation (:func:`drum_bodies`); a rigid frame
(``2d-frame``, whose histories are the frame's tilt and the epistyle's
translation) is its columns, each with its capital, turning in unison about
their pivots and the epistyle translating on them, as the model says, the
row read back from the file's attributes (:func:`frame_bodies`). Each view
shows its own model's critical tilt.

Ground displacement is the double trapezoidal integral of the ground
acceleration from rest, without baseline correction: it shows how the ground
moves, not a survey of where it ends.

A run ends at the overturn (:func:`frame`): the models compute no further,
and the histories hold the last computed state to the end of the record (the
compliant model stops when a body reaches its lying tilt, which for a drum
high on the shaft is in mid-air). From the overturn on, a view shows that
last state as one still picture, greyed, with plate, path and arrow stopped
with it, and a caption saying when the column fell and which bodies fell. A
body that fell is drawn only where it lies on the ground (a rigid column
that lay down); one still in the air when the run ended is not drawn, and
the caption says that where it came to rest is not computed. Drawing it
anywhere, frozen in the air or laid on the ground at a guessed place, would
show a position the model never computed, and where fallen drums lie is
what an archaeologist compares with a site. The animation ends
:data:`HOLD` seconds after the last of its runs ended.
"""

import math
import os
import textwrap
from dataclasses import dataclass

import numpy as np

from pipeline.atomic import atomic_path
from pipeline.errors import InputError
from pipeline.models import DEFAULT
from pipeline.models import title as model_title  # the one description of each model
from pipeline.paths import MARKED

#: Segments around the circumference of a drawn frustum.
SEGMENTS = 32
#: Light direction (towards the light) for the shading of the faces.
LIGHT = np.array([-0.4, -0.7, 0.6]) / np.linalg.norm([-0.4, -0.7, 0.6])
STONE = np.array([0.87, 0.82, 0.72])  # marble, lit
STRIPE = np.array([0.55, 0.25, 0.18])


@dataclass(frozen=True)
class Shape:
    """A frustum body: base radius, top radius and height [m].

    ``sides`` 0 is a round frustum; ``sides`` 4 a square block (a capital) whose base and
    top are squares of half-side ``R`` and ``r`` [m], their sides along the body's x and y,
    or with ``half_y`` a rectangular block (an epistyle block: half length ``R`` along x,
    half width ``half_y``).
    """

    R: float
    r: float
    h: float
    sides: int = 0
    half_y: float = 0.0

    @property
    def z_cm(self):
        """Height of the centre of mass above the base [m] (a square block: h/2)."""
        from pipeline.structures.column import Column

        return Column(self.R, self.r, self.h).z_cm


@dataclass(frozen=True)
class Pose:
    """Where a body is: centre of its base [m] and orientation (body -> ground rotation matrix).

    Attributes
    ----------
    centre : numpy.ndarray
        (3,) position of the centre of the base in the drawing frame [m].
    rotation : numpy.ndarray
        (3, 3) rotation taking body axes (z along the body's axis) to the
        drawing frame.
    """

    centre: np.ndarray
    rotation: np.ndarray


def euler_rotation(phi, theta, psi):
    """Rotation matrix of the paper's Euler angles (Z-X-Z: precession phi, inclination theta, spin psi) [rad].

    The body axis is ``R @ (0, 0, 1) = (sin phi sin theta, -cos phi sin theta,
    cos theta)``; the contact point is at ``-R_base`` along ``Rz(phi) Rx(theta)
    (0, 1, 0)`` from the centre of the base, as in :mod:`pipeline.simulate`.
    """
    cf, sf = math.cos(phi), math.sin(phi)
    ct, st = math.cos(theta), math.sin(theta)
    cp, sp = math.cos(psi), math.sin(psi)
    rz_phi = np.array([[cf, -sf, 0.0], [sf, cf, 0.0], [0.0, 0.0, 1.0]])
    rx = np.array([[1.0, 0.0, 0.0], [0.0, ct, -st], [0.0, st, ct]])
    rz_psi = np.array([[cp, -sp, 0.0], [sp, cp, 0.0], [0.0, 0.0, 1.0]])
    return rz_phi @ rx @ rz_psi


def _unit_rings(segments=SEGMENTS):
    angle = np.linspace(0.0, 2.0 * math.pi, segments, endpoint=False)
    return np.cos(angle), np.sin(angle)


_COS, _SIN = _unit_rings()


def frustum_faces(shape, pose):
    """Shaded polygons of one frustum body at one pose.

    Parameters
    ----------
    shape : Shape
    pose : Pose

    Returns
    -------
    (list of numpy.ndarray, numpy.ndarray)
        Polygons (each (k, 3) vertices [m] in the drawing frame: the side
        quadrilaterals, the base and the top) and their RGB face colours
        (n_faces, 3), lit by :data:`LIGHT`; the first side face is the stripe.
    """
    if shape.sides:  # corners at 45 deg, at sqrt(2) times the half-side
        angle = 2.0 * math.pi * (np.arange(shape.sides) + 0.5) / shape.sides
        cos, sin = math.sqrt(2.0) * np.cos(angle), math.sqrt(2.0) * np.sin(angle)
    else:
        cos, sin = _COS, _SIN
    n = cos.size
    across = shape.half_y / shape.R if shape.half_y else 1.0  # a rectangle's sides along y
    bottom = np.stack([shape.R * cos, across * shape.R * sin, np.zeros(n)], axis=1)
    top = np.stack([shape.r * cos, across * shape.r * sin, np.full(n, shape.h)], axis=1)
    bottom = bottom @ pose.rotation.T + pose.centre
    top = top @ pose.rotation.T + pose.centre
    nxt = np.roll(np.arange(n), -1)
    sides = np.stack([bottom, bottom[nxt], top[nxt], top], axis=1)  # (n, 4, 3)
    normals = np.cross(sides[:, 1] - sides[:, 0], sides[:, 3] - sides[:, 0])
    axis = pose.rotation[:, 2]
    cap_normals = np.stack([-axis, axis])
    normals = np.concatenate([normals, cap_normals])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    light = 0.35 + 0.65 * np.clip(normals @ LIGHT, 0.0, None)
    colours = np.tile(STONE, (n + 2, 1))
    colours[0] = STRIPE
    colours = np.clip(colours * light[:, None], 0.0, 1.0)
    return list(sides) + [bottom, top], colours


def ground_displacement(acc, time):
    """Displacement [m] of the ground from its acceleration [m/s^2] (trapezoidal, twice, from rest)."""
    from scipy.integrate import cumulative_trapezoid

    acc = np.nan_to_num(np.asarray(acc, dtype=float))
    velocity = cumulative_trapezoid(acc, time, initial=0.0)
    return cumulative_trapezoid(velocity, time, initial=0.0)


def _filled(values, default=0.0):
    """Carry the last finite value forward over NaN (angles undefined at rest)."""
    values = np.asarray(values, dtype=float).copy()
    good = np.isfinite(values)
    if not good.any():
        return np.full(values.shape, default)
    index = np.where(good, np.arange(values.size), 0)
    np.maximum.accumulate(index, out=index)
    out = values[index]
    out[: np.argmax(good)] = default
    return out


class Motion:
    """The arrays of one run needed to draw it (all over ``time``), in SI.

    Parameters
    ----------
    run : xarray.Dataset
        One simulation, histories over ``time`` alone
        (:func:`pipeline.dataset.one_run`).
    """

    def __init__(self, run):
        self.run = run
        self.time = run["time"].values
        self.shape = Shape(float(run["column_R"]), float(run["column_r"]), float(run["column_h"]))
        self.model = str(run.attrs.get("model", DEFAULT))
        theta = np.nan_to_num(run["theta"].values)
        phi = _filled(run["phi"].values)
        psi = _filled(run["psi"].values) if "psi" in run else np.zeros_like(theta)
        psi = np.nan_to_num(psi)
        R = self.shape.R
        x_p, y_p = run["x_p"].values, run["y_p"].values
        if "x_b" in run and np.isfinite(run["x_b"].values).any():
            x_b, y_b = _filled(run["x_b"].values), _filled(run["y_b"].values)
        else:  # planar rocking: the centre follows from the pivot (at rest the base sits at the origin)
            x_b = np.where(np.isfinite(x_p), x_p - np.sin(phi) * np.cos(theta) * R, 0.0)
            y_b = np.where(np.isfinite(y_p), y_p + np.cos(phi) * np.cos(theta) * R, 0.0)
        self.phi, self.theta, self.psi = phi, theta, psi
        self.base = np.stack([x_b, y_b, R * np.sin(theta)], axis=1)
        self.contact = np.stack([x_p, y_p], axis=1)
        acc = [run[f"ground_acc_{c}"].values if f"ground_acc_{c}" in run else np.zeros_like(theta) for c in "xyz"]
        self.acc = np.nan_to_num(np.stack(acc, axis=1))
        self.ground = np.stack([ground_displacement(a, self.time) for a in self.acc.T], axis=1)
        # the model's own critical tilt (a rigid frame's is the frame's), else the column's
        self.theta_crit = float(run.attrs.get("theta_crit_rad", run["theta_crit"]))
        self.height = self.shape.h
        self.drums = ()
        self.frame = ()  # a rigid frame's bodies: (Shape, what it is, x of its column's axis [m]) each
        self.labels = ()
        self.row = False
        self.origin = np.zeros(2)  # where the base whose contact path is drawn stood (x_p, y_p are from there)
        self.span = (-self.shape.R, self.shape.R)
        if "drum_dx" in run and np.isfinite(run["drum_dx"].values).any():
            self._drums(run)
        elif "epistyle_dx" in run and np.isfinite(run["epistyle_dx"].values).any():
            self._frame(run)
        self.overturn_time = math.nan
        self.overturn_row = None  # the row holding the last computed state, from which the histories are held
        if "phase" in run:
            over = np.flatnonzero(run["phase"].values == 2)
            if over.size:
                self.overturn_row = int(over[0])
                self.overturn_time = float(self.time[over[0]])
                if "overturn_time" in run and np.isfinite(run["overturn_time"].values):  # between two rows
                    self.overturn_time = float(run["overturn_time"])
        # the body that lay down or fell first (the bodies above it went with it); a file without it: all fell
        first = int(run["overturn_drum"]) if "overturn_drum" in run else 0
        self.fell_from = first if first >= 0 else 0

    def _drums(self, run):
        """Each body's shape and, over time, its centre of mass [m] and Euler angles [rad].

        Drums (kind 0), square capitals (1) and a colonnade's epistyle blocks (2: half length
        ``drum_R``, half width ``drum_r``), each where it stood (``drum_x``, ``drum_y``, 0 for a
        single column) displaced by ``drum_dx``, ``drum_dy``, ``drum_dz``."""
        kind = run["drum_kind"].values
        self.drums = tuple(Shape(float(R), float(r), float(h), 0) if k == 0 else
                           Shape(float(R), float(R), float(h), 4, float(r) if k == 2 else 0.0)
                           for R, r, h, k in zip(run["drum_R"].values, run["drum_r"].values, run["drum_h"].values,
                                                 kind))
        rest = np.array([z + shape.z_cm for z, shape in zip(run["drum_z"].values, self.drums)])
        x0 = run["drum_x"].values if "drum_x" in run else np.zeros(len(self.drums))
        y0 = run["drum_y"].values if "drum_y" in run else np.zeros(len(self.drums))
        self.drum_centre = np.stack([x0[None, :] + run["drum_dx"].values, y0[None, :] + run["drum_dy"].values,
                                     rest[None, :] + run["drum_dz"].values], axis=2)
        self.labels = tuple(str(x) for x in run["body_label"].values) if "body_label" in run else ()
        self.row = bool(np.any(kind == 2))  # a colonnade: its bodies fall each on its own
        if self.row:  # the contact path is its first column's base's, from where that base stood
            self.origin = np.array([float(x0[0]), float(y0[0])])
        self.span = (float(np.min(x0 - run["drum_R"].values)), float(np.max(x0 + run["drum_R"].values)))
        self.drum_theta = np.nan_to_num(run["drum_theta"].values)
        # the direction of the tilt is undefined upright: any there, with the spin taking up the rest
        self.drum_phi = np.stack([_filled(column) for column in run["drum_phi"].values.T], axis=1)
        self.drum_psi = np.nan_to_num(run["drum_rotation"].values) - self.drum_phi
        self.height = float(np.max(run["drum_z"].values + run["drum_h"].values))

    def _frame(self, run):
        """A rigid frame (2d-frame): every column's shaft and capital and the epistyle, from the structure the
        file's attributes describe (:func:`pipeline.structures.description.colonnade_from_attributes`).

        The columns turn in unison by the frame's tilt about their pivots, each base where it stood
        moved by ``x_b``; the epistyle translates by ``epistyle_dx``, ``epistyle_dz``, as the model says."""
        from pipeline.structures.column import Column
        from pipeline.structures.description import colonnade_from_attributes, column_labels

        row = colonnade_from_attributes(run.attrs, Column(self.shape.R, self.shape.r, self.shape.h),
                                        f"the {self.model} run")
        cap, c = row.capital, row.half_abacus
        labels, bodies = [], []
        for k, x in enumerate(row.axes()):
            labels += column_labels(row.column, k)[0]
            bodies.append((self.shape, "shaft", x))
            if cap is not None:
                bodies.append((Shape(c, c, cap.height, 4), "capital", x))
        length = 0.5 * (row.block_extent(row.n_blocks - 1)[1] - row.block_extent(0)[0])  # the row's blocks as one
        bodies.append((Shape(length, length, row.block_height, 4, 0.5 * row.epistyle_width), "epistyle", 0.0))
        self.frame, self.labels = tuple(bodies), tuple(labels) + ("epistyle",)
        self.frame_top = row.abacus_top
        self.epistyle = np.stack([_filled(run["epistyle_dx"].values), _filled(run["epistyle_dz"].values)], axis=1)
        axes = row.axes()
        reach = max(c, self.shape.R)
        self.span = (axes[0] - reach, axes[-1] + reach)
        self.origin = np.array([axes[0], 0.0])  # every column's pivot moves alike: the path under the first
        self.height = row.abacus_top + row.block_height

    @property
    def bodies(self):
        """The function that places this run's bodies at a row: :func:`drum_bodies` (drums, a compliant
        colonnade), :func:`frame_bodies` (a rigid frame) or :func:`rigid_bodies` (a rigid column)."""
        return drum_bodies if self.drums else (frame_bodies if self.frame else rigid_bodies)

    def index(self, t):
        """Row of the histories at time ``t`` [s] (the last at or before it)."""
        return int(np.clip(np.searchsorted(self.time, t + 1e-9, side="right") - 1, 0, self.time.size - 1))

    @property
    def ended(self):
        """Whether the run ended before its record did (the column overturned)."""
        return self.overturn_row is not None

    def body_name(self, b):
        """How a caption names body ``b``: ``"the column"``, ``"drum 2"`` (from the bottom, from 1), ``"the
        capital"``, or its label in a colonnade (``"column 2 drum 1"``, ``"block 3"``)."""
        if self.labels:  # a numbered body by its label; one of its kind with an article ("the capital")
            label = self.labels[b]
            return label if any(ch.isdigit() for ch in label) else f"the {label}"
        if len(self.drums) <= 1 and not self.frame:
            return "the column"
        return "the capital" if self.drums[b].sides else f"drum {b + 1}"


def rigid_bodies(motion, i):
    """The bodies of a rigid column at row ``i``: one frustum at its Euler angles, moving with the ground."""
    rotation = euler_rotation(motion.phi[i], motion.theta[i], motion.psi[i])
    return [(motion.shape, Pose(motion.base[i] + motion.ground[i], rotation))]


def frame_bodies(motion, i):
    """The bodies of a rigid frame at row ``i``, moving with the ground: each column's shaft and capital turned
    by the frame's tilt about its pivot (its base centre where it stood plus ``x_b``, raised by R sin theta
    on its rim, as :func:`rigid_bodies` places a column), the epistyle translated by ``epistyle_dx`` and
    ``epistyle_dz`` from where it lay on the abacus tops. In a flight (``lift_off``) the columns stay drawn on
    the ground, as a rigid column is, and the epistyle at its computed height."""
    rotation = euler_rotation(motion.phi[i], motion.theta[i], 0.0)
    out = []
    for shape, what, x in motion.frame:
        if what == "epistyle":  # it translates, level, with the capitals' top edges
            dx, dz = motion.epistyle[i]
            out.append((shape, Pose(np.array([x + dx, 0.0, motion.frame_top + dz]) + motion.ground[i], np.eye(3))))
        elif what == "shaft":
            base = motion.base[i] + np.array([x, 0.0, 0.0]) + motion.ground[i]
            out.append((shape, Pose(base, rotation)))
        else:  # the capital on its shaft's top
            out.append((shape, Pose(out[-1][1].centre + rotation[:, 2] * motion.shape.h, rotation)))
    return out


def drum_bodies(motion, i):
    """The bodies of a column of drums at row ``i``, bottom first, moving with the ground.

    Each drum (and a capital) is placed by its own state: the Euler angles from its tilt
    ``drum_theta``, the direction of the tilt ``drum_phi`` and its rotation about the vertical
    ``drum_rotation`` (= phi + psi), and its centre of mass displaced by ``drum_dx``,
    ``drum_dy``, ``drum_dz`` from where it stood; the base centre lies ``z_cm`` below the
    centre of mass along the drum's axis.
    """
    out = []
    for b, shape in enumerate(motion.drums):
        rotation = euler_rotation(motion.drum_phi[i, b], motion.drum_theta[i, b], motion.drum_psi[i, b])
        base = motion.drum_centre[i, b] - rotation[:, 2] * shape.z_cm + motion.ground[i]
        out.append((shape, Pose(base, rotation)))
    return out


#: Seconds of animation a view's last computed state is shown after the last run in the animation ended [s].
HOLD = 2.0
#: A body whose lowest point is within this fraction of its base radius of the ground lies on it.
ON_THE_GROUND = 0.1


@dataclass(frozen=True)
class Frame:
    """What a view shows at one time.

    Attributes
    ----------
    row : int
        Row of the histories drawn (from the overturn on, the overturn's: the last computed state).
    bodies : tuple
        ``(index, Shape, Pose)`` of each body drawn; a body that fell and is not on the ground is left out.
    ended : bool
        The run has ended (the column overturned at or before this time): drawn greyed, still.
    caption : str
        What the view says of the end of the run ("" before it).
    """

    row: int
    bodies: tuple
    ended: bool
    caption: str


def lowest_point(shape, pose):
    """Height of the lowest point of a body [m] (a vertex of its drawn outline)."""
    faces, _ = frustum_faces(shape, pose)
    return float(min(face[:, 2].min() for face in faces[-2:]))  # the base and the top hold every vertex


def frame(motion, t, bodies=None):
    """What the view of ``motion`` shows at time ``t`` [s] (:class:`Frame`), before drawing it.

    Before the overturn, the bodies at the row of ``t``. From it on, the row of the overturn (the
    last computed state): the bodies below the one that fell first as computed; the bodies that fell
    only where they lie on the ground (lowest point within :data:`ON_THE_GROUND` of the base
    radius), the others left out; the caption says when the column fell, which bodies fell and
    that what followed is not computed.

    Parameters
    ----------
    motion : Motion
    t : float
        Time [s].
    bodies : callable, optional
        ``bodies(motion, i) -> list of (Shape, Pose)`` (default :attr:`Motion.bodies`).
    """
    if bodies is None:
        bodies = motion.bodies
    ended = motion.ended and t >= motion.overturn_time - 1e-9
    row = motion.overturn_row if ended else motion.index(t)
    drawn = [(b, shape, pose) for b, (shape, pose) in enumerate(bodies(motion, row))]
    if not ended:
        return Frame(row, tuple(drawn), False, "")
    if motion.row:  # a colonnade's bodies fall each on its own: those tilted past 60 deg or dropped
        fell = [item for item in drawn if _fallen(motion, row, item)]
    else:  # a column: the body that fell first and everything on it
        fell = [item for item in drawn if item[0] >= motion.fell_from]
    lying = [item for item in fell if abs(lowest_point(item[1], item[2])) <= ON_THE_GROUND * item[1].R]
    in_air = [b for b, _, _ in fell if b not in {b for b, _, _ in lying}]
    drawn = [item for item in drawn if item not in fell or item in lying]
    words = [f"Overturned at {motion.overturn_time:.2f} s: the run ends here; greyed: its last computed state"]
    if lying:
        verb = "lies" if len(lying) == 1 else "lie"
        words.append(f"{_names(motion, [b for b, _, _ in lying])} fell and {verb} on the ground as computed")
    if in_air:
        they = "it" if len(in_air) == 1 else "they"
        words.append(f"{_names(motion, in_air)} fell: not drawn, where {they} came to rest is not computed")
    return Frame(row, tuple(drawn), True, "\n".join(textwrap.fill(w, 80) for w in words))  # within a view


#: A colonnade's body has fallen when tilted past this [rad] or dropped by this part of its height.
FALLEN_TILT = math.radians(60.0)
FALLEN_DROP = 0.5


def _fallen(motion, row, item):
    """Whether a colonnade's body has fallen at ``row``: tilted past :data:`FALLEN_TILT` or dropped by
    :data:`FALLEN_DROP` of its height from where it stood (the last computed state of a run that ended)."""
    b, shape, _pose = item
    drop = -float(motion.run["drum_dz"].values[row, b]) if "drum_dz" in motion.run else 0.0
    return motion.drum_theta[row, b] > FALLEN_TILT or drop > FALLEN_DROP * shape.h


def _names(motion, indices):
    names = [motion.body_name(b) for b in indices]
    text = ", ".join(names[:-1]) + " and " + names[-1] if len(names) > 1 else names[0]
    return text[0].upper() + text[1:]


def _greyed(colours):
    """Face colours of the last computed state: their lightness kept, their colour gone, paler."""
    light = colours @ np.array([0.299, 0.587, 0.114])
    return np.repeat((0.45 + 0.45 * light)[:, None], 3, axis=1)


class ModelView:
    """The 3D view of one model: the plate, the bodies, the contact path, the acceleration arrow.

    Parameters
    ----------
    ax : mpl_toolkits.mplot3d.Axes3D
    motion : Motion
    bodies : callable, optional
        ``bodies(motion, i) -> list of (Shape, Pose)`` (default :attr:`Motion.bodies`).
    """

    def __init__(self, ax, motion, bodies=None):
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        if bodies is None:
            bodies = motion.bodies
        self.ax, self.motion, self.bodies = ax, motion, bodies
        shape = motion.shape
        reach = motion.height + shape.R
        ground = motion.ground[:, :2]
        centre = 0.5 * (ground.min(axis=0) + ground.max(axis=0))
        half = 0.5 * float(np.max(ground.max(axis=0) - ground.min(axis=0))) + 0.55 * reach
        row = 0.5 * (motion.span[1] - motion.span[0])  # a colonnade's half length along x
        centre[0] += 0.5 * (motion.span[0] + motion.span[1])
        half_x = max(half, row + 0.25 * reach)
        self.plate_half = 0.5 * reach
        self.plate_half_x = max(self.plate_half, row + 0.1 * reach)
        ax.set_xlim(centre[0] - half_x, centre[0] + half_x)
        ax.set_ylim(centre[1] - half, centre[1] + half)
        ax.set_zlim(0.0, 1.05 * reach)
        ax.set_box_aspect((2.0 * half_x, 2.0 * half, 1.05 * reach))  # one scale on every axis
        ax.set_axis_off()
        ax.view_init(elev=16, azim=-62)
        # draw in a fixed order (ground, path, arrow, bodies): mplot3d's sorting of whole collections by
        # their mean depth would put the large plate in front of the column
        ax.computed_zorder = False
        self.plate = Poly3DCollection([np.zeros((4, 3))], facecolors=[(0.80, 0.83, 0.78)], edgecolors="0.55",
                                      linewidths=0.5, zorder=0)
        ax.add_collection3d(self.plate)
        (self.path,) = ax.plot([], [], [], color="C0", lw=1.2, zorder=1)
        (self.arrow,) = ax.plot([], [], [], color="C3", lw=2.5, zorder=2)
        (self.head,) = ax.plot([], [], [], color="C3", marker="o", ms=5, ls="none", zorder=2)
        self.solids = []
        for _ in bodies(motion, 0):
            solid = Poly3DCollection([np.zeros((3, 3))], linewidths=0.0, zorder=3)
            ax.add_collection3d(solid)
            self.solids.append(solid)
        self.arrow_scale = 0.8 * self.plate_half / max(float(np.max(np.hypot(*motion.acc[:, :2].T))), 1e-9)
        self.title = ax.set_title("", fontsize=8)
        self.caption = ax.text2D(0.5, 0.01, "", transform=ax.transAxes, ha="center", va="bottom", fontsize=7,
                                 color="C3", wrap=False)

    def draw(self, t):
        """Move every artist to time ``t`` [s]."""
        m = self.motion
        now = frame(m, t, self.bodies)
        i = now.row  # from the overturn on, everything stays with the last computed state
        g = m.ground[i]
        h, hx = self.plate_half, self.plate_half_x
        corners = np.array([[-hx, -h, 0.0], [hx, -h, 0.0], [hx, h, 0.0], [-hx, h, 0.0]]) + [g[0], g[1], 0.0]
        self.plate.set_verts([corners])
        shown = {b: (shape, pose) for b, shape, pose in now.bodies}
        for b, solid in enumerate(self.solids):
            solid.set_visible(b in shown)
            if b in shown:
                faces, colours = frustum_faces(*shown[b])
                solid.set_verts(faces)
                solid.set_facecolor(_greyed(colours) if now.ended else colours)
        self.caption.set_text(now.caption)
        drawn = np.isfinite(m.contact[: i + 1, 0])
        if math.isfinite(m.overturn_time):  # the path ends with the fall
            drawn &= m.time[: i + 1] < m.overturn_time
        path = m.contact[: i + 1][drawn] + m.origin + g[:2]
        self.path.set_data_3d(path[:, 0], path[:, 1], np.zeros(len(path)))
        base = g[:2] + np.array([-0.55 * hx, -0.55 * h])  # from a corner of the plate, clear of the column
        tip = base + m.acc[i, :2] * self.arrow_scale
        self.arrow.set_data_3d([base[0], tip[0]], [base[1], tip[1]], [0.0, 0.0])
        self.head.set_data_3d([tip[0]], [tip[1]], [0.0])
        tilt = math.degrees(m.theta[i])
        state = f", overturned at {m.overturn_time:.2f} s" if now.ended else ""
        name = model_title(m.model)
        if m.drums or m.frame:
            name = f"{name}: {len(m.drums or m.frame)} bodies"
        accel = float(np.hypot(*m.acc[i, :2])) / 9.80665
        clock = m.overturn_time if now.ended else m.time[i]  # the clock stops with the run
        self.title.set_text(f"{name}\nt = {clock:5.2f} s   tilt θ = {tilt:5.2f}° "
                            f"(θ_crit {math.degrees(m.theta_crit):.1f}°){state}\n"
                            f"ground acceleration (red arrow) {accel:.2f} g")


#: Frames per second an animation may have: GIF stores a frame's delay in hundredths of a second.
FPS_RANGE = (0.1, 100.0)
#: Resolution [dots per inch] a frame may have: below 10 a view is a few pixels, above 600 a frame of
#: two views is 5760 x 3120 pixels.
DPI_RANGE = (10.0, 600.0)
#: Frames an animation may have (about half an hour of drawing at 0.1 s a frame).
MAX_FRAMES = 20000


def check_animation_options(fps, speed, dpi):
    """Refuse ``--fps``, ``--speed`` and ``--dpi`` outside what can be drawn, naming the option and the fix."""
    if not (math.isfinite(fps) and FPS_RANGE[0] <= fps <= FPS_RANGE[1]):
        raise InputError(f"--fps {fps:g}: give frames per second between {FPS_RANGE[0]:g} and {FPS_RANGE[1]:g} "
                         "(GIF keeps a frame at least a hundredth of a second), e.g. 10")
    if not (math.isfinite(speed) and speed > 0):
        raise InputError(f"--speed {speed:g}: give the seconds of motion per second of animation as a positive "
                         "number, e.g. 1 (real time) or 0.5 (half speed)")
    if not (math.isfinite(dpi) and DPI_RANGE[0] <= dpi <= DPI_RANGE[1]):
        raise InputError(f"--dpi {dpi:g}: give a resolution between {DPI_RANGE[0]:g} and {DPI_RANGE[1]:g} dots per "
                         "inch, e.g. 80")


def frame_times(time, fps, speed=1.0, end=None):
    """Times [s] of the frames: every ``speed / fps`` seconds of motion from the first row to ``end``.

    With ``speed`` 1 the animation plays in real time. ``end`` [s]: the last time drawn (default
    the last row's). More than :data:`MAX_FRAMES` frames are refused before any is drawn.
    """
    if not (fps > 0 and speed > 0):
        raise InputError(f"--fps {fps} and --speed {speed} must be positive numbers")
    step = speed / fps
    span = float(min(time[-1], time[-1] if end is None else end) - time[0])
    n = span / step + 1e-9
    if not n < MAX_FRAMES:
        raise InputError(f"--fps {fps:g} and --speed {speed:g}: {span:g} s of motion would take {n:.3g} frames "
                         f"(at most {MAX_FRAMES}); lower --fps or raise --speed")
    return time[0] + step * np.arange(int(math.floor(n)) + 1)


def check_animation_path(path, option="--out", inputs=(), kind=MARKED):
    """The suffix of ``path`` (``.gif`` or ``.mp4``) if it can be written here; else an InputError saying why.

    ``inputs`` ([(what, path)]) are files the command reads, which ``path`` may not name; an
    existing file there is replaced only if this project wrote it (``kind``, see
    :func:`pipeline.paths.check_output_file`: every animation carries the project's mark,
    :func:`_writer`).
    """
    from pipeline.paths import check_output_file

    suffix = os.path.splitext(os.fspath(path))[1].lower()
    if suffix not in (".gif", ".mp4"):
        raise InputError(f"{option} {path}: give a file name ending in .gif or .mp4")
    if suffix == ".mp4":
        try:
            import imageio_ffmpeg  # noqa: F401
        except ImportError:
            raise InputError(f"{option} {path}: MP4 needs the ffmpeg of imageio-ffmpeg (pip install -e '.[video]'); "
                             "or write a .gif") from None
    check_output_file(path, option, kind=kind, inputs=inputs)
    return suffix


def _writer(path, fps):
    """A matplotlib movie writer for the suffix of ``path``: .gif (Pillow) or .mp4 (ffmpeg of imageio-ffmpeg).

    Both mark the file as this project's (:func:`pipeline.paths.mark_text`): the GIF in a
    comment extension, the MP4 in its ``comment`` metadata (in the ``moov`` box at the end).
    """
    from matplotlib import animation

    from pipeline.paths import mark_text

    if check_animation_path(path, kind=None) == ".gif":  # the file was checked by the command

        class MarkedPillowWriter(animation.PillowWriter):
            def finish(self):  # matplotlib's finish, with the comment Pillow writes into a GIF
                self._frames[0].save(self.outfile, save_all=True, append_images=self._frames[1:],
                                     duration=int(1000 / self.fps), loop=0, comment=mark_text())

        return MarkedPillowWriter(fps=fps)
    import imageio_ffmpeg
    import matplotlib

    matplotlib.rcParams["animation.ffmpeg_path"] = imageio_ffmpeg.get_ffmpeg_exe()
    return animation.FFMpegWriter(fps=fps, codec="libx264", extra_args=["-pix_fmt", "yuv420p"],
                                  metadata={"comment": mark_text()})


def _figure(runs, dpi):
    """(figure, views): one 3D view per run, side by side."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    motions = [Motion(run) for run in runs]
    fig = plt.figure(figsize=(4.8 * len(motions), 5.2), dpi=dpi)
    fig.subplots_adjust(left=0.0, right=1.0, bottom=0.0, top=0.86, wspace=0.0)
    views = [ModelView(fig.add_subplot(1, len(motions), k + 1, projection="3d"), m) for k, m in enumerate(motions)]
    record = runs[0].attrs.get("record_id", "")
    what = "the colonnade" if any(m.row or m.frame for m in motions) else "the column"
    fig.suptitle(f"{record}: {what} moving with the ground" if record and record != "free-motion"
                 else f"free motion of {what}", fontsize=10)
    return fig, views


def _end_time(motions, speed):
    """The last time drawn [s]: :data:`HOLD` seconds of animation after the last run ended (its record's end
    if one of them did not overturn): nothing is left to see but still pictures."""
    ends = [min(m.overturn_time + HOLD * speed, m.time[-1]) if m.ended else m.time[-1] for m in motions]
    return max(ends)


def render_frame(runs, t, dpi=80):
    """One frame of :func:`animate` at time ``t`` [s], as an RGB array (height, width, 3) of uint8."""
    import matplotlib.pyplot as plt

    fig, views = _figure(runs, dpi)
    try:
        for view in views:
            view.draw(t)
        fig.canvas.draw()
        return np.asarray(fig.canvas.buffer_rgba())[..., :3].copy()
    finally:
        plt.close(fig)


def animate(runs, path, fps=10.0, speed=1.0, dpi=80, progress=None):
    """Write an animation of one or more runs side by side (one 3D view each).

    A run that overturned is shown still and greyed from the overturn on (:func:`frame`); the
    animation ends :data:`HOLD` seconds after the last run ended.

    Parameters
    ----------
    runs : list of xarray.Dataset
        One simulation each (histories over ``time`` alone, same time grid);
        :func:`pipeline.dataset.one_run`.
    path : str or os.PathLike
        ``.gif`` or ``.mp4``; written under a temporary name, then renamed.
    fps : float
        Frames per second of the animation [1/s].
    speed : float
        Seconds of motion per second of animation [1]: 1 is real time.
    dpi : float
        Resolution [dots per inch]; each view is 4.8 x 5.2 inches.
    progress : callable, optional
        Called with (frame, n_frames) after each frame.

    Returns
    -------
    int
        Number of frames written.
    """
    import matplotlib.pyplot as plt

    path = os.fspath(path)
    check_animation_options(fps, speed, dpi)
    writer = _writer(path, fps)
    fig, views = _figure(runs, dpi)
    try:
        times = frame_times(views[0].motion.time, fps, speed, end=_end_time([v.motion for v in views], speed))
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        with atomic_path(path) as tmp, writer.saving(fig, tmp, dpi):  # the temporary name keeps the suffix
            for k, t in enumerate(times):
                for view in views:
                    view.draw(t)
                writer.grab_frame()
                if progress is not None:
                    progress(k + 1, len(times))
    finally:
        plt.close(fig)
    return len(times)


def animate_file(path, out, fps=10.0, speed=1.0, models=None, dpi=80):
    """Animate a histories file of ``frustum simulate`` (:func:`animate`); every model in it side by side.

    Parameters
    ----------
    path : str
        netCDF written by ``frustum simulate``.
    out : str
        ``.gif`` or ``.mp4``.
    models : list of str, optional
        Models to draw (default: all in the file).

    Returns
    -------
    int
        Number of frames.
    """
    from pipeline.dataset import one_run, open_results

    check_animation_options(fps, speed, dpi)
    check_animation_path(out, inputs=[("results file", path)])
    if not os.path.exists(path):
        raise InputError(f"{path}: no such file; give the netCDF written by 'frustum simulate'")
    try:
        ds = open_results(path)
    except (OSError, ValueError, RuntimeError) as exc:  # truncated, not netCDF, unreadable
        raise InputError(f"{path}: cannot be read as netCDF ({' '.join(str(exc).split())}); give the complete file "
                         "'frustum simulate' wrote (run it again if it was cut short)") from None
    missing = [name for name in ("time", "theta", "phi", "x_p", "y_p", "column_R") if name not in ds.variables]
    if missing or "model" not in ds.dims:
        raise InputError(f"{path}: not a histories file of 'frustum simulate' (missing {', '.join(missing) or 'model'})")
    if "drum" in ds.dims and "drum_dz" not in ds.variables:
        raise InputError(f"{path}: a column of drums written before the drums' poses were kept (drum_dz, "
                         "drum_phi); run 'frustum simulate' again to animate it")
    available = [str(m) for m in ds["model"].values]
    models = models or available
    unknown = [m for m in models if m not in available]
    if unknown:
        raise InputError(f"{path}: model(s) {', '.join(unknown)} not in the file; it has {', '.join(available)}")
    runs = [one_run(ds, model=m) for m in models]
    return animate(runs, out, fps=fps, speed=speed, dpi=dpi)


__all__ = ["check_animation_path", "check_animation_options", "MAX_FRAMES", "render_frame", "Shape", "Pose", "euler_rotation", "frustum_faces", "rigid_bodies",
           "drum_bodies", "frame_bodies", "Motion", "ModelView", "Frame", "frame", "lowest_point", "HOLD",
           "frame_times", "animate", "animate_file"]
