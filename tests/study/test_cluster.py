"""Studies on Dask: a real `dask scheduler` + two `dask worker` processes on loopback, and the local cluster.

Both give the serial run's numbers exactly.
"""

import os
import signal
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from dask_processes import free_port as _free_port
from dask_processes import running_cluster
from pipeline.cli import main
from pipeline.dataset import open_results
from pipeline.study import load_study, run_study


@pytest.fixture(scope="module")
def dask_cluster(tmp_path_factory):
    """Address of a scheduler with two workers on loopback, shared by the module's tests."""
    with running_cluster(tmp_path_factory.mktemp("dask")) as (address, _):
        yield address


def test_external_cluster_equals_serial(dask_cluster, write_study, small_reference, same_results, capsys):
    """`frustum study run --scheduler ADDRESS` through two worker processes: identical numbers."""
    path = write_study()
    assert main(["study", "run", str(path), "--scheduler", dask_cluster, "--quiet"]) == 0
    assert "4 task(s) computed, 0 from the checkpoint" in capsys.readouterr().out
    same_results(open_results(path.parent / "small.nc"), small_reference[1])


def test_drum_study_is_the_same_serial_on_a_local_and_an_external_cluster(dask_cluster, write_study, drum_reference,
                                                                         same_results):
    """Two drums on compliant joints (and the monolith) through Dask: every number identical to the
    serial run, the joints' residual dislocation included, on two `dask worker` processes and on a
    local cluster of two."""
    from study_files import DRUM_STUDY

    serial = drum_reference[1]
    comp = serial.sel(model="3d-compliant", column="two-drums")
    assert serial.sizes["joint"] == 2 and (comp.joint_slip.sel(joint=1) > 0).all()  # the joint slid: not all zeros
    path = write_study(DRUM_STUDY, name="drums.toml")
    external = run_study(load_study(path), out=str(path.parent / "external.nc"), scheduler=dask_cluster,
                         progress=False)
    assert len(external.computed) == 2
    same_results(open_results(external.path), serial)
    local = run_study(load_study(path), out=str(path.parent / "local.nc"), workers=2, progress=False)
    same_results(open_results(local.path), serial)


def test_both_workers_took_tasks(dask_cluster, write_study):
    """The tasks really spread over the two workers (each records what it ran)."""
    import distributed

    report = run_study(load_study(write_study()), scheduler=dask_cluster, progress=False)
    assert len(report.computed) == 4
    with distributed.Client(dask_cluster, timeout="30s") as client:
        # every worker has imported and run pipeline.study tasks
        ran = client.run(lambda: "pipeline.study.run" in sys.modules)
    assert len(ran) == 2 and all(ran.values())


def test_local_cluster_equals_serial(write_study, small_reference, same_results, capsys):
    """The default: a LocalCluster of two processes started by the command."""
    path = write_study()
    assert main(["study", "run", str(path), "--workers", "2", "--quiet"]) == 0
    same_results(open_results(path.parent / "small.nc"), small_reference[1])
    assert not (path.parent / "small.nc.checkpoint").exists()


def test_one_cluster_serves_several_studies(write_study, small_reference, same_results):
    """run_study(cluster=...) leaves the cluster running: the next study runs on the same worker processes."""
    from pipeline.study import Cluster

    path = write_study()
    with Cluster(workers=2) as cluster:
        first = run_study(load_study(path), out=str(path.parent / "a.nc"), cluster=cluster, progress=False)
        pids = cluster.client.run(os.getpid)
        second = run_study(load_study(path), out=str(path.parent / "b.nc"), cluster=cluster, progress=False)
        assert cluster.client.run(os.getpid) == pids and len(pids) == 2  # same two workers, still up
        assert len(first.computed) == len(second.computed) == 4
    assert cluster._client is None and cluster._local is None  # closed on leaving the block
    same_results(open_results(path.parent / "a.nc"), small_reference[1])
    same_results(open_results(path.parent / "b.nc"), small_reference[1])


def test_workflow_starts_its_local_cluster_once_and_only_when_needed(tmp_path, monkeypatch):
    """Two steps that compute share one local cluster; a rerun with everything up to date starts none."""
    import textwrap

    from study_files import SMALL_STUDY
    from pipeline.study import cluster as study_cluster

    starts = []
    real = study_cluster._connect
    monkeypatch.setattr(study_cluster, "_connect", lambda *a: starts.append(a) or real(*a))
    (tmp_path / "small.toml").write_text(SMALL_STUDY, encoding="utf-8")
    (tmp_path / "other.toml").write_text(SMALL_STUDY.replace("tail = 2.0", "tail = 1.0"), encoding="utf-8")
    wf = tmp_path / "wf.toml"
    wf.write_text(textwrap.dedent("""\
        title = "two steps"
        log = "wf.log"
        [execution]
        workers = 2
        [[steps]]
        study = "small.toml"
        output = "small.nc"
        [[steps]]
        study = "other.toml"
        output = "other.nc"
    """), encoding="utf-8")
    assert main(["workflow", "run", str(wf)]) == 0
    assert len(starts) == 1 and (tmp_path / "small.nc").is_file() and (tmp_path / "other.nc").is_file()
    assert main(["workflow", "run", str(wf)]) == 0
    assert len(starts) == 1  # nothing to compute: no cluster started


