"""Imperfect drums: beds offset and tilted within a tolerance, friction drawn from a range, seeded.

Real columns are not the perfect stacks of the models: each drum sits on the one below a little
off its axis, on a bed dressed a little out of level, and the friction of its joints is not one
number. Mouzakis et al. (2002, Earthquake Engng Struct. Dyn. 31(9)) found a 1:3 marble Parthenon
column driven in one direction to move out of that plane, triggered by such imperfections, and
apparently identical tests to differ radically. :class:`Imperfections` states a structure's
imperfections (a tolerance [m], a seed, optionally a friction range) and :func:`draw` draws them,
one value per joint of the structure's columns:

* **offset** (a bed joint: drum on drum, the capital on the shaft): the upper body's axis stands
  off the lower one's by a horizontal vector uniform in a disc of radius ``tolerance``. The base
  of a column on the ground takes none: the ground has no axis to be off.
* **tilt** (every joint of a column, the base on the ground too: a stylobate out of level): the
  bed plane leans so that it is out of level by ``rise``, uniform in [0, ``tolerance``], across
  its diameter D: ``tan(tilt) = rise / D``, the normal leaning towards an azimuth uniform on the
  circle (the direction in which the bed descends). The two faces of the joint share the plane,
  so the bodies' axes stay vertical at rest and the bed leans under them.
* **friction** (every joint of a column, with ``friction_range``): uniform in ``[lo, hi]``.

The epistyle's bearings on the capitals and the head joints between its blocks take none (an
epistyle block spans two capitals, whose offsets it follows; its beds are the capitals' tops,
level with their axes).

Reproducible, to the bit on any machine: ``numpy.random.Generator(PCG64(seed))`` gives uniform
doubles (:meth:`numpy.random.Generator.random`, one at a time), and everything drawn from them is
IEEE arithmetic and square roots, correctly rounded everywhere (no sine or cosine: a point in a
disc and a direction on the circle are drawn by rejection from the square). The draw order is
fixed: columns left to right (a colonnade's), in each column its joints bottom up (the base,
each bed joint, the capital's), and for each joint, always and in this order: the offset (pairs
(u, v) = 2 U - 1 until u^2 + v^2 <= 1; a base discards it), the tilt's direction (pairs until
0 < u^2 + v^2 <= 1, then normalised), the rise (one U) and the friction (one U, used only with a
range). So a joint's draw does not depend on the kind of the joint or on whether a friction range
is given, and a column's draws are the first of its colonnade's (the column alone and column 1
of a row of it are imperfect alike).

The bodies' masses and inertias are the perfect drums': a bed cut out of level by the tolerance
moves a drum's centre of mass off its axis by ``R^2 tan(tilt) / (4 h)``, at most ``tolerance R /
(8 h)`` for a bed of diameter 2 R (an eighth of the tolerance for a drum as tall as it is wide),
and leaves its volume to second order.

Nothing here imports a model or a kernel.
"""

import math
from dataclasses import dataclass

import numpy as np

from pipeline.errors import InputError

__all__ = ["Imperfections", "JointDraw", "draw", "bed_diameters", "check_tolerance", "MAX_TOLERANCE_RATIO",
           "SEED_RANGE", "FRICTION_RANGE"]

#: The largest tolerance, as a fraction of the smallest bed diameter of a structure's columns.
#:
#: Why 5 %: a bed out of level by 5 % of its diameter leans 2.9 deg, and a drum 5 % of its diameter
#: off the one below overhangs it by a hand's breadth on a Parthenon drum (95 mm of 1.9 m). Classical
#: drums were set with dressed beds (anathyrosis) to within a millimetre or so, and shake-table
#: replicas within less: an imperfection of centimetres is a damaged or dislocated column, another
#: structure, which the model runs as one (drums and their dislocations), not as a tolerance. Beyond
#: 5 % the first-order picture of an imperfection (a small lean, a small overhang, the drums' mass
#: properties left perfect, see the module's note) no longer holds either.
MAX_TOLERANCE_RATIO = 0.05
#: Seeds: whole numbers in this closed range (stored as int64 in results files).
SEED_RANGE = (0, 2**32 - 1)
#: Friction coefficients a range may span [1]: the joint friction's range.
FRICTION_RANGE = (1e-3, 100.0)


