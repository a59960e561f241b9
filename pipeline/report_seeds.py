"""The report of a study of imperfect drums: what was drawn, and do apparently identical structures differ?

A study's ``[imperfections]`` (docs/studies.md) gives its results a dimension ``seed``: each seed is
one structure built to the same tolerance (every drum's bed offset and tilted by random amounts up
to it, the joints' friction drawn from a range), and the models it names draw one per seed; the
others run perfect drums once, repeated along ``seed``. The fits, counts and figures of the report
pool the seeds as they pool the incidence angles (:func:`pipeline.fragility.counted`). This module
says what was drawn (:func:`imperfection_lines`) and asks the seeds the question of Mouzakis et al.
(2002, Earthquake Engng Struct. Dyn. 31(9)), whose apparently identical shake-table tests of a 1:3
marble Parthenon column gave radically different results: under the same record, scale and angle
(a *cell*), do the seeds agree?

:func:`seed_spread` counts, per structure, seeded model and stripe (and pooled over the stripes),
the cells in which every seed stood, every seed fell, or the seeds divided; the share of the seeds
that fell in the divided cells; the spread of the peak tilt ratio over the seeds in the cells where
all stood (the median and the largest of max/min over the seeds); and, where the study also ran the
perfect structure (a model of the same registry model without imperfections), in how many cells
the perfect run's outcome differs from the seeds' majority. No threshold enters: a cell divides
when its seeds' outcomes are not all alike. :func:`seeds_section` writes it as Markdown and
:func:`seed_columns` as the columns of ``summary.csv``.
"""

import numpy as np

from pipeline import fragility as F
from pipeline import models as MD
from pipeline.units import G

__all__ = ["seeded_models", "perfect_counterpart", "imperfection_lines", "seed_spread", "seeds_section",
           "seed_columns", "CELL_DIMS"]

#: The dimensions of a cell the seeds share: one record at one incidence angle (at one stripe).
CELL_DIMS = ("record", "angle")

#: Mouzakis et al., the shake-table tests the section answers.
MOUZAKIS = ("Mouzakis H.P., Psycharis I.N., Papastamatiou D.Y., Carydis P.G., Papantonopoulos C., Zambas C. "
            "(2002), Experimental investigation of the earthquake response of a model of a marble classical "
            "column, Earthquake Engineering and Structural Dynamics 31(9), 1681-1698")


def seeded_models(results):
    """The models of ``results`` that drew imperfect drums from each seed ([] without a ``seed`` dimension)."""
    if "seed" not in results.dims:
        return []
    models = [str(m) for m in results["model"].values]
    if "seeded" not in results.variables:  # as the fits read such a file: every model seeded
        return models
    return [m for m, s in zip(models, results["seeded"].values) if int(s)]


def perfect_counterpart(results, model):
    """The first model of the study that runs the same registry model as ``model`` with perfect drums, or
    None (the perfect structure the seeds are imperfect copies of)."""
    if "seeded" not in results.variables:
        return None
    base = MD.base_of(results, model)
    return next((str(m) for m, s in zip(results["model"].values, results["seeded"].values)
                 if not int(s) and MD.base_of(results, str(m)) == base), None)


def _tolerance_words(results, fmt):
    tol = results.attrs.get("imperfection_tolerance_m")
    return f"{fmt(1e3 * float(tol))} mm" if tol is not None else "a tolerance the file does not state"


def _friction_words(results, fmt):
    given = str(results.attrs.get("imperfection_friction_range", "")).split()
    try:
        lo, hi = (float(v) for v in given)
    except ValueError:
        return "the joints' friction the one the options give"
    return f"the friction of every joint drawn from {fmt(lo)} to {fmt(hi)}"


def imperfection_lines(results, fmt):
    """Markdown bullets for "What was simulated": the tolerance, the seeds, the friction range and the
    models that drew them ([] without seeds). ``fmt`` writes a number as the report does."""
    drew = seeded_models(results)
    if not drew:
        return []
    seeds = [int(s) for s in results["seed"].values]
    perfect = [str(m) for m in results["model"].values if str(m) not in drew]
    line = (f"- **Imperfect drums**: {' and '.join(f'`{m}`' for m in drew)} drew a structure for each of "
            f"{len(seeds)} seed(s) ({', '.join(map(str, seeds))}): every drum's bed offset and tilted by random "
            f"amounts up to {_tolerance_words(results, fmt)}, {_friction_words(results, fmt)}. Each seed is one "
            "structure built to that tolerance; the fits, counts and figures pool the seeds as they pool the "
            "incidence angles (docs/fragility.md)")
    if perfect:
        line += (f"; {' and '.join(f'`{m}`' for m in perfect)} ran perfect drums, once for all seeds and counted "
                 "once")
    return [line + "."]


