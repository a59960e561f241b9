"""One netCDF convention for the three kinds of results file: labels select in plain xarray, CF checks pass.

The three kinds: the histories of ``frustum simulate`` (both models in one
file), the results of ``frustum study run`` and the fit of ``frustum
fragility``. Each is written by the package's own writers, opened with plain
``xarray.open_dataset`` (no project code) and checked with cfchecks, which
must run: the test set-up (``make test``) installs the UDUNITS-2 library it
loads, so a missing library fails here rather than skipping.
"""

import shutil
import subprocess
import sys
from pathlib import Path

import netCDF4
import numpy as np
import pytest
import xarray as xr

from pipeline import fragility as F
from pipeline.citation import REFERENCE
from pipeline.dataset import histories_file, write_netcdf
from pipeline.structures.column import Column
from pipeline.groundmotion.synthesis import one_sine_pulse
from pipeline.settings import Excitation, ModelSettings
from pipeline.simulate import simulate
from pipeline.study import load_study, run_study

CF_TABLES = Path(__file__).parent / "data" / "cf"

STUDY = """\
title = "one file of each kind: the study"
output = "study.nc"
models = ["3d", "2d"]
options = {tail = 1.0}
excitation = {angles = [0.0, 30.0], scales = [1.0, 2.0], sa_period = 0.5}
records = {synthetic = [{generator = "one_sine_pulse", id = "pulse", ap = 6.0, tp = 0.6, dt = 0.01}]}
columns = [{named = "pompeys-pillar"}, {name = "paper", R = 0.5, r = 0.4, h = 4.0}]
"""

# a study of imperfect drums (issue 48): the dimension seed and the draws on (column, seed, joint)
SEEDED = """\
title = "one file of each kind: a study of imperfect drums"
output = "seeded.nc"
models = ["3d", "3d-compliant"]
options = {tail = 0.2, contact_sectors = 8}
excitation = {scales = [1.0]}
records = {synthetic = [{generator = "one_sine_pulse", id = "pulse", ap = 3.0, tp = 0.6, dt = 0.01}]}
columns = [{name = "two", R = 0.5, r = 0.4, h = 4.0, drums = 2}]
imperfections = {tolerance = 0.002, seeds = [1, 2], friction_range = [0.5, 0.7]}
"""


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """{kind: path} of one file of each kind, written by the pipeline."""
    folder = tmp_path_factory.mktemp("convention")
    motion = one_sine_pulse(6.0, 0.6, dt=0.01, record_id="pulse")
    column = Column(0.5, 0.4, 4.0)
    runs = [simulate(column, motion, Excitation(angle=30.0), ModelSettings(model=m, tail=1.0))
            for m in ("3d", "2d")]
    # with the runs' summaries, as frustum simulate writes it: the CF check covers those variables too
    write_netcdf(histories_file([r.histories for r in runs], column="paper", record="pulse",
                                summaries=[r.summary for r in runs]), folder / "simulate.nc")
    (folder / "study.toml").write_text(STUDY, encoding="utf-8")
    run_study(load_study(folder / "study.toml"), serial=True, progress=False)
    F.write(F.fragility(F.open_results(folder / "study.nc"), bootstrap=5), folder / "fragility.nc")
    (folder / "seeded.toml").write_text(SEEDED, encoding="utf-8")
    run_study(load_study(folder / "seeded.toml"), serial=True, progress=False)
    return {kind: folder / f"{kind}.nc" for kind in ("simulate", "study", "fragility", "seeded")}


def test_simulate_file_selects_by_label_in_plain_xarray(files):
    with xr.open_dataset(files["simulate"]) as ds:
        assert list(ds["model"].values) == ["3d", "2d"]
        run = ds.sel(column="paper", record="pulse", model="2d")
        assert run["theta"].dims == ("time",)
        np.testing.assert_allclose(run["theta_deg"].values, np.degrees(run["theta"].values))
        assert run["theta_deg"].attrs["units"] == "degree"
        assert float(run["angle"]) == pytest.approx(30.0) and run["angle"].attrs["units"] == "degree"
        assert ds["time"].dtype == np.float64 and ds["time"].attrs["units"] == "s"
        assert "standard_name" not in ds["time"].attrs  # elapsed seconds, not a date
        assert float(ds["theta_crit_deg"].sel(column="paper")) == pytest.approx(15.10, abs=0.01)
        # the 2D model has no spin: NaN there, values for 3D
        assert np.isnan(run["psi"].values).all() and np.isfinite(ds["psi"].sel(model="3d").values).any()


def test_study_file_selects_by_label_in_plain_xarray(files):
    with xr.open_dataset(files["study"]) as ds:
        cell = ds.sel(column="paper", model="3d", record="pulse")
        assert cell["peak_theta"].dims == ("angle", "scale")
        np.testing.assert_allclose(cell["peak_theta_deg"].values, np.degrees(cell["peak_theta"].values))
        assert ds["residual_rotation_deg"].attrs["units"] == "degree"
        assert list(ds["column"].values) == ["pompeys-pillar", "paper"]
        assert float(ds["latitude"].sel(column="pompeys-pillar")) > 31


def test_fragility_file_selects_by_label_in_plain_xarray(files):
    with xr.open_dataset(files["fragility"]) as ds:
        cell = ds.sel(state="overturning", column="paper", model="2d")
        assert cell["median"].attrs["units"] == "m s-2"
        assert int(cell["n_runs"]) == 4  # 1 record x 2 angles x 2 scales
        assert float(ds["theta_crit_deg"].sel(column="paper")) == pytest.approx(15.10, abs=0.01)


@pytest.mark.parametrize("kind", ["simulate", "study", "fragility"])
def test_every_file_names_the_paper(files, kind):
    with netCDF4.Dataset(files[kind]) as nc:
        assert nc.references == REFERENCE


def _cfchecks():
    checker = shutil.which("cfchecks", path=str(Path(sys.executable).parent))
    assert checker, "cfchecks is missing: it is in the test extra (pip install -e '.[test]')"
    return checker


@pytest.mark.parametrize("kind", ["simulate", "study", "fragility", "seeded"])
def test_cf_checker_finds_no_error(files, kind, tmp_path):
    """cfchecks 4.1 knows CF up to 1.8: it checks a copy whose Conventions reads CF-1.8.

    We use nothing of CF 1.9/1.10. Offline tables (tests/data/cf): the subset
    of the standard-name table (version 93) with the names we write, and empty
    area-type and region tables. Accepted warning: column_R / column_r differ
    only by case (CF 2.3 warns); the names are the project's schema.
    """
    copy = tmp_path / f"{kind}.nc"
    shutil.copy(files[kind], copy)
    with netCDF4.Dataset(copy, "a") as nc:
        nc.Conventions = "CF-1.8"
    run = subprocess.run(
        [_cfchecks(), "-v", "1.8", "-s", str(CF_TABLES / "cf-standard-name-table-subset.xml"),
         "-a", str(CF_TABLES / "cf-area-type-table-empty.xml"), "-r", str(CF_TABLES / "cf-region-names-empty.xml"),
         str(copy)], capture_output=True, text=True, timeout=120,
    )
    out = run.stdout + run.stderr
    assert "udunits" not in out.lower(), ("cfchecks cannot load the UDUNITS-2 library: `make setup-test` installs "
                                          "it (Debian: apt-get install libudunits2-0)\n" + out)
    assert "ERRORS detected: 0" in out, out
    warnings = [line for line in out.splitlines() if line.startswith("WARN:")]
    assert warnings == ["WARN: (2.3): variable clash"], out
