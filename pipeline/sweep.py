"""A study's grid -> tasks -> Dask -> one results Dataset, resumable.

The grid is columns x records x angles x scales x models. One task runs one
record on a block of columns for every angle, scale and model, so that a task
lasts long enough (about a second) for Dask's per-task cost (a few ms) to stay
far below 5 %. This is the only module of the package that imports Dask.

Physics used to save work: the 3D column is axisymmetric, so its response to
the record turned by the incidence angle is the response to the record as
recorded, turned by that angle (:mod:`pipeline.simulate` already runs 3D in the
record's frame). Every 3D summary value is therefore exactly independent of
the angle: a task runs 3D once per (column, record, scale) and broadcasts the
values over the angles. The 2D model (rocking in the plane of the X component
of the turned pair) is run at every angle, as is the compliant-contact model
(``3d-compliant``), whose discrete contact points are not axisymmetric.

Nothing is lost: each finished task is written, atomically, to a checkpoint
folder next to the output (``OUTPUT.checkpoint/``) by the process that drives
the study; a rerun of the same study (same file bytes, records, software
version) skips the tasks found there. The final netCDF file is written under a
temporary name and renamed; the checkpoint folder is removed afterwards.
Only the driving process writes files, so workers need no shared disk.

Public: :func:`run_study`, :class:`Cluster` (one cluster for several studies),
:func:`plan`, :func:`longest_first`, :func:`run_task`, :func:`assemble`,
:func:`record_intensity`.
"""

import contextlib
import hashlib
import json
import math
import os
import re
import shutil
import sys
import time
from dataclasses import dataclass, field

import numpy as np
import xarray as xr

from pipeline import __version__
from pipeline.atomic import PARTIAL_PREFIX, atomic_open
from pipeline.dataset import STUDY_VARIABLES, annotate, append_history, write_results
from pipeline.errors import InputError, OutputError
from pipeline.limits import check_fits, results_bytes
from pipeline.locking import try_lock
from pipeline.models import REGISTRY
from pipeline.paths import check_output_file
from pipeline.settings import Excitation, ModelSettings
from pipeline.simulate import simulate

FLOAT_VARIABLES = ("peak_theta", "peak_theta_ratio", "peak_time", "overturn_time", "uplift_time", "peak_mu_mob",
                   "residual_rotation", "residual_displacement", "work_ground", "energy_balance_error")
FLAG_VARIABLES = ("overturned", "uplifted", "sliding_onset", "lift_off", "status")
INT_VARIABLES = ("n_impacts",)
RESULT_VARIABLES = FLOAT_VARIABLES + INT_VARIABLES + FLAG_VARIABLES
_DTYPES = {**{n: np.float64 for n in FLOAT_VARIABLES}, **{n: np.int32 for n in INT_VARIABLES},
           **{n: np.int8 for n in FLAG_VARIABLES}}
DIMS = ("column", "record", "angle", "scale", "model")
# A study that runs the compliant model also holds (pipeline.compliant): the largest residual
# slip of a bed joint over its diameter, the body that fell first (-1: none), and per joint
# (dimension ``joint``; joint k is the base of body k) the residual dislocation. NaN for the
# rigid models and for the joints a column does not have.
COMPLIANT_VARIABLES = ("dislocation_ratio", "overturn_drum")
JOINT_VARIABLES = ("joint_slip", "joint_twist", "joint_tilt", "joint_opening")
_DTYPES.update({"dislocation_ratio": np.float64, "overturn_drum": np.int32,
                **{n: np.float64 for n in JOINT_VARIABLES}})

# Simulations a task should hold at least (one FEMA record: ~5-20 ms each).
TARGET_SIMULATIONS_PER_TASK = 64


