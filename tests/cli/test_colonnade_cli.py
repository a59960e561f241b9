"""``frustum simulate --colonnade N --interaxial S --epistyle HEIGHT[,WIDTH] [--course HEIGHT]`` (issue 37, item 1).

A colonnade's run writes the frame's histories beside the models of single columns; every bad or
missing colonnade option is refused before computing, in one ``frustum: error:`` line that names
the option and the fix, with no file written.
"""

import math

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


@pytest.mark.parametrize("argv, fragments", [
    (SIM + ["--model", "2d-frame"], ["--model 2d-frame runs a colonnade", "give --colonnade N --interaxial S "
                                     "--epistyle HEIGHT", "--colonnade parthenon-east"]),
    (SIM + ROW + ["--model", "2d"], ["--colonnade is read by --model 3d-compliant, 2d-frame", "--model 2d does not run colonnades",
                                     "drop --colonnade"]),
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
     ["--colonnade parthenon-east is a named colonnade, which brings its column and epistyle: drop --column"]),
    (["simulate", "--model", "2d-frame", "--colonnade", "2", "--interaxial", "2", "--epistyle", "1", "--record",
      "SYN-RICKER"], ["give the column as --column R,r,h"]),
    (["simulate", "--column", "0.5,0.4,4", "--theta0", "5", "--duration", "1"] + ROW, ["--colonnade is read by"]),
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
