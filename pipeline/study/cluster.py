"""The Dask cluster a study runs on: the only module of the package that imports Dask.

Connecting to a scheduler (its address checked first, within seconds), or starting a local
cluster of processes kept quiet (:data:`LOCAL_CLUSTER_CONFIG`), and handing tasks to it a
window at a time (:func:`run_on_cluster`). It knows nothing of studies: what a task is and what
runs it come from :mod:`pipeline.study.orchestrate`.
"""

import os
import re
import time

from pipeline.errors import InputError

#: Seconds within which a malformed, unreachable or non-Dask scheduler address is reported.
SCHEDULER_TIMEOUT = 8.0
_SCHEMES = ("tcp", "tls", "ws", "wss")
_HOST = re.compile(r"^[A-Za-z0-9]([A-Za-z0-9.-]*[A-Za-z0-9])?$|^\[[0-9A-Fa-f:.]+\]$")


async def _identity(address, timeout):
    """The scheduler's ``identity`` reply, every step bounded by ``timeout`` [s]."""
    import asyncio

    from distributed.comm import connect

    comm = await asyncio.wait_for(connect(address, timeout=timeout), timeout)
    try:
        await asyncio.wait_for(comm.write({"op": "identity", "reply": True}), timeout)
        return await asyncio.wait_for(comm.read(), timeout)
    finally:
        comm.abort()


def scheduler_address(address):
    """``PROTOCOL://HOST:PORT`` from a scheduler address (``HOST:PORT`` means tcp), or InputError if malformed."""
    from urllib.parse import urlsplit

    full = address if "://" in address else f"tcp://{address}"
    parts = urlsplit(full)
    try:
        port = parts.port
    except ValueError:
        port = None
    host = parts.netloc.rsplit(":", 1)[0] if parts.netloc else ""
    if parts.scheme not in _SCHEMES or not _HOST.match(host) or port is None or parts.path not in ("", "/"):
        raise InputError(f"--scheduler {address!r}: not a scheduler address; give PROTOCOL://HOST:PORT with "
                         f"PROTOCOL one of {', '.join(_SCHEMES)}, e.g. tcp://10.0.0.5:8786")
    return full


def _probe_tcp(address, full, timeout, fix):
    """InputError at once if nothing listens on a tcp scheduler address.

    Dask's own connect retries a refused port until its timeout, which on a
    loaded machine turns "nothing there" into "no answer in time"; a plain
    socket tells the two apart.
    """
    import socket
    from urllib.parse import urlsplit

    parts = urlsplit(full)
    if parts.scheme != "tcp":
        return
    try:
        socket.create_connection((parts.hostname, parts.port), timeout=timeout).close()
    except OSError as exc:
        reason = exc.strerror or str(exc) or type(exc).__name__
        raise InputError(f"--scheduler {address}: cannot connect ({reason}); {fix}") from None


def check_scheduler(address, timeout=SCHEDULER_TIMEOUT):
    """Refuse, within ``timeout`` [s], a scheduler address that is malformed, unreachable or not Dask's.

    ``distributed.Client`` waits for ever on a port where something else
    listens (it never answers Dask's handshake), so the address is first
    asked for its identity with every step under a time limit.

    Returns
    -------
    str
        The address with its protocol (``tcp://host:port``).
    """
    import asyncio
    import concurrent.futures

    fix = "start one with `dask scheduler`, or drop --scheduler for a local cluster"
    full = scheduler_address(address)
    _probe_tcp(address, full, timeout, fix)
    pool = concurrent.futures.ThreadPoolExecutor(1)  # its own event loop, whatever the caller runs
    try:
        reply = pool.submit(asyncio.run, _identity(full, timeout)).result(timeout + 1.0)
    except (TimeoutError, asyncio.TimeoutError, concurrent.futures.TimeoutError):
        raise InputError(f"--scheduler {address}: no Dask scheduler answered within {timeout:g} s (is something "
                         f"else listening on that port?); {fix}") from None
    except Exception as exc:  # noqa: BLE001 - OSError, CommClosedError, ...: nobody to talk to
        raise InputError(f"--scheduler {address}: cannot connect ({' '.join(str(exc).split()) or type(exc).__name__})"
                         f"; {fix}") from None
    finally:
        pool.shutdown(wait=False)
    if not isinstance(reply, dict) or reply.get("type") != "Scheduler":
        raise InputError(f"--scheduler {address}: answers, but is not a Dask scheduler; {fix}")
    return full


# Dask settings of the local cluster (the nannies pass them on to their workers). A study's
# tasks are CPU-bound and the cluster shares the cores with them, so its own housekeeping is
# kept quiet: together these cut an idle two-worker cluster from 0.07 to 0.01 cores
# (docs/studies.md).
LOCAL_CLUSTER_CONFIG = {
    # distributed starts workers with MALLOC_TRIM_THRESHOLD_=65536 (return memory to the OS
    # early); the many small arrays of each simulation then cost ~25 % more time. The
    # workers' memory is small: keep glibc's default.
    "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None,
    # the statistical profiler samples every worker thread 100 times a second for a dashboard
    # nobody watches during a batch study
    "distributed.worker.profile.enabled": False,
    # event-loop health ticks (50 a second per server), resource sampling and the nannies'
    # memory checks, from milliseconds to seconds: a study's memory is small and bounded
    "distributed.admin.tick.interval": "1s",
    "distributed.admin.system-monitor.interval": "2s",
    "distributed.worker.memory.monitor-interval": "1s",
}


