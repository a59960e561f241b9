"""Colonnades: columns in a straight row carrying an epistyle of blocks, and the rigid frame they make.

A :class:`Colonnade` is ``N`` identical columns (each a :class:`pipeline.structures.drums.DrumColumn`
with its capital, or without one) whose axes stand in a row along the x axis at the interaxial
spacing ``S``, and an epistyle (architrave) of ``N - 1`` blocks laid from axis to axis: block
``k`` spans from the axis of column ``k`` to that of column ``k + 1``, the first from the outer
edge of capital 0 and the last to the outer edge of capital ``N - 1``, so that a row of 2 has one
block over both capitals (real architraves are laid so: their joints fall on the column axes, and
the corner block runs to the outer face). Optionally a course above the epistyle (frieze and
cornice), given as a height of the epistyle's width and density, rides on each block as mass.

Frame of reference (every length in metres): x along the row, y across it, z up from the
ground; the row is centred on x = 0 (column ``k``'s axis at ``(k - (N - 1)/2) S``). The abacus
top, on which the blocks bear, is at height ``H_t`` (the shaft's height plus the capital's).

Derived quantities that the rigid frame (``2d-frame``, :func:`frame_block`) and a 3D assembly
of bodies both need are pure functions or properties here: the axes, each block's extent, mass,
centre and central inertia, the bearing rectangle of a block on each capital (in that capital's
frame), the head joints between neighbouring blocks, the masses, and the frame's equivalent
rocking block (docs/model.md, "The rigid planar frame").

Nothing here imports a model or a kernel.
"""

import math
import tomllib
from dataclasses import dataclass
from importlib import resources
from typing import NamedTuple

from pipeline.errors import InputError
from pipeline.structures.column import Column
from pipeline.structures.drums import DrumColumn, named_drum_column
from pipeline.units import G

__all__ = ["Colonnade", "RigidColumn", "FrameBlock", "Bearing", "HeadJoint", "rigid_column", "frame_block",
           "named_colonnade", "named_colonnades", "MAX_COLUMNS", "MAX_INTERAXIAL", "MAX_INTERAXIAL_DIAMETERS",
           "MAX_SPAN_DEPTH", "MAX_EPISTYLE_FRACTION", "EPISTYLE_WIDTH_RANGE"]

#: The longest row accepted (the Parthenon's flanks have 17 columns).
MAX_COLUMNS = 64

# Plausibility limits of a colonnade of stone (Colonnade.__post_init__, _check_plausible): wide margins around
# what was built, so that a slip of a digit is refused while every real colonnade passes.
#: The widest interaxial spacing in base diameters [1]: a clear intercolumniation of 4 diameters, the araeostyle,
#: which no stone architrave spans (Vitruvius, De architectura 3.3.4-5: stone architraves already break at 3
#: diameters, the diastyle; the araeostyle takes timber beams; its 4 diameters as in Rich 1849, "Diastylos").
MAX_INTERAXIAL_DIAMETERS = 5.0
#: The widest interaxial spacing [m]: the widest span quoted for a Greek stone architrave is the central span
#: of the Artemision's west front at Ephesus, 8.75 m axis to axis (Lethaby 1908, Greek Buildings Represented by
#: Fragments in the British Museum, p. 27, after the Austrian survey: "these spans are immense").
MAX_INTERAXIAL = 10.0
#: The longest span over the epistyle's depth [1]: the Parthenon's architrave spans 3.2 times its depth (4.3 m
#: over 1.35 m), the Artemision's 7.5 (8.75 m over 1.17 m, Lethaby 1908, p. 21: "3 ft 10 deep").
MAX_SPAN_DEPTH = 10.0
#: The highest epistyle over the columns' height to the abacus top [1]: the Parthenon's is about an eighth of
#: it (1.35 m on 10.43 m), Vitruvius's Doric one a fourteenth (one module on 14, De architectura 4.3).
MAX_EPISTYLE_FRACTION = 0.5
#: The epistyle's width over the abacus side [1]: the architrave as wide as the abacus, or as the shaft's
#: upper diameter (0.74 of the Parthenon's abacus, the Doric rule of colonnades.toml's source), overhanging it
#: by a few inches at Ephesus (Lethaby 1908, p. 21); narrower than half, the blocks would stand on a strip of
#: their capitals, wider than twice, overhang them by more than the abacus on each side.
EPISTYLE_WIDTH_RANGE = (0.5, 2.0)


