"""Re-simulate a study's runs that lifted off, or changed, with the current code: did a flight sink?

A rigid run whose contact could neither push nor fly entered a flight that sank from its first
instant (its landing event never fired): the column went through the ground, its tilt turning at
the flight's constant rate until it reached the lying tilt, and the run said "overturned"
(``pipeline.dynamics.rigid.loop.holds_rim``). This script re-runs, with the code on the path:

- ``--changed FILE.json``: the runs that :file:`compare.py` (branch ``run-end``) listed as changed
  in outcome, ``models[i]["changed_outcome_runs"]`` (each with its model);
- ``--lift-off``: every run of the results file with ``lift_off`` = 1 (one incidence angle of an
  angle-invariant model: the others are the same run turned);
- ``--sample N``: N runs per model drawn at random (``--seed``) among the others (not changed,
  not lifted off in the file), which the fix must leave as they were.

Each run goes through the rigid kernel as :func:`pipeline.simulate.simulate_rigid` makes it, with
the results file's options, record scale factor (``scale_factor``) and vertical component; its
summary is compared variable by variable (``pipeline.models.rigid.RESULTS``) with the file
(bit for bit, NaN equal to NaN), and the lowest point of the base is followed through the flight
phases at the output rows (every ``output_step``): the centre of mass's height less
``z_cm cos(theta) + R sin(theta)``, per R; below ``-DEPTH`` the run went through the ground.
Printed per model and selection: how many runs overturn, stand or are undecided now, how many
flew or went through the ground, how many match the file, and which variables moved. With
``--point-contact`` each run is also made on a rigid base (``normal_stiffness`` inf: a point
contact without the patch whose couple causes the holds), an independent reference for the
outcomes: how many of the new outcomes, and of the file's, agree with it.

Usage (from the checkout root, the code to check on the path; most runs take a fraction of a second)::

    python studies/run_end/landing_rerun.py RESULTS.nc [--changed FILE.json] [--lift-off]
        [--sample 200] [--seed 38] [--point-contact] [--json OUT.json]

e.g. ``python studies/run_end/landing_rerun.py out/model_2d_vs_3d.nc --changed
model_2d_vs_3d.json --lift-off --sample 200 --point-contact --json landing.json``: 4066 runs, each
twice, in 3.5 min on one core (2026-11-28, load ~2; the kernels compiled before).
"""

import argparse
import json
import math
import os
import sys
import time

import numpy as np
import xarray as xr

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(os.path.dirname(HERE)))

from pipeline import simulate as S  # noqa: E402
from pipeline.dynamics.rigid import frustum as fk  # noqa: E402
from pipeline.dynamics.rigid import rocking as rk  # noqa: E402
from pipeline.dynamics.rigid.layout import PHASE_FLIGHT  # noqa: E402
from pipeline.groundmotion import load  # noqa: E402
from pipeline.models import REGISTRY  # noqa: E402
from pipeline.models.rigid import RESULTS  # noqa: E402
from pipeline.settings import Excitation, ModelSettings  # noqa: E402
from pipeline.structures.column import Column  # noqa: E402

DEPTH = 1e-3  # [R] far below any contact penetration of a rigid run (the patch's is ~1e-6 R)


def cells_of(ds, model):
    """The model's results as (column, record, angle, scale) arrays."""
    return ds.sel(model=model).transpose("column", "record", "angle", "scale")


def lowest_base_point(raw, column, planar):
    """Lowest height of the base above the ground in flight [R] (inf without flight rows)."""
    zc = column.z_cm / column.R
    flight = raw.phase[:raw.states.shape[0]] == PHASE_FLIGHT
    st = raw.states[flight]
    if not st.shape[0]:
        return math.inf
    if planar:
        th = np.abs(st[:, rk.THETA2])
        z = st[:, rk.Z2]
    else:
        th = st[:, fk.THETA]
        z = st[:, fk.ZC]
    return float(np.min(z - (zc * np.cos(th) + np.sin(th))))


def same(a, b):
    return a == b or (isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b))


def outcome_of(summary):
    return "undecided" if summary["undecided"] else ("overturned" if summary["overturned"] else "stands")


def run_one(column, motion, excitation, settings):
    """simulate_rigid's own steps, keeping the kernel's raw arrays (the flight's heights): (raw, summary)."""
    planar = REGISTRY[settings.model].planar
    y0 = np.zeros(rk.N_STATE2 if planar else fk.N_STATE)
    raw = S._run(column, settings, S.kernel_record(motion, excitation, planar), motion.dt / S.time_scale(column.R),
                 y0, motion.duration + settings.tail, settings.settle_limit)
    return raw, S.kernel_summary(raw, column.R, column.critical_tilt, settings, motion, excitation)


