"""Overturning of the paper's column under one-sine acceleration pulses.

For pulse frequencies omega_p / p from 1 to 12 and amplitudes a_p / (g tan
alpha) from 1 to 12 (alpha = theta_crit, p = Housner's frequency parameter),
does the column overturn? Three maps: the 2D rocking model, the 3D model under
the same one-directional pulse (planar by construction, so identical to 2D:
by axisymmetry a one-directional motion in any direction is planar rocking),
and the 3D model with a transverse pulse of 10 % of the amplitude and half the
period added along y, where out-of-plane wobbling can develop (rocking is
unstable out of plane, paper Section 3.1).

Run:  python studies/pulses/one_sine.py --out docs/figures/one_sine_overturning.png
"""

import argparse
import math
import time

import numpy as np

from pipeline.structures.column import Column
from pipeline.groundmotion import GroundMotion, one_sine_pulse
from pipeline.plotting import plt
from pipeline.settings import Excitation, ModelSettings
from pipeline.simulate import simulate

COLUMN = Column(0.5, 0.4, 4.0)


def _pulse(ap, tp, transverse):
    main = one_sine_pulse(ap, tp, dt=0.002, duration=tp + 0.01)
    if not transverse:
        return main
    side = one_sine_pulse(transverse * ap, tp / 2, dt=0.002, duration=tp + 0.01)
    return GroundMotion.from_arrays(main.acc_x, side.acc_x, main.dt, record_id="one-sine+transverse")


def overturning_map(frequencies, amplitudes, model, transverse):
    p = COLUMN.frequency_parameter()
    tan_alpha = math.tan(COLUMN.critical_tilt)
    grid = np.zeros((len(amplitudes), len(frequencies)), dtype=bool)
    for j, ratio_w in enumerate(frequencies):
        tp = 2 * math.pi / (ratio_w * p)
        for i, ratio_a in enumerate(amplitudes):
            pulse = _pulse(ratio_a * 9.80665 * tan_alpha, tp, transverse)
            r = simulate(COLUMN, pulse, Excitation(), ModelSettings(model=model, tail=6.0), histories=False)
            grid[i, j] = r.summary["overturned"]
    return grid


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", default="docs/figures/one_sine_overturning.png")
    parser.add_argument("--n", type=int, default=45, help="grid points per axis")
    args = parser.parse_args()
    frequencies = np.linspace(1.0, 12.0, args.n)
    amplitudes = np.linspace(1.0, 12.0, args.n)
    cases = [("2d", 0.0, "2D rocking"), ("3d", 0.0, "3D, pulse along x (stays planar)"),
             ("3d", 0.1, "3D, + transverse pulse (10 %, half the period)")]
    t0 = time.time()
    maps = [overturning_map(frequencies, amplitudes, m, d) for m, d, _ in cases]
    print(f"{3 * args.n**2} simulations in {time.time() - t0:.1f} s")
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.8), sharey=True, constrained_layout=True)
    for ax, grid, (_, _, title) in zip(axes, maps, cases):
        ax.contourf(frequencies, amplitudes, grid.astype(float), levels=[-0.5, 0.5, 1.5], colors=["#d9ecd0", "#e8a29a"])
        ax.contour(frequencies, amplitudes, grid.astype(float), levels=[0.5], colors="k", linewidths=0.8)
        ax.set_title(title)
        ax.set_xlabel(r"pulse frequency $\omega_p / p$ [1]")
    axes[0].set_ylabel(r"pulse amplitude $a_p / (g \tan\alpha)$ [1]")
    from matplotlib.patches import Patch
    axes[2].legend(handles=[Patch(color="#e8a29a", label="overturns"), Patch(color="#d9ecd0", label="stands")],
                   loc="upper left")
    p = COLUMN.frequency_parameter()
    fig.suptitle(f"One-sine pulse overturning, column R = 0.5 m, r = 0.4 m, h = 4 m "
                 f"(p = {p:.2f} rad/s, tan α = {math.tan(COLUMN.critical_tilt):.3f})")
    fig.savefig(args.out, dpi=110)
    print(f"wrote {args.out}")
    differ = int(np.sum(maps[0] != maps[1]))
    oblique = int(np.sum(maps[0] != maps[2]))
    print(f"grid cells where 3D along x differs from 2D: {differ}; where 3D with the transverse pulse "
          f"differs from 2D: {oblique} of {args.n**2}")


if __name__ == "__main__":
    main()
