"""The rigid bodies and joints of a structure, as geometry in SI units: what the compliant model runs.

A structure (:mod:`pipeline.structures`) becomes a list of :class:`Part` (drums, capitals,
epistyle blocks: mass, principal inertia, pose at rest) and a list of :class:`Contact` (a face
of a lower body or of the ground, of any orientation, and the contact points of the upper
body on it), plus the bodies whose tilt is the run's peak theta (each column's top) and the
order in which the fixed-step integrator's solve eliminates the bodies. No joint law here:
:mod:`pipeline.compliant.tables` turns these into the kernel's dimensionless tables with the
settings' stiffnesses, friction and damping.

The bodies' axes are principal and a drum's or a capital's axis is z; a block's x runs along
the row. At rest (before the joints are pressed) every body stands on the face below it with
its bearing face on that face: the static solve (:mod:`pipeline.compliant.rest`) then presses
the joints in.

Imperfect drums (``settings.imperfect``, :mod:`pipeline.structures.imperfections`): each body of a
column stands off the one below by its joint's drawn offset, on a bed plane that leans by its
joint's drawn tilt through the centre of the lower body's top face (the ground's plane through
the column's axis for the base); the bodies stay upright, so the two faces of a joint share the
lean: the lower face's axes and the upper body's bearing face are the same tilted frame
(:func:`face_axes`), and the upper body's bearing face centre (on its axis) lies on the plane, a
hair above or below the perfect height (the offset along the lean). The layout keeps the draw
(:attr:`Layout.imperfections`).
"""

import math
from dataclasses import dataclass

import numpy as np

from pipeline.dynamics.compliant import joint as jl
from pipeline.dynamics.compliant.layout import GROUND, SHAPE_DISC
from pipeline.errors import InputError
from pipeline.structures.column import Column
from pipeline.structures.description import column_labels
from pipeline.structures.drums import DrumColumn
from pipeline.structures.imperfections import draw

__all__ = ["Part", "Contact", "Layout", "as_stack", "stack_layout", "lying_tilt", "face_axes", "drawn"]

# Drawing codes of a body's shape (pipeline.dataset's drum_kind).
KIND_DRUM, KIND_CAPITAL, KIND_BLOCK = 0, 1, 2
IDENTITY = np.eye(3)
# a vertical face whose normal is +x of its body: its x along the body's y, its y along z
END_FACE = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])


@dataclass(frozen=True)
class Part:
    """One rigid body of a structure [SI].

    Attributes
    ----------
    label : str
        What it is, for people (:mod:`pipeline.structures.description`): ``"drum 2"``, ``"capital"``,
        ``"column 3 drum 1"``, ``"epistyle block 2"``.
    kind : int
        ``KIND_DRUM``, ``KIND_CAPITAL`` or ``KIND_BLOCK``.
    mass : float
        [kg].
    inertia : tuple of float
        Principal moments about the centre of mass, (I_x, I_y, I_z) [kg m^2].
    centre : tuple of float
        Centre of mass at rest (x, y, z) [m].
    zc : float
        Height of the centre of mass above the body's base [m].
    height : float
        [m].
    lie : float
        Tilt at which it lies on its side [rad].
    on_ground : bool
        It stands on the ground (it cannot fall off a support).
    shape : tuple of float
        For drawing: (R, r, h) of a drum, (half side, half side, h) of a capital,
        (half length, half width, h) of a block [m].
    column : int
        The column it belongs to (-1: an epistyle block).
    """

    label: str
    kind: int
    mass: float
    inertia: tuple
    centre: tuple
    zc: float
    height: float
    lie: float
    on_ground: bool
    shape: tuple
    column: int = 0


@dataclass(frozen=True)
class Contact:
    """One joint of a structure [SI].

    Attributes
    ----------
    kind : str
        ``"base"`` (a column on the ground), ``"bed"`` (drum on drum), ``"capital"`` (capital on
        the shaft), ``"bearing"`` (an epistyle block on a capital), ``"head"`` (block on block,
        end to end).
    lower, upper : int
        The bodies (lower -1: the ground).
    origin : tuple of float
        The face's centre in the lower body's axes, from its centre of mass (the ground's:
        absolute) [m].
    axes : numpy.ndarray
        (3, 3): the face's x, y and normal (towards the upper body) as columns, in the lower
        body's axes.
    upper_centre : tuple of float
        The upper body's bearing face centre in its axes [m].
    upper_axes : numpy.ndarray
        (3, 3): that face's axes in the upper body's axes (equal to ``axes`` seen from the
        ground when the joint is closed and undisturbed).
    shape : int
        ``SHAPE_DISC`` (radius ``half[0]``) or ``SHAPE_RECT`` (half sides ``half``).
    half : tuple of float
        [m].
    points : numpy.ndarray
        (n, 6): each contact point in the upper body's axes (x, y, z), on its bearing face
        (u, v) [m], and its area [m^2].
    load : float
        The mass the joint carries at rest [kg] (the upper body's own for a head joint, which
        carries nothing): the time and length scales of its law.
    column : int
        The column it belongs to (-1: the epistyle's).
    rim : bool
        A disc on which a column rocks: its uplift and landings are counted.
    label : str
        What it is, for people (:mod:`pipeline.structures.description`): ``"base of column 2"``,
        ``"bed joint under drum 3"``, ``"capital 2 / epistyle block 1"``, ``"head joint blocks 1-2"``.
    """

    kind: str
    lower: int
    upper: int
    origin: tuple
    axes: np.ndarray
    upper_centre: tuple
    upper_axes: np.ndarray
    shape: int
    half: tuple
    points: np.ndarray
    load: float
    column: int = 0
    rim: bool = True
    label: str = ""