class RigidColumn(NamedTuple):
    """A column with its capital as one rigid body, in the vertical plane of the row.

    Attributes
    ----------
    mass : float
        Mass of the shaft and the capital [kg].
    z_c : float
        Height of their centre of mass above the base [m].
    inertia_pivot : float
        Moment of inertia about a rim point of the base, about the horizontal axis across the
        row (y) [kg m^2]: the ``I_P`` of rocking in the row's plane.
    inertia_central : float
        The same about the centre of mass [kg m^2].
    """

    mass: float
    z_c: float
    inertia_pivot: float
    inertia_central: float


class FrameBlock(NamedTuple):
    """The rigid planar frame of a colonnade as one rocking block (docs/model.md, "The rigid planar frame").

    The columns rock in unison about the base rims on one side (pivot at ``+R`` of every axis
    when leaning towards +x); the epistyle rests on the capitals' top edges opposite the pivots
    (at horizontal distance ``R + c`` from the pivot, height ``H_t``) and translates with them.
    Potential and kinetic energy are those of one block whose centre of mass lies at
    ``(b_e, z_e)`` from its pivot, of mass ``m_tot`` and inertia ``I_e`` about the pivot.

    Attributes
    ----------
    n : int
        Number of columns.
    m, z_c, I_P : float
        One column's mass [kg], centre height [m] and inertia about a base rim point [kg m^2],
        with its capital.
    M : float
        Mass of the epistyle with its course [kg].
    R, c, H_t : float
        Base radius, half the abacus side (r without capital) and the abacus top's height [m].
    m_tot : float
        ``N m + M`` [kg].
    b_e, z_e : float
        Horizontal and vertical lever of the equivalent block's centre of mass from its pivot
        [m]: ``(N m R + M (R + c)) / m_tot`` and ``(N m z_c + M H_t) / m_tot``.
    L_t : float
        Pivot to bearing edge, ``hypot(R + c, H_t)`` [m].
    I_e : float
        ``N I_P + M L_t^2`` [kg m^2].
    """

    n: int
    m: float
    z_c: float
    I_P: float
    M: float
    R: float
    c: float
    H_t: float
    m_tot: float
    b_e: float
    z_e: float
    L_t: float
    I_e: float

    @property
    def alpha(self):
        """Slenderness angle of the equivalent block, ``atan(b_e / z_e)`` [rad]: its critical tilt."""
        return math.atan2(self.b_e, self.z_e)

    @property
    def lever(self):
        """Pivot to the equivalent centre of mass, ``L_e = hypot(b_e, z_e)`` [m]."""
        return math.hypot(self.b_e, self.z_e)

    @property
    def frequency_parameter(self):
        """``p_e = sqrt(m_tot g L_e / I_e)`` [rad/s]."""
        return math.sqrt(self.m_tot * G * self.lever / self.I_e)

    @property
    def uplift_acceleration(self):
        """Horizontal ground acceleration that tips the frame off its full bases, ``g tan(alpha_e)`` [m/s^2]."""
        return G * self.b_e / self.z_e

    @property
    def restitution(self):
        """theta' after / before a landing, from angular momentum about the new pivots with the epistyle's
        impulse at the new top edge: ``1 - 2 (N m R^2 + M (R + c)^2) / I_e`` [1] (may be negative for
        squat frames; a run clips it at 0)."""
        return 1.0 - 2.0 * (self.n * self.m * self.R**2 + self.M * (self.R + self.c) ** 2) / self.I_e

    def kernel_constants(self):
        """``(Iy, zc, A)``: the planar kernel's dimensionless constants, lengths per ``b_e``, masses per ``m_tot``.

        ``Iy = I_e / (m_tot b_e^2)``, ``zc = z_e / b_e`` and the central inertia
        ``A = Iy - 1 - zc^2`` (:mod:`pipeline.dynamics.rigid.rocking`).
        """
        iy = self.I_e / (self.m_tot * self.b_e**2)
        zc = self.z_e / self.b_e
        return iy, zc, iy - 1.0 - zc * zc


