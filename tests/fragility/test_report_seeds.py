"""The report of a study of imperfect drums (issue 48, item 2's spread over seeds): the seeds pooled as
angles in every count, and "do apparently identical structures differ?" counted cell by cell.

Synthetic results: the runs of five angles relabelled as the seeds of one angle (as tests/fragility/
test_seeds.py does), a model ``imperfect`` that draws a structure per seed beside ``perfect``, the same
registry model with perfect drums, run once and repeated along the seeds. Every number of the new
section is recomputed here from the dataset.
"""

import csv
import os

import numpy as np
import pytest
import xarray as xr
from fragility_synthetic import make_results

from pipeline import report_seeds as RS
from pipeline.report import _fmt, write_report
from pipeline.units import G

SEEDS = (3, 7, 11, 19, 23)
STRIPES = G * np.array([0.4, 0.7, 1.0, 1.4, 2.0])


def seeded_results(failed=0):
    """``perfect`` and ``imperfect`` (both 3d-compliant) on one column, 12 records, one angle, five seeds."""
    ds, _ = make_results(columns=("paper",), n_records=12, angles=tuple(range(len(SEEDS))), scales=STRIPES,
                         record_pga=np.ones(12), models=("perfect", "imperfect"), seed=6, failed=failed,
                         true_median={("paper", "perfect"): G, ("paper", "imperfect"): G})
    ds["scale"].attrs["units"] = "m s-2"
    out = ds.rename({"angle": "seed"}).assign_coords(seed=np.array(SEEDS, dtype=np.int64))
    out = out.expand_dims(angle=[0.0]).transpose("column", "record", "angle", "scale", "model", "seed")
    perfect = out.sel(model="perfect").isel(seed=[0] * len(SEEDS)).assign_coords(seed=out["seed"])
    out = xr.concat([perfect.expand_dims(model=["perfect"]), out.sel(model=["imperfect"])], dim="model",
                    data_vars="all", coords="minimal", compat="override")
    out = out.transpose("column", "record", "angle", "scale", "model", "seed")
    out = out.assign_coords(seeded=("model", np.array([0, 1], dtype=np.int8)),
                            base_model=("model", np.array(["3d-compliant"] * 2, dtype=object)),
                            model_variant=("model", np.array(["", "imperfections"], dtype=object)))
    out.attrs.update(imperfection_tolerance_m=0.003, imperfection_friction_range="0.5 0.7",
                     imperfection_models="imperfect")
    return out


def _expected(ds, scale=None):
    """The test's own count of one stripe (or all): cells (record, angle) over the seeds."""
    one = ds.sel(column="paper", model="imperfect")
    perfect = ds.sel(column="paper", model="perfect").isel(seed=0)
    if scale is not None:
        one, perfect = one.sel(scale=[scale]), perfect.sel(scale=[scale])
    ok = (one["status"] == 0).all("seed")  # a cell in which every seed ran
    both = ok & (perfect["status"] == 0)  # ... and the perfect structure too
    falls = (one["overturned"] == 1).sum("seed")
    n = len(SEEDS)
    stand, fall = ok & (falls == 0), ok & (falls == n)
    divided = ok & ~stand & ~fall
    ratio = one["peak_theta_ratio"].max("seed") / one["peak_theta_ratio"].min("seed")
    spread = ratio.values[stand.values]
    majority = 2 * falls > n
    differ = both & (majority != (perfect["overturned"] == 1))
    return {"cells": int(ok.sum()), "all_stand": int(stand.sum()), "all_fall": int(fall.sum()),
            "divided": int(divided.sum()),
            "share": float(falls.where(divided).sum()) / (n * int(divided.sum())) if divided.any() else np.nan,
            "spread_median": float(np.median(spread)) if spread.size else np.nan,
            "spread_max": float(spread.max()) if spread.size else np.nan, "spread_cells": spread.size,
            "differ": int(differ.sum()), "compared": int(both.sum())}


def test_the_spread_over_seeds_is_counted_cell_by_cell():
    ds = seeded_results()
    rows = RS.seed_spread(ds)
    assert [(r["model"], r["scale"]) for r in rows] == [("imperfect", s) for s in [*STRIPES, None]]
    assert {r["perfect"] for r in rows} == {"perfect"}
    for r in rows:
        want = _expected(ds, r["scale"])
        assert r["cells"] == want["cells"] == r["compared"] == 12 * (1 if r["scale"] is not None else len(STRIPES))
        for key in ("all_stand", "all_fall", "divided", "differ", "compared"):
            assert r[key] == want[key], (key, r["scale"])
        assert r["all_stand"] + r["all_fall"] + r["divided"] == r["cells"]
        assert r["ties"] == 0  # five seeds: always a majority
        if want["divided"]:
            assert r["seeds_falling_in_divided"] == pytest.approx(want["share"], rel=1e-12)
        if want["spread_cells"]:
            assert (r["spread_median"], r["spread_max"]) == pytest.approx((want["spread_median"], want["spread_max"]),
                                                                           rel=1e-12)
    pooled = rows[-1]
    assert pooled["divided"] > 5 and pooled["all_stand"] > 5 and pooled["all_fall"] > 5  # the data reach every kind
    assert pooled["differ"] > 0 and pooled["spread_median"] > 1.0


