"""A ``frustum simulate`` file carries the run's summary: the same values and flags as ``simulate()``.

Before, the file held only histories: whether the column overturned, when, its peak, impacts,
sliding, the restitution reached and a stack's dislocations were printed and lost (issue 26).
"""

import math

import numpy as np
import pytest
import xarray as xr

import pipeline.simulate
from pipeline.cli import main
from pipeline.dataset import FLAGS, SUMMARY_DRUM_VARIABLES, SUMMARY_JOINT_VARIABLES, SUMMARY_VARIABLES, VARIABLES

COLUMN = "R0.5-r0.4-h4"


@pytest.fixture
def summaries(monkeypatch):
    """The summary of every ``simulate()`` call the command makes, in order."""
    seen = []
    original = pipeline.simulate.simulate

    def spy(*args, **kwargs):
        response = original(*args, **kwargs)
        seen.append(response.summary)
        return response

    monkeypatch.setattr(pipeline.simulate, "simulate", spy)
    return seen


def _assert_file_holds(path, models, summaries):
    with xr.open_dataset(path) as ds:
        for model, summary in zip(models, summaries):
            run = ds.sel(column=COLUMN, record="SYN-ONESINE", model=model)
            names = [n for n in SUMMARY_VARIABLES if n in summary]
            assert {"peak_theta", "overturned", "overturn_time", "n_impacts", "sliding_onset", "lift_off",
                    "peak_theta_ratio"} <= set(names)
            for name in names:
                value = run[name].values
                if name in FLAGS:
                    assert value.dtype == np.int8 and int(value) == int(summary[name]), name
                    assert run[name].attrs["flag_meanings"] == FLAGS[name][1], name
                else:
                    np.testing.assert_equal(value, summary[name], err_msg=name)  # NaN equals NaN
                    assert run[name].attrs["units"] == VARIABLES[name].units, name
            assert float(run["peak_theta_deg"]) == pytest.approx(math.degrees(summary["peak_theta"]), rel=1e-12)
            assert run["peak_theta_deg"].attrs["units"] == "degree"
            for name in SUMMARY_JOINT_VARIABLES + SUMMARY_DRUM_VARIABLES:
                if name in summary:
                    np.testing.assert_array_equal(run[name].values, summary[name], err_msg=name)
                    assert run[name].attrs["units"] == VARIABLES[name].units


def test_rigid_file_summary_equals_simulate(tmp_path, summaries):
    out = tmp_path / "r.nc"
    # a one-sine pulse at 1.8 g: the column uplifts and its base slides, in 3D and 2D
    assert main(["simulate", "--column", "0.5,0.4,4", "--record", "SYN-ONESINE", "--scale", "6",
                 "--model", "3d,2d", "--tail", "1", "--out", str(out)]) == 0
    assert len(summaries) == 2 and all(s["sliding_onset"] and s["uplifted"] for s in summaries)
    _assert_file_holds(out, ["3d", "2d"], summaries)
    with xr.open_dataset(out) as ds:
        assert ds["overturned"].dims == ("column", "record", "model")
        assert "joint" not in ds.dims  # a rigid file has no joints to describe


def test_overturned_rigid_run_says_when(tmp_path, summaries):
    out = tmp_path / "o.nc"
    assert main(["simulate", "--column", "0.5,0.4,4", "--record", "SYN-ONESINE", "--scale", "14",
                 "--tail", "1", "--out", str(out)]) == 0
    assert summaries[0]["overturned"]
    _assert_file_holds(out, ["3d"], summaries)
    with xr.open_dataset(out) as ds:
        assert int(ds["overturned"].squeeze()) == 1 and float(ds["overturn_time"].squeeze()) > 0


