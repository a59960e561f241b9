"""Model against model on the same study: medians with bands, cell-by-cell outcomes, peak ratios.

A study that runs several models (or variants of one, ``[models.NAME]`` in the study file) on
the same columns, records, angles and scales can be asked whether its models agree, and a
single chaotic run cannot answer that: 5 % more shaking, another step or another model flips
one run's outcome. So models are compared the way their users judge them, by statistics:

* the median intensity of overturning of each model with its bootstrap band over records
  (:func:`pipeline.fragility.fragility`), and whether a model's median lies inside the
  reference model's band;
* cell by cell: over the (record, angle, scale) cells both models ran without failure, how
  often they agree on overturning, and how often only one of them overturned;
* the ratio of their peak tilts on the cells where neither overturned (median and the 10th
  and 90th percentiles).

Every model is compared with one reference, the study's first model unless another is named.
"""

import math

import numpy as np
import xarray as xr

from pipeline.dataset import annotate, append_history
from pipeline.errors import InputError
from pipeline.fragility import _normalise, _sample_dims, _valid, _where, counted
from pipeline.models import results_title
from pipeline.units import G

__all__ = ["merge_results", "reference_model", "compare_models", "outcome_agreement", "peak_ratio", "comparison_rows",
           "markdown_section"]

#: The percentiles of the peak ratio stated beside its median [%].
RATIO_PERCENTILES = (10.0, 90.0)


def merge_results(datasets):
    """Results of several files on the same cells as one, their models side by side.

    For a comparison of models run apart: two studies of the same grid, or a peer engine's
    cells written in the layout of a study's results. A variable one file lacks is NaN for its
    models.

    Parameters
    ----------
    datasets : sequence of xarray.Dataset
        Study results (:func:`pipeline.fragility.open_results`), with the same columns, records,
        incidence angles and scales, and models of distinct names.

    Returns
    -------
    xarray.Dataset
        Concatenated along ``model``; the attributes of the first, its ``history`` followed by
        the others'.
    """
    datasets = [_normalise(ds, _where(ds)) for ds in datasets]
    first = datasets[0]
    seen = {}
    for ds in datasets:
        for dim in ("column", "record", "angle", "scale"):
            a, b = np.asarray(first[dim].values), np.asarray(ds[dim].values)
            same = a.shape == b.shape and (np.array_equal(a, b) if a.dtype.kind == "f" else list(a) == list(b))
            if not same:
                raise InputError(f"{_where(ds)}: its {dim} values differ from those of {_where(first)}; results "
                                 "are compared cell by cell, so give files of the same columns, records, angles "
                                 "and scales")
        if ds["scale"].attrs.get("units", "1") != first["scale"].attrs.get("units", "1"):
            raise InputError(f"{_where(ds)}: its scale is in {ds['scale'].attrs.get('units', '1')!r}, that of "
                             f"{_where(first)} in {first['scale'].attrs.get('units', '1')!r}; scale both the same way")
        for m in ds["model"].values:
            if str(m) in seen:
                raise InputError(f"model {str(m)!r} is in both {seen[str(m)]} and {_where(ds)}; each model may "
                                 "come from one file")
            seen[str(m)] = _where(ds)
    if len(datasets) == 1:
        return first
    # what does not vary with the model (the records' intensities, the columns' dimensions) is the first file's
    keep = set(first.dims)
    datasets = [first] + [ds.drop_vars([n for n, v in ds.variables.items() if "model" not in v.dims and n not in keep])
                          for ds in datasets[1:]]
    # a coordinate along the models that some files lack: their models are the registry's own (base_model)
    labels = {n: v for ds in datasets for n, v in ds.coords.items() if "model" in v.dims and n != "model"}
    for k, ds in enumerate(datasets):
        for name, like in labels.items():
            if name not in ds.coords:
                models = [str(m) for m in ds["model"].values]
                fill = models if name == "base_model" else [""] * len(models) if like.dtype.kind in "OUS" \
                    else [math.nan] * len(models)
                datasets[k] = ds = ds.assign_coords({name: ("model", fill, dict(like.attrs))})
    merged = xr.concat(datasets, dim="model", data_vars="minimal", coords="minimal", compat="override",
                       join="outer", combine_attrs="override")
    merged.attrs["history"] = "\n".join(str(ds.attrs.get("history", "")) for ds in datasets if ds.attrs.get("history"))
    merged.attrs["source_file"] = ", ".join(_where(ds) for ds in datasets)
    return merged


