"""What a structure is, in words and attributes: written once, read by every file, report, figure and summary.

A structure (:class:`pipeline.structures.column.Column`, :class:`pipeline.structures.drums.DrumColumn`,
:class:`pipeline.structures.colonnade.Colonnade`) is described here:

* :func:`title` says what it is in a phrase ("a colonnade of 8 columns of 11 drums and a capital
  carrying 7 epistyle blocks (parthenon-east: Parthenon, Athens ...)", "a column of 4 drums and a
  capital", "a monolithic column"); :func:`what_ran` joins such phrases with the models that ran them
  into the opening line of a file, a report or a study's console summary;
* :func:`attributes` gives the global attributes of a results file that holds one structure, and
  :func:`dimensions` its numbers by catalog name (one per column of a study's results);
* :func:`body_labels` and :func:`joint_labels` name its bodies and joints in the order the compliant
  model assembles them (each column in turn, bottom up, then the epistyle blocks; each column's
  base, bed joints and capital joint, then every block's two bearings and the head joints), built
  from :func:`column_labels`, :func:`block_label`, :func:`bearing_label` and :func:`head_label`,
  which the assembly reads for each body and joint it makes.

The words, one scheme: a single column's bodies are "drum 2" (from the bottom, from 1), "shaft" (a
monolith) and "capital", its joints "base of the column", "bed joint under drum 2" and "capital on
its shaft"; in a colonnade each is prefixed by its column ("column 2 drum 3", "column 2 capital",
"base of column 2", "column 2 bed joint under drum 3", "column 2 capital on its shaft"), the blocks
are "epistyle block 1", a block's bearing on a capital "capital 2 / epistyle block 1" and the joint
between two blocks "head joint blocks 1-2".

Nothing here imports a model or a kernel.
"""

import math
import re
from typing import NamedTuple

from pipeline.errors import InputError
from pipeline.structures.colonnade import Colonnade, named_colonnades
from pipeline.structures.drums import Capital, DrumColumn
from pipeline.structures.kinds import kind_of
from pipeline.structures.named import named_columns

__all__ = ["title", "named_title", "what_ran", "run_title", "history_attributes", "attributes", "dimensions",
           "DIMENSIONS", "colonnade_from_attributes", "body_labels", "joint_labels", "column_labels", "block_label",
           "bearing_label", "head_label", "whole_label", "BodyPart", "classify_body"]

#: A colonnade's numbers by catalog name (:mod:`pipeline.dataset`): ``(name, unit, value of a colonnade)``;
#: a column alone has 1 column, 0 blocks and NaN lengths. Global attributes name a length with its unit
#: (``interaxial_m``).
DIMENSIONS = (
    ("n_columns", "1", lambda row: row.n_columns),
    ("interaxial", "m", lambda row: row.interaxial),
    ("epistyle_height", "m", lambda row: row.epistyle_height),
    ("epistyle_width", "m", lambda row: row.epistyle_width),
    ("course_height", "m", lambda row: row.course_height),
    ("n_blocks", "1", lambda row: row.n_blocks),
)


def _stack(structure):
    """The column of a structure as a :class:`DrumColumn` (a colonnade's every column)."""
    if isinstance(structure, Colonnade):
        return structure.column
    return structure if isinstance(structure, DrumColumn) else DrumColumn(structure)


def _outline(structure):
    return _stack(structure).column


def _named(structure):
    """``(id, entry)`` of the data file's named colonnade or column this structure is, or None.

    A structure is the named one when it carries its id as its name and the entry's numbers (a
    colonnade's columns, spacing and epistyle; a column's R, r, h), so that a row someone labels
    with a monument's id is not given that monument's title and source.
    """
    if isinstance(structure, Colonnade):
        entry = named_colonnades().get(structure.name)
        if entry is not None and (entry["columns"], entry["interaxial"], entry["epistyle_height"]) == \
                (structure.n_columns, structure.interaxial, structure.epistyle_height):
            return structure.name, entry
        return None
    outline = _outline(structure)
    name = structure.name if isinstance(structure, DrumColumn) and structure.name else outline.name
    entry = named_columns().get(name)
    if entry is not None and (entry["R"], entry["r"], entry["h"]) == (outline.R, outline.r, outline.h):
        return name, entry
    return None