@dataclass(frozen=True)
class Task:
    """One unit of work: a record on a block of columns, every angle, scale and model.

    Attributes
    ----------
    index : int
        Task number in the study (names its checkpoint file).
    record : int
        Index of the record in the study.
    start, stop : int
        Column indices of the block, ``columns[start:stop]``.
    columns : tuple of pipeline.geometry.Column
    angles : tuple of float
        Incidence angles [degree].
    factors : tuple of float
        Factors on the record, one per scale level [1].
    settings : tuple of pipeline.settings.ModelSettings
        One per model.
    vertical : bool
    stacks : tuple
        Per column, its drums (:class:`pipeline.drums.DrumColumn`) for the compliant model,
        or None (the monolith); empty: every column a monolith.
    n_joints : int
        Length of the ``joint`` dimension of the results (0: no compliant model).
    """

    index: int
    record: int
    start: int
    stop: int
    columns: tuple
    angles: tuple
    factors: tuple
    settings: tuple
    vertical: bool
    stacks: tuple = ()
    n_joints: int = 0

    @property
    def shape(self):
        """Shape of the task's result arrays: (columns, angles, scales, models)."""
        return (len(self.columns), len(self.angles), len(self.factors), len(self.settings))

    @property
    def n_simulations(self):
        """Simulations actually run (an angle-invariant model once over all angles)."""
        per = sum(1 if REGISTRY[s.model].angle_invariant else len(self.angles) for s in self.settings)
        return len(self.columns) * len(self.factors) * per


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


# -- intensity measures --------------------------------------------------------------------------

def record_intensity(motion, sa_period=None):
    """Angle-independent intensity measures of a record as given (factor 1).

    Parameters
    ----------
    motion : pipeline.groundmotion.GroundMotion
    sa_period : float, optional
        Period [s] of the spectral acceleration.

    Returns
    -------
    dict
        ``pga``: peak of the horizontal acceleration vector max|(a_x, a_y)|
        [m/s^2]; ``pgv``: peak of the horizontal velocity vector (trapezoidal
        integration from rest) [m/s]; ``sa``: 5 %-damped RotD50 spectral
        acceleration at ``sa_period`` [m/s^2] (NaN without a period). The
        vector peaks do not change when the pair is turned, so they do not
        depend on the incidence angle; all three are linear in the scale factor.
    """
    from pipeline.groundmotion import intensity as im

    ax, ay, dt = np.asarray(motion.acc_x), np.asarray(motion.acc_y), motion.dt
    out = {
        "pga": float(np.max(np.hypot(ax, ay))),
        "pgv": float(np.max(np.hypot(im.velocity(ax, dt), im.velocity(ay, dt)))),
        "sa": math.nan,
    }
    if sa_period is not None:
        out["sa"] = im.rotd50(ax, ay, dt, measure="sa", period=sa_period)
    return out


def scale_factors(study, measures):
    """Factors on each record, one per scale level: (n_records, n_scales) [1]."""
    if study.scales is not None:
        return np.tile(np.asarray(study.scales, dtype=np.float64), (len(measures), 1))
    out = np.empty((len(measures), len(study.intensity.values)))
    for i, (spec, m) in enumerate(zip(study.records, measures)):
        value = m[study.intensity.measure]
        if not value > 0:
            raise InputError(f"{study.path}: field {spec.field}: record {spec.id!r} has "
                             f"{study.intensity.measure} = {value!r}; it cannot be scaled to a target level")
        out[i] = np.asarray(study.intensity.values) / value
    return out


# -- plan ----------------------------------------------------------------------------------------

def n_tasks(study):
    """Number of tasks of a study: records x column blocks."""
    return len(study.records) * math.ceil(len(study.columns) / block_size(study))


def memory_estimate(study):
    """Memory a study's run needs in the driving process [bytes] (:func:`pipeline.limits.results_bytes`).

    A study that runs the compliant model also holds, per cell, its two scalars and the
    per-joint dislocations (``JOINT_VARIABLES`` x ``n_joints`` float64), copied once when written.
    """
    extra = 0
    if study.n_joints:
        scalars = sum(np.dtype(_DTYPES[n]).itemsize for n in COMPLIANT_VARIABLES)
        extra = 2 * (scalars + len(JOINT_VARIABLES) * 8 * study.n_joints)
    return results_bytes(study.n_simulations, n_tasks(study), extra)


