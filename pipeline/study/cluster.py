"""The Dask cluster a study runs on: the only module of the package that imports Dask.

Connecting to a scheduler (its address checked first, within seconds), or starting a local
cluster of processes kept quiet (:data:`LOCAL_CLUSTER_CONFIG`), and handing tasks to it a
window at a time (:func:`run_on_cluster`). It knows nothing of studies: what a task is and what
runs it come from :mod:`pipeline.study.orchestrate`.
"""

import contextlib
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


#: Seconds without a worker after which a run says so, and that it waits (issue 38).
NOTICE_AFTER = 60.0
#: Default of ``--worker-wait`` [s]: how long a run waits for workers to come back before it stops.
WORKER_WAIT = 600.0
#: Exit status of a run that stopped waiting for workers (sysexits.h EX_TEMPFAIL, "try again later").
EXIT_NO_WORKERS = 75
#: Seconds between two looks at the results in flight.
POLL = 0.1
#: Seconds between two redraws of the progress clock while waiting.
TICK = 1.0
#: Seconds between two counts of the workers (a call to the scheduler).
COUNT_EVERY = 2.0
#: Seconds after which a count the scheduler has not answered counts as no worker.
ANSWER_TIMEOUT = 30.0
#: Seconds a local cluster gets to close before it is left to the end of the process.
CLOSE_TIMEOUT = 30.0


class WorkersGone(RuntimeError):
    """The cluster had no worker, or its scheduler did not answer, for longer than the run may wait.

    Raised by :func:`run_on_cluster`; the finished tasks are kept by the caller (the checkpoint)
    and the command exits with :data:`EXIT_NO_WORKERS`.
    """


