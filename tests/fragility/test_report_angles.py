"""The report's probability of overturning by incidence angle (issue 37: is a colonnade weaker across its
row than along it?). Synthetic results with a known truth per angle (fragility_synthetic)."""

import numpy as np
import xarray as xr
from fragility_synthetic import make_results

from pipeline import fragility as F
from pipeline import report_angles as A
from pipeline.report import _fmt, write_report
from pipeline.units import G

MODELS = ("3d-compliant", "2d")  # one 3D model that feels the direction, one planar
STRIPES = G * np.array([0.25, 0.5, 1.0, 1.5, 2.0, 3.0])  # m/s2: every record scaled to these PGAs
TRUTH = {0.0: 0.8 * G, 90.0: 1.6 * G}  # median capacity [m/s2] along and across (beta 0.4)


def _results(columns=("paper", "slender")):
    """A study in stripes whose 3D model is twice as strong at 90 deg as at 0 deg."""
    parts = []
    for seed, (angle, median) in enumerate(TRUTH.items(), start=1):
        cells = [(c, m) for c in columns for m in MODELS]
        ds, _ = make_results(columns=columns, angles=(angle,), models=MODELS, scales=STRIPES, record_pga=np.ones(20),
                             true_median=dict.fromkeys(cells, median), true_beta=dict.fromkeys(cells, 0.4), seed=seed)
        parts.append(ds)
    ds = xr.concat(parts, dim="angle", data_vars="minimal", coords="minimal", compat="override")
    ds["scale"].attrs["units"] = "m s-2"
    return ds


def test_each_angle_is_fitted_on_its_own_runs_for_the_3d_models_that_feel_it():
    results = _results()
    by = A.fragility_by_angle(results, bootstrap=100, seed=3)
    assert list(by["model"].values) == ["3d-compliant"]  # the planar 2d model has its polar figure instead
    # the same fit as the angle's runs alone, to round-off
    alone = F.fragility(results.sel(angle=[90.0], model=["3d-compliant"]), states=(), bootstrap=100, seed=3)
    for name in ("median", "median_upper", "beta"):
        np.testing.assert_allclose(by[name].sel(angle=90.0).values, alone[name].sel(state="overturning").values,
                                   rtol=1e-12)
    for angle, median in TRUTH.items():
        fit = by.sel(angle=angle)
        # 20 records, beta 0.4: the median's standard error is about 0.4 / sqrt(20) = 9 % in log; 0.25 is 2.8 of it
        assert (np.abs(np.log(fit["median"].values / median)) < 0.25).all()
    # twice as strong across: the bands (about +-15 % for beta 0.4 and 20 records) do not overlap
    assert (by["median_upper"].sel(angle=0.0).values < by["median_lower"].sel(angle=90.0).values).all()


def test_the_report_tables_each_angle_with_its_stripes_and_draws_the_medians(tmp_path):
    results = _results(columns=("paper",))
    # a few runs of the planar model failed (status 1) or were undecided (settle limit, still moving): the report
    # counts each for what it is (the undecided ones were once called failed)
    assert list(results["model"].values) == list(MODELS) and results["status"].dims[-1] == "model"
    status, undecided = results["status"].values.copy(), np.zeros(results["status"].shape, np.int8)
    status[..., 1].flat[:3] = 1  # three runs of the 2d model failed
    undecided[..., 1].flat[3:7] = 1  # four others were undecided
    results["status"] = (results["status"].dims, status)
    results["undecided"] = (results["status"].dims, undecided)
    written = write_report(results, tmp_path / "report", bootstrap=20, seed=5)
    text = open(written["report"], encoding="utf-8").read()
    assert "- 480 simulations in the dataset, 3 failed and left out.\n" in text
    assert ("- **4 run(s) undecided**: still able to fall when they reached their settle limit. They count as "
            "**standing** in every fit and count below" in text)
    from pipeline.report_undecided import undecided_effect

    effect = undecided_effect(results)  # the medians both ways, beside the count
    both = [float(effect[k].sel(column="paper", model="2d")) / G for k in ("standing", "overturned")]
    assert both[1] < both[0]  # four more overturnings lower the median
    assert f"| paper | 2d | 4 | {both[0]:.3g} | {both[1]:.3g} |" in text
    section = text.split("## Probability of overturning by incidence angle")[1].split("\n## ")[0]
    by = A.fragility_by_angle(results, bootstrap=20, seed=5)
    rows = [[x.strip() for x in line.strip("|").split("|")] for line in section.splitlines()
            if line.startswith("| paper |")]
    assert len(rows) == 2 and all(row[1] == "3D-COMPLIANT" for row in rows)
    for row in rows:
        fit = by.sel(column=row[0], model="3d-compliant", angle=float(row[2]))
        assert row[3] == (f"{_fmt(float(fit['median']) / G)} ({_fmt(float(fit['median_lower']) / G)} to "
                          f"{_fmt(float(fit['median_upper']) / G)})")
        cell = results.sel(column=row[0], model="3d-compliant", angle=float(row[2]))
        per_stripe = [int(cell["overturned"].sel(scale=s).sum()) for s in STRIPES]
        assert row[5] == f"{sum(per_stripe)} / 120"
        assert row[6] == " / ".join(map(str, per_stripe))
    assert "overturned at 0.25, 0.5, 1, 1.5, 2, 3 g" in section
    assert any(f.endswith("median_by_angle.png") for f in written["figures"])
    assert "![" in text and "median_by_angle.png" in text


def test_one_angle_or_models_that_do_not_feel_it_give_no_section():
    assert A.fragility_by_angle(make_results(angles=(0.0,), models=MODELS)[0]) is None
    rigid, _ = make_results(models=("3d", "2d"))  # the rigid 3D model is axisymmetric, 2d planar
    assert A.fragility_by_angle(rigid) is None
    assert A.angle_section(rigid, None, _fmt) == []
