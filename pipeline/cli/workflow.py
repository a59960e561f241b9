"""``frustum workflow run FILE``: run a workflow's studies in order, idempotently, with a log.

A workflow file (TOML) names studies and where their outputs and plots go::

    title = "Nightly studies"
    log = "../out/nightly.log"          # relative to the workflow file

    [execution]                         # optional: how the studies run
    workers = 2                         # local cluster size (default: cores)
    # scheduler = "tcp://10.0.0.5:8786" # or an existing cluster
    # worker_wait = 1800                # seconds without workers before stopping (default 600)

    [[steps]]
    study = "../studies/quickstart.toml"
    output = "../out/quickstart.nc"     # default: the study's output field
    plot = "../out/quickstart.png"      # optional

A step is up to date when its output exists and records the same study file
digest, record digests and software version as now; then nothing is
recomputed (a missing or older plot is redrawn from the file). Steps run in
order; the first failing step stops the workflow and the command exits 1 (75 if the
cluster had no worker for ``worker_wait`` seconds: the step's checkpoint is kept).
Two runs of the same workflow never overlap (a lock next to the log): the
second exits 75 (EX_TEMPFAIL, "try again later"). With ``--quiet`` a
successful run, and a run that exits 75, print nothing (cron mails only
failures); the log file gets every line either way. Before any step runs,
outputs and plots that two steps share, an output that would replace an
input or a file of the user's, and a log that cannot be written are refused
(exit 2).

``frustum workflow install-units`` writes the systemd service and timer of
``workflows/systemd/*.in`` filled in with this checkout's path and this
installation's ``frustum``.
"""

import os
import sys
import time
import tomllib
import traceback
from datetime import datetime, timezone
from pathlib import Path

from pipeline import __version__
from pipeline.errors import InputError
from pipeline.locking import try_lock
from pipeline.paths import check_plot_file

#: Exit status when another run holds the workflow's lock (sysexits.h EX_TEMPFAIL).
EXIT_LOCKED = 75

_TOP = {"title", "log", "execution", "steps"}
_EXECUTION = {"workers", "scheduler", "worker_wait"}
_STEP = {"study", "output", "plot"}


def register(subparsers):
    """Add the ``workflow`` sub-command group."""
    p = subparsers.add_parser(
        "workflow", help="run a workflow: ordered studies, outputs and plots (for cron/systemd)",
        description="Workflows: a TOML file naming studies, their outputs and plots. `frustum workflow run` "
        "is idempotent (up-to-date steps are skipped), logs to a file and exits non-zero on failure.",
    )
    sub = p.add_subparsers(dest="workflow_command", metavar="ACTION")
    run = sub.add_parser("run", help="run the workflow's steps that are not up to date")
    run.add_argument("file", metavar="FILE.toml", help="workflow file")
    run.add_argument("--workers", type=int, default=None, metavar="N", help="override execution.workers")
    run.add_argument("--scheduler", metavar="ADDRESS", help="override execution.scheduler")
    run.add_argument("--worker-wait", type=float, default=None, metavar="SECONDS",
                     help="override execution.worker_wait: how long a step waits when the cluster has no worker "
                     "before the workflow stops, its checkpoint kept (exit 75; default 600 s)")
    run.add_argument("--force", action="store_true", help="rerun every step even if up to date")
    run.add_argument("--quiet", action="store_true",
                     help="print nothing unless a step fails (the log file gets every line); for cron")
    run.set_defaults(handler=run_workflow_command)
    units = sub.add_parser(
        "install-units", help="write the systemd service and timer for this checkout",
        description="Fill workflows/systemd/*.in with this checkout's path and this installation's frustum "
        "and write them (default: the user's systemd folder). Then: systemctl --user daemon-reload && "
        "systemctl --user enable --now frustum-workflow.timer")
    units.add_argument("--dir", default=None, metavar="DIR",
                       help="folder to write the units to (default ~/.config/systemd/user)")
    units.add_argument("--checkout", default=None, metavar="DIR",
                       help="the project's checkout (default: the one this frustum is installed from, "
                       "else the current folder)")
    units.add_argument("--workflow", default="workflows/nightly.toml", metavar="FILE.toml",
                       help="workflow the service runs, relative to the checkout (default workflows/nightly.toml)")
    units.set_defaults(handler=install_units_command)
    p.set_defaults(handler=lambda args: (p.print_help(), 2)[1])


