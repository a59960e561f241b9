"""What the report says of runs undecided at their settle limit, and what counting them otherwise moves.

A run still able to fall when it reached its settle limit (the cap of simulated time after the
record and its tail, ``settle_limit``) neither stood nor fell. Since issue 47 such runs enter the
fits as a stated choice (:data:`pipeline.fragility.DEFAULT_UNDECIDED`: as runs that stood), and the
report measures the choice both ways: the median of overturning with them counted as standing and
as overturned, per structure and model, beside the count. A study with no undecided run says so.

:func:`undecided_effect` fits; :func:`undecided_lines` writes the Markdown.
"""

import math

from pipeline import fragility as F
from pipeline.units import G

__all__ = ["undecided_effect", "undecided_lines"]




def undecided_effect(results, im="pga"):
    """The median of overturning with the undecided runs counted each way.

    Parameters
    ----------
    results : xarray.Dataset
        Study results.
    im : str
        Intensity measure of the fits.

    Returns
    -------
    dict
        ``{choice: DataArray (column, model) of the median [IM units]}`` for ``"standing"`` and
        ``"overturned"`` (NaN where that fit has no median).
    """
    out = {}
    for choice in ("standing", "overturned"):
        frag = F.fragility(results, im=im, states=(), dislocations=(), undecided=choice)
        out[choice] = frag["median"].sel(state="overturning", drop=True)
    return out


def undecided_lines(results, settle_limit=None):
    """Markdown lines: how many runs were undecided, how they count, and what the other way moves.

    Parameters
    ----------
    results : xarray.Dataset
        Study results, resolved (:func:`pipeline.fragility.resolve_undecided`) or not.
    settle_limit : float, optional
        The cap of free motion after the tail [s], if the study states one.
    """
    choice = F.undecided_choice(results)
    results = F._normalise(results, F._where(results))
    counts = F._undecided_runs(results)  # (column, model), angle-invariant models' runs counted once
    total = int(counts.sum())
    cap = f" ({settle_limit:g} s of still ground after the record and its tail)" if settle_limit else ""
    if total == 0:
        return [f"- No run was undecided: every run stood for good or fell within its settle limit{cap}."]
    lines = [f"- **{total} run(s) undecided**: still able to fall when they reached their settle limit{cap}. "
             f"They count as **{choice}** in every fit and count below"
             + (" (the stated choice: they had not fallen when the cap ran out)" if choice == "standing" else "")
             + "; counted the other way, the median PGA of overturning would be:", "",
             "| structure | model | undecided | median PGA [g], as standing | as overturned |", "|---|---|---|---|---|"]
    effect = undecided_effect(results)
    for i, c in enumerate(results["column"].values):
        for j, m in enumerate(results["model"].values):
            n = int(counts[i, j])
            if n:
                g = [float(effect[k].sel(column=c, model=m)) / G for k in ("standing", "overturned")]
                lines.append(f"| {c} | {m} | {n} | " + " | ".join("n/a" if not math.isfinite(v) else f"{v:.3g}"
                                                                   for v in g) + " |")
    return lines + [""]
