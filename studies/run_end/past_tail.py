"""How far past the record and its tail the runs of a study went (issue 38, item 0).

Study results keep no end time. A run that went on past its tail (the column still able to
overturn, or its swing still rising, when the tail ended) ends in another state than before,
so its ``residual_displacement`` and ``energy_balance_error`` differ from the old code's; up
to the tail both codes integrate the same equations with the same steps, so nothing else can
change those. This script re-simulates with the new code, with histories, every run of a
model whose results changed, and a random sample of the runs that did not change, and
reports where each run ended (the last history row, every ``output_step`` = 0.01 s) against
the end of its record and tail. Each re-simulated run is checked against the new results file.

Usage (from the checkout root, with the new code on the path)::

    python studies/run_end/past_tail.py OLD.nc NEW.nc [--sample 200] [--json FILE.json]
"""

import argparse
import json
import os
import sys

import numpy as np
import xarray as xr

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(os.path.dirname(HERE)))
sys.path.insert(0, HERE)

from compare import FLOATS, INTS, _model_cells, _moved  # noqa: E402
from pipeline.groundmotion import load  # noqa: E402
from pipeline.settings import Excitation, ModelSettings  # noqa: E402
from pipeline.simulate import simulate  # noqa: E402
from pipeline.structures.column import Column  # noqa: E402

OUTPUT_STEP = 0.01  # [s] the histories' default sampling: the end is known to this


def changed_cells(o, n):
    """(column, record, angle, scale) indices of the cells where any result differs."""
    any_change = np.zeros(o["peak_theta"].shape, bool)
    for name in FLOATS:
        any_change |= _moved(o[name].values, n[name].values)
    for name in INTS + ("overturned",):
        any_change |= o[name].values != n[name].values
    if "undecided" in n:
        any_change |= n["undecided"].values == 1
    return any_change


def rerun(n, cell, model, options, motions):
    c, r, a, s = cell
    column = Column(float(n["column_R"].values[c]), float(n["column_r"].values[c]), float(n["column_h"].values[c]))
    rec = str(n["record"].values[r])
    if rec not in motions:
        motions[rec] = load(rec)
    motion = motions[rec]
    factor = float(n["scale_factor"].values[r, s])
    settings = ModelSettings(model=model, **options)
    resp = simulate(column, motion, Excitation(angle=float(n["angle"].values[a]), scale=factor,
                                               vertical=n.attrs.get("vertical_component") == "used"),
                    settings, histories=True)
    end = float(resp.histories["time"].values[-1])
    t_end = motion.duration + options.get("tail", 5.0)
    same = (resp.summary["peak_theta"] == float(n["peak_theta"].values[c, r, a, s])
            and resp.summary["residual_displacement"] == float(n["residual_displacement"].values[c, r, a, s]))
    return {"column": str(n["column"].values[c]), "record": rec, "angle": float(n["angle"].values[a]),
            "scale": float(n["scale"].values[s]), "run_end": t_end, "history_end": end,
            "past_tail": end - t_end, "overturned": bool(resp.summary["overturned"]),
            "undecided": bool(resp.summary["undecided"]), "matches_results": bool(same)}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("old")
    parser.add_argument("new")
    parser.add_argument("--sample", type=int, default=200, help="unchanged runs re-simulated per model")
    parser.add_argument("--seed", type=int, default=38)
    parser.add_argument("--json")
    args = parser.parse_args(argv)
    old, new = xr.load_dataset(args.old), xr.load_dataset(args.new)
    options = {k: v for k, v in json.loads(new.attrs.get("model_options", "{}")).items()}
    rng = np.random.default_rng(args.seed)
    motions, report = {}, {}
    for model in (str(m) for m in new["model"].values):
        o, n = _model_cells(old, model), _model_cells(new, model)
        changed = changed_cells(o, n)
        unchanged = np.argwhere(~changed & (n["overturned"].values == 0))
        pick = unchanged[rng.choice(len(unchanged), size=min(args.sample, len(unchanged)), replace=False)]
        runs = [rerun(n, tuple(cell), model, options, motions) for cell in np.argwhere(changed)]
        sample = [rerun(n, tuple(cell), model, options, motions) for cell in pick]
        past = np.array([r["past_tail"] for r in runs])
        went_on = past > 0.5 * OUTPUT_STEP
        report[model] = {
            "changed_runs": len(runs),
            "changed_runs_past_tail": int(went_on.sum()),
            "past_tail_s": ({"median": float(np.median(past[went_on])), "max": float(past[went_on].max()),
                             "p90": float(np.percentile(past[went_on], 90))} if went_on.any() else None),
            "changed_runs_matching_results": int(sum(r["matches_results"] for r in runs)),
            "sample_unchanged_standing": len(sample),
            "sample_past_tail": int(sum(r["past_tail"] > 0.5 * OUTPUT_STEP for r in sample)),
            "sample_matching_results": int(sum(r["matches_results"] for r in sample)),
            "runs": runs,
        }
        short = {k: v for k, v in report[model].items() if k != "runs"}
        print(model, json.dumps(short))
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(report, fh, indent=1)


if __name__ == "__main__":
    main()
