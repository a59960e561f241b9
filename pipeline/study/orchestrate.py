"""Running a study: plan it, take what the checkpoint holds, compute the rest, write one results file.

:func:`run_study` checks the output and the memory before anything is computed, loads the
kernels once, runs the tasks left (in this process, or on a Dask cluster through
:mod:`pipeline.study.cluster`), keeps each finished task in the checkpoint
(:mod:`pipeline.study.checkpoint`), and writes the results netCDF under a temporary name and
renames it; the checkpoint folder is removed once the file is on disk.

An interrupt (Ctrl-C, SIGTERM) that arrives after the results file is written carries its
path (``exc.results_written``), so that the command says the results are complete rather than
"run again" (which would find no checkpoint and compute everything again).
"""

import os
import sys
import time
from dataclasses import dataclass, field
from functools import partial

import xarray as xr

from pipeline import __version__
from pipeline.dataset import append_history, write_results
from pipeline.errors import OutputError
from pipeline.paths import check_output_file
from pipeline.study.checkpoint import Checkpoint, checkpoint_key
from pipeline.study.cluster import Cluster, WorkersGone, run_on_cluster
from pipeline.study.grid import check_memory, longest_first, plan, record_intensity, scale_factors
from pipeline.study.kernels import prepare_kernels, warm_up
from pipeline.study.progress import Progress
from pipeline.study.results import assemble, blank_arrays
from pipeline.study.run import failed_result, run_task
from pipeline.study.studyfile import load_motions


@dataclass
class RunReport:
    """What :func:`run_study` did.

    Attributes
    ----------
    path : str
        The results file.
    dataset : xarray.Dataset
    n_tasks : int
    computed, skipped : list of int
        Task indices computed in this run, and found in the checkpoint.
    simulations : int
        Simulations run in this run (3D shared over angles counts once).
    grid_size : int
        Cells of the results grid.
    seconds : float
        Wall time of the computing phase [s] (cluster start-up included).
    failed : int
        Cells with status 1.
    first_error : str
        The first failed simulation's message ("" when none failed), for a
        summary of a run in which every cell failed.
    startup_seconds : float
        Of which starting or connecting to the cluster and loading the
        kernels on the workers [s].
    compute_seconds : float
        From the cluster being ready to the last task's result [s].
    task_seconds : float
        Sum of the tasks' own compute times [s]; ``task_seconds /
        (n_workers * compute_seconds)`` is the busy fraction.
    task_cpu_seconds : float
        CPU time the tasks got [s]; below ``task_seconds`` when other
        processes compete for the cores.
    n_workers : int
    """

    path: str
    dataset: xr.Dataset = field(repr=False)
    n_tasks: int = 0
    computed: list = field(default_factory=list)
    skipped: list = field(default_factory=list)
    simulations: int = 0
    grid_size: int = 0
    seconds: float = 0.0
    failed: int = 0
    first_error: str = ""
    startup_seconds: float = 0.0
    compute_seconds: float = 0.0
    task_seconds: float = 0.0
    task_cpu_seconds: float = 0.0
    n_workers: int = 1


def _place(arrays, result):
    ri, a, b = result["record"], result["start"], result["stop"]
    for name, values in result["arrays"].items():
        arrays[name][a:b, ri] = values


def run_study(study, *, out=None, motions=None, scheduler=None, workers=None, serial=False, progress=True,
              keep_checkpoint=False, window=None, cluster=None, worker_wait=None):
    """Run a study and write its results file.

    Parameters
    ----------
    study : pipeline.study.Study
    out : str, optional
        Results file; default ``study.output``.
    motions : list of GroundMotion, optional
        The study's records, already loaded (:func:`pipeline.study.load_motions`).
    scheduler : str, optional
        Address of an existing ``dask.distributed`` scheduler
        (``tcp://host:port``); default: a local cluster of processes.
    workers : int, optional
        Worker processes of the local cluster (default: the number of cores).
    serial : bool
        Run the tasks in this process, without Dask (same numbers).
    progress : bool
        Show a progress bar on stderr.
    keep_checkpoint : bool
        Keep the checkpoint folder after the results file is written.
    window : int, optional
        Tasks in flight at once on the cluster (default 2 per worker + 2):
        bounds the memory of scheduler and driver for any study size.
    cluster : Cluster, optional
        A cluster already in use (several studies in a row): the study runs
        on it and leaves it running; ``scheduler`` and ``workers`` are then
        ignored. Default: a cluster for this study alone, closed at the end.
    worker_wait : float, optional
        Seconds the run waits when its cluster has no worker before it stops
        (default :data:`pipeline.study.cluster.WORKER_WAIT`; a given
        ``cluster`` keeps its own).

    Returns
    -------
    RunReport

    Raises
    ------
    InputError
        Before computing: an output that cannot be written, a grid that
        cannot fit in memory.
    OutputError
        A checkpoint or the results file could not be written (disk full,
        read-only): the finished tasks stay in the checkpoint.
    WorkersGone
        The cluster had no worker for ``worker_wait`` seconds (or lost its
        scheduler): the finished tasks stay in the checkpoint.
    KeyboardInterrupt
        Ctrl-C or SIGTERM; with ``results_written`` (the path) if the results
        file was complete when it arrived.
    """
    out = check_study_output(study, out)
    check_memory(study)
    motions = motions if motions is not None else load_motions(study)
    measures = [record_intensity(m, study.sa_period) for m in motions]
    factors = scale_factors(study, measures)
    tasks = plan(study, factors)
    fresh = not os.path.lexists(out + ".checkpoint")
    ckpt = Checkpoint(out + ".checkpoint", checkpoint_key(study, motions, tasks))
    own = cluster is None  # a cluster for this study alone; it connects only if a task is left to compute
    cluster = cluster or Cluster(scheduler, workers, worker_wait)
    written = []  # the results file, once it is complete
    try:
        try:
            return _run_checkpointed(study, out, motions, measures, factors, tasks, ckpt, cluster, serial, progress,
                                     keep_checkpoint, window, written)
        except BaseException:
            if fresh and not written and not ckpt.done():  # a run that could not start leaves no empty folder
                ckpt.remove()
            raise
        finally:
            ckpt.release()
            if own:
                cluster.close()  # holds Ctrl-C and SIGTERM until closed: they arrive here, after it
    except KeyboardInterrupt as exc:
        if written:  # the results are complete: the command says so rather than "run again"
            exc.results_written = written[0]
        raise


