"""Synthetic study results in the schema of ``frustum study run`` (issue 5), with a known truth.

Each run has a lognormal capacity C (median ``true_median`` [m/s^2], dispersion
``true_beta``) and reaches theta/theta_crit = PGA / C, overturning when that
reaches 1. So P(overturning | PGA = x) = Phi(ln(x / median) / beta) exactly, and
P(ratio >= s | x) = Phi(ln(x / (s median)) / beta) for the damage states.

3D runs share one capacity over all angles (the 3D model is angle-independent);
2D runs draw one per angle.
"""

import numpy as np
import xarray as xr

from pipeline.units import G


def make_results(
    columns=("paper", "slender"),
    n_records=20,
    angles=(0.0, 45.0, 90.0, 135.0),
    scales=(0.25, 0.5, 1.0, 1.5, 2.0, 3.0),
    models=("3d", "2d"),
    true_median=None,
    true_beta=None,
    record_pga=None,
    seed=1,
    coordinates=False,
    failed=0,
):
    """Return (results Dataset, truth dict {(column, model): (median [m/s^2], beta)}).

    ``record_pga`` [m/s^2] per record (default: all 1 g, so each scale is one
    IM stripe); ``true_median``/``true_beta`` map (column, model) to the truth
    (defaults differ per column and model). ``failed`` runs get status 1 and
    garbage values that must be ignored.
    """
    rng = np.random.default_rng(seed)
    nC, nR, nA, nK, nM = len(columns), n_records, len(angles), len(scales), len(models)
    if record_pga is None:
        record_pga = np.full(nR, G)
    record_pga = np.asarray(record_pga, float)
    truth = {}
    for i, c in enumerate(columns):
        for j, m in enumerate(models):
            med = (true_median or {}).get((c, m), G * (0.8 + 0.4 * i) * (1.0 if m == "3d" else 1.3))
            bet = (true_beta or {}).get((c, m), 0.4 + 0.1 * j)
            truth[(c, m)] = (med, bet)
    pga = record_pga[:, None] * np.asarray(scales)[None, :]  # (record, scale)
    ratio = np.zeros((nC, nR, nA, nK, nM))
    for i, c in enumerate(columns):
        for j, m in enumerate(models):
            med, bet = truth[(c, m)]
            if m == "3d":
                cap = med * np.exp(bet * rng.standard_normal((nR, 1, nK)))
                cap = np.broadcast_to(cap, (nR, nA, nK))
            else:
                cap = med * np.exp(bet * rng.standard_normal((nR, nA, nK)))
            ratio[i, :, :, :, j] = pga[:, None, :] / cap
    overturned = ratio >= 1.0
    theta_crit = np.array([0.122, 0.08, 0.2, 0.15, 0.1][:nC])
    peak_ratio = np.where(overturned, 5.8, ratio)
    status = np.zeros(ratio.shape, np.int8)
    if failed:
        flat = rng.choice(status.size, size=failed, replace=False)
        status.flat[flat] = 1
    dims = ("column", "record", "angle", "scale", "model")
    ds = xr.Dataset(
        {
            "peak_theta": (dims, peak_ratio * theta_crit[:, None, None, None, None], {"units": "rad"}),
            "peak_theta_ratio": (dims, peak_ratio, {"units": "1"}),
            "overturned": (dims, overturned.astype(np.int8)),
            "overturn_time": (dims, np.where(overturned, 10.0, np.nan), {"units": "s"}),
            "uplifted": (dims, (ratio > 0.01).astype(np.int8)),
            "n_impacts": (dims, np.zeros(ratio.shape, np.int32)),
            "peak_mu_mob": (dims, np.full(ratio.shape, 0.2)),
            "sliding_onset": (dims, np.zeros(ratio.shape, np.int8)),
            "lift_off": (dims, np.zeros(ratio.shape, np.int8)),
            "residual_rotation": (dims, np.zeros(ratio.shape), {"units": "rad"}),
            "residual_displacement": (dims, np.zeros(ratio.shape), {"units": "m"}),
            "status": (dims, status),
        },
        coords={
            "column": np.array(columns, dtype=object),
            "record": np.array([f"SYN-{k + 1:02d}" for k in range(nR)], dtype=object),
            "angle": ("angle", np.asarray(angles, float), {"units": "degree"}),
            "scale": ("scale", np.asarray(scales, float), {"units": "1"}),
            "model": np.array(models, dtype=object),
            "column_R": ("column", np.full(nC, 0.5), {"units": "m"}),
            "column_r": ("column", np.full(nC, 0.4), {"units": "m"}),
            "column_h": ("column", 0.5 / np.tan(theta_crit) * 1.0, {"units": "m"}),
            "slenderness": ("column", 1.0 / np.tan(theta_crit)),
            "beta": ("column", np.full(nC, 0.8)),
            "theta_crit": ("column", theta_crit, {"units": "rad"}),
            "earthquake": ("record", np.array(["Synthetic"] * nR, dtype=object)),
            "station": ("record", np.array([f"ST{k}" for k in range(nR)], dtype=object)),
            "year": ("record", np.full(nR, 2000)),
            "magnitude": ("record", np.full(nR, 6.5)),
            "record_sha256": ("record", np.array(["0" * 64] * nR, dtype=object)),
            "pga": (("record", "scale"), pga, {"units": "m s-2", "long_name": "peak ground acceleration"}),
            "pgv": (("record", "scale"), pga * 0.1, {"units": "m s-1", "long_name": "peak ground velocity"}),
        },
        attrs={"title": "synthetic study results for tests", "Conventions": "CF-1.10"},
    )
    if coordinates:
        ds.coords["latitude"] = ("column", np.linspace(37.97, 38.0, nC), {"units": "degrees_north"})
        ds.coords["longitude"] = ("column", np.linspace(23.72, 23.75, nC), {"units": "degrees_east"})
    return ds, truth
