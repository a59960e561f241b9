"""The report of a study of colonnades: what falls first, what the standing ones keep, and drum damage.

Three questions an archaeologist or a restorer asks of a colonnade's runs (issue 48, item 3):

* **What falls first.** Of the runs that overturned, how many began with an end column (column 1
  or N), an inner column, or an epistyle block, and which body (drum k, capital) most often: read
  from each run's ``overturn_body`` by :func:`pipeline.structures.description.classify_body` (a model
  that runs the colonnade as one body, the rigid frame, says "the colonnade": it fell as one).
* **What the standing ones keep.** Of the runs that stood, the epistyle's residual slip on its
  capitals (``epistyle_slip``) and the widest opening of its head joints (``epistyle_opening``):
  median and 90th percentile, at each stripe and pooled (and pooled at each incidence angle when a
  model depends on it).
* **Damage states by drum dislocation** (``dislocation_<s>``, :data:`pipeline.fragility.DISLOCATION_STATES`):
  the fitted medians with the words of docs/fragility.md, for every model that runs drums.

Runs are counted as the fits count them (:func:`pipeline.fragility.counted`: a model's repeats over
the angles or the seeds once; the seeds of imperfect drums pooled as angles). :func:`falls_first` and
:func:`epistyle_kept` compute; :func:`colonnade_section`, :func:`dislocation_section` write Markdown
and :func:`colonnade_columns` the columns of ``summary.csv``.
"""

from collections import Counter

import numpy as np

from pipeline import fragility as F
from pipeline import models as MD
from pipeline.errors import InputError
from pipeline.report_angles import _median_text as median_text
from pipeline.structures.description import classify_body
from pipeline.units import G

__all__ = ["check_labels", "colonnade_cells", "falls_first", "epistyle_kept", "colonnade_section",
           "dislocation_section", "colonnade_columns", "FIRST", "DISLOCATION_WORDS", "PERCENTILES"]

#: Where a fall began: the categories of :func:`falls_first`, in the order the report writes them.
FIRST = ("end column", "inner column", "epistyle block", "as one body", "no body named")

#: The percentiles of the epistyle's slip and opening the report states [%].
PERCENTILES = (50.0, 90.0)

#: What each default dislocation state means (docs/fragility.md; why, at
#: :data:`pipeline.fragility.DISLOCATION_STATES`): DS1, DS2, DS3.
DISLOCATION_WORDS = dict(zip(F.DISLOCATION_STATES, (
    "DS1: a dislocation the eye sees (19 mm on a Parthenon drum)",
    "DS2: the drums need re-setting",
    "DS3: a column markedly weakened for the next earthquake")))


def _colonnade_columns(results):
    """The columns of the results that are colonnades (more than one column in their row)."""
    if "n_columns" not in results.coords:
        return []
    return [str(c) for c, n in zip(results["column"].values, results["n_columns"].values) if int(n) > 1]


def _runs_colonnade(results, column, model):
    """Whether ``model`` ran the colonnade of ``column`` (not its column alone): its registry entry runs
    colonnades, or (a model the registry does not know) one of its runs named a body of the row."""
    entry = MD.of_results(results, model)
    if entry is not None:
        return "colonnade" in entry.bodies
    if "overturn_body" not in results.variables:
        return False
    parts = (classify_body(b) for b in np.unique(results["overturn_body"].sel(column=column, model=model).values))
    return any(p is not None and (p.column is not None or p.kind in ("epistyle block", "whole")) for p in parts)


def check_labels(results):
    """Refuse results whose ``overturn_body`` holds a label :func:`classify_body` cannot read, naming the file,
    the variable and the label (before anything is fitted or written)."""
    if "overturn_body" not in results.variables:
        return
    for label in np.unique(results["overturn_body"].values.astype(str)):
        try:
            classify_body(label)
        except InputError as err:
            raise InputError(f"{F._where(results)}: variable 'overturn_body': {err}") from None


def colonnade_cells(results):
    """``[(column, model), ...]``: each colonnade of the results with each model that ran it as a row."""
    return [(c, str(m)) for c in _colonnade_columns(results) for m in results["model"].values
            if _runs_colonnade(results, c, str(m))]


def _where_counted(results, mask, sel):
    """The flat boolean of the runs at ``sel`` that satisfy ``mask`` and that the fits count, with the dims
    in the order of :func:`pipeline.fragility._sample_dims`."""
    dims = [d for d in F._sample_dims(results) if d not in sel]
    keep = (mask.broadcast_like(results["overturned"]) & (F.counted(results) > 0)).sel(sel)
    return keep.transpose(*dims).values.ravel(), dims


def _values(results, name, sel, dims):
    return results[name].broadcast_like(results["overturned"]).sel(sel).transpose(*dims).values.ravel()