class Bearing(NamedTuple):
    """Where an epistyle block bears on a capital: a rectangle in the capital's frame.

    The capital's frame has its origin on the column's axis at the abacus top, x along the row,
    y across. Without a capital the block bears on the shaft's top disc: the face is then the
    part of the disc (radius ``c``) inside the rectangle (``on_disc``).

    Attributes
    ----------
    block, column : int
        The block and the column (capital) it rests on.
    x0, x1, y0, y1 : float
        The rectangle [m].
    on_disc : bool
        True without a capital (the face is the disc's part inside the rectangle).
    """

    block: int
    column: int
    x0: float
    x1: float
    y0: float
    y1: float
    on_disc: bool

    @property
    def area(self):
        """Area of the rectangle [m^2] (of the bounding rectangle when ``on_disc``)."""
        return (self.x1 - self.x0) * (self.y1 - self.y0)


class HeadJoint(NamedTuple):
    """The joint between the end faces of two neighbouring blocks, over an inner column's axis.

    Its face is vertical with a horizontal normal ``(1, 0, 0)`` (from ``left`` into ``right``),
    in the row's frame: the plane ``x``, the rectangle ``y0..y1`` by ``z0..z1``.

    Attributes
    ----------
    left, right : int
        The blocks on either side (``right = left + 1``).
    column : int
        The column under the joint.
    x, y0, y1, z0, z1 : float
        [m]
    """

    left: int
    right: int
    column: int
    x: float
    y0: float
    y1: float
    z0: float
    z1: float

    @property
    def normal(self):
        """Unit normal of the face, from the left block into the right one."""
        return (1.0, 0.0, 0.0)


def _positive(name, value, unit="m"):
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise InputError(f"colonnade {name} = {value!r} is not a number; give it in {unit}") from None
    if not (math.isfinite(value) and value > 0.0):
        raise InputError(f"colonnade {name} = {value!r} {unit} must be a positive finite number in {unit}")
    return value


def rigid_column(stack):
    """A column (drums and capital) as one rigid body: :class:`RigidColumn` [kg, m, kg m^2].

    The shaft is the frustum of its outline at the column's density, whatever its drums; the
    capital (if any) the square block on top, at the same density.
    """
    if isinstance(stack, Column):
        stack = DrumColumn(stack)
    rho = stack.density
    shaft = Column(stack.column.R, stack.column.r, stack.column.h, density=rho)
    m_s, z_s = shaft.mass, shaft.z_cm
    i_s = shaft.inertia_transverse_hat * m_s * shaft.R**2  # about a rim point
    cap = stack.capital
    if cap is None:
        return RigidColumn(m_s, z_s, i_s, i_s - m_s * (shaft.R**2 + z_s**2))
    m_k = cap.mass(rho)
    z_k = shaft.h + 0.5 * cap.height
    i_k = cap.inertia(rho)[0] + m_k * (shaft.R**2 + z_k**2)  # transverse, parallel axes to the rim point
    m = m_s + m_k
    z_c = (m_s * z_s + m_k * z_k) / m
    i_p = i_s + i_k
    return RigidColumn(m, z_c, i_p, i_p - m * (shaft.R**2 + z_c**2))


def frame_block(n, column, epistyle_mass, R, c, H_t):
    """The rigid planar frame as one rocking block (:class:`FrameBlock`), from its parts.

    Parameters
    ----------
    n : int
        Number of columns.
    column : RigidColumn
        One column with its capital.
    epistyle_mass : float
        Mass of the whole epistyle with its course [kg] (0: the columns alone, each rocking as
        the `2d` model's body).
    R : float
        Base radius of a column [m].
    c : float
        Half the abacus side, or the shaft's top radius r without capital [m].
    H_t : float
        Height of the abacus top (the bearing edges) above the ground [m].
    """
    m, z_c, i_p = column.mass, column.z_c, column.inertia_pivot
    M = float(epistyle_mass)
    m_tot = n * m + M
    b_e = (n * m * R + M * (R + c)) / m_tot
    z_e = (n * m * z_c + M * H_t) / m_tot
    l_t = math.hypot(R + c, H_t)
    return FrameBlock(n, m, z_c, i_p, M, R, c, H_t, m_tot, b_e, z_e, l_t, n * i_p + M * l_t**2)


