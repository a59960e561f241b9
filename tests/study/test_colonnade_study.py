"""Study files run colonnades: a column entry carries a row (a table, or a named colonnade); the models of
colonnades run it and the others the column, with the numbers of simulate() (issue 37, items 1 and 2)."""

import numpy as np
import pytest

from pipeline.errors import InputError
from pipeline.settings import Excitation
from pipeline.simulate import simulate
from pipeline.structures.colonnade import named_colonnade
from pipeline.study import load_motions, load_study, run_study

STUDY = """\
title = "colonnade"
output = "colonnade.nc"
models = ["2d", "2d-frame"]

[[columns]]
name = "row"
R = 0.5
r = 0.4
h = 4.0
capital = [1.0, 0.4]
colonnade = {columns = 3, interaxial = 2.0, epistyle_height = 0.5, course_height = 0.3}

[[columns]]
colonnade = "parthenon-east"

[records]
synthetic = [{generator = "ricker_wavelet", id = "ricker", ap = 4.0, fp = 2.0, dt = 0.01, duration = 2.0}]

[excitation]
angles = [0.0, 30.0]
scales = [1.0, 3.0]

[options]
tail = 1.0
"""


def test_a_study_runs_the_frame_on_each_columns_row_and_the_2d_model_on_the_column(write_study):
    study = load_study(write_study(STUDY))
    row, front = study.columns
    assert row.colonnade.n_columns == 3 and row.colonnade.course_height == 0.3 and row.colonnade.capital.side == 1.0
    named = named_colonnade("parthenon-east")  # the same row (only the labels differ)
    assert front.label == "parthenon-east" and front.colonnade.frame == named.frame
    assert front.colonnade.column.cuts == named.column.cuts and front.colonnade.capital == named.capital
    assert "parthenon" in front.source and front.column.R == 0.9525
    assert row.body(study.variant("2d-frame")) is row.colonnade
    ds = run_study(study, serial=True, progress=False).dataset
    assert np.all(ds.status.values == 0)
    motion = load_motions(study)[0]
    for info in study.columns:
        for model in ("2d", "2d-frame"):
            direct = simulate(info.body(study.variant(model)), motion, Excitation(angle=30.0, scale=3.0),
                              study.settings(model), histories=False).summary
            cell = ds.sel(column=info.label, model=model, angle=30.0, scale=3.0).isel(record=0)
            for name in ("peak_theta", "peak_theta_ratio", "uplift_time", "residual_displacement"):
                assert float(cell[name]) == direct[name] or (np.isnan(cell[name]) and np.isnan(direct[name])), name
    # the frame and the column alone differ: the epistyle changes the answer
    frame, alone = (ds.sel(column="row", model=m).peak_theta.values for m in ("2d-frame", "2d"))
    assert not np.allclose(frame, alone)


def test_a_named_colonnade_takes_a_course_as_its_comment_says(write_study):
    """colonnades.toml: "a study may add them as course_height" (the frieze and cornice it leaves out)."""
    text = STUDY.replace('colonnade = "parthenon-east"', 'colonnade = {named = "parthenon-east", course_height = 1.9}')
    study = load_study(write_study(text), load_records=False)
    front = study.columns[1]
    crowned, row = named_colonnade("parthenon-east", course_height=1.9), front.colonnade
    assert front.label == "parthenon-east" and row.course_height == 1.9
    assert (row.n_columns, row.interaxial, row.epistyle_height, row.epistyle_width, row.epistyle_mass) == \
        (crowned.n_columns, crowned.interaxial, crowned.epistyle_height, crowned.epistyle_width, crowned.epistyle_mass)
    assert front.source == load_study(write_study(STUDY), load_records=False).columns[1].source


