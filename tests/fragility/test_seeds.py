"""Fragility of imperfect drums: the seeds of a column and model pooled as samples of one structure (issue 48).

A study's ``[imperfections]`` gives its results a dimension ``seed``. Pooled as angles are, the runs of
every seed are samples at their stripe, the bootstrap resamples records with every seed of a record
together, and a model of perfect drums (``seeded`` 0, one run repeated along the seeds) counts once. The
check: the same synthetic runs laid out along ``seed`` and along ``angle`` give the same fits and bounds.
"""

import numpy as np
import xarray as xr
from fragility_synthetic import make_results

from pipeline import fragility as F


def _as_seeds(ds):
    """The synthetic runs with their angles relabelled as the seeds of one angle; the angle-invariant 3d
    model (one capacity over the angles) becomes a model of perfect drums (repeated along the seeds)."""
    out = ds.rename({"angle": "seed"}).assign_coords(seed=np.arange(1, ds.sizes["angle"] + 1, dtype=np.int64))
    out = out.expand_dims(angle=[0.0]).transpose("column", "record", "angle", "scale", "model", "seed", ...)
    return out.assign_coords(seeded=("model", np.array([m != "3d" for m in ds.model.values], dtype=np.int8)))


def test_seeds_pool_as_angles_do_fits_counts_and_bootstrap_alike():
    angles, seeds = make_results(n_records=12, angles=(0.0, 30.0, 60.0), seed=8)
    seeds = _as_seeds(angles)
    assert seeds.overturned.dims == ("column", "record", "angle", "scale", "model", "seed")
    by_angle = F.fragility(angles, bootstrap=40, seed=3)
    by_seed = F.fragility(seeds, bootstrap=40, seed=3)
    assert (by_seed.fit_status == F.FIT_OK).sum() > 0  # regular fits, not only degenerate ones
    for name in ("median", "beta", "n_runs", "n_exceed", "n_records", "median_lower", "median_upper",
                 "probability_upper", "stripe_fraction", "stripe_runs"):
        np.testing.assert_array_equal(by_seed[name].values, by_angle[name].values, err_msg=name)
    # the angle-invariant model counted once per record and stripe on both sides
    runs = by_seed.n_runs.sel(state="overturning")
    assert int(runs.sel(column="paper", model="3d")) == 12 * 6
    assert int(runs.sel(column="paper", model="2d")) == 12 * 6 * 3
    assert by_seed.attrs["seeds_pooled"] == "1 2 3" and by_seed.seeded.values.tolist() == [0, 1]


def test_a_model_of_perfect_drums_counts_its_repeats_once_and_its_undecided_runs_too():
    ds, _ = make_results(columns=("paper",), n_records=6, angles=(0.0, 30.0), models=("2d",), seed=2)
    perfect = _as_seeds(ds.isel(angle=[0, 0])).assign_coords(seeded=("model", np.array([0], dtype=np.int8)))
    perfect["undecided"] = xr.zeros_like(perfect.overturned).where(perfect.record != perfect.record[0], 1)
    frag = F.fragility(perfect)
    once = F.fragility(ds.isel(angle=[0]).assign(undecided=xr.zeros_like(ds.isel(angle=[0]).overturned)
                                                  .where(ds.record != ds.record[0], 1)))
    for name in ("median", "beta", "n_runs", "n_undecided"):
        np.testing.assert_array_equal(frag[name].values, once[name].values, err_msg=name)
    assert int(frag.n_undecided.squeeze()) == 6  # record 1's six stripes, once: not once per seed
