"""The paper's drum stack in PyBullet on the FEMA P695 far-field cells (issue 25, the peer engine).

The stack, its engine settings and the checks it passed before any record are in
``pybullet_stack.py`` (PyBullet is an optional extra: ``pip install -e '.[peer]'``; never needed
by the package or its tests). This script runs the stack on the cells of
``studies/drums_vs_rigid/paper.toml`` (the 22 far-field pairs, both horizontal components, angle
0, no vertical, each pair scaled so that its peak horizontal resultant equals the stripe), keeps
one JSON row per run under ``out/drums_vs_rigid/pybullet/`` (written atomically, named by a
digest of the settings; a rerun resumes), and writes the cells in the layout of a study's results
(``out/drums_vs_rigid/pybullet.nc``, model ``pybullet``) so that ``frustum report`` compares them
with the study's models by the same statistics::

    python studies/drums_vs_rigid/peer_pybullet.py cells --drums 4 [--workers 1] \
        [--stripes 0.2,0.4,0.6,0.8,1.0,1.5] [--out studies/drums_vs_rigid/results-pybullet.md]
    frustum report out/drums_vs_rigid/paper.nc out/drums_vs_rigid/pybullet.nc \
        --out studies/drums_vs_rigid/paper-report --reference stack
    python studies/drums_vs_rigid/peer_pybullet.py time [--drums 1,4,10]
"""

import argparse
import hashlib
import json
import math
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed

import numpy as np

from pipeline.atomic import atomic_path
from pipeline.units import G

HERE = os.path.dirname(os.path.abspath(__file__))
if HERE not in sys.path:  # the engine beside this script
    sys.path.insert(0, HERE)

from pybullet_stack import (ANGLE, DROP, FRICTION, ITERATIONS, MARGIN, POLYGON, STEP, TAIL,  # noqa: E402
                            TILT_DOWN, _load, _pybullet, checks, paper_stack, pybullet_version, record_run)

REPO = os.path.dirname(os.path.dirname(HERE))
OUT = os.path.join(REPO, "out", "drums_vs_rigid", "pybullet")
RESULTS = os.path.join(REPO, "out", "drums_vs_rigid", "pybullet.nc")
STRIPES = (0.2, 0.4, 0.6, 0.8, 1.0, 1.5)  # PGA [g], paper.toml's
VERSION = 1  # bumped when the model changes under the same settings
MODEL = "pybullet"


def record_info(record):
    """``(peak horizontal resultant [m/s^2], duration [s])`` of a catalog record (the study's ``pga``)."""
    m = _load(record)
    return float(np.max(np.hypot(m.acc_x, m.acc_y))), float(m.duration)


def design(n_drums):
    """What a cached row depends on (named by its digest)."""
    return dict(version=VERSION, engine=f"pybullet {pybullet_version()}", column=repr(paper_stack(n_drums)),
                step=STEP, iterations=ITERATIONS, residual_threshold=0.0, margin=MARGIN, polygon=POLYGON,
                friction=FRICTION, friction_anchor=False, tilt_down=TILT_DOWN, fell="below drum 0's top",
                drop=DROP, tail=TAIL, angle=ANGLE,
                field="uniform, linear between samples, mid-step")


def digest(n_drums):
    return hashlib.sha256(json.dumps(design(n_drums), sort_keys=True).encode()).hexdigest()[:8]


def cell_path(out, n_drums, record, stripe):
    return os.path.join(out, f"paper-{n_drums}drums-{record}-{stripe:.6g}g-{digest(n_drums)}.json")


def run_cell(task):
    """One cell ``(out, n_drums, record, stripe [g])``: its row, from the cache or run and written."""
    out, n_drums, record, stripe = task
    path = cell_path(out, n_drums, record, stripe)
    if os.path.exists(path):
        with open(path, encoding="utf-8") as fh:
            return json.load(fh)
    pga, duration = record_info(record)  # peak horizontal resultant [m/s^2]
    scale = stripe * G / pga
    r = record_run(n_drums, record, scale)
    row = {"column": "paper", "model": f"{MODEL}-{n_drums}", "n_drums": n_drums, "record": record,
           "stripe": float(stripe), "scale": float(scale),
           "overturned": bool(r["overturned"]), "overturn_time": _num(r["overturn_time"]),
           "criterion": r["criterion"], "overturn_drum": int(r["overturn_drum"]), "drop_time": _num(r["drop_time"]),
           "peak_theta": float(r["peak_theta"]), "drum_peak_theta": [float(x) for x in r["drum_peak_theta"]],
           "joint_slip": [float(x) for x in r["joint_slip"]], "steps": int(r["steps"]),
           "cpu": float(r["cpu_total"]), "simulated": float(duration + TAIL), "digest": digest(n_drums)}
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8") as fh:
        json.dump(row, fh)
    return row


