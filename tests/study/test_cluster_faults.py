"""Runs that never hang or spill (issue 38, item 3; item 2's late interrupt): a cluster whose workers all die,
a local cluster whose shutdown races its heartbeats, the clock while the cluster starts, a Ctrl-C or SIGTERM
after the results file is written.

Each run is `frustum study run` in a child process, as a user runs it; its tasks are slowed (a function of
the child's ``__main__``, which reaches the workers by value) so that the faults land mid-study whatever the
machine.
"""

import os
import pty
import re
import signal
import subprocess
import sys
import textwrap
import threading
import time

import pytest

from dask_processes import running_cluster
from pipeline.dataset import open_results
from pipeline.study import load_study, run_study
from study_files import SMALL_STUDY

MANY_TASKS = SMALL_STUDY.replace("block_columns = 2", "block_columns = 1")  # 4 columns x 2 records = 8 tasks

# argv: study file, seconds each task sleeps, then the options of `frustum study run`
CHILD = textwrap.dedent("""\
    import faulthandler, signal, sys, time
    faulthandler.register(signal.SIGUSR1, all_threads=True)  # where it hangs, if it does (_end)
    signal.signal(signal.SIGINT, signal.default_int_handler)  # as from a terminal (a background job ignores it)
    from pipeline.study import orchestrate
    real = orchestrate.run_task
    delay = float(sys.argv[2])  # read here: a worker has argv of its own
    def slow(task, motion):
        time.sleep(delay)
        return real(task, motion)
    orchestrate.run_task = slow
    {patch}
    if __name__ == "__main__":  # the local cluster's workers start by importing this script
        from pipeline.cli import main
        sys.exit(main(["study", "run", sys.argv[1], *sys.argv[3:]]))
""")

# The scheduler answers each heartbeat after 1 s, so that one is always under way when a worker closes: the
# race that printed "Failed to communicate with scheduler during heartbeat" and its traceback about one close
# in 15 (pipeline/study/cluster.py, _SHUTDOWN_LOGGERS), here at every close.
SLOW_HEARTBEATS = textwrap.dedent("""\
    import asyncio
    from distributed.scheduler import Scheduler
    start = Scheduler.__init__
    def slow_heartbeats(self, *args, **kwargs):
        start(self, *args, **kwargs)
        answer = self.handlers["heartbeat_worker"]  # the handler of the workers' calls (not add_worker's own)
        async def late(**msg):
            await asyncio.sleep(1.0)
            return answer(**msg)
        self.handlers["heartbeat_worker"] = late
    Scheduler.__init__ = slow_heartbeats
""")

# A SIGTERM to the command itself when its local cluster starts to close, i.e. after the results file is
# written: the ~10 s window of issue 38, item 2.
TERM_WHILE_CLOSING = textwrap.dedent("""\
    import os
    from pipeline.study import cluster
    close = cluster._close_local
    def close_terminated(client, local):
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(0.5)  # it lands while the close is under way
        return close(client, local)
    cluster._close_local = close_terminated
""")

# What nothing on the terminal may look like: a traceback, a log record of distributed, its heartbeat error.
NOISE = re.compile(r"Traceback|distributed\.\w+ - (ERROR|WARNING|CRITICAL)|heartbeat|Exception", re.I)


def _child(path, argv, sleep=0.3, patch="", terminal=False):
    """Start CHILD on the study ``path``; stderr on a pseudo-terminal if ``terminal`` (returns its reader too)."""
    command = [sys.executable, "-c", CHILD.format(patch=patch), str(path), str(sleep), *argv]
    if not terminal:
        return subprocess.Popen(command, start_new_session=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                text=True), None
    master, slave = pty.openpty()
    proc = subprocess.Popen(command, start_new_session=True, stdout=subprocess.PIPE, stderr=slave, text=True)
    os.close(slave)
    chunks = []

    def read():
        while True:
            try:
                data = os.read(master, 4096)
            except OSError:  # the child closed its end
                break
            if not data:
                break
            chunks.append(data.decode(errors="replace"))
        os.close(master)

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    return proc, (reader, chunks)


def _wait_for_tasks(proc, checkpoint, n, timeout=180.0, terminal=()):
    deadline = time.monotonic() + timeout
    while len(_tasks(checkpoint)) < n:
        assert proc.poll() is None, (proc.communicate(), "".join(terminal))
        assert time.monotonic() < deadline, "the study did not checkpoint in time"
        time.sleep(0.02)


def _tasks(checkpoint):
    return sorted(p for p in os.listdir(checkpoint) if p.startswith("task-")) if os.path.isdir(checkpoint) else []


