"""The spread of outcomes over seeds of imperfect drums, as Mouzakis et al. (2002) saw it on the shake table.

The paper's column (R 0.5, r 0.4, h 4 m) in 4 drums with a capital 1.1 x 0.3 m, under FEMA-FF-01's x
component alone (no y, no vertical), perfect and with ten seeds of imperfect drums, at one scale::

    python studies/imperfections/spread.py 1.8 0.002     # scale, tolerance [m]

One line per run (JSON): the peak tilt over theta_crit, the outcome and the body that fell first, the
peaks of the top's tilt in and out of the plane of the drive. docs/model.md ("Imperfect drums") quotes
its table (scales 1.7 and 1.8, tolerances 2 and 5 mm).
"""

import json
import sys
import time

import numpy as np

from pipeline.groundmotion import GroundMotion, load
from pipeline.settings import Excitation, ModelSettings
from pipeline.simulate import simulate
from pipeline.structures.column import Column
from pipeline.structures.drums import Capital, DrumColumn

COLUMN = DrumColumn.equal(Column(0.5, 0.4, 4.0), 4, Capital(1.1, 0.3))


def x_component(record_id="FEMA-FF-01"):
    """The record's x component alone, y zero."""
    record = load(record_id)
    acc = np.asarray(record.acc_x, dtype=np.float64)
    return GroundMotion.from_arrays(acc, np.zeros_like(acc), record.dt, record_id=f"{record_id}-x")


def top_tilts(histories):
    """Peaks of the top body's axis components in (x) and out of (y) the plane of the drive [1]."""
    theta = histories.drum_theta.values[:, -1]
    phi = np.nan_to_num(histories.drum_phi.values[:, -1])  # Z-X-Z: axis (sin phi sin theta, -cos phi sin theta)
    return float(np.max(np.abs(np.sin(theta) * np.sin(phi)))), float(np.max(np.abs(np.sin(theta) * np.cos(phi))))


def run(motion, scale, **options):
    start = time.perf_counter()
    response = simulate(COLUMN, motion, Excitation(scale=scale, vertical=False),
                        ModelSettings(model="3d-compliant", **options))
    s = response.summary
    inside, outside = top_tilts(response.histories)
    return {"scale": scale, "seed": options.get("seed"), "tolerance_m": options.get("imperfections", 0.0),
            "peak_theta_ratio": s["peak_theta_ratio"], "overturned": bool(s["overturned"]),
            "undecided": bool(s["undecided"]), "first_to_fall": s["overturn_body"], "in_plane": inside,
            "out_of_plane": outside, "dislocation_ratio": s["dislocation_ratio"],
            "seconds": time.perf_counter() - start}


def main(scale, tolerance, seeds=range(1, 11)):
    motion = x_component()
    print(json.dumps(run(motion, scale)), flush=True)
    for seed in seeds:
        print(json.dumps(run(motion, scale, imperfections=tolerance, seed=seed)), flush=True)


if __name__ == "__main__":
    main(float(sys.argv[1]), float(sys.argv[2]))
