"""``frustum fragility`` and ``frustum report`` round trips on a small synthetic study."""

import csv
import json
import math
import os

import numpy as np
import pytest
import xarray as xr
from fragility_synthetic import make_results

from pipeline import fragility as F
from pipeline.cli import main
from pipeline.report import DEFAULT_PGA_LEVELS_G, _fmt, _pct
from pipeline.units import G


@pytest.fixture(scope="module")
def study_file(tmp_path_factory):
    ds, _ = make_results(n_records=8, coordinates=True, seed=21)
    path = tmp_path_factory.mktemp("study") / "results.nc"
    ds.to_netcdf(path)
    return path, ds


def test_fragility_cli_round_trip(study_file, tmp_path, capsys):
    path, ds = study_file
    out = tmp_path / "frag.nc"
    assert main([ "fragility", str(path), "--out", str(out), "--bootstrap", "20", "--seed", "3"]) == 0
    printed = capsys.readouterr().out
    assert "paper 3d: overturning median pga" in printed
    expected = F.fragility(F.open_results(path), bootstrap=20, seed=3)
    with xr.open_dataset(out) as back:
        for name in ("median", "beta", "median_lower", "median_upper", "beta_lower", "beta_upper"):
            np.testing.assert_array_equal(back[name].values, expected[name].values)
        assert list(back["state"].values) == ["overturning", "theta_ratio_0.25", "theta_ratio_0.5", "theta_ratio_1"]
        assert back["median"].attrs["units"] == "m s-2"
        assert back.attrs["bootstrap_seed"] == 3


def test_fragility_cli_options(study_file, tmp_path):
    path, _ = study_file
    out = tmp_path / "frag.nc"
    assert main(["fragility", str(path), "--out", str(out), "--im", "pgv", "--states", "0.3"]) == 0
    with xr.open_dataset(out) as back:
        assert back["median"].attrs["units"] == "m s-1"
        assert list(back["state"].values) == ["overturning", "theta_ratio_0.3"]


def test_fragility_cli_counts_undecided_runs_as_asked(study_file, tmp_path, capsys):
    """Issue 47, item 5: ``--undecided`` says how runs still able to fall at their settle limit count; the
    console says how many there were and how they counted, the file says the choice."""
    _, ds = study_file
    ds = ds.copy()
    undecided = np.zeros(ds["overturned"].shape, np.int8)
    undecided[0, :2, :, 2, :] = 1  # paper: 2 records at scale 1
    ds["undecided"] = (ds["overturned"].dims, undecided)
    ds["overturned"] = ds["overturned"].where(undecided == 0, 0)  # an undecided run has not overturned
    path = tmp_path / "results.nc"
    ds.to_netcdf(path)
    medians = {}
    for choice in ("standing", "overturned"):
        out = tmp_path / f"{choice}.nc"
        assert main(["fragility", str(path), "--out", str(out), "--undecided", choice]) == 0
        assert f"2 undecided counted as {choice})" in capsys.readouterr().out
        with xr.open_dataset(out) as back:
            assert back.attrs["undecided_runs"].startswith(choice)
            medians[choice] = float(back["median"].sel(state="overturning", column="paper", model="3d"))
    assert medians["overturned"] < medians["standing"]
    with pytest.raises(SystemExit) as refused:
        main(["fragility", str(path), "--out", str(tmp_path / "x.nc"), "--undecided", "fell"])
    assert refused.value.code == 2
    assert "--undecided: invalid choice: 'fell'" in capsys.readouterr().err


@pytest.mark.parametrize("argv, message", [
    (["--im", "sa"], "intensity measure 'sa' is not in the dataset"),
    (["--states", "a,b"], "--states"),
    (["--confidence", "1.5"], "confidence"),
])
def test_fragility_cli_bad_input(study_file, tmp_path, capsys, argv, message):
    path, _ = study_file
    assert main(["fragility", str(path), "--out", str(tmp_path / "x.nc"), *argv]) == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "x.nc").exists()


def test_fragility_cli_missing_file_and_variable(tmp_path, capsys, study_file):
    assert main(["fragility", str(tmp_path / "none.nc"), "--out", str(tmp_path / "x.nc")]) == 2
    assert "no such file" in capsys.readouterr().err
    path, ds = study_file
    broken = tmp_path / "broken.nc"
    ds.drop_vars("overturned").to_netcdf(broken)
    assert main(["fragility", str(broken), "--out", str(tmp_path / "x.nc")]) == 2
    assert "'overturned' is missing" in capsys.readouterr().err


