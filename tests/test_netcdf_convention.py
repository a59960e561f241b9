"""One netCDF convention for the kinds of results file: labels select in plain xarray, CF checks pass.

The kinds: the histories of ``frustum simulate`` (both models in one
file), the results of ``frustum study run``, the fit of ``frustum
fragility`` and the site risk of ``frustum risk``, each also of a colonnade
(issue 47: the files say what stood and which models ran it). Each is
written by the package's own writers, opened with plain
``xarray.open_dataset`` (no project code) and checked with cfchecks, which
must run: the test set-up (``make test``) installs the UDUNITS-2 library it
loads, so a missing library fails here rather than skipping.
"""

import math
import shutil
import subprocess
import sys
from pathlib import Path

import netCDF4
import numpy as np
import pytest
import xarray as xr

from pipeline import fragility as F
from pipeline import risk as R
from pipeline.citation import REFERENCE
from pipeline.dataset import histories_file, write_netcdf
from pipeline.structures.column import Column
from pipeline.groundmotion.synthesis import one_sine_pulse
from pipeline.settings import Excitation, ModelSettings
from pipeline.simulate import simulate
from pipeline.structures import description as D
from pipeline.structures.colonnade import Colonnade
from pipeline.structures.drums import Capital, DrumColumn
from pipeline.study import load_study, run_study

CF_TABLES = Path(__file__).parent / "data" / "cf"
HAZARD = Path(__file__).parent / "data" / "hazard" / "hazard_curve-mean-PGA_1.csv"

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


# a row of two of the paper's columns with capitals under one epistyle block, run by the models of colonnades and
# (its column alone) by the 3D model; the compliant run rocks on for longer than the frame's (settle limit)
ROW_STUDY = """\
title = "a row of two columns"
output = "row_study.nc"
models = ["3d", "3d-compliant", "2d-frame"]
options = {tail = 2.0, contact_sectors = 8}
excitation = {angles = [0.0], scales = [0.5, 2.0]}
records = {synthetic = [{generator = "one_sine_pulse", id = "pulse", ap = 3.0, tp = 1.0, dt = 0.01}]}
[[columns]]
name = "row"
R = 0.5
r = 0.4
h = 4.0
capital = [1.1, 0.3]
colonnade = {columns = 2, interaxial = 2.5, epistyle_height = 0.8}
"""
ROW = Colonnade(DrumColumn(Column(0.5, 0.4, 4.0), capital=Capital(1.1, 0.3)), 2, 2.5, 0.8)
KINDS = ["simulate", "study", "fragility", "row_simulate", "row_study", "row_fragility", "row_risk", "seeded"]


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
    pulse = one_sine_pulse(3.0, 0.4, dt=0.01, record_id="pulse")
    runs = [simulate(ROW, pulse, Excitation(), ModelSettings(model=m, tail=0.5, **extra))
            for m, extra in (("3d-compliant", {"contact_sectors": 8}), ("2d-frame", {}))]
    assert runs[0].histories.sizes["time"] > runs[1].histories.sizes["time"]  # the premise: one grid, two ends
    write_netcdf(histories_file([r.histories for r in runs], column="row", record="pulse",
                                summaries=[r.summary for r in runs]), folder / "row_simulate.nc")
    (folder / "row.toml").write_text(ROW_STUDY, encoding="utf-8")
    run_study(load_study(folder / "row.toml"), serial=True, progress=False)
    F.write(F.fragility(F.open_results(folder / "row_study.nc"), bootstrap=5), folder / "row_fragility.nc")
    frag = R.open_fragility(folder / "row_fragility.nc")
    R.write(R.site_risk(frag, R.read_hazard_curve(HAZARD)), folder / "row_risk.nc")
    (folder / "seeded.toml").write_text(SEEDED, encoding="utf-8")
    run_study(load_study(folder / "seeded.toml"), serial=True, progress=False)
    return {kind: folder / f"{kind}.nc" for kind in KINDS}


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


@pytest.mark.parametrize("kind", KINDS)
def test_every_file_names_the_paper(files, kind):
    with netCDF4.Dataset(files[kind]) as nc:
        assert nc.references == REFERENCE


def _cfchecks():
    checker = shutil.which("cfchecks", path=str(Path(sys.executable).parent))
    assert checker, "cfchecks is missing: it is in the test extra (pip install -e '.[test]')"
    return checker