def _plural(n, one, many):
    return f"{n} {one if n == 1 else many}"


def _column_words(stack, many):
    """A column's make in words: "monolithic column(s)", "column(s) of 4 drums", "... and a capital"."""
    noun = "columns" if many else "column"
    if stack.n_drums == 1:
        words = f"monolithic {noun}"
        return words + (" with capitals" if many else " with a capital") if stack.capital is not None else words
    words = f"{noun} of {stack.n_drums} drums"
    return words + (" and a capital" if stack.capital is not None else "")


def named_title(structure):
    """``"parthenon-east: Parthenon, Athens (Greece): the east front, ..."``: the data file's id and title of a
    named colonnade or column, or ``""``."""
    named = _named(structure)
    return f"{named[0]}: {named[1].get('title', named[0])}" if named else ""


def title(structure, named=True):
    """What a structure is, in a phrase that follows "the response of" or "run by".

    ``"a monolithic column"``, ``"a column of 4 drums and a capital"``, ``"a colonnade of 8 columns of
    11 drums and a capital carrying 7 epistyle blocks (parthenon-east: Parthenon, Athens ...)"``; a
    named monument with its id and title (unless ``named`` is False).
    """
    stack = _stack(structure)
    if isinstance(structure, Colonnade):
        words = (f"a colonnade of {structure.n_columns} {_column_words(stack, True)} carrying "
                 f"{_plural(structure.n_blocks, 'epistyle block', 'epistyle blocks')}")
    else:
        words = "a " + _column_words(stack, False)
    said = named_title(structure) if named else ""
    return f"{words} ({said})" if said else words


#: What a structure run as one body is called when it falls as one: a column, a colonnade (the rigid frame).
_WHOLE = ("the column", "the colonnade")


def whole_label(structure):
    """The label of a structure that a model runs as one body and that fell as one: "the column", "the
    colonnade" (the rigid frame)."""
    return _WHOLE[1] if isinstance(structure, Colonnade) else _WHOLE[0]


def what_ran(runs):
    """The opening line of a file, report or study summary: each structure with the models that ran it.

    Parameters
    ----------
    runs : sequence of (str, sequence of (str, str))
        ``(title of a structure, [(model title, model name), ...])``, in the order to say them;
        a structure with its label, if any, in its title.

    Returns
    -------
    str
        ``"a colonnade of 6 columns ... run by the 3D compliant drums on joints (3d-compliant) and the
        2D rigid frame of a colonnade (2d-frame); a monolithic column run by the 3D rolling frustum (3d)"``.
    """
    parts = []
    for words, models in runs:
        names = [f"the {t} ({n})" if t != n else f"the model {n}" for t, n in models]
        said = ", ".join(names[:-1]) + " and " + names[-1] if len(names) > 1 else "".join(names)
        parts.append(f"{words} run by {said}" if said else words)
    return "; ".join(parts)


def dimensions(structure):
    """A structure's numbers by catalog name (:data:`DIMENSIONS`): a colonnade's, or a column alone's (1
    column, 0 blocks, NaN lengths)."""
    row = structure if isinstance(structure, Colonnade) else None
    out = {}
    for name, unit, value in DIMENSIONS:
        if row is not None:
            out[name] = value(row)
        else:
            out[name] = {"n_columns": 1, "n_blocks": 0}.get(name, math.nan)
    return out