class Cluster:
    """The Dask cluster studies run on: connected or started on first use, reusable by several studies.

    Parameters
    ----------
    scheduler : str, optional
        Address of an existing ``dask.distributed`` scheduler
        (``tcp://host:port``); default: a local cluster of processes.
    workers : int, optional
        Worker processes of the local cluster (default: the number of cores).
    worker_wait : float, optional
        How long a run waits [s] when the cluster has no worker (all died, none
        started yet) before it stops with :class:`WorkersGone` (default
        :data:`WORKER_WAIT`); it says so after :data:`NOTICE_AFTER`.

    Notes
    -----
    Use it as a context manager and pass it to :func:`run_study` as
    ``cluster=``: a workflow of several studies then starts its local cluster
    (about 2 s) once, and only if a study needs computing. :meth:`start`
    starts it in a background thread (while the records load, say).
    Closing it stops a local cluster, with nothing of its shutdown on the
    terminal (:func:`_close_local`), and disconnects from an external one
    (which keeps running).
    """

    def __init__(self, scheduler=None, workers=None, worker_wait=None):
        self.scheduler = scheduler
        self.workers = workers
        self.worker_wait = WORKER_WAIT if worker_wait is None else float(worker_wait)
        self._client = None
        self._local = None
        self._starting = None  # (thread, outcome) of a start in the background

    @property
    def client(self):
        """The ``distributed.Client``, connecting or starting the cluster on first use."""
        return self.ready()

    def describe(self):
        """What the cluster is, for a progress line: "2 workers" or the scheduler's address."""
        if self.scheduler:
            return f"the scheduler {self.scheduler}"
        n = self.workers or os.cpu_count() or 1
        return f"{n} worker{'s' if n > 1 else ''}"

    def start(self, prepare=None, when=None):
        """Start connecting, or starting the local cluster, in a background thread; returns at once.

        Parameters
        ----------
        prepare : callable, optional
            Run once on every worker when the cluster is up (loading the kernels).
        when : threading.Event, optional
            ``prepare`` waits for it (set once the kernels are compiled in this
            process, so that the workers load them rather than compile them).
        """
        import threading

        if self._client is not None or self._starting is not None:
            return
        outcome = {}

        def connect():
            try:
                outcome["connected"] = client, _ = _connect(self.scheduler, self.workers)
            except BaseException as exc:  # noqa: BLE001 - handed to the thread that waits for the cluster
                outcome["error"] = exc
                return
            if prepare is None:
                return
            while when is not None and not when.wait(0.2):
                if outcome.get("closing"):
                    return
            try:
                if not outcome.get("closing"):
                    client.run(prepare)
            except Exception:  # noqa: BLE001 - a head start only (or closed meanwhile): run_on_cluster prepares again
                pass

        # a daemon thread: an interrupted command does not wait at exit for a start nobody needs
        thread = threading.Thread(target=connect, name="frustum-cluster-start", daemon=True)
        self._starting = (thread, outcome)
        thread.start()

    def ready(self, tick=None):
        """The client, once the cluster is up (started here if :meth:`start` was not called).

        Parameters
        ----------
        tick : callable, optional
            Called about once a second while waiting (a progress clock).
        """
        if self._client is not None:
            return self._client
        if self._starting is None:
            if tick is None:  # nothing to show meanwhile: start here, in this thread
                self._client, self._local = _connect(self.scheduler, self.workers)
                return self._client
            self.start()
        thread, outcome = self._starting
        while thread.is_alive():
            thread.join(TICK)
            if tick is not None and thread.is_alive():
                tick()
        self._starting = None
        if "error" in outcome:
            raise outcome["error"]
        self._client, self._local = outcome["connected"]
        return self._client

    def close(self):
        """Disconnect, and stop the local cluster if this object started it (waiting for a start under way).

        A Ctrl-C or SIGTERM that arrives meanwhile is held until the cluster
        is closed (a second one does not wait), so that an interrupted close
        leaves no worker process behind and prints nothing.
        """
        with _signals_held():
            thread = None
            if self._starting is not None:  # a start under way: wait for the cluster, not for its workers' warm-up
                thread, outcome = self._starting
                outcome["closing"] = True
                while thread.is_alive() and "connected" not in outcome:
                    thread.join(0.2)
                self._starting = None
                self._client, self._local = outcome.get("connected", (None, None))
            client, local = self._client, self._local
            self._client = self._local = None
            if local is not None:
                _close_local(client, local)
            elif client is not None:  # an external cluster keeps running; a lost one is given up quietly
                restore = _silence_logs()
                try:
                    with contextlib.suppress(Exception):
                        client.close(timeout=CLOSE_TIMEOUT)
                finally:
                    restore()
            if thread is not None:
                thread.join(CLOSE_TIMEOUT)  # its warm-up call ends with the client

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _connect(scheduler, workers):
    """(client, local cluster or None): connect to ``scheduler`` or start a local cluster.

    The client is not made Dask's default scheduler: the study submits to it
    directly, and xarray, seeing a default distributed client, would take a
    cluster-wide lock through the scheduler for every variable it writes
    (0.25 s instead of 0.05 s for a small results file). A scheduler without
    workers is not refused here: the run waits for them (:func:`run_on_cluster`).
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
        return client, None
    import dask

    n = workers or os.cpu_count() or 1
    with dask.config.set(LOCAL_CLUSTER_CONFIG):
        local = distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                         dashboard_address=":0", silence_logs=logging.ERROR)
    return distributed.Client(local, set_as_default=False), local


# Loggers of a shutdown: a worker that closes aborts its own heartbeat call to the scheduler
# if one is under way (distributed.Worker.close closes its connections after stopping the
# periodic heartbeat, not after the call in flight), and logs that at ERROR with a
# 25-line traceback ("Failed to communicate with scheduler during heartbeat"), about one
# close in 15 on a loaded machine. No order of closing avoids it, so the workers' and this
# process's loggers of these libraries are silenced for the close alone: errors of the run
# itself are shown as before.
_SHUTDOWN_LOGGERS = ("distributed", "tornado", "asyncio")


def _silence_logs():
    """Raise the shutdown's loggers above CRITICAL in this process; returns what restores them."""
    import logging

    names = [n for n in list(logging.root.manager.loggerDict)
             if n.split(".")[0] in _SHUTDOWN_LOGGERS] + list(_SHUTDOWN_LOGGERS)
    saved = {n: logging.getLogger(n).level for n in names}
    for n in names:
        logging.getLogger(n).setLevel(logging.CRITICAL + 1)

    def restore():
        for n, level in saved.items():
            logging.getLogger(n).setLevel(level)

    return restore


def _silence_worker():
    """Run on each worker of a local cluster just before it closes (see :data:`_SHUTDOWN_LOGGERS`)."""
    _silence_logs()
    return True


def _close_local(client, local):
    """Close a local cluster so that nothing of its shutdown reaches the terminal.

    The order: the workers are told to keep their shutdown quiet, the client
    disconnects, then the cluster retires and closes its workers (nannies and
    processes) before its scheduler. Each step is bounded by
    :data:`CLOSE_TIMEOUT`; a step that fails leaves the rest to the end of
    the process (the worker processes are daemons of this one).
    """
    restore = _silence_logs()
    try:
        with contextlib.suppress(Exception):
            client.run(_silence_worker)
        with contextlib.suppress(Exception):
            client.close(timeout=CLOSE_TIMEOUT)
        with contextlib.suppress(Exception):
            local.close(timeout=CLOSE_TIMEOUT)
    finally:
        restore()


