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
