"""Compare a study's results before and after the end-of-run change (issue 38, item 0).

Two results files of the same study file, one written by the code before commit 14e56f2
(``old``) and one after it (``new``), are compared cell by cell: outcome (stands, overturned,
undecided), peak theta, the other summary variables, and the fitted fragility medians.
The 3D model does not depend on the incidence angle (its runs are computed once per column,
record and stripe): its runs are counted at the first angle only, after checking that every
angle holds the same numbers.

Usage (from the checkout root, with the new code on the path)::

    python studies/run_end/compare.py OLD.nc NEW.nc [--json FILE.json]
"""

import argparse
import json
import math
import os
import sys

import numpy as np
import xarray as xr

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(os.path.dirname(HERE)))

from pipeline import fragility as F  # noqa: E402
from pipeline.groundmotion import load  # noqa: E402
from pipeline.models import REGISTRY  # noqa: E402

REL = 1e-9  # a peak has moved when |new - old| > REL |old| (the brief's threshold)
FLOATS = ("peak_theta", "peak_time", "overturn_time", "uplift_time", "peak_mu_mob", "residual_rotation",
          "residual_displacement", "work_ground", "energy_balance_error")
INTS = ("n_impacts", "uplifted", "sliding_onset", "lift_off", "status")


def _moved(a, b, rel=REL):
    """Cells whose float differs beyond ``rel`` relative (NaN against NaN is no change)."""
    both_nan = np.isnan(a) & np.isnan(b)
    diff = np.abs(b - a) > rel * np.abs(a)
    return ~both_nan & (diff | (np.isnan(a) != np.isnan(b)))


def _model_cells(ds, model):
    """One model's cells as (column, record, angle, scale); a model that does not depend on the
    angle is kept at the first angle, after checking that the others equal it."""
    one = ds.sel(model=model)
    if getattr(REGISTRY.get(model), "angle_invariant", False):
        for name in ("peak_theta", "overturned"):
            v = one[name].values
            same = (v == v[:, :, :1, :]) | (np.isnan(v) & np.isnan(v[:, :, :1, :])) if v.dtype.kind == "f" \
                else v == v[:, :, :1, :]
            if not same.all():
                raise SystemExit(f"{model}: {name} differs between angles; count every angle")
        one = one.isel(angle=[0])
    return one.transpose("column", "record", "angle", "scale")


def _stats(x):
    x = np.asarray(x, dtype=float)
    if x.size == 0:
        return None
    return {"median": float(np.median(x)), "max": float(np.max(x)), "min": float(np.min(x))}


def _run_end(ds):
    """End of each record and its tail [s], per record: the record's duration plus the study's tail."""
    tail = float(json.loads(ds.attrs.get("model_options", "{}")).get("tail", 5.0))
    return np.array([load(str(r)).duration + tail for r in ds["record"].values]), tail


def compare_model(old, new, model, t_end):
    o, n = _model_cells(old, model), _model_cells(new, model)
    runs = int(o["peak_theta"].size)
    crit = o["theta_crit"].values[:, None, None, None]
    t_end = np.broadcast_to(t_end[None, :, None, None], o["peak_theta"].shape)
    ov_o = o["overturned"].values == 1
    ov_n = n["overturned"].values == 1
    un_n = n["undecided"].values == 1 if "undecided" in n else np.zeros_like(ov_n)
    st_o, st_n = ~ov_o, ~ov_n & ~un_n
    out = {"model": model, "runs": runs,
           "status_nonzero_old": int((o["status"].values != 0).sum()),
           "status_nonzero_new": int((n["status"].values != 0).sum()),
           "outcome_old": {"stands": int(st_o.sum()), "overturned": int(ov_o.sum())},
           "outcome_new": {"stands": int(st_n.sum()), "overturned": int(ov_n.sum()), "undecided": int(un_n.sum())},
           "stands_to_overturned": int((st_o & ov_n).sum()),
           "stands_to_undecided": int((st_o & un_n).sum()),
           "overturned_to_stands": int((ov_o & st_n).sum()),
           "overturned_to_undecided": int((ov_o & un_n).sum())}
    pk_o, pk_n = o["peak_theta"].values, n["peak_theta"].values
    moved = _moved(pk_o, pk_n)
    same_outcome = (st_o & st_n) | (ov_o & ov_n)
    out["peak_moved"] = int(moved.sum())
    out["peak_moved_outcome_changed"] = int((moved & ~same_outcome).sum())
    out["peak_moved_stands_both"] = int((moved & st_o & st_n).sum())
    out["peak_moved_overturned_both"] = int((moved & ov_o & ov_n).sum())
    out["peak_moved_down"] = int((moved & (pk_n < pk_o)).sum())
    keep = moved & st_o & st_n
    if keep.any():
        d = pk_n[keep] - pk_o[keep]
        rel = d / np.where(pk_o[keep] > 0, pk_o[keep], np.nan)
        out["stands_both_peak_change_deg"] = _stats(np.degrees(d))
        out["stands_both_peak_change_rel"] = _stats(rel[np.isfinite(rel)]) if np.isfinite(rel).any() else None
        out["stands_both_peak_from_zero"] = int((pk_o[keep] == 0).sum())
        out["stands_both_peak_change_ratio"] = _stats((d / np.broadcast_to(crit, pk_o.shape)[keep]))
        out["stands_both_new_peak_after_tail"] = int((n["peak_time"].values[keep] > t_end[keep] + 1e-9).sum())
        out["stands_both_new_peak_ratio"] = _stats(n["peak_theta"].values[keep]
                                                   / np.broadcast_to(crit, pk_o.shape)[keep])
    newly = st_o & ov_n
    if newly.any():
        out["new_overturn_after_tail"] = int((n["overturn_time"].values[newly] > t_end[newly]).sum())
        out["new_overturn_time_past_tail_s"] = _stats(n["overturn_time"].values[newly] - t_end[newly])
        out["new_overturn_old_peak_ratio"] = _stats(pk_o[newly] / np.broadcast_to(crit, pk_o.shape)[newly])
    if un_n.any():
        out["undecided_old_peak_ratio"] = _stats(pk_o[un_n] / np.broadcast_to(crit, pk_o.shape)[un_n])
    out["changed"] = {}
    for name in FLOATS:
        out["changed"][name] = int(_moved(o[name].values, n[name].values).sum())
    for name in INTS:
        out["changed"][name] = int((o[name].values != n[name].values).sum())
    ot = ov_o & ov_n
    out["overturn_time_moved_both_overturned"] = int(_moved(o["overturn_time"].values[ot],
                                                            n["overturn_time"].values[ot]).sum())
    any_change = moved.copy()
    for name in FLOATS:
        any_change |= _moved(o[name].values, n[name].values)
    for name in INTS + ("overturned",):
        any_change |= o[name].values != n[name].values
    any_change |= un_n
    out["any_variable_changed"] = int(any_change.sum())
    # where the changed runs are: per column and per record
    out["changed_outcome_by_column"] = {str(c): int(v) for c, v in zip(
        o["column"].values, (~same_outcome).sum(axis=(1, 2, 3))) if v}
    out["peak_moved_by_column"] = {str(c): int(v) for c, v in zip(o["column"].values, moved.sum(axis=(1, 2, 3))) if v}
    cells = np.argwhere(~same_outcome)
    out["changed_outcome_runs"] = [
        {"column": str(o["column"].values[c]), "record": str(o["record"].values[r]),
         "angle": float(o["angle"].values[a]), "scale": float(o["scale"].values[s]),
         "old": "overturned" if ov_o[c, r, a, s] else "stands",
         "new": "overturned" if ov_n[c, r, a, s] else ("undecided" if un_n[c, r, a, s] else "stands"),
         "old_peak_ratio": float(pk_o[c, r, a, s] / crit[c, 0, 0, 0]),
         "new_overturn_time": float(n["overturn_time"].values[c, r, a, s]),
         "run_end": float(t_end[c, r, a, s])} for c, r, a, s in cells]
    return out


