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
from pipeline.dynamics.compliant.layout import (
    J_KN, N_BODY_STATS, N_DIAG, N_HBODY, N_JOINT_STATS, N_SUMMARY, S_END_TIME, S_ENERGY_END, S_ENERGY_START,
    S_OVERTURN_TIME, S_STATUS, S_UNDECIDED, kept_size,
)
from pipeline.errors import InputError
from pipeline.units import G

__all__ = ["Raw", "fixed_step", "check_fixed_step", "integrate"]


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
    (:func:`pipeline.dynamics.compliant.linear_system.stiffest_mode`); the step is
    ``settings.step`` if given (refused if above the limit, naming the joint whose springs hold
    most of that mode's energy and their stiffness), else ``step_safety`` times the limit.

    Raises
    ------
    InputError
        A given step above the stability limit, before anything is computed.
    """
    omega, shares = linear_system.stiffest_mode(params, y)
    limit = 2.0 / omega * asm.time
    if settings.step is not None:
        if settings.step > limit:
            j = int(np.argmax(shares))
            contact = asm.layout.contacts[j]
            stiffness = asm.joints[j, J_KN] * asm.mass * G / asm.length ** 3
            option = "normal_stiffness" if contact.kind == "base" else "joint_stiffness"
            raise InputError(
                f"step = {settings.step:g} s is above the stability limit {limit:.3g} s of the semi-implicit "
                f"integrator for this structure (2 / omega of its stiffest joint mode, "
                f"{100 * shares[j]:.0f} % of it in {joint_labels(asm.layout)[j]}, k_n = {stiffness:.3g} Pa/m, "
                f"{option}): give a step of at most {limit:.3g} s, or omit step for "
                f"{numerics(settings)['step_safety']:g} of the limit")
        return float(settings.step), limit
    return numerics(settings)["step_safety"] * limit, limit


def check_fixed_step(structure, settings):
    """Refuse a given fixed step above the stability limit of a structure, as its run would.

    The registry's check of the compliant model (``Model.checker``): a study calls it for every
    column (monolith, drums, colonnade) a model runs, so that a step its runs would refuse is
    refused by ``frustum study check`` and before ``frustum study run`` computes, with the words
    of ``frustum simulate``. Nothing is checked (nor assembled) without a given step, or with an
    adaptive integrator: the default step is a fraction ``step_safety`` < 1 of the limit. The
    joints' dashpots do not enter the limit (they are implicit in the fixed-step scheme).

    Raises
    ------
    pipeline.errors.InputError
        ``step = ... s is above the stability limit ... s ...`` (:func:`fixed_step`).
    """
    if settings.step is None or settings.integrator != "semi-implicit":
        return
    from pipeline.compliant.rest import laid_state

    probe = assemble(structure, settings, 0.0)
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

    If the column could still fall at ``duration`` (:func:`pipeline.dynamics.compliant.stack.stands_for_good`),
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
        k = 0
        while k < m:
            stop = min(k_decide + 1, max(k, 1) + piece) if k <= k_decide else min(m, k + second)
            k = si.run(params, y, t_mon, k, stop, step / asm.time, stride, theta_commit,
                       raw.hist_y, raw.hist_diag, raw.hist_body, raw.summary, raw.body_stats, raw.joint_stats,
                       raw.joint_committed, y0, between, scratch)
            if progress is not None and k <= k_decide + 1:  # the record and its tail (after them: deciding)
                progress(min(k - 1, k_decide) * monitor, k_decide * monitor)
            if k > k_decide and _stands_for_good(asm, params, y, raw):
                break
        if math.isnan(raw.summary[S_OVERTURN_TIME]) and not _stands_for_good(asm, params, y, raw):
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


def _stands_for_good(asm, params, y, raw):
    return statistics.stands_for_good(y, params, raw.summary[S_ENERGY_START], asm.barrier, asm.critical)


def _trimmed(raw, k_decide):
    """The run's samples and history rows up to its end (a column down has them all), at least up
    to the record and its tail (sample ``k_decide``)."""
    end = max(raw.t_mon[k_decide], raw.summary[S_END_TIME])
    last = int(np.searchsorted(raw.t_mon, end * (1.0 + 1e-12), side="right")) - 1
    raw.t_mon = raw.t_mon[:last + 1]
    rows = last // raw.stride + 1
    raw.hist_y, raw.hist_diag, raw.hist_body = raw.hist_y[:rows], raw.hist_diag[:rows], raw.hist_body[:rows]
    return raw


