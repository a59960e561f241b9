"""``frustum risk`` and ``frustum report --hazard`` end to end on small synthetic inputs (issue 27).

Every refusal: exit status 2, one line naming the option or file and the fix, no traceback, the
user's files byte-identical.
"""

import csv
import math
import shutil

import pytest
import xarray as xr
from cli_files import snapshot, unchanged
from hazard_files import example_openquake_text, openquake_text

from pipeline.cli import main
from pipeline.paths import result_kind


def _err(capsys):
    err = capsys.readouterr().err
    assert "Traceback" not in err
    return err


@pytest.fixture(scope="module")
def inputs(results_nc, tmp_path_factory):
    """(fragility.nc with 20 bootstrap replicates, an OpenQuake PGA curve of two sites, an SA(1.0) curve)."""
    folder = tmp_path_factory.mktemp("risk-inputs")
    frag = folder / "frag.nc"
    assert main(["fragility", str(results_nc), "--out", str(frag), "--bootstrap", "20"]) == 0
    pga = folder / "hazard_curve-mean-PGA_1.csv"
    pga.write_bytes(example_openquake_text().encode())
    sa = folder / "hazard_curve-mean-SA(1.0)_1.csv"
    sa.write_bytes(openquake_text([0.05, 0.2, 0.8], [[0.3, 0.05, 0.002]], [(1.0, 2.0)], imt="SA(1.0)").encode())
    return frag, pga, sa


def test_risk_end_to_end(inputs, tmp_path, capsys):
    frag, pga, _ = inputs
    out, table, fig = tmp_path / "risk.nc", tmp_path / "risk.csv", tmp_path / "risk.png"
    assert main(["risk", str(frag), "--hazard", str(pga), "--years", "50", "--out", str(out), "--csv", str(table),
                 "--plot", str(fig)]) == 0
    text = capsys.readouterr().out
    assert "site-0 paper 3d overturning:" in text and "in 50 yr" in text and "about 1 in" in text
    assert result_kind(out) == "risk"
    with xr.open_dataset(out) as ds:
        cell = ds.sel(site="site-0", column="paper", model="3d", state="overturning")
        lam = float(cell["annual_frequency"])
        assert 0 < lam < 1
        assert float(cell["probability_in_period"]) == pytest.approx(-math.expm1(-50 * lam), rel=1e-12)
        assert math.isfinite(float(cell["annual_frequency_band_lower"]))  # the 20 replicates gave a band
        assert ds.attrs["hazard_level_units_in_file"] == "g" and ds["hazard_level"].attrs["units"] == "m s-2"
    with open(table, encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 2 * 4  # 2 sites x 1 column x 1 model x 4 states
    assert float(rows[0]["annual_frequency_per_yr"]) == pytest.approx(lam, rel=1e-3)  # 4 significant digits
    assert fig.stat().st_size > 10_000
    # a rerun overwrites its own outputs
    assert main(["risk", str(frag), "--hazard", str(pga), "--out", str(out), "--csv", str(table), "--years", "100"]) == 0
    with xr.open_dataset(out) as ds:
        assert float(ds["years"]) == 100.0


def test_plain_two_column_curve(inputs, tmp_path):
    frag, _, _ = inputs
    curve = tmp_path / "site.csv"
    curve.write_text("# made-up site\nPGA [g],annual_rate [1/yr]\n0.05,0.05\n0.1,0.012\n0.3,0.0012\n0.6,0.00015\n"
                     "1.0,0.00002\n")
    assert main(["risk", str(frag), "--hazard", str(curve), "--out", str(tmp_path / "r.nc")]) == 0


@pytest.mark.parametrize("case, words", [
    ("sa", "the hazard curve is for Sa(T = 1 s) but the fragility"),
    ("missing", "no such file"),
    ("years", "--years -5: give a positive number of years"),
    ("badcurve", "name the intensity measure and its unit"),
    ("out-is-input", "is the fragility file this command reads"),
    ("out-over-user-file", "exists and is not a netCDF result written by frustum"),
    ("csv-over-user-file", "is not a CSV written by 'frustum risk'"),
    ("state", "--state 'collapse' is not in"),
    ("not-a-fragility", "not a fragility file"),
])
def test_risk_refuses_bad_input_in_one_line(inputs, results_nc, user_files, tmp_path, capsys, case, words):
    frag, pga, sa = inputs
    out = tmp_path / "risk.nc"
    bad = tmp_path / "bad.csv"
    bad.write_text("PGA,rate\n0.1,0.01\n0.2,0.001\n")
    args = {
        "sa": [str(frag), "--hazard", str(sa), "--out", str(out)],
        "missing": [str(frag), "--hazard", str(tmp_path / "nope.csv"), "--out", str(out)],
        "years": [str(frag), "--hazard", str(pga), "--out", str(out), "--years", "-5"],
        "badcurve": [str(frag), "--hazard", str(bad), "--out", str(out)],
        "out-is-input": [str(frag), "--hazard", str(pga), "--out", str(frag)],
        "out-over-user-file": [str(frag), "--hazard", str(pga), "--out", str(user_files["notes.txt"])],
        "csv-over-user-file": [str(frag), "--hazard", str(pga), "--out", str(out), "--csv",
                               str(user_files["notes.txt"])],
        "state": [str(frag), "--hazard", str(pga), "--out", str(out), "--state", "collapse"],
        "not-a-fragility": [str(results_nc), "--hazard", str(pga), "--out", str(out)],
    }[case]
    before = snapshot(frag, pga, sa, *user_files.values())
    assert main(["risk", *args]) == 2
    err = _err(capsys)
    assert words in err and len(err.strip().splitlines()) == 1, err
    assert unchanged(before)
    assert not out.exists()


def test_risk_refuses_to_replace_another_kind_of_result(inputs, results_nc, tmp_path, capsys):
    frag, pga, _ = inputs
    other = tmp_path / "study.nc"
    shutil.copy(results_nc, other)
    before = snapshot(other)
    assert main(["risk", str(frag), "--hazard", str(pga), "--out", str(other)]) == 2
    assert "is a results file of 'frustum study run'" in _err(capsys)
    assert unchanged(before)


def test_report_with_hazard_states_the_risk_in_plain_words(results_nc, inputs, tmp_path, capsys):
    _, pga, sa = inputs
    folder = tmp_path / "report"
    assert main(["report", str(results_nc), "--out", str(folder), "--hazard", str(pga), "--bootstrap", "10"]) == 0
    text = (folder / "report.md").read_text(encoding="utf-8")
    assert "## Risk at the site" in text
    assert "chance of overturning in 50 years**" in text and "on average once in" in text
    assert (folder / "risk.nc").is_file() and (folder / "risk.csv").is_file()
    assert result_kind(folder / "risk.nc") == "risk"
    assert "risk_paper" in text  # the figure
    # an Sa curve is refused before any fitting, naming both measures
    assert main(["report", str(results_nc), "--out", str(tmp_path / "r2"), "--hazard", str(sa)]) == 2
    err = _err(capsys)
    assert "Sa(T = 1 s)" in err and "against PGA" in err
    assert not (tmp_path / "r2").exists()
    assert main(["report", str(results_nc), "--out", str(tmp_path / "r3"), "--years", "20"]) == 2
    assert "give --hazard" in _err(capsys)
