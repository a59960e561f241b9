"""Study files: what parses, and what fails before computing with the field named."""

import math
import re

import pytest

from pipeline.cli import main
from pipeline.structures.named import named_columns
from pipeline.errors import InputError
from pipeline.study import load_study

from study_files import SMALL_STUDY


def test_small_study_parses(write_study):
    study = load_study(write_study())
    assert [c.label for c in study.columns] == ["paper", "squat", "R0.4-s7-b0.9", "R0.4-s9-b0.9"]
    assert study.shape == (4, 2, 3, 3, 2)
    grid = study.columns[3].column
    assert math.isclose(grid.h, 3.6) and math.isclose(grid.r, 0.36)
    paper = named_columns()["paper"]
    assert (study.columns[0].column.R, study.columns[0].column.r, study.columns[0].column.h) == \
        (paper["R"], paper["r"], paper["h"])
    assert study.settings("2d").tail == 2.0 and study.settings("2d").model == "2d"
    assert len(study.digest) == 64 and study.output.endswith("small.nc")


def test_named_columns_cite_a_source():
    for key, entry in named_columns().items():
        assert entry["source"], key
        assert entry["R"] > 0 and entry["r"] > 0 and entry["h"] > 0


def _broken(old, new):
    assert old in SMALL_STUDY, old
    return SMALL_STUDY.replace(old, new)