# a risk file's rates in year-1 draw the checker's caution on UDUNITS' year, a matter of the risk files' own
@pytest.mark.parametrize("kind", [k for k in KINDS if k != "row_risk"])
def test_cf_checker_finds_no_error(files, kind, tmp_path):
    """cfchecks 4.1 knows CF up to 1.8: it checks a copy whose Conventions reads CF-1.8.

    We use nothing of CF 1.9/1.10. Offline tables (tests/data/cf): the subset
    of the standard-name table (version 93) with the names we write, and empty
    area-type and region tables. Accepted warning: column_R / column_r (and
    drum_R / drum_r) differ only by case (CF 2.3 warns); the names are the
    project's schema. A
    colonnade's files too: every variable and coordinate with its units (before
    issue 47, drum_x and drum_y had none and drum_kind's flags were a
    coordinate's; a colonnade's file of two models could not be written).
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
    # column_R / column_r, and in a compliant file drum_R / drum_r
    assert warnings == ["WARN: (2.3): variable clash"] * (2 if kind == "row_simulate" else 1), out


def test_a_colonnades_histories_say_what_stood_and_which_models_ran_it(files):
    """Before issue 47 the compliant colonnade's file was titled "a free-standing column", held none of the row's
    numbers, no joint labels and no overturn_body, and the two models could not share one file."""
    with xr.open_dataset(files["row_simulate"]) as ds:
        words = "a colonnade of 2 monolithic columns with capitals carrying 1 epistyle block"
        assert ds.attrs["title"] == (f"Response to ground motion of {words} run by the 3D compliant drums on joints "
                                     "(3d-compliant) and the 2D rigid frame of a colonnade (2d-frame)")
        assert ds.attrs["structure"] == words and ds.attrs["structure_kind"] == "colonnade"
        assert (ds.attrs["n_columns"], ds.attrs["interaxial_m"], ds.attrs["epistyle_height_m"],
                ds.attrs["epistyle_width_m"], ds.attrs["course_height_m"], ds.attrs["n_blocks"]) == \
            (2, 2.5, 0.8, 1.1, 0.0, 1)
        assert list(ds["body_label"].values) == ["column 1 shaft", "column 1 capital", "column 2 shaft",
                                                 "column 2 capital", "epistyle block 1"]
        assert list(ds["joint_label"].values) == ["base of column 1", "column 1 capital on its shaft",
                                                  "base of column 2", "column 2 capital on its shaft",
                                                  "capital 1 / epistyle block 1", "capital 2 / epistyle block 1"]
        assert ds["joint"].attrs["long_name"].startswith("joint index in the structure's order (joint_label")
        assert list(ds["overturn_body"].values.ravel()) == ["", ""]  # both stood
        for name in ds.variables:  # every variable and coordinate has units, or is a flag with its meanings
            assert "units" in ds[name].attrs or "flag_meanings" in ds[name].attrs, name
        # each model's own critical tilt: the frame's is the frame's, the column's the column's
        crit = ds["theta_crit_model_deg"].sel(column="row")
        assert float(crit.sel(model="2d-frame")) == pytest.approx(math.degrees(ROW.frame.alpha), rel=1e-12)
        assert float(crit.sel(model="3d-compliant")) == pytest.approx(15.10, abs=0.01)
        assert float(ds["theta_crit_deg"].sel(column="row")) == pytest.approx(15.10, abs=0.01)
        # the compliant run went on to its settle limit; the frame's rows after its end are not computed
        frame = ds["theta"].sel(column="row", record="pulse", model="2d-frame").values
        assert np.isfinite(frame[:117]).all() and np.isnan(frame[117:]).all()


def test_a_colonnades_positions_are_from_where_its_base_stood(files):
    """x_b and y_b of the compliant colonnade (its first column's base) from where that base stood, as x_p is:
    0 at rest, not the column's place along the row (-1.25 m, which put --plot's contact path 1.25 m off the
    base); the rest places are coordinates in metres."""
    with xr.open_dataset(files["row_simulate"]) as ds:
        run = ds.sel(column="row", record="pulse", model="3d-compliant")
        assert float(run["x_b"][0]) == 0.0 and float(run["y_b"][0]) == 0.0
        slid = float(np.nanmax(np.abs(run["x_b"])))
        assert slid < 0.01 and float(np.nanmax(np.abs(run["x_p"]))) <= 0.5 + slid + 1e-6  # within the base's rim
        assert run["drum_x"].attrs["units"] == "m" and run["drum_y"].attrs["units"] == "m"
        np.testing.assert_allclose(run["drum_x"].values[[0, 2]], [-1.25, 1.25], atol=1e-5)
        assert "from where it stood at rest" in run["x_b"].attrs["long_name"]


def test_a_colonnades_study_fragility_and_risk_files_name_it(files):
    """The study's summary opens with what stood and which models ran it (before: "free-standing column(s)
    modelled as rigid conical frustums"); the row's numbers and joint labels per column, the body that fell
    first per run; the fragility and risk files carry the structures on, in their titles too."""
    words = "a colonnade of 2 monolithic columns with capitals carrying 1 epistyle block"
    with xr.open_dataset(files["row_study"]) as ds:
        assert ds.attrs["summary"] == (
            f"Earthquake response of {words} (row) run by the 3D compliant drums on joints (3d-compliant) and the 2D "
            "rigid frame of a colonnade (2d-frame); a monolithic column (the column of row alone) run by the 3D "
            "rolling frustum (3d), to 1 record(s), 1 incidence angle(s), 2 scale level(s).")
        assert ds.attrs["structures"] == f"row: {words}"
        row = ds.sel(column="row")
        assert (int(row["n_columns"]), float(row["interaxial"]), float(row["epistyle_height"]),
                float(row["epistyle_width"]), int(row["n_blocks"])) == (2, 2.5, 0.8, 1.1, 1)
        assert row["interaxial"].attrs["units"] == "m"
        assert list(row["joint_label"].values) == ["base of column 1", "column 1 capital on its shaft",
                                                   "base of column 2", "column 2 capital on its shaft",
                                                   "capital 1 / epistyle block 1", "capital 2 / epistyle block 1"]
        # at 0.5 x 3 m/s2 everything stands, at 2 x everything falls: the compliant row's body that fell first, the
        # frame and the column alone as one body each
        fell = row["overturn_body"].sel(record="pulse", angle=0.0)
        assert list(row["overturned"].sel(record="pulse", angle=0.0).values.ravel()) == [0, 0, 0, 1, 1, 1]
        assert list(fell.sel(scale=0.5).values) == ["", "", ""]
        assert list(fell.sel(scale=2.0).values) == ["the column", "column 2 shaft", "the colonnade"]
        drum = int(row["overturn_drum"].sel(record="pulse", angle=0.0, scale=2.0, model="3d-compliant"))
        assert D.body_labels(ROW)[drum] == "column 2 shaft"
    for kind, title in (("row_fragility", "Lognormal fragility curves"),
                        ("row_risk", "Risk of damage states at sites")):
        with xr.open_dataset(files[kind]) as ds:
            assert ds.attrs["title"] == f"{title}: row: {words}" and ds.attrs["structures"] == f"row: {words}"
            assert float(ds["interaxial"].sel(column="row")) == 2.5 and ds["interaxial"].attrs["units"] == "m"
            assert int(ds["n_columns"].sel(column="row")) == 2


def test_a_colonnades_report_opens_with_what_stood_and_which_models_ran_it(files, tmp_path):
    """`frustum report` of the row's study: the line under the title names the colonnade and its models (before:
    "Earthquake response of 1 free-standing column(s) modelled as rigid conical frustums ...")."""
    from pipeline.report import write_report

    write_report(F.open_results(files["row_study"]), tmp_path / "report", bootstrap=0)
    lines = (tmp_path / "report" / "report.md").read_text(encoding="utf-8").splitlines()
    assert lines[0] == "# a row of two columns" and lines[1] == ""
    assert lines[2].startswith("Earthquake response of a colonnade of 2 monolithic columns with capitals carrying 1 "
                               "epistyle block (row) run by the 3D compliant drums on joints (3d-compliant) and the 2D "
                               "rigid frame of a colonnade (2d-frame); a monolithic column (the column of row alone) "
                               "run by the 3D rolling frustum (3d)")
    assert "free-standing" not in "\n".join(lines[:3])
