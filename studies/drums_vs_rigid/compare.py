"""The rigid rolling model against the compliant monolith and the drum stack (issue 13).

Two columns: the paper's (R = 0.5, r = 0.4, h = 4 m) and the Parthenon peristyle
column of ``pipeline/data/columns.toml`` (shaft R = 0.9525, r = 0.74, h = 9.57 m, 11
drums and a capital). Three models of each:

* ``rigid``: the rolling frustum of the paper (``model="3d"``) on the shaft's outline;
* ``monolith``: the compliant-contact model (``model="3d-compliant"``) on the same
  outline as one body (``--drums 1``; no capital);
* ``stack``: the compliant-contact model on the drums (the paper's column cut into 4
  equal drums; the Parthenon column's 11 drums and its capital), joint friction the
  default (the base's).

All three on the same bed, as in ``studies/rigid_vs_compliant``: normal stiffness
k_n = 1e10 Pa/m, friction 0.7, the compliant model's normal dashpots calibrated on the
shaft's outline (:func:`pipeline.compliant.calibrated_damping`) and the planar
restitution they reach given to the rigid model too, so that a difference between the
models is the model's, not the bed's. Records: the 22 FEMA P695 far-field pairs, both
horizontal components, angle 0, no vertical, each pair scaled so that its peak
horizontal resultant equals the stripe's PGA. For each column and model the lognormal
overturning fragility is fitted by maximum likelihood
(:func:`pipeline.fragility.fit_lognormal`), with a 90 % band of its median from 1000
resamples of the records with replacement.

Every run is kept as one JSON file under ``out/drums_vs_rigid/`` (written atomically),
named by column, model, record, stripe and a digest of the study's settings: a rerun
resumes where the last one stopped, and ``--dry-run`` prices what is left from the costs
measured so far.

Run:  python studies/drums_vs_rigid/compare.py [--workers 2] > studies/drums_vs_rigid/results.md
"""

import argparse
import hashlib
import heapq
import json
import math
import os
import platform
import sys
import time
import zlib
from concurrent.futures import ProcessPoolExecutor, as_completed
from functools import lru_cache

import numpy as np

from pipeline.atomic import atomic_path
from pipeline.compliant import calibrated_damping
from pipeline.drums import DrumColumn, named_drum_column
from pipeline.fragility import fit_lognormal
from pipeline.geometry import Column
from pipeline.models.compliant import COMPLIANT_DRUMS
from pipeline.settings import Excitation, ModelSettings
from pipeline.simulate import simulate
from pipeline.units import G

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(REPO, "out", "drums_vs_rigid")

COLUMN_KEYS = ("paper", "parthenon")
MODELS = ("rigid", "monolith", "stack")
# The stack again with the band past a bed joint's edge halved and doubled (edge_band, in
# spacings of the outer rings of contact points; the stack's own is
# pipeline.compliant.NUMERICS["edge_band"] = 0.5): a numerical choice, not measured physics,
# so the report shows what it moves. Run on demand (--models), not by default.
BAND_DEFAULT = COMPLIANT_DRUMS.numerics["edge_band"]
BAND_VARIANTS = {"stack-narrow": 0.5 * BAND_DEFAULT, "stack-wide": 2.0 * BAND_DEFAULT}
# The stack again with another integrator (issue 25): the semi-implicit default at half its
# step (step_safety halved), and the adaptive DOPRI5 reference it replaced; on demand too.
INTEGRATOR_VARIANTS = {"stack-half-step": {"step_factor": 0.5}, "stack-dopri5": {"integrator": "dopri5"}}
VARIANTS = (*BAND_VARIANTS, *INTEGRATOR_VARIANTS)
ALL_MODELS = MODELS + VARIANTS
RECORDS = tuple(f"FEMA-FF-{i:02d}" for i in range(1, 23))
STRIPES = (0.2, 0.4, 0.6, 0.8, 1.0, 1.5)  # PGA [g]
STIFFNESS = 1e10  # normal stiffness of base and joints, k_n [Pa/m]
FRICTION = 0.7  # base friction [1]; the joints default to it
ANGLE = 0.0  # incidence angle [deg]
VERTICAL = False
TAIL = ModelSettings().tail  # free motion after the record [s]
N_BOOT = 1000
SEED = 2026
# A lognormal median from fewer stripes than this is not fitted: two parameters from one or two
# intensity levels say more about the stripes chosen than about the column.
MIN_STRIPES = 3
MACHINE = "2-core x86_64 sandbox, shared with other jobs"

# Cost per second of simulated time [s/s] when nothing is cached (dry runs only): measured
# once on FEMA-FF-01 at 0.3 g (no overturning, the full record and tail) in one process on
# the shared 2-core sandbox: 0.1 s, 0.7 s and 43 s per run for the paper's column, 0.08 s,
# 0.6 s and 326 s for the Parthenon column.
PRIOR_RATE = {("paper", "rigid"): 0.0029, ("paper", "monolith"): 0.0212, ("paper", "stack"): 1.226,
              ("parthenon", "rigid"): 0.0021, ("parthenon", "monolith"): 0.0177, ("parthenon", "stack"): 9.31}
# A stack's cost grows faster than its number of bodies (12 bodies cost 7.6x 4 bodies above):
# another column's measured rate is scaled by (bodies ratio)^BODY_EXPONENT.
BODY_EXPONENT = 1.85

# What the cached rows depend on: changing any of it starts a new cache (a new digest).
# version: bumped when the models change under the same settings (2: the joint law's energy
# booking and the rigid slip layer of 2026-11-23; rows of version 1 are not comparable; 3: the
# semi-implicit integrator of the compliant models and the bed calibrated with it, 2026-11-25;
# 4: its statistics at every step, its step exactly step_safety x the stability limit, the
# samples interpolated between steps (the bed calibrated at that step), 2026-11-25).
DESIGN = dict(version=4, integrator="semi-implicit", stiffness=STIFFNESS, friction=FRICTION, joint_friction=None, angle=ANGLE,
              vertical=VERTICAL, tail=TAIL, calibration="rigid_vs_compliant: calibrated_damping on the outline")