def check_memory(study):
    """Refuse, before anything is loaded or computed, a study whose grid cannot fit in memory."""
    nc, nr, na, ns, nm = study.shape
    check_fits(memory_estimate(study),
               f"{study.path}: the results grid of {study.n_simulations:,} cells ({nc:,} columns x {nr:,} records x "
               f"{na:,} angles x {ns:,} scales x {nm} models, {n_tasks(study):,} tasks)",
               "split the study into several files (fewer columns, records, angles or scales each)")


def block_size(study):
    """Columns per task: the study's ``block_columns`` or enough for ~64 simulations.

    The automatic size is then evened out over the blocks it makes (10 columns
    at 7 per block become 5 + 5, not 7 + 3), so that tasks are alike and none
    is left long at the end. Depends on the study only (not on the number of
    workers), so that a study resumed with another cluster finds the same
    tasks in its checkpoint.
    """
    n = len(study.columns)
    if study.block_columns:
        return min(study.block_columns, n)
    per_column = len(study.levels) * sum(1 if REGISTRY[m].angle_invariant else len(study.angles)
                                         for m in study.models)
    size = max(1, min(n, math.ceil(TARGET_SIMULATIONS_PER_TASK / per_column)))
    return math.ceil(n / math.ceil(n / size))


def plan(study, factors):
    """The study's tasks, record-major.

    Parameters
    ----------
    study : pipeline.study.Study
    factors : numpy.ndarray
        (n_records, n_scales) factors from :func:`scale_factors`.

    Returns
    -------
    list of Task
    """
    size = block_size(study)
    angles = tuple(float(a) for a in study.angles)
    settings = tuple(study.settings(m) for m in study.models)
    columns = [c.column for c in study.columns]
    stacks = [c.stack for c in study.columns]
    tasks = []
    for ri in range(len(study.records)):
        for start in range(0, len(columns), size):
            stop = min(start + size, len(columns))
            tasks.append(Task(len(tasks), ri, start, stop, tuple(columns[start:stop]), angles,
                              tuple(float(f) for f in factors[ri]), settings, study.vertical,
                              tuple(stacks[start:stop]), study.n_joints))
    return tasks


def longest_first(tasks, motions):
    """The tasks in the order to hand them to a cluster: the most expensive first.

    A study ends when its last task does; with the long tasks started first, the
    ones left for the end are short and the workers finish together (the
    longest-processing-time rule). The cost of a task is estimated as its
    simulations times the record's duration (plus the free tail every run
    integrates), with the more slender block first among equals, since slender
    columns uplift earlier and rock longer. Only the order changes: task
    indices, results and checkpoint are the same.

    Parameters
    ----------
    tasks : list of Task
    motions : list of GroundMotion
        The study's records, indexed by ``Task.record``.

    Returns
    -------
    list of Task
    """
    def cost(task):
        tail = max(s.tail for s in task.settings)
        slender = max(c.slenderness for c in task.columns)
        return (-task.n_simulations * (motions[task.record].duration + tail), -slender, task.index)

    return sorted(tasks, key=cost)


def result_variables(n_joints=0):
    """Names of a study's result arrays: the common ones, and the compliant model's if ``n_joints`` > 0."""
    return RESULT_VARIABLES + (COMPLIANT_VARIABLES + JOINT_VARIABLES if n_joints else ())


def result_shape(name, shape, n_joints):
    """Shape of one result array: ``shape``, with the ``joint`` dimension last for a joint variable."""
    return tuple(shape) + ((n_joints,) if name in JOINT_VARIABLES else ())


def blank_arrays(shape, status, n_joints=0):
    """Result arrays of ``shape`` before any simulation: floats NaN, counts and flags 0 (``overturn_drum``
    -1), ``status`` as given; with ``n_joints`` > 0 also the compliant model's."""
    arrays = {name: np.zeros(result_shape(name, shape, n_joints), dtype=_DTYPES[name])
              for name in result_variables(n_joints)}
    for name, values in arrays.items():
        if values.dtype.kind == "f":
            values[...] = np.nan
    arrays["status"][...] = status
    if n_joints:
        arrays["overturn_drum"][...] = -1
    return arrays


# -- one task ------------------------------------------------------------------------------------