def compare_fragility(old, new):
    """Fitted medians and dispersions, old and new, for every (state, column, model) that moved."""
    fo, fn = F.fragility(old), F.fragility(new)
    rows = []
    for state in fo["state"].values:
        for column in fo["column"].values:
            for model in fo["model"].values:
                a = fo.sel(state=state, column=column, model=model)
                b = fn.sel(state=state, column=column, model=model)
                ma, mb = float(a["median"]), float(b["median"])
                row = {"state": str(state), "column": str(column), "model": str(model),
                       "median_old": ma, "median_new": mb, "beta_old": float(a["beta"]), "beta_new": float(b["beta"]),
                       "n_exceed_old": int(a["n_exceed"]), "n_exceed_new": int(b["n_exceed"]),
                       "n_runs_old": int(a["n_runs"]), "n_runs_new": int(b["n_runs"]),
                       "n_undecided_new": int(fn["n_undecided"].sel(column=column, model=model))}
                row["moved"] = bool(_moved(np.array([ma]), np.array([mb]))[0]
                                    or _moved(np.array([row["beta_old"]]), np.array([row["beta_new"]]))[0]
                                    or row["n_exceed_old"] != row["n_exceed_new"] or row["n_runs_old"] != row["n_runs_new"])
                rows.append(row)
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("old")
    parser.add_argument("new")
    parser.add_argument("--json", help="write everything here")
    args = parser.parse_args(argv)
    old = xr.load_dataset(args.old)
    new = xr.load_dataset(args.new)
    for coord in ("column", "record", "angle", "scale", "model"):
        if not np.array_equal(old[coord].values, new[coord].values):
            raise SystemExit(f"{coord}: the two files do not hold the same grid")
    for coord in ("scale_factor", "pga"):
        if not np.array_equal(old[coord].values, new[coord].values):
            raise SystemExit(f"{coord}: the two files scale the records differently")
    t_end, tail = _run_end(old)
    report = {"old": args.old, "new": args.new, "tail_s": tail,
              "models": [compare_model(old, new, str(m), t_end) for m in old["model"].values]}
    report["fragility"] = compare_fragility(F.open_results(args.old), F.open_results(args.new))
    for m in report["models"]:
        short = {k: v for k, v in m.items() if k not in ("changed_outcome_runs",)}
        print(json.dumps(short, indent=1))
    moved = [r for r in report["fragility"] if r["moved"]]
    print(f"fragility: {len(moved)} of {len(report['fragility'])} (state, column, model) fits moved")
    for r in moved:
        print(f"  {r['state']:>20s} {r['column']:>16s} {r['model']:>3s}: median {r['median_old']:.6g} -> "
              f"{r['median_new']:.6g} m/s2 ({100 * (r['median_new'] / r['median_old'] - 1):+.3f} %), beta "
              f"{r['beta_old']:.4g} -> {r['beta_new']:.4g}, exceed {r['n_exceed_old']} -> {r['n_exceed_new']}, "
              f"runs {r['n_runs_old']} -> {r['n_runs_new']} (undecided {r['n_undecided_new']})")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(report, fh, indent=1)


if __name__ == "__main__":
    main()