def drum_column(key):
    """The multi-drum column of a column key.

    Parameters
    ----------
    key : {"paper", "parthenon"}

    Returns
    -------
    pipeline.drums.DrumColumn
        Its ``.column`` is the shaft's outline (R, r, h [m]).
    """
    if key == "paper":
        return DrumColumn.equal(Column(0.5, 0.4, 4.0, name="paper"), 4, name="paper")
    if key == "parthenon":
        return named_drum_column("parthenon-peristyle")
    raise ValueError(f"unknown column {key!r}; choose from {', '.join(COLUMN_KEYS)}")


def is_stack(model):
    """Whether a model simulates the drums (the stack or one of its band variants)."""
    return model == "stack" or model in VARIANTS


def body(key, model):
    """What each model simulates: the shaft (rigid), the shaft as one body (monolith), the drums (stack)."""
    stack = drum_column(key)
    if model == "rigid":
        return stack.column
    if model == "monolith":
        return DrumColumn.equal(stack.column, 1, name=stack.name)
    if is_stack(model):
        return stack
    raise ValueError(f"unknown model {model!r}; choose from {', '.join(ALL_MODELS)}")


def n_bodies(key, model):
    """Number of rigid bodies of a model of a column [1]."""
    return drum_column(key).n_bodies if is_stack(model) else 1


def label(key):
    """A human name of a column."""
    stack = drum_column(key)
    c = stack.column
    drums = f"{stack.n_drums} drums" + (" and a capital" if stack.capital is not None else "")
    name = "paper's column" if key == "paper" else "Parthenon peristyle column"
    return f"{name} (R {c.R:g}, r {c.r:g}, h {c.h:g} m; stack: {drums})"


def bed(key):
    """The shared bed of a column: compliant dashpots and the restitution they reach.

    Returns
    -------
    tuple of float
        ``(c_n [Pa s/m], restitution [1])`` from :func:`pipeline.compliant.calibrated_damping`
        on the shaft's outline (target: the rigid model's own restitution).
    """
    base = ModelSettings(model="3d-compliant", normal_stiffness=STIFFNESS, friction=FRICTION)
    damping, reached = calibrated_damping(drum_column(key).column, base)
    return float(damping), float(reached)


@lru_cache(maxsize=None)
def default_step(key):
    """The semi-implicit integrator's default step for a column's stack [s] (what the stack runs)."""
    from pipeline.compliant import assemble, fixed_step, rest_state

    base = ModelSettings(model="3d-compliant", normal_stiffness=STIFFNESS, friction=FRICTION)
    asm = assemble(drum_column(key), base, 0.0)
    params = asm.params()
    return fixed_step(asm, params, rest_state(params, base), base)[0]


def settings(model, damping, restitution, key=None):
    """Model settings on the shared bed.

    Parameters
    ----------
    model : {"rigid", "monolith", "stack"}
    damping : float
        Normal dashpots per unit area c_n [Pa s/m].
    restitution : float
        Planar restitution [1] (the rigid model's impact law; recorded for the compliant one).
    key : str, optional
        The column (the half-step variant's step is a fraction of its stack's default).
    """
    name = "3d" if model == "rigid" else "3d-compliant"
    numerics = (("edge_band", BAND_VARIANTS[model]),) if model in BAND_VARIANTS else ()
    variant = dict(INTEGRATOR_VARIANTS.get(model, {}))
    if "step_factor" in variant:  # a fraction of the stack's own default step, exactly
        variant = {"step": variant.pop("step_factor") * default_step(key)}
    return ModelSettings(model=name, normal_stiffness=STIFFNESS, friction=FRICTION, restitution=restitution,
                         contact_damping=damping, tail=TAIL, numerics=numerics, **variant)


# Changes of the bed-joint law, which only the stack has (rigid and monolith rows stay valid):
# 2: the band past a face's edge runs off as a smoothstep (2026-11-23), not linearly.
STACK_REVISION = 2
# 3: the compliant models run the fixed-step semi-implicit integrator by default and the shared
# bed is calibrated with it (issue 25, 2026-11-25): every model's rows are new (DESIGN version).


def digest(model=None):
    """Short digest of :data:`DESIGN` and the columns' geometry (names the cache files).

    A stack's rows also depend on :data:`STACK_REVISION`, a band variant's on its band too.
    """
    design = {**DESIGN, "columns": {k: repr(drum_column(k)) for k in COLUMN_KEYS}}
    if is_stack(model) and STACK_REVISION > 1:
        design["stack_revision"] = STACK_REVISION
    if model in BAND_VARIANTS:
        design["edge_band"] = BAND_VARIANTS[model]
    if model in INTEGRATOR_VARIANTS:
        design["variant"] = INTEGRATOR_VARIANTS[model]
    text = json.dumps(design, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:8]


def cache_path(out, job):
    """The JSON file of one job ``(column, model, record, stripe [g])``."""
    key, model, record, stripe = job
    return os.path.join(out, f"{key}-{model}-{record}-{stripe:.6g}g-{digest(model)}.json")


@lru_cache(maxsize=None)
def load_record(record):
    """A record of the catalog (:func:`pipeline.groundmotion.load`), once per process."""
    from pipeline.groundmotion import load

    return load(record)


def record_info(record):
    """``(peak horizontal resultant [m/s^2], duration [s])`` of a record."""
    m = load_record(record)
    return float(np.max(np.hypot(m.acc_x, m.acc_y))), float(m.duration)


def run(task):
    """One run, or its cached row.

    Parameters
    ----------
    task : tuple
        ``(out, job, damping, restitution)``: the cache folder, the job
        ``(column, model, record, stripe [g])``, the bed's c_n [Pa s/m] and restitution [1].

    Returns
    -------
    dict
        The row (see :func:`make_row`), also written to the job's JSON file.
    """
    out, job, damping, restitution = task
    path = cache_path(out, job)
    if os.path.exists(path):
        with open(path, encoding="utf-8") as fh:
            return json.load(fh)
    key, model, record, stripe = job
    pga, duration = record_info(record)
    scale = stripe * G / pga
    t = time.perf_counter()
    summary = simulate(body(key, model), load_record(record), Excitation(angle=ANGLE, scale=scale, vertical=VERTICAL),
                       settings(model, damping, restitution, key), histories=False).summary
    wall = time.perf_counter() - t
    row = make_row(job, summary, wall, scale, duration)
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8") as fh:
        json.dump(row, fh)
    return row