def attributes(structure):
    """The global attributes of a results file that holds ``structure`` (CF: plain numbers and text).

    Every structure: ``structure`` (:func:`title`), ``structure_kind``, ``n_drums`` and ``capital``
    ("SIDE x HEIGHT m" or "none"; with one ``capital_side_m`` and ``capital_height_m``); a colonnade
    also :data:`DIMENSIONS` (lengths as ``NAME_m``); a
    named colonnade ``colonnade``, ``colonnade_title`` and ``colonnade_source``, a named column
    ``named_column``, ``column_title`` and ``column_source`` (from the data files).
    """
    stack = _stack(structure)
    cap = stack.capital
    out = {"structure": title(structure), "structure_kind": kind_of(structure), "n_drums": stack.n_drums,
           "capital": "none" if cap is None else f"{cap.side:g} x {cap.height:g} m"}
    if cap is not None:
        out.update(capital_side_m=cap.side, capital_height_m=cap.height)
    if isinstance(structure, Colonnade):
        for name, unit, value in DIMENSIONS:
            out[name if unit == "1" else f"{name}_{unit}"] = value(structure)
        named = _named(structure)
        if named:
            out.update(colonnade=named[0], colonnade_title=named[1].get("title", ""),
                       colonnade_source=named[1].get("source", ""))
    named = _named(stack)
    if named:
        out.update(named_column=named[0], column_title=named[1].get("title", ""),
                   column_source=named[1].get("source", ""))
    return out


def colonnade_from_attributes(attrs, outline, where="the file"):
    """The colonnade a file's :func:`attributes` describe, read back: its columns of ``outline`` (a
    :class:`pipeline.structures.column.Column`, the file's ``column_R``, ``column_r``, ``column_h``) with the
    capital they name, in a row under the epistyle they give. The shafts are monoliths: the attributes
    give the number of drums, not their heights.

    Raises
    ------
    InputError
        An attribute is missing (a file written before they were), naming ``where`` and the fix.
    """
    missing = [f"{name}_{unit}" if unit != "1" else name for name, unit, _value in DIMENSIONS
               if (f"{name}_{unit}" if unit != "1" else name) not in attrs]
    if missing:
        raise InputError(f"{where} does not say which colonnade ran (no attribute {missing[0]}): it was written "
                         "before files recorded their structure; run 'frustum simulate' again")
    capital = Capital(float(attrs["capital_side_m"]), float(attrs["capital_height_m"])) \
        if "capital_side_m" in attrs else None
    return Colonnade(DrumColumn(outline, capital=capital), int(attrs["n_columns"]), float(attrs["interaxial_m"]),
                     float(attrs["epistyle_height_m"]), float(attrs["epistyle_width_m"]),
                     float(attrs["course_height_m"]), str(attrs.get("colonnade", "")))


def run_title(structure, model):
    """The title of one run's histories: ``"Response to ground motion of a colonnade ... run by the 3D
    compliant drums on joints (3d-compliant)"``; ``model`` has a ``title`` and a ``name`` (a registry entry)."""
    return f"Response to ground motion of {what_ran([(title(structure), [(model.title, model.name)])])}"


def history_attributes(structure, model):
    """The global attributes of one run's histories: its :func:`run_title` and :func:`attributes`."""
    return {"title": run_title(structure, model), **attributes(structure)}


# Labels -----------------------------------------------------------------------------------------------
def column_labels(stack, column=None):
    """The bodies and joints of one column, bottom up: ``(body labels, joint labels)``.

    Parameters
    ----------
    stack : DrumColumn or Column
    column : int, optional
        Its index in a colonnade (0 first), None for a column alone.
    """
    stack = _stack(stack)
    prefix = "" if column is None else f"column {column + 1} "
    bodies = [prefix + (f"drum {k + 1}" if stack.n_drums > 1 else "shaft") for k in range(stack.n_drums)]
    joints = [f"base of column {column + 1}" if column is not None else "base of the column"]
    joints += [f"{prefix}bed joint under drum {k + 1}" for k in range(1, stack.n_drums)]
    if stack.capital is not None:
        bodies.append(prefix + "capital")
        joints.append(prefix + "capital on its shaft")
    return tuple(bodies), tuple(joints)


def block_label(block):
    """Epistyle block ``block`` (0 first): ``"epistyle block 1"``."""
    return f"epistyle block {block + 1}"


