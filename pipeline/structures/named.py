"""Named real columns: the presets of ``pipeline/data/columns.toml``.

Each entry (its key the column's id) gives the dimensions R, r, h [m] of a real column and
where they come from, its position (latitude, longitude [degree]) where known, and for a
column built of drums their number (``drums``) or heights (``drum_heights`` [m]) and a
capital (``capital_side``, ``capital_height`` [m]). Read by the study files (``named = ...``)
and by :func:`pipeline.structures.drums.named_drum_column`; a module of its own so that both read it
without importing each other.
"""

import tomllib
from importlib import resources

__all__ = ["named_columns"]


def named_columns():
    """The named real columns of ``pipeline/data/columns.toml`` (id -> dict)."""
    text = resources.files("pipeline").joinpath("data/columns.toml").read_text(encoding="utf-8")
    return tomllib.loads(text)