def make_row(job, summary, wall, scale, duration):
    """What is kept of one run.

    Parameters
    ----------
    job : tuple
        ``(column, model, record, stripe [g])``.
    summary : dict
        ``simulate(...).summary``.
    wall : float
        Wall time of the run [s].
    scale : float
        Factor on the record [1].
    duration : float
        Length of the record [s].

    Returns
    -------
    dict
        ``overturned``, ``collapsed`` (a body fell off the one below), ``peak_theta`` [rad],
        ``residual_displacement`` [m]; for compliant models ``overturn_drum`` (first body to
        lie down, 0 the bottom drum, -1 none), ``joint_slip`` and ``joint_diameter`` [m] (base
        first), ``dislocation_ratio`` [1]; ``wall`` [s], ``simulated`` (record + tail [s]).
    """
    key, model, record, stripe = job

    def listed(name):
        value = summary.get(name)
        return None if value is None else [float(v) for v in np.atleast_1d(value)]

    overturn_drum = summary.get("overturn_drum")
    return {
        "column": key, "model": model, "record": record, "stripe": float(stripe), "scale": float(scale),
        "n_bodies": n_bodies(key, model),
        "overturned": bool(summary["overturned"]),
        "collapsed": bool(summary.get("collapsed", False)),
        "peak_theta": float(summary["peak_theta"]),
        "residual_displacement": float(summary["residual_displacement"]),
        "overturn_drum": None if overturn_drum is None else int(overturn_drum),
        "joint_slip": listed("joint_slip"),
        "joint_diameter": listed("joint_diameter"),
        "dislocation_ratio": None if "dislocation_ratio" not in summary else float(summary["dislocation_ratio"]),
        "wall": float(wall),
        "simulated": float(duration + TAIL),
    }


# -- cost ---------------------------------------------------------------------------------------

def all_cached(out):
    """Every row of this design's digests in the cache folder (any record or stripe)."""
    rows, tags = [], {m: (f"-{m}-", f"-{digest(m)}.json") for m in ALL_MODELS}
    if os.path.isdir(out):
        for name in sorted(os.listdir(out)):
            if not name.startswith(".") and any(t in name and name.endswith(d) for t, d in tags.values()):
                with open(os.path.join(out, name), encoding="utf-8") as fh:
                    rows.append(json.load(fh))
    return rows


def rates(rows):
    """Measured cost per simulated second [s/s] of each (column, model), from cached rows."""
    acc = {}
    for r in rows:
        w, s = acc.get((r["column"], r["model"]), (0.0, 0.0))
        acc[(r["column"], r["model"])] = (w + r["wall"], s + r["simulated"])
    return {k: w / s for k, (w, s) in acc.items() if s > 0}


def rate_for(key, model, measured):
    """Cost per simulated second [s/s] of a (column, model) and where it comes from.

    Measured if cached runs exist; else the stack's for a band variant; else
    :data:`PRIOR_RATE` (one measured run); else the same model of another column, scaled by
    the bodies ratio to :data:`BODY_EXPONENT`.
    """
    if (key, model) in measured:
        return measured[(key, model)], "measured"
    if model in VARIANTS:
        rate, src = rate_for(key, "stack", measured)
        return rate, f"the stack's ({src})"
    if (key, model) in PRIOR_RATE:
        return PRIOR_RATE[(key, model)], "prior (one run)"
    for (k, m), rate in measured.items():
        if m == model:
            return rate * (n_bodies(key, model) / n_bodies(k, m)) ** BODY_EXPONENT, f"scaled from {k}"
    raise ValueError(f"no cost known for {key} {model}")


def makespan(costs, workers):
    """Wall time [s] of jobs of the given costs [s] on ``workers`` processes, longest first."""
    loads = [0.0] * max(1, workers)
    for c in sorted(costs, reverse=True):
        heapq.heapreplace(loads, loads[0] + c)
    return max(loads)


# -- analysis -----------------------------------------------------------------------------------

def fit_median(outcomes, records):
    """Lognormal median [g] and its fit from ``outcomes[record] = [(stripe [g], overturned), ...]``.

    ``records`` may repeat (a bootstrap resample); records without runs are skipped.
    """
    im, k = [], []
    for rec in records:
        for stripe, over in outcomes.get(rec, ()):
            im.append(stripe)
            k.append(1 if over else 0)
    if not im:
        return math.nan, None
    im = np.round(np.array(im, dtype=float), 6)
    k = np.array(k)
    levels = np.unique(im)
    n = np.array([np.sum(im == x) for x in levels])
    kk = np.array([np.sum(k[im == x]) for x in levels])
    fit = fit_lognormal(levels, n, kk)
    return float(fit.median), fit


def medians(rows, n_boot=N_BOOT, seed=SEED):
    """Per (column, model): median [g], 90 % band [g] from record resamples, beta, counts.

    Returns
    -------
    dict
        ``{(column, model): {"median", "lo", "hi", "beta", "status", "runs", "overturned"}}``.
    """
    groups = {}
    for r in rows:
        groups.setdefault((r["column"], r["model"]), {}).setdefault(r["record"], []).append(
            (r["stripe"], r["overturned"]))
    out = {}
    for key, outcomes in sorted(groups.items()):
        # one stream per (column, model), so that a model's band does not depend on which
        # other models the report holds (a shared stream gave the Parthenon column other bands
        # alone than after the paper's)
        rng = np.random.default_rng([seed, zlib.crc32("/".join(key).encode())])
        records = sorted(outcomes)
        levels = {round(s, 6) for v in outcomes.values() for s, _o in v}
        if len(levels) < MIN_STRIPES:
            out[key] = {"median": math.nan, "lo": math.nan, "hi": math.nan, "beta": math.nan,
                        "status": f"not fitted ({len(levels)} stripe{'s' if len(levels) != 1 else ''})",
                        "runs": sum(len(v) for v in outcomes.values()),
                        "overturned": sum(o for v in outcomes.values() for _s, o in v)}
            continue
        med, fit = fit_median(outcomes, records)
        boot = np.array([fit_median(outcomes, list(rng.choice(records, size=len(records))))[0]
                         for _ in range(n_boot)], dtype=float)
        boot = boot[~np.isnan(boot)]
        # no interpolation between order statistics: a resample with no overturning has an infinite median
        lo, hi = np.quantile(boot, [0.05, 0.95], method="inverted_cdf") if boot.size else (math.nan, math.nan)
        out[key] = {"median": med, "lo": float(lo), "hi": float(hi),
                    "beta": math.nan if fit is None else float(fit.beta),
                    "status": "no data" if fit is None else _STATUS_TEXT.get(fit.status, str(fit.status)),
                    "runs": sum(len(v) for v in outcomes.values()),
                    "overturned": sum(o for v in outcomes.values() for _s, o in v)}
    return out