def load_workflow(path):
    """Read and validate a workflow file.

    Returns
    -------
    dict
        ``title``, ``log`` (absolute), ``workers``, ``scheduler`` and
        ``steps``: list of dicts with absolute ``study``, ``output`` (or None)
        and ``plot`` (or None).
    """
    path = Path(path).resolve()
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise InputError(f"{path}: cannot read the workflow file ({exc.strerror}); check the path") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{path}: not a valid TOML file: {exc}") from None

    def fail(field, message):
        raise InputError(f"{path}: field {field}: {message}")

    for key in data:
        if key not in _TOP:
            fail(key, f"unknown field; allowed: {', '.join(sorted(_TOP))}")
    execution = data.get("execution", {})
    if not isinstance(execution, dict):
        fail("execution", "must be a table")
    for key in execution:
        if key not in _EXECUTION:
            fail(f"execution.{key}", f"unknown field; allowed: {', '.join(sorted(_EXECUTION))}")
    workers = execution.get("workers")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        fail("execution.workers", f"must be a positive integer, got {workers!r}")
    scheduler = execution.get("scheduler")
    if scheduler is not None:
        if not isinstance(scheduler, str):
            fail("execution.scheduler", "must be an address string such as tcp://host:8786")
        from pipeline.study import scheduler_address

        try:
            scheduler_address(scheduler)
        except InputError as exc:
            fail("execution.scheduler", str(exc))
    wait = execution.get("worker_wait")
    if wait is not None:
        from pipeline.cli.study import worker_wait

        if isinstance(wait, bool) or not isinstance(wait, (int, float)):
            fail("execution.worker_wait", f"must be a number of seconds, got {wait!r}")
        try:
            worker_wait(float(wait), "")
        except InputError as exc:
            fail("execution.worker_wait", str(exc).strip())
    steps = data.get("steps")
    if not isinstance(steps, list) or not steps:
        fail("steps", "give one or more [[steps]] with study = FILE")

    def resolve(value, field):
        if value is None:
            return None
        if not isinstance(value, str) or not value:
            fail(field, f"must be a path, got {value!r}")
        return str((path.parent / value).resolve())

    out = []
    for i, step in enumerate(steps):
        if not isinstance(step, dict):
            fail(f"steps[{i}]", "must be a table")
        for key in step:
            if key not in _STEP:
                fail(f"steps[{i}].{key}", f"unknown field; allowed: {', '.join(sorted(_STEP))}")
        if "study" not in step:
            fail(f"steps[{i}].study", "missing: name the study file")
        study = resolve(step["study"], f"steps[{i}].study")
        if not os.path.isfile(study):
            fail(f"steps[{i}].study", f"{study} does not exist")
        plot = resolve(step.get("plot"), f"steps[{i}].plot")
        if plot is not None:
            try:  # a plot matplotlib cannot write is refused before any step computes (a user's file: below)
                check_plot_file(plot, "", kind=None)
            except InputError as exc:
                fail(f"steps[{i}].plot", str(exc).strip())
        out.append({"study": study, "output": resolve(step.get("output"), f"steps[{i}].output"), "plot": plot})
    log = resolve(data.get("log", f"{path.stem}.log"), "log")
    _check_outputs(path, out, log)
    return {"title": data.get("title", path.stem), "log": log, "workers": workers, "scheduler": scheduler,
            "worker_wait": wait, "steps": out, "path": str(path)}


def _check_outputs(path, steps, log):
    """Refuse, before any step runs, an output or plot that two steps share, that replaces an input or a file of
    the user's, and a log that cannot be written.

    A study that cannot be read is left to its step, which reports it (exit 1);
    its default output is then unknown here.
    """
    from pipeline.paths import check_output_file
    from pipeline.study import load_study, study_inputs

    inputs = [("workflow file", str(path))] + [(f"study file of steps[{i}]", s["study"]) for i, s in enumerate(steps)]
    written = {}  # real path -> the field that writes it

    def claim(target, field):
        key = os.path.realpath(target)
        if key in written:
            raise InputError(f"{path}: field {field}: {target} is also written by {written[key]}; give every "
                             "step its own output and plot")
        written[key] = field

    for i, step in enumerate(steps):
        try:
            study = load_study(step["study"], load_records=False)
        except InputError:
            study = None
        field = f"steps[{i}].output"
        if study is not None:
            label = f"{path}: field {field}" if step["output"] else f"{step['study']}: field output (steps[{i}])"
            output = check_output_file(step["output"] or study.output, label, kind="study",
                                       inputs=inputs + study_inputs(study))
            claim(output, field if step["output"] else f"the study of steps[{i}] (its output field)")
        elif step["output"]:
            check_output_file(step["output"], f"{path}: field {field}", kind="study", inputs=inputs)
            claim(step["output"], field)
        if step["plot"]:
            check_output_file(step["plot"], f"{path}: field steps[{i}].plot", inputs=inputs)
            claim(step["plot"], f"steps[{i}].plot")
    check_output_file(log, f"{path}: field log", kind=None,  # appended to, never replaced
                      inputs=inputs + [(f"output of {f}", p) for p, f in written.items()])