def study_inputs(study):
    """[(what, path)] of the files a study reads: the study file and its record files."""
    inputs = [("study file", study.path)]
    for record in study.records:
        if getattr(record, "kind", None) == "file":
            paths = record.path if isinstance(record.path, (list, tuple)) else [record.path]
            inputs += [("record file", p) for p in paths]
    return inputs


def check_study_output(study, out=None, label=None):
    """The study's results path, absolute, refused before computing if it cannot be written or is not ours to replace.

    Parameters
    ----------
    study : pipeline.study.Study
    out : str, optional
        Results file given by the user (default ``study.output``).
    label : str, optional
        How the user gave it, for the messages (default ``--out``, or the study's ``output`` field).
    """
    label = label or ("--out" if out else f"{study.path}: field output")
    return check_output_file(out or study.output, label, kind="study", inputs=study_inputs(study))


def _run_checkpointed(study, out, motions, measures, factors, tasks, ckpt, cluster, serial, progress,
                      keep_checkpoint, window, written):
    arrays = blank_arrays(study.grid_shape, status=1, n_joints=study.n_joints)  # failures until a task fills them
    done, found, errors = set(), ckpt.done(), []
    for task in tasks:
        if task.index in found:
            result = ckpt.load(task.index, task.shape, task.n_joints)
            if result is not None:
                _place(arrays, result)
                done.add(task.index)
                errors += [f"record {study.records[result['record']].id}: {e}" for e in result.get("errors") or []]
    pending = [t for t in tasks if t.index not in done]
    report = RunReport(out, None, len(tasks), [], sorted(done), 0, study.n_simulations)
    report.first_error = errors[0] if errors else ""
    t0 = time.monotonic()
    if pending:  # compiled once, here, before any worker starts and before the progress bar's clock
        prepare_kernels(study.registry_models, sys.stderr if progress else None)
    bar = Progress(len(tasks), len(done), enabled=progress)

    def finish(result, save=True):
        if save:  # a failed task is not checkpointed: the next run tries it again
            try:
                ckpt.save(result)
            except OSError as exc:
                raise OutputError(f"{ckpt.folder}: cannot write the checkpoint ({exc.strerror or exc}); the "
                                  f"{len(report.computed) + len(report.skipped)} task(s) finished before are kept "
                                  "there: free space and run the same command again") from None
        _place(arrays, result)
        report.computed.append(result["index"])
        report.simulations += result["runs"]
        report.task_seconds += result["seconds"]
        report.task_cpu_seconds += result.get("cpu_seconds") or 0.0
        report.compute_seconds = time.monotonic() - t0 - report.startup_seconds
        if result["errors"] and not report.first_error:
            report.first_error = f"record {study.records[result['record']].id}: {result['errors'][0]}"
        for line in result["errors"]:
            print(f"frustum: simulation failed (status 1): record {study.records[result['record']].id}: {line}",
                  file=sys.stderr)
        bar.advance()

    try:
        if pending and serial:
            report.startup_seconds = time.monotonic() - t0
            for task in pending:
                finish(run_task(task, motions[task.record]))
        elif pending:
            def started(n_workers):
                report.startup_seconds = time.monotonic() - t0
                report.n_workers = n_workers
                bar.restart()  # the ETA counts computing; the clock goes on counting the start as well

            def failed(task, message):  # a task that raised on every try: its cells fail, nothing is checkpointed
                finish(failed_result(task, message), save=False)

            # the longest tasks first, each carrying its record; the workers load the kernels first
            run_on_cluster(longest_first(pending, motions), run_task, lambda task: (motions[task.record],), finish,
                           failed, cluster, window=window, prepare=partial(warm_up, study.registry_models),
                           started=started, tick=bar.tick, say=bar.note)
    except WorkersGone as exc:
        bar.end()
        kept = len(ckpt.done())  # a task that failed on the way is not among them
        if not kept:
            raise WorkersGone(f"{exc}; no task had finished: run the same command again later") from None
        raise WorkersGone(f"{exc}; {kept} of {len(tasks)} task(s) finished, kept in {ckpt.folder}: run the same "
                          "command again later to resume") from None
    except BaseException:
        bar.end()  # what stopped the run is said on a line of its own
        raise
    report.seconds = time.monotonic() - t0
    bar.show(final=True)
    ds = assemble(study, motions, measures, factors, arrays)
    append_history(ds, f"frustum {__version__} study run {study.path} (sha256 {study.digest}): "
                       f"{len(report.computed)} tasks computed, {len(report.skipped)} from checkpoint")
    try:
        write_results(ds, out)
    except OutputError as exc:
        raise OutputError(f"{exc}; the {len(tasks)} finished task(s) are kept in {ckpt.folder}: free space (or "
                          "give another --out) and run the same command again") from None
    written.append(out)
    report.dataset = ds
    report.failed = int(ds.status.sum())
    if not keep_checkpoint:
        ckpt.remove(results=out)
    return report