def test_a_seeded_study_is_reported_its_seeds_pooled_and_its_section_from_the_dataset(tmp_path):
    ds = seeded_results(failed=3)
    out = write_report(ds, tmp_path / "report", bootstrap=20, seed=1)
    text = open(out["report"], encoding="utf-8").read()
    # what was simulated: the tolerance, the seeds, the friction range and which model drew them
    assert ("- **Imperfect drums**: `imperfect` drew a structure for each of 5 seed(s) (3, 7, 11, 19, 23): every "
            "drum's bed offset and tilted by random amounts up to 3 mm, the friction of every joint drawn from 0.5 "
            "to 0.7.") in text
    assert "`perfect` ran perfect drums, once for all seeds and counted once." in text
    # the perfect model's runs once, the imperfect one's per seed: 12 records x 5 stripes x (1 + 5)
    assert "- 360 simulations in the dataset, " in text
    frag = out["frag"]
    runs = frag["n_runs"].sel(state="overturning", column="paper")
    ok = ds["status"].sel(column="paper") == 0
    assert int(runs.sel(model="imperfect")) == int(ok.sel(model="imperfect").sum())
    assert int(runs.sel(model="perfect")) == int(ok.sel(model="perfect").isel(seed=0).sum())
    section = text[text.index("## Imperfect drums: do apparently identical structures differ?"):]
    section = section[:section.index("\n## ")]
    table = [line for line in section.splitlines() if line.startswith("| paper |")]
    assert len(table) == len(STRIPES) + 1
    for line, scale in zip(table, [*STRIPES, None]):
        cells = [c.strip() for c in line.strip("|").split("|")]
        want = _expected(ds, scale)
        stripe = "**all**" if scale is None else f"{_fmt(scale / G)} g"
        assert cells[:8] == ["paper", "imperfect", stripe, str(want["cells"]), str(want["all_stand"]),
                             str(want["all_fall"]), str(want["divided"]),
                             f"{100 * want['share']:.0f} %" if want["divided"] else "n/a"]
        assert cells[8] == (f"{_fmt(100 * (want['spread_median'] - 1))} % ({_fmt(100 * (want['spread_max'] - 1))} %) "
                            f"in {want['spread_cells']} cell(s)" if want["spread_cells"] else "n/a")
        assert cells[9] == f"`perfect`: {want['differ']} of {want['compared']}"
    assert "Mouzakis" in section
    with open(out["csv"], newline="", encoding="utf-8") as fh:
        rows = {r["model"]: r for r in csv.DictReader(fh)}
    want = _expected(ds)
    assert int(rows["imperfect"]["seed_cells_divided"]) == want["divided"]
    assert int(rows["imperfect"]["perfect_differs_from_seeds"]) == want["differ"]
    assert rows["perfect"]["seed_cells"] == ""
    # the failed runs (status 1) counted once each: none is a repeat of the perfect model here
    assert int(rows["imperfect"]["failed_runs_excluded"]) + int(rows["perfect"]["failed_runs_excluded"]) == \
        int(((ds["status"] != 0) & ((ds["model"] == "imperfect") | (ds["seed"] == SEEDS[0]))).sum())


def test_the_model_comparison_pools_each_seeds_cell_against_the_perfect_run():
    """Each seed's run is one cell against the perfect run (pooled as angles); two models of perfect drums would
    only repeat theirs along the seeds, so their cells count once."""
    from pipeline import comparison as C
    from pipeline import fragility as F

    ds = seeded_results(failed=4)
    frag = F.fragility(ds)
    versus = C.compare_models(ds, frag, reference="perfect").sel(column="paper", model="imperfect")
    ok = ds["status"].sel(column="paper") == 0
    both = ok.sel(model="imperfect") & ok.sel(model="perfect").isel(seed=0)
    over = ds["overturned"].sel(column="paper") == 1
    same = (over.sel(model="imperfect") == over.sel(model="perfect").isel(seed=0)) & both
    assert int(versus["cells"]) == int(both.sum()) and int(versus["same"]) == int(same.sum())
    twins = ds.isel(seed=[0] * len(SEEDS)).assign_coords(seed=ds["seed"],
                                                          seeded=("model", np.array([0, 0], dtype=np.int8)))
    again = C.outcome_agreement(twins, "paper", "perfect", "imperfect")
    once = (twins["status"].sel(column="paper").isel(seed=0) == 0).all("model")
    assert again["cells"] == int(once.sum()) > 0


def test_the_polar_figure_of_a_planar_model_pools_the_seeds_as_records(tmp_path):
    from pipeline.plotting_fragility import plot_angle_polar

    ds, _ = make_results(columns=("paper",), n_records=6, angles=(0.0, 45.0, 90.0), models=("3d", "2d"), seed=3)
    seeded = ds.expand_dims(seed=np.array([1, 2], dtype=np.int64)).transpose(*ds["overturned"].dims, "seed", ...)
    seeded = seeded.assign_coords(seeded=("model", np.array([0, 0], dtype=np.int8)))
    files = plot_angle_polar(seeded, str(tmp_path / "polar"), "paper", model="2d")
    assert files and all(os.path.getsize(f) > 0 for f in files)
