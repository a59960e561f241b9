"""Running the compliant kernels: the fixed step and its stability limit, the integrators, the end of a run.

:func:`integrate` runs either integrator on an assembly's kernel parameters from a state, with
its statistics and history rows (:mod:`pipeline.dynamics.compliant.assembly`), and goes on past
the record and its tail until the outcome is decided (docs/model.md, "The end of a run").
"""

import math
from dataclasses import dataclass

import numpy as np

from pipeline.compliant.summary import joint_labels
from pipeline.compliant.tables import assemble, numerics
from pipeline.dynamics.compliant import adaptive
from pipeline.dynamics.compliant import assembly as sk
from pipeline.dynamics.compliant import linear_system
from pipeline.dynamics.compliant import semi_implicit as si
from pipeline.dynamics.compliant import statistics
from pipeline.dynamics.compliant.vector_lanes import compile_with_slp
from pipeline.dynamics.compliant.layout import (
    GROUND, J_DELTA, J_KN, J_LOWER, N_BODY_STATS, N_DIAG, N_HBODY, N_JOINT_STATS, N_SUMMARY, S_END_TIME,
    S_ENERGY_END, S_ENERGY_START, S_OVERTURN_TIME, S_STATUS, S_UNDECIDED, kept_size,
)
from pipeline.errors import InputError
from pipeline.units import G

__all__ = ["Raw", "fixed_step", "check_run", "integrate", "BOUNCE_STEP", "MAX_STEP_OVER_LIMIT"]

# The default step with the springs at the step's end is at most this fraction of 2 / omega_b, omega_b the
# bounce of the most lightly loaded base on its bed (sqrt(g / delta), delta its static sinking): backward
# Euler's own damping of that mode, about h omega_b / 2, is then at most 0.375 of critical. The bounce is the
# mode a rocking landing excites, and the restitution a column reaches depends on it: the paper's column as a
# monolith on 1e10 Pa/m, critically damped, lands with e = 0.960 at fine steps, 0.953 at 0.70 ms and 0.947 at
# its explicit limit 1.40 ms (undamped 0.989, 0.969, 0.957): the fraction binds on single bodies, whose
# stiffest mode is that bounce; a column of drums or a colonnade has stiffer modes, and its step is smaller.
BOUNCE_STEP = 0.375
# A given step with the springs at the step's end may be up to this many times the explicit springs' limit:
# stable at any step, the scheme damps the joint modes by h k more as the step grows, and its energy budget
# misses +0.12 to +0.17 of the work at 1.5 times the limit already (docs/model.md); step_safety's range ends here.
MAX_STEP_OVER_LIMIT = 2.0


@dataclass
class Raw:
    """Dimensionless arrays of one kernel run."""

    t_mon: np.ndarray
    stride: int
    hist_y: np.ndarray
    hist_diag: np.ndarray
    hist_body: np.ndarray
    summary: np.ndarray
    body_stats: np.ndarray
    joint_stats: np.ndarray
    joint_committed: np.ndarray
    y0: np.ndarray
    y_end: np.ndarray
    step: float = math.nan  # fixed step [s] (semi-implicit), NaN for the adaptive integrators