def _end(proc, timeout, terminal=()):
    """(stdout, stderr) of the child within ``timeout`` [s]; killed (its group) if it hangs."""
    try:
        return proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.kill(proc.pid, signal.SIGUSR1)  # its threads' stacks, on its stderr
        time.sleep(2.0)
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
        pytest.fail(f"the command hung: {timeout:g} s after the fault it was still running\n{err or ''.join(terminal)}")


def test_a_cluster_whose_workers_all_die_says_so_and_stops_with_the_checkpoint_kept(tmp_path, write_study,
                                                                                    small_reference, same_results):
    """Both workers of an external cluster killed mid-study: the run said nothing and waited for ever, its
    clock stopped. Now its clock runs, it says that it waits, and after --worker-wait it stops: exit 75, the
    finished tasks in the checkpoint, from which a later run completes the study."""
    path = write_study(MANY_TASKS)
    checkpoint = str(path.parent / "small.nc") + ".checkpoint"
    (tmp_path / "cluster").mkdir()
    with running_cluster(tmp_path / "cluster", 2) as (address, workers):
        proc, (reader, chunks) = _child(path, ["--scheduler", address, "--worker-wait", "6"], sleep=0.5,
                                        terminal=True)
        try:
            _wait_for_tasks(proc, checkpoint, 1, terminal=chunks)
        finally:
            for worker in workers:  # the worker processes we started, by their group id
                os.killpg(worker.pid, signal.SIGKILL)
        killed = time.monotonic()
        _end(proc, timeout=60, terminal=chunks)
        stopped = time.monotonic() - killed
        reader.join(timeout=10)
    err = "".join(chunks)
    assert proc.returncode == 75, err
    lines = [line.strip() for line in re.split(r"[\r\n]+", err) if line.strip()]
    kept = _tasks(checkpoint)
    assert 1 <= len(kept) < 8
    # the notice, within min(60 s, wait / 2) of the last worker (the count is taken every 2 s)
    notice = [line for line in lines if line.startswith("frustum: no workers for ") and "; waiting" in line]
    assert len(notice) == 1 and re.match(r"frustum: no workers for [34] s;", notice[0]) and notice[0].endswith(
        f"; waiting for workers (start some with `dask worker {address}`) up to --worker-wait 6 s, Ctrl-C keeps "
        "the checkpoint"), lines
    assert re.fullmatch(
        rf"frustum: no workers for [67] s \(--worker-wait 6\): stopped; {len(kept)} of 8 task\(s\) finished, kept "
        rf"in {re.escape(checkpoint)}: run the same command again later to resume", lines[-1]), lines
    # 6 s of waiting, seen within a count (2 s) and a look (0.1 s) of the kill; a hang fails above
    assert 6.0 <= stopped < 6.0 + 2.0 + 10.0, stopped
    # the clock ran while no task finished: redraws of the bar at the same count, the elapsed time growing
    waiting = [float(m.group(1)) for m in re.finditer(rf"{len(kept)}/8 tasks .*? elapsed +([0-9.]+) s[^\r\n]*"
                                                       r"\(waiting for workers\)", err)]
    assert len(waiting) >= 3 and waiting[-1] - waiting[0] >= 3.0, waiting
    assert not NOISE.search(err), err
    assert not (path.parent / "small.nc").exists()

    report = run_study(load_study(path), serial=True, progress=False)  # the next run takes what was kept
    assert sorted(report.skipped) == [int(p[5:11]) for p in kept] and len(report.computed) == 8 - len(kept)
    same_results(report.dataset, small_reference[1])


def test_a_lost_scheduler_stops_the_run_and_keeps_the_checkpoint(tmp_path, write_study):
    """The scheduler killed mid-study: its client cancels every task. They were counted as failed cells, a
    results file of NaN was written and the checkpoint removed; now the run stops (75) with the tasks kept."""
    path = write_study(MANY_TASKS)
    checkpoint = str(path.parent / "small.nc") + ".checkpoint"
    (tmp_path / "cluster").mkdir()
    with running_cluster(tmp_path / "cluster", 2, scheduler=True) as (address, workers, scheduler):
        proc, _ = _child(path, ["--scheduler", address, "--quiet"], sleep=0.5)
        try:
            _wait_for_tasks(proc, checkpoint, 1)
        finally:
            os.killpg(scheduler.pid, signal.SIGKILL)
        out, err = _end(proc, timeout=60)
    assert proc.returncode == 75, err
    kept = _tasks(checkpoint)
    assert 1 <= len(kept) < 8
    assert err.splitlines()[-1] == (
        f"frustum: lost the connection to the scheduler {address}: stopped; {len(kept)} of 8 task(s) finished, "
        f"kept in {checkpoint}: run the same command again later to resume"), err
    assert not (path.parent / "small.nc").exists()
    assert "Traceback" not in err


