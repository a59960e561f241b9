"""A report describes the models it ran, each from its one description, and no other (issue 26).

Before, every report described the rigid 3D and 2D models only, with sentences that had become
false once the contact physics was added ("the base never slides", "the model does not follow
sliding", "the column would have jumped"), and a study of the compliant model got them too.
"""

import re

import numpy as np
import pytest
from fragility_synthetic import make_results

from pipeline import models as MD
from pipeline.report import write_report

STALE = ("never slides", "does not follow sliding", "would have jumped", "without slipping",
         "the only energy losses")


def _report(models, tmp_path):
    ds, _ = make_results(models=models, columns=("paper",), n_records=8, angles=(0.0, 90.0),
                         scales=(0.5, 1.0, 2.0), seed=4)
    ds["sliding_onset"][...] = (ds["peak_theta_ratio"] > 0.5).astype(np.int8)  # some runs slid
    if "3d-compliant" in models:  # as a study writes it: NaN for the rigid models
        slip = (0.1 / ds["peak_theta_ratio"]).where(ds["overturned"] == 0, 0.3)
        ds["dislocation_ratio"] = slip.where(ds["model"] == "3d-compliant").transpose(*ds["overturned"].dims)
    out = write_report(ds, tmp_path / "_".join(models), bootstrap=0)
    return open(out["report"], encoding="utf-8").read()


def _sentences_of(model, ran=()):
    """Text of the description of ``model`` that no description of the models ``ran`` holds."""
    d = MD.describe(model)
    theirs = " ".join(MD.markdown(m) + MD.describe(m).sliding_onset + MD.describe(m).lift_off + MD.describe(m).reference
                      for m in ran)
    return [s for s in (d.title, d.body, d.contact, d.sliding_onset, d.lift_off, d.reference, *d.follows)
            if s not in theirs]


def test_every_model_has_one_description():
    assert len({m.title for m in MD.REGISTRY.values()}) == len(MD.REGISTRY)
    assert all(m.description.body and m.description.reference for m in MD.REGISTRY.values())


def test_the_compliant_model_is_described_by_its_bodies_joints_and_law():
    text = MD.markdown("3d-compliant")
    for words in ("drums", "capital", "contact points", "spring-dashpot", "compression", "shear spring",
                  "Coulomb", "sliding", "flight", "dislocations"):
        assert words in text, words


@pytest.mark.parametrize("models", [("3d-compliant",), ("3d", "3d-compliant")])
def test_a_compliant_report_names_its_model_and_no_model_it_did_not_run(models, tmp_path):
    text = _report(models, tmp_path)
    assert MD.markdown("3d-compliant") in text
    assert ("## Model against model" in text) == (len(models) > 1)  # a report of one model compares none
    assert "3D compliant drums on joints (`3d-compliant`)" in text  # in the list of models
    assert "- 3D-COMPLIANT: in " in text and MD.describe("3d-compliant").sliding_onset in text
    for other in set(MD.REGISTRY) - set(models):
        for sentence in _sentences_of(other, ran=models):
            assert sentence not in text, (other, sentence)
    assert "2D" not in text and "Housner" not in text and "planar rocking" not in text
    if "3d" not in models:
        assert "the 3D results" not in text and not re.search(r"\b3D\b(?!-COMPLIANT| compliant)", text)
    for stale in STALE:
        assert stale not in text


def test_a_rigid_report_does_not_describe_the_compliant_model_and_says_the_contact_it_follows(tmp_path):
    text = _report(("3d", "2d"), tmp_path)
    for model in ("3d", "2d"):
        assert MD.markdown(model) in text
    for sentence in _sentences_of("3d-compliant", ran=("3d", "2d")):
        assert sentence not in text
    assert "compliant" not in text and "drum" not in text and "dislocation" not in text
    for stale in STALE:
        assert stale not in text
    # the rigid models slide and fly since the contact physics: their flags say the motion follows it
    assert "- 3D: in " in text and MD.describe("3d").sliding_onset in text
    assert MD.describe("2d").lift_off in text
