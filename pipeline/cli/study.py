"""``frustum study run|check``: a study file -> Dask -> one CF netCDF file (and a plot)."""

import argparse
import signal
import sys
import time

from pipeline.errors import InputError

_EXAMPLES = """\
examples:
  the default study on a local cluster of processes (one per core):
    frustum study run studies/quickstart.toml --plot out/quickstart.png
  on an existing dask.distributed cluster, giving up after 30 minutes without workers:
    frustum study run studies/quickstart.toml --scheduler tcp://10.0.0.5:8786 --worker-wait 1800
  check a study file without computing (records are loaded once):
    frustum study check studies/quickstart.toml
A study killed midway resumes where it stopped: run the same command again.
"""


def register(subparsers):
    """Add the ``study`` sub-command group."""
    p = subparsers.add_parser(
        "study", help="run a study (columns x records x angles x scales x models) to netCDF",
        description="Studies: a TOML file names columns, records, incidence angles, scales and models; "
        "Dask runs the grid and one CF netCDF file collects the results (docs/studies.md).",
        epilog=_EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    sub = p.add_subparsers(dest="study_command", metavar="ACTION")
    run = sub.add_parser("run", help="run a study and write its results (resumable)",
                         epilog=_EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter)
    run.add_argument("file", metavar="FILE.toml", help="study file")
    run.add_argument("--out", metavar="FILE.nc", help="results file (default: the study's output field)")
    where = run.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="address of an existing dask.distributed scheduler, e.g. tcp://host:8786 "
                       "(default: start a local cluster of processes)")
    where.add_argument("--serial", action="store_true", help="run in this process without Dask (same numbers)")
    run.add_argument("--workers", type=int, default=None, metavar="N",
                     help="worker processes of the local cluster (default: number of cores; not with --scheduler "
                     "or --serial)")
    # the numbers are pipeline.study.cluster's (EXIT_NO_WORKERS, WORKER_WAIT, NOTICE_AFTER; a test holds them
    # together), written here: importing it would import every study module to build the parser
    run.add_argument("--worker-wait", type=float, default=None, metavar="SECONDS",
                     help="how long to wait when the cluster has no worker (all died, or none started yet) before "
                     "stopping with the finished tasks kept in the checkpoint, exit status 75 (default 600 s, inf: "
                     "for ever; the run says that it waits after 60 s)")
    run.add_argument("--plot", metavar="FILE.png",
                     help="also draw a summary plot of the results (.png, .pdf, .svg, ...)")
    run.add_argument("--keep-checkpoint", action="store_true",
                     help="keep the checkpoint folder OUT.checkpoint after writing the results")
    run.add_argument("--quiet", action="store_true", help="no progress bar")
    run.set_defaults(handler=run_study_command)
    check = sub.add_parser("check", help="validate a study file (and load its records) without computing")
    check.add_argument("file", metavar="FILE.toml")
    check.set_defaults(handler=check_study_command)
    p.set_defaults(handler=lambda args: (p.print_help(), 2)[1])


def _load(path, out=None, plot=None, records=True):
    """The study and its records (None if not ``records``); everything that can be refused is refused before the
    records load."""
    from pipeline.paths import check_plot_file
    from pipeline.study import check_memory, check_study_output, load_motions, load_study, study_inputs

    study = load_study(path, load_records=False)
    out = check_study_output(study, out)
    if plot:
        check_plot_file(plot, "--plot", inputs=study_inputs(study) + [("results file", out)])
    check_memory(study)
    motions = load_motions(study) if records else None
    return study, motions


def describe(study):
    """A few lines that say what a study computes."""
    from pipeline.study import block_size

    from pipeline.study.results import what_ran

    nc, nr, na, ns, nm = study.shape
    levels = "scales" if study.scales is not None else f"target {study.intensity.measure} levels"
    seeds = f" x {len(study.seeds)} seed(s) of imperfect drums" if study.seeds else ""
    text = (f"{study.title}: {what_ran(study)}\n{nc} column(s) x {nr} record(s) x {na} angle(s) x {ns} {levels} x "
            f"{nm} model(s){seeds} = {study.n_simulations} results; {block_size(study)} column(s) per task")
    variants = [study.variant(m) for m in study.models if study.variant(m).name != study.variant(m).model
                or study.variant(m).describe()]
    if variants:
        text += "\nmodels: " + "; ".join(f"{v.name} = {v.model}" + (f" ({v.describe()})" if v.describe() else "")
                                          for v in variants)
    if study.calibration is not None:
        text += (f"\none bed for every model: the dashpots of '{study.calibration}' calibrated on each column's "
                 "outline, and the restitution they reach")
    stacks = [c for c in study.columns if c.stack is not None and c.colonnade is None]
    if stacks:
        text += ("\ncolumns of drums (the compliant model runs them, the rigid models their shafts): "
                 + ", ".join(f"{c.label} ({c.stack.describe()})" for c in stacks))
    rows = [c for c in study.columns if c.colonnade is not None]
    if rows:
        text += ("\ncolonnades (the models of colonnades run them, the others their column alone): "
                 + "; ".join(f"{c.label} = {c.describe()}" for c in rows))
    return text