@dataclass(frozen=True)
class Imperfections:
    """The imperfections of a structure's drums: a tolerance, a seed and a friction range.

    Parameters
    ----------
    tolerance : float
        [m], 0 or more: each bed offset within a disc of this radius and out of level by up to it
        across its diameter (0: the geometry perfect, only the friction drawn).
    seed : int
        Seed of the draw, a whole number in :data:`SEED_RANGE`: the same seed and structure draw
        the same imperfections.
    friction_range : tuple of float, optional
        ``(lo, hi)`` [1]: each joint of a column takes a friction coefficient uniform in it;
        None: the settings' friction.

    Raises
    ------
    pipeline.errors.InputError
        A negative, infinite or NaN tolerance, a seed that is not a whole number in range, a range
        that is not two numbers ``lo <= hi`` in :data:`FRICTION_RANGE`.
    """

    tolerance: float
    seed: int
    friction_range: tuple | None = None

    def __post_init__(self):
        t = self.tolerance
        if isinstance(t, bool) or not isinstance(t, (int, float)) or not (math.isfinite(t) and t >= 0.0):
            raise InputError(f"imperfections = {t!r} m: the tolerance of the drums' beds must be a length in metres, "
                             "0 or more (e.g. 0.002 for beds within 2 mm)")
        object.__setattr__(self, "tolerance", float(t))
        seed, (lo, hi) = self.seed, SEED_RANGE
        if isinstance(seed, bool) or not isinstance(seed, (int, float, np.integer)) or not (
                math.isfinite(seed) and seed == int(seed) and lo <= seed <= hi):
            raise InputError(f"seed = {seed!r}: the seed of the imperfections must be a whole number in [{lo}, {hi}]")
        object.__setattr__(self, "seed", int(seed))
        if self.friction_range is not None:
            object.__setattr__(self, "friction_range", check_friction_range(self.friction_range))

    def describe(self):
        """In words: ``"beds within 2 mm (seed 3), joint friction 0.5-0.7"``."""
        text = f"beds within {1e3 * self.tolerance:g} mm (seed {self.seed})"
        if self.friction_range is not None:
            text += f", joint friction {self.friction_range[0]:g}-{self.friction_range[1]:g}"
        return text


def check_friction_range(value, label="friction_range"):
    """``(lo, hi)`` as floats if ``value`` is two friction coefficients ``lo <= hi`` in :data:`FRICTION_RANGE`."""
    lo, hi = FRICTION_RANGE
    ok = isinstance(value, (list, tuple)) and len(value) == 2 and all(
        isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and lo <= v <= hi for v in value)
    if not ok or value[0] > value[1]:
        raise InputError(f"{label} = {value!r}: give two friction coefficients LO,HI with LO <= HI, each in "
                         f"[{lo:g}, {hi:g}] (e.g. 0.5,0.7); each joint of a column draws its own uniformly "
                         "between them")
    return float(value[0]), float(value[1])


@dataclass(frozen=True)
class JointDraw:
    """The imperfections drawn for a structure: one value per joint of its columns.

    Joints in the draw order (module docstring): column by column, in each its joints bottom up,
    joint k of a column the base of its body k (0 the base on the ground).

    Attributes
    ----------
    imperfections : Imperfections
        What was drawn from.
    column : numpy.ndarray of int
        The column each joint belongs to.
    offset_x, offset_y : numpy.ndarray
        The upper body's axis from the lower one's [m] (0 at a base).
    slope_x, slope_y : numpy.ndarray
        The bed's normal leans as ``(slope_x, slope_y, 1)`` [1]: ``tan(tilt)`` times the unit
        direction of the lean.
    tilt, azimuth : numpy.ndarray
        The lean of the bed's normal from the vertical [rad] and its direction, counter-clockwise
        from x [rad] (the bed descends that way).
    friction : numpy.ndarray
        Each joint's friction coefficient [1]; NaN without a friction range.
    """

    imperfections: Imperfections
    column: np.ndarray
    offset_x: np.ndarray
    offset_y: np.ndarray
    slope_x: np.ndarray
    slope_y: np.ndarray
    tilt: np.ndarray
    azimuth: np.ndarray
    friction: np.ndarray

    @property
    def n_joints(self):
        return self.column.size

    def recorded(self, n_joints=None):
        """What a results file keeps of the draw, by catalog name (:mod:`pipeline.dataset`): the tolerance
        [m], seed and friction range [1] (NaN without one), and per joint (``n_joints``, the draw's
        own followed by NaN for the joints it has none for: an epistyle's) the offset [m], tilt and
        its azimuth [rad] and friction [1]."""
        n = self.n_joints if n_joints is None else n_joints
        lo, hi = self.imperfections.friction_range or (math.nan, math.nan)

        def per_joint(values):
            return np.concatenate([values, np.full(n - values.size, np.nan)])

        return {"imperfection_tolerance": self.imperfections.tolerance, "imperfection_seed": self.imperfections.seed,
                "imperfection_friction_min": lo, "imperfection_friction_max": hi,
                "bed_offset_x": per_joint(self.offset_x), "bed_offset_y": per_joint(self.offset_y),
                "bed_tilt": per_joint(self.tilt), "bed_tilt_azimuth": per_joint(self.azimuth),
                "bed_friction": per_joint(self.friction)}

    def normal(self, j):
        """The unit normal of joint j's bed (pointing up) [1]."""
        sx, sy = float(self.slope_x[j]), float(self.slope_y[j])
        norm = math.sqrt(sx * sx + sy * sy + 1.0)
        return sx / norm, sy / norm, 1.0 / norm


