"""Planning a study: its grid cut into tasks, the factors on each record, the memory it needs.

The grid is columns x records x angles x scales x models (x seeds, with ``[imperfections]``). One
task runs one record on a block of columns for every angle, scale, model and seed, so that a task
lasts long enough (about a second) for Dask's per-task cost (a few ms) to stay far below 5 %. An
angle-invariant model runs once per (column, record, scale) and is broadcast over the angles, a
model that does not draw imperfections once and broadcast over the seeds (:mod:`pipeline.study.run`).
"""

import math
from dataclasses import dataclass

import numpy as np

from pipeline.errors import InputError
from pipeline.limits import check_fits, results_bytes
from pipeline.models import REGISTRY
from pipeline.study.results import COMPLIANT_VARIABLES, DTYPES, JOINT_VARIABLES

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
    columns : tuple of pipeline.structures.column.Column
    angles : tuple of float
        Incidence angles [degree].
    factors : tuple of float
        Factors on the record, one per scale level [1].
    settings : tuple of pipeline.settings.ModelSettings
        One per model.
    vertical : bool
    stacks : tuple
        Per column, its drums (:class:`pipeline.structures.drums.DrumColumn`) for the compliant model,
        or None (the monolith); empty: every column a monolith.
    n_joints : int
        Length of the ``joint`` dimension of the results (0: no compliant model).
    drums : tuple of bool
        Per model, whether it runs a column's drums (empty: each model as its registry entry says).
    beds : tuple
        Per column, ``(c_n [Pa s/m], restitution [1])`` of the calibrated bed every model gets,
        or empty (no calibration).
    colonnades : tuple
        Per column, its colonnade (:class:`pipeline.structures.colonnade.Colonnade`), which the
        models of colonnades run, or None; empty: no column carries one.
    seeds : tuple of int
        The study's seeds of imperfect drums (the last dimension of the task's arrays), or empty.
    seeded : tuple of bool
        Per model, whether it draws its drums from each seed (else it runs once, repeated along them).
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
    drums: tuple = ()
    beds: tuple = ()
    colonnades: tuple = ()
    seeds: tuple = ()
    seeded: tuple = ()

    @property
    def shape(self):
        """Shape of the task's result arrays: (columns, angles, scales, models[, seeds])."""
        return (len(self.columns), len(self.angles), len(self.factors), len(self.settings)) + \
            ((len(self.seeds),) if self.seeds else ())

    @property
    def n_simulations(self):
        """Simulations actually run (an angle-invariant model once over all angles, a model without
        imperfections once over all seeds)."""
        per = sum((1 if REGISTRY[s.model].angle_invariant else len(self.angles))
                  * (len(self.seeds) if self.seeded and self.seeded[m] else 1) for m, s in enumerate(self.settings))
        return len(self.columns) * len(self.factors) * per


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
        scalars = sum(np.dtype(DTYPES[n]).itemsize for n in COMPLIANT_VARIABLES)
        extra = 2 * (scalars + len(JOINT_VARIABLES) * 8 * study.n_joints)
    return results_bytes(study.n_simulations, n_tasks(study), extra)


def check_memory(study):
    """Refuse, before anything is loaded or computed, a study whose grid cannot fit in memory."""
    nc, nr, na, ns, nm = study.shape
    seeds = f" x {len(study.seeds):,} seeds" if study.seeds else ""
    check_fits(memory_estimate(study),
               f"{study.path}: the results grid of {study.n_simulations:,} cells ({nc:,} columns x {nr:,} records x "
               f"{na:,} angles x {ns:,} scales x {nm} models{seeds}, {n_tasks(study):,} tasks)",
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
    per_column = len(study.levels) * sum((1 if REGISTRY[study.variant(m).model].angle_invariant else len(study.angles))
                                         * (len(study.seeds) if study.seeded(m) else 1) for m in study.models)
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
    drums = tuple(study.variant(m).drums for m in study.models) if study.variants else ()
    bed = study.beds()
    columns = [c.column for c in study.columns]
    stacks = [c.stack for c in study.columns]
    rows = [c.colonnade for c in study.columns] if any(c.colonnade for c in study.columns) else []
    seeded = tuple(study.seeded(m) for m in study.models) if study.seeds else ()
    tasks = []
    for ri in range(len(study.records)):
        for start in range(0, len(columns), size):
            stop = min(start + size, len(columns))
            tasks.append(Task(len(tasks), ri, start, stop, tuple(columns[start:stop]), angles,
                              tuple(float(f) for f in factors[ri]), settings, study.vertical,
                              tuple(stacks[start:stop]), study.n_joints, drums, tuple(bed[start:stop]),
                              tuple(rows[start:stop]), study.seeds, seeded))
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
