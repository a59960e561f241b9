"""``frustum simulate --colonnade N --interaxial S --epistyle HEIGHT[,WIDTH] [--course HEIGHT]`` (issue 37, item 1).

A colonnade's run writes the frame's histories beside the models of single columns; every bad or
missing colonnade option is refused before computing, in one ``frustum: error:`` line that names
the option and the fix, with no file written.
"""

import math

import numpy as np
import pytest
import xarray as xr

from pipeline.cli import main
from pipeline.structures.colonnade import Colonnade, named_colonnade
from pipeline.structures.column import Column

SIM = ["simulate", "--column", "0.5,0.4,4", "--record", "SYN-RICKER"]
ROW = ["--colonnade", "3", "--interaxial", "1.5", "--epistyle", "0.5,0.9", "--course", "0.4"]


def test_a_colonnade_runs_as_a_frame_beside_the_single_column(tmp_path, capsys):
    out = tmp_path / "row.nc"
    assert main(SIM + ROW + ["--model", "2d,2d-frame", "--scale", "3", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "3 columns at 1.5 m carrying 2 epistyle block(s) 0.5 m high, 0.9 m wide and a course 0.4 m high" in text
    assert "2d-frame: peak theta" in text and "2d: peak theta" in text
    ds = xr.open_dataset(out).sel(column="R0.5-r0.4-h4-x3", record="SYN-RICKER")
    frame = ds.sel(model="2d-frame")
    assert float(abs(frame.epistyle_dx).max()) > 0 and math.isnan(float(ds.sel(model="2d").epistyle_dx.max()))
    # the frame's peak ratio is over its own critical tilt, not the column's
    row = Colonnade(Column(0.5, 0.4, 4.0), 3, 1.5, 0.5, 0.9, 0.4)
    assert float(frame.peak_theta_ratio) == pytest.approx(float(frame.peak_theta) / row.frame.alpha, rel=1e-12)
    assert "--colonnade 3 --interaxial 1.5 --epistyle 0.5,0.9 --course 0.4" in ds.attrs["history"]


def test_a_named_colonnade_brings_its_column(tmp_path, capsys):
    out = tmp_path / "front.nc"
    assert main(["simulate", "--model", "2d-frame", "--colonnade", "parthenon-east", "--record", "SYN-RICKER",
                 "--out", str(out)]) == 0
    assert named_colonnade("parthenon-east").describe() in capsys.readouterr().out
    ds = xr.open_dataset(out)
    assert list(ds.column.values) == ["parthenon-east"] and float(ds.column_R.values[0]) == 0.9525


def test_the_frame_beside_the_column_runs_as_in_a_study(tmp_path, capsys):
    """Issue 47, item 4: --model 2d,2d-frame with a capital runs as the same pair runs in a study (docs/studies.md):
    the frame runs the row, the 2d model the shaft alone, as if no capital were given. Before, it was refused
    blaming the capital. Here the column slides (friction 0.3) and rests sooner than the frame: the file holds
    both, the column's histories ending where its run did."""
    pulse = ["--record", "SYN-ONESINE", "--scale", "3", "--friction", "0.3", "--tail", "1"]
    both, alone = tmp_path / "both.nc", tmp_path / "alone.nc"
    assert main(["simulate", "--column", "0.5,0.4,4", "--capital", "1.0,0.4", "--colonnade", "3", "--interaxial", "2",
                 "--epistyle", "0.5", "--model", "2d,2d-frame", *pulse, "--out", str(both)]) == 0
    text = capsys.readouterr().out
    assert "2d: peak theta = 5.043 deg (0.33 theta_crit), stands, slid 93.7 mm" in text
    assert "2d-frame: peak theta = 4.441 deg (0.34 theta_crit), stands, slid 40.6 mm" in text
    assert main(["simulate", "--column", "0.5,0.4,4", "--model", "2d", *pulse, "--out", str(alone)]) == 0
    with xr.open_dataset(both) as ds, xr.open_dataset(alone) as one:
        column = ds.sel(model="2d").squeeze()
        single = one.sel(model="2d").squeeze()
        n = single.sizes["time"]
        assert ds.sizes["time"] > n  # the frame ran on
        np.testing.assert_array_equal(column.theta.values[:n], single.theta.values)
        assert np.isnan(column.theta.values[n:]).all() and (column.phase.values[n:] == single.phase.values[-1]).all()
        assert float(column.peak_theta) == float(single.peak_theta)


def test_a_named_colonnade_takes_a_course(tmp_path, capsys):
    out = tmp_path / "crowned.nc"
    assert main(["simulate", "--model", "2d-frame", "--colonnade", "parthenon-east", "--course", "1.9", "--record",
                 "SYN-RICKER", "--out", str(out)]) == 0
    assert named_colonnade("parthenon-east", course_height=1.9).describe() in capsys.readouterr().out
    with xr.open_dataset(out) as ds:
        assert "--colonnade parthenon-east --course 1.9" in ds.attrs["history"]
        crowned = named_colonnade("parthenon-east", course_height=1.9)
        run = ds.squeeze()
        assert float(run.peak_theta_ratio) == pytest.approx(float(run.peak_theta) / crowned.frame.alpha, rel=1e-12)
        assert crowned.frame.alpha != named_colonnade("parthenon-east").frame.alpha  # the course weighs


@pytest.mark.parametrize("argv, fragments", [
    (SIM + ["--model", "2d-frame"], ["--model 2d-frame runs a colonnade", "give --colonnade N --interaxial S "
                                     "--epistyle HEIGHT", "--colonnade parthenon-east"]),
    (SIM + ROW + ["--model", "2d"], ["no model of the run runs colonnades (2d runs the column alone), so --colonnade "
                                     "would be ignored; colonnades are run by 3d-compliant, 2d-frame: drop --colonnade"]),
    (SIM + ["--model", "2d-frame", "--colonnade", "2", "--interaxial", "2"], ["--colonnade 2: give --epistyle too"]),
    (SIM + ["--model", "2d-frame", "--colonnade", "2.5", "--interaxial", "2", "--epistyle", "1"],
     ["--colonnade 2.5: give a whole number of columns", "parthenon-east"]),
    (SIM + ["--model", "2d-frame", "--colonnade", "parthenon", "--interaxial", "2", "--epistyle", "1"],
     ["--colonnade parthenon: give a whole number of columns (at least 2), or the name of a named colonnade"]),
    (SIM + ["--model", "2d-frame", "--colonnade", "1", "--interaxial", "2", "--epistyle", "1"],
     ["colonnade columns = 1", "at least 2"]),
    (SIM + ["--model", "2d-frame", "--capital", "1.0,0.4", "--colonnade", "2", "--interaxial", "0.9", "--epistyle",
            "1"], ["colonnade interaxial = 0.9 m is less than the abacus side 1 m", "at least 1 m"]),
    (SIM + ["--model", "2d-frame", "--colonnade", "2", "--interaxial", "2", "--epistyle", "1,2,3"],
     ["--epistyle '1,2,3'", "height of the blocks, and optionally their width"]),
    (SIM + ["--model", "2d-frame", "--colonnade", "2", "--interaxial", "2", "--epistyle", "1", "--course", "-1"],
     ["colonnade course_height = -1.0 m", "0 or more"]),
    (SIM + ["--interaxial", "2"], ["--interaxial describes a colonnade: give --colonnade N"]),
    (SIM + ["--model", "2d-frame", "--colonnade", "parthenon-east"],
     ["--colonnade parthenon-east is a named colonnade, which brings its column and epistyle (--course may be "
      "added): drop --column"]),
    (["simulate", "--model", "2d-frame", "--colonnade", "2", "--interaxial", "2", "--epistyle", "1", "--record",
      "SYN-RICKER"], ["give the column as --column R,r,h"]),
    (["simulate", "--column", "0.5,0.4,4", "--theta0", "5", "--duration", "1"] + ROW,
     ["no model of the run runs colonnades (3d runs the column alone)"]),
])
def test_bad_colonnade_options_are_refused_before_computing(argv, fragments, tmp_path, capsys):
    out = tmp_path / "x.nc"
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv] + ["--out", str(out)]
    assert main(argv) == 2
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("frustum: error:"), err
    for fragment in fragments:
        assert fragment in lines[0]
    assert "Traceback" not in err and not out.exists()