def bearing_label(block, column, capital=True):
    """Where block ``block`` bears on column ``column`` (0 first): ``"capital 2 / epistyle block 1"``
    (without capitals, on the shaft: ``"column 2 / epistyle block 1"``)."""
    return f"{'capital' if capital else 'column'} {column + 1} / {block_label(block)}"


def head_label(left, right):
    """The joint between blocks ``left`` and ``right`` (0 first): ``"head joint blocks 1-2"``."""
    return f"head joint blocks {left + 1}-{right + 1}"


def body_labels(structure):
    """Every body of a structure, in the compliant model's order: each column bottom up, then the blocks."""
    if not isinstance(structure, Colonnade):
        return column_labels(structure)[0]
    out = []
    for i in range(structure.n_columns):
        out += column_labels(structure.column, i)[0]
    return tuple(out) + tuple(block_label(k) for k in range(structure.n_blocks))


def joint_labels(structure):
    """Every joint of a structure, in the compliant model's order: each column's (base, bed joints, capital
    joint), then each block's bearings on its two capitals, then the head joints between blocks."""
    if not isinstance(structure, Colonnade):
        return column_labels(structure)[1]
    out = []
    for i in range(structure.n_columns):
        out += column_labels(structure.column, i)[1]
    capital = structure.capital is not None
    for k in range(structure.n_blocks):
        out += [bearing_label(k, b.column, capital) for b in structure.bearings(k)]
    out += [head_label(h.left, h.right) for h in structure.head_joints()]
    return tuple(out)


class BodyPart(NamedTuple):
    """What a body label (:func:`body_labels`, :func:`whole_label`) names, read back by :func:`classify_body`.

    Attributes
    ----------
    column : int or None
        The body's column in a colonnade (0 first); None for an epistyle block, a column alone
        and a structure that fell as one body.
    part : str
        The body without its column: ``"drum 3"``, ``"shaft"``, ``"capital"``, ``"epistyle block 2"``,
        or the whole ``"the column"`` / ``"the colonnade"``.
    """

    column: object
    part: str

    @property
    def kind(self):
        """``"drum"``, ``"shaft"``, ``"capital"``, ``"epistyle block"`` or ``"whole"``."""
        if self.part in _WHOLE:
            return "whole"
        return self.part.rstrip("0123456789").strip()


#: A body label, the inverse of :func:`column_labels`, :func:`block_label` and :func:`whole_label`.
_BODY = re.compile(r"(?:column (?P<column>[1-9][0-9]*) )?(?P<part>drum [1-9][0-9]*|shaft|capital)"
                   r"|(?P<block>epistyle block [1-9][0-9]*)|(?P<whole>" + "|".join(_WHOLE) + ")")


def classify_body(label):
    """Which column and which part a body label names: ``"column 2 drum 3"`` -> ``BodyPart(1, "drum 3")``,
    ``"epistyle block 1"`` -> ``BodyPart(None, "epistyle block 1")``, ``"the colonnade"`` ->
    ``BodyPart(None, "the colonnade")``, ``"capital"`` (a column alone) -> ``BodyPart(None, "capital")``.

    Parameters
    ----------
    label : str
        A label of :func:`body_labels` or :func:`whole_label` (e.g. a study's ``overturn_body``);
        ``""`` (no body fell) gives None.

    Returns
    -------
    BodyPart or None

    Raises
    ------
    InputError
        A label this scheme does not write, naming it.
    """
    label = str(label).strip()
    if not label:
        return None
    match = _BODY.fullmatch(label)
    if match is None:
        raise InputError(f"body label {label!r} is not one this project writes (\"column 2 drum 3\", \"column 2 "
                         "capital\", \"epistyle block 1\", \"drum 2\", \"shaft\", \"capital\", \"the column\", "
                         "\"the colonnade\"; docs/studies.md): label the bodies so, or run the study again with "
                         "'frustum study run'")
    if match["block"] or match["whole"]:
        return BodyPart(None, match["block"] or match["whole"])
    return BodyPart(int(match["column"]) - 1 if match["column"] else None, match["part"])
