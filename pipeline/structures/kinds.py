"""The kinds of structure the models run, by name: what a model declares (``Model.bodies``) and what a
structure is.

* ``"column"``: a monolith, :class:`pipeline.structures.column.Column`;
* ``"drums"``: a column of drums and a capital, :class:`pipeline.structures.drums.DrumColumn`;
* ``"colonnade"``: a row of columns carrying an epistyle, :class:`pipeline.structures.colonnade.Colonnade`.

:func:`kind_of` names a structure's kind, :func:`describe_kind` says it in words for errors and
:func:`example` gives a small one of each kind (a study's kernel warm-up, the models' contract test).
"""

from pipeline.errors import InputError
from pipeline.structures.colonnade import Colonnade
from pipeline.structures.column import Column
from pipeline.structures.drums import Capital, DrumColumn

__all__ = ["KINDS", "RUNS", "kind_of", "describe_kind", "example"]

#: Every kind of structure, in the order help lists them.
KINDS = ("column", "drums", "colonnade")

#: What a model runs, in words: ``"a model of KINDS[k] runs ..."``.
RUNS = {"column": "monolithic columns", "drums": "columns of drums", "colonnade": "colonnades"}


def kind_of(structure):
    """The kind (one of :data:`KINDS`) of ``structure``; anything else is refused naming what it is."""
    if isinstance(structure, Column):
        return "column"
    if isinstance(structure, DrumColumn):
        return "drums"
    if isinstance(structure, Colonnade):
        return "colonnade"
    raise InputError(f"a model runs a Column, a DrumColumn or a Colonnade, got {type(structure).__name__}")


def describe_kind(structure):
    """``structure``'s kind in words, for errors (``"a column of 3 drum(s)"``)."""
    kind = kind_of(structure)
    if kind == "drums":
        return f"a column of {structure.n_drums} drum(s)" + (" and a capital" if structure.capital else "")
    if kind == "colonnade":
        return f"a colonnade of {structure.n_columns} columns"
    return "a monolithic column"


def example(kind):
    """A small structure of ``kind``: the paper's column (R 0.5, r 0.4, h 4 m), as two drums, or two of it
    with a capital 1.0 x 0.4 m carrying an epistyle 0.5 m high at 2 m."""
    paper = Column(0.5, 0.4, 4.0)
    if kind == "column":
        return paper
    if kind == "drums":
        return DrumColumn.equal(paper, 2)
    if kind == "colonnade":
        return Colonnade(DrumColumn(paper, capital=Capital(1.0, 0.4)), 2, 2.0, 0.5)
    raise InputError(f"{kind!r} is not a kind of structure; choose one of {', '.join(KINDS)}")