@dataclass(frozen=True)
class Layout:
    """A structure's bodies and joints, the watched bodies and the elimination order."""

    parts: tuple
    contacts: tuple
    watched: tuple
    order: tuple
    length: float  # the reference length L [m]: the first column's base radius
    # the imperfections drawn for it (pipeline.structures.imperfections.JointDraw: its first joints,
    # the columns' in their order), or None: perfect drums
    imperfections: object = None

    @property
    def n_bodies(self):
        return len(self.parts)


def lying_tilt(R, r, h):
    """Tilt at which the side of a frustum (R, r, h) touches the ground [rad].

    Pivoting on its rim, the generator through the pivot leans inwards by atan((R - r)/h)
    when upright, so it reaches the ground at ``pi/2 + atan((R - r)/h)`` (91.43 deg for
    R = 0.5, r = 0.4, h = 4 m; 90 deg for a cylinder or a block).
    """
    return 0.5 * math.pi + math.atan((R - r) / h)


def as_stack(column):
    """A :class:`DrumColumn` from a Column (the monolith) or a DrumColumn."""
    if isinstance(column, DrumColumn):
        return column
    if isinstance(column, Column):
        return DrumColumn(column)
    raise InputError(f"column must be a Column or a DrumColumn, got {type(column).__name__}")


def disc_points(radius, inner_ratio, settings, height, axes=None):
    """Contact points of a disc (or annulus) whose centre is ``height`` below the body's centre, in the
    plane of ``axes`` (its x, y and normal as columns, in the body's axes; None: level): (n, 6) rows."""
    pts = jl.contact_points(radius, inner_ratio * radius, settings.contact_rings, settings.contact_sectors)
    rows = np.zeros((len(pts), 6))
    rows[:, 0], rows[:, 1], rows[:, 2] = pts[:, 0], pts[:, 1], -height
    if axes is not None:  # the face leans: each point at its (u, v) in the face's plane
        rows[:, :3] = pts[:, :2] @ np.asarray(axes)[:, :2].T
        rows[:, 2] -= height
    rows[:, 3], rows[:, 4], rows[:, 5] = pts[:, 0], pts[:, 1], pts[:, 2]
    return rows


def face_axes(normal):
    """The axes of a face whose unit normal is ``normal`` (x, y, z) [1], as columns (x, y, normal): the
    level axes turned by the least rotation that takes the vertical to the normal (no twist about
    it), exactly the identity for a level face."""
    a, b, c = normal
    k = 1.0 / (1.0 + c)
    return np.array([[1.0 - a * a * k, -a * b * k, a], [-a * b * k, 1.0 - b * b * k, b], [-a, -b, c]])


def drawn(structure, settings):
    """The imperfections ``settings`` draw for ``structure``
    (:class:`pipeline.structures.imperfections.JointDraw`), or None for perfect drums."""
    imperfect = getattr(settings, "imperfect", None)
    return None if imperfect is None else draw(imperfect, structure)


def _places(heights, x0, beds, first):
    """Where each body of a column stands at rest: ``(axis x, axis y, height of its bed's centre)`` [m],
    bottom up; with ``beds`` (a :class:`JointDraw`, the column's joints from row ``first``) each body
    off the one below by its joint's offset, its bed's centre on the leaning plane."""
    axis_x, axis_y, bottom = x0, 0.0, 0.0
    places = []
    for k, _ in enumerate(heights):
        if k > 0:
            bottom += heights[k - 1]
            if beds is not None:
                ex, ey = float(beds.offset_x[first + k]), float(beds.offset_y[first + k])
                axis_x, axis_y = axis_x + ex, axis_y + ey
                # the plane through the lower top's centre with normal (s_x, s_y, 1): z falls by s . e
                bottom -= float(beds.slope_x[first + k]) * ex + float(beds.slope_y[first + k]) * ey
        places.append((axis_x, axis_y, bottom))
    return places


