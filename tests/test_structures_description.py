"""A structure's description, written once (pipeline/structures/description.py): its title, its attributes read
back, and its bodies' and joints' labels, which are the compliant model's own (issue 47, item 1)."""

import math

import pytest

from pipeline.compliant.layouts import layout_of
from pipeline.errors import InputError
from pipeline.settings import ModelSettings
from pipeline.structures import description as D
from pipeline.structures.colonnade import Colonnade, named_colonnade
from pipeline.structures.column import Column
from pipeline.structures.drums import Capital, DrumColumn, named_drum_column

PAPER = Column(0.5, 0.4, 4.0)
ROW = Colonnade(DrumColumn.equal(PAPER, 2, Capital(1.1, 0.3)), 3, 2.5, 0.8, 1.0, 0.2)


@pytest.mark.parametrize("structure, words", [
    (PAPER, "a monolithic column"),
    (DrumColumn.equal(PAPER, 4, Capital(1.1, 0.3)), "a column of 4 drums and a capital"),
    (DrumColumn(PAPER, capital=Capital(1.1, 0.3)), "a monolithic column with a capital"),
    (ROW, "a colonnade of 3 columns of 2 drums and a capital carrying 2 epistyle blocks"),
    (Colonnade(PAPER, 2, 2.0, 0.5), "a colonnade of 2 monolithic columns carrying 1 epistyle block"),
    (named_colonnade("parthenon-east"), "a colonnade of 8 columns of 11 drums and a capital carrying 7 epistyle "
     "blocks (parthenon-east: Parthenon, Athens (Greece): the east front, 8 Doric columns carrying the architrave)"),
    (named_drum_column("parthenon-peristyle"), "a column of 11 drums and a capital (parthenon-peristyle: Parthenon, "
     "Athens (Greece): Doric column of the peristyle, marble drums and capital)"),
])
def test_a_structure_says_what_it_is(structure, words):
    assert D.title(structure) == words


def test_a_row_labelled_with_a_monuments_id_is_not_given_its_title():
    """The data file's title and source belong to the named entry's numbers, not to its id alone."""
    mine = Colonnade(named_drum_column("parthenon-peristyle"), 3, 4.3, 1.35, name="parthenon-east")
    assert D.title(mine).endswith("carrying 2 epistyle blocks")
    assert "colonnade_source" not in D.attributes(mine)
    assert D.attributes(named_colonnade("parthenon-east"))["colonnade_source"].startswith("approximate: 8 columns")


def test_the_models_that_ran_a_structure_are_named_with_it():
    class Model:
        def __init__(self, title, name):
            self.title, self.name = title, name

    line = D.what_ran([("a colonnade of 2 monolithic columns carrying 1 epistyle block",
                        [("3D compliant drums on joints", "3d-compliant"),
                         ("2D rigid frame of a colonnade", "2d-frame")]),
                       ("a monolithic column", [("3D rolling frustum", "3d")])])
    assert line == ("a colonnade of 2 monolithic columns carrying 1 epistyle block run by the 3D compliant drums on "
                    "joints (3d-compliant) and the 2D rigid frame of a colonnade (2d-frame); a monolithic column run "
                    "by the 3D rolling frustum (3d)")
    assert D.run_title(PAPER, Model("3D rolling frustum", "3d")) == \
        "Response to ground motion of a monolithic column run by the 3D rolling frustum (3d)"


def test_a_colonnades_attributes_hold_it_and_read_back_to_the_same_row():
    attrs = D.attributes(ROW)
    assert attrs["structure"] == D.title(ROW) and attrs["structure_kind"] == "colonnade"
    assert (attrs["n_columns"], attrs["interaxial_m"], attrs["epistyle_height_m"], attrs["epistyle_width_m"],
            attrs["course_height_m"], attrs["n_blocks"]) == (3, 2.5, 0.8, 1.0, 0.2, 2)
    assert (attrs["n_drums"], attrs["capital"], attrs["capital_side_m"], attrs["capital_height_m"]) == \
        (2, "1.1 x 0.3 m", 1.1, 0.3)
    back = D.colonnade_from_attributes(attrs, PAPER)
    # the row as the rigid frame sees it: the same axes, blocks and frame (the shafts as monoliths)
    assert back.axes() == ROW.axes() and back.block_extent(1) == ROW.block_extent(1)
    assert back.frame == ROW.frame and back.column == DrumColumn(PAPER, capital=Capital(1.1, 0.3))
    del attrs["n_blocks"]
    with pytest.raises(InputError, match="does not say which colonnade ran .no attribute n_blocks.*run 'frustum "
                                         "simulate' again"):
        D.colonnade_from_attributes(attrs, PAPER, "the run")
    alone = D.dimensions(PAPER)
    assert alone["n_columns"] == 1 and alone["n_blocks"] == 0 and math.isnan(alone["interaxial"])