def up_to_date(study, motions, output):
    """Whether ``output`` holds the results of this study, these records and this software version."""
    if not os.path.isfile(output):
        return False
    from pipeline.dataset import open_results

    try:
        ds = open_results(output)
    except Exception:  # noqa: BLE001 - an unreadable file is simply not up to date
        return False
    if "status" in ds and int(ds.status.sum()) >= ds.status.size:  # every cell failed: try again
        return False
    return (ds.attrs.get("study_sha256") == study.digest
            and ds.attrs.get("source", "").startswith(f"frustum-pipeline {__version__} ")
            and list(ds.record_sha256.values.astype(str)) == [m.sha256() for m in motions])


class _Log:
    """Time-stamped lines to the log file and, unless quiet, to stderr.

    Quiet, the lines are kept and printed only if the run fails (:meth:`flush_to_stderr`).
    """

    def __init__(self, path, quiet=False):
        try:
            os.makedirs(os.path.dirname(path), exist_ok=True)
            self.file = open(path, "a", encoding="utf-8")  # noqa: SIM115 - closed in run_workflow
        except OSError as exc:  # checked by load_workflow; this is a change since (or a race)
            raise InputError(f"field log {path!r}: cannot be written ({exc.strerror or exc}); choose a folder you "
                             "may write in") from None
        self.quiet = quiet
        self.held = []

    def __call__(self, line):
        stamp = datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
        self.file.write(f"{stamp} {line}\n")
        self.file.flush()
        if self.quiet:
            self.held.append(line)
        else:
            print(line, file=sys.stderr)

    def flush_to_stderr(self):
        """Print the lines held back by ``quiet`` (a failed run tells why)."""
        for line in self.held:
            print(line, file=sys.stderr)
        self.held = []


def run_workflow(path, workers=None, scheduler=None, force=False, quiet=False, worker_wait=None):
    """Run a workflow; returns the exit status (0 done, 1 a step failed, 75 another run holds the lock or the
    cluster had no worker for ``worker_wait`` seconds).

    Parameters
    ----------
    path : str
        Workflow file.
    workers, scheduler, worker_wait
        Override the file's ``execution`` table.
    force : bool
        Rerun steps that are up to date.
    quiet : bool
        Print nothing on success; on failure, the run's lines.
    """
    from pipeline.study import Cluster

    wf = load_workflow(path)
    workers = workers or wf["workers"]
    scheduler = scheduler or wf["scheduler"]
    worker_wait = wf["worker_wait"] if worker_wait is None else worker_wait
    log = _Log(wf["log"], quiet=quiet)
    lock = try_lock(wf["log"] + ".lock")
    status = 1
    try:
        if lock is None:
            log(f"workflow {wf['path']}: another run holds {wf['log']}.lock; not starting (exit {EXIT_LOCKED}: "
                "try again later)")
            status = EXIT_LOCKED
            return status
        log(f"workflow {wf['path']} ({wf['title']}): start, frustum {__version__}, {len(wf['steps'])} step(s)")
        # one cluster for all steps, started by the first step that computes
        with Cluster(scheduler, workers, worker_wait) as cluster:
            status = _run_steps(wf, log, cluster, force)
        return status
    finally:
        if status not in (0, EXIT_LOCKED):  # an overlap is expected under cron: the log has it, no mail
            log.flush_to_stderr()
        if lock is not None:
            lock.release()
        log.file.close()