def _stripe_label(results, scale, fmt):
    if scale is None:
        return "all"
    return f"{fmt(float(scale) / G)} g" if F.in_stripes(results) else f"x {fmt(float(scale))}"


def _by_cell(values, like, sel):
    """``values`` at ``sel`` over (record, angle, scale, seed), as ``like`` (the runs' flags) lies."""
    values = values.broadcast_like(like).sel(sel)
    return values.transpose(*CELL_DIMS, "scale", "seed").values


def _counts(over, ok, ratio, perfect=None, perfect_ok=None):
    """The counts of one set of cells: arrays over (cell, seed) (``perfect``, ``perfect_ok`` over cells)."""
    n = over.shape[-1]
    whole = ok.all(axis=-1)  # the cells in which every seed ran: only they can agree or divide
    falls = np.where(over & ok, 1, 0).sum(axis=-1)
    stand, fall = whole & (falls == 0), whole & (falls == n)
    divided = whole & ~stand & ~fall
    with np.errstate(divide="ignore", invalid="ignore"):
        spread = ratio.max(axis=-1) / ratio.min(axis=-1)
    spread = spread[stand & np.isfinite(spread)]
    out = {"cells": int(whole.sum()), "cells_incomplete": int((~whole & ok.any(axis=-1)).sum()),
           "all_stand": int(stand.sum()), "all_fall": int(fall.sum()), "divided": int(divided.sum()),
           "seeds_falling_in_divided": (float(falls[divided].sum()) / (n * int(divided.sum()))
                                        if divided.any() else np.nan),
           "spread_cells": int(spread.size),
           "spread_median": float(np.median(spread)) if spread.size else np.nan,
           "spread_max": float(np.max(spread)) if spread.size else np.nan}
    if perfect is not None:
        both = whole & perfect_ok
        tie = 2 * falls == n
        majority = 2 * falls > n
        out.update(compared=int(both.sum()), ties=int((both & tie).sum()),
                   differ=int((both & ~tie & (majority != perfect)).sum()))
    return out


def seed_spread(results):
    """Do the seeds of one cell agree? Per structure, seeded model and stripe, and over all stripes.

    Parameters
    ----------
    results : xarray.Dataset
        Study results with a ``seed`` dimension, undecided runs resolved
        (:func:`pipeline.fragility.resolve_undecided`).

    Returns
    -------
    list of dict
        One per (column, model, stripe), then the stripes pooled (``scale`` None): ``column``,
        ``model``, ``scale`` [the study's scale units], ``seeds`` [1]; the cells (record, angle) in
        which every seed ran (``cells``; ``cells_incomplete``: some seed failed, left out), those in
        which all stood (``all_stand``), all fell (``all_fall``) or the seeds divided (``divided``);
        ``seeds_falling_in_divided`` [1], the share of the seeds that fell in the divided cells (NaN
        without one); over the cells in which all stood, max/min of ``peak_theta_ratio`` over the
        seeds: its median and largest (``spread_median``, ``spread_max`` [1], over ``spread_cells``);
        with a perfect counterpart (:func:`perfect_counterpart`, ``perfect``; else None) the cells
        both ran (``compared``), those where the perfect run's outcome differs from the seeds'
        majority (``differ``) and those without a majority (``ties``, half the seeds fell).
    """
    rows = []
    valid = F._valid(results)
    n_seeds = results.sizes["seed"]
    for c in results["column"].values:
        for m in seeded_models(results):
            perfect = perfect_counterpart(results, m)
            like = results["overturned"]
            over, ok, ratio = (_by_cell(v, like, dict(column=c, model=m))
                               for v in (like > 0, valid, results["peak_theta_ratio"]))
            if perfect is not None:  # one run, repeated along the seeds
                p_over, p_ok = (_by_cell(v, like, dict(column=c, model=perfect))[..., 0] for v in (like > 0, valid))
            for k, s in enumerate([*results["scale"].values, None]):
                pick = (slice(None),) * 2 + ((k,) if s is not None else (slice(None),))
                flat = [a[pick].reshape(-1, n_seeds) for a in (over, ok, ratio)]
                extra = () if perfect is None else (p_over[pick].ravel(), p_ok[pick].ravel())
                rows.append({"column": str(c), "model": m, "scale": None if s is None else float(s),
                             "seeds": n_seeds, "perfect": perfect, **_counts(*flat, *extra)})
    return rows


