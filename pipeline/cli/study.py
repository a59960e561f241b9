"""``frustum study run|check``: a study file -> Dask -> one CF netCDF file (and a plot)."""

import argparse
import sys
import time

from pipeline.errors import InputError

_EXAMPLES = """\
examples:
  the default study on a local cluster of processes (one per core):
    frustum study run studies/quickstart.toml --plot out/quickstart.png
  on an existing dask.distributed cluster:
    frustum study run studies/quickstart.toml --scheduler tcp://10.0.0.5:8786
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


def _load(path, out=None, plot=None):
    """The study and its records; everything that can be refused is refused before the records load."""
    from pipeline.paths import check_plot_file
    from pipeline.study import check_memory, check_study_output, load_motions, load_study, study_inputs

    study = load_study(path, load_records=False)
    out = check_study_output(study, out)
    if plot:
        check_plot_file(plot, "--plot", inputs=study_inputs(study) + [("results file", out)])
    check_memory(study)
    motions = load_motions(study)
    return study, motions


def describe(study):
    """A few lines that say what a study computes."""
    from pipeline.study import block_size

    nc, nr, na, ns, nm = study.shape
    levels = "scales" if study.scales is not None else f"target {study.intensity.measure} levels"
    text = (f"{study.title}: {nc} column(s) x {nr} record(s) x {na} angle(s) x {ns} {levels} x "
            f"{nm} model(s) = {study.n_simulations} results; {block_size(study)} column(s) per task")
    variants = [study.variant(m) for m in study.models if study.variant(m).name != study.variant(m).model
                or study.variant(m).describe()]
    if variants:
        text += "\nmodels: " + "; ".join(f"{v.name} = {v.model}" + (f" ({v.describe()})" if v.describe() else "")
                                          for v in variants)
    if study.calibration is not None:
        text += (f"\none bed for every model: the dashpots of '{study.calibration}' calibrated on each column's "
                 "outline, and the restitution they reach")
    stacks = [c for c in study.columns if c.stack is not None]
    if stacks:
        text += ("\ncolumns of drums (the compliant model runs them, the rigid models their shafts): "
                 + ", ".join(f"{c.label} ({c.stack.describe()})" for c in stacks))
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


def run_study_command(args):
    """Handler of ``frustum study run``."""
    from pipeline.study import run_study

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
    t0 = time.monotonic()
    study, motions = _load(args.file, args.out, args.plot)
    print(describe(study), file=sys.stderr)
    report = run_study(study, out=args.out, motions=motions, scheduler=args.scheduler, workers=args.workers,
                       serial=args.serial, progress=not args.quiet, keep_checkpoint=args.keep_checkpoint)
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
        print(f"wrote {args.plot}")
    if report.failed:
        print(f"frustum: warning: {report.failed} simulation(s) failed: status = 1 in the results", file=sys.stderr)
    print(f"total {time.monotonic() - t0:.1f} s", file=sys.stderr)
    return 0
