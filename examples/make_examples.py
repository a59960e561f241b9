"""Write the README's small example inputs: synthetic, named so, and made here (nothing downloaded).

Run from the repository root::

    .venv/bin/python examples/make_examples.py

It writes, from one motion (10 s of Kanai-Tajimi filtered noise, seed 38, two independent
horizontal components, baseline-corrected (linear) and tapered (5 % each end), the larger peak
0.3 g):

* ``examples/synthetic-pair_X.AT2`` and ``_Y.AT2``: the motion as a PEER NGA AT2 pair, one
  file per component, in g (``frustum simulate --record X.AT2,Y.AT2``);
* ``examples/synthetic-record-g.txt``: its x component as one column in g, a sample every
  0.01 s, as OpenSees ``Path`` files hold them (``--units g --dt 0.01 --missing-y zero``);
* ``examples/synthetic-hazard_curve-mean-PGA.csv``: a hazard curve in the layout of the
  OpenQuake engine's CSV export (``frustum risk --hazard FILE``): probabilities of exceedance of
  PGA in 50 years at one site, from the annual rate ``0.1 (1 + a / 0.05 g)^-3`` [1/yr] (a
  made-up site of moderate seismicity, at longitude 0, latitude 0, not any place's hazard).

Every file says in its header that it is synthetic and who wrote it. Everything is
deterministic: running it again writes the same bytes. Licence: MIT, as the project.
"""

import math
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import numpy as np  # noqa: E402

from pipeline.groundmotion import synthesis as syn  # noqa: E402
from pipeline.units import G  # noqa: E402

PAIR = (HERE / "synthetic-pair_X.AT2", HERE / "synthetic-pair_Y.AT2")
RECORD = HERE / "synthetic-record-g.txt"
HAZARD = HERE / "synthetic-hazard_curve-mean-PGA.csv"
#: The hazard curve's levels [g], as an OpenQuake job's intensity_measure_types_and_levels might give them.
LEVELS_G = (0.005, 0.01, 0.02, 0.04, 0.07, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.7, 1.0, 1.3, 1.6, 2.0, 3.0, 4.0)
INVESTIGATION_TIME = 50.0  # [yr]


def motion():
    """The examples' ground motion: processed as a recording's would be, so that it reads without a warning."""
    from pipeline.groundmotion.processing import baseline_correct, taper

    raw = syn.kanai_tajimi(38, duration=10.0, dt=0.01, pga=0.3 * G, record_id="synthetic-pair")
    gm = taper(baseline_correct(raw, "linear"), 0.05)  # from rest, to rest
    peak = max(float(np.abs(gm.acc_x).max()), float(np.abs(gm.acc_y).max()))
    return gm.scaled(0.3 * G / peak)


def write_pair(gm, paths=PAIR):
    """The motion as a PEER AT2 pair (x, y), the PEER format's 7 significant digits."""
    from obspy import Stream

    from pipeline.groundmotion.at2 import write_at2

    for component, trace, path in zip("XY", gm.stream, paths):
        trace = trace.copy()
        trace.stats.channel = f"HN{component}"
        trace.stats.station = "SYNTH"
        write_at2(Stream([trace]), path, event="SYNTHETIC, not a recording (examples/make_examples.py)",
                  date="1/1/2000")
    return paths


def write_record(gm, path=RECORD):
    """The motion's x component as one column in g (y is given as zero on the command line)."""
    lines = ["# SYNTHETIC ground acceleration, not a recording: Kanai-Tajimi filtered noise (seed 38), 10 s,",
             "# baseline-corrected and tapered, written by examples/make_examples.py (MIT licence); the x component of",
             "# examples/synthetic-pair_X.AT2. One column: acceleration [g], a sample every 0.01 s."]
    lines += [f"{value: .6f}" for value in gm.acc_x / G]
    path.write_text("\n".join(lines) + "\n", encoding="ascii")
    return path


def annual_rate(level_g):
    """The made-up site's annual rate of exceeding a PGA [1/yr] at ``level_g`` [g]."""
    return 0.1 * (1.0 + level_g / 0.05) ** -3


def write_hazard(path=HAZARD):
    """The hazard curve in the OpenQuake engine's CSV layout (its metadata row says who made it)."""
    poe = [1.0 - math.exp(-annual_rate(a) * INVESTIGATION_TIME) for a in LEVELS_G]
    header = ["lon", "lat", "depth"] + [f"poe-{a:.7f}" for a in LEVELS_G]
    meta = ("generated_by='examples/make_examples.py: a SYNTHETIC curve, not an OpenQuake result', "
            f"kind='mean', investigation_time={INVESTIGATION_TIME}, imt='PGA'")
    rows = ["#" + "," * (len(header) - 1) + f'"{meta}"', ",".join(header),
            ",".join(["0.00000", "0.00000", "0.00000"] + [f"{p:.6E}" for p in poe])]
    path.write_text("\n".join(rows) + "\n", encoding="ascii")
    return path


if __name__ == "__main__":
    gm = motion()
    for written in (*write_pair(gm), write_record(gm), write_hazard()):
        print(f"wrote {written.relative_to(HERE.parent)} ({written.stat().st_size} bytes)")
