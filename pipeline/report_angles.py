"""The probability of overturning by incidence angle, for the report.

The report's main fragility pools a study's incidence angles: every angle's run of a record is one
more observation of that record. That answers "how likely is this structure to fall under these
records, from any direction". A colonnade is not axisymmetric, and the question asked of it is
another: is it weaker across its row (90 deg) than along it (0 deg)? So for every model that feels
the direction (its registry entry is not ``angle_invariant``) each angle's runs are fitted on their
own here, with the same records, estimator and bootstrap as the pooled fit, and tabled and drawn
side by side. (A planar model's outcome against the angle is the report's polar figure.)

:func:`fragility_by_angle` fits, :func:`angle_section` writes the Markdown, :func:`plot_angle_medians`
draws the medians with their bands.
"""

import numpy as np
import xarray as xr

from pipeline import fragility as F
from pipeline import models as MD
from pipeline.units import G

__all__ = ["angled_models", "fragility_by_angle", "angle_section", "plot_angle_medians"]

#: The fits that have a median: maximum likelihood, or the step between perfectly separated runs.
_HAS_MEDIAN = (F.FIT_OK, F.FIT_SEPARATED)


def angled_models(results):
    """The 3D models of ``results`` whose runs depend on the incidence angle, when it ran more than one.

    A planar model feels the direction too, but only through the component along it: the report
    draws its outcome against the angle already (``angle_polar``).
    """
    if results.sizes.get("angle", 1) < 2:
        return []
    return [str(m) for m in results["model"].values
            if not (MD.flag(results, str(m), "angle_invariant") or MD.flag(results, str(m), "planar"))]


def fragility_by_angle(results, bootstrap=0, seed=0, confidence=F.DEFAULT_CONFIDENCE):
    """Overturning fragility fitted at each incidence angle on its own.

    Parameters
    ----------
    results : xarray.Dataset
        Study results (:func:`pipeline.fragility.open_results`).
    bootstrap : int
        Resamples of the records for the bands (0: none).
    seed : int
        Seed of the resampling (the same at every angle, so that each angle resamples the same
        records).
    confidence : float
        Level of the bands [1].

    Returns
    -------
    xarray.Dataset or None
        The variables of :func:`pipeline.fragility.fragility` for the state ``overturning`` and the
        models of :func:`angled_models`, with a dimension ``angle`` [deg]; None when no model
        depends on the angle or the study ran one angle.
    """
    models = angled_models(results)
    if not models:
        return None
    fits = []
    for angle in results["angle"].values:
        one = results.sel(angle=[angle], model=models)
        fit = F.fragility(one, im="pga", states=(), bootstrap=bootstrap, seed=seed,
                          confidence=confidence)
        keep = [v for v in ("median", "median_lower", "median_upper", "beta", "fit_status", "n_runs", "n_exceed")
                if v in fit]
        fits.append(fit[keep].sel(state="overturning", drop=True).expand_dims(angle=[float(angle)]))
    out = xr.concat(fits, dim="angle")
    out["angle"].attrs.update(units="degree", long_name="incidence angle from the row (0: along it)")
    out.attrs.update(confidence_level=confidence, bootstrap_replicates=bootstrap)
    return out


def _stripe_counts(results, column, model, angle):
    """Overturned runs of a cell at each stripe of a study in stripes (:func:`pipeline.fragility.in_stripes`)."""
    cell = dict(column=column, model=model, angle=angle)
    valid = F._valid(results).sel(cell) & (F.counted(results).sel(cell) > 0)  # a perfect model's seeds once
    over = (results["overturned"].sel(cell) > 0) & valid
    return [int(over.sel(scale=s).sum()) for s in results["scale"].values]


def _median_text(fit, fmt):
    """The median PGA [g] and its band as the report writes it, or why there is none."""
    status = int(fit["fit_status"])
    if status not in _HAS_MEDIAN:
        return F.FIT_STATUS[status].replace("_", " ")
    text = fmt(float(fit["median"]) / G)
    if "median_lower" in fit and np.isfinite(float(fit["median_lower"])):
        text += f" ({fmt(float(fit['median_lower']) / G)} to {fmt(float(fit['median_upper']) / G)})"
    return text