class Cluster:
    """The Dask cluster studies run on: connected or started on first use, reusable by several studies.

    Parameters
    ----------
    scheduler : str, optional
        Address of an existing ``dask.distributed`` scheduler
        (``tcp://host:port``); default: a local cluster of processes.
    workers : int, optional
        Worker processes of the local cluster (default: the number of cores).

    Notes
    -----
    Use it as a context manager and pass it to :func:`run_study` as
    ``cluster=``: a workflow of several studies then starts its local cluster
    (about 2 s) once, and only if a study needs computing. Closing it stops a
    local cluster and disconnects from an external one (which keeps running).
    """

    def __init__(self, scheduler=None, workers=None):
        self.scheduler = scheduler
        self.workers = workers
        self._client = None
        self._local = None

    @property
    def client(self):
        """The ``distributed.Client``, connecting or starting the cluster on first use."""
        if self._client is None:
            self._client, self._local = _connect(self.scheduler, self.workers)
        return self._client

    def close(self):
        """Disconnect, and stop the local cluster if this object started it."""
        if self._client is not None:
            self._client.close()
        if self._local is not None:
            self._local.close()
        self._client = self._local = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _connect(scheduler, workers):
    """(client, local cluster or None): connect to ``scheduler`` or start a local cluster.

    The client is not made Dask's default scheduler: the study submits to it
    directly, and xarray, seeing a default distributed client, would take a
    cluster-wide lock through the scheduler for every variable it writes
    (0.25 s instead of 0.05 s for a small results file).
    """
    import logging

    import distributed

    if scheduler:
        address = check_scheduler(scheduler)
        try:
            client = distributed.Client(address, timeout="30s", set_as_default=False)
        except OSError as exc:
            raise InputError(f"--scheduler {scheduler}: cannot connect ({exc}); start it with `dask scheduler` "
                             "or drop --scheduler for a local cluster") from None
        try:
            client.wait_for_workers(1, timeout=60)
        except TimeoutError:
            client.close()
            raise InputError(f"--scheduler {scheduler}: the scheduler has no worker after 60 s; start some with "
                             f"`dask worker {address}`") from None
        return client, None
    import dask

    n = workers or os.cpu_count() or 1
    with dask.config.set(LOCAL_CLUSTER_CONFIG):
        local = distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                         dashboard_address=":0", silence_logs=logging.ERROR)
    return distributed.Client(local, set_as_default=False), local


def run_on_cluster(tasks, run, args, finish, fail, cluster, window=None, prepare=None, started=None):
    """Run ``run(task, *args(task))`` for every task on the cluster; each result reaches ``finish`` as it comes.

    Parameters
    ----------
    tasks : list
        In the order to hand them out; each has an ``index`` (it names the Dask key).
    run : callable
        What a worker runs per task.
    args : callable
        ``task -> tuple``: the rest of ``run``'s arguments.
    finish : callable
        ``finish(result)``, in this process, for each task that ran.
    fail : callable
        ``fail(task, message)`` for a task that raised on every try: the others go on.
    cluster : Cluster
    window : int, optional
        Tasks in flight at once (default 2 per worker + 2): bounds the memory of scheduler and
        driver for any number of tasks.
    prepare : callable, optional
        Run once on every worker before the tasks (e.g. loading the compiled kernels).
    started : callable, optional
        ``started(n_workers)``, called when the cluster is ready.
    """
    import distributed

    client = cluster.client
    n_workers = max(1, len(client.scheduler_info().get("workers", {})))
    if prepare is not None:
        client.run(prepare)  # loads the kernels on new workers; a no-op on warm ones
    if started is not None:
        started(n_workers)
    limit = window or 2 * n_workers + 2
    # Each task carries its arguments (a record: tens of kB) rather than a scattered copy:
    # scattered data lives on one worker and is lost with it, while a task's own arguments are
    # kept by the scheduler, so a dead worker costs only a retry elsewhere.
    queue = iter(tasks)
    running = distributed.as_completed(loop=client.loop)
    in_flight = {}

    def submit_next():
        task = next(queue, None)
        if task is not None:
            future = client.submit(run, task, *args(task), pure=False, retries=2,
                                   key=f"frustum-task-{task.index}-{os.getpid()}-{time.monotonic_ns()}")
            in_flight[future.key] = task
            running.add(future)

    try:
        for _ in range(limit):
            submit_next()
        for future in running:
            task = in_flight.pop(future.key)
            try:
                result = future.result()
            except Exception as exc:  # noqa: BLE001 - after its retries a task's cells fail, the study goes on
                fail(task, f"task failed after retries: {type(exc).__name__}: {exc}")
            else:
                finish(result)
            future.release()  # results are not kept on the cluster
            submit_next()
    finally:
        for future in list(running.futures):  # interrupted: leave nothing running on a shared cluster
            future.cancel()