@dataclass(frozen=True)
class Colonnade:
    """A row of identical columns carrying an epistyle of blocks laid from axis to axis.

    Parameters
    ----------
    column : pipeline.structures.drums.DrumColumn or pipeline.structures.column.Column
        Every column of the row: its outline, drums, capital and density (a plain
        :class:`Column` is the monolith without capital).
    n_columns : int
        Number of columns, at least 2.
    interaxial : float
        Spacing of the column axes, S [m]: at least the abacus side (or the base diameter, if
        larger), so that neighbouring capitals and bases do not overlap.
    epistyle_height : float
        Height of the epistyle blocks [m].
    epistyle_width : float, optional
        Their width across the row [m]; default the abacus side (2 r without capital).
    course_height : float, optional
        A course above the epistyle (frieze and cornice) as a height [m] of the epistyle's width
        and density, riding on each block as mass (0: none). Its mass per metre of row is
        ``rho w course_height``.
    name : str, optional
    """

    column: DrumColumn
    n_columns: int
    interaxial: float
    epistyle_height: float
    epistyle_width: float | None = None
    course_height: float = 0.0
    name: str = ""

    def __post_init__(self):
        column = self.column
        if isinstance(column, Column):
            column = DrumColumn(column)
        if not isinstance(column, DrumColumn):
            raise InputError(f"a colonnade needs a column (a Column or a DrumColumn), got {type(column).__name__}")
        object.__setattr__(self, "column", column)
        n = self.n_columns
        if isinstance(n, float) and n.is_integer():
            n = int(n)
        if isinstance(n, bool) or not isinstance(n, int) or not 2 <= n <= MAX_COLUMNS:
            raise InputError(f"colonnade columns = {self.n_columns!r}: a colonnade is a row of 2 to {MAX_COLUMNS} "
                             "columns (give a whole number of columns, at least 2; one column alone is the "
                             "column itself)")
        object.__setattr__(self, "n_columns", n)
        spacing = _positive("interaxial", self.interaxial)
        object.__setattr__(self, "interaxial", spacing)
        object.__setattr__(self, "epistyle_height", _positive("epistyle_height", self.epistyle_height))
        width = self.abacus_side if self.epistyle_width is None else _positive("epistyle_width", self.epistyle_width)
        object.__setattr__(self, "epistyle_width", width)
        try:
            course = float(self.course_height)
        except (TypeError, ValueError):
            course = math.nan
        if not (math.isfinite(course) and course >= 0.0):
            raise InputError(f"colonnade course_height = {self.course_height!r} m must be a finite height in metres, "
                             "0 or more (0: no course above the epistyle)")
        object.__setattr__(self, "course_height", course)
        capitals = self.abacus_side
        bases = 2.0 * column.column.R
        if spacing < capitals:
            raise InputError(f"colonnade interaxial = {spacing:g} m is less than the abacus side {capitals:g} m: "
                             f"neighbouring capitals would overlap; give an interaxial spacing of at least "
                             f"{capitals:g} m (or a smaller capital)")
        if spacing < bases:
            raise InputError(f"colonnade interaxial = {spacing:g} m is less than the base diameter {bases:g} m: "
                             f"neighbouring columns would overlap at their bases; give an interaxial spacing of at "
                             f"least {bases:g} m")
        self._check_plausible()

    def _check_plausible(self):
        """Refuse dimensions no stone colonnade has, each with its reason (the limits' sources are the module's
        ``MAX_*`` and :data:`EPISTYLE_WIDTH_RANGE`)."""
        spacing, height, width = self.interaxial, self.epistyle_height, self.epistyle_width
        diameter = 2.0 * self.column.column.R
        if spacing > MAX_INTERAXIAL:
            raise InputError(f"colonnade interaxial = {spacing:g} m is more than {MAX_INTERAXIAL:g} m: no stone "
                             "epistyle is known to span so far (the widest, 8.75 m axis to axis, is the central span "
                             "of the Artemision's west front at Ephesus); give an interaxial spacing of at most "
                             f"{MAX_INTERAXIAL:g} m")
        widest = MAX_INTERAXIAL_DIAMETERS * diameter
        if spacing > widest:
            raise InputError(f"colonnade interaxial = {spacing:g} m is more than {MAX_INTERAXIAL_DIAMETERS:g} base "
                             f"diameters ({widest:g} m): a clear intercolumniation beyond 4 diameters is Vitruvius's "
                             "araeostyle, which no stone architrave spans (De architectura 3.3.5); give an interaxial "
                             f"spacing of at most {widest:g} m, or a thicker column")
        if height < spacing / MAX_SPAN_DEPTH:
            raise InputError(f"colonnade epistyle_height = {height:g} m is less than 1/{MAX_SPAN_DEPTH:g} of its span "
                             f"(interaxial {spacing:g} m): no stone architrave spans more than about {MAX_SPAN_DEPTH:g} "
                             "times its depth (the Parthenon's 3.2, the Artemision's at Ephesus 7.5); give an "
                             f"epistyle at least {spacing / MAX_SPAN_DEPTH:g} m high")
        tallest = MAX_EPISTYLE_FRACTION * self.abacus_top
        if height > tallest:
            raise InputError(f"colonnade epistyle_height = {height:g} m is more than {MAX_EPISTYLE_FRACTION:g} of the "
                             f"columns' height {self.abacus_top:g} m (to the abacus top): an architrave is an eighth "
                             "(the Parthenon's) to a fourteenth (Vitruvius's Doric) of it; give an epistyle at most "
                             f"{tallest:g} m high")
        lo, hi = (f * self.abacus_side for f in EPISTYLE_WIDTH_RANGE)
        if not lo <= width <= hi:
            why = ("the blocks would stand on a strip of their capitals" if width < lo else
                   "the blocks would overhang their capitals by more than the abacus on each side")
            raise InputError(f"colonnade epistyle_width = {width:g} m is outside {EPISTYLE_WIDTH_RANGE[0]:g} to "
                             f"{EPISTYLE_WIDTH_RANGE[1]:g} times the abacus side {self.abacus_side:g} m: {why}; give "
                             f"a width from {lo:g} to {hi:g} m (default: the abacus side)")

    # The row -------------------------------------------------------------------
    @property
    def capital(self):
        """The columns' capital (:class:`pipeline.structures.drums.Capital`), or None."""
        return self.column.capital

    @property
    def density(self):
        """Density of the columns, the epistyle and its course [kg/m^3]."""
        return self.column.density

    @property
    def half_abacus(self):
        """c: half the abacus side, or the shaft's top radius r without capital [m]."""
        cap = self.column.capital
        return 0.5 * cap.side if cap is not None else self.column.column.r

    @property
    def abacus_side(self):
        """The abacus side, 2 c [m]."""
        return 2.0 * self.half_abacus

    @property
    def abacus_top(self):
        """H_t: height of the abacus top (the blocks' bed) above the ground [m]."""
        cap = self.column.capital
        return self.column.column.h + (cap.height if cap is not None else 0.0)

    @property
    def n_blocks(self):
        """Number of epistyle blocks, N - 1."""
        return self.n_columns - 1

    @property
    def block_height(self):
        """Height of a block with its course, the body that rides on the capitals [m]."""
        return self.epistyle_height + self.course_height

    def axes(self):
        """x of the column axes [m], the row centred on 0."""
        n, s = self.n_columns, self.interaxial
        return tuple((k - 0.5 * (n - 1)) * s for k in range(n))

    # Blocks ----------------------------------------------------------------------
    def _check_block(self, k):
        if isinstance(k, bool) or not isinstance(k, int) or not 0 <= k < self.n_blocks:
            raise InputError(f"block {k!r}: this colonnade has blocks 0 to {self.n_blocks - 1}")

    def block_extent(self, k):
        """(x0, x1) of block k along the row [m]: axis k to axis k + 1, the end blocks to the capitals' outer edges."""
        self._check_block(k)
        axes, c = self.axes(), self.half_abacus
        x0 = axes[k] - (c if k == 0 else 0.0)
        x1 = axes[k + 1] + (c if k == self.n_blocks - 1 else 0.0)
        return x0, x1

    def block_length(self, k):
        """Length of block k along the row [m]."""
        x0, x1 = self.block_extent(k)
        return x1 - x0

    def block_mass(self, k):
        """Mass of block k with its course [kg]."""
        return self.density * self.block_length(k) * self.epistyle_width * self.block_height

    def block_centre(self, k):
        """Centre of mass of block k with its course, (x, y, z) in the row's frame [m]."""
        x0, x1 = self.block_extent(k)
        return 0.5 * (x0 + x1), 0.0, self.abacus_top + 0.5 * self.block_height

    def block_inertia(self, k):
        """Central moments of inertia of block k with its course about x, y, z [kg m^2] (principal axes).

        The block and its course are one box, length L by width w by height h_e + h_course.
        """
        m = self.block_mass(k)
        L, w, h = self.block_length(k), self.epistyle_width, self.block_height
        return m * (w * w + h * h) / 12.0, m * (L * L + h * h) / 12.0, m * (L * L + w * w) / 12.0

    def bearings(self, k):
        """The two bearing faces of block k: on capital k and on capital k + 1 (:class:`Bearing`)."""
        self._check_block(k)
        c, half_w = self.half_abacus, 0.5 * self.epistyle_width
        y0, y1, on_disc = max(-half_w, -c), min(half_w, c), self.column.capital is None
        # the block covers capital k from its axis (from its outer edge: the first block) and capital
        # k + 1 up to its axis (to its outer edge: the last block); S >= 2 c, so no block reaches past
        return (Bearing(k, k, -c if k == 0 else 0.0, c, y0, y1, on_disc),
                Bearing(k, k + 1, -c, c if k == self.n_blocks - 1 else 0.0, y0, y1, on_disc))

    def head_joints(self):
        """The joints between neighbouring blocks, over the inner columns' axes (:class:`HeadJoint`).

        The face is the epistyle's end face, its height the epistyle's (the course above, riding on
        its block as mass, is not jointed here).
        """
        half_w, z0 = 0.5 * self.epistyle_width, self.abacus_top
        return tuple(HeadJoint(k - 1, k, k, self.axes()[k], -half_w, half_w, z0, z0 + self.epistyle_height)
                     for k in range(1, self.n_columns - 1))

    @property
    def n_joints(self):
        """Joints of the row as an assembly of bodies: each column's (a base, a bed joint per drum above the
        first and the capital's), two bearings per block and a head joint over each inner column."""
        return self.n_columns * self.column.n_bodies + 2 * self.n_blocks + len(self.head_joints())

    # Masses ------------------------------------------------------------------------
    @property
    def rigid_column(self):
        """One column with its capital as one rigid body (:class:`RigidColumn`)."""
        return rigid_column(self.column)

    @property
    def column_mass(self):
        """Mass of one column with its capital [kg]."""
        return self.rigid_column.mass

    @property
    def epistyle_mass(self):
        """Mass of every block with its course [kg]."""
        return sum(self.block_mass(k) for k in range(self.n_blocks))

    @property
    def total_mass(self):
        """Columns, capitals, epistyle and course [kg]."""
        return self.n_columns * self.column_mass + self.epistyle_mass

    @property
    def frame(self):
        """The rigid planar frame as one rocking block (:class:`FrameBlock`, :func:`frame_block`)."""
        return frame_block(self.n_columns, self.rigid_column, self.epistyle_mass, self.column.column.R,
                           self.half_abacus, self.abacus_top)

    def describe(self):
        """A one-line human description."""
        label = f"{self.name}: " if self.name else ""
        course = f" and a course {self.course_height:g} m high" if self.course_height > 0 else ""
        f = self.frame
        return (f"{label}{self.n_columns} columns at {self.interaxial:g} m carrying {self.n_blocks} epistyle "
                f"block(s) {self.epistyle_height:g} m high, {self.epistyle_width:g} m wide{course} "
                f"(epistyle / columns mass {f.M / (f.n * f.m):.3g}, frame theta_crit = "
                f"{math.degrees(f.alpha):.2f} deg); each column {self.column.describe()}")


def named_colonnades():
    """The named colonnades of ``pipeline/data/colonnades.toml`` (id -> dict)."""
    text = resources.files("pipeline").joinpath("data/colonnades.toml").read_text(encoding="utf-8")
    return tomllib.loads(text)


def named_colonnade(key, course_height=None):
    """A named colonnade of ``pipeline/data/colonnades.toml``: its named column (with its drums and capital),
    the number of columns, the interaxial spacing and the epistyle (and course).

    Parameters
    ----------
    key : str
    course_height : float, optional
        A course (frieze and cornice) on its epistyle [m], instead of the entry's (its ``course_height``,
        0 if it has none): what a study or ``frustum simulate --course`` may add to a named colonnade.
    """
    presets = named_colonnades()
    if key not in presets:
        raise InputError(f"{key!r} is not a named colonnade; known: {', '.join(sorted(presets))}")
    p = presets[key]
    course = p.get("course_height", 0.0) if course_height is None else course_height
    return Colonnade(named_drum_column(p["column"]), p["columns"], p["interaxial"], p["epistyle_height"],
                     p.get("epistyle_width"), course, key)