def common_cells(rows):
    """Rows of the columns whose models ran different cells, cut to the cells every model ran.

    A model run on fewer records or stripes (the Parthenon stack) and fitted on them is not
    compared like for like with models fitted on the full design; fitted on the cells all
    of :data:`MODELS` share, the medians are. The band variants are left out (they are
    compared with the stack cell by cell).

    Returns
    -------
    list of dict
        The rows of those columns' :data:`MODELS` on the shared record x stripe cells; empty
        where every model of every column ran the same cells.
    """
    cells = {}
    for r in rows:
        if r["model"] in MODELS:
            cells.setdefault(r["column"], {}).setdefault(r["model"], set()).add((r["record"], r["stripe"]))
    shared = {key: set.intersection(*per.values()) for key, per in cells.items()
              if len(per) > 1 and len({frozenset(c) for c in per.values()}) > 1}
    return [r for r in rows if r["column"] in shared and r["model"] in MODELS
            and (r["record"], r["stripe"]) in shared[r["column"]]]


def _status_text():
    from pipeline import fragility as fr

    names = {"FIT_OK": "ok", "FIT_NO_EXCEEDANCE": "none overturned", "FIT_ALL_EXCEED": "all overturned",
             "FIT_SEPARATED": "separated (beta 0)", "FIT_DECREASING": "decreasing", "FIT_NO_DATA": "no data"}
    return {getattr(fr, n): t for n, t in names.items() if hasattr(fr, n)}


_STATUS_TEXT = _status_text()


def model_pairs(present):
    """The pairs of models compared: every pair of :data:`MODELS`, and the stack with each band variant.

    Parameters
    ----------
    present : iterable of str
        Models that have rows.

    Returns
    -------
    list of tuple
        ``(a, b)`` in :data:`ALL_MODELS` order.
    """
    present = set(present)
    have = [m for m in ALL_MODELS if m in present]
    main = [m for m in have if m in MODELS]
    pairs = [(a, b) for i, a in enumerate(main) for b in main[i + 1:]]
    return pairs + [("stack", v) for v in have if v in VARIANTS and "stack" in have]


def _paired_cells(rows, field, keep=None):
    """Per column and pair of models (:func:`model_pairs`): a row field on the cells both ran.

    Parameters
    ----------
    rows : list of dict
    field : str
        The row's value compared (``"overturned"``, ``"peak_theta"``, ...).
    keep : callable, optional
        Only rows for which ``keep(row)`` is true count.

    Returns
    -------
    dict
        ``{(column, a, b): [(value of a, value of b), ...]}`` over the record x stripe cells
        that both models have, in cell order (empty if none).
    """
    cells = {}
    for r in rows:
        if keep is None or keep(r):
            cells.setdefault((r["column"], r["model"]), {})[(r["record"], r["stripe"])] = r[field]
    out = {}
    for key in dict.fromkeys(c for c, _m in cells):
        for a, b in model_pairs(m for k, m in cells if k == key):
            ca, cb = cells[(key, a)], cells[(key, b)]
            out[(key, a, b)] = [(ca[c], cb[c]) for c in sorted(set(ca) & set(cb))]
    return out


def agreement(rows):
    """Per column and pair of models: cells (record x stripe) run by both and how they compare.

    Returns
    -------
    dict
        ``{(column, a, b): {"cells", "same", "a_only", "b_only"}}``: ``a_only`` the cells where
        model ``a`` overturned and ``b`` did not.
    """
    return {pair: {"cells": len(both),
                   "same": sum(a == b for a, b in both),
                   "a_only": sum(a and not b for a, b in both),
                   "b_only": sum(b and not a for a, b in both)}
            for pair, both in _paired_cells(rows, "overturned").items()}


def tilt_ratios(rows):
    """Per column and pair of models: peak tilt of B over A on the cells where both stood.

    The rigid and monolith peak tilt is the shaft's, the stack's the top body's (the drum or
    capital highest up), all about the vertical.

    Returns
    -------
    dict
        ``{(column, a, b): {"cells", "median", "p10", "p90"}}`` [1]; ``cells`` counts the
        record x stripe cells where neither model overturned.
    """
    out = {}
    for pair, both in _paired_cells(rows, "peak_theta", keep=lambda r: not r["overturned"]).items():
        ratio = np.array([b / a for a, b in both if a > 0], dtype=float)
        if ratio.size:
            p10, med, p90 = np.percentile(ratio, [10, 50, 90])
            out[pair] = {"cells": int(ratio.size), "median": float(med), "p10": float(p10), "p90": float(p90)}
    return out


def largest_bed_slip(row):
    """Largest residual slip of a bed joint (the base left out) [m]; 0 for a monolith, None for rigid."""
    slip = row.get("joint_slip")
    if slip is None:
        return None
    return max(slip[1:]) if len(slip) > 1 else 0.0