@pytest.mark.parametrize("change, fragments", [
    (("colonnade = {columns = 3", "colonnade = {columns = 1"), ["columns[0].colonnade", "colonnade columns = 1"]),
    (("columns = 3, interaxial = 2.0", "columns = 3, interaxial = 0.5"),
     ["columns[0].colonnade", "less than the abacus side 1 m"]),
    ((", epistyle_height = 0.5", ""), ["columns[0].colonnade.epistyle_height", "missing"]),
    (("course_height = 0.3", "course_height = 0.3, frieze = 1"), ["columns[0].colonnade.frieze", "unknown field"]),
    (("columns = 3,", "columns = 3.5,"), ["columns[0].colonnade.columns", "whole number"]),
    (('colonnade = "parthenon-east"', 'colonnade = "nope"'), ["columns[1].colonnade", "'nope' is not a named "
                                                              "colonnade; known: parthenon-east"]),
    (('colonnade = "parthenon-east"', 'colonnade = "parthenon-east"\nR = 1.0'),
     ["columns[1].R", "is a named colonnade, which brings its column"]),
    (('[[columns]]\ncolonnade = "parthenon-east"\n', '[[columns]]\nnamed = "paper"\n'),
     ["field columns", "model '2d-frame' runs colonnades, and column 'paper' carries none"]),
    # issue 47, item 4: a named colonnade takes a course, nothing else
    (('colonnade = "parthenon-east"', 'colonnade = {named = "parthenon-east", interaxial = 4.0}'),
     ["field columns[1].colonnade.interaxial", "a named colonnade brings its columns, interaxial and epistyle: only "
      "course_height may be added to it"]),
    (('colonnade = "parthenon-east"', 'colonnade = {named = "parthenon-east", course_height = -1.0}'),
     ["field columns[1].colonnade", "course_height = -1.0 m", "0 or more"]),
    (('colonnade = "parthenon-east"', 'colonnade = {named = "nope", course_height = 1.0}'),
     ["field columns[1].colonnade", "'nope' is not a named colonnade"]),
    # and plausible dimensions, each with its reason
    (("interaxial = 2.0, epistyle_height = 0.5", "interaxial = 2.0, epistyle_height = 0.001"),
     ["field columns[0].colonnade", "epistyle_height = 0.001 m is less than 1/10 of its span"]),
    # a study of rigid columns alone ignores no colonnade: it refuses it, in simulate's words
    (('models = ["2d", "2d-frame"]', 'models = ["2d"]'),
     ["field columns[0].colonnade: no model of the study runs colonnades (2d runs the column alone)"]),
])
def test_a_bad_colonnade_names_its_field(write_study, change, fragments):
    text = STUDY.replace(*change)
    assert text != STUDY
    with pytest.raises(InputError) as err:
        load_study(write_study(text), load_records=False)
    for fragment in fragments:
        assert fragment in str(err.value)


COMPLIANT_ROW = """\
title = "a compliant frame"
output = "frame.nc"
models = ["3d-compliant"]

[[columns]]
name = "frame"
R = 0.5
r = 0.4
h = 4.0
capital = [1.0, 0.4]
colonnade = {columns = 2, interaxial = 2.0, epistyle_height = 0.5}

[[columns]]
name = "alone"
R = 0.5
r = 0.4
h = 4.0
drums = 2

[records]
synthetic = [{generator = "ricker_wavelet", id = "ricker", ap = 2.0, fp = 2.0, dt = 0.01, duration = 1.0}]

[excitation]
angles = [0.0, 90.0]
scales = [1.0]

[options]
tail = 0.5
contact_sectors = 8
"""


def test_the_report_of_a_colonnade_study_says_what_stood_and_how_the_epistyle_moved(write_study, tmp_path):
    """Issue 37, item 4: the results name each structure in words (the study check's words), and the report
    describes it, explains the colonnade's outcome and tables the epistyle's slip and opening of the runs
    that stood, as the results hold them (a column alone has none)."""
    from pipeline.fragility import open_results
    from pipeline.report import write_report

    study = load_study(write_study(COMPLIANT_ROW))
    frame, alone = study.columns
    ds = run_study(study, serial=True, progress=False).dataset
    assert list(ds["structure"].values) == [frame.describe(), alone.stack.describe()]
    assert frame.colonnade.describe() == f"frame: {frame.describe()}"  # the label is not said twice
    assert "2 columns at 2 m carrying 1 epistyle block(s) 0.5 m high" in str(ds["structure"].values[0])
    assert np.isnan(ds.epistyle_slip.sel(column="alone")).all()
    path = tmp_path / "frame.nc"
    ds.to_netcdf(path)
    written = write_report(open_results(path), tmp_path / "report", bootstrap=0)
    text = open(written["report"], encoding="utf-8").read()
    assert f"- **frame**: {frame.describe()}." in text
    assert f"- **alone**: {alone.stack.describe()}." in text
    assert "falls off the body it rests on" in text
    section = text.split("## What falls first, and what the standing ones keep")[1].split("\n## ")[0]
    section = section[section.index("Of the runs that stood"):]
    rows = [line for line in section.splitlines() if line.startswith("| frame |")]
    # the stripe, all stripes, and all stripes at each angle (report_colonnade); the column alone has none
    assert len(rows) == 4 and not any(line.startswith("| alone |") for line in section.splitlines())
    for line, angle in zip(rows[2:], (0.0, 90.0)):
        cell = ds.sel(column="frame", model="3d-compliant", angle=angle).isel(record=0, scale=0)
        stood = int(cell.overturned) == 0
        cells = [x.strip() for x in line.strip("|").split("|")]
        assert cells[2:5] == ["all", f"{angle:g}", str(int(stood))]
        if stood:
            assert cells[5] == f"{1e3 * float(cell.epistyle_slip):.3g}"
