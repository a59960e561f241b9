"""Parallel efficiency of a study on the local Dask cluster: two workers against one.

Runs ``studies/bench_500.toml`` (exactly 500 simulations, 10 tasks) serially in
this process, then on a local cluster of one and of two worker processes
(fresh clusters each time; interleaved, best of ``--repeat``), and prints simulations per
second, the speed-up S = T(1 worker) / T(2 workers) (the issue's target: 1.8
or more) and the parallel efficiency E = S / 2, for the compute phase
(cluster already up, kernels loaded) and end to end (cluster start included). Also the busy fraction: the tasks' own wall time over
workers x compute-phase wall time, i.e. 1 - (scheduling overhead + load
imbalance); and the CPU share of the tasks: their CPU time over their wall time
(below 1 when other processes compete for the cores, which caps the efficiency
whatever Dask does). Then end to end on clusters already running (the case of
``--scheduler`` and of a workflow's later steps). Last, the machine's own ceiling: two copies of the serial
run started together in two processes, without Dask.

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

from pipeline.study import Cluster, load_motions, load_study, run_study
from pipeline.study.kernels import warm_up

ROOT = Path(__file__).resolve().parents[1]


def one(study, motions, out, **kwargs):
    report = run_study(study, out=out, motions=motions, progress=False, **kwargs)
    return report, report.compute_seconds


MEMORY_CHILD = """\
import resource, sys, time
from pipeline.study import load_study, run_study
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


CEILING_CHILD = """\
import sys, time
from pipeline.study import load_motions, load_study
from pipeline.study.grid import plan, record_intensity, scale_factors
from pipeline.study.kernels import warm_up
from pipeline.study.run import run_task
study = load_study(sys.argv[1], load_records=False)
motions = load_motions(study)
warm_up(study.models)
tasks = plan(study, scale_factors(study, [record_intensity(m) for m in motions]))
time.sleep(max(0.0, float(sys.argv[2]) - time.time()))  # start together
t0 = time.perf_counter()
for task in tasks:
    run_task(task, motions[task.record])
print(time.perf_counter() - t0)
"""


def ceiling(study_path, serial_seconds):
    """What the machine itself allows: two copies of the serial study at once, no Dask.

    Returns T(serial, alone) / T(one of two copies run at the same time) x 2:
    2.0 when two processes get two full cores, lower when the cores are shared
    (hyper-threads, other jobs, memory bandwidth).
    """
    go = time.time() + 8.0  # both children loaded and warm before this instant
    children = [subprocess.Popen([sys.executable, "-c", CEILING_CHILD, study_path, repr(go)],
                                 stdout=subprocess.PIPE, text=True) for _ in range(2)]
    times = [float(c.communicate()[0]) for c in children]
    return 2.0 * serial_seconds / max(times), times


def running_cluster(study, motions, repeat):
    """End to end on clusters already running (``--scheduler``, or a workflow's later steps).

    The whole ``run_study`` call is timed: plan, checkpoint, compute, assembling
    and writing the netCDF file. A first run on each cluster loads the kernels
    on its workers and is not counted.
    """
    with tempfile.TemporaryDirectory() as tmp, Cluster(workers=1) as one_worker, Cluster(workers=2) as two:
        out = os.path.join(tmp, "bench.nc")
        times = {1: [], 2: []}
        for cluster in (one_worker, two):
            run_study(study, out=out, motions=motions, cluster=cluster, progress=False)
        for _ in range(repeat):
            for n, cluster in ((1, one_worker), (2, two)):
                t0 = time.monotonic()
                run_study(study, out=out, motions=motions, cluster=cluster, progress=False)
                times[n].append(time.monotonic() - t0)
    t1, t2 = min(times[1]), min(times[2])
    print(f"running cluster, end to end (best of {repeat}): 1 worker {t1:.2f} s, 2 workers {t2:.2f} s: "
          f"speed-up {t1 / t2:.2f}, parallel efficiency {t1 / (2 * t2):.2f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--study", default=None)
    parser.add_argument("--repeat", type=int, default=3)
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
    runs = {"serial": [], "1 worker": [], "2 workers": []}
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "bench.nc")
        # interleaved (serial, 1, 2, serial, 1, 2, ...) so that a drift of the machine's
        # speed during the benchmark touches all three alike
        for _ in range(args.repeat):
            for label, kwargs in [("serial", {"serial": True}), ("1 worker", {"workers": 1}),
                                  ("2 workers", {"workers": 2})]:
                t0 = time.monotonic()
                report, compute = one(study, motions, out, **kwargs)
                runs[label].append((report, compute, time.monotonic() - t0))
    best = {}
    for label, results in runs.items():
        report, compute, total = min(results, key=lambda r: r[1])
        best[label] = (compute, total)
        busy = report.task_seconds / (report.n_workers * compute)
        cpu_share = report.task_cpu_seconds / report.task_seconds
        print(f"{label:>9}: {report.simulations} simulations, {len(report.computed)} tasks; compute "
              f"{compute:6.2f} s = {report.simulations / compute:6.1f} sim/s (best of {len(results)}: "
              f"{', '.join(f'{r[1]:.2f}' for r in results)}); end to end {total:6.2f} s "
              f"(start-up {report.startup_seconds:5.2f} s); busy fraction {busy:.3f}; "
              f"CPU share of the tasks {cpu_share:.2f}")
    c1, t1 = best["1 worker"]
    c2, t2 = best["2 workers"]
    paired = sorted(r1[1] / r2[1] for r1, r2 in zip(runs["1 worker"], runs["2 workers"]))
    print(f"compute phase: speed-up T1/T2 = {c1:.2f}/{c2:.2f} = {c1 / c2:.2f}, "
          f"parallel efficiency T1/(2 T2) = {c1 / (2 * c2):.2f}; "
          f"run by run: {', '.join(f'{x:.2f}' for x in paired)}")
    print(f"end to end:    speed-up T1/T2 = {t1:.2f}/{t2:.2f} = {t1 / t2:.2f}, "
          f"parallel efficiency T1/(2 T2) = {t1 / (2 * t2):.2f}")
    print(f"dask overhead (1 worker vs serial, compute phase): {best['1 worker'][0] / best['serial'][0] - 1:+.1%}")
    running_cluster(study, motions, args.repeat)
    limit, times = ceiling(args.study, best["serial"][0])
    print(f"machine ceiling: two serial copies at once took {times[0]:.2f} s and {times[1]:.2f} s "
          f"against {best['serial'][0]:.2f} s alone: the cores allow a speed-up of {limit:.2f}")
    print(f"load average at end {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