def _num(x):
    return None if x is None or (isinstance(x, float) and math.isnan(x)) else float(x)


def run_cells(n_drums, stripes, workers, out=OUT):
    from pipeline.groundmotion import list_records

    os.makedirs(out, exist_ok=True)
    records = [str(r) for r in list_records("FEMA-FF")]
    tasks = [(out, n_drums, rec, s) for s in stripes for rec in records]
    left = sum(not os.path.exists(cell_path(out, n_drums, rec, s)) for _o, _n, rec, s in tasks)
    print(f"{len(tasks)} cells, {left} to run on {workers} process(es)", file=sys.stderr)
    rows, t0 = [], time.time()
    if workers <= 1:
        for k, task in enumerate(tasks):
            rows.append(run_cell(task))
            _progress(k + 1, len(tasks), rows[-1], t0)
    else:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            futures = [pool.submit(run_cell, t) for t in tasks]
            for k, f in enumerate(as_completed(futures)):
                rows.append(f.result())
                _progress(k + 1, len(tasks), rows[-1], t0)
    return sorted(rows, key=lambda r: (r["stripe"], r["record"])), records


def _progress(done, total, row, t0):
    print(f"[{done}/{total}] {row['record']} {row['stripe']:g} g: "
          f"{'down at %.2f s (%s, drum %d)' % (row['overturn_time'], row['criterion'], row['overturn_drum']) if row['overturned'] else 'stood, top %.2f deg' % math.degrees(row['peak_theta'])}"
          f", {row['cpu']:.1f} s CPU ({time.time() - t0:.0f} s wall so far)", file=sys.stderr, flush=True)


def write_results(rows, records, stripes, n_drums, path=RESULTS, column="paper"):
    """The cells as a study's results (dims column, record, angle, scale, model), for ``frustum report``.

    ``scale`` holds the stripes in m/s^2 (every record scaled to the stripe's PGA, as the study's
    intensity targets); ``model`` is ``pybullet``; ``peak_theta`` is the top drum's peak tilt
    [rad] and ``peak_theta_ratio`` it over the outline's theta_crit, as the project's stack.
    """
    from pipeline.dataset import annotate, append_history, write_netcdf
    import xarray as xr

    theta_crit = paper_stack(n_drums).column.critical_tilt
    shape = (1, len(records), 1, len(stripes), 1)
    data = {k: np.full(shape, np.nan) for k in ("peak_theta", "overturn_time")}
    over, status = np.zeros(shape, np.int8), np.ones(shape, np.int8)  # a cell not run: failed
    cell = {(r["record"], r["stripe"]): r for r in rows}
    for i, rec in enumerate(records):
        for j, s in enumerate(stripes):
            r = cell.get((rec, s))
            if r is not None:
                data["peak_theta"][0, i, 0, j, 0] = r["peak_theta"]
                data["overturn_time"][0, i, 0, j, 0] = np.nan if r["overturn_time"] is None else r["overturn_time"]
                over[0, i, 0, j, 0], status[0, i, 0, j, 0] = int(r["overturned"]), 0
    dims = ("column", "record", "angle", "scale", "model")
    ds = xr.Dataset({"peak_theta": (dims, data["peak_theta"]),
                     "peak_theta_ratio": (dims, data["peak_theta"] / theta_crit),
                     "overturn_time": (dims, data["overturn_time"]), "overturned": (dims, over),
                     "status": (dims, status),
                     "pga": (("record", "scale"), np.tile(np.asarray(stripes) * G, (len(records), 1)))},
                    coords={"column": [column], "record": list(records), "angle": [ANGLE],
                            "scale": ("scale", np.asarray(stripes) * G, {"units": "m s-2"}), "model": [MODEL],
                            "theta_crit": ("column", [theta_crit]),
                            "model_description": ("model", [
                                f"the same {n_drums}-drum stack in PyBullet {pybullet_version()}, an independent "
                                f"engine (sequential impulses, step {STEP * 1e3:g} ms, restitution 0, friction "
                                f"{FRICTION:g}, convex-hull drums; studies/drums_vs_rigid/pybullet_stack.py): "
                                "overturned when a drum's axis passes "
                                f"{math.degrees(TILT_DOWN):g} deg or a drum falls off the one below"])})
    annotate(ds)
    ds["scale"].attrs.update(units="m s-2", long_name="target PGA of the stripe")
    ds.attrs.update(title=f"The paper's column in {n_drums} drums in PyBullet {pybullet_version()}",
                    summary="Cells of studies/drums_vs_rigid/paper.toml run in an independent engine (PyBullet, "
                    "studies/drums_vs_rigid/pybullet_stack.py): overturning and the top drum's peak tilt.",
                    model_options=json.dumps(design(n_drums), sort_keys=True))
    append_history(ds, f"studies/drums_vs_rigid/peer_pybullet.py cells --drums {n_drums}")
    return write_netcdf(ds, path)