def _run_steps(wf, log, cluster, force):
    """Run the workflow's steps in order on ``cluster``; returns the exit status."""
    from pipeline.study import load_motions, load_study, run_study
    from pipeline.study.cluster import EXIT_NO_WORKERS, WorkersGone

    for i, step in enumerate(wf["steps"]):
        t0 = time.monotonic()
        try:
            study = load_study(step["study"], load_records=False)
            motions = load_motions(study)
            output = step["output"] or study.output
            if not force and up_to_date(study, motions, output):
                log(f"step {i + 1}: {step['study']}: up to date ({output}), nothing recomputed")
                computed = False
            else:
                report = run_study(study, out=output, motions=motions, cluster=cluster, progress=False)
                log(f"step {i + 1}: {step['study']}: {len(report.computed)} task(s) computed, "
                    f"{len(report.skipped)} from checkpoint, {report.simulations} simulations, "
                    f"{report.failed} failed, {time.monotonic() - t0:.1f} s -> {output}")
                computed = True
                if report.failed and report.failed >= report.dataset.status.size:  # nothing ran: a failure
                    log(f"step {i + 1}: {step['study']}: FAILED: all {report.failed} cells failed; the first: "
                        f"{report.first_error or 'unknown'}")
                    log(f"workflow {wf['path']}: failed at step {i + 1}")
                    return 1
            plot = step["plot"]
            if plot and (computed or not os.path.isfile(plot) or os.path.getmtime(plot) < os.path.getmtime(output)):
                from pipeline.dataset import open_results
                from pipeline.plotting import plot_study

                plot_study(open_results(output), plot)
                log(f"step {i + 1}: plot -> {plot}")
        except WorkersGone as exc:  # its checkpoint keeps the finished tasks: try again later
            log(f"step {i + 1}: {step['study']}: stopped: {exc}")
            log(f"workflow {wf['path']}: stopped at step {i + 1} (exit {EXIT_NO_WORKERS}: try again later)")
            log.flush_to_stderr()  # unlike an overlap, worth a word even when quiet
            return EXIT_NO_WORKERS
        except Exception as exc:  # noqa: BLE001 - log every failure, exit non-zero
            log(f"step {i + 1}: {step['study']}: FAILED: {type(exc).__name__}: {exc}")
            if not isinstance(exc, InputError):
                log(traceback.format_exc().rstrip())
            log(f"workflow {wf['path']}: failed at step {i + 1}")
            return 1
    log(f"workflow {wf['path']}: done")
    return 0


def run_workflow_command(args):
    """Handler of ``frustum workflow run``."""
    from pipeline.cli.study import worker_wait

    if args.workers is not None and args.workers < 1:
        raise InputError(f"--workers {args.workers}: give a positive number of worker processes")
    return run_workflow(args.file, workers=args.workers, scheduler=args.scheduler, force=args.force,
                        quiet=args.quiet, worker_wait=worker_wait(args.worker_wait))


UNIT_TEMPLATES = ("frustum-workflow.service.in", "frustum-workflow.timer.in")


def install_units(checkout, frustum, workflow="workflows/nightly.toml", folder=None):
    """Write the systemd units of ``workflows/systemd/*.in`` filled in for a checkout.

    Parameters
    ----------
    checkout : str
        Absolute path of the project's checkout (``{checkout}`` in the templates).
    frustum : str
        Absolute path of the ``frustum`` executable (``{frustum}``).
    workflow : str
        Workflow file the service runs, relative to the checkout (``{workflow}``).
    folder : str, optional
        Where to write the units (default ``~/.config/systemd/user``).

    Returns
    -------
    list of str
        The files written (atomically: temporary name, then rename).
    """
    from pipeline.atomic import atomic_open

    folder = folder or os.path.join(os.path.expanduser("~"), ".config", "systemd", "user")
    templates = Path(checkout) / "workflows" / "systemd"
    if not (Path(checkout) / workflow).is_file():
        raise InputError(f"--workflow {workflow}: no such file in {checkout}; give a workflow file of the checkout")
    os.makedirs(folder, exist_ok=True)
    written = []
    for name in UNIT_TEMPLATES:
        try:
            text = (templates / name).read_text(encoding="utf-8")
        except OSError as exc:
            raise InputError(f"{templates / name}: cannot read the unit template ({exc.strerror})") from None
        text = text.replace("{checkout}", checkout).replace("{frustum}", frustum).replace("{workflow}", workflow)
        target = os.path.join(folder, name[:-3])
        with atomic_open(target, "w", encoding="utf-8") as fh:
            fh.write(text)
        written.append(target)
    return written


def install_units_command(args):
    """Handler of ``frustum workflow install-units``."""
    checkout = args.checkout
    if checkout is None:
        source = Path(__file__).resolve().parents[2]  # an editable install: the checkout itself
        checkout = source if (source / "workflows" / "systemd").is_dir() else Path.cwd()
    checkout = str(Path(checkout).resolve())
    frustum = str(Path(sys.executable).parent / "frustum")
    for path in install_units(checkout, frustum, args.workflow, args.dir):
        print(f"wrote {path}")
    print("now: systemctl --user daemon-reload && systemctl --user enable --now frustum-workflow.timer")
    print(f"or, for cron (crontab -e): 17 2 * * *  cd {checkout} && {frustum} workflow run --quiet {args.workflow}")
    return 0
