"""The compliant frame of two columns driven by the in-plane component alone (issue 37).

``frame.toml`` drives both models with the FEMA P695 pairs at angle 0: the rigid planar frame
(``2d-frame``) takes the component along the row, the compliant model both components, so its
frame is also shaken across the row, where an epistyle does not brace it. This script reruns the
compliant frames of ``frame.toml`` (4 drums and a capital a column) and of ``frame_cause.toml``
(monolithic shafts) on the stripes 0.6, 0.8 and 1.0 g with the across-row component set to zero
after the pair is scaled as the study scales it (peak of the horizontal resultant = the stripe),
so that both models see the same input, and counts the overturnings against the study files'
results (``out/colonnade/frame.nc``, ``out/colonnade/frame_cause.nc``; run those first)::

    python studies/colonnade/in_plane.py [--workers 2]

Prints a Markdown table (about 8 min on two cores).

The in-plane agreement rests on one bed (1e10 Pa/m, its dashpots calibrated). ``--beds`` spans
that choice: for each normal stiffness given, the drum frame in plane and the rigid planar frame
(``2d-frame``) on the same bed (same stiffness, the restitution the calibrated dashpots reach,
given the bed's dashpots too, as ``frame.toml`` gives them, or its own patch damping), and the
rigid frame with its own restitution (Makris & Vassiliou's, from angular momentum) on rigid ground,
with the outcome cell by cell::

    python studies/colonnade/in_plane.py --beds 1e9,1e10,1e11   # about 30 min on two cores

Is the frame weaker across its row than along it? ``--one-component`` drives the column alone and
the frame of two with the same component (each pair's x) along the row and turned across it::

    python studies/colonnade/in_plane.py --one-component        # 264 runs, about 15 min on two cores
"""

import argparse
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, ROOT)

from pipeline.units import G  # noqa: E402

STRIPES = (0.6, 0.8, 1.0)  # g: where frame.toml's two models disagree most
RECORDS = [f"FEMA-FF-{k:02d}" for k in range(1, 23)]
FRAMES = {"4 drums + capital (frame.toml)": 4, "monolithic shaft + capital (frame_cause.toml)": 1}


def _frame(drums, columns=2):
    """The paper's column in ``drums`` drums with its capital: a frame of ``columns`` under an epistyle, or alone (1)."""
    from pipeline.structures.colonnade import Colonnade
    from pipeline.structures.column import Column
    from pipeline.structures.drums import Capital, DrumColumn

    column = DrumColumn.equal(Column(0.5, 0.4, 4.0), drums, Capital(1.1, 0.3))
    return column if columns == 1 else Colonnade(column, columns, 2.3, 0.7)


def _settings(model="3d-compliant", **bed):
    from pipeline.settings import ModelSettings

    options = dict(normal_stiffness=1e10, friction=0.7, joint_friction=0.6, tail=5.0)
    options.update(bed)  # the compliant model's default scheme unless a variant names its numerics
    return ModelSettings(model=model, **options)


def _run(args):
    """One run driven by the record's x component alone: ``(drums, record, stripe [g])``, optionally followed
    by the model, its bed options, the angle [deg] that component is turned to (0: along the row, 90: across)
    and the number of columns (1: the column alone)."""
    drums, record_id, stripe, *variant = args
    from pipeline.groundmotion import GroundMotion, load
    from pipeline.settings import Excitation
    from pipeline.simulate import simulate

    model, bed, angle, columns = tuple(variant) + ("3d-compliant", {}, 0.0, 2)[len(variant):]
    motion = load(record_id)
    ax, ay = np.asarray(motion.acc_x), np.asarray(motion.acc_y)
    factor = stripe * G / float(np.max(np.hypot(ax, ay)))  # as the study scales the pair
    in_plane = GroundMotion.from_arrays(ax, np.zeros_like(ay), motion.dt, record_id=f"{record_id} x only")
    s = simulate(_frame(drums, columns), in_plane, Excitation(angle=angle, scale=factor), _settings(model, **bed),
                 histories=False).summary
    return drums, record_id, stripe, bool(s["overturned"]), bool(s.get("undecided", False))


def _run_variants(variants, workers, stripes=STRIPES):
    """The runs of each variant ``{name: (model, bed options[, angle, columns])}`` of the 4-drum frame over
    ``stripes`` [g] x :data:`RECORDS`, on a pool: ``{name: [run, ...]}`` (:func:`_run`'s tuples) and the
    wall time [s]."""
    jobs = [(4, r, s, *v) for v in variants.values() for s in stripes for r in RECORDS]
    t0 = time.time()
    with ProcessPoolExecutor(workers) as pool:
        runs = list(pool.map(_run, jobs))
    per = len(stripes) * len(RECORDS)
    return {name: runs[i * per:(i + 1) * per] for i, name in enumerate(variants)}, time.time() - t0


def _counts(runs):
    """Overturnings of ``runs`` at each stripe of :data:`STRIPES`."""
    return [sum(o for _, _, s, o, _ in runs if s == stripe) for stripe in STRIPES]