def test_unreachable_scheduler_is_an_input_error(write_study, capsys):
    port = _free_port()
    assert main(["study", "run", str(write_study()), "--scheduler", f"tcp://127.0.0.1:{port}", "--quiet"]) == 2
    assert "cannot connect" in capsys.readouterr().err


def test_a_worker_that_dies_costs_only_a_retry(tmp_path, write_study, same_results):
    """Kill one of two workers (its whole process group) mid-study: the study completes, same numbers."""
    import threading

    from study_files import SMALL_STUDY

    text = SMALL_STUDY.replace("block_columns = 2", "block_columns = 1").replace(
        "duration = 6.0", "duration = 20.0")
    path = write_study(text)
    reference = run_study(load_study(path), out=str(tmp_path / "serial.nc"), serial=True, progress=False)
    checkpoint = tmp_path / "small.nc.checkpoint"
    (tmp_path / "cluster").mkdir()
    with running_cluster(tmp_path / "cluster", 2) as (address, workers):
        killed = []

        def killer():
            deadline = time.monotonic() + 60
            while time.monotonic() < deadline:
                if checkpoint.is_dir() and len(list(checkpoint.glob("task-*"))) >= 1:
                    os.killpg(workers[1].pid, signal.SIGKILL)
                    killed.append(len(list(checkpoint.glob("task-*"))))
                    return
                time.sleep(0.005)

        thread = threading.Thread(target=killer)
        thread.start()
        report = run_study(load_study(path), scheduler=address, progress=False)
        thread.join()
    assert killed and killed[0] < report.n_tasks, "the worker was not killed mid-study"
    assert workers[1].poll() is not None
    assert sorted(report.computed) == list(range(report.n_tasks))
    same_results(report.dataset, reference.dataset)


def test_a_task_that_keeps_failing_marks_its_cells_failed(write_study, small_reference, monkeypatch):
    """A task that raises on every try (after Dask's retries) gives status 1 for its cells, not a dead study."""
    from pipeline.study import orchestrate

    real = orchestrate.run_task

    def broken(task, motion):  # a local function: cloudpickle ships it by value to the worker
        if task.index == 1:
            raise MemoryError("injected task failure")
        return real(task, motion)

    monkeypatch.setattr(orchestrate, "run_task", broken)
    report = run_study(load_study(write_study()), workers=1, progress=False, keep_checkpoint=True)
    ds = report.dataset
    bad = ds.isel(record=0, column=slice(2, 4))  # task 1: record 0, columns 2-3
    assert (bad.status == 1).all() and bad.peak_theta.isnull().all()
    assert report.failed == bad.status.size
    good = ds.isel(record=1)
    assert (good.status == 0).all()
    np.testing.assert_array_equal(good.peak_theta.values, small_reference[1].isel(record=1).peak_theta.values)
    # the failed task was not checkpointed: a rerun tries it again
    assert Path(report.path + ".checkpoint", "task-000001.npz").exists() is False


def test_a_port_that_is_not_dask_fails_within_10_s(write_study, capsys):
    """A plain TCP server that accepts and never answers: Dask's client once waited for ever."""
    import socket
    import threading
    import time

    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(8)
    accepted = []
    threading.Thread(target=lambda: accepted.append(server.accept()), daemon=True).start()
    try:
        t0 = time.monotonic()
        address = f"tcp://127.0.0.1:{server.getsockname()[1]}"
        assert main(["study", "run", str(write_study()), "--scheduler", address, "--quiet"]) == 2
        elapsed = time.monotonic() - t0
    finally:
        server.close()
    err = capsys.readouterr().err
    assert elapsed < 10.0, elapsed
    assert accepted  # it did connect: the refusal comes from the silence, not from a closed port
    assert f"--scheduler {address}: no Dask scheduler answered within 8 s" in err
    assert "Traceback" not in err


@pytest.mark.parametrize("address", ["tcp://localhost", "localhost:abc", "foo://host:8786", "tcp//host:8786",
                                     "tcp://:8786", "tcp://host:99999"])
def test_a_malformed_scheduler_address_fails_at_once(write_study, capsys, address):
    import time

    t0 = time.monotonic()
    assert main(["study", "run", str(write_study()), "--scheduler", address, "--quiet"]) == 2
    assert time.monotonic() - t0 < 10.0
    err = capsys.readouterr().err
    assert f"--scheduler {address!r}: not a scheduler address; give PROTOCOL://HOST:PORT" in err
