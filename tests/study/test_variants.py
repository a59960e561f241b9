"""Study files name model variants and calibrate one bed for every model (issue 28).

A variant is a registry model under a name of its own, with options, numerics or a body of its
own (``[models.NAME]``). The checks: each variant runs exactly what the same settings give to
:func:`pipeline.simulate.simulate` (so a variant with nothing changed is its model, bit for
bit), the results say which model each variant is and what it changes, and the calibrated bed
is :func:`pipeline.compliant.calibrated_damping` of each column's outline.
"""

import numpy as np
import pytest

from pipeline.compliant import calibrated_damping
from pipeline.errors import InputError
from pipeline.settings import Excitation
from pipeline.simulate import simulate
from pipeline.study import load_motions, load_study, run_study

STUDY = """\
title = "variants"
output = "variants.nc"

[models.rigid]
model = "3d"

[models.stack]
model = "3d-compliant"

[models.same]
model = "3d-compliant"

[models.monolith]
model = "3d-compliant"
body = "outline"

[models.wide]
model = "3d-compliant"
numerics = { edge_band = 1.0 }
options = { joint_friction = 0.5 }

[calibration]
bed = "monolith"

[[columns]]
name = "two"
R = 0.5
r = 0.4
h = 4.0
drums = 2

[records]
synthetic = [{generator = "ricker_wavelet", id = "ricker", ap = 5.0, fp = 2.0, dt = 0.01, duration = 2.0}]

[excitation]
angles = [0.0]
scales = [1.0]

[options]
tail = 0.5
normal_stiffness = 1e10
friction = 0.7
contact_rings = 2                  # few points: the checks are of the study's plumbing, not the joint law
contact_sectors = 8
"""


def test_variants_run_what_their_settings_give_and_say_what_they_are(write_study):
    study = load_study(write_study(STUDY))
    assert study.models == ("rigid", "stack", "same", "monolith", "wide")
    wide = study.settings("wide")
    assert wide.model == "3d-compliant" and dict(wide.numerics) == {"edge_band": 1.0}
    assert wide.joint_friction == 0.5 and wide.normal_stiffness == 1e10  # its options over the study's
    ds = run_study(study, serial=True, progress=False).dataset
    assert list(ds["base_model"].values) == ["3d", "3d-compliant", "3d-compliant", "3d-compliant", "3d-compliant"]
    assert "edge_band = 1" in str(ds["model_variant"].sel(model="wide").values)
    assert "outline" in str(ds["model_variant"].sel(model="monolith").values)
    assert np.all(ds["status"].values == 0)
    # nothing changed: the same numbers as its model, bit for bit
    for name in ("peak_theta", "residual_displacement", "work_ground"):
        a, b = ds[name].sel(model="stack").values, ds[name].sel(model="same").values
        assert a.tobytes() == b.tobytes(), name
    # each variant is what simulate() gives its settings, its body and the calibrated bed
    column = study.columns[0]
    damping, reached = calibrated_damping(column.column, study.settings("monolith"))
    assert float(ds["bed_damping"].sel(column="two")) == damping
    assert float(ds["bed_restitution"].sel(column="two")) == reached
    motion = load_motions(study)[0]
    for name, body in (("monolith", column.column), ("wide", column.stack), ("rigid", column.column)):
        settings = study.settings(name, bed=(damping, reached))
        assert settings.contact_damping == damping and settings.restitution == reached
        direct = simulate(body, motion, Excitation(angle=0.0, scale=1.0), settings, histories=False).summary
        assert ds["peak_theta"].sel(model=name).values.ravel()[0] == direct["peak_theta"], name


def test_a_list_of_models_still_reads(write_study):
    text = STUDY.split("[models.rigid]")[0] + 'models = ["3d", "3d-compliant"]\n\n[[columns]]' + STUDY.split("[[columns]]")[1]
    study = load_study(write_study(text))
    assert study.models == ("3d", "3d-compliant") and study.settings("3d").model == "3d"


@pytest.mark.parametrize("old, new, field", [
    ('[models.wide]\nmodel = "3d-compliant"', '[models.wide]\nmodel = "4d"', "models.wide.model"),
    ('numerics = { edge_band = 1.0 }', 'numerics = { edge_bnad = 1.0 }', "models.wide.numerics"),
    ('numerics = { edge_band = 1.0 }', 'numerics = { edge_band = -1.0 }', "edge_band"),
    ('options = { joint_friction = 0.5 }', 'options = { joint_fiction = 0.5 }', "models.wide.options"),
    ('body = "outline"', 'body = "drum"', "models.monolith.body"),
    ('body = "outline"', 'colour = "red"', "models.monolith"),
    ('bed = "monolith"', 'bed = "rigid"', "calibration.bed"),
    ('bed = "monolith"', 'bed = "nothing"', "calibration.bed"),
])
def test_a_bad_variant_is_refused_naming_its_field(write_study, old, new, field):
    assert old in STUDY
    with pytest.raises(InputError, match=field.replace(".", r"\.")):
        load_study(write_study(STUDY.replace(old, new)))