def rectangle_nodes(settings):
    """Gauss-Lobatto nodes along each side of a rectangular face: a quarter of the disc's sectors
    (its points' count within a few), at least 3 (the second moment exact)."""
    return max(3, settings.contact_sectors // 4)


def column_layout(stack, x0, first, column, settings, row=False, carried=0.0, columns=1, beds=None):
    """The bodies and joints of one column of drums (and its capital) whose axis stands at (x0, 0).

    Parameters
    ----------
    stack : DrumColumn
    x0 : float
        Position of its axis along the row [m].
    first : int
        Index of its bottom drum among the structure's bodies.
    column : int
        Its index among the structure's columns.
    settings : pipeline.settings.ModelSettings
        Contact points and anathyrosis.
    row : bool
        It stands in a colonnade: its labels name its column ("column 2 drum 1").
    carried : float
        Mass resting on its capital (its share of an epistyle) [kg]: every joint of the column
        carries it too.
    columns : int
        Columns of the structure it stands in (a per-joint list is one column's: :func:`per_joint`).
    beds : pipeline.structures.imperfections.JointDraw, optional
        The structure's imperfections: this column's joints are its rows ``column * n`` onward
        (n the column's bodies); None: perfect drums.

    Returns
    -------
    tuple of list
        ``(parts, contacts)``.
    """
    density = stack.density
    drums = stack.drums()
    n = stack.n_bodies
    inner = [settings.base_anathyrosis] + per_joint(settings.anathyrosis, n - 1, "anathyrosis", 0.0, columns)
    parts, contacts = [], []
    labels, joint_labels = column_labels(stack, column if row else None)
    first_joint = column * n  # this column's first joint in the draw
    places = _places([d.h for d in drums] + ([stack.capital.height] if stack.capital is not None else []), x0, beds,
                     first_joint)
    for k, d in enumerate(drums):
        m = density * d.volume
        a, c = d.central_inertia_hat
        it, ia = a * m * d.R ** 2, c * m * d.R ** 2
        px, py, bottom = places[k]
        parts.append(Part(labels[k], KIND_DRUM, m, (it, it, ia), (px, py, bottom + d.z_cm), d.z_cm, d.h,
                          lying_tilt(d.R, d.r, d.h), k == 0, (d.R, d.r, d.h), column))
    if stack.capital is not None:
        cap = stack.capital
        it, ia = cap.inertia(density)
        half = 0.5 * cap.side
        px, py, bottom = places[-1]
        parts.append(Part(labels[-1], KIND_CAPITAL, cap.mass(density), (it, it, ia),
                          (px, py, bottom + 0.5 * cap.height), 0.5 * cap.height, cap.height, 0.5 * math.pi,
                          False, (half, half, cap.height), column))
    above = np.cumsum([p.mass for p in parts][::-1])[::-1] + carried
    for k, part in enumerate(parts):
        radius = drums[0].R if k == 0 else drums[k - 1].r  # the face below: the ground's base, a drum's top
        axes = IDENTITY if beds is None else face_axes(beds.normal(first_joint + k))
        points = disc_points(radius, inner[k], settings, part.zc, None if beds is None else axes)
        if k == 0:
            lower, origin, kind = GROUND, (x0, 0.0, 0.0), "base"
        else:
            below = parts[k - 1]
            lower, origin = first + k - 1, (0.0, 0.0, below.height - below.zc)
            kind = "capital" if part.kind == KIND_CAPITAL else "bed"
        contacts.append(Contact(kind, lower, first + k, origin, axes, (0.0, 0.0, -part.zc), axes,
                                SHAPE_DISC, (math.inf if k == 0 else radius, 0.0), points, float(above[k]),
                                column, True, joint_labels[k]))
    return parts, contacts


def per_joint(value, n, name, default, columns=1):
    """One value per bed joint (n of them) from None, a number or a sequence.

    The one rule of the options given per bed joint (``joint_friction``, ``anathyrosis``): a
    sequence gives one value per bed joint of a single column, bottom first; a colonnade
    (``columns`` > 1) takes one number for all its joints, every column alike.
    """
    if value is None:
        return [default] * n
    if isinstance(value, (int, float)):
        return [float(value)] * n
    if columns > 1:
        raise InputError(f"{name}: a list gives one value per bed joint of a single column; a colonnade of "
                         f"{columns} columns takes one number for all its joints: give one {name}, or run its "
                         "column alone")
    values = [float(v) for v in value]
    if len(values) != n:
        raise InputError(f"{name} has {len(values)} values for {n} bed joint(s): give one number, or one per joint")
    return values


def stack_layout(column, settings):
    """A monolith or a column of drums (and a capital) on the ground, its axis at the origin."""
    stack = as_stack(column)
    beds = drawn(stack, settings)
    parts, contacts = column_layout(stack, 0.0, 0, 0, settings, beds=beds)
    n = len(parts)
    return Layout(tuple(parts), tuple(contacts), (n - 1,), tuple(range(n)), stack.column.R, beds)
