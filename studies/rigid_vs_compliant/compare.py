"""The rigid model against the independent compliant-contact model, pooled (issue 10).

Three columns, the paper's (R = 0.5, r = 0.4, h = 4 m) and two cylinders with
h/R = 4 and 12 (R = 0.5 m), under the 22 FEMA P695 far-field pairs (both
components, angle 0) scaled to 11 PGA stripes (0.1 g to 3 g). Both models on
the same bed: normal stiffness k_n, the compliant model's dashpots (calibrated
to a target planar restitution, :func:`pipeline.compliant.calibrated_damping`)
and the restitution they reach, friction 0.7. For each column and model the
lognormal overturning fragility is fitted by maximum likelihood, and the
compliant model's median gets a 90 % band by resampling the 22 records with
replacement (1000 resamples). The rigid model passes when its median lies in
that band.

Run:  python studies/rigid_vs_compliant/compare.py [--workers 2] > studies/rigid_vs_compliant/results.md
"""

import argparse
import functools
import json
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from pipeline.atomic import atomic_path
from pipeline.compliant import calibrated_damping
from pipeline.fragility import fit_lognormal
from pipeline.geometry import Column
from pipeline.groundmotion import load
from pipeline.settings import Excitation, ModelSettings
from pipeline.simulate import simulate
from pipeline.units import G

COLUMNS = {
    "paper (R 0.5, r 0.4, h 4 m)": Column(0.5, 0.4, 4.0),
    "cylinder h/R = 4": Column(0.5, 0.5, 2.0),
    "cylinder h/R = 12": Column(0.5, 0.5, 6.0),
}
RECORDS = [f"FEMA-FF-{i:02d}" for i in range(1, 23)]
STRIPES = [0.1, 0.2, 0.3, 0.4, 0.5, 0.65, 0.8, 1.0, 1.5, 2.0, 3.0]  # [g]
STIFFNESS = 1e10  # [Pa/m]
FRICTION = 0.7
N_BOOT = 1000


@functools.lru_cache(maxsize=None)
def settings_pair(column):
    """The compliant settings and the rigid ones on the same bed (stiffness, dashpots, restitution)."""
    compliant = ModelSettings(model="3d-compliant", normal_stiffness=STIFFNESS, friction=FRICTION)
    damping, reached = calibrated_damping(column, compliant)
    compliant = ModelSettings(model="3d-compliant", normal_stiffness=STIFFNESS, friction=FRICTION,
                              restitution=reached, contact_damping=damping)
    rigid = ModelSettings(model="3d", normal_stiffness=STIFFNESS, friction=FRICTION, restitution=reached,
                          contact_damping=damping)
    return compliant, rigid, damping, reached


OUT = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "out",
                   "rigid_vs_compliant")


def _run(job):
    """One run; kept in out/rigid_vs_compliant/ (one JSON file, written atomically) so a rerun resumes."""
    name, model, record, scale = job
    path = os.path.join(OUT, f"column{list(COLUMNS).index(name)}-{model}-{record}-{scale:.9g}.json")
    if os.path.exists(path):
        with open(path, encoding="utf-8") as fh:
            return tuple(json.load(fh))
    column = COLUMNS[name]
    compliant, rigid, _d, _e = settings_pair(column)
    settings = compliant if model == "compliant" else rigid
    t = time.perf_counter()
    s = simulate(column, load(record), Excitation(scale=scale), settings, histories=False).summary
    row = (name, model, record, scale, bool(s["overturned"]), time.perf_counter() - t)
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8") as fh:
        json.dump(row, fh)
    return row


def _fit(rows, records):
    """Lognormal median [g] from (record, pga_g, overturned) rows of the given records (repeats allowed)."""
    im, k = [], []
    for rec in records:
        for pga, over in rows[rec]:
            im.append(pga)
            k.append(1 if over else 0)
    im = np.round(np.array(im), 6)
    levels = np.unique(im)
    n = np.array([np.sum(im == x) for x in levels])
    kk = np.array([sum(o for x, o in zip(im, k) if x == lv) for lv in levels])
    return fit_lognormal(levels, n, kk).median


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    os.makedirs(OUT, exist_ok=True)
    start = time.perf_counter()
    pga = {r: float(np.max(np.hypot(load(r).acc_x, load(r).acc_y))) for r in RECORDS}  # [m/s^2]
    jobs = [(name, model, r, g * G / pga[r]) for name in COLUMNS for model in ("compliant", "rigid")
            for r in RECORDS for g in STRIPES]
    jobs.sort(key=lambda j: j[1] != "compliant")  # the long ones first
    with ProcessPoolExecutor(args.workers) as pool:
        out = list(pool.map(_run, jobs, chunksize=1))
    rng = np.random.default_rng(2026)
    print("# The rigid model against the compliant-contact model, pooled over the far-field set\n")
    print(f"22 FEMA P695 far-field pairs x 11 PGA stripes per column and model, angle 0; both models on the same "
          f"bed (k_n = {STIFFNESS:g} Pa/m, the compliant model's calibrated dashpots and the restitution they "
          f"reach, friction {FRICTION}). Median of the lognormal overturning fragility (maximum likelihood); "
          f"90 % band of the compliant median from {N_BOOT} resamples of the 22 records. Made by "
          f"`python studies/rigid_vs_compliant/compare.py` ({len(jobs)} runs, {sum(row[5] for row in out) / 3600:.1f} "
          f"CPU hours as each run measured itself, on the 2-core machine beside other jobs; this invocation "
          f"{(time.perf_counter() - start) / 60:.0f} min on {args.workers} workers, cached runs reused).\n")
    print("| column | restitution | compliant median PGA [g] | 90 % band [g] | rigid median PGA [g] | inside |"
          " cost per run, compliant / rigid [s] |")
    print("|---|---|---|---|---|---|---|")
    for name, column in COLUMNS.items():
        _c, _r, damping, reached = settings_pair(column)
        rows = {m: {r: [] for r in RECORDS} for m in ("compliant", "rigid")}
        cost = {"compliant": [], "rigid": []}
        for n, model, record, scale, over, seconds in out:
            if n == name:
                rows[model][record].append((scale * pga[record] / G, over))
                cost[model].append(seconds)
        med_c = _fit(rows["compliant"], RECORDS)
        med_r = _fit(rows["rigid"], RECORDS)
        boot = [_fit(rows["compliant"], list(rng.choice(RECORDS, size=len(RECORDS)))) for _ in range(N_BOOT)]
        lo, hi = np.nanpercentile(np.array(boot, dtype=float), [5, 95])
        inside = lo <= med_r <= hi
        print(f"| {name} | {reached:.3f} | {med_c:.3f} | {lo:.3f} - {hi:.3f} | {med_r:.3f} | "
              f"{'yes' if inside else 'no'} | {np.mean(cost['compliant']):.2f} / {np.mean(cost['rigid']):.3f} |")


if __name__ == "__main__":
    sys.exit(main())