def stack_stats(rows):
    """Per column and stripe of the stack runs: residual bed-joint slip and which body lay down.

    Slip statistics are over the runs that stood (an overturned run's final state is frozen
    where a body lay down).

    Returns
    -------
    dict
        ``{(column, stripe): {"runs", "standing", "slip_med", "slip_p90" [m], "ratio_med",
        "ratio_p90" [1], "overturned", "upper_first", "collapsed"}}``.
    """
    groups = {}
    for r in rows:
        if r["model"] == "stack":
            groups.setdefault((r["column"], r["stripe"]), []).append(r)
    out = {}
    for key, rs in sorted(groups.items()):
        standing = [r for r in rs if not r["overturned"]]
        slip = np.array([largest_bed_slip(r) for r in standing], dtype=float)
        ratio = np.array([r["dislocation_ratio"] for r in standing], dtype=float)
        down = [r for r in rs if r["overturned"]]
        pct = (lambda a, q: float(np.percentile(a, q)) if a.size else math.nan)
        out[key] = {"runs": len(rs), "standing": len(standing),
                    "slip_med": pct(slip, 50), "slip_p90": pct(slip, 90),
                    "ratio_med": pct(ratio, 50), "ratio_p90": pct(ratio, 90),
                    "overturned": len(down),
                    "upper_first": sum(1 for r in down if (r["overturn_drum"] or 0) > 0),
                    "collapsed": sum(1 for r in down if r["collapsed"])}
    return out


def costs(rows):
    """Per (column, model): runs, mean wall time per run [s], cost per simulated second [s/s]."""
    out = {}
    for r in rows:
        out.setdefault((r["column"], r["model"]), []).append((r["wall"], r["simulated"]))
    return {k: {"runs": len(v), "mean": float(np.mean([w for w, _s in v])),
                "rate": sum(w for w, _s in v) / sum(s for _w, s in v)} for k, v in out.items()}


# -- report -------------------------------------------------------------------------------------

def design(rows):
    """What was run: ``{(column, model): (records, stripes [g], runs)}``, in report order."""
    out = {}
    for r in rows:
        recs, levels, n = out.get((r["column"], r["model"]), (set(), set(), 0))
        out[(r["column"], r["model"])] = (recs | {r["record"]}, levels | {r["stripe"]}, n + 1)
    columns = list(dict.fromkeys(r["column"] for r in rows))
    return {k: (sorted(v[0]), sorted(v[1]), v[2])
            for k, v in sorted(out.items(), key=lambda kv: (columns.index(kv[0][0]), ALL_MODELS.index(kv[0][1])))}


def _record_span(records):
    """``A .. B`` for a full set of the catalog's records, else the list."""
    if list(records) == list(RECORDS):
        return f"{records[0]} .. {records[-1]}"
    return ", ".join(r.replace("FEMA-FF-", "FF-") for r in records)


def g_text(x, stripes):
    """A median [g] as text; the fit's limits named."""
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "n/a"
    if math.isinf(x):
        return f"> {max(stripes):g} (none overturned)"
    if x == 0:
        return f"< {min(stripes):g} (all overturned)"
    return f"{x:.3f}"


def band_text(lo, hi, stripes):
    """A 90 % band [g] as text (``> max`` / ``< min`` where a resample's fit has no finite median)."""
    if math.isnan(lo) or math.isnan(hi):
        return "n/a"
    short = (lambda x: f"> {max(stripes):g}" if math.isinf(x) else f"< {min(stripes):g}" if x == 0 else f"{x:.3f}")
    return f"{short(lo)} - {short(hi)}"


def _median_phrase(x, stripes):
    """A median [g] in a sentence."""
    if math.isnan(x):
        return "not defined"
    if math.isinf(x):
        return f"above {max(stripes):g} g (no run overturned)"
    if x == 0:
        return f"below {min(stripes):g} g (every run overturned)"
    return f"{x:.3f} g"


def _model_text(key, model):
    if is_stack(model):
        stack = drum_column(key)
        text = f"{stack.n_drums}-drum stack" + (" with capital" if stack.capital is not None else "")
        if model in BAND_VARIANTS:
            text += f", edge band {BAND_VARIANTS[model]:g}"
        return text + {"stack-half-step": ", half step", "stack-dopri5": ", DOPRI5"}.get(model, "")
    return {"rigid": "rigid model", "monolith": "monolith"}[model]


def findings(rows, med, agree, stacks, cost, stripes, tilts=None, common=None):
    """3-5 plain sentences read from the tables (no more than they show).

    ``common`` are the :func:`medians` of :func:`common_cells`, for the columns whose models
    ran different cells.
    """
    tilts = tilts or {}
    common = common or {}
    out = []
    for key in dict.fromkeys(r["column"] for r in rows):
        name = "the paper's column" if key == "paper" else "the Parthenon column"
        parts = [(med[(key, m)]["status"] if med[(key, m)]["status"].startswith("not fitted")
                  else _median_phrase(med[(key, m)]["median"], stripes)) + f" for the {_model_text(key, m)}"
                 for m in MODELS if (key, m) in med]  # the band variants have their own sentence
        text = f"For {name} the fitted median overturning PGA is " + ", ".join(parts)
        inside = []
        for a, b in (("rigid", "monolith"), ("monolith", "stack"), ("rigid", "stack")):
            if (key, a) in med and (key, b) in med:
                m, ref = med[(key, a)]["median"], med[(key, b)]
                if 0 < m < math.inf and not math.isnan(ref["lo"]):  # a finite median only
                    where = "inside" if ref["lo"] <= m <= ref["hi"] else "outside"
                    inside.append(f"the {_model_text(key, a)}'s median lies {where} the "
                                  f"{_model_text(key, b)}'s 90 % band")
                break
        text += ("; " + inside[0] if inside else "") + "."
        out.append(text)
        shared = {m: common[(key, m)] for m in MODELS if (key, m) in common}
        if shared:
            runs = next(iter(shared.values()))["runs"]
            out.append(f"Fitted on the {runs} record x stripe cells every model ran, the medians are "
                       + ", ".join((v["status"] if v["status"].startswith("not fitted")
                                    else _median_phrase(v["median"], stripes)) + f" for the {_model_text(key, m)}"
                                   + ("" if math.isnan(v["lo"]) else
                                      f" (90 % band {band_text(v['lo'], v['hi'], stripes)} g)")
                                   for m, v in shared.items()) + ".")
        clauses = []
        for a, b in (("rigid", "monolith"), ("monolith", "stack"), ("rigid", "stack")):
            ag = agree.get((key, a, b))
            if not ag or not ag["cells"]:
                continue
            c = (f"the {_model_text(key, a)} and the {_model_text(key, b)} give the same outcome in "
                 f"{ag['same']} of {ag['cells']} record x stripe cells")
            if ag["same"] < ag["cells"]:
                c += (f" (only the {_model_text(key, a)} overturns in {ag['a_only']}, only the "
                      f"{_model_text(key, b)} in {ag['b_only']})")
            clauses.append(c)
            if len(clauses) == 2:
                break
        tr = tilts.get((key, "monolith", "stack"))
        if tr:
            clauses.append(f"where both stood, the stack's top body tilted {tr['median']:.2f} times as far as the "
                           f"monolith (median over {tr['cells']} cells, P10-P90 {tr['p10']:.2f}-{tr['p90']:.2f})")
        st = {s: v for (k, s), v in stacks.items() if k == key}
        if st:
            down = sum(v["overturned"] for v in st.values())
            upper = sum(v["upper_first"] for v in st.values())
            if down:
                clauses.append(f"in {upper} of the stack's {down} overturnings an upper body lay down first")
            standing = [(s, v) for s, v in sorted(st.items()) if v["standing"]]
            if standing:
                s, v = standing[-1]
                clauses.append(f"at {s:g} g the largest residual bed-joint slip of the stacks left standing has "
                               f"a median of {1e3 * v['slip_med']:.1f} mm ({100 * v['ratio_med']:.2f} % of the "
                               f"joint diameter, {v['standing']} run{'s' if v['standing'] != 1 else ''})")
        if clauses:
            out.append(clauses[0][0].upper() + clauses[0][1:] + "".join("; " + c for c in clauses[1:]) + ".")
        band = band_phrases(key, agree, tilts)
        if band:
            out.append("The band past a bed joint's edge, a numerical choice: " + "; ".join(band) + ".")
    per = [f"{cost[k]['mean']:.2f} s for the {_model_text(k[0], k[1])} of the {k[0]} column"
           for k in sorted(cost, key=lambda k: (k[0], ALL_MODELS.index(k[1])))]
    if per:
        out.append("A run cost on average " + ", ".join(per) + f" ({MACHINE}).")
    return out


