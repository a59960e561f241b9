"""Parallel efficiency of a study on the local Dask cluster: two workers against one.

Runs ``studies/bench_500.toml`` (exactly 500 simulations, 25 tasks) serially in
this process, then on a local cluster of one and of two worker processes
(fresh clusters each time; best of ``--repeat``), and prints simulations per
second, the speed-up S = T(1 worker) / T(2 workers) (the issue's target: 1.8
or more) and the parallel efficiency E = S / 2, for the compute phase
(cluster already up, kernels loaded) and end to end (cluster start included). Also the busy fraction: the tasks' own wall time over
workers x compute-phase wall time, i.e. 1 - (scheduling overhead + load
imbalance); and the CPU share of the tasks: their CPU time over their wall time
(below 1 when other processes compete for the cores, which caps the efficiency
whatever Dask does).

``--memory`` instead runs ``studies/bench_100k.toml`` (100,000 simulations,
short synthetic records) on a local cluster of two workers and prints the peak
resident memory of the driving process (which also hosts the scheduler) and of
the workers, against the same study cut to its first 3 records (12,000
simulations): bounded memory means the peaks do not grow with the study.

Run by hand (not a test): ``.venv/bin/python benchmarks/bench_study.py [--memory]``.
The numbers depend on what else the machine runs: quote ratios from one run.
"""

import argparse
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from pipeline.study import load_motions, load_study
from pipeline.sweep import run_study, warm_up

ROOT = Path(__file__).resolve().parents[1]


def one(study, motions, out, **kwargs):
    report = run_study(study, out=out, motions=motions, progress=False, **kwargs)
    return report, report.compute_seconds


MEMORY_CHILD = """\
import resource, sys, time
from pipeline.study import load_study
from pipeline.sweep import run_study
if __name__ == "__main__":
    study = load_study(sys.argv[1])
    if sys.argv[3] != "all":  # keep the first N records only
        import dataclasses
        study = dataclasses.replace(study, records=study.records[: int(sys.argv[3])])
    report = run_study(study, out=sys.argv[2], workers=2, progress=False)
    own = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    kids = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    print(f"{report.simulations} {report.compute_seconds:.2f} {report.seconds:.2f} {own:.0f} {kids:.0f}")
"""


def memory(study_path):
    """Peak memory of driver(+scheduler) and workers: 12,000 vs 100,000 simulations."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "bench.nc")
        for n_records in ("3", "all"):
            line = subprocess.run([sys.executable, "-c", MEMORY_CHILD, study_path, out, n_records],
                                  capture_output=True, text=True, check=True).stdout.split()
            sims, compute, total, own, kids = line
            print(f"{int(sims):>7} simulations: compute {float(compute):6.1f} s = "
                  f"{int(sims) / float(compute):6.0f} sim/s, total {float(total):6.1f} s; peak RSS driver+scheduler "
                  f"{own} MiB, largest worker {kids} MiB")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--study", default=None)
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--memory", action="store_true", help="memory at 12,000 and 100,000 simulations")
    args = parser.parse_args()
    if args.memory:
        print(f"machine: {platform.machine()}, {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f}")
        memory(args.study or str(ROOT / "studies" / "bench_100k.toml"))
        return
    args.study = args.study or str(ROOT / "studies" / "bench_500.toml")
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
    print(f"compute phase: speed-up T1/T2 = {c1:.2f}/{c2:.2f} = {c1 / c2:.2f}, "
          f"parallel efficiency T1/(2 T2) = {c1 / (2 * c2):.2f}")
    print(f"end to end:    speed-up T1/T2 = {t1:.2f}/{t2:.2f} = {t1 / t2:.2f}, "
          f"parallel efficiency T1/(2 T2) = {t1 / (2 * t2):.2f}")
    print(f"dask overhead (1 worker vs serial, compute phase): {rows['1 worker'][0] / rows['serial'][0] - 1:+.1%}")
    print(f"load average at end {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