def report(rows, records, stripes, n_drums):
    """The Markdown report of the PyBullet cells: how, per stripe, every cell.

    Medians with their bands and the comparison with the project's stack, cell by cell, are
    ``frustum report``'s (this script writes the cells as a study's results, :func:`write_results`).
    """
    lines = [f"# The paper's column in {n_drums} drums in PyBullet: FEMA P695 far field", "",
             f"Made by `python studies/drums_vs_rigid/peer_pybullet.py cells --drums {n_drums} --stripes "
             f"{','.join(f'{s:g}' for s in stripes)}` (PyBullet {pybullet_version()}; settings and checks in "
             "`peer_pybullet.md`). The paper's column (R 0.5, r 0.4, h 4 m, marble 2700 kg/m^3) cut into "
             f"{n_drums} equal drums, each a convex hull of {POLYGON}-gons with the project's mass and central "
             f"inertia; ground plane; friction {FRICTION:g} on the ground and the bed joints, restitution 0; step "
             f"{STEP * 1e3:g} ms, {ITERATIONS} solver iterations every step, collision margin {MARGIN:g} m. The 22 "
             "far-field pairs, both horizontal components, angle 0, no vertical, each pair scaled so its peak "
             "horizontal resultant equals the stripe, as a uniform inertial field linear between samples, then a "
             f"{TAIL:g} s free tail. Overturned: a drum's axis past {math.degrees(TILT_DOWN):g} deg (`tilt`; the "
             "project's stack: past its lying tilt, 91.4 deg) or a drum above the bottom one with its centre below "
             "the bottom drum's top face at rest (`fell`), whichever comes first; the run stops there. Also counted, "
             f"not a criterion: runs in which the top drum's centre sank more than {DROP:g} of its height below its "
             "rest height (`drop`).", "",
             "The median overturning PGA with its band, and the comparison with the project's models cell by cell: "
             "`frustum report out/drums_vs_rigid/paper.nc out/drums_vs_rigid/pybullet.nc --reference stack` "
             "(`paper-report/`)."]
    lines += ["", "## Per stripe", "",
              "| PGA [g] | runs | overturned | by tilt / fell | first down, bottom drum first | "
              "top drum sank > half a drum: overturned / stood | "
              "stood: median peak tilt of top drum [deg] | stood: residual bed-joint slip, median / P90 [mm] | "
              "mean CPU per run [s] |",
              "|---|---|---|---|---|---|---|---|---|"]
    for s in stripes:
        rs = [r for r in rows if r["stripe"] == s]
        down = [r for r in rs if r["overturned"]]
        stood = [r for r in rs if not r["overturned"]]
        by = [sum(r["criterion"] == c for r in down) for c in ("tilt", "fell")]
        sank = [sum(r["drop_time"] is not None for r in x) for x in (down, stood)]
        first = [sum(r["overturn_drum"] == k for r in down) for k in range(n_drums)]
        tilt = f"{math.degrees(np.median([r['peak_theta'] for r in stood])):.2f}" if stood else "-"
        slips = np.array([max(r["joint_slip"][1:]) for r in stood]) * 1e3 if stood and n_drums > 1 else None
        slip = f"{np.median(slips):.1f} / {np.percentile(slips, 90):.1f}" if slips is not None else "-"
        lines.append(f"| {s:g} | {len(rs)} | {len(down)} | {by[0]} / {by[1]} | {', '.join(map(str, first))} | "
                     f"{sank[0]} / {sank[1]} | {tilt} | {slip} | {np.mean([r['cpu'] for r in rs]):.2f} |")
    lines += ["", "## Every cell", "",
              "Overturned: `X t` (time [s], criterion, first drum down, 0 the bottom one); stood: peak tilt of the "
              "top drum [deg] / largest residual bed-joint slip [mm].", "",
              "| record | " + " | ".join(f"{s:g} g" for s in stripes) + " |",
              "|---|" + "---|" * len(stripes)]
    cell = {(r["record"], r["stripe"]): r for r in rows}
    for rec in records:
        out = []
        for s in stripes:
            r = cell.get((rec, s))
            if r is None:
                out.append("")
            elif r["overturned"]:
                out.append(f"X {r['overturn_time']:.2f} ({r['criterion']}, {r['overturn_drum']})")
            else:
                slip = max(r["joint_slip"][1:]) * 1e3 if n_drums > 1 else 0.0
                out.append(f"{math.degrees(r['peak_theta']):.2f} / {slip:.1f}")
        lines.append(f"| {rec} | " + " | ".join(out) + " |")
    cpu = sum(r["cpu"] for r in rows)
    lines += ["", f"CPU: {cpu:.0f} s over {len(rows)} runs ({cpu / max(1, len(rows)):.2f} s per run; a run "
              "stops when the stack is down), one process on the shared 2-core x86_64 sandbox."]
    return "\n".join(lines) + "\n"