def _cells(results, column, reference, model):
    """The (record, angle[, seed], scale) cells of a column that both models ran without failure.

    An angle-invariant model ran once per record and scale, a model of perfect drums once over the
    seeds of a study of imperfect drums; where both models only repeat a run, the repeat is not
    counted (:func:`pipeline.fragility.counted`).

    Returns
    -------
    numpy.ndarray of bool
        Dims (record, angle[, seed], scale).
    """
    dims = _sample_dims(results)
    valid = _valid(results).broadcast_like(results["overturned"]).transpose(*dims).sel(column=column)
    once = counted(results).sel(column=column) > 0
    pair = [valid.sel(model=m) for m in (reference, model)]
    return (pair[0] & pair[1] & (once.sel(model=reference) | once.sel(model=model))).values


def outcome_agreement(results, column, reference, model):
    """Cell-by-cell overturning of two models on one column.

    Parameters
    ----------
    results : xarray.Dataset
        Study results (dims column, record, angle, scale, model) with ``overturned``.
    column, reference, model : str
        The column, the reference model and the model compared with it.

    Returns
    -------
    dict
        ``cells`` (run by both without failure), ``same`` (both overturned or both stood),
        ``reference_only`` (only the reference overturned) and ``model_only`` (only the model
        overturned); counts [1].
    """
    both = _cells(results, column, reference, model)
    over = results["overturned"].transpose(*_sample_dims(results)).sel(column=column)
    a = over.sel(model=reference).values.astype(bool)[both]
    b = over.sel(model=model).values.astype(bool)[both]
    return {"cells": int(both.sum()), "same": int(np.sum(a == b)), "reference_only": int(np.sum(a & ~b)),
            "model_only": int(np.sum(b & ~a))}


def peak_ratio(results, column, reference, model, variable="peak_theta"):
    """Peak response of a model over the reference's, on the cells where neither overturned.

    Parameters
    ----------
    results : xarray.Dataset
    column, reference, model : str
    variable : str
        The peak compared (default ``peak_theta``, the peak tilt [rad]: a column's, or a
        stack's top body's).

    Returns
    -------
    dict
        ``cells`` [1] where both stood and the reference's peak is positive, ``median``,
        ``p10``, ``p90`` of the ratio [1] (NaN without such cells).
    """
    both = _cells(results, column, reference, model)
    over = results["overturned"].transpose(*_sample_dims(results)).sel(column=column)
    peak = results[variable].transpose(*_sample_dims(results)).sel(column=column)
    stood = both & ~over.sel(model=reference).values.astype(bool) & ~over.sel(model=model).values.astype(bool)
    a, b = peak.sel(model=reference).values[stood], peak.sel(model=model).values[stood]
    keep = np.isfinite(a) & np.isfinite(b) & (a > 0)
    ratio = b[keep] / a[keep]
    if ratio.size == 0:
        return {"cells": 0, "median": math.nan, "p10": math.nan, "p90": math.nan}
    p10, med, p90 = np.percentile(ratio, [RATIO_PERCENTILES[0], 50.0, RATIO_PERCENTILES[1]])
    return {"cells": int(ratio.size), "median": float(med), "p10": float(p10), "p90": float(p90)}


def reference_model(results, reference=None, label="reference model"):
    """The model of ``results`` every other is compared with: ``reference``, or the first model.

    Cheap (it reads the ``model`` coordinate only), so that a command checks the name before it
    computes anything.

    Parameters
    ----------
    results : xarray.Dataset
        Study results, or several merged (:func:`merge_results`).
    reference : str, optional
        A model of the results.
    label : str
        How the reference was given, for the message (``"--reference"``).

    Raises
    ------
    pipeline.errors.InputError
        ``reference`` is not a model of the results, naming them.
    """
    models = [str(m) for m in results["model"].values]
    if reference is None:
        return models[0]
    if reference not in models:
        raise InputError(f"{label} {reference!r} is not a model of {_where(results)}; its models are "
                         f"{', '.join(models)}: give one of them")
    return reference