def test_drum_file_summary_equals_simulate(tmp_path, summaries):
    """Two drums and a capital under a short pulse (about 10 s): dislocations, restitution, bodies."""
    out = tmp_path / "d.nc"
    assert main(["simulate", "--column", "0.5,0.4,4", "--model", "3d-compliant", "--drum-heights", "1.5,2.5",
                 "--capital", "1.0,0.3", "--record", "SYN-ONESINE", "--scale", "2", "--tail", "0.2",
                 "--out", str(out)]) == 0
    (summary,) = summaries
    assert summary["joint_slip"][1:].max() > 1e-3  # the bed joints slid: the dislocations are not all 0
    # issue 26: 1.43 with friction 0.7 when the dashpot's share counted; the step's statistics
    # hold each point's shear force within its cone (mu = 0.7 on every joint here)
    assert summary["joint_peak_mu_mob"].max() <= 0.7 * (1 + 1e-12)
    assert summary["joint_peak_mu_mob"].max() > 0.5  # the joints did mobilise their friction
    _assert_file_holds(out, ["3d-compliant"], summaries)
    with xr.open_dataset(out) as ds:
        run = ds.sel(column=COLUMN, record="SYN-ONESINE", model="3d-compliant")
        assert run["joint_slip"].dims == ("joint",) and run.sizes["joint"] == 3  # base, bed joint, capital
        np.testing.assert_array_equal(run["joint_diameter"].values, summary["joint_diameter"])
        assert int(run["overturn_drum"]) == summary["overturn_drum"] == -1
        assert float(run["restitution"]) == summary["restitution"] and 0 < summary["restitution"] < 1
        assert float(run["dislocation_ratio"]) == summary["dislocation_ratio"] > 0
        assert int(ds["n_drums"].sel(column=COLUMN)) == 2
        np.testing.assert_array_equal(run["joint_tilt_deg"].values, np.degrees(summary["joint_tilt"]))


# Issue 47, item 3: the console tells a structure's parts by the summary's names, a few lines, and a rigid
# run that slid says so. The numbers are those of the runs below (pinned: a change of the models' numerics
# that moves them shows here); what each line names is checked against the file the same run wrote.

ROW = ["simulate", "--model", "3d-compliant", "--column", "0.5,0.4,4", "--drums", "2", "--capital", "1.0,0.4",
       "--colonnade", "3", "--interaxial", "2", "--epistyle", "0.5", "--record", "SYN-RICKER", "--tail", "0.2"]


def _printed(capsys, model):
    """The lines a run of ``model`` printed: its own and the indented ones after it."""
    lines = capsys.readouterr().out.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(f"{model}: "))
    end = next(i for i in range(start + 1, len(lines)) if not lines[i].startswith("  "))
    return lines[start:end]


def test_a_colonnade_is_told_column_by_column_and_joint_kind_by_joint_kind(tmp_path, capsys, summaries):
    out = tmp_path / "row.nc"
    assert main(ROW + ["--scale", "2", "--out", str(out)]) == 0
    assert _printed(capsys, "3d-compliant") == [
        "3d-compliant: peak theta = 1.971 deg (0.13 theta_crit), stands, its base 0.4 mm from where it stood, 26 "
        "impacts, peak mu_mob = 0.48, mean plastic slip of a base's points 0.4 mm",
        "  peak tilt [deg] of each column (its largest body): column 1 drum 2 1.98, column 2 drum 2 1.90, "
        "column 3 drum 2 1.91",
        "  peak tilt [deg] of each epistyle block: block 1 0.68, block 2 0.63",
        "  epistyle at the end: its blocks moved up to 1.5 mm on their capitals, its head joints open up to 2.5 mm",
        "  residual slips, the largest of each kind of joint: bases 0.4 mm (base of column 1); bed joints "
        "0.2 mm (column 1 bed joint under drum 2); capitals on shafts 0.2 mm (column 1 capital on its shaft); "
        "block bearings 1.5 mm (capital 2 / epistyle block 2); head joints 0.7 mm (head joint blocks 1-2); the "
        "largest of a bed joint or capital on its shaft over the joint's diameter 0.03 %",
    ]
    (summary,) = summaries
    # 11 bodies and 14 joints, told in 5 lines; every name is the summary's, every number its value
    assert len(summary["body_label"]) == 11 and len(summary["joint_label"]) == 14
    with xr.open_dataset(out) as ds:
        run = ds.sel(column="R0.5-r0.4-h4-x3", record="SYN-RICKER", model="3d-compliant")
        tilts = np.degrees(run["drum_peak_theta"].values)
        slips = run["joint_slip"].values * 1e3
    labels = list(summary["body_label"])
    assert f"{tilts[labels.index('column 1 drum 2')]:.2f}" == "1.98"
    assert f"{tilts[:3].max():.2f}" == "1.98" and f"{tilts[labels.index('epistyle block 2')]:.2f}" == "0.63"
    # the bed joints' largest is of the bed joints (the bases' 0.4 mm and the bearings' 1.5 mm are larger)
    joints = list(summary["joint_label"])
    beds = [j for j, kind in enumerate(summary["joint_kind"]) if kind == "bed"]
    assert max(slips[beds]) == slips[joints.index("column 1 bed joint under drum 2")]
    assert f"{slips.max():.1f}" == "1.5" and summary["epistyle_slip"] * 1e3 == pytest.approx(slips.max())


