"""Speed of one earthquake response: compiled event-driven integrator vs scipy.

The paper's column (R = 0.5 m, r = 0.4 m, h = 4 m) under FEMA P695 far-field
record 1 (both components, angle 0) at scales 1, 2 and 3, the 3D model, side
by side in one run:

* compiled: :func:`pipeline.dynamics.rigid.run3d.run_frustum` (numba DOP853 with
  events), timed as the best of several calls after compilation, and the
  whole :func:`pipeline.simulate.simulate` call (summary included, no
  histories);
* scipy: the same model with every rolling phase integrated by
  ``solve_ivp(method="DOP853")`` at the same tolerances, in a subprocess with
  ``NUMBA_DISABLE_JIT=1`` so that the right-hand side is plain Python.

Run by hand:  python benchmarks/bench_response.py [--rtol 1e-9] [--repeat 5]
"""

import argparse
import json
import math
import os
import platform
import subprocess
import sys
import time

import numpy as np

COLUMN = (0.5, 0.4, 4.0)
RECORD = "FEMA-FF-01"
SCALES = (1.0, 2.0, 3.0)


def _problem(scale, rtol):
    from pipeline.dynamics.rigid import frustum as fk
    from pipeline.dynamics.rigid import layout as lay
    from pipeline.structures.column import Column
    from pipeline.groundmotion import load
    from pipeline.settings import ModelSettings
    from pipeline.simulate import _options
    from pipeline.units import G

    column = Column(*COLUMN)
    motion = load(RECORD)
    settings = ModelSettings(rtol=rtol, atol=rtol * 1e-3)
    ts = math.sqrt(column.R / G)
    record = np.ascontiguousarray(np.stack([motion.acc_x, motion.acc_y, np.zeros(motion.npts)], 1) * scale / G)
    dt = motion.dt / ts
    params = (column.kernel_constants(), record, dt, _options(column, settings))
    t_end = (motion.duration + settings.tail) / ts
    t_out = np.arange(0.0, t_end, settings.output_step / ts)
    args = dict(
        params=params, y0=np.zeros(fk.N_STATE), t_end=t_end, t_out=t_out,
        y_out=np.zeros((len(t_out), fk.N_STATE)), phase_out=np.zeros(len(t_out), np.int8),
        t_breaks=np.arange(len(record)) * dt, rtol=settings.rtol, atol=settings.atol,
        summary=np.zeros(lay.N_SUMMARY), impacts=np.zeros((1000, 4)),
    )
    return column, motion, settings, args


def _call(runner, a):
    return runner(a["params"], -1.0, a["y0"], a["t_end"], a["t_out"], a["y_out"], a["phase_out"],
                  a["t_breaks"], a["rtol"], a["atol"], a["summary"], a["impacts"])


def scipy_child(rtol):
    """Runs in the subprocess (NUMBA_DISABLE_JIT=1): prints one JSON line per run.

    Each scale at ``rtol``, then scale 1 at ``rtol / 100`` (scipy's converged
    answer: it has no way to keep steps off the record's kinks, so at equal
    tolerance it is less accurate).
    """
    from pipeline.dynamics.reference import run_frustum_scipy
    from pipeline.dynamics.rigid import layout as lay

    for scale, tol in [(s, rtol) for s in SCALES] + [(SCALES[0], rtol / 100)]:
        _column, _motion, _settings, a = _problem(scale, tol)
        t0 = time.perf_counter()
        _call(run_frustum_scipy, a)
        elapsed = time.perf_counter() - t0
        s = a["summary"]
        print(json.dumps({"scale": scale, "rtol": tol, "time": elapsed, "peak_theta": s[lay.S_PEAK_THETA],
                          "overturned": not math.isnan(s[lay.S_OVERTURN_TIME]), "nfev": s[lay.S_NFEV],
                          "impacts": s[lay.S_N_IMPACTS]}), flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--rtol", type=float, default=1e-9)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--scipy-child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.scipy_child:
        scipy_child(args.rtol)
        return
    from pipeline.dynamics.rigid import layout as lay
    from pipeline.dynamics.rigid.run3d import run_frustum
    from pipeline.settings import Excitation
    from pipeline.simulate import simulate

    print(f"machine: {platform.platform()}, {platform.processor() or platform.machine()}, "
          f"{os.cpu_count()} cores, Python {platform.python_version()}")
    print(f"problem: column R,r,h = {COLUMN} m, {RECORD} both components, angle 0, 3D model, "
          f"rtol = {args.rtol:g}, atol = {args.rtol * 1e-3:g}, free tail 5 s")
    compiled = {}
    for scale in SCALES:
        column, motion, settings, a = _problem(scale, args.rtol)
        _call(run_frustum, a)  # compile / load cache
        times = []
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            _call(run_frustum, a)
            times.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        for _ in range(args.repeat):
            simulate(column, motion, Excitation(scale=scale), settings, histories=False)
        whole = (time.perf_counter() - t0) / args.repeat
        s = a["summary"]
        compiled[scale] = dict(time=min(times), whole=whole, peak_theta=s[lay.S_PEAK_THETA],
                               overturned=not math.isnan(s[lay.S_OVERTURN_TIME]), nfev=s[lay.S_NFEV],
                               impacts=s[lay.S_N_IMPACTS])
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    child = subprocess.run([sys.executable, __file__, "--scipy-child", "--rtol", str(args.rtol)],
                           env=env, capture_output=True, text=True, check=True)
    rows = [json.loads(line) for line in child.stdout.splitlines()]
    reference = {row["scale"]: row for row in rows if row["rtol"] == args.rtol}
    converged = rows[-1]
    header = (f"{'scale':>5} | {'compiled [s]':>12} {'simulate() [s]':>14} {'nfev':>8} | "
              f"{'scipy [s]':>9} {'nfev':>8} | {'speed-up':>8} | {'peak theta [deg]':>16} {'rel. diff':>9} | outcome")
    print(header)
    print("-" * len(header))
    for scale in SCALES:
        c, r = compiled[scale], reference[scale]
        rel = abs(c["peak_theta"] - r["peak_theta"]) / r["peak_theta"]
        outcome = "overturned" if c["overturned"] else "stands"
        if c["overturned"] != r["overturned"]:
            outcome += " (scipy differs!)"
        print(f"{scale:5.1f} | {c['time']:12.4f} {c['whole']:14.4f} {c['nfev']:8.0f} | {r['time']:9.2f} "
              f"{r['nfev']:8.0f} | {r['time'] / c['time']:7.0f}x | {math.degrees(c['peak_theta']):16.6f} "
              f"{rel:9.1e} | {outcome}, {c['impacts']:.0f} impacts")
    c = compiled[SCALES[0]]
    rel = abs(c["peak_theta"] - converged["peak_theta"]) / converged["peak_theta"]
    print(f"scipy at rtol {converged['rtol']:g}, scale {SCALES[0]:g}: {converged['time']:.2f} s, "
          f"{converged['nfev']:.0f} rhs calls, peak theta {math.degrees(converged['peak_theta']):.6f} deg; "
          f"compiled at rtol {args.rtol:g} differs by {rel:.1e} relative "
          f"(speed-up at equal accuracy: {converged['time'] / c['time']:.0f}x)")


if __name__ == "__main__":
    main()