def compare_models(results, frag, reference=None, state="overturning"):
    """Every model of a study against a reference model, per column.

    Parameters
    ----------
    results : xarray.Dataset
        Study results (dims column, record, angle, scale, model).
    frag : xarray.Dataset
        Their fragility (:func:`pipeline.fragility.fragility`), with bootstrap bounds
        (``median_lower``, ``median_upper``) for the band test.
    reference : str, optional
        The model the others are compared with (default: the first model of the study).
    state : str
        The damage state whose medians are compared (default ``overturning``, whose cells are
        also compared one by one).

    Returns
    -------
    xarray.Dataset
        Dims (column, model), ``model`` the models other than the reference; medians [IM
        units] with their bands for both, ``median_ratio`` [1], ``inside_reference_band``
        (flag), the cell counts of :func:`outcome_agreement` and the peak-tilt ratios of
        :func:`peak_ratio`. Empty of models when the study has one model.
    """
    results = _normalise(results, _where(results))
    models = [str(m) for m in results["model"].values]
    reference = reference_model(results, reference)
    others = [m for m in models if m != reference]
    columns = [str(c) for c in results["column"].values]
    sub = frag.sel(state=state)
    units = frag["median"].attrs.get("units", "")
    banded = "median_lower" in frag

    def med(name, m):
        return sub[name].sel(model=m).values.astype(float) if name in sub else np.full(len(columns), math.nan)

    shape = (len(columns), len(others))
    out = {k: np.full(shape, math.nan) for k in ("median", "median_lower", "median_upper", "median_reference",
                                                  "median_reference_lower", "median_reference_upper", "median_ratio",
                                                  "peak_ratio_median", "peak_ratio_p10", "peak_ratio_p90")}
    counts = {k: np.zeros(shape, np.int32) for k in ("cells", "same", "reference_only", "model_only",
                                                     "peak_ratio_cells")}
    inside = np.zeros(shape, np.int8)
    for j, m in enumerate(others):
        out["median"][:, j], out["median_reference"][:, j] = med("median", m), med("median", reference)
        out["median_lower"][:, j], out["median_upper"][:, j] = med("median_lower", m), med("median_upper", m)
        out["median_reference_lower"][:, j] = med("median_lower", reference)
        out["median_reference_upper"][:, j] = med("median_upper", reference)
        for i, c in enumerate(columns):
            a, b = out["median_reference"][i, j], out["median"][i, j]
            out["median_ratio"][i, j] = b / a if np.isfinite(a) and np.isfinite(b) and a > 0 else math.nan
            lo, hi = out["median_reference_lower"][i, j], out["median_reference_upper"][i, j]
            inside[i, j] = bool(banded and np.isfinite(b) and lo <= b <= hi)
            agree = outcome_agreement(results, c, reference, m)
            for k in ("cells", "same", "reference_only", "model_only"):
                counts[k][i, j] = agree[k]
            ratio = peak_ratio(results, c, reference, m)
            counts["peak_ratio_cells"][i, j] = ratio["cells"]
            out["peak_ratio_median"][i, j], out["peak_ratio_p10"][i, j], out["peak_ratio_p90"][i, j] = (
                ratio["median"], ratio["p10"], ratio["p90"])
    dims = ("column", "model")
    level = f"{100 * frag.attrs.get('confidence_level', 0.9):g} %"
    im_units = {"units": units}
    data = {
        "median": (dims, out["median"], {**im_units, "long_name": f"median intensity of {state} of the model"}),
        "median_lower": (dims, out["median_lower"], {**im_units, "long_name": f"lower bound of the model's median, {level} bootstrap"}),
        "median_upper": (dims, out["median_upper"], {**im_units, "long_name": f"upper bound of the model's median, {level} bootstrap"}),
        "median_reference": (dims, out["median_reference"], {**im_units, "long_name": f"median intensity of {state} of the reference model"}),
        "median_reference_lower": (dims, out["median_reference_lower"], {**im_units, "long_name": f"lower bound of the reference's median, {level} bootstrap"}),
        "median_reference_upper": (dims, out["median_reference_upper"], {**im_units, "long_name": f"upper bound of the reference's median, {level} bootstrap"}),
        "median_ratio": (dims, out["median_ratio"], {"units": "1", "long_name": "median of the model over median of the reference"}),
        "inside_reference_band": (dims, inside, {"units": "1", "flag_values": np.array([0, 1], np.int8),
                                                 "flag_meanings": "outside inside",
                                                 "long_name": "the model's median lies inside the reference's bootstrap band"}),
        "cells": (dims, counts["cells"], {"units": "1", "long_name": "(record, angle, scale) cells both models ran without failure"}),
        "same": (dims, counts["same"], {"units": "1", "long_name": f"cells where both models agree on {state}"}),
        "reference_only": (dims, counts["reference_only"], {"units": "1", "long_name": "cells where only the reference overturned"}),
        "model_only": (dims, counts["model_only"], {"units": "1", "long_name": "cells where only the model overturned"}),
        "peak_ratio_cells": (dims, counts["peak_ratio_cells"], {"units": "1", "long_name": "cells where both stood (peak ratios)"}),
        "peak_ratio_median": (dims, out["peak_ratio_median"], {"units": "1", "long_name": "median of peak_theta of the model over the reference's, where both stood"}),
        "peak_ratio_p10": (dims, out["peak_ratio_p10"], {"units": "1", "long_name": "10th percentile of the peak_theta ratio"}),
        "peak_ratio_p90": (dims, out["peak_ratio_p90"], {"units": "1", "long_name": "90th percentile of the peak_theta ratio"}),
    }
    ds = xr.Dataset(data, coords={"column": columns, "model": others})
    for name in ("base_model", "model_variant"):  # a study's variants: which model each is, and how
        if name in results.coords and results[name].dims == ("model",):
            ds.coords[name] = ("model", [str(results[name].sel(model=m).values) for m in others])
    ds.attrs["reference_title"] = results_title(results, reference)
    own = {name: dict(var.attrs) for name, var in ds.variables.items()}
    annotate(ds, catalog={})  # Conventions and source only: these variables are not the study's
    for name, attrs in own.items():
        ds[name].attrs = attrs
    ds.attrs.update(title="Model against model on one study", reference_model=reference, state=state,
                    intensity_measure=frag.attrs.get("intensity_measure", "pga"),
                    confidence_level=float(frag.attrs.get("confidence_level", math.nan)),
                    bootstrap_replicates=int(frag.attrs.get("bootstrap_replicates", 0)),
                    comment="every model against the reference model on the (record, angle, scale) cells both "
                    "ran without failure; the medians and bands are those of the study's fragility")
    for key in ("study", "study_digest", "source_file", "title"):
        if key in results.attrs:
            ds.attrs[f"results_{key}"] = str(results.attrs[key])
    append_history(ds, f"pipeline.comparison reference={reference} state={state}")
    return ds