def test_a_colonnade_says_which_body_fell_first(tmp_path, capsys, summaries):
    assert main(ROW + ["--scale", "12", "--out", str(tmp_path / "fell.nc")]) == 0
    (summary,) = summaries
    assert summary["overturned"] and summary["overturn_body"] in summary["body_label"]
    first = _printed(capsys, "3d-compliant")[0]
    assert f"overturned at {summary['overturn_time']:.2f} s, {summary['overturn_body']} falling first," in first


def test_a_column_of_drums_names_its_drums(tmp_path, capsys, summaries):
    assert main(["simulate", "--model", "3d-compliant", "--column", "0.5,0.4,4", "--drums", "3", "--capital",
                 "1.0,0.4", "--record", "SYN-RICKER", "--scale", "2", "--tail", "0.2",
                 "--out", str(tmp_path / "d.nc")]) == 0
    assert _printed(capsys, "3d-compliant") == [
        "3d-compliant: peak theta = 2.641 deg (0.17 theta_crit), stands, slid 0.1 mm, 6 impacts, peak mu_mob = 0.70, "
        "mean plastic slip of the base's points 0.2 mm",
        "  peak tilt [deg] of each body: drum 1 1.85, drum 2 2.63, drum 3 2.64, capital 2.64",
        "  residual slips, the largest of each kind of joint: bases 0.1 mm (base of the column); bed joints 0.2 mm (bed "
        "joint under drum 3); capitals on shafts 0.7 mm (capital on its shaft); the largest of a bed joint or "
        "capital on its shaft over the joint's diameter 0.09 %",
    ]


def test_a_rigid_run_that_slid_says_how_far(tmp_path, capsys, summaries):
    """Friction 0.3 under a one-sine pulse at 0.9 g: the column slides and rocks, and stands where it slid to."""
    out = tmp_path / "slid.nc"
    assert main(["simulate", "--column", "0.5,0.4,4", "--record", "SYN-ONESINE", "--scale", "3", "--friction", "0.3",
                 "--model", "3d,2d", "--tail", "1", "--out", str(out)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert "3d: peak theta = 5.040 deg (0.33 theta_crit), stands, slid 93.8 mm, 5 impacts, peak mu_mob = 0.30" in lines
    assert "2d: peak theta = 5.043 deg (0.33 theta_crit), stands, slid 93.7 mm, 5 impacts, peak mu_mob = 0.30" in lines
    # how far: where the histories leave the base (at rest by their last sample: to round-off)
    with xr.open_dataset(out) as ds:
        for model, summary in zip(("3d", "2d"), summaries):
            run = ds.sel(column=COLUMN, record="SYN-ONESINE", model=model)
            x_b, y_b = (run[name].dropna("time").values for name in ("x_b", "y_b"))
            assert summary["sliding_onset"]
            assert math.hypot(x_b[-1], y_b[-1] if y_b.size else 0.0) == pytest.approx(
                summary["residual_displacement"], rel=1e-12)
