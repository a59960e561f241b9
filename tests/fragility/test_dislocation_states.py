"""Damage states on the residual dislocation of drums: fitted by the same likelihood as overturning.

Synthetic results (fragility_synthetic.py) with one lognormal capacity C per run: the peak
ratio is PGA / C (overturning at 1) and the largest residual joint slip over the diameter is
taken as 0.1 PGA / C, so the run reaches ``dislocation_s`` (slip/D >= s, or overturned) exactly
when PGA >= 10 s C: for s <= 0.1 the true median is 10 s times the overturning median.
"""

import numpy as np
import pytest
import xarray as xr
from fragility_synthetic import make_results

from pipeline import fragility as F
from pipeline.cli import main
from pipeline.errors import InputError


def drum_results(seed=5, **kwargs):
    ds, truth = make_results(models=("3d", "3d-compliant"), seed=seed, **kwargs)
    ratio = ds["pga"] / ds["peak_theta_ratio"]  # C, per run (the overturned runs hold 5.8: no matter)
    dislocation = (0.1 * ds["pga"] / ratio).where(ds["overturned"] == 0, 0.3)
    # the rigid model has no joints: NaN, as a study writes it
    ds["dislocation_ratio"] = dislocation.where(ds["model"] == "3d-compliant").transpose(*ds["overturned"].dims)
    return ds, truth


def test_dislocation_states_match_a_direct_fit_of_their_counts():
    ds, _ = drum_results()
    frag = F.fragility(ds, states=())  # the dislocation states by default: the results hold dislocation_ratio
    assert list(frag["state"].values) == ["overturning", "dislocation_0.01", "dislocation_0.05", "dislocation_0.1"]
    assert list(frag["state_measure"].values) == ["overturned"] + ["dislocation_ratio"] * 3
    np.testing.assert_array_equal(frag["state_threshold"].values[1:], F.DISLOCATION_STATES)
    one = ds.sel(column="paper", model="3d-compliant")
    x = one["pga"].broadcast_like(one["overturned"]).values.ravel()
    for s in F.DISLOCATION_STATES:
        k = ((one["dislocation_ratio"] >= s) | (one["overturned"] == 1)).values.ravel()
        direct = F.fit_lognormal(x, np.ones_like(x), k)
        cell = frag.sel(state=f"dislocation_{s:g}", column="paper", model="3d-compliant")
        # the same counts through the same likelihood: equal to round-off
        assert float(cell["median"]) == pytest.approx(direct.median, rel=1e-12)
        assert float(cell["beta"]) == pytest.approx(direct.beta, rel=1e-12)
        assert int(cell["n_exceed"]) == int(k.sum())
    # without joints (the rigid monolith, NaN) a dislocation state is reached only by overturning
    rigid = frag.sel(column="paper", model="3d")
    for s in F.DISLOCATION_STATES:
        assert float(rigid["median"].sel(state=f"dislocation_{s:g}")) == float(rigid["median"].sel(state="overturning"))


def test_dislocation_medians_follow_the_synthetic_truth():
    """Median of dislocation_s = 10 s times the overturning median (module docstring); 2880 runs per
    fit, SE of ln median ~ beta / sqrt(n) ~ 0.01: 5 %."""
    ds, truth = drum_results(seed=8, n_records=60, columns=("paper",), scales=np.geomspace(0.05, 4, 16))
    frag = F.fragility(ds, states=(), dislocations=(0.01, 0.05))
    true_median, _ = truth[("paper", "3d-compliant")]
    cell = frag.sel(column="paper", model="3d-compliant")
    assert float(cell["median"].sel(state="overturning")) == pytest.approx(true_median, rel=0.05)
    assert float(cell["median"].sel(state="dislocation_0.01")) == pytest.approx(0.1 * true_median, rel=0.05)
    assert float(cell["median"].sel(state="dislocation_0.05")) == pytest.approx(0.5 * true_median, rel=0.05)


def test_dislocation_states_name_what_is_missing_or_wrong():
    ds, _ = make_results(n_records=4)
    assert "dislocation_0.01" not in F.fragility(ds)["state"].values  # no joints in the results: none by default
    with pytest.raises(InputError, match="dislocation_ratio.*3d-compliant"):
        F.fragility(ds, dislocations=(0.01,))
    with pytest.raises(InputError, match="positive"):
        F.fragility(drum_results()[0], dislocations=(-0.01,))
    assert F.parse_state("dislocation_0.05") == ("dislocation", 0.05)
    assert F.parse_state("theta_ratio_0.5") == F.parse_state(0.5) == ("theta_ratio", 0.5)


def test_fragility_cli_fits_the_dislocation_states(tmp_path, capsys):
    ds, _ = drum_results(n_records=6)
    path = tmp_path / "drums.nc"
    ds.to_netcdf(path)
    out = tmp_path / "frag.nc"
    assert main(["fragility", str(path), "--out", str(out), "--states", "0.5", "--dislocations", "0.02,0.2"]) == 0
    with xr.open_dataset(out) as back:
        assert [str(s) for s in back["state"].values] == ["overturning", "theta_ratio_0.5", "dislocation_0.02",
                                                          "dislocation_0.2"]
        expected = F.fragility(F.open_results(path), states=(0.5,), dislocations=(0.02, 0.2))
        np.testing.assert_array_equal(back["median"].values, expected["median"].values)
    assert main(["fragility", str(path), "--out", str(out), "--dislocations", "none"]) == 0
    with xr.open_dataset(out) as back:
        assert not any(str(s).startswith("dislocation") for s in back["state"].values)
    assert main(["fragility", str(path), "--out", str(out), "--dislocations", "1%"]) == 2
    assert "--dislocations '1%'" in capsys.readouterr().err