def run_task(task, motion):
    """Run one task; a failing simulation is flagged (status 1), not raised.

    Parameters
    ----------
    task : Task
    motion : pipeline.groundmotion.GroundMotion

    Returns
    -------
    dict
        ``index``, ``record``, ``start``, ``stop``, ``runs`` (simulations run),
        ``seconds`` (wall time [s]), ``cpu_seconds`` (CPU time of the
        process [s]), ``errors`` (first messages) and
        ``arrays``: name -> array (n_block_columns, n_angles, n_scales, n_models).
    """
    t0, c0 = time.perf_counter(), time.process_time()
    arrays = blank_arrays(task.shape, status=0, n_joints=task.n_joints)
    runs, errors = 0, []
    for ci, shaft in enumerate(task.columns):
        stack = task.stacks[ci] if task.stacks else None
        for mi, settings in enumerate(task.settings):
            model = REGISTRY[settings.model]
            # a model of drums runs the drums; a model of monoliths the shaft as a monolith
            column = stack if (stack is not None and model.drums) else shaft
            for si, factor in enumerate(task.factors):
                # angle-invariant: one run at the first angle, broadcast (axisymmetry, module docstring)
                angle_runs = [(task.angles[0], slice(None))] if model.angle_invariant else \
                    [(a, ai) for ai, a in enumerate(task.angles)]
                for angle, where in angle_runs:
                    runs += 1
                    index = (ci, where, si, mi)
                    try:
                        summary = simulate(column, motion, Excitation(angle=angle, scale=factor,
                                                                      vertical=task.vertical),
                                           settings, histories=False).summary
                    except Exception as exc:  # noqa: BLE001 - one failure must not kill the study
                        arrays["status"][index] = 1
                        if len(errors) < 5:
                            errors.append(f"{column.name} {settings.model} angle {angle:g} deg "
                                          f"factor {factor:g}: {type(exc).__name__}: {exc}")
                        continue
                    for name in FLOAT_VARIABLES:
                        arrays[name][index] = summary[name]
                    arrays["n_impacts"][index] = summary["n_impacts"]
                    for name in FLAG_VARIABLES[:-1]:
                        arrays[name][index] = 1 if summary[name] else 0
                    if task.n_joints:
                        # a rigid column is one body: if anything fell, it did
                        arrays["overturn_drum"][index] = summary.get("overturn_drum", 0 if summary["overturned"] else -1)
                        if "joint_slip" in summary:
                            arrays["dislocation_ratio"][index] = summary["dislocation_ratio"]
                            joints = index + (slice(0, len(summary["joint_slip"])),)
                            for name in JOINT_VARIABLES:
                                arrays[name][joints] = summary[name]
    return {"index": task.index, "record": task.record, "start": task.start, "stop": task.stop, "runs": runs,
            "seconds": time.perf_counter() - t0, "cpu_seconds": time.process_time() - c0, "errors": errors,
            "arrays": arrays}


def failed_result(task, message):
    """What a task that could not run yields: every cell status 1 (NaN, flags 0)."""
    arrays = blank_arrays(task.shape, status=1, n_joints=task.n_joints)
    return {"index": task.index, "record": task.record, "start": task.start, "stop": task.stop, "runs": 0,
            "seconds": 0.0, "cpu_seconds": 0.0, "errors": [f"columns {task.start}-{task.stop - 1}: {message}"],
            "arrays": arrays}


def warm_up(models):
    """Run a tiny simulation per model (names) so the compiled kernels are loaded (or compiled once).

    Called in the driving process before workers start, so that a stale numba
    cache is rebuilt once rather than by every worker; workers call it too so
    that loading the cache is not counted inside the first task.
    """
    from pipeline.geometry import Column
    from pipeline.groundmotion.synthesis import one_sine_pulse

    motion = one_sine_pulse(5.0, 0.2, dt=0.01, duration=0.3, record_id="warm-up")
    for model in models:
        simulate(Column(0.5, 0.4, 4.0), motion, Excitation(), ModelSettings(model=model, tail=0.2),
                 histories=False)
    return True


#: What the first run on a machine is told: compiling both models' kernels took 40-70 s on
#: the project's 2-core machines; later runs load them from numba's cache in about 2 s.
COMPILE_NOTICE = ("frustum: compiling the simulation kernels for this machine, once (one to two minutes on two cores); "
                  "later runs load them from the cache")