def angle_section(results, by_angle, fmt):
    """Markdown lines: the table of :func:`fragility_by_angle` ([] when it is None).

    Parameters
    ----------
    results : xarray.Dataset
        The study results the fits were made from (for the runs' counts per stripe).
    by_angle : xarray.Dataset or None
        From :func:`fragility_by_angle`.
    fmt : callable
        Formats a number as the rest of the report does.
    """
    if by_angle is None:
        return []
    stripes = F.in_stripes(results)
    band = (f", {100 * by_angle.attrs['confidence_level']:g} % bootstrap band over the records "
            f"({by_angle.attrs['bootstrap_replicates']} replicates)") if by_angle.attrs["bootstrap_replicates"] else ""
    lines = ["## Probability of overturning by incidence angle", "",
             "The fits above pool the incidence angles. Here each angle's runs are fitted on their own (the same "
             "records, maximum likelihood" + band + "), for each model whose runs depend on the direction of "
             "shaking in space (a planar model's are in its polar figure); "
             "a colonnade's angle is measured from its row (0: along it, 90: across it).", ""]
    head = "| column | model | angle [deg] | median PGA [g] | dispersion beta | overturned / runs |"
    if stripes:
        head += " overturned at " + ", ".join(fmt(float(s) / G) for s in results["scale"].values) + " g |"
    lines += [head, "|" + "---|" * (head.count("|") - 1)]
    for c in by_angle["column"].values:
        for m in by_angle["model"].values:
            for a in by_angle["angle"].values:
                fit = by_angle.sel(column=c, model=m, angle=a)
                row = (f"| {c} | {str(m).upper()} | {fmt(float(a))} | {_median_text(fit, fmt)} | "
                       f"{fmt(float(fit['beta'])) if int(fit['fit_status']) in _HAS_MEDIAN else 'n/a'} | "
                       f"{int(fit['n_exceed'])} / {int(fit['n_runs'])} |")
                if stripes:
                    row += " " + " / ".join(map(str, _stripe_counts(results, c, str(m), a))) + " |"
                lines.append(row)
    return lines + [""]


def plot_angle_medians(by_angle, stem, title=None):
    """Median PGA of overturning against the incidence angle, with its band, a line per column.

    Parameters
    ----------
    by_angle : xarray.Dataset
        From :func:`fragility_by_angle`.
    stem : str
        Path without extension.
    title : str, optional

    Returns
    -------
    list of str
        The files written (PNG and PDF).
    """
    from pipeline.plotting_fragility import _save, plt
    from pipeline.models import title as model_title

    models = [str(m) for m in by_angle["model"].values]
    columns = [str(c) for c in by_angle["column"].values]
    angles = by_angle["angle"].values.astype(float)
    spread = 0.012 * (np.ptp(angles) or 90.0)  # columns side by side at each angle, so their bars do not hide
    fig, axes = plt.subplots(1, len(models), figsize=(4.2 + 2.8 * len(models), 4.6), constrained_layout=True,
                             squeeze=False)
    for ax, m in zip(axes[0], models):
        for i, c in enumerate(columns):
            cell = by_angle.sel(column=c, model=m)
            ok = np.isin(cell["fit_status"].values, _HAS_MEDIAN)
            med = np.where(ok, cell["median"].values / G, np.nan)
            x = angles + (i - (len(columns) - 1) / 2) * spread
            if "median_lower" in cell:
                lo, hi = cell["median_lower"].values / G, cell["median_upper"].values / G
                err = np.array([np.where(ok, med - lo, np.nan), np.where(ok, hi - med, np.nan)])
                ax.errorbar(x, med, yerr=np.nan_to_num(err), fmt="o-", capsize=3, label=c)
            else:
                ax.plot(x, med, "o-", label=c)
        ax.set_xticks(angles, [f"{a:g}" for a in angles])
        ax.set_xlabel("incidence angle [deg] (0: along the row, 90: across it)")
        ax.set_ylabel("median PGA of overturning [g]")
        ax.set_title(model_title(m), fontsize="small", loc="left")
        ax.grid(True, alpha=0.3)
        # below the axes: inside, it hid the upper ends of the bands
        ax.legend(title="column", fontsize="small", loc="upper center", bbox_to_anchor=(0.5, -0.16),
                  ncol=min(len(columns), 4))
    band = (f"; bars: {100 * by_angle.attrs['confidence_level']:g} % bootstrap band over records"
            if by_angle.attrs["bootstrap_replicates"] else "")
    fig.suptitle(title or "Median PGA of overturning at each incidence angle" + band, fontsize="medium")
    return _save(fig, stem)