def fixed_step(asm, params, y, settings):
    """The semi-implicit integrator's step for a structure [s], and its stability limit [s].

    The limit is ``2 / omega_max`` of the stiffest joint mode in the state y
    (:func:`pipeline.dynamics.compliant.linear_system.stiffest_mode`), the bound of the springs
    taken at the step's start (numerics ``springs = "explicit"``); the step is ``settings.step``
    if given, else ``step_safety`` times the limit. With the springs at the step's end (the
    default) no step is unstable and the limit is the yardstick of the default step, which is
    also at most :data:`BOUNCE_STEP` of the bases' bounce period over pi; with them at
    its start a step at or above the limit is refused, naming the joint whose springs hold most
    of that mode's energy and their stiffness.

    Raises
    ------
    InputError
        Explicit springs and a given step at or above the stability limit, or ``step_safety`` >= 1;
        the springs at the step's end and a given step above :data:`MAX_STEP_OVER_LIMIT` times the
        limit; before anything is computed.
    """
    omega, shares = linear_system.stiffest_mode(params, y)
    limit = 2.0 / omega * asm.time
    choices = numerics(settings)
    step = float(settings.step) if settings.step is not None else choices["step_safety"] * limit
    if settings.step is None and choices["springs"] == "implicit":
        delta = float(asm.joints[asm.joints[:, J_LOWER] == GROUND, J_DELTA].min())
        step = min(step, BOUNCE_STEP * 2.0 * math.sqrt(delta) * asm.time)
    j = int(np.argmax(shares))  # the joint whose springs hold most of the stiffest mode's energy
    mode = f"2 / omega of its stiffest joint mode, {100 * shares[j]:.0f} % of it in {joint_labels(asm.layout)[j]}"
    if choices["springs"] == "implicit" and step > MAX_STEP_OVER_LIMIT * limit:
        raise InputError(
            f"step = {step:g} s is above twice the stability limit {limit:.3g} s of explicit springs for this "
            f"structure ({mode}): the springs at the step's end are stable there, but their own damping of the "
            f"joint modes grows with the step; give a step of at most {MAX_STEP_OVER_LIMIT * limit:.3g} s, or omit "
            "step for the default")
    if choices["springs"] == "explicit" and step >= limit:
        stiffness = asm.joints[j, J_KN] * asm.mass * G / asm.length ** 3
        option = "normal_stiffness" if asm.layout.contacts[j].kind == "base" else "joint_stiffness"
        given = (f"step = {settings.step:g} s" if settings.step is not None else
                 f"step_safety = {choices['step_safety']:g} ({step:.3g} s)")
        raise InputError(
            f"{given} is at or above the stability limit {limit:.3g} s of the semi-implicit integrator with "
            f"springs = explicit for this structure ({mode}, k_n = {stiffness:.3g} Pa/m, {option}): give a step "
            f"below {limit:.3g} s or step_safety below 1 (0.5 was this scheme's default), or springs = implicit")
    return step, limit


def check_run(structure, settings):
    """Refuse, before anything is computed, what a run of a structure with these settings would refuse,
    as its run would.

    The registry's check of the compliant model (``Model.checker``): ``frustum simulate`` calls it
    for every model before the first run, and a study for every column (monolith, drums, colonnade)
    each model runs, so that ``frustum study check`` refuses what ``frustum study run`` would fail
    cell by cell, with the words of ``frustum simulate``. The structure is always assembled (its
    layout and joints refuse a colonnade without capitals, a per-joint list that does not fit,
    :func:`pipeline.compliant.parts.per_joint`, and imperfections its beds cannot take: a tolerance too
    large for them, a bed leaning past its joint's friction angle); its fixed step is checked (:func:`fixed_step`) with a
    given step, or with the springs at the step's start and ``step_safety`` 1 or more. The joints'
    dashpots do not enter the limit (they are implicit in the fixed-step scheme).

    Raises
    ------
    pipeline.errors.InputError
        ``step = ... s is at or above the stability limit ... s ...`` (:func:`fixed_step`), or the
        layout's and joints' own refusals.
    """
    probe = assemble(structure, settings, 0.0)
    choices = numerics(settings)
    if settings.integrator != "semi-implicit" or (
            settings.step is None and (choices["springs"] == "implicit" or choices["step_safety"] < 1.0)):
        return
    from pipeline.compliant.rest import laid_state

    fixed_step(probe, probe.params(), laid_state(probe), settings)