def check_study_command(args):
    """Handler of ``frustum study check``."""
    from pipeline.limits import available_memory, size_text
    from pipeline.study import memory_estimate

    study, _ = _load(args.file)
    print(describe(study))
    print(f"output: {study.output}")
    print(f"memory: about {size_text(memory_estimate(study))} ({size_text(available_memory())} available)")
    return 0


def worker_wait(value, label="--worker-wait"):
    """``value`` [s] checked: a number of seconds, 0 or more, ``inf`` for ever (None: the default)."""
    import math

    from pipeline.study.cluster import WORKER_WAIT

    if value is not None and (math.isnan(value) or value < 0):  # inf: wait for ever, saying so
        raise InputError(f"{label} {value:g}: give the seconds to wait for workers, 0 or more (default "
                         f"{WORKER_WAIT:g})")
    return value


def _start_and_load(study, cluster, progress):
    """The study's records, loaded while its cluster starts (in a thread) and its workers load the kernels.

    The kernels are compiled here first if numba's cache is cold, so that the workers load
    them rather than compile them each.
    """
    import threading
    from functools import partial

    from pipeline.study import load_motions
    from pipeline.study.kernels import prepare_kernels, warm_up

    if cluster is None:
        return load_motions(study)
    kernels_ready = threading.Event()
    cluster.start(prepare=partial(warm_up, study.registry_models), when=kernels_ready)
    prepare_kernels(study.registry_models, sys.stderr if progress else None)
    kernels_ready.set()
    return load_motions(study)


def run_study_command(args):
    """Handler of ``frustum study run``."""
    from pipeline.study import run_study
    from pipeline.study.cluster import EXIT_NO_WORKERS, Cluster, WorkersGone

    if args.workers is not None and args.workers < 1:
        raise InputError(f"--workers {args.workers}: give a positive number of worker processes")
    if args.workers is not None and (args.scheduler or args.serial):  # it would be ignored
        where = (f"--scheduler {args.scheduler} runs on the workers of that cluster" if args.scheduler
                 else "--serial runs in this process, without workers")
        raise InputError(f"--workers {args.workers} is the size of the local cluster, and {where}: "
                         f"drop --workers, or drop {'--scheduler' if args.scheduler else '--serial'}")
    if args.scheduler:
        from pipeline.study import scheduler_address

        scheduler_address(args.scheduler)  # a malformed address is refused before the records load
    wait = worker_wait(args.worker_wait)
    if wait is not None and args.serial:
        raise InputError("--worker-wait: a --serial run has no workers to wait for; drop one of the two")
    t0 = time.monotonic()
    study, _ = _load(args.file, args.out, args.plot, records=False)
    print(describe(study), file=sys.stderr)
    # the local cluster starts (and its workers load the kernels) while the records load
    cluster = None if args.serial else Cluster(args.scheduler, args.workers, wait)
    report, drawn = None, []
    try:
        try:
            motions = _start_and_load(study, cluster, not args.quiet)
            report = run_study(study, out=args.out, motions=motions, serial=args.serial, progress=not args.quiet,
                               keep_checkpoint=args.keep_checkpoint, cluster=cluster)
        finally:
            if cluster is not None:
                cluster.close()  # holds Ctrl-C and SIGTERM until closed: they arrive here, after it
        return _summary(args, report, t0, drawn)
    except WorkersGone as exc:  # the checkpoint keeps the finished tasks: try again later
        print(f"frustum: {exc}", file=sys.stderr)
        return EXIT_NO_WORKERS
    except KeyboardInterrupt as exc:
        written = getattr(exc, "results_written", None) or (report.path if report is not None else None)
        if written is None:  # the checkpoint keeps the finished tasks: the command line says "run again"
            raise
        from pipeline.cli import Terminated

        plot = f"; the plot {args.plot} was not drawn" if args.plot and not drawn else ""
        print(f"frustum: {'terminated' if isinstance(exc, Terminated) else 'interrupted'} after the results were "
              f"written: {written} is complete, nothing to run again{plot}", file=sys.stderr)
        return 128 + (signal.SIGTERM if isinstance(exc, Terminated) else signal.SIGINT)


def _summary(args, report, t0, drawn):
    """The lines that close a run, and its plot (``drawn`` gets its path); the exit status."""
    print(f"{len(report.computed)} task(s) computed, {len(report.skipped)} from the checkpoint; "
          f"{report.simulations} simulations in {report.seconds:.1f} s"
          + (f" ({report.simulations / report.seconds:.0f}/s)" if report.simulations and report.seconds else "")
          + f"; {report.failed} failed; wrote {report.path}")
    if report.failed and report.failed >= report.dataset.status.size:  # nothing ran: not a success, nothing to plot
        print(f"frustum: error: all {report.failed} cells of the study failed (status = 1 in {report.path}); "
              f"the first: {report.first_error or 'see the messages above'}", file=sys.stderr)
        return 1
    if args.plot:
        from pipeline.plotting import plot_study

        plot_study(report.dataset, args.plot)
        drawn.append(args.plot)
        print(f"wrote {args.plot}")
    if report.failed:
        print(f"frustum: warning: {report.failed} simulation(s) failed: status = 1 in the results", file=sys.stderr)
    print(f"total {time.monotonic() - t0:.1f} s", file=sys.stderr)
    return 0