def test_the_senders_closed_connection_is_not_shown_once_a_run_has_started(caplog):
    """The lost-scheduler test above failed now and then (1 run in 5 of the suite on 2026-12-06): the
    client's batched sender logs "Batched Comm Closed <TCP ...>" with its traceback at INFO whenever it
    notices the lost connection, which may be before the run's own words. From a run's start that
    record is dropped, for the rest of the process; the sender's other records pass."""
    import logging

    from pipeline.study.cluster import _rescheduling_quiet

    sender = logging.getLogger("distributed.batched")
    with caplog.at_level(logging.INFO, logger="distributed.batched"):
        with _rescheduling_quiet():
            pass
        sender.info("Batched Comm Closed %r", "<TCP (closed) remote=tcp://127.0.0.1:43001>")
        sender.error("Error in batched write")
    assert [r.getMessage() for r in caplog.records if r.name == "distributed.batched"] == ["Error in batched write"]


def test_the_local_cluster_closes_without_a_word_while_its_heartbeats_are_under_way(write_study):
    """A heartbeat under way when a worker closes was logged with its traceback; nothing of the shutdown
    reaches the terminal now. A real error of the run still does (test_a_task_that_keeps_failing_...)."""
    path = write_study()
    proc, _ = _child(path, ["--workers", "2", "--quiet"], sleep=0.0, patch=SLOW_HEARTBEATS)
    out, err = _end(proc, timeout=240)
    assert proc.returncode == 0, err
    assert err.splitlines()[-1].startswith("total "), err
    assert not NOISE.search(err), err
    assert (path.parent / "small.nc").exists() and not os.path.exists(str(path.parent / "small.nc") + ".checkpoint")


def test_the_clock_runs_and_says_what_it_waits_for_while_the_cluster_starts(write_study, monkeypatch):
    """The bar sat at "0/4 elapsed 0.0 s" while the local cluster started (15-22 s for the quickstart)."""
    import io

    from pipeline.study import cluster as study_cluster

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    real = study_cluster._connect

    def slow_start(*args):
        time.sleep(3.0)  # a slow machine's start, whatever this one's
        return real(*args)

    monkeypatch.setattr(study_cluster, "_connect", slow_start)
    terminal = Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    run_study(load_study(write_study()), workers=1)
    draws = terminal.getvalue().split("\r")
    starting = [float(m.group(1)) for d in draws
                for m in [re.search(r"0/4 tasks .*elapsed +([0-9.]+) s \(starting 1 worker\)", d)] if m]
    assert len(starting) >= 2 and starting[-1] >= 2.0, draws
    final = re.search(r"4/4 tasks 100.0% elapsed +([0-9.]+) s", draws[-1])
    assert final and float(final.group(1)) >= 3.0, draws[-1]  # the start is in the clock


@pytest.mark.parametrize("plot", [False, True])
def test_a_sigterm_after_the_results_are_written_says_so(write_study, small_reference, same_results, plot):
    """A SIGTERM while the local cluster closes, after the results file is written: "terminated: run again to
    resume" was false (the file was complete, the checkpoint gone: running again recomputed everything)."""
    path = write_study()
    out = path.parent / "small.nc"
    argv = ["--workers", "1", "--quiet"] + (["--plot", str(path.parent / "small.png")] if plot else [])
    proc, _ = _child(path, argv, sleep=0.0, patch=TERM_WHILE_CLOSING)
    stdout, err = _end(proc, timeout=240)
    assert proc.returncode == 143, err
    assert err.splitlines()[-1] == (f"frustum: terminated after the results were written: {out} is complete, nothing "
                                    "to run again" + (f"; the plot {path.parent / 'small.png'} was not drawn"
                                                      if plot else "")), err
    assert not NOISE.search(err), err
    same_results(open_results(out), small_reference[1])
    assert not os.path.exists(str(out) + ".checkpoint")  # removed once the file was on disk, as a run that ends
    assert not (path.parent / "small.png").exists()


def test_the_checkpoint_goes_only_once_the_results_file_is_on_disk(write_study, monkeypatch):
    """The results file and its folder are flushed to disk before the checkpoint is removed."""
    from pipeline.study import checkpoint

    events = []
    real_fsync, real_rmtree = os.fsync, checkpoint.shutil.rmtree
    monkeypatch.setattr(checkpoint.os, "fsync", lambda fd: events.append(("fsync", os.readlink(
        f"/proc/self/fd/{fd}"))) or real_fsync(fd))
    monkeypatch.setattr(checkpoint.shutil, "rmtree", lambda folder, **k: events.append(("rmtree", folder)) or
                        real_rmtree(folder, **k))
    path = write_study()
    out = str(path.parent / "small.nc")
    run_study(load_study(path), serial=True, progress=False)
    assert events[-3:] == [("fsync", out), ("fsync", str(path.parent)), ("rmtree", out + ".checkpoint")]