#: Without a readable cache index (another numba version), a load this long [s] is taken for a compile.
COMPILE_NOTICE_AFTER = 10.0

def kernels_cached(models):
    """Whether numba's cache holds the compiled kernels of every model (None: cannot tell).

    Reads the cache index of each model's compiled entry points (``Model.entry_points`` of the
    registry; numba's ``FunctionCache``; an index of a changed source counts as missing).
    """
    import importlib

    try:
        return all(bool(getattr(importlib.import_module(module), name)._cache._cache_file._load_index())
                   for model in models for module, name in REGISTRY[model].entry_points)
    except (AttributeError, OSError, EOFError, ValueError):
        return None


def prepare_kernels(models, stream=None):
    """Load the compiled kernels in this process, compiling them first if numba's cache is cold or stale.

    Called before any Dask worker starts, so that the compile happens once,
    here, and the workers load the result from the cache. With a cold cache
    the other models' kernels compile at the same time in a helper process
    each (one per core), and, when ``stream`` is given, one line says that
    the kernels compile once and about how long, and one when they are ready.

    Parameters
    ----------
    models : sequence of str
    stream : file, optional
        Where to say it (e.g. ``sys.stderr``); None: silent.

    Returns
    -------
    float
        Seconds spent [s].
    """
    import subprocess
    import threading

    models = tuple(models)
    t0 = time.monotonic()
    cached = kernels_cached(models)
    said = threading.Event()

    def say():
        said.set()
        if stream is not None:
            print(COMPILE_NOTICE, file=stream, flush=True)

    helpers = []
    if cached is False:
        say()
        helpers = [subprocess.Popen([sys.executable, "-c", f"from pipeline.sweep import warm_up; warm_up(({m!r},))"],
                                    stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                   for m in models[1:] if os.cpu_count() and os.cpu_count() > 1]
    notice = threading.Timer(COMPILE_NOTICE_AFTER, say) if cached is None else None
    if notice is not None:
        notice.daemon = True
        notice.start()
    try:
        warm_up(models[:1])
    finally:
        if notice is not None:
            notice.cancel()
        for helper in helpers:
            helper.wait()  # whatever a helper failed to cache, the next line compiles here
    warm_up(models[1:])
    seconds = time.monotonic() - t0
    if said.is_set() and stream is not None:
        print(f"frustum: kernels ready after {seconds:.0f} s", file=stream, flush=True)
    return seconds


# -- checkpoint ----------------------------------------------------------------------------------

class Checkpoint:
    """Per-study folder of finished tasks (``task-NNNNNN.npz``, written atomically).

    Parameters
    ----------
    folder : str
    key : str
        Identity of the computation (study digest, record digests, software
        version, task layout). A folder holding another key is emptied.
    """

    def __init__(self, folder, key):
        self.folder = folder
        self.key = key
        os.makedirs(folder, exist_ok=True)
        # one run per checkpoint at a time; the kernel releases the lock if the run dies
        self._lock = try_lock(os.path.join(folder, ".lock"))
        if self._lock is None:
            raise InputError(f"{folder}: another run of this study is writing here; wait for it to finish "
                             "(or give another --out)") from None
        manifest = os.path.join(folder, "manifest.json")
        old = None
        if os.path.exists(manifest):
            try:
                with open(manifest, encoding="utf-8") as f:
                    old = json.load(f).get("key")
            except (OSError, ValueError):
                old = None
        if old != key:
            for name in os.listdir(folder):
                if name.startswith("task-") or name.startswith(PARTIAL_PREFIX):
                    os.unlink(os.path.join(folder, name))
            self._atomic(manifest, json.dumps({"key": key, "software": __version__}).encode())

    def _path(self, index):
        return os.path.join(self.folder, f"task-{index:06d}.npz")

    def _atomic(self, path, payload):
        with atomic_open(path, "wb", fsync=True) as f:
            f.write(payload)

    def done(self):
        """Indices of the finished tasks found in the folder."""
        return {int(n[5:11]) for n in os.listdir(self.folder) if n.startswith("task-") and n.endswith(".npz")}

    def save(self, result):
        """Write one task's result (atomic: temporary name, then rename)."""
        import io

        buf = io.BytesIO()
        meta = {k: result.get(k) for k in ("index", "record", "start", "stop", "runs", "seconds", "cpu_seconds",
                                           "errors")}
        np.savez(buf, meta=np.array(json.dumps(meta)), **result["arrays"])
        self._atomic(self._path(result["index"]), buf.getvalue())

    def load(self, index, shape=None, n_joints=0):
        """Read one task's result back (same layout as :func:`run_task` returns).

        A file that cannot be read whole (truncated by a full disk or a crash
        of the file system, edited, of another layout) is reported on stderr by
        name and deleted, and None is returned: its task is computed again.

        Parameters
        ----------
        index : int
        shape : tuple, optional
            The task's (columns, angles, scales, models); a file whose arrays
            differ (in names or shapes, :func:`result_variables`) is damaged.
        n_joints : int
            The task's ``joint`` dimension (0: no compliant model).
        """
        path = self._path(index)
        try:
            with np.load(path) as f:
                meta = json.loads(str(f["meta"]))
                meta["arrays"] = {name: f[name] for name in f.files if name != "meta"}
            arrays = meta["arrays"]
            if meta.get("index") != index or (shape is not None and (
                    set(arrays) != set(result_variables(n_joints))
                    or any(a.shape != result_shape(name, shape, n_joints) for name, a in arrays.items()))):
                raise ValueError("its contents belong to another task layout")
        except Exception as exc:  # noqa: BLE001 - zipfile, numpy, json and OS errors alike mean "damaged"
            print(f"frustum: warning: checkpoint file {path} is damaged ({type(exc).__name__}: "
                  f"{' '.join(str(exc).split())}); its task is computed again", file=sys.stderr)
            with contextlib.suppress(OSError):
                os.unlink(path)
            return None
        return meta

    def release(self):
        """Let another run use the folder."""
        self._lock.release()

    def remove(self):
        """Delete the folder (after the results file is written) and release it."""
        self.release()
        shutil.rmtree(self.folder, ignore_errors=True)


def checkpoint_key(study, motions, tasks):
    """Identity of a study's computation, for the checkpoint."""
    h = hashlib.sha256()
    for part in [study.digest, __version__, str(block_size(study)), str(len(tasks))]:
        h.update(part.encode())
    for m in motions:
        h.update(m.sha256().encode())
    return h.hexdigest()


# -- progress ------------------------------------------------------------------------------------

class Progress:
    """A text progress bar on stderr: work done, elapsed time and ETA (a line every 5 s when not a terminal).

    ``unit`` names what is counted (finished tasks; seconds of motion for a single long run).
    """

    def __init__(self, total, done=0, stream=None, enabled=True, width=30, unit="tasks"):
        self.total, self.done, self.width, self.unit = total, done, width, unit
        self.stream = stream or sys.stderr
        self.enabled = enabled
        self.start = time.monotonic()
        self.first = done
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.last_line = -1.0
        self.show()

    def advance(self, n=1):
        self.done += n
        self.show()

    def update(self, done):
        """Set the work done so far (a run that reports its own progress)."""
        self.done = done
        self.show()

    def restart(self):
        """Start the clock again (the cluster is ready): elapsed and ETA count only computing."""
        self.start = time.monotonic()
        self.first = self.done
        self.last_line = -1.0

    def show(self, final=False):
        if not self.enabled or (final and getattr(self, "shown_total", False)):
            return
        elapsed = time.monotonic() - self.start
        frac = self.done / self.total if self.total else 1.0
        if not self.tty and not final and self.done not in (self.first, self.total) \
                and elapsed - self.last_line < 5.0:
            return  # in logs: a line every 5 s at most
        self.last_line = elapsed
        new = self.done - self.first
        eta = elapsed / new * (self.total - self.done) if new else math.nan
        bar = "#" * int(round(frac * self.width))
        text = (f"[{bar:<{self.width}}] {self.done:g}/{self.total:g} {self.unit} {100 * frac:5.1f}% "
                f"elapsed {elapsed:6.1f} s" + (f" eta {eta:6.1f} s" if math.isfinite(eta) else ""))
        self.stream.write(("\r" + text) if self.tty else text + "\n")
        if self.tty and self.done == self.total:
            self.stream.write("\n")
        self.stream.flush()
        self.shown_total = self.done == self.total


# -- run -----------------------------------------------------------------------------------------


def _place(arrays, result):
    ri, a, b = result["record"], result["start"], result["stop"]
    for name, values in result["arrays"].items():
        arrays[name][a:b, ri] = values


def run_study(study, *, out=None, motions=None, scheduler=None, workers=None, serial=False, progress=True,
              keep_checkpoint=False, window=None, cluster=None):
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
    """
    from pipeline.study import load_motions

    out = check_study_output(study, out)
    check_memory(study)
    motions = motions if motions is not None else load_motions(study)
    measures = [record_intensity(m, study.sa_period) for m in motions]
    factors = scale_factors(study, measures)
    tasks = plan(study, factors)
    fresh = not os.path.lexists(out + ".checkpoint")
    ckpt = Checkpoint(out + ".checkpoint", checkpoint_key(study, motions, tasks))
    own = cluster is None  # a cluster for this study alone; it connects only if a task is left to compute
    cluster = cluster or Cluster(scheduler, workers)
    try:
        return _run_checkpointed(study, out, motions, measures, factors, tasks, ckpt, cluster, serial, progress,
                                 keep_checkpoint, window)
    except BaseException:
        if fresh and not ckpt.done():  # a run that could not start (no scheduler) leaves no empty folder
            ckpt.remove()
        raise
    finally:
        ckpt.release()
        if own:
            cluster.close()


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
                      keep_checkpoint, window):
    arrays = blank_arrays(study.shape, status=1, n_joints=study.n_joints)  # failures until a task fills them
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
        prepare_kernels(study.models, sys.stderr if progress else None)
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

    if pending:
        if serial:
            report.startup_seconds = time.monotonic() - t0
            for task in pending:
                finish(run_task(task, motions[task.record]))
        else:
            def started(n_workers):
                report.startup_seconds = time.monotonic() - t0
                report.n_workers = n_workers
                bar.restart()  # the ETA counts computing, not starting the cluster

            _run_dask(pending, motions, finish, cluster, window, study.models, started)
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
    report.dataset = ds
    report.failed = int(ds.status.sum())
    if not keep_checkpoint:
        ckpt.remove()
    return report


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


def _run_dask(pending, motions, finish, cluster, window, models, started=None):
    import distributed

    client = cluster.client
    n_workers = max(1, len(client.scheduler_info().get("workers", {})))
    client.run(warm_up, models)  # loads the kernels on new workers; a no-op on warm ones
    if started is not None:
        started(n_workers)
    limit = window or 2 * n_workers + 2
    # Each task carries its record (tens of kB) rather than a scattered copy: scattered
    # data lives on one worker and is lost with it, while a task's own arguments are
    # kept by the scheduler, so a dead worker costs only a retry elsewhere.
    queue = iter(longest_first(pending, motions))
    running = distributed.as_completed(loop=client.loop)
    in_flight = {}

    def submit_next():
        task = next(queue, None)
        if task is not None:
            future = client.submit(run_task, task, motions[task.record], pure=False, retries=2,
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
                finish(failed_result(task, f"task failed after retries: {type(exc).__name__}: {exc}"), save=False)
            else:
                finish(result)
            future.release()  # results are not kept on the cluster
            submit_next()
    finally:
        for future in list(running.futures):  # interrupted: leave nothing running on a shared cluster
            future.cancel()


# -- results -------------------------------------------------------------------------------------

def assemble(study, motions, measures, factors, arrays):
    """The results Dataset of a study (see docs/studies.md for the schema)."""
    n_joints = study.n_joints
    ds = xr.Dataset({name: (DIMS + (("joint",) if name in JOINT_VARIABLES else ()), arrays[name])
                     for name in result_variables(n_joints)})
    cols = [c.column for c in study.columns]
    coords = {
        "column": ("column", [c.label for c in study.columns]),
        "record": ("record", [s.id for s in study.records]),
        "angle": ("angle", np.asarray(study.angles, dtype=np.float64)),
        "scale": ("scale", np.asarray(study.levels, dtype=np.float64)),
        "model": ("model", list(study.models)),
        "column_R": ("column", [c.R for c in cols]),
        "column_r": ("column", [c.r for c in cols]),
        "column_h": ("column", [c.h for c in cols]),
        "slenderness": ("column", [c.slenderness for c in cols]),
        "beta": ("column", [c.beta for c in cols]),
        "theta_crit": ("column", [c.critical_tilt for c in cols]),
        "earthquake": ("record", [str(m.metadata.get("event") or m.metadata.get("generator") or "unknown")
                                  for m in motions]),
        "station": ("record", [str(m.metadata.get("station") or "unknown") for m in motions]),
        "year": ("record", np.array([int(m.metadata.get("year") or -1) for m in motions], dtype=np.int32)),
        "magnitude": ("record", np.array([float(m.metadata.get("magnitude") or math.nan) for m in motions])),
        "record_sha256": ("record", [m.sha256() for m in motions]),
        "scale_factor": (("record", "scale"), factors),
        "pga": (("record", "scale"), factors * np.array([[m["pga"]] for m in measures])),
        "pgv": (("record", "scale"), factors * np.array([[m["pgv"]] for m in measures])),
    }
    if any(math.isfinite(c.latitude) for c in study.columns):
        coords["latitude"] = ("column", [c.latitude for c in study.columns])
        coords["longitude"] = ("column", [c.longitude for c in study.columns])
    if study.sa_period is not None:
        coords["sa"] = (("record", "scale"), factors * np.array([[m["sa"]] for m in measures]))
    if n_joints:
        diameters = np.full((len(cols), n_joints), np.nan)
        for ci, info in enumerate(study.columns):
            faces = info.stack.joint_diameters() if info.stack is not None else (2.0 * info.column.R,)
            diameters[ci, :len(faces)] = faces
        coords["joint"] = ("joint", np.arange(n_joints, dtype=np.int32))
        coords["joint_diameter"] = (("column", "joint"), diameters)
        coords["n_drums"] = ("column", np.array([1 if c.stack is None else c.stack.n_drums for c in study.columns],
                                                dtype=np.int32))
    ds = ds.assign_coords(coords)
    annotate(ds, STUDY_VARIABLES)
    if study.intensity is not None:
        units = {"pga": "m s-2", "pgv": "m s-1"}[study.intensity.measure]
        ds["scale"].attrs.update(units=units, long_name=f"target {study.intensity.measure} of the scaled record "
                                 "(peak of the horizontal vector); the factor is scale_factor",
                                 comment=f"the study file states the targets in {study.intensity.units}: "
                                 + ", ".join(f"{v:g}" for v in study.intensity.stated))
    if study.sa_period is not None:
        ds["sa"].attrs["period"] = study.sa_period
        ds["sa"].attrs["long_name"] += f" (period {study.sa_period:g} s)"
    ds["angle"].attrs["comment"] = "degrees counter-clockwise; 3D results do not depend on it (axisymmetry)"
    ds["model"].attrs["comment"] = "; ".join(
        [f"{m.name}: {m.in_short}" for m in REGISTRY.values()]
        + ["the rigid models run a column of drums as a monolith of its shaft"])
    ds.attrs.update({
        "title": study.title,
        "summary": study.summary or (
            f"Earthquake response of {len(cols)} free-standing column(s) modelled as rigid conical frustums "
            f"to {len(motions)} record(s), {len(study.angles)} incidence angle(s), {len(study.levels)} scale "
            f"level(s), model(s) {', '.join(study.models)}."),
        "source": f"frustum-pipeline {__version__} (pipeline.sweep)",
        "study_file": os.path.basename(study.path),
        "study_path": study.path,
        "study_sha256": study.digest,
        "model_options": json.dumps(dict(study.options), sort_keys=True),
        "vertical_component": "used" if study.vertical else "ignored",
        "energy_units": "energies and work per unit weight, E/(m g) [m]",
    })
    return ds
