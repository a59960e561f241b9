"""How much the optional contact damping changes peak theta and overturning.

The paper's column (R = 0.5 m, r = 0.4 m, h = 4 m), 3D model, FEMA P695
far-field records 1-8 (both components, angle 0) at scales 1, 1.5 and 2, with
the viscous contact couple nu = 0 (the paper's model: impacts only), 0.02 and
0.1. Prints a Markdown table (peak theta / theta_crit, X = overturned) and the
energy removed by the couple as a share of the ground's work.

Run:  python studies/dissipation/dissipation.py > studies/dissipation/results.md
"""

from pipeline.structures.column import Column
from pipeline.groundmotion import load
from pipeline.settings import Excitation, ModelSettings
from pipeline.simulate import simulate

COLUMN = Column(0.5, 0.4, 4.0)
RECORDS = [f"FEMA-FF-{i:02d}" for i in range(1, 9)]
SCALES = (1.0, 1.5, 2.0)
DAMPINGS = (0.0, 0.02, 0.1)


def main():
    print("| record | scale | " + " | ".join(f"nu = {d:g}" for d in DAMPINGS) + " | dissipated / work (nu = 0.1) |")
    print("|---|---|" + "---|" * len(DAMPINGS) + "---|")
    overturned = {d: 0 for d in DAMPINGS}
    for rid in RECORDS:
        motion = load(rid)
        for scale in SCALES:
            cells, share = [], float("nan")
            for d in DAMPINGS:
                s = simulate(COLUMN, motion, Excitation(scale=scale), ModelSettings(damping=d), histories=False).summary
                overturned[d] += s["overturned"]
                cells.append("X" if s["overturned"] else f"{s['peak_theta_ratio']:.2f}")
                if d == DAMPINGS[-1] and s["work_ground"] > 0:
                    share = s["energy_dissipated"] / s["work_ground"]
            print(f"| {rid} | {scale:g} | " + " | ".join(cells) + f" | {share:.2f} |")
    n = len(RECORDS) * len(SCALES)
    print()
    print("Overturned: " + ", ".join(f"nu = {d:g}: {overturned[d]} of {n}" for d in DAMPINGS))


if __name__ == "__main__":
    main()