def test_labels_follow_one_scheme():
    bodies, joints = D.column_labels(DrumColumn.equal(PAPER, 3, Capital(1.1, 0.3)))
    assert bodies == ("drum 1", "drum 2", "drum 3", "capital")
    assert joints == ("base of the column", "bed joint under drum 2", "bed joint under drum 3", "capital on its shaft")
    assert D.column_labels(PAPER) == (("shaft",), ("base of the column",))
    assert D.body_labels(ROW)[3:6] == ("column 2 drum 1", "column 2 drum 2", "column 2 capital")
    assert D.body_labels(ROW)[-2:] == ("epistyle block 1", "epistyle block 2")
    assert D.joint_labels(ROW)[3:6] == ("base of column 2", "column 2 bed joint under drum 2",
                                        "column 2 capital on its shaft")
    assert D.joint_labels(ROW)[-5:] == ("capital 1 / epistyle block 1", "capital 2 / epistyle block 1",
                                        "capital 2 / epistyle block 2", "capital 3 / epistyle block 2",
                                        "head joint blocks 1-2")


@pytest.mark.parametrize("structure", [PAPER, DrumColumn.equal(PAPER, 3, Capital(1.1, 0.3)), ROW],
                         ids=["monolith", "drums", "colonnade"])
def test_the_compliant_models_bodies_and_joints_carry_the_structures_labels_in_its_order(structure):
    """The assembly names each body and joint it makes from the description; the description's lists are in
    the assembly's order (each body and joint checked by its kind and its column)."""
    layout = layout_of(structure, ModelSettings(model="3d-compliant", contact_sectors=8))
    assert tuple(p.label for p in layout.parts) == D.body_labels(structure)
    assert tuple(c.label for c in layout.contacts) == D.joint_labels(structure)
    assert len(D.joint_labels(structure)) == (structure.n_joints if isinstance(structure, Colonnade) else
                                              len(layout.contacts))
    for c, label in zip(layout.contacts, D.joint_labels(structure)):
        column = f"column {c.column + 1}" if isinstance(structure, Colonnade) and c.column >= 0 else None
        word = {"base": "base of", "bed": "bed joint under", "capital": "capital on its shaft",
                "bearing": " / epistyle", "head": "head joint"}[c.kind]
        assert word in label and (column is None or column in label), (c.kind, label)


@pytest.mark.parametrize("structure", [ROW, named_colonnade("parthenon-east"), Colonnade(PAPER, 2, 2.0, 0.5),
                                       DrumColumn.equal(PAPER, 4, Capital(1.1, 0.3)), PAPER])
def test_a_body_label_reads_back_to_its_column_and_part(structure):
    """classify_body is the inverse of the labels: each body of a structure, in the model's order, gives back the
    column it stands in (None for a block or a column alone) and its part; the whole reads as the whole."""
    labels = D.body_labels(structure)
    parts = [D.classify_body(label) for label in labels]
    if isinstance(structure, Colonnade):
        per_column = len(D.column_labels(structure.column)[0])
        for i in range(structure.n_columns):  # column i's bodies, bottom up, without their column's words
            mine = parts[i * per_column:(i + 1) * per_column]
            assert [p.column for p in mine] == [i] * per_column
            assert [p.part for p in mine] == list(D.column_labels(structure.column)[0])
        blocks = parts[structure.n_columns * per_column:]
        assert blocks == [D.BodyPart(None, D.block_label(k)) for k in range(structure.n_blocks)]
        assert {p.kind for p in blocks} == {"epistyle block"}
    else:
        assert parts == [D.BodyPart(None, label) for label in labels]
    assert {p.kind for p in parts} <= {"drum", "shaft", "capital", "epistyle block"}
    whole = D.classify_body(D.whole_label(structure))
    assert whole == D.BodyPart(None, D.whole_label(structure)) and whole.kind == "whole"


def test_a_body_label_of_another_scheme_is_refused_naming_it():
    assert D.classify_body("") is None  # no body fell
    assert D.classify_body("column 12 drum 11") == D.BodyPart(11, "drum 11")
    assert D.classify_body("column 2 drum 3 ") == D.BodyPart(1, "drum 3")  # a label padded in a file
    for label in ("column 0 drum 1", "drum 0", "column 2", "block 1", "the frame", "column 2 drum 3 capital"):
        with pytest.raises(InputError, match=f"body label '{label}' is not one this project writes"):
            D.classify_body(label)
