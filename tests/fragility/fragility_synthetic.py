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


def colonnade_body_labels(n_columns, n_drums, n_blocks):
    """The bodies of a colonnade of ``n_columns`` columns of ``n_drums`` drums and a capital under ``n_blocks``
    epistyle blocks, as a study labels them (docs/studies.md): "column 2 drum 3", "column 2 capital",
    "epistyle block 1"."""
    bodies = [f"column {i} {part}" for i in range(1, n_columns + 1)
              for part in [f"drum {k}" for k in range(1, n_drums + 1)] + ["capital"]]
    return bodies + [f"epistyle block {b}" for b in range(1, n_blocks + 1)]


def make_colonnade_results(n_columns=4, n_drums=3, seed=5, **kwargs):
    """Synthetic results of a study of a colonnade ``row`` beside a column alone ``paper``, run by the
    compliant model (the row as bodies on joints), the rigid frame (the row as one body) and the rigid 3D
    model (each column alone), as ``frustum study run`` writes them (issue 48, item 3).

    Besides :func:`make_results`: ``n_columns`` and ``n_blocks`` per column (1 and 0 for the column
    alone); ``overturn_body`` per run, "" where it stood, else a body drawn at random (the compliant
    model's from :func:`colonnade_body_labels`, its drums and capital for the column alone; "the
    colonnade" for the frame, "the column" for the 3D model); ``epistyle_slip`` and
    ``epistyle_opening`` [m], lognormal, for the compliant model's runs of the row (NaN elsewhere, and
    for the runs that fell); ``dislocation_ratio`` for the compliant model, 0.03 ``peak_theta_ratio``.
    """
    kwargs.setdefault("columns", ("row", "paper"))
    kwargs.setdefault("models", ("3d-compliant", "2d-frame", "3d"))
    ds, truth = make_results(seed=seed, **kwargs)
    rng = np.random.default_rng(seed + 100)
    n_blocks = n_columns - 1
    columns = [str(c) for c in ds["column"].values]
    ds.coords["n_columns"] = ("column", np.array([n_columns if c == "row" else 1 for c in columns]))
    ds.coords["n_blocks"] = ("column", np.array([n_blocks if c == "row" else 0 for c in columns]))
    over = ds["overturned"].values > 0
    bodies = np.full(over.shape, "", dtype=object)
    slip, opening = np.full(over.shape, np.nan), np.full(over.shape, np.nan)
    models = [str(m) for m in ds["model"].values]
    for i, c in enumerate(columns):
        for j, m in enumerate(models):
            cell = (i, Ellipsis, j)
            if m == "3d-compliant":
                labels = (colonnade_body_labels(n_columns, n_drums, n_blocks) if c == "row" else
                          [f"drum {k}" for k in range(1, n_drums + 1)] + ["capital"])
                drawn = rng.choice(np.array(labels, dtype=object), size=over[cell].shape)
            else:
                drawn = np.full(over[cell].shape, "the colonnade" if m == "2d-frame" and c == "row" else "the column",
                                dtype=object)
            bodies[cell] = np.where(over[cell], drawn, "")
            if m == "3d-compliant" and c == "row":
                slip[cell] = np.where(over[cell], np.nan, 0.004 * np.exp(rng.standard_normal(over[cell].shape)))
                opening[cell] = np.where(over[cell], np.nan, 0.002 * np.exp(rng.standard_normal(over[cell].shape)))
    dims = ds["overturned"].dims
    ds["overturn_body"] = (dims, bodies)
    ds["epistyle_slip"] = (dims, slip, {"units": "m"})
    ds["epistyle_opening"] = (dims, opening, {"units": "m"})
    ratio = (0.03 * ds["peak_theta_ratio"]).where(ds["overturned"] == 0, 0.3)  # DS1 from a third of theta_crit
    ds["dislocation_ratio"] = ratio.where(ds["model"] == "3d-compliant").transpose(*dims)
    return ds, truth
