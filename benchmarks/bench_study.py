"""Parallel efficiency of a study on the local Dask cluster: two workers against one.

Runs ``studies/bench_500.toml`` (exactly 500 simulations, 25 tasks) serially in
this process, then on a local cluster of one and of two worker processes
(fresh clusters each time; best of ``--repeat``), and prints simulations per
second and the parallel efficiency

    E = T(1 worker) / (2 T(2 workers))

for the compute phase (cluster already up, kernels loaded) and end to end
(cluster start included). Also the busy fraction: the tasks' own wall time over
workers x compute-phase wall time, i.e. 1 - (scheduling overhead + load
imbalance); and the CPU share of the tasks: their CPU time over their wall time
(below 1 when other processes compete for the cores, which caps the efficiency
whatever Dask does).

Run by hand (not a test): ``.venv/bin/python benchmarks/bench_study.py``.
The numbers depend on what else the machine runs: quote ratios from one run.
"""

import argparse
import os
import platform
import tempfile
import time
from pathlib import Path

from pipeline.study import load_motions, load_study
from pipeline.sweep import run_study, warm_up

ROOT = Path(__file__).resolve().parents[1]


def one(study, motions, out, **kwargs):
    report = run_study(study, out=out, motions=motions, progress=False, **kwargs)
    return report, report.compute_seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--study", default=str(ROOT / "studies" / "bench_500.toml"))
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args()
    study = load_study(args.study, load_records=False)
    motions = load_motions(study)
    warm_up(study.models)
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"load average {os.getloadavg()[0]:.2f} at start, python {platform.python_version()}")
    print(f"study: {study.title} ({study.n_simulations} cells)")
    rows = {}
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "bench.nc")
        for label, kwargs in [("serial", {"serial": True}), ("1 worker", {"workers": 1}),
                              ("2 workers", {"workers": 2})]:
            best = None
            for _ in range(args.repeat):
                t0 = time.monotonic()
                report, compute = one(study, motions, out, **kwargs)
                total = time.monotonic() - t0
                if best is None or compute < best[1]:
                    best = (report, compute, total)
            report, compute, total = best
            busy = report.task_seconds / (report.n_workers * compute)
            cpu_share = report.task_cpu_seconds / report.task_seconds
            rows[label] = (compute, total)
            print(f"{label:>9}: {report.simulations} simulations, {len(report.computed)} tasks; compute "
                  f"{compute:6.2f} s = {report.simulations / compute:6.1f} sim/s; end to end {total:6.2f} s "
                  f"(start-up {report.startup_seconds:5.2f} s); busy fraction {busy:.3f}; "
                  f"CPU share of the tasks {cpu_share:.2f}")
    c1, t1 = rows["1 worker"]
    c2, t2 = rows["2 workers"]
    print(f"parallel efficiency, compute phase: T1/(2 T2) = {c1:.2f}/(2 x {c2:.2f}) = {c1 / (2 * c2):.2f}")
    print(f"parallel efficiency, end to end:    T1/(2 T2) = {t1:.2f}/(2 x {t2:.2f}) = {t1 / (2 * t2):.2f}")
    print(f"dask overhead (1 worker vs serial, compute phase): {rows['1 worker'][0] / rows['serial'][0] - 1:+.1%}")
    print(f"load average at end {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
