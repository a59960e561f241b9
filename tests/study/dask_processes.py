"""A real `dask scheduler` and `dask worker` processes on loopback, for the cluster tests (imported by name:
``from dask_processes import running_cluster``)."""

import contextlib
import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

DASK = Path(sys.executable).parent / "dask"
START_TIMEOUT = 60.0  # [s] scheduler file and two workers


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def stop(proc):
    """Stop one process group we started (its id), politely then for good."""
    if proc.poll() is None:
        try:
            os.killpg(proc.pid, signal.SIGTERM)
            proc.wait(timeout=15)
        except (ProcessLookupError, subprocess.TimeoutExpired):
            try:
                os.killpg(proc.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            proc.wait(timeout=15)


@contextlib.contextmanager
def running_cluster(folder, n_workers=2, scheduler=False):
    """A scheduler and single-threaded workers, subprocesses of the `dask` CLI; always cleaned up.

    Yields (address, worker processes), and the scheduler's process last if ``scheduler``. Each
    process is its own process group, stopped by its id.
    """
    scheduler_file = folder / "scheduler.json"
    port = free_port()
    procs = []
    logs = []

    def start(args, name):
        log = open(folder / f"{name}.log", "w")  # noqa: SIM115 - closed below
        logs.append(log)
        procs.append(subprocess.Popen([str(DASK), *args], stdout=log, stderr=subprocess.STDOUT,
                                      start_new_session=True, cwd=folder))
        return procs[-1]

    try:
        start(["scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard",
               "--scheduler-file", str(scheduler_file)], "scheduler")
        deadline = time.monotonic() + START_TIMEOUT
        address = None
        while address is None:  # the file appears before its contents are written
            assert procs[0].poll() is None, (folder / "scheduler.log").read_text()
            assert time.monotonic() < deadline, "the dask scheduler did not start"
            time.sleep(0.1)
            try:
                address = json.loads(scheduler_file.read_text())["address"]
            except (OSError, ValueError, KeyError):
                pass
        workers = [start(["worker", address, "--nworkers", "1", "--nthreads", "1", "--no-dashboard",
                          "--host", "127.0.0.1", "--name", f"test-worker-{i}", "--local-directory", str(folder)],
                         f"worker-{i}") for i in range(n_workers)]
        import distributed

        with distributed.Client(address, timeout="30s") as client:
            client.wait_for_workers(n_workers, timeout=START_TIMEOUT)
        yield (address, workers, procs[0]) if scheduler else (address, workers)
    finally:
        for proc in reversed(procs):
            stop(proc)
        for log in logs:
            log.close()
