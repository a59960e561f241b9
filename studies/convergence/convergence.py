"""Convergence of peak theta with the integration tolerance, FEMA P695 far field.

The paper's column, 3D model, each far-field record at scale 1 (angle 0), at
rtol 1e-8, 1e-9 (the default), 1e-10 and 1e-11 (atol = rtol / 1000): the
relative change of peak theta against rtol 1e-11, for the records under which
the column stands. Prints a Markdown table and the worst case.

Run:  python studies/convergence/convergence.py > studies/convergence/results.md
"""

import math

from pipeline.structures.column import Column
from pipeline.groundmotion import load_set
from pipeline.settings import ModelSettings
from pipeline.simulate import simulate

COLUMN = Column(0.5, 0.4, 4.0)
RTOLS = (1e-8, 1e-9, 1e-10, 1e-11)


def main():
    print("| record | peak theta [deg] (rtol 1e-11) | " + " | ".join(f"rel. change at {r:g}" for r in RTOLS[:-1])
          + " | rhs calls at 1e-9 |")
    print("|---|---|" + "---|" * (len(RTOLS) - 1) + "---|")
    worst = {r: 0.0 for r in RTOLS[:-1]}
    standing = 0
    for motion in load_set("FEMA-FF"):
        runs = [simulate(COLUMN, motion, settings=ModelSettings(rtol=r, atol=r * 1e-3), histories=False).summary
                for r in RTOLS]
        if not any(s["uplifted"] for s in runs):
            print(f"| {motion.record_id} | never uplifts | | | | |")
            continue
        if any(s["overturned"] for s in runs):
            outcomes = "".join("X" if s["overturned"] else "s" for s in runs)
            print(f"| {motion.record_id} | overturns ({outcomes}) | | | | |")
            continue
        standing += 1
        ref = runs[-1]["peak_theta"]
        rel = [abs(s["peak_theta"] - ref) / ref for s in runs[:-1]]
        for r, v in zip(RTOLS, rel):
            worst[r] = max(worst[r], v)
        print(f"| {motion.record_id} | {math.degrees(ref):.4f} | " + " | ".join(f"{v:.1e}" for v in rel)
              + f" | {runs[1]['rhs_evaluations']} |")
    print()
    print(f"Worst relative change over the {standing} records under which the column stands: "
          + ", ".join(f"rtol {r:g}: {worst[r]:.1e}" for r in RTOLS[:-1]))


if __name__ == "__main__":
    main()