# -- timing ---------------------------------------------------------------------------------------

def timing(drums=(1, 4, 10), record="FEMA-FF-01", scale=1.0):
    """CPU seconds of one run per stack: ``record`` x ``scale``, 30 s + the tail.

    Twice: the whole 35 s whatever happens (the benchmark's cost), and stopped when the stack
    is down (as the study runs it).
    """
    print(f"PyBullet {pybullet_version()}: {record} x{scale:g}, record + {TAIL:g} s tail, step {STEP * 1e3:g} ms, "
          f"{ITERATIONS} iterations, one process (time.process_time, building the world included)")
    print("| drums | CPU [s], the full run | steps | CPU [s], stopped when down | steps | outcome | "
          "peak tilt of top drum to then [deg] |")
    print("|---|---|---|---|---|---|---|")
    out = {}
    for n in drums:
        full = record_run(n, record, scale, stop=False)
        r = record_run(n, record, scale)
        out[n] = (full, r)
        what = f"down at {r['overturn_time']:.2f} s ({r['criterion']}, drum {r['overturn_drum']})" \
            if r["overturned"] else "stood"
        print(f"| {n} | {full['cpu_total']:.2f} | {full['steps']} | {r['cpu_total']:.2f} | {r['steps']} | {what} | "
              f"{math.degrees(r['peak_theta']):.2f} |", flush=True)
    return out


# -- command line ---------------------------------------------------------------------------------

def _stripes(text):
    try:
        values = tuple(float(x) for x in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"--stripes {text!r}: give PGAs in g separated by commas") from None
    if not values or any(not (math.isfinite(v) and v > 0) for v in values):
        raise argparse.ArgumentTypeError(f"--stripes {text!r}: PGAs must be positive numbers in g")
    return tuple(sorted(set(values)))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="command", required=True)
    sub.add_parser("checks", help="rest, slide closed form, rocking onset (before any record)")
    cells = sub.add_parser("cells", help="the stack on the 22 FEMA P695 far-field pairs at PGA stripes")
    cells.add_argument("--drums", type=int, default=4, help="number of equal drums (default 4)")
    cells.add_argument("--workers", type=int, default=1, help="processes (default 1)")
    cells.add_argument("--stripes", type=_stripes, default=STRIPES, help="PGAs [g], comma-separated")
    cells.add_argument("--out", default=None, help="Markdown report file (default: standard output)")
    tm = sub.add_parser("time", help="CPU seconds of one FEMA-FF-01 x1 run for 1, 4 and 10 drums")
    tm.add_argument("--drums", default="1,4,10", help="stacks to time, comma-separated")
    args = ap.parse_args(argv)
    _pybullet()
    if args.command == "checks":
        return checks()
    if args.command == "time":
        timing(tuple(int(x) for x in args.drums.split(",")))
        return 0
    rows, records = run_cells(args.drums, args.stripes, max(1, args.workers))
    print(f"wrote {write_results(rows, records, args.stripes, args.drums)}", file=sys.stderr)
    text = report(rows, records, args.stripes, args.drums)
    if args.out:
        with atomic_path(args.out) as tmp, open(tmp, "w", encoding="utf-8") as fh:
            fh.write(text)
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