def band_phrases(key, agree, tilts):
    """What each band variant of a column's stack changed, against the stack, as clauses."""
    out = []
    for variant, width in BAND_VARIANTS.items():
        ag = agree.get((key, "stack", variant))
        if not ag or not ag["cells"]:
            continue
        factor = width / BAND_DEFAULT
        what = "halved" if factor == 0.5 else "doubled" if factor == 2 else f"times {factor:g}"
        text = (f"{what} (edge_band {width:g}), it changes the stack's outcome in {ag['cells'] - ag['same']} of "
                f"{ag['cells']} cells ({ag['b_only']} now overturn, {ag['a_only']} now stand)")
        tr = tilts.get((key, "stack", variant))
        if tr:
            text += (f", and where both stood the top body's peak tilt by a factor of median {tr['median']:.3f} "
                     f"(P10-P90 {tr['p10']:.3f}-{tr['p90']:.3f}, {tr['cells']} cells)")
        out.append(text)
    return out


def _median_table(med, columns, stripes):
    """The lines of a markdown table of :func:`medians`, columns in report order."""
    lines = ["| column | model | runs | overturned | median PGA [g] | 90 % band [g] | beta | fit |",
             "|---|---|---|---|---|---|---|---|"]
    for (key, model), m in sorted(med.items(), key=lambda kv: (columns.index(kv[0][0]), ALL_MODELS.index(kv[0][1]))):
        beta = "n/a" if math.isnan(m["beta"]) else f"{m['beta']:.3f}"
        lines.append(f"| {key} | {_model_text(key, model)} | {m['runs']} | {m['overturned']} | "
                     f"{g_text(m['median'], stripes)} | {band_text(m['lo'], m['hi'], stripes)} | {beta} | "
                     f"{m['status']} |")
    return lines