def seeds_section(results, fmt, rows=None):
    """Markdown lines: "Imperfect drums: do apparently identical structures differ?" ([] without seeded
    models, or with one seed). ``fmt`` writes a number as the report does; ``rows`` from
    :func:`seed_spread` (computed if not given)."""
    if len(seeded_models(results)) == 0 or results.sizes["seed"] < 2:
        return []
    rows = seed_spread(results) if rows is None else rows
    seeds = results.sizes["seed"]
    perfect = any(r["perfect"] for r in rows)
    lines = ["## Imperfect drums: do apparently identical structures differ?", "",
             "Mouzakis et al. (2002) shook a 1:3 marble replica of a Parthenon column and found apparently identical "
             f"tests to give radically different results. Here each of the {seeds} seeds is the same structure built "
             f"to the same tolerance ({_tolerance_words(results, fmt)}), shaken by the same record at the same "
             "incidence angle and stripe: a *cell*. The seeds agree in a cell when all stand or all fall, and "
             "divide otherwise; in the divided cells, the share of the seeds that fell says which way they lean. "
             "Where every seed stood, the peak tilt ratio (peak tilt over theta_crit) still differs between them: "
             "how far the largest seed's lies above the smallest's in a cell, the median and the largest over "
             "those cells."
             + (" The last column compares the perfect structure the study also ran (the same model, no "
                "imperfections) with the seeds' majority in each cell; a tie is a cell in which half the seeds "
                "fell." if perfect else ""), "",
             "| structure | model | stripe | cells | all stand | all fall | divided | seeds falling in divided cells "
             "| where all stood: peak tilt ratio of the largest seed above the smallest's, median (largest) "
             "| perfect run differs from the seeds' "
             "majority |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        vs = (f"`{r['perfect']}`: {r['differ']} of {r['compared']}" + (f" ({r['ties']} tied)" if r["ties"] else "")
              if r["perfect"] else "no perfect run")
        spread = (f"{fmt(100 * (r['spread_median'] - 1))} % ({fmt(100 * (r['spread_max'] - 1))} %) in "
                  f"{r['spread_cells']} cell(s)" if r["spread_cells"] else "n/a")
        stripe = _stripe_label(results, r["scale"], fmt)
        lines.append(f"| {r['column']} | {r['model']} | {'**all**' if r['scale'] is None else stripe} | {r['cells']} | "
                     f"{r['all_stand']} | {r['all_fall']} | {r['divided']} | "
                     f"{'n/a' if not r['divided'] else format(100 * r['seeds_falling_in_divided'], '.0f') + ' %'} | "
                     f"{spread} | {vs} |")
    lines.append("")
    for r in (r for r in rows if r["scale"] is None):
        where = [_stripe_label(results, q["scale"], fmt) for q in rows
                 if q["column"] == r["column"] and q["model"] == r["model"] and q["scale"] is not None and q["divided"]]
        share = f" ({100 * r['divided'] / r['cells']:.0f} %)" if r["cells"] else ""
        text = (f"- '{r['column']}' ({r['model']}): the seeds divided in {r['divided']} of {r['cells']} cells{share}"
                + (f", at the stripe(s) {', '.join(where)}" if where else "") + ".")
        if r["cells_incomplete"]:
            text += f" {r['cells_incomplete']} cell(s) in which some seed failed are left out."
        lines.append(text)
    lines += ["", f"Reference: {MOUZAKIS}.", ""]
    return lines


def seed_columns(rows, column, model):
    """The pooled numbers of :func:`seed_spread` for one row of ``summary.csv`` (empty for a model of
    perfect drums)."""
    pooled = next((r for r in rows if r["column"] == column and r["model"] == model and r["scale"] is None), None)
    keys = ("cells", "all_stand", "all_fall", "divided", "seeds_falling_in_divided", "spread_median", "differ", "ties")
    names = ("seed_cells", "seed_cells_all_stand", "seed_cells_all_fall", "seed_cells_divided",
             "seed_fraction_falling_in_divided", "seed_peak_ratio_max_over_min_median", "perfect_differs_from_seeds",
             "perfect_ties_with_seeds")
    return {name: ("" if pooled is None or key not in pooled else pooled[key]) for name, key in zip(names, keys)}