def comparison_rows(comparison):
    """The comparison as rows (one per column and model), for tables and CSV.

    Returns
    -------
    list of dict
    """
    rows = []
    for c in comparison["column"].values:
        for m in comparison["model"].values:
            cell = comparison.sel(column=c, model=m)
            row = {"column": str(c), "reference": comparison.attrs["reference_model"], "model": str(m)}
            for name in comparison.data_vars:
                value = cell[name].values
                row[name] = int(value) if value.dtype.kind in "iub" else float(value)
            rows.append(row)
    return rows


def _g(value):
    """An intensity [m/s^2] in g, three significant digits ("n/a" if none)."""
    return f"{value / G:.3g}" if np.isfinite(value) else "n/a"


def _band(lo, hi):
    return f"{_g(lo)}-{_g(hi)}" if np.isfinite(lo) or np.isfinite(hi) else "no band"


def markdown_section(comparison):
    """The report's section "Model against model" (Markdown lines).

    Parameters
    ----------
    comparison : xarray.Dataset
        From :func:`compare_models`, on PGA.

    Returns
    -------
    list of str
    """
    reference = comparison.attrs["reference_model"]
    level = f"{100 * comparison.attrs.get('confidence_level', 0.9):g} %"
    lines = [f"## Model against model (reference: {comparison.attrs.get('reference_title', reference)}, "
             f"`{reference}`)", "",
             "A single run near the capacity of a column is chaotic: a little more shaking, another step or "
             "another model can flip its outcome. Models are therefore compared by statistics: the median PGA "
             f"of overturning with its {level} bootstrap band over records (is a model's median inside the "
             "reference's band?), cell by cell over the (record, angle, scale) cells both models ran (how often "
             "they agree on overturning, and which one alone overturned), and the ratio of their peak tilts "
             "where both stood (median and 10th-90th percentiles).", "",
             "| column | model | median PGA [g] (band) | reference [g] (band) | inside the reference's band | "
             "cells | same outcome | only the reference overturned | only the model overturned | "
             "peak tilt / reference's (p10-p90) |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for row in comparison_rows(comparison):
        cells = row["cells"]
        same = f"{row['same']} ({100 * row['same'] / cells:.0f} %)" if cells else "0"
        ratio = (f"{row['peak_ratio_median']:.2f} ({row['peak_ratio_p10']:.2f}-{row['peak_ratio_p90']:.2f}), "
                 f"{row['peak_ratio_cells']} cells" if row["peak_ratio_cells"] else "no cell where both stood")
        inside = "yes" if row["inside_reference_band"] else (
            "no" if np.isfinite(row["median"]) and np.isfinite(row["median_reference_lower"]) else "n/a")
        lines.append(f"| {row['column']} | {results_title(comparison, row['model'])} (`{row['model']}`) | {_g(row['median'])} "
                     f"({_band(row['median_lower'], row['median_upper'])}) | {_g(row['median_reference'])} "
                     f"({_band(row['median_reference_lower'], row['median_reference_upper'])}) | {inside} | {cells} | "
                     f"{same} | {row['reference_only']} | {row['model_only']} | {ratio} |")
    lines += ["", "The same numbers are in `comparison.csv` and `comparison.nc`.", ""]
    return lines