def report(rows, stripes, records, meta):
    """The markdown report.

    Parameters
    ----------
    rows : list of dict
        Rows of :func:`make_row`.
    stripes : sequence of float
        PGA stripes [g].
    records : sequence of str
    meta : dict
        ``beds`` ``{column: (c_n [Pa s/m], restitution)}``, ``command``, ``minutes``,
        ``workers``, ``failed`` (list of job texts).

    Returns
    -------
    str
    """
    med = medians(rows)
    common = medians(common_cells(rows))
    agree = agreement(rows)
    stacks = stack_stats(rows)
    tilts = tilt_ratios(rows)
    cost = costs(rows)
    L = ["# Drum stacks against the rigid rolling model\n"]
    columns = list(dict.fromkeys(r["column"] for r in rows))
    L.append(f"FEMA P695 far-field record pairs, both horizontal components scaled so that the peak "
             f"horizontal resultant is the stripe, angle {ANGLE:g} deg, no vertical. Models: rigid rolling frustum "
             f"(`3d`) and compliant monolith on the shaft's outline, compliant drum stack (`3d-compliant`). "
             f"Same bed for all: k_n = {STIFFNESS:g} Pa/m, friction {FRICTION} (joints too), the compliant "
             f"dashpots calibrated on the outline and the restitution they reach given to the rigid model. "
             f"Lognormal median of overturning by maximum likelihood; 90 % band from {N_BOOT} resamples of the "
             f"records (fits need {MIN_STRIPES} stripes or more). {len(rows)} runs; made by "
             f"`{meta.get('command', 'compare.py')}` " + (
                 "(tabulated from the cache: the runs' own wall times are in the cost table below).\n"
                 if meta.get("report_only") else
                 f"({meta.get('minutes', 0):.0f} min for the runs not cached, {meta.get('workers', 1)} workers, "
                 f"{MACHINE}).\n"))
    L.append("| column | model | records | PGA stripes [g] | runs |")
    L.append("|---|---|---|---|---|")
    for (key, model), (recs, levels, n) in design(rows).items():
        L.append(f"| {key} | {_model_text(key, model)} | {len(recs)} ({_record_span(recs)}) | "
                 f"{', '.join(f'{x:g}' for x in levels)} | {n} |")
    L.append("")
    L.append("| column | c_n [Pa s/m] | restitution |")
    L.append("|---|---|---|")
    for key in columns:
        if key in meta.get("beds", {}):
            c, e = meta["beds"][key]
            L.append(f"| {label(key)} | {c:.4g} | {e:.4f} |")
    L.append("\n## Median overturning PGA\n")
    L.extend(_median_table(med, columns, stripes))
    if common:
        L.append("\n## Median overturning PGA on the cells every model ran\n")
        L.append("Where a model ran fewer records or stripes than the others, the medians above are fitted "
                 "on different cells; here every model of the column is fitted on the record x stripe cells "
                 "they all ran (same resampling of records as above).\n")
        L.extend(_median_table(common, columns, stripes))
    L.append("\n## Agreement of the overturning outcome, cell by cell (record x stripe)\n")
    L.append("| column | model A | model B | cells | same outcome | fraction | only A overturns | only B overturns |")
    L.append("|---|---|---|---|---|---|---|---|")
    for (key, a, b), ag in agree.items():
        frac = f"{ag['same'] / ag['cells']:.3f}" if ag["cells"] else "n/a"
        L.append(f"| {key} | {_model_text(key, a)} | {_model_text(key, b)} | {ag['cells']} | {ag['same']} | "
                 f"{frac} | {ag['a_only']} | {ag['b_only']} |")
    if tilts:
        L.append("\n## Peak tilt, cell by cell, where neither model overturned\n")
        L.append("Peak tilt of model B over model A on the same record and stripe: the shaft's for the rigid "
                 "model and the monolith, the top body's for the stack.\n")
        L.append("| column | model A | model B | cells | median B/A | P10 | P90 |")
        L.append("|---|---|---|---|---|---|---|")
        for (key, a, b), t in tilts.items():
            L.append(f"| {key} | {_model_text(key, a)} | {_model_text(key, b)} | {t['cells']} | "
                     f"{t['median']:.3f} | {t['p10']:.3f} | {t['p90']:.3f} |")
    if stacks:
        L.append("\n## Drum stacks: residual bed-joint slip and which body lay down\n")
        L.append("Largest residual slip over the bed joints of a run (the base left out), over the runs that "
                 "stood; as a fraction of the joint's diameter the largest slip/diameter of the run "
                 "(`dislocation_ratio`). \"Upper body first\": the first body to lie down was not the bottom "
                 "drum (`overturn_drum` > 0); \"fell off\": a body fell off the one below.\n")
        L.append("| column | PGA [g] | runs | standing | slip median [mm] | slip P90 [mm] | slip/D median | "
                 "slip/D P90 | overturned | upper body first | fell off |")
        L.append("|---|---|---|---|---|---|---|---|---|---|---|")
        for (key, s), v in stacks.items():
            f = (lambda x, k=1.0, d=1: "n/a" if math.isnan(x) else f"{k * x:.{d}f}")
            L.append(f"| {key} | {s:g} | {v['runs']} | {v['standing']} | {f(v['slip_med'], 1e3, 2)} | "
                     f"{f(v['slip_p90'], 1e3, 2)} | {f(v['ratio_med'], 1, 5)} | {f(v['ratio_p90'], 1, 5)} | "
                     f"{v['overturned']} | {v['upper_first']} | {v['collapsed']} |")
    L.append("\n## Cost per run\n")
    L.append(f"Wall time of one run in one process ({MACHINE}); runs that overturn stop early.\n")
    L.append("| column | model | bodies | runs | mean wall time [s] | per simulated second [s/s] |")
    L.append("|---|---|---|---|---|---|")
    for key, model in sorted(cost, key=lambda k: (columns.index(k[0]), ALL_MODELS.index(k[1]))):
        c = cost[(key, model)]
        L.append(f"| {key} | {_model_text(key, model)} | {n_bodies(key, model)} | {c['runs']} | "
                 f"{c['mean']:.3f} | {c['rate']:.4f} |")
    L.append("\n## What the numbers say\n")
    L.append(" ".join(findings(rows, med, agree, stacks, cost, stripes, tilts, common)))
    if meta.get("failed"):
        L.append("\n## Runs that failed (left out above)\n")
        L.extend(f"- {f}" for f in meta["failed"])
    return "\n".join(L) + "\n"


# -- command line -------------------------------------------------------------------------------

def _choices(text, allowed, what):
    items = [x.strip() for x in text.split(",") if x.strip()]
    bad = [x for x in items if x not in allowed]
    if bad or not items:
        raise SystemExit(f"--{what}: {', '.join(bad) or 'nothing given'} not known; choose from {', '.join(allowed)}")
    return list(dict.fromkeys(items))


