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


def _run(args):
    drums, record_id, stripe = args
    from pipeline.groundmotion import GroundMotion, load
    from pipeline.settings import Excitation, ModelSettings
    from pipeline.simulate import simulate
    from pipeline.structures.colonnade import Colonnade
    from pipeline.structures.column import Column
    from pipeline.structures.drums import Capital, DrumColumn

    motion = load(record_id)
    ax, ay = np.asarray(motion.acc_x), np.asarray(motion.acc_y)
    factor = stripe * G / float(np.max(np.hypot(ax, ay)))  # as the study scales the pair
    in_plane = GroundMotion.from_arrays(ax, np.zeros_like(ay), motion.dt, record_id=f"{record_id} x only")
    column = DrumColumn.equal(Column(0.5, 0.4, 4.0), drums, Capital(1.1, 0.3))
    frame = Colonnade(column, 2, 2.3, 0.7)
    settings = ModelSettings(model="3d-compliant", normal_stiffness=1e10, friction=0.7, joint_friction=0.6, tail=5.0)
    s = simulate(frame, in_plane, Excitation(angle=0.0, scale=factor), settings, histories=False).summary
    return drums, record_id, stripe, bool(s["overturned"]), bool(s.get("undecided", False))


def _study_counts(path, model):
    import xarray as xr
    ds = xr.open_dataset(path).sel(model=model).squeeze()
    return {round(float(s) / G, 3): int(ds.overturned.sel(scale=s).sum()) for s in ds.scale.values}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args(argv)
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
        counts = [sum(o for d, _, s, o, _ in runs if d == drums and s == st) for st in STRIPES]
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
