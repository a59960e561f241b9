"""Acceleration units accepted at the edges (files, text, command line)."""

from pipeline.errors import InputError
from pipeline.groundmotion.options import how_to_give
from pipeline.units import G

__all__ = ["ACCELERATION_UNITS", "to_ms2_factor"]

#: Factor converting each accepted unit to m/s^2.
ACCELERATION_UNITS = {
    "m/s^2": 1.0,
    "m/s**2": 1.0,
    "m/s2": 1.0,
    "cm/s^2": 0.01,
    "cm/s**2": 0.01,
    "cm/s2": 0.01,
    "gal": 0.01,
    "mm/s^2": 0.001,
    "mm/s**2": 0.001,
    "mm/s2": 0.001,
    "g": G,
}


def to_ms2_factor(units, where):
    """Factor from ``units`` to m/s^2; InputError naming ``where`` if unknown."""
    if units is None:
        raise InputError(
            f"{where}: the file does not state its units; give {how_to_give('units')} with U one of "
            f"{', '.join(sorted(set(ACCELERATION_UNITS)))}"
        )
    key = str(units).strip().lower().replace(" ", "")
    if key not in ACCELERATION_UNITS:
        raise InputError(
            f"{where}: unknown acceleration units {units!r}; use one of "
            f"{', '.join(sorted(set(ACCELERATION_UNITS)))}"
        )
    return ACCELERATION_UNITS[key]
