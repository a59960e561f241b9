"""Model against model (issue 28): medians with bands, cell-by-cell outcomes, peak ratios.

The expected counts are built into the results by hand, so every number below is exact: a
comparison that counted a failed run, an angle twice or the wrong model's outcome would differ.
"""

import numpy as np
import pytest
import xarray as xr
from fragility_synthetic import make_results

from pipeline.comparison import compare_models, comparison_rows, merge_results, outcome_agreement, peak_ratio
from pipeline.errors import InputError
from pipeline.fragility import fragility
from pipeline.paths import result_kind
from pipeline.report import write_report


def _pair(models=("3d", "2d"), n_records=6):
    """Results of two models with overturning and peak tilts set cell by cell.

    Reference (first model): overturns at the two largest scales. The other: overturns at the
    largest scale only, except in record 0 where it also overturns at the smallest; its peak tilt
    is 1.5 times the reference's wherever both stand. One run of the other model fails.
    """
    ds, _ = make_results(models=models, columns=("paper",), n_records=n_records, angles=(0.0, 90.0),
                         scales=(0.5, 1.0, 2.0), seed=3)
    dims = ds["overturned"].dims
    over = np.zeros(ds["overturned"].shape, np.int8)
    ia, ib = dims.index("model"), dims.index("scale")
    idx = [slice(None)] * len(dims)

    def at(model, scale, record=slice(None)):
        i = list(idx)
        i[ia], i[ib], i[dims.index("record")] = model, scale, record
        return tuple(i)

    over[at(0, 1)] = over[at(0, 2)] = 1
    over[at(1, 2)] = 1
    over[at(1, 0, 0)] = 1
    ds["overturned"][...] = over
    theta = np.full(over.shape, 0.05)
    theta[at(1, slice(None))] = 0.075
    ds["peak_theta"][...] = np.where(over == 1, 1.0, theta)
    status = np.zeros(over.shape, np.int8)
    fail = [0] * len(dims)
    fail[ia], fail[dims.index("record")], fail[ib] = 1, 1, 0
    status[tuple(fail)] = 1  # the other model, record 1, first angle, scale 0.5
    ds["status"][...] = status
    return ds


def test_cells_count_each_outcome_once_and_skip_failed_runs():
    ds = _pair()
    got = outcome_agreement(ds, "paper", "3d", "2d")
    # 2d depends on the angle: 6 records x 2 angles x 3 scales = 36 cells, one failed -> 35.
    # Scale 1.0: only the reference overturned, in every record and angle (12 cells).
    # Scale 0.5, record 0: only the model overturned (2 angles).
    assert got == {"cells": 35, "same": 21, "reference_only": 12, "model_only": 2}


def test_two_angle_invariant_models_count_each_run_once():
    ds = _pair(models=("3d", "3d-compliant"))
    ds = ds.assign(base_model=("model", np.array(["3d", "3d"], dtype=object)))  # a variant of 3d
    got = outcome_agreement(ds, "paper", "3d", "3d-compliant")
    # both angle-invariant (the variant is a 3d): 6 records x 3 scales; the failed run is at angle 0
    assert got == {"cells": 17, "same": 10, "reference_only": 6, "model_only": 1}


def test_peak_ratio_where_both_stood():
    ds = _pair()
    got = peak_ratio(ds, "paper", "3d", "2d")
    # both stood at scale 0.5 except record 0 (the model overturned) and the failed run: 5 x 2 - 1
    assert got["cells"] == 9
    assert got["median"] == pytest.approx(1.5, rel=1e-12)
    assert got["p10"] == pytest.approx(1.5, rel=1e-12) and got["p90"] == pytest.approx(1.5, rel=1e-12)


def test_compare_models_states_the_band_test_and_is_a_comparison_file(tmp_path):
    ds = _pair()
    frag = fragility(ds, bootstrap=40, seed=1)
    cmp = compare_models(ds, frag)
    assert cmp.attrs["reference_model"] == "3d" and list(cmp["model"].values) == ["2d"]
    row = comparison_rows(cmp)[0]
    cell = frag.sel(state="overturning", column="paper")
    lo, hi = float(cell["median_lower"].sel(model="3d")), float(cell["median_upper"].sel(model="3d"))
    med = float(cell["median"].sel(model="2d"))
    assert row["inside_reference_band"] == int(lo <= med <= hi)
    assert row["median_ratio"] == pytest.approx(med / float(cell["median"].sel(model="3d")))
    assert (row["cells"], row["same"], row["reference_only"], row["model_only"]) == (35, 21, 12, 2)
    # the other way round: the counts swap sides
    back = comparison_rows(compare_models(ds, frag, reference="2d"))[0]
    assert (back["reference_only"], back["model_only"]) == (2, 12)
    from pipeline.dataset import write_netcdf

    path = write_netcdf(cmp, tmp_path / "comparison.nc")
    assert result_kind(path) == "comparison"
    assert xr.open_dataset(path)["cells"].attrs["units"] == "1"


def test_an_unknown_reference_is_refused_with_the_models():
    ds = _pair()
    with pytest.raises(InputError, match=r"reference model 'stack'.*3d, 2d"):
        compare_models(ds, fragility(ds), reference="stack")


def test_the_report_compares_models_and_writes_the_tables(tmp_path):
    ds = _pair()
    out = write_report(ds, tmp_path / "r", bootstrap=20, reference="2d")
    text = open(out["report"], encoding="utf-8").read()
    assert "## Model against model (reference: 2D planar rocking, `2d`)" in text
    assert "| paper | 3D rolling frustum (`3d`) |" in text
    header = open(out["comparison_csv"], encoding="utf-8").readline()
    assert header.startswith("column,reference,model,median,")
    assert any(p.endswith("median_model_vs_model.png") for p in out["figures"])


def test_results_of_two_files_merge_into_the_same_comparison(tmp_path):
    ds = _pair()
    a, b = ds.sel(model=["3d"]), ds.sel(model=["2d"]).drop_vars("n_impacts")  # a peer need not write everything
    merged = merge_results([a, b])
    assert list(merged["model"].values) == ["3d", "2d"]
    assert np.isnan(merged["n_impacts"].sel(model="2d")).all()
    assert outcome_agreement(merged, "paper", "3d", "2d") == outcome_agreement(ds, "paper", "3d", "2d")
    with pytest.raises(InputError, match="record values differ"):
        merge_results([a, b.isel(record=slice(1, None))])
    with pytest.raises(InputError, match="model '3d' is in both"):
        merge_results([a, a])