BAD = {
    "unknown top-level field": (_broken('title = "small test study"', 'title = "x"\nfriction = 0.5'), "friction"),
    "unknown option": (_broken("tail = 2.0", "tail = 2.0\nfrction = 0.5"), "options.frction"),
    "unknown column field": (_broken("R = 0.6", "R = 0.6\nradius = 1"), "columns[1].radius"),
    "wrong type: string for a number": (_broken("R = 0.6", 'R = "0.6"'), "columns[1].R"),
    "wrong type: angles not a list": (_broken("angles = [0.0, 30.0, 90.0]", "angles = 30"), "excitation.angles"),
    "wrong type: vertical": (_broken("scales = [0.5, 1.0, 2.0]", 'scales = [0.5, 1.0, 2.0]\nvertical = "yes"'),
                             "excitation.vertical"),
    "empty grid: no angles": (_broken("angles = [0.0, 30.0, 90.0]", "angles = []"), "excitation.angles"),
    "empty grid: no scales": (_broken("scales = [0.5, 1.0, 2.0]", "scales = []"), "excitation.scales"),
    "empty grid: no models": (_broken('models = ["3d", "2d"]', "models = []"), "models"),
    "unknown model": (_broken('models = ["3d", "2d"]', 'models = ["3d", "4d"]'), "models[1]"),
    "negative scale": (_broken("scales = [0.5, 1.0, 2.0]", "scales = [-1.0]"), "excitation.scales[0]"),
    "unknown named column": (_broken('named = "paper"', 'named = "parthenon-42"'), "columns[0].named"),
    "column out of range": (_broken("h = 3.0", "h = 3000.0"), "columns[1]"),
    "unknown generator": (_broken('generator = "ricker_wavelet"', 'generator = "ricker"'),
                          "records.synthetic[0].generator"),
    "unknown generator parameter": (_broken("ap = 4.0", "ap = 4.0, amplitude = 2"),
                                    "records.synthetic[0].amplitude"),
    "unknown record set": (_broken("[records]", '[records]\nsets = ["FEMA-XX"]'), "records.sets[0]"),
    "block_columns": (_broken("block_columns = 2", "block_columns = 0"), "execution.block_columns"),
    "unknown horizontal components": (_broken("scales = [0.5, 1.0, 2.0]", 'scales = [0.5, 1.0, 2.0]\ncomponents = "y"'),
                                      "excitation.components"),
    "duplicate column label": (_broken('name = "squat"', 'name = "paper"'), "columns"),
    "duplicate record id": (_broken('id = "kt-1"', 'id = "ricker"'), "records"),
    "intensity without units": (_broken("scales = [0.5, 1.0, 2.0]", 'intensity = {measure = "pga", values = [0.3]}'),
                                "excitation.intensity.units"),
    "intensity in a unit of another measure": (_broken("scales = [0.5, 1.0, 2.0]",
                                                       'intensity = {measure = "pgv", units = "g", values = [0.3]}'),
                                               "excitation.intensity.units"),
    "scales and intensity": (_broken("scales = [0.5, 1.0, 2.0]",
                                     'scales = [1.0]\nintensity = {measure = "pga", units = "g", values = [0.1]}'),
                             "excitation.intensity"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_invalid_fields_are_named(write_study, case):
    text, field = BAD[case]
    path = write_study(text)
    with pytest.raises(InputError) as info:
        load_study(path)
    message = str(info.value)
    assert str(path) in message
    assert re.search(rf"field {re.escape(field)}(?![\w.\[])", message), message


def test_empty_columns(write_study):
    text = SMALL_STUDY.split("[[columns]]")[0] + "[records]" + SMALL_STUDY.split("[records]")[1]
    with pytest.raises(InputError, match=r"field columns: no columns"):
        load_study(write_study(text))


def test_empty_records(write_study):
    start = SMALL_STUDY.index("synthetic = [")
    end = SMALL_STUDY.index("[excitation]")
    with pytest.raises(InputError, match=r"field records: no records"):
        load_study(write_study(SMALL_STUDY[:start] + "ids = []\n\n" + SMALL_STUDY[end:]))


@pytest.mark.parametrize("records, field", [
    ('ids = ["FEMA-FF-99"]', "records.ids[0]"),
    ('files = [{path = "missing.mseed", units = "g"}]', "records.files[0]"),
    ('synthetic = [{generator = "ricker_wavelet", id = "bad", ap = 4.0, fp = -2.0}]', "records.synthetic[0]"),
])
def test_record_that_cannot_be_loaded_fails_before_computing(write_study, tmp_path, capsys, records, field):
    start = SMALL_STUDY.index("synthetic = [")
    end = SMALL_STUDY.index("[excitation]")
    path = write_study(SMALL_STUDY[:start] + records + "\n\n" + SMALL_STUDY[end:])
    with pytest.raises(InputError, match=rf"field {re.escape(field)}: record .* cannot be loaded"):
        load_study(path)
    # the command line: exit 2, field named, nothing computed or written
    assert main(["study", "run", str(path), "--serial", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert f"field {field}" in err
    assert not (tmp_path / "small.nc").exists() and not (tmp_path / "small.nc.checkpoint").exists()


def test_cli_bad_file_exits_2(tmp_path, capsys):
    assert main(["study", "check", str(tmp_path / "nope.toml")]) == 2
    assert "cannot read the study file" in capsys.readouterr().err


def test_cli_check_describes(write_study, capsys):
    assert main(["study", "check", str(write_study())]) == 0
    out = capsys.readouterr().out
    assert "4 column(s) x 2 record(s) x 3 angle(s) x 3 scales x 2 model(s) = 144 results" in out


def test_quickstart_study_is_valid():
    from pathlib import Path

    study = load_study(Path(__file__).parents[2] / "studies" / "quickstart.toml", load_records=False)
    assert study.columns[0].column.R == 0.5 and study.columns[0].column.r == 0.4 and study.columns[0].column.h == 4
    assert all(r.id.startswith("FEMA-FF-") for r in study.records)
    assert len(study.angles) > 1 and len(study.scales) > 1


def test_record_file_with_units_loads_as_the_catalog_record(write_study):
    """A record given as a file (MiniSEED, m/s^2) is the same samples as its catalog entry."""
    from pathlib import Path

    from pipeline.groundmotion import load
    from pipeline.study import load_motions

    mseed = Path(__file__).parents[2] / "records" / "synthetic" / "SYN-RICKER.mseed"
    start = SMALL_STUDY.index("synthetic = [")
    end = SMALL_STUDY.index("[excitation]")
    text = SMALL_STUDY[:start] + f'files = [{{path = "{mseed}", units = "m/s2", id = "ricker-file"}}]\n\n' \
        + SMALL_STUDY[end:]
    study = load_study(write_study(text))
    assert [r.id for r in study.records] == ["ricker-file"] and study.records[0].kind == "file"
    assert load_motions(study)[0].sha256() == load("SYN-RICKER").sha256()


@pytest.mark.parametrize("measure, wrong, choices", [
    ("pga", None, 'units = "g" or units = "m/s2"'),
    ("pga", '"gal"', 'units = "g" or units = "m/s2"'),
    ("pgv", '"m/s2"', 'units = "m/s" or units = "cm/s"'),
])
def test_intensity_units_are_required_and_the_choices_named(write_study, measure, wrong, choices):
    units = f", units = {wrong}" if wrong else ""
    text = _broken("scales = [0.5, 1.0, 2.0]", f'intensity = {{measure = "{measure}"{units}, values = [0.3]}}')
    with pytest.raises(InputError, match="field excitation.intensity.units: ") as info:
        load_study(write_study(text))
    assert choices in str(info.value)


def test_intensity_targets_in_g_are_converted_once(write_study):
    """``values = [0.3]`` with ``units = "g"`` is 0.3 g = 2.941995 m/s^2, never 0.3 m/s^2 (issue 11)."""
    g = load_study(write_study(_broken("scales = [0.5, 1.0, 2.0]",
                                       'intensity = {measure = "pga", units = "g", values = [0.1, 0.3]}')))
    si = load_study(write_study(_broken("scales = [0.5, 1.0, 2.0]",
                                        'intensity = {measure = "pga", units = "m/s2", values = [0.980665, 2.941995]}'),
                                name="si.toml"))
    assert g.intensity.values == si.intensity.values == (0.980665, 2.941995)  # exact: 0.1 * 9.80665 == 0.980665
    assert g.intensity.stated == (0.1, 0.3) and g.intensity.units == "g"
    assert g.levels == si.levels


def test_shipped_studies_state_their_intensity_units():
    from pathlib import Path

    root = Path(__file__).parents[2]
    for path in sorted(root.glob("studies/**/*.toml")):
        study = load_study(path, load_records=False)
        if study.intensity is not None:
            assert study.intensity.units in ("g", "m/s2", "m/s", "cm/s"), path


# -- what a study is refused before computing, as the command line would refuse it (issue 38, item 1) --

# A column of the paper's outline, one short record, the rigid and the compliant model; parsed only
# (load_records=False, or study check): nothing here is computed.
CHECKS = """\
title = "checks"
output = "checks.nc"
models = ["3d", "3d-compliant"]

[[columns]]
name = "mono"
R = 0.5
r = 0.4
h = 4.0

[records]
synthetic = [{generator = "ricker_wavelet", id = "ricker", ap = 4.0, fp = 2.0, dt = 0.01}]

[excitation]
angles = [0.0]
scales = [1.0]

[options]
tail = 0.5
"""


def _checks(*pairs):
    """CHECKS with each (old, new) replaced."""
    text = CHECKS
    for old, new in pairs:
        assert old in text, old
        text = text.replace(old, new)
    return text


_MODELS = 'models = ["3d", "3d-compliant"]'
_TAIL = "tail = 0.5"


def _error_line(err):
    lines = [line for line in err.splitlines() if line.startswith("frustum: error: ")]
    assert len(lines) == 1, err
    return lines[0][len("frustum: error: "):]


_EXPLICIT = ('[models.3d]\nmodel = "3d"\n\n[models.3d-compliant]\nmodel = "3d-compliant"\n'
             'numerics = { springs = "explicit" }')


def test_a_step_above_the_stability_limit_is_refused_in_the_words_of_simulate(write_study, tmp_path, capsys):
    """``frustum simulate --step 0.01`` refuses at once (above twice the limit, where the springs at the
    step's end would damp too much); the study check says the same of the same column; with the springs
    at the step's start the limit itself is refused, in the words of ``simulate()``."""
    path = write_study(_checks((_TAIL, _TAIL + "\nstep = 0.01")))
    assert main(["study", "check", str(path)]) == 2
    study = _error_line(capsys.readouterr().err)
    assert main(["simulate", "--column", "0.5,0.4,4", "--record", "SYN-RICKER", "--model", "3d-compliant",
                 "--step", "0.01", "--out", str(tmp_path / "h.nc")]) == 2
    simulate = _error_line(capsys.readouterr().err)
    assert simulate.startswith("step = 0.01 s is above twice the stability limit")
    assert study == f"{path}: field options.step: column 'mono', model 3d-compliant: {simulate}"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["study.toml"]  # nothing written by either
    path = write_study(_checks((_TAIL, _TAIL + "\nstep = 0.0015"), (_MODELS, _EXPLICIT)))
    assert main(["study", "check", str(path)]) == 2
    study = _error_line(capsys.readouterr().err)
    from pipeline.groundmotion import load
    from pipeline.settings import Excitation, ModelSettings
    from pipeline.simulate import simulate as run
    from pipeline.structures.column import Column

    with pytest.raises(InputError) as refused:
        run(Column(0.5, 0.4, 4.0), load("SYN-RICKER"), Excitation(),
            ModelSettings(model="3d-compliant", step=0.0015, tail=0.5, numerics=(("springs", "explicit"),)))
    assert str(refused.value).startswith("step = 0.0015 s is at or above the stability limit")
    assert study == f"{path}: field options.step: column 'mono', model 3d-compliant: {refused.value}"


def test_the_stability_limit_is_checked_for_every_column_as_each_model_runs_it(write_study):
    """Four drums have a shorter stability limit than their monolith (lighter bodies on the same
    joints): a step between the two limits is refused for the drums of the model that runs them,
    and taken by a variant that runs the column's outline."""
    from pipeline.compliant import as_stack, assemble, fixed_step
    from pipeline.compliant.rest import laid_state
    from pipeline.settings import ModelSettings
    from pipeline.structures.column import Column
    from pipeline.structures.drums import DrumColumn

    def limit(column):
        probe = assemble(as_stack(column), ModelSettings(model="3d-compliant"), 0.0)
        return fixed_step(probe, probe.params(), laid_state(probe), ModelSettings(model="3d-compliant"))[1]

    mono = Column(0.5, 0.4, 4.0)
    low, high = limit(DrumColumn.equal(mono, 4)), limit(mono)
    assert low < 0.7 * high  # the premise of the test
    step = (low * high) ** 0.5
    drums = '[[columns]]\nname = "four"\nR = 0.5\nr = 0.4\nh = 4.0\ndrums = 4\n\n[records]'
    variants = ('[models.rigid]\nmodel = "3d"\n\n[models.stack]\nmodel = "3d-compliant"\n'
                'numerics = { springs = "explicit" }\n\n'
                '[models.outline]\nmodel = "3d-compliant"\nnumerics = { springs = "explicit" }\nbody = "outline"')
    text = _checks((_TAIL, f"{_TAIL}\nstep = {step!r}"), ("[records]", drums), (_MODELS, variants))
    with pytest.raises(InputError, match=rf"field options\.step: column 'four', model stack: step = {step:g} s is "
                       rf"at or above the stability limit {low:.3g} s"):
        load_study(write_study(text), load_records=False)
    # the stack at a step of its own below its limit: the outline's step is checked on the monolith alone
    own = f'[models.stack]\nmodel = "3d-compliant"\nnumerics = {{ springs = "explicit" }}\noptions = {{step = {0.9 * low!r}}}\n'
    study = load_study(write_study(text.replace('[models.stack]\nmodel = "3d-compliant"\nnumerics = { springs = "explicit" }\n', own)), load_records=False)
    assert study.settings("outline").step == step and study.settings("stack").step == 0.9 * low


UNREAD = {  # (replacements of CHECKS, field, fragment of the message)
    "step of rigid models only": (((_MODELS, 'models = ["3d", "2d"]'), (_TAIL, _TAIL + "\nstep = 1e-5")),
                                  "options.step", "it is an option of 3d-compliant"),
    "monitor_step of the fixed-step integrator": (((_TAIL, _TAIL + "\nmonitor_step = 0.002"),), "options.monitor_step",
                                                  "3d-compliant does not read it with integrator = semi-implicit"),
    "an option every model sets for itself": (
        ((_MODELS, '[models.a]\nmodel = "3d"\noptions = {friction = 0.5}\n\n[models.b]\nmodel = "3d-compliant"\n'
                   'options = {friction = 0.6}'), (_TAIL, _TAIL + "\nfriction = 0.4")),
        "options.friction", "a sets its own, models.a.options.friction; b sets its own"),
    "contact_damping beside a calibrated bed": (
        ((_MODELS, '[models.a]\nmodel = "3d"\n\n[models.b]\nmodel = "3d-compliant"\n\n[calibration]\nbed = "b"'),
         (_TAIL, _TAIL + "\ncontact_damping = 1e5")),
        "options.contact_damping", "a gets the calibrated bed's, [calibration] bed = 'b'"),
    "a variant's restitution beside a calibrated bed": (
        ((_MODELS, '[models.a]\nmodel = "3d"\noptions = {restitution = 0.8}\n\n[models.b]\nmodel = "3d-compliant"\n\n'
                   '[calibration]\nbed = "b"'),), "models.a.options.restitution", "a gets the calibrated bed's"),
    "a variant's option of another model": (
        ((_MODELS, '[models.a]\nmodel = "3d"\noptions = {joint_friction = 0.5}'),), "models.a.options.joint_friction",
        "3d does not read joint_friction, an option of 3d-compliant"),
    "step_safety of an adaptive integrator": (
        ((_MODELS, '[models.a]\nmodel = "3d-compliant"\noptions = {integrator = "dopri5"}\n'
                   'numerics = {step_safety = 0.3}'),), "models.a.numerics.step_safety", "with integrator = dopri5"),
    "step_safety beside the study's step": (
        ((_MODELS, '[models.a]\nmodel = "3d-compliant"\nnumerics = {step_safety = 0.3}'),
         (_TAIL, _TAIL + "\nstep = 0.001")), "models.a.numerics.step_safety", "with step = 0.001"),
    "drum heights of rigid models": (
        ((_MODELS, 'models = ["3d", "2d"]'), ("h = 4.0", "h = 4.0\ndrum_heights = [2.0, 2.0]")),
        "columns[0].drum_heights", "no model of the study runs drums (3d, 2d run each column as one rigid body)"),
    "a capital on rigid models": (((_MODELS, 'models = ["2d"]'), ("h = 4.0", "h = 4.0\ncapital = [1.2, 0.5]")),
                                  "columns[0].capital", "(2d runs each column as one rigid body)"),
    "a grid of drums of rigid models": (
        ((_MODELS, 'models = ["3d"]'), ("[records]", "[column_grid]\nR = 0.5\nslenderness = 8.0\nbeta = 0.8\n"
                                                     "drums = [1, 4]\n\n[records]")),
        "column_grid.drums", "drums are run by 3d-compliant"),
    "the outline of a rigid model": (((_MODELS, '[models.a]\nmodel = "2d"\nbody = "outline"'),), "models.a.body",
                                     "2d runs the column's outline as one body already"),
    "a variant under another model's name": (((_MODELS, '[models.3d-compliant]\nmodel = "3d"'),),
                                             "models.3d-compliant", "may not be named '3d-compliant', the name of the "
                                             "registry model 3d-compliant (3D compliant drums on joints)"),
}


@pytest.mark.parametrize("case", sorted(UNREAD))
def test_what_no_model_of_the_study_reads_is_refused_naming_the_field(write_study, case):
    pairs, field, fragment = UNREAD[case]
    path = write_study(_checks(*pairs))
    with pytest.raises(InputError) as info:
        load_study(path, load_records=False)
    message = str(info.value)
    assert message.startswith(f"{path}: field {field}: "), message
    assert fragment in message, message


READ = {  # (replacements of CHECKS, what the study then holds)
    "a step some model reads": ((_TAIL, _TAIL + "\nstep = 0.001"),),
    "the bed's target restitution": ((_MODELS, '[models.a]\nmodel = "3d"\n\n[models.b]\nmodel = "3d-compliant"\n\n'
                                               '[calibration]\nbed = "b"'), (_TAIL, _TAIL + "\nrestitution = 0.8")),
    "monitor_step of an adaptive variant": ((_MODELS, '[models.a]\nmodel = "3d-compliant"\n\n[models.b]\n'
                                                      'model = "3d-compliant"\noptions = {integrator = "dopri5"}'),
                                            (_TAIL, _TAIL + "\nmonitor_step = 0.002")),
    "drums beside a model of drums": (("h = 4.0", "h = 4.0\ndrums = 2"),),
    "step_safety of the fixed step": ((_MODELS, '[models.a]\nmodel = "3d-compliant"\nnumerics = {step_safety = 0.3}'),),
    "a variant under its own model's name": (
        (_MODELS, '[models.3d]\n\n[models.2d]\nmodel = "2d"\noptions = {friction = 0.5}'),),
}


@pytest.mark.parametrize("case", sorted(READ))
def test_what_some_model_reads_is_taken(write_study, case):
    load_study(write_study(_checks(*READ[case])), load_records=False)


def test_one_component_drives_with_the_x_component_alone(write_study):
    """Issue 48: a drive in one direction, as a shake table gives it (Mouzakis et al. 2002): ``[excitation]
    components = "x"`` keeps each record's x component, its y set to zero before the records are scaled (so a
    stripe is that component's own peak), and the angles turn it (0 along x, 90 across). The processing log
    says so; the pair as recorded is the default."""
    import numpy as np

    from pipeline.study.grid import record_intensity
    from pipeline.study.studyfile import load_motions

    pair = load_study(write_study())
    one = load_study(write_study(_broken("scales = [0.5, 1.0, 2.0]", 'scales = [0.5, 1.0, 2.0]\ncomponents = "x"')))
    assert pair.components == "pair" and one.components == "x"
    assert np.any(load_motions(pair)[1].acc_y)  # kt-1 shakes both ways as recorded
    for a, b in zip(load_motions(pair), load_motions(one)):
        np.testing.assert_array_equal(b.acc_x, a.acc_x)
        assert not np.any(b.acc_y)
        assert any("one_component(keep='x')" in line for line in b.processing)
        assert record_intensity(b, None)["pga"] == pytest.approx(np.max(np.abs(a.acc_x)), rel=1e-15)
