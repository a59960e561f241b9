"""Nothing lost: a study killed midway resumes without recomputing finished tasks."""

import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

from pipeline.dataset import open_results
from pipeline.study import load_study, run_study
from pipeline.study.checkpoint import Checkpoint
from pipeline.study.results import DTYPES

# The child runs the small study (serially, or on a local cluster of two workers) with
# every task slowed down by 0.4 s, so that the parent can kill it after a few
# checkpointed tasks, whatever the machine. On the cluster the slowed task reaches the
# workers by value (cloudpickle sends functions of __main__ whole).
CHILD = textwrap.dedent("""\
    import signal, sys, time
    # as from a terminal: a shell starting a background job has SIGINT ignored, and Python keeps that
    signal.signal(signal.SIGINT, signal.default_int_handler)
    from pipeline.study import load_study, orchestrate
    real = orchestrate.run_task
    def slow(task, motion):
        time.sleep(0.4)
        return real(task, motion)
    orchestrate.run_task = slow
    if sys.argv[2] == "cli":  # the command, as a user runs it
        from pipeline.cli import main
        sys.exit(main(["study", "run", sys.argv[1], "--serial", "--quiet"]))
    mode = {"serial": True} if sys.argv[2] == "serial" else {"workers": 2}
    orchestrate.run_study(load_study(sys.argv[1]), progress=False, **mode)
""")

MANY_TASKS = 'block_columns = 1'  # 4 columns x 2 records = 8 tasks


def _kill_after(path, checkpoint, n_done, mode="serial", timeout=120.0, sig=None):
    """Run CHILD, kill it after ``n_done`` checkpointed tasks (SIGKILL to its group, or ``sig`` to it).

    Returns the finished process (``returncode``; ``stdout`` holds its output and errors).
    """
    proc = subprocess.Popen([sys.executable, "-c", CHILD, str(path), mode], start_new_session=True,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    try:
        deadline = time.monotonic() + timeout
        while True:
            done = sorted(p for p in os.listdir(checkpoint) if p.startswith("task-")) \
                if os.path.isdir(checkpoint) else []
            if len(done) >= n_done:
                break
            assert proc.poll() is None, proc.stdout.read().decode()
            assert time.monotonic() < deadline, "the study did not checkpoint in time"
            time.sleep(0.02)
        if sig is not None:
            os.kill(proc.pid, sig)
            proc.wait(timeout=30)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)  # the process group we started (with its workers)
        proc.wait(timeout=30)
    return proc


def test_killed_study_resumes_without_recomputing(write_study, small_reference, same_results):
    from study_files import SMALL_STUDY

    path = write_study(SMALL_STUDY.replace("block_columns = 2", MANY_TASKS))
    out = path.parent / "small.nc"
    checkpoint = str(out) + ".checkpoint"
    assert _kill_after(path, checkpoint, 3).returncode == -signal.SIGKILL
    assert not out.exists()  # killed: no results file, not even a partial one
    assert not [p for p in os.listdir(path.parent) if p.startswith(".partial-")]
    finished = sorted(int(p[5:11]) for p in os.listdir(checkpoint) if p.startswith("task-"))
    assert 3 <= len(finished) < 8
    stamps = {i: os.stat(os.path.join(checkpoint, f"task-{i:06d}.npz")).st_mtime_ns for i in finished}

    report = run_study(load_study(path), serial=True, progress=False, keep_checkpoint=True)
    assert report.skipped == finished  # loaded, not recomputed
    assert sorted(report.computed) == sorted(set(range(8)) - set(finished))
    assert report.simulations == sum(12 for _ in report.computed)  # 1 column x 3 scales x (1 + 3 angles)
    for i, stamp in stamps.items():  # the finished tasks' files were not rewritten
        assert os.stat(os.path.join(checkpoint, f"task-{i:06d}.npz")).st_mtime_ns == stamp
    ds = open_results(out)
    assert (ds.status == 0).all() and ds.peak_theta.notnull().all()  # complete
    same_results(ds, small_reference[1])

    # a third run finds everything in the checkpoint and computes nothing
    again = run_study(load_study(path), serial=True, progress=False)
    assert again.computed == [] and again.simulations == 0 and len(again.skipped) == 8
    assert not os.path.exists(checkpoint)  # removed once the results are written


