"""Multi-drum columns: a column's outline cut into stacked drums, with an optional capital.

A :class:`DrumColumn` is the frustum of a :class:`pipeline.structures.column.Column` cut by
horizontal bed joints at given heights, every drum a frustum of the same taper, plus an
optional square capital (abacus) resting on the top of the shaft. The compliant-contact
model (:mod:`pipeline.compliant`) runs it; one drum is the monolith.
"""

import math
from dataclasses import dataclass

from pipeline.structures.named import named_columns
from pipeline.errors import InputError
from pipeline.structures.column import Column
from pipeline.units import MARBLE_DENSITY

MAX_DRUMS = 40


@dataclass(frozen=True)
class Capital:
    """A square capital block (abacus) on top of the shaft.

    Parameters
    ----------
    side : float
        Side of the square block [m].
    height : float
        Height of the block [m].

    It rests on the shaft's top face, whose disc is its bed joint; its mass and inertia are
    those of the block (the echinus under it is left out).
    """

    side: float
    height: float

    def __post_init__(self):
        for name in ("side", "height"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise InputError(f"capital {name} = {value!r} m must be a positive length in metres")
            object.__setattr__(self, name, float(value))

    def mass(self, density):
        """Mass [kg] at a density [kg/m^3]."""
        return density * self.side**2 * self.height

    def inertia(self, density):
        """Central moments of inertia (transverse, axial) [kg m^2] of the block."""
        m = self.mass(density)
        return m * (self.side**2 + self.height**2) / 12.0, m * self.side**2 / 6.0


@dataclass(frozen=True)
class DrumColumn:
    """A column of stacked drums (frustums of one taper), optionally with a capital.

    Parameters
    ----------
    column : pipeline.structures.column.Column
        The outline of the shaft (R, r, h [m]) and its density.
    cuts : tuple of float
        Heights of the bed joints above the base [m], increasing, strictly inside (0, h).
        Empty: a monolith.
    capital : Capital, optional
    name : str, optional
    """

    column: Column
    cuts: tuple = ()
    capital: Capital | None = None
    name: str = ""

    def __post_init__(self):
        if not isinstance(self.column, Column):
            raise InputError(f"a drum column needs a Column outline, got {type(self.column).__name__}")
        try:
            cuts = tuple(float(c) for c in self.cuts)
        except (TypeError, ValueError):
            raise InputError(f"drum heights {self.cuts!r} must be numbers in metres") from None
        h = self.column.h
        previous = 0.0
        for z in cuts:
            if not (math.isfinite(z) and previous < z < h):
                raise InputError(
                    f"bed joint at {z!r} m: the joints must increase strictly between 0 and the column's "
                    f"height {h:g} m (give the heights of the joints above the base, bottom first)")
            previous = z
        if len(cuts) + 1 > MAX_DRUMS:
            raise InputError(f"{len(cuts) + 1} drums: at most {MAX_DRUMS} are supported")
        object.__setattr__(self, "cuts", cuts)
        if self.capital is not None and not isinstance(self.capital, Capital):
            raise InputError(f"capital must be a Capital, got {type(self.capital).__name__}")

    @classmethod
    def equal(cls, column, n, capital=None, name=""):
        """The column cut into ``n`` drums of equal height."""
        if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= MAX_DRUMS:
            raise InputError(f"drums = {n!r} must be a whole number from 1 to {MAX_DRUMS}")
        return cls(column, tuple(column.h * k / n for k in range(1, n)), capital, name)

    @classmethod
    def from_heights(cls, column, heights, capital=None, name=""):
        """The column cut into drums of the given heights [m], bottom first, summing to h."""
        heights = [float(x) for x in heights]
        if any(not (math.isfinite(x) and x > 0) for x in heights):
            raise InputError(f"drum heights {heights} must be positive lengths in metres")
        total = sum(heights)
        if not math.isclose(total, column.h, rel_tol=1e-9, abs_tol=1e-9):
            raise InputError(
                f"drum heights add up to {total:g} m but the column is {column.h:g} m high: "
                "give heights that sum to the column's height")
        cuts, z = [], 0.0
        for x in heights[:-1]:
            z += x
            cuts.append(z)
        return cls(column, tuple(cuts), capital, name)

    @property
    def density(self):
        """Density [kg/m^3]: the column's, or marble's when it has none."""
        return self.column.density if self.column.density is not None else MARBLE_DENSITY

    @property
    def n_drums(self):
        """Number of drums of the shaft."""
        return len(self.cuts) + 1

    @property
    def n_bodies(self):
        """Number of rigid bodies: the drums, and the capital if any."""
        return self.n_drums + (self.capital is not None)

    def joint_diameters(self):
        """Diameter of each joint's bearing face [m], joint k the base of body k.

        Joint 0 is the base of drum 0 on the ground, joint k >= 1 the bed joint on body k - 1:
        the top face of the drum below, which is also the base of the drum above (one taper),
        or under a capital the top of the shaft, smaller than the block.
        """
        return (2.0 * self.column.R,) + tuple(2.0 * self.radius_at(z) for z in self.cuts) + \
            ((2.0 * self.column.r,) if self.capital is not None else ())

    def radius_at(self, z):
        """Radius of the shaft at height z above the base [m]."""
        c = self.column
        return c.R + (c.r - c.R) * z / c.h

    def drums(self):
        """The drums, bottom first, as columns (frustums) with the shaft's density."""
        edges = (0.0,) + self.cuts + (self.column.h,)
        return tuple(
            Column(self.radius_at(z0), self.radius_at(z1), z1 - z0, density=self.density)
            for z0, z1 in zip(edges[:-1], edges[1:])
        )

    def describe(self):
        """A one-line human description."""
        text = f"{self.n_drums} drum(s) of " + self.column.describe()
        if self.capital is not None:
            text += f", capital {self.capital.side:g} x {self.capital.side:g} x {self.capital.height:g} m"
        return text


def named_drum_column(key):
    """A named column of ``pipeline/data/columns.toml`` as drums (and capital) where it has them.

    Entries with ``drums`` (a number of equal drums) or ``drum_heights`` [m], and optionally
    ``capital_side`` and ``capital_height`` [m]; other entries give the monolith.
    """
    presets = named_columns()
    if key not in presets:
        raise InputError(f"{key!r} is not a named column; known: {', '.join(sorted(presets))}")
    p = presets[key]
    column = Column(p["R"], p["r"], p["h"], name=key)
    capital = Capital(p["capital_side"], p["capital_height"]) if "capital_side" in p else None
    if "drum_heights" in p:
        return DrumColumn.from_heights(column, p["drum_heights"], capital, key)
    return DrumColumn.equal(column, int(p.get("drums", 1)), capital, key)