def _columns(structure):
    """``(the column of drums, number of columns)`` of a DrumColumn, a Column or a Colonnade."""
    from pipeline.structures.column import Column
    from pipeline.structures.drums import DrumColumn

    if isinstance(structure, Column):
        return DrumColumn(structure), 1
    if isinstance(structure, DrumColumn):
        return structure, 1
    column = getattr(structure, "column", None)
    if isinstance(column, DrumColumn) and hasattr(structure, "n_columns"):
        return column, structure.n_columns
    raise InputError(f"imperfections are drawn for a Column, a DrumColumn or a Colonnade, got "
                     f"{type(structure).__name__}")


def bed_diameters(structure):
    """Each joint's bed diameter [m], in the draw order: per column, the base's 2 R, each bed joint's
    (the top of the drum below) and the capital's (the shaft's top)."""
    stack, n = _columns(structure)
    return np.array(stack.joint_diameters() * n, dtype=np.float64)


def check_tolerance(imperfections, structure):
    """Refuse a tolerance above :data:`MAX_TOLERANCE_RATIO` of the structure's smallest bed diameter."""
    smallest = float(np.min(bed_diameters(structure)))
    most = MAX_TOLERANCE_RATIO * smallest
    if imperfections.tolerance > most:
        raise InputError(f"imperfections = {imperfections.tolerance:g} m is more than {100 * MAX_TOLERANCE_RATIO:g} % "
                         f"of the smallest bed diameter of the columns ({smallest:g} m): a bed that far out of level "
                         f"or off the drum below is a dislocated column, not a tolerance; give at most {most:.4g} m "
                         "(millimetres: classical drums were set within about 1 mm)")


def _in_disc(rng, positive=False):
    """(u, v) uniform in the unit disc, by rejection from the square (IEEE arithmetic only)."""
    while True:
        u = 2.0 * rng.random() - 1.0
        v = 2.0 * rng.random() - 1.0
        r2 = u * u + v * v
        if r2 <= 1.0 and (r2 > 0.0 or not positive):
            return u, v, r2


def draw(imperfections, structure):
    """The imperfections of ``structure`` drawn from ``imperfections`` (a :class:`JointDraw`).

    A pure function of its arguments: the same structure and imperfections give the same draw to
    the bit (module docstring: the generator, the order, IEEE arithmetic).

    Parameters
    ----------
    imperfections : Imperfections
    structure : Column, DrumColumn or Colonnade

    Raises
    ------
    pipeline.errors.InputError
        A tolerance above :data:`MAX_TOLERANCE_RATIO` of the smallest bed diameter
        (:func:`check_tolerance`).
    """
    check_tolerance(imperfections, structure)
    stack, n_columns = _columns(structure)
    diameters = bed_diameters(structure)
    per = stack.n_bodies
    n = n_columns * per
    rng = np.random.Generator(np.random.PCG64(imperfections.seed))
    tol = imperfections.tolerance
    values = np.zeros((n, 5))  # offset x, y, slope x, y, friction
    for j in range(n):
        u, v, _ = _in_disc(rng)
        if j % per:  # a bed joint; the base on the ground keeps its draw unused
            values[j, 0], values[j, 1] = tol * u, tol * v
        dx, dy, r2 = _in_disc(rng, positive=True)
        slope = tol * rng.random() / diameters[j]
        length = math.sqrt(r2)
        values[j, 2], values[j, 3] = slope * (dx / length), slope * (dy / length)
        values[j, 4] = rng.random()
    friction = np.full(n, np.nan)
    if imperfections.friction_range is not None:
        lo, hi = imperfections.friction_range
        friction = lo + (hi - lo) * values[:, 4]
    slope_x, slope_y = values[:, 2].copy(), values[:, 3].copy()
    tan = np.sqrt(slope_x * slope_x + slope_y * slope_y)
    return JointDraw(imperfections, np.repeat(np.arange(n_columns), per), values[:, 0].copy(), values[:, 1].copy(),
                     slope_x, slope_y, np.arctan(tan), np.where(tan > 0.0, np.arctan2(slope_y, slope_x), 0.0),
                     friction)