def _stripes(text):
    try:
        values = [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise SystemExit(f"--stripes: {text!r} must be PGA values in g separated by commas, e.g. 0.2,0.4") from None
    if not values or any(not (math.isfinite(v) and v > 0) for v in values):
        raise SystemExit(f"--stripes: {text!r} must be positive PGA values in g")
    return sorted(set(values))


def parser():
    p = argparse.ArgumentParser(
        description="Rigid rolling model vs compliant monolith vs drum stack, on the FEMA far-field set "
                    "(issue 13). Each run is cached under --out, so a rerun resumes. The markdown report goes "
                    "to stdout, progress to stderr.",
        epilog="Example: python studies/drums_vs_rigid/compare.py --dry-run; "
               "nice -n 10 python studies/drums_vs_rigid/compare.py --workers 2 > studies/drums_vs_rigid/results.md")
    p.add_argument("--columns", default=",".join(COLUMN_KEYS),
                   help=f"columns, comma separated, from {', '.join(COLUMN_KEYS)} (default: all)")
    p.add_argument("--models", default=",".join(MODELS),
                   help="models, comma separated: rigid (3d on the shaft), monolith (3d-compliant, one body), "
                        "stack (3d-compliant, the drums) (default: these three); also stack-narrow and "
                        "stack-wide, the stack with the band past a bed joint's edge halved and doubled, and "
                        "stack-half-step and stack-dopri5, the stack at half the semi-implicit step and with "
                        "the adaptive DOPRI5 reference")
    p.add_argument("--records", default=",".join(RECORDS),
                   help="catalog record ids, comma separated (default: FEMA-FF-01..FEMA-FF-22)")
    p.add_argument("--stripes", default=",".join(f"{s:g}" for s in STRIPES),
                   help="PGA levels [g], comma separated (default: 0.2,0.4,0.6,0.8,1,1.5)")
    p.add_argument("--workers", type=int, default=2, help="worker processes (default 2)")
    p.add_argument("--out", default=OUT, help=f"cache folder of the per-run JSON files (default {OUT})")
    p.add_argument("--dry-run", action="store_true",
                   help="list the jobs and estimate the wall time from the costs cached so far; run nothing")
    p.add_argument("--shuffle", action="store_true",
                   help="run the jobs in a seeded random order instead of the longest first, so that a run "
                        "stopped early leaves a random sample of records, not the longest ones")
    p.add_argument("--report-only", action="store_true",
                   help="run nothing: report every run cached for --columns and --models, whatever its "
                        "record and stripe (how parts run with different designs make one report)")
    return p


def _command(argv):
    """The command line that made a report (``argv`` if given, else the process's own)."""
    args = sys.argv[1:] if argv is None else argv
    return " ".join(["python studies/drums_vs_rigid/compare.py", *args])


def _write_report(rows, columns, stripes, records, meta):
    """The report of the rows, in column, model, record and stripe order, on stdout."""
    rows = sorted(rows, key=lambda r: (columns.index(r["column"]), ALL_MODELS.index(r["model"]), r["record"], r["stripe"]))
    sys.stdout.write(report(rows, stripes, records, meta))


def main(argv=None):
    args = parser().parse_args(argv)
    columns = _choices(args.columns, COLUMN_KEYS, "columns")
    models = _choices(args.models, ALL_MODELS, "models")
    records = [x.strip() for x in args.records.split(",") if x.strip()]
    stripes = _stripes(args.stripes)
    if args.workers < 1:
        raise SystemExit("--workers must be at least 1")
    if args.report_only:
        rows = [r for r in all_cached(args.out) if r["column"] in columns and r["model"] in models]
        if not rows:
            raise SystemExit(f"--report-only: no run of {', '.join(columns)} x {', '.join(models)} is cached in "
                             f"{args.out} (digests {digest()}, stack {digest('stack')}); run the study first")
        records = sorted({r["record"] for r in rows})
        stripes = sorted({r["stripe"] for r in rows})
        columns = [k for k in columns if any(r["column"] == k for r in rows)]
        beds = {k: bed(k) for k in columns}
        _write_report(rows, columns, stripes, records, {"beds": beds, "command": _command(argv),
                                                         "report_only": True, "failed": []})
        return 0
    info = {r: record_info(r) for r in records}  # loads (and checks) every record before any run
    jobs = [(k, m, r, s) for k in columns for m in models for r in records for s in stripes]
    cached = {}
    for j in jobs:
        path = cache_path(args.out, j)
        if os.path.exists(path):
            with open(path, encoding="utf-8") as fh:
                cached[j] = json.load(fh)
    measured = rates(all_cached(args.out))
    est = {}
    for j in jobs:
        rate, _src = rate_for(j[0], j[1], measured)
        est[j] = rate * (info[j[2]][1] + TAIL)
    pending = sorted((j for j in jobs if j not in cached), key=lambda j: -est[j])  # the longest first
    if args.shuffle:
        pending = [pending[i] for i in np.random.default_rng(SEED).permutation(len(pending))]
    if args.dry_run:
        print(f"{len(jobs)} jobs, {len(cached)} cached, {len(pending)} to run; cache {args.out} "
              f"(digest {digest()}, stack {digest('stack')})\n")
        print("| column | model | bodies | jobs | cached | to run | cost per simulated second [s/s] | source | "
              "estimated CPU time to run [h] |")
        print("|---|---|---|---|---|---|---|---|---|")
        for k in columns:
            for m in models:
                js = [j for j in jobs if j[:2] == (k, m)]
                rate, src = rate_for(k, m, measured)
                todo = [j for j in js if j not in cached]
                print(f"| {k} | {m} | {n_bodies(k, m)} | {len(js)} | {len(js) - len(todo)} | {len(todo)} | "
                      f"{rate:.4f} | {src} | {sum(est[j] for j in todo) / 3600:.2f} |")
        total = sum(est[j] for j in pending)
        span = makespan([est[j] for j in pending], args.workers)
        print(f"\nEstimated: {total / 3600:.2f} h of CPU, {span / 3600:.2f} h of wall time on {args.workers} "
              f"worker(s), longest first, if each worker has a core to itself (runs that overturn stop early, so "
              f"rates measured at low stripes overestimate; shared cores stretch it).\n")
        print("Jobs to run, longest first (column, model, record, stripe [g], estimated [s]):")
        for j in pending:
            print(f"  {j[0]} {j[1]} {j[2]} {j[3]:g} {est[j]:.1f}")
        return 0
    os.makedirs(args.out, exist_ok=True)
    beds = {}
    for k in columns:  # the rigid runs need it too (restitution), and the report prints it
        print(f"calibrating the bed of {k} ...", file=sys.stderr, flush=True)
        beds[k] = bed(k)
    start = time.perf_counter()
    rows = list(cached.values())
    failed = []
    if pending:
        with ProcessPoolExecutor(args.workers) as pool:
            futures = {pool.submit(run, (args.out, j, *beds[j[0]])): j for j in pending}
            for i, fut in enumerate(as_completed(futures), 1):
                j = futures[fut]
                try:
                    rows.append(fut.result())
                except Exception as exc:  # one failed run must not lose the others
                    failed.append(f"{j[0]} {j[1]} {j[2]} {j[3]:g} g: {type(exc).__name__}: {exc}")
                elapsed = time.perf_counter() - start
                print(f"[{i}/{len(pending)}] {j[0]} {j[1]} {j[2]} {j[3]:g} g done, {elapsed / 60:.1f} min",
                      file=sys.stderr, flush=True)
    meta = {"beds": beds, "command": _command(argv), "minutes": (time.perf_counter() - start) / 60,
            "workers": args.workers, "failed": failed}
    _write_report(rows, columns, stripes, records, meta)
    for f in failed:
        print(f"failed: {f}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