def _category(part, n_columns):
    if part is None:
        return FIRST[4]
    if part.kind == "epistyle block":
        return FIRST[2]
    if part.column is None:
        return FIRST[3]
    return FIRST[0] if part.column in (0, n_columns - 1) else FIRST[1]


def falls_first(results, column, model, angle=None):
    """Where the falls of one colonnade and model began.

    Parameters
    ----------
    results : xarray.Dataset
        Study results with ``overturn_body``, undecided runs resolved.
    column, model : str
    angle : float, optional
        One incidence angle [deg] (default: every angle pooled).

    Returns
    -------
    dict
        ``overturned``: runs that overturned [1]; per category of :data:`FIRST` the number that began
        there (``no body named``: runs counted as overturned that no body fell in, undecided runs
        counted so); ``most_often``: the parts (``"drum 1"``, ``"capital"``, ``"epistyle block 2"``)
        that began most falls, tied ones together, and ``most_often_runs``, how many each began.
    """
    sel = dict(column=column, model=model, **({} if angle is None else {"angle": angle}))
    fell, dims = _where_counted(results, F._valid(results) & (results["overturned"] > 0), sel)
    parts = [classify_body(b) for b in _values(results, "overturn_body", sel, dims)[fell]]
    n_columns = int(results["n_columns"].sel(column=column))
    out = {"overturned": len(parts), **dict.fromkeys(FIRST, 0)}
    out.update(Counter(_category(p, n_columns) for p in parts))
    bodies = Counter(p.part for p in parts if p is not None and p.kind != "whole")
    top = max(bodies.values(), default=0)
    out["most_often"] = [b for b, n in bodies.items() if n == top and top]
    out["most_often_runs"] = top
    return out


def epistyle_kept(results, column, model, scale=None, angle=None):
    """The epistyle of the runs of one colonnade and model that stood.

    Parameters
    ----------
    scale : float, optional
        One stripe (default: every stripe pooled).
    angle : float, optional
        One incidence angle [deg] (default: every angle pooled).

    Returns
    -------
    dict
        ``stood`` [1], the runs that stood with an epistyle; ``slip_50``, ``slip_90``, ``opening_50``,
        ``opening_90`` [m]: the percentiles :data:`PERCENTILES` of ``epistyle_slip`` and
        ``epistyle_opening`` over them (NaN without one).
    """
    sel = dict(column=column, model=model)
    sel.update({k: v for k, v in (("scale", scale), ("angle", angle)) if v is not None})
    stood_mask = F._valid(results) & (results["overturned"] == 0) & np.isfinite(results["epistyle_slip"])
    stood, dims = _where_counted(results, stood_mask, sel)
    out = {"stood": int(stood.sum())}
    for name, key in (("epistyle_slip", "slip"), ("epistyle_opening", "opening")):
        values = _values(results, name, sel, dims)[stood]
        for q in PERCENTILES:
            out[f"{key}_{q:.0f}"] = float(np.percentile(values, q)) if values.size else np.nan
    return out


def _with_epistyle(results):
    if "epistyle_slip" not in results.variables:
        return []
    return [(c, m) for c, m in colonnade_cells(results)
            if bool(np.isfinite(results["epistyle_slip"].sel(column=c, model=m)).any())]


def _angles(results, model):
    """The incidence angles a model's colonnade numbers are also given at: each, when it depends on them."""
    if results.sizes["angle"] < 2 or MD.flag(results, model, "angle_invariant"):
        return []
    return [float(a) for a in results["angle"].values]


def _stripe(results, scale, fmt):
    return f"{fmt(float(scale) / G)} g" if F.in_stripes(results) else f"x {fmt(float(scale))}"