class _signals_held:
    """Hold SIGINT and SIGTERM while the block runs, then deliver the first (a second one is not held).

    In the main thread only (elsewhere the block just runs): Python runs
    signal handlers there.
    """

    def __enter__(self):
        import signal
        import threading

        self.held, self.previous = [], {}
        if threading.current_thread() is not threading.main_thread():
            return self
        signals = (signal.SIGINT, signal.SIGTERM)

        def hold(signum, frame):
            if self.held:  # asked twice: do not wait
                self._restore()
                signal.raise_signal(signum)
                return
            self.held.append(signum)

        for s in signals:
            if callable(signal.getsignal(s)):  # Python's own handler (or the command's): ours to hold
                self.previous[s] = signal.signal(s, hold)
        return self

    def _restore(self):
        import signal

        for s, handler in self.previous.items():
            signal.signal(s, handler)
        self.previous = {}

    def __exit__(self, *exc):
        import signal

        restored = bool(self.previous)
        self._restore()
        if restored and self.held:
            signal.raise_signal(self.held[0])  # as if it arrived now: the handler raises here


class _CommClosedQuiet:
    """Drop the "Batched Comm Closed" record (with its traceback) of distributed's batched sender.

    When the scheduler goes away, the client's background sender notices the closed connection
    whenever it next writes, and logs it at INFO with a traceback, sometimes during the run's
    stop and sometimes after it. :func:`run_on_cluster` says in its own words that the connection
    was lost and what was kept; the traceback tells the user nothing more (it made the lost-scheduler
    test fail when it came before the run's own message). Other records of the logger pass.
    """

    def filter(self, record):
        return not str(record.msg).startswith("Batched Comm Closed")


_COMM_CLOSED_QUIET = _CommClosedQuiet()


class _rescheduling_quiet:
    """Drop the client's "Couldn't gather N keys, rescheduling" warning while a run goes on.

    A worker that dies holding a finished task's result costs that task a second computation,
    which :func:`run_on_cluster` waits for (and says that it waits for workers, if none is
    left): the warning and its key tell the user nothing to do. Other records of the logger pass.
    Also quiets the sender's closed connection (:class:`_CommClosedQuiet`), for the rest of the
    process: it is logged whenever the sender notices it, after the run as well.
    """

    def filter(self, record):
        return not str(record.msg).startswith("Couldn't gather")

    def __enter__(self):
        import logging

        logging.getLogger("distributed.client").addFilter(self)
        logging.getLogger("distributed.batched").addFilter(_COMM_CLOSED_QUIET)  # once: a second add is none
        return self

    def __exit__(self, *exc):
        import logging

        logging.getLogger("distributed.client").removeFilter(self)


def count_workers(client, timeout=10.0):
    """Running workers the scheduler knows, or None if it does not answer within ``timeout`` [s]."""
    try:
        return len(client.sync(client.scheduler.ncores_running, callback_timeout=timeout))
    except Exception:  # noqa: BLE001 - closed client, lost connection, time-out: no answer
        return None


class _WorkerWatch:
    """Counts the seconds the cluster has had no worker; says so, and gives up after ``wait`` [s].

    The scheduler is asked every :data:`COUNT_EVERY` seconds without waiting for its answer
    (a loaded scheduler answers late: the run goes on meanwhile); a question unanswered
    for :data:`ANSWER_TIMEOUT` counts as no worker from when it was asked.

    Parameters
    ----------
    client : distributed.Client
    wait : float
        Seconds without a worker after which :meth:`check` raises :class:`WorkersGone`.
    say : callable
        ``say(line)``: a notice for the user.
    scheduler : str or None
        The external scheduler's address (None: a local cluster), for the advice.
    workers : int
        Workers at the start.
    """

    def __init__(self, client, wait, say, scheduler, workers):
        self.client, self.wait, self.say, self.scheduler = client, wait, say, scheduler
        self.notice = min(NOTICE_AFTER, wait / 2)  # said before giving up, whatever the wait
        self.workers = workers
        self.since = None if workers else time.monotonic()  # when no worker was first seen
        self.told = False
        self.question, self.asked, self.next_count = None, 0.0, 0.0

    def waiting(self):
        """Whether the run is waiting for workers (none at the last count)."""
        return self.since is not None

    def _ask(self):
        import asyncio

        async def ask():
            return await self.client.scheduler.ncores_running()

        return asyncio.run_coroutine_threadsafe(ask(), self.client.loop.asyncio_loop)

    def _answer(self, n, asked):
        self.workers = n
        if n:
            if self.told:
                self.say(f"frustum: {n} worker(s) back after {asked - self.since:.0f} s; going on")
            self.since, self.told = None, False
        elif self.since is None:
            self.since = asked

    def check(self):
        """Ask the scheduler, or read its answer; raise :class:`WorkersGone` after ``wait`` without workers."""
        now = time.monotonic()
        if self.question is not None:
            if self.question.done():
                try:
                    n = len(self.question.result())
                except Exception:  # noqa: BLE001 - lost connection, closed client: no answer
                    n = None
                self.question = None
                self._answer(n, self.asked)
            elif now - self.asked >= ANSWER_TIMEOUT:
                self.question.cancel()
                self.question = None
                self._answer(None, self.asked)
        elif now >= self.next_count:
            try:
                self.question = self._ask()
            except Exception:  # noqa: BLE001 - a closed client cannot ask: no answer
                self._answer(None, now)
            self.asked, self.next_count = now, now + COUNT_EVERY
        if self.since is None:
            return
        gone = now - self.since
        what = "no answer from the scheduler" if self.workers is None else "no workers"
        if gone >= self.wait:
            raise WorkersGone(f"{what} for {gone:.0f} s (--worker-wait {self.wait:g}): stopped")
        if not self.told and gone >= self.notice:
            advice = f" (start some with `dask worker {self.scheduler}`)" if self.scheduler and \
                self.workers is not None else ""
            self.say(f"frustum: {what} for {gone:.0f} s; waiting for workers{advice} up to --worker-wait "
                     f"{self.wait:g} s, Ctrl-C keeps the checkpoint")
            self.told = True