def integrate(asm, params, y0, duration, monitor, stride, settings, histories, theta_commit=math.inf,
               step=None, progress=None, settle_limit=0.0):
    """Run the kernel for ``duration`` [s], sampling every ``monitor`` [s]; history every ``stride``.

    The integrator, its tolerances (adaptive) or step (fixed) come from ``settings``. The
    adaptive ones take their statistics at the samples; the fixed-step one at every step, its
    samples (history rows) interpolated between steps, so the grid never changes its steps.
    ``step`` [s] is the fixed step if already found (:func:`fixed_step`).
    ``progress(done, total)`` [s], if given, is called as the run goes on (the fixed-step
    integrator runs in pieces for it; the result is the same).

    If the column could still fall at ``duration`` (:func:`pipeline.dynamics.compliant.statistics.stands_for_good`),
    the run goes on (the ground still after the record) until it stands for good or falls, at
    most ``settle_limit`` [s] more (then ``S_UNDECIDED``); the histories end with the run.
    """
    n_bodies = asm.n_bodies
    dtau = monitor / asm.time
    k_decide = int(math.ceil(duration / monitor - 1e-9))  # the sample that ends the record and its tail
    m = int(math.ceil((duration + settle_limit) / monitor - 1e-9)) + 1
    t_mon = np.arange(m) * dtau
    n_hist = (m - 1) // stride + 1 if histories else 0
    raw = Raw(
        t_mon=t_mon, stride=stride,
        hist_y=np.full((n_hist, kept_size(n_bodies, asm.n_joints)), np.nan),
        hist_diag=np.full((n_hist, N_DIAG), np.nan),
        hist_body=np.full((n_hist, n_bodies, N_HBODY), np.nan),
        summary=np.zeros(N_SUMMARY), body_stats=np.zeros((n_bodies, N_BODY_STATS)),
        joint_stats=np.zeros((asm.n_joints, N_JOINT_STATS)),
        joint_committed=np.zeros((asm.n_joints, N_JOINT_STATS)),
        y0=y0, y_end=np.zeros_like(y0))
    if settings.integrator == "semi-implicit":
        if step is None:
            step = fixed_step(asm, params, y0, settings)[0]
        raw.step = step
        y = y0.copy()
        scratch = si.make_scratch(params, asm.pattern)
        between = np.empty((2, y0.shape[0]))
        # pieces of about a second of motion (a progress line; the same result as one piece), and
        # after the record and its tail, pieces of the same length between checks of the outcome
        second = max(1, int(round(1.0 / monitor)))
        piece = second if progress is not None else m
        peaked = np.zeros(len(asm.layout.watched), dtype=bool)  # _stands_for_good's memory
        decided = False
        h = step / asm.time
        arrays = (raw.hist_y, raw.hist_diag, raw.hist_body, raw.summary, raw.body_stats, raw.joint_stats,
                  raw.joint_committed, y0, between, scratch)
        compile_with_slp(si.run, (params, y, t_mon, 0, m, h, stride, theta_commit) + arrays)
        k = 0
        while k < m:
            stop = min(k_decide + 1, max(k, 1) + piece) if k <= k_decide else min(m, k + second)
            k = si.run(params, y, t_mon, k, stop, h, stride, theta_commit, *arrays)
            if progress is not None and k <= k_decide + 1:  # the record and its tail (after them: deciding)
                progress(min(k - 1, k_decide) * monitor, k_decide * monitor)
            if k > k_decide and _stands_for_good(asm, params, y, raw, peaked):
                decided = True
                break
        if math.isnan(raw.summary[S_OVERTURN_TIME]) and not decided and \
                not _stands_for_good(asm, params, y, raw, peaked):
            raw.summary[S_UNDECIDED] = 1.0
        raw.summary[S_ENERGY_END] = sk.energy(y, params)
        raw.y_end[:] = y
        return _trimmed(raw, k_decide)
    record, dt = params[4], params[5]
    breaks = np.arange(record.shape[0]) * dt  # kinks of the linearly interpolated record
    atol = np.full(y0.shape[0], settings.atol)
    adaptive.run(params, y0, t_mon, stride, breaks, settings.rtol, atol, np.inf,
           np.ones(2 * n_bodies), theta_commit, raw.hist_y, raw.hist_diag, raw.hist_body, raw.summary,
           raw.body_stats, raw.joint_stats, raw.joint_committed, raw.y_end, k_decide, asm.barrier, asm.critical,
           adaptive.METHODS[settings.integrator])
    if raw.summary[S_STATUS] < 0:
        raise RuntimeError(
            f"integration failed at t = {raw.summary[S_END_TIME] * asm.time:.6g} s "
            f"(status {raw.summary[S_STATUS]:.0f}); try other tolerances or joint parameters")
    return _trimmed(raw, k_decide)


def _stands_for_good(asm, params, y, raw, peaked):
    return statistics.stands_for_good(y, params, raw.summary[S_ENERGY_START], asm.barrier, asm.critical, peaked)


def _trimmed(raw, k_decide):
    """The run's samples and history rows up to its end (a column down has them all), at least up
    to the record and its tail (sample ``k_decide``)."""
    end = max(raw.t_mon[k_decide], raw.summary[S_END_TIME])
    last = int(np.searchsorted(raw.t_mon, end * (1.0 + 1e-12), side="right")) - 1
    raw.t_mon = raw.t_mon[:last + 1]
    rows = last // raw.stride + 1
    raw.hist_y, raw.hist_diag, raw.hist_body = raw.hist_y[:rows], raw.hist_diag[:rows], raw.hist_body[:rows]
    return raw