def test_report_files_and_numbers_equal_the_dataset(study_file, tmp_path):
    path, ds = study_file
    out = tmp_path / "report"
    assert main(["report", str(path), "--out", str(out), "--bootstrap", "10"]) == 0
    text = (out / "report.md").read_text()
    frag = F.fragility(F.open_results(path), bootstrap=10, seed=0)
    # figures exist, as PNG and PDF, and each PNG is embedded
    figures = sorted(p for p in os.listdir(out / "figures") if p.endswith(".png"))
    assert figures and all((out / "figures" / p.replace(".png", ".pdf")).exists() for p in figures)
    for name in figures:
        assert f"(figures/{name})" in text
    # CSV: one row per column and model, numbers equal the fragility dataset and the results
    with open(out / "summary.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == ds.sizes["column"] * ds.sizes["model"]
    for row in rows:
        cell = frag.sel(state="overturning", column=row["column"], model=row["model"])
        assert float(row["median_pga_overturning_m_s2"]) == pytest.approx(float(cell["median"]), rel=5e-4)  # 4 digits
        assert float(row["beta_overturning"]) == pytest.approx(float(cell["beta"]), rel=5e-4)
        assert float(row["median_pga_overturning_g"]) == pytest.approx(float(cell["median"]) / G, rel=5e-4)
        one = ds.sel(column=row["column"], model=row["model"])
        if row["model"] == "3d":
            one = one.isel(angle=[0])
        valid = one["status"] == 0
        assert int(row["runs"]) == int(valid.sum())
        assert int(row["runs_overturned"]) == int(((one["overturned"] == 1) & valid).sum())
        for level in DEFAULT_PGA_LEVELS_G:
            p = F.probability(level * G, float(cell["median"]), float(cell["beta"]))
            assert float(row[f"p_overturning_at_{level:g}g"]) == pytest.approx(float(p), rel=5e-4, abs=1e-300)
            # ... and the same number, as printed, is in the Markdown
            assert _pct(float(p)) in text
        assert _fmt(float(cell["median"]) / G) in text
    # the 2D-against-3D section states the medians and their ratio from the fit
    assert "## 2D against 3D" in text
    for c in ds["column"].values:
        m3 = float(frag["median"].sel(state="overturning", column=c, model="3d"))
        m2 = float(frag["median"].sel(state="overturning", column=c, model="2d"))
        assert f"| {c} | {_fmt(m3 / G)} | {_fmt(m2 / G)} | {_fmt(m2 / m3)} |" in text
    # stated levels in g and m/s^2
    assert "P at 0.3 g (2.94 m/s²)" in text
    # GeoJSON: the columns carry coordinates
    geo = json.loads((out / "columns.geojson").read_text())
    assert len(geo["features"]) == len(rows)
    lon, lat = geo["features"][0]["geometry"]["coordinates"]
    assert lat == pytest.approx(float(ds["latitude"].values[0]))
    assert (out / "fragility.nc").exists()


def test_report_stripe_fractions_are_the_runs(study_file, tmp_path):
    """The per-stripe fractions in the report are counted from the runs, not from the fit."""
    path, ds = study_file
    from pipeline.report import write_report

    res = F.open_results(path)
    out = write_report(res, tmp_path / "r", bootstrap=0)
    text = open(out["report"]).read()
    for c in ds["column"].values:
        for k, s in enumerate(ds["scale"].values):
            f3 = float(ds["overturned"].sel(column=c, model="3d", scale=s).isel(angle=0)
                       .where(ds["status"].sel(column=c, model="3d", scale=s).isel(angle=0) == 0).mean())
            f2 = float(ds["overturned"].sel(column=c, model="2d", scale=s)
                       .where(ds["status"].sel(column=c, model="2d", scale=s) == 0).mean())
            assert f"| {_pct(f3)} | {_pct(f2)} |" in text


def test_report_without_overturning_and_single_model(tmp_path):
    ds, _ = make_results(n_records=4, models=("3d",), columns=("paper",), scales=(0.01, 0.02))
    from pipeline.report import write_report

    out = write_report(ds, tmp_path / "r", bootstrap=5)
    text = open(out["report"]).read()
    assert "no exceedance observed" in text
    assert "## 2D against 3D" not in text
    assert out["geojson"] is None
    assert math.isnan(float(out["frag"]["median"].sel(state="overturning").item()))