def rerun(one, cell, model, options, vertical, motions, point_contact=False):
    """One run of the results file ``one`` (a model's cells) with the code on the path."""
    c, r, a, s = cell
    column = Column(float(one["column_R"].values[c]), float(one["column_r"].values[c]),
                    float(one["column_h"].values[c]))
    rec = str(one["record"].values[r])
    if rec not in motions:
        motions[rec] = load(rec)
    motion = motions[rec]
    angle = float(one["angle"].values[a])
    factor = float(one["scale_factor"].values[r, s])
    settings = ModelSettings(model=model, **options)
    excitation = Excitation(angle=angle, scale=factor, vertical=vertical)
    planar = REGISTRY[model].planar
    start = time.perf_counter()
    raw, summary = run_one(column, motion, excitation, settings)
    seconds = time.perf_counter() - start
    moved = []
    for name in RESULTS:
        if name not in one or name not in summary:
            continue
        was = one[name].values[c, r, a, s].item()
        now = summary[name]
        if isinstance(now, bool):
            now = int(now)
        if not same(float(now), float(was)):
            moved.append(name)
    low = lowest_base_point(raw, column, planar)
    outcome = outcome_of(summary)
    was_outcome = ("undecided" if "undecided" in one and one["undecided"].values[c, r, a, s] == 1
                   else "overturned" if one["overturned"].values[c, r, a, s] == 1 else "stands")
    return {"column": str(one["column"].values[c]), "record": rec, "angle": angle,
            "scale": float(one["scale"].values[s]), "factor": factor, "outcome": outcome, "was": was_outcome,
            "lift_off": bool(summary["lift_off"]), "lift_off_was": bool(one["lift_off"].values[c, r, a, s]),
            "lowest_base_point_R": low, "through_ground": bool(low < -DEPTH),
            "overturn_time": summary["overturn_time"], "peak_theta": summary["peak_theta"],
            "energy_balance_error": summary["energy_balance_error"], "moved": moved, "seconds": seconds,
            "point_contact": (outcome_of(run_one(column, motion, excitation,
                                                 ModelSettings(model=model, **{**options,
                                                                               "normal_stiffness": math.inf}))[1])
                              if point_contact else None)}


def tally(runs):
    """Counts of a selection's re-simulated runs."""
    moved = {}
    for x in runs:
        for name in x["moved"]:
            moved[name] = moved.get(name, 0) + 1
    out = {"runs": len(runs)}
    for key in ("overturned", "stands", "undecided"):
        out[key] = sum(x["outcome"] == key for x in runs)
        out[f"{key}_in_file"] = sum(x["was"] == key for x in runs)
    out.update({
        "lift_off": sum(x["lift_off"] for x in runs),
        "through_ground": sum(x["through_ground"] for x in runs),
        "lowest_base_point_R": min((x["lowest_base_point_R"] for x in runs), default=math.inf),
        "identical_to_file": sum(not x["moved"] for x in runs),
        "moved_variables": moved,
        "largest_budget_error_m": max((abs(x["energy_balance_error"]) for x in runs), default=0.0),
        "agrees_with_point_contact": sum(x["outcome"] == x["point_contact"] for x in runs),
        "file_agrees_with_point_contact": sum(x["was"] == x["point_contact"] for x in runs),
        "seconds": sum(x["seconds"] for x in runs),
    })
    return out


def index_of(one, run):
    """(column, record, angle, scale) indices of a run named by its coordinates."""
    return (int(np.flatnonzero(one["column"].values == run["column"])[0]),
            int(np.flatnonzero(one["record"].values == run["record"])[0]),
            int(np.flatnonzero(np.isclose(one["angle"].values, run["angle"]))[0]),
            int(np.flatnonzero(np.isclose(one["scale"].values, run["scale"]))[0]))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("results")
    parser.add_argument("--changed", help="compare.py's JSON: its changed_outcome_runs are re-simulated")
    parser.add_argument("--lift-off", action="store_true", help="re-simulate every run that lifted off")
    parser.add_argument("--sample", type=int, default=0, help="other runs re-simulated per model, at random")
    parser.add_argument("--seed", type=int, default=38)
    parser.add_argument("--point-contact", action="store_true",
                        help="also run each on a point contact (normal_stiffness inf), the outcomes' reference")
    parser.add_argument("--json")
    args = parser.parse_args(argv)
    ds = xr.load_dataset(args.results)
    options = json.loads(ds.attrs.get("model_options", "{}"))
    vertical = ds.attrs.get("vertical_component") == "used"
    changed = {}
    if args.changed:
        with open(args.changed, encoding="utf-8") as fh:
            for entry in json.load(fh)["models"]:
                changed[entry["model"]] = entry.get("changed_outcome_runs", [])
    rng = np.random.default_rng(args.seed)
    motions, report = {}, {}
    for model in (str(m) for m in ds["model"].values):
        one = cells_of(ds, model)
        picked = {}
        if changed.get(model):
            picked["changed"] = [index_of(one, run) for run in changed[model]]
        lifted = one["lift_off"].values == 1
        if REGISTRY[model].angle_invariant:
            lifted[:, :, 1:, :] = False  # the other angles are the same run, turned
        if args.lift_off:
            picked["lift_off"] = [tuple(int(i) for i in cell) for cell in np.argwhere(lifted)]
        if args.sample:
            other = ~(one["lift_off"].values == 1)
            for cell in picked.get("changed", []):
                other[cell] = False
            pool = np.argwhere(other)
            pick = pool[rng.choice(len(pool), size=min(args.sample, len(pool)), replace=False)]
            picked["sample"] = [tuple(int(i) for i in cell) for cell in pick]
        report[model] = {}
        for name, cells in picked.items():
            runs = [rerun(one, cell, model, options, vertical, motions, args.point_contact) for cell in cells]
            report[model][name] = {"summary": tally(runs), "runs": runs}
            print(model, name, json.dumps(report[model][name]["summary"]), flush=True)
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(report, fh, indent=1)


if __name__ == "__main__":
    main()