def test_study_killed_on_the_cluster_resumes_on_the_cluster(write_study, small_reference, same_results):
    """The same, driver and workers killed together mid-study, then resumed on a fresh local cluster."""
    from study_files import SMALL_STUDY

    path = write_study(SMALL_STUDY.replace("block_columns = 2", MANY_TASKS))
    out = path.parent / "small.nc"
    checkpoint = str(out) + ".checkpoint"
    assert _kill_after(path, checkpoint, 3, mode="cluster").returncode == -signal.SIGKILL
    assert not out.exists()
    finished = sorted(int(p[5:11]) for p in os.listdir(checkpoint) if p.startswith("task-"))
    assert 3 <= len(finished) < 8
    stamps = {i: os.stat(os.path.join(checkpoint, f"task-{i:06d}.npz")).st_mtime_ns for i in finished}

    report = run_study(load_study(path), workers=2, progress=False, keep_checkpoint=True)
    assert report.skipped == finished
    assert sorted(report.computed) == sorted(set(range(8)) - set(finished))
    for i, stamp in stamps.items():  # the finished tasks' files were not rewritten
        assert os.stat(os.path.join(checkpoint, f"task-{i:06d}.npz")).st_mtime_ns == stamp
    ds = open_results(out)
    assert (ds.status == 0).all() and ds.peak_theta.notnull().all()
    same_results(ds, small_reference[1])


def test_changed_study_discards_the_old_checkpoint(write_study):
    from study_files import SMALL_STUDY

    path = write_study(SMALL_STUDY.replace("block_columns = 2", MANY_TASKS))
    out = path.parent / "small.nc"
    run_study(load_study(path), serial=True, progress=False, keep_checkpoint=True)
    other = Checkpoint(str(out) + ".checkpoint", "irrelevant")
    assert len(other.done()) == 0  # another key: emptied
    other.release()
    run_study(load_study(path), serial=True, progress=False, keep_checkpoint=True)
    path.write_text(path.read_text().replace("tail = 2.0", "tail = 1.0"))
    report = run_study(load_study(path), serial=True, progress=False)
    assert report.skipped == [] and len(report.computed) == 8


def test_checkpoint_roundtrip(tmp_path):
    result = {"index": 3, "record": 1, "start": 0, "stop": 2, "runs": 5, "seconds": 0.1, "errors": [],
              "arrays": {name: np.arange(4, dtype=dt).reshape(2, 1, 2, 1)
                         for name, dt in DTYPES.items()}}
    ck = Checkpoint(str(tmp_path / "c"), "key")
    ck.save(result)
    assert ck.done() == {3}
    back = ck.load(3)
    for name, arr in result["arrays"].items():
        assert back["arrays"][name].dtype == arr.dtype and np.array_equal(back["arrays"][name], arr)
    assert [p for p in os.listdir(tmp_path / "c") if p.startswith(".partial-")] == []


def test_two_runs_of_one_study_do_not_share_a_checkpoint(write_study):
    import pytest

    from pipeline.errors import InputError

    path = write_study()
    held = Checkpoint(str(path.parent / "small.nc") + ".checkpoint", "running")
    try:
        with pytest.raises(InputError, match="another run of this study is writing here"):
            run_study(load_study(path), serial=True, progress=False)
    finally:
        held.release()
    assert run_study(load_study(path), serial=True, progress=False).failed == 0


@pytest.mark.parametrize("sig, status, line", [
    (signal.SIGINT, 130, "frustum: interrupted: run again to resume"),  # Ctrl-C (issue 11)
    (signal.SIGTERM, 143, "frustum: terminated: run again to resume"),  # systemd, a batch system: 128 + 15
])
def test_a_stopped_command_exits_with_one_line_and_keeps_its_tasks(write_study, sig, status, line):
    """A real SIGINT or SIGTERM: one line, its status, the finished tasks kept, no results file (SIGTERM alone
    would end Python without a word)."""
    from study_files import SMALL_STUDY

    path = write_study(SMALL_STUDY.replace("block_columns = 2", MANY_TASKS))
    checkpoint = str(path.parent / "small.nc") + ".checkpoint"
    proc = _kill_after(path, checkpoint, 1, mode="cli", sig=sig)
    output = proc.stdout.read().decode()
    assert proc.returncode == status, output
    assert output.splitlines()[-1] == line and "Traceback" not in output
    assert 1 <= len([p for p in os.listdir(checkpoint) if p.startswith("task-")]) < 8
    assert not (path.parent / "small.nc").exists()