def run_on_cluster(tasks, run, args, finish, fail, cluster, window=None, prepare=None, started=None, tick=None,
                   say=None):
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
    tick : callable, optional
        ``tick(status)`` about once a second whatever happens (a progress clock), with what the
        run waits for ("starting 2 workers", "waiting for workers") or "".
    say : callable, optional
        ``say(line)`` for notices (no workers for a while, workers back); default: stderr.

    Raises
    ------
    WorkersGone
        The cluster had no worker for ``cluster.worker_wait`` seconds, or its scheduler
        closed the connection: the tasks not finished are left undone.
    """
    import sys

    import distributed

    tick = tick or (lambda status: None)
    say = say or (lambda line: print(line, file=sys.stderr, flush=True))
    starting = f"starting {cluster.describe()}" if not cluster.scheduler else f"connecting to {cluster.scheduler}"
    client = cluster.ready(tick=lambda: tick(starting))
    n_workers = count_workers(client) or 0
    if prepare is not None and n_workers:
        client.run(prepare)  # loads the kernels on new workers; a no-op on warm ones
    if started is not None:
        started(max(1, n_workers))
    watch = _WorkerWatch(client, cluster.worker_wait, say, cluster.scheduler, n_workers)
    # Each task carries its arguments (a record: tens of kB) rather than a scattered copy:
    # scattered data lives on one worker and is lost with it, while a task's own arguments are
    # kept by the scheduler, so a dead worker costs only a retry elsewhere.
    queue = iter(tasks)
    # results are fetched in the client's event loop as they come; one whose worker died with it
    # is computed again (when there are workers) before it comes
    running = distributed.as_completed(loop=client.loop, with_results=True, raise_errors=False)
    in_flight = {}  # future key -> task

    def submit_next():
        task = next(queue, None)
        if task is not None:
            future = client.submit(run, task, *args(task), pure=False, retries=2,
                                   key=f"frustum-task-{task.index}-{os.getpid()}-{time.monotonic_ns()}")
            in_flight[future.key] = task
            running.add(future)
        return task is not None

    def limit():  # the window follows the workers there are (none yet: a few tasks wait at the scheduler)
        return window or 2 * max(1, watch.workers or 0) + 2

    try:
        with _rescheduling_quiet():
            while len(in_flight) < limit() and submit_next():
                pass
            while not running.is_empty():
                done = running.next_batch(block=False)
                if not done:
                    time.sleep(POLL)  # as as_completed itself waits; between the looks, the clock and the workers
                for future, result in done:
                    task = in_flight.pop(future.key)
                    if future.status == "error":  # raised on the workers, after its retries: its cells fail
                        exc = result[1] if isinstance(result, tuple) else result
                        fail(task, f"task failed after retries: {type(exc).__name__}: {exc}")
                    elif future.status == "cancelled":  # the client lost its scheduler: no result will come
                        raise WorkersGone(f"lost the connection to the scheduler {cluster.scheduler or ''}".rstrip()
                                          + ": stopped")
                    else:
                        finish(result)
                    future.release()  # results are not kept on the cluster
                while len(in_flight) < limit() and submit_next():
                    pass
                watch.check()
                tick("waiting for workers" if watch.waiting() else "")
    finally:
        for future in list(running.futures):  # interrupted: leave nothing running on a shared cluster
            with contextlib.suppress(Exception):  # a lost scheduler cannot be told
                future.cancel()