def colonnade_section(results, fmt):
    """Markdown lines: "What falls first, and what the standing ones keep" ([] without a colonnade run as
    a row). ``fmt`` writes a number as the report does."""
    cells = colonnade_cells(results)
    if not cells:
        return []
    lines = ["## What falls first, and what the standing ones keep", ""]
    if "overturn_body" in results.variables:
        lines += ["Of the runs that overturned, the body that lay down or fell first (`overturn_body`): in an end "
                  "column (column 1 or the last), an inner column or an epistyle block; a model that runs the "
                  "colonnade as one body (the rigid frame) fell as one. *Most often*: the part of a column or the "
                  "block that began the most falls. Runs are counted as the fits count them (every record, stripe"
                  + (", seed" if "seed" in results.dims else "") + " and angle).", "",
                  "| structure | model | angle [deg] | overturned | " + " | ".join(FIRST[:4]) + " | most often |",
                  "|---|---|---|---|---|---|---|---|---|"]
        unnamed = 0
        for c, m in cells:
            for a in [None, *_angles(results, m)]:
                first = falls_first(results, c, m, a)
                unnamed += first[FIRST[4]] if a is None else 0
                often = (f"{', '.join(first['most_often'])} ({first['most_often_runs']}"
                         + (" each)" if len(first["most_often"]) > 1 else ")")) if first["most_often"] else "n/a"
                lines.append(f"| {c} | {m} | {'all' if a is None else fmt(a)} | {first['overturned']} | "
                             + " | ".join(str(first[k]) for k in FIRST[:4]) + f" | {often} |")
        lines.append("")
        if unnamed:
            lines += [f"{unnamed} run(s) counted as overturned name no body: undecided at their settle limit and "
                      "counted so (above).", ""]
    kept = _with_epistyle(results)
    if kept:
        lines += ["Of the runs that stood, the residual slip of the epistyle blocks on their capitals (the largest "
                  "of the row, `epistyle_slip`) and the widest opening of a head joint between blocks "
                  "(`epistyle_opening`) at the end of the run [mm]: median and 90th percentile at each stripe, "
                  "then over every stripe (and over every stripe at each angle).", "",
                  "| structure | model | stripe | angle [deg] | runs stood | slip median | slip 90 % | opening median "
                  "| opening 90 % |", "|---|---|---|---|---|---|---|---|---|"]
        for c, m in kept:
            groups = [(s, None) for s in results["scale"].values] + [(None, None)]
            groups += [(None, a) for a in _angles(results, m)]
            for s, a in groups:
                e = epistyle_kept(results, c, m, s, a)
                stats = " | ".join(fmt(1e3 * e[f"{k}_{q:.0f}"]) for k in ("slip", "opening") for q in PERCENTILES)
                lines.append(f"| {c} | {m} | {'all' if s is None else _stripe(results, s, fmt)} | "
                             f"{'all' if a is None else fmt(a)} | {e['stood']} | {stats} |")
        lines.append("")
    return lines


def _dislocation_states(frag):
    return [str(s) for s, kind in zip(frag["state"].values, frag["state_measure"].values)
            if str(kind) == "dislocation_ratio"] if "state_measure" in frag.coords else []


def dislocation_section(results, frag, fmt):
    """Markdown lines: the fitted damage states by drum dislocation of every model that runs drums ([] when
    the fragility has none)."""
    states = _dislocation_states(frag)
    models = [str(m) for m in frag["model"].values if MD.flag(results, str(m), "drums")]
    if not states or not models:
        return []
    banded = "median_lower" in frag
    head = []
    for state in states:
        s = float(frag["state_threshold"].sel(state=state))
        words = next((w for t, w in DISLOCATION_WORDS.items() if np.isclose(t, s)), None)
        head.append(f"{words.split(':')[0] if words else state}: slip >= {fmt(100 * s)} % of D")
    lines = ["## Damage states by drum dislocation", "",
             "A bed joint's residual slip s over its diameter D (`dislocation_ratio`, the largest of the structure's "
             "bed joints) reaching a threshold, or the run overturned (docs/fragility.md): "
             + "; ".join(f"{fmt(100 * t)} % of D, {w}" for t, w in DISLOCATION_WORDS.items()) + ". A drum slid by s "
             "carries the part above on a lever arm shortened from D/2 to D/2 - s, so its resistance to overturning "
             "drops by 2 s/D. Median PGA [g] of each state" + (" with its bootstrap band" if banded else "")
             + ", and the runs that reached it; a column without bed joints reaches these only by overturning.", "",
             "| structure | model | " + " | ".join(head) + " |", "|---|---|" + "---|" * len(head)]
    for c in frag["column"].values:
        for m in models:
            cells = []
            for state in states:
                cell = frag.sel(state=state, column=c, model=m)
                cells.append(f"{median_text(cell, fmt)}; {int(cell['n_exceed'])} / {int(cell['n_runs'])}")
            lines.append(f"| {c} | {m} | " + " | ".join(cells) + " |")
    return lines + [""]


def colonnade_columns(results, column, model):
    """The pooled numbers of :func:`falls_first` and :func:`epistyle_kept` for one row of ``summary.csv``
    (empty where the model did not run ``column`` as a colonnade)."""
    names = [f"first_{k.replace(' ', '_')}" for k in FIRST] + ["first_most_often"] + [
        f"epistyle_{k}_{q:.0f}_mm" for k in ("slip", "opening") for q in PERCENTILES] + ["epistyle_runs_stood"]
    out = dict.fromkeys(names, "")
    if (column, model) in colonnade_cells(results) and "overturn_body" in results.variables:
        first = falls_first(results, column, model)
        out.update({f"first_{k.replace(' ', '_')}": first[k] for k in FIRST})
        out["first_most_often"] = " / ".join(first["most_often"])
    if (column, model) in _with_epistyle(results):
        e = epistyle_kept(results, column, model)
        out.update({f"epistyle_{k}_{q:.0f}_mm": 1e3 * e[f"{k}_{q:.0f}"] for k in ("slip", "opening")
                    for q in PERCENTILES})
        out["epistyle_runs_stood"] = e["stood"]
    return out