def _one_component(workers):
    """The column alone and the frame of two, each driven by one component along and across the row: a table."""
    variants = {f"{name}, {where}": ("3d-compliant", {}, angle, columns)
                for name, columns in (("alone", 1), ("frame of 2", 2))
                for where, angle in (("along the row (0 deg)", 0.0), ("across it (90 deg)", 90.0))}
    outcome, seconds = _run_variants(variants, workers)
    print(f"Overturnings of 22 records at each stripe, the x component of each pair alone "
          f"({len(variants) * len(STRIPES) * len(RECORDS)} runs, {seconds:.0f} s on {workers} workers).\n")
    print("| structure, drive | " + " | ".join(f"{s:g} g" for s in STRIPES) + " | all | undecided |")
    print("|---|" + "---|" * (len(STRIPES) + 2))
    for name, rows in outcome.items():
        counts = _counts(rows)
        print(f"| {name} | " + " | ".join(map(str, counts)) + f" | {sum(counts)} | {sum(u for *_, u in rows)} |")


def _bed_band(stiffnesses, workers):
    """The drum frame and the rigid planar frame in plane on beds of each normal stiffness [Pa/m]: a table."""
    from pipeline.models import REGISTRY

    variants, compliant_of = {}, {}  # compliant_of: a rigid frame's variant -> the compliant frame on its bed
    for k in stiffnesses:
        damping, reached = REGISTRY["3d-compliant"].calibrate(_frame(4), _settings(normal_stiffness=k))
        compliant = f"{k:.0e} Pa/m, compliant frame (c_n {damping:.3g} Pa s/m, e {reached:.3f})"
        variants[compliant] = ("3d-compliant", dict(normal_stiffness=k))
        own = f"{k:.0e} Pa/m, 2d-frame at e {reached:.3f}, its own patch damping"
        variants[own] = ("2d-frame", dict(normal_stiffness=k, restitution=reached))
        # the study's one bed ([calibration] bed in frame.toml): the dashpots too
        bed = f"{k:.0e} Pa/m, 2d-frame at e {reached:.3f} and the bed's c_n"
        variants[bed] = ("2d-frame", dict(normal_stiffness=k, restitution=reached, contact_damping=damping))
        compliant_of.update({own: compliant, bed: compliant})
    variants["rigid ground, 2d-frame at its own restitution"] = \
        ("2d-frame", dict(normal_stiffness=float("inf"), friction=float("inf")))
    outcome, seconds = _run_variants(variants, workers)
    print(f"Overturnings of 22 records at each stripe, in plane ({len(variants) * len(STRIPES) * len(RECORDS)} "
          f"runs, {seconds:.0f} s on {workers} workers); 'alike': cells where the bed's two models agree "
          "(undecided runs left out).\n")
    print("| bed, model | " + " | ".join(f"{s:g} g" for s in STRIPES) + " | all | undecided | alike |")
    print("|---|" + "---|" * (len(STRIPES) + 3))
    for name, rows in outcome.items():
        counts = _counts(rows)
        alike = ""
        if name in compliant_of:
            pairs = [(a, b) for a, b in zip(outcome[compliant_of[name]], rows) if not (a[4] or b[4])]
            alike = f"{sum(a[3] == b[3] for a, b in pairs)} of {len(pairs)}"
        print(f"| {name} | " + " | ".join(map(str, counts)) + f" | {sum(counts)} | {sum(u for *_, u in rows)} "
              f"| {alike} |")


def _study_counts(path, model):
    import xarray as xr
    ds = xr.open_dataset(path).sel(model=model).squeeze()
    return {round(float(s) / G, 3): int(ds.overturned.sel(scale=s).sum()) for s in ds.scale.values}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--beds", metavar="K1,K2,...", type=lambda text: [float(k) for k in text.split(",")],
                        help="normal stiffnesses [Pa/m] of the beds to span (see above) instead of the table of "
                             "the study files")
    parser.add_argument("--one-component", action="store_true",
                        help="the column alone and the frame driven by one component along and across the row")
    args = parser.parse_args(argv)
    if args.beds:
        return _bed_band(args.beds, args.workers)
    if args.one_component:
        return _one_component(args.workers)
    jobs = [(d, r, s) for d in FRAMES.values() for s in STRIPES for r in RECORDS]
    t0 = time.time()
    with ProcessPoolExecutor(args.workers) as pool:
        runs = list(pool.map(_run, jobs))
    out = os.path.join(ROOT, "out", "colonnade")
    both = {4: _study_counts(os.path.join(out, "frame.nc"), "compliant"),
            1: _study_counts(os.path.join(out, "frame_cause.nc"), "compliant")}
    rigid = _study_counts(os.path.join(out, "frame.nc"), "frame")
    print(f"Overturnings of 22 records at each stripe ({len(jobs)} compliant runs, {time.time() - t0:.0f} s "
          f"on {args.workers} workers).\n")
    print("| frame | drive | " + " | ".join(f"{s:g} g" for s in STRIPES) + " | all |")
    print("|---|---|" + "---|" * (len(STRIPES) + 1))
    for name, drums in FRAMES.items():
        counts = _counts([run for run in runs if run[0] == drums])
        undecided = sum(u for d, _, _, _, u in runs if d == drums)
        study = [both[drums][round(s, 3)] for s in STRIPES]
        print(f"| {name} | both components (study) | " + " | ".join(map(str, study)) + f" | {sum(study)} |")
        print(f"| {name} | in-plane component only | " + " | ".join(map(str, counts)) + f" | {sum(counts)}"
              + (f" ({undecided} undecided)" if undecided else "") + " |")
    study = [rigid[round(s, 3)] for s in STRIPES]
    print("| rigid planar frame (2d-frame) | in-plane component | " + " | ".join(map(str, study))
          + f" | {sum(study)} |")


if __name__ == "__main__":
    main()
