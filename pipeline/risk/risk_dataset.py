"""The risk dataset: :func:`site_risk` integrates every site, damage state, column and model of a fragility
against a hazard curve into one CF Dataset, with its coordinates and ``risk_flag``.

Where the fragility's median lies beyond the curve's last level, most of the risk comes from the
extrapolation and the result is flagged (``risk_flag``) and warned about. Where the first segment
falls so steeply that, extended below a_0, the integral passes the largest float, ``central`` is NaN
with ``risk_flag`` ``integral_overflows`` (:func:`pipeline.risk.words.no_risk_reason` says which
segment); ``lower`` remains.
"""

import math
import os
import warnings

import numpy as np
import xarray as xr

from pipeline import fragility as F
from pipeline.dataset import annotate, append_history
from pipeline.errors import HazardWarning, InputError
from pipeline.risk.fragility_file import check_im, fragility_im
from pipeline.risk.hazard import usable_curve
from pipeline.risk.integral import RISK_SHARES, _integrand, _shares, probability_in, return_period, risk_integral
from pipeline.units import G


#: Default period of the probability stated [yr].
DEFAULT_YEARS = 50.0

#: risk_flag values: how far a number rests on the data (CF flag_values / flag_meanings).
RISK_OK, RISK_MEDIAN_BEYOND, RISK_NO_EXCEEDANCE, RISK_ALL_EXCEED, RISK_NO_FIT, RISK_OVERFLOW = range(6)
RISK_FLAGS = {
    RISK_OK: "ok",
    RISK_MEDIAN_BEYOND: "median_beyond_hazard_curve",
    RISK_NO_EXCEEDANCE: "no_median_no_exceedance_observed",
    RISK_ALL_EXCEED: "no_median_every_run_exceeds",
    RISK_NO_FIT: "no_fit",
    RISK_OVERFLOW: "integral_overflows",
}

LIMITS = ("The fragility's PGA is the peak of the horizontal acceleration vector and its Sa the RotD50 of the "
          "record pair (pipeline.study.grid); a hazard curve is for the component its ground-motion models predict "
          "(often RotD50 or the geometric mean), which for PGA is lower than the vector peak by some 10-20 %: "
          "no conversion is applied, so with such a curve the risk is underestimated. Shaking beyond the "
          "curve's last level is bounded (annual_frequency_lower, annual_frequency_upper), the central value "
          "extends the curve's last segment. Occurrences are Poisson (probability in T years = "
          "1 - exp(-lambda T)); the column is assumed undamaged before each earthquake (no accumulation).")


def _flags(status, beyond_curve, overflow):
    flag = np.full(status.shape, RISK_NO_FIT, np.int8)
    flag[(status == F.FIT_OK) | (status == F.FIT_SEPARATED)] = RISK_OK
    flag[status == F.FIT_NO_EXCEEDANCE] = RISK_NO_EXCEEDANCE
    flag[status == F.FIT_ALL_EXCEED] = RISK_ALL_EXCEED
    out = np.broadcast_to(flag, beyond_curve.shape).copy()
    out[(out == RISK_OK) & beyond_curve] = RISK_MEDIAN_BEYOND
    out[overflow] = RISK_OVERFLOW  # no number at all says more than where the median lies
    return out


def _grid(hazard, medians, betas, n):
    lo = min(usable_curve(hazard, s)[0][0] for s in range(len(hazard.sites))) / 2.0
    hi_curve = max(usable_curve(hazard, s)[0][-1] for s in range(len(hazard.sites)))
    ok = np.isfinite(medians) & (medians > 0)
    reach = np.where(ok, medians * np.exp(2.5 * np.nan_to_num(betas, nan=0.0)), 0.0)
    hi = min(max(hi_curve * 3.0, float(reach.max(initial=0.0))), hi_curve * 30.0)
    return np.geomspace(lo, hi, n)


def site_risk(frag, hazard, years=DEFAULT_YEARS, n_grid=301):
    """The risk of every site, damage state, column and model of a fragility.

    Parameters
    ----------
    frag : xarray.Dataset
        Fragility from :func:`pipeline.fragility.fragility` or :func:`open_fragility`: ``median``
        [m/s^2 for PGA and Sa], ``beta`` [1], ``fit_status``, and with a bootstrap
        ``median_bootstrap``/``beta_bootstrap`` (the replicates).
    hazard : HazardCurve
        Same intensity measure as the fragility (:func:`check_im`), levels in SI.
    years : float or sequence of float
        Period of the probability stated [yr] (``probability_in_period``); a sequence (``[50, 2100]``)
        gives ``probability_in_period`` a dimension ``years``, a number a scalar coordinate.
    n_grid : int
        Points of the intensity grid of the integrand (for plots and the shares).

    Returns
    -------
    xarray.Dataset
        Dims ``site``, ``state``, ``column``, ``model`` (labels), ``intensity`` and ``hazard_level``.
        ``annual_frequency`` [1/yr] with ``_lower``/``_upper`` (bounds for the curve's end) and, with
        bootstrap replicates, ``_band_lower``/``_band_upper`` at the fragility's confidence level;
        the same for ``probability_in_period`` [1]; ``return_period`` [yr]; the shares below the
        first and beyond the last level [1]; ``intensity_risk_05/50/95`` [IM units];
        ``risk_flag``; ``risk_integrand`` [1/yr per unit ln IM], ``fragility_probability`` [1] and
        ``hazard_rate_interpolated`` [1/yr] on ``intensity``; the curve as read, ``hazard_rate``
        [1/yr] (and ``hazard_poe``) on ``hazard_level``. A hazard curve from code values
        (:mod:`pipeline.risk.hazard_code`) is recorded in the attributes, with where it is extrapolated.
    """
    years = check_years(years)
    check_im(frag, hazard)
    im, period, units = fragility_im(frag)
    status = frag["fit_status"].transpose("state", "column", "model").values.astype(int)
    usable = (status == F.FIT_OK) | (status == F.FIT_SEPARATED)
    median = np.where(usable, frag["median"].transpose("state", "column", "model").values, np.nan)
    beta = np.where(usable, frag["beta"].transpose("state", "column", "model").values, np.nan)
    replicates = "median_bootstrap" in frag.variables and frag.sizes.get("bootstrap", 0) > 0
    if replicates:
        med_b = frag["median_bootstrap"].transpose("bootstrap", "state", "column", "model").values
        bet_b = frag["beta_bootstrap"].transpose("bootstrap", "state", "column", "model").values
    confidence = float(frag.attrs.get("confidence_level", F.DEFAULT_CONFIDENCE))
    grid = _grid(hazard, median, beta, n_grid)

    nS = len(hazard.sites)
    shape = (nS,) + median.shape
    out = {name: np.full(shape, np.nan) for name in (
        "annual_frequency", "annual_frequency_lower", "annual_frequency_upper", "annual_frequency_band_lower",
        "annual_frequency_band_upper", "share_below_first_level", "share_beyond_last_level")}
    shares = np.full(shape + (len(RISK_SHARES),), np.nan)
    integrand = np.full(shape + (grid.size,), np.nan)
    h_grid = np.full((nS, grid.size), np.nan)
    beyond_curve = np.zeros(shape, bool)
    overflow = np.zeros(shape, bool)
    curve_end = np.full(nS, np.nan)
    for s in range(nS):
        levels, rates = usable_curve(hazard, s)
        curve_end[s] = levels[-1]
        parts = risk_integral(levels, rates, median, beta, hazard.tails)
        # a usable fit whose integral is no number: beyond the largest float (risk_flag integral_overflows)
        overflow[s] = usable & ~np.isfinite(parts.central)
        central = np.where(overflow[s], np.nan, parts.central)
        with np.errstate(invalid="ignore", divide="ignore"):
            out["annual_frequency"][s] = central
            out["annual_frequency_lower"][s] = parts.lower
            out["annual_frequency_upper"][s] = parts.upper
            out["share_below_first_level"][s] = parts.below / central
            out["share_beyond_last_level"][s] = (central - parts.below - parts.inside) / central
        beyond_curve[s] = np.isfinite(median) & (median > levels[-1])
        dens, hg, _ = _integrand(grid, levels, rates, median, beta, hazard.tails)
        integrand[s] = dens
        h_grid[s] = hg
        shares[s] = _shares(grid, dens, parts.below, central)
        if replicates:
            lam = risk_integral(levels, rates, med_b, bet_b, hazard.tails).central  # (bootstrap, state, column, model)
            lo, hi = _band(lam, confidence)
            out["annual_frequency_band_lower"][s] = np.where(usable, lo, np.nan)
            out["annual_frequency_band_upper"][s] = np.where(usable, hi, np.nan)
    flag = _flags(status, beyond_curve, overflow)
    _warn(hazard, frag, flag, median, curve_end, units)

    dims = ("site", "state", "column", "model")
    level = f"{100 * confidence:g} %"
    ds = xr.Dataset(coords=_coords(frag, hazard, grid, years, im, units))
    for name, values in out.items():
        ds[name] = (dims, values)
    for name in ("", "_lower", "_upper", "_band_lower", "_band_upper"):
        lam = out[f"annual_frequency{name}"]
        ds[f"probability_in_period{name}"] = ((dims, probability_in(lam, years)) if np.ndim(years) == 0 else
                                              (dims + ("years",), probability_in(lam[..., None], years)))
    ds["return_period"] = (dims, return_period(out["annual_frequency"]))
    for j, share in enumerate(RISK_SHARES):
        ds[f"intensity_risk_{round(100 * share):02d}"] = (dims, shares[..., j], {"units": units})
    ds["risk_flag"] = (dims, flag)
    ds["risk_integrand"] = (dims + ("intensity",), integrand)
    ds["fragility_probability"] = (("state", "column", "model", "intensity"),
                                   F.probability(grid, median[..., None],
                                                 np.where(np.isfinite(median) & (median > 0), beta, 1.0)[..., None]))
    ds["hazard_rate_interpolated"] = (("site", "intensity"), h_grid)
    ds["hazard_rate"] = (("site", "hazard_level"), np.asarray(hazard.rate, float),
                         {"comment": "1 / return period of the code values"} if hazard.format == "code" else {})
    if hazard.poe is not None:
        ds["hazard_poe"] = (("site", "hazard_level"), np.asarray(hazard.poe, float),
                            {"comment": f"in the investigation time, {hazard.investigation_time:g} years"})
    ds["hazard_curve_end"] = (("site",), curve_end, {"units": units})
    fdims = ("state", "column", "model")
    ds["fragility_median"] = (fdims, frag["median"].transpose(*fdims).values, {"units": units})
    ds["fragility_beta"] = (fdims, frag["beta"].transpose(*fdims).values)
    ds["fit_status"] = (fdims, frag["fit_status"].transpose(*fdims).values, dict(frag["fit_status"].attrs))
    own = {name: dict(var.attrs) for name, var in ds.variables.items()}
    annotate(ds)
    for name, attrs in own.items():  # IM-dependent units stay the fragility's
        ds[name].attrs = {**ds[name].attrs, **attrs}
    for name in ("annual_frequency_band_lower", "annual_frequency_band_upper", "probability_in_period_band_lower",
                 "probability_in_period_band_upper"):
        ds[name].attrs["long_name"] += f" ({level})"
        if not replicates:
            ds[name].attrs["comment"] = ("NaN: the fragility file has no bootstrap replicates (median_bootstrap); "
                                         "rerun 'frustum fragility --bootstrap N'")
    ds.attrs.update(
        title=F.structures_title("Risk of damage states at sites", frag.attrs),
        summary="Mean annual frequency of each damage state, column and model of a fragility at each site of a "
                "hazard curve: lambda = integral P(DS | a) |dH/da| da, the hazard curve interpolated log-log, "
                "each segment integrated in closed form against the lognormal fragility; the part beyond the "
                "curve's last level bounded (annual_frequency_lower/upper).",
        intensity_measure=im,
        intensity_measure_units=units,
        **({"intensity_measure_period": period} if period is not None else {}),
        years=years,
        **_hazard_attrs(hazard),
        fragility_file=os.path.basename(str(frag.attrs.get("source_file", ""))),
        confidence_level=confidence,
        bootstrap_replicates=int(frag.sizes.get("bootstrap", 0)) if replicates else 0,
        method="Cornell C.A. (1968) Engineering seismic risk analysis, BSSA 58(5); closed form per power-law "
               "segment (Kennedy R.P., Short S.A. (1994) UCRL-15910; Cornell C.A. et al. (2002) J. Struct. Eng. "
               "128(4)); Poisson occurrence",
        limits=LIMITS + (f" The hazard curve is a power law through code values, extrapolated {hazard.extrapolated}."
                         if hazard.format == "code" else ""),
    )
    for key in ("results_study", "results_study_digest", "results_title", "structures"):
        if key in frag.attrs:
            ds.attrs[key] = str(frag.attrs[key])
    append_history(ds, f"pipeline.risk hazard={os.path.basename(hazard.source)} "
                       f"years={','.join(f'{y:g}' for y in np.atleast_1d(years))}")
    return ds


def check_years(years):
    """The periods of the stated probability [yr]: a positive number, or several, each once.

    Returns a float for a number, a float array for a sequence; refuses the rest by value.
    """
    many = np.ndim(years) > 0
    values = np.atleast_1d(np.asarray(years, float)) if many else np.array([float(years)])
    for y in map(float, values):
        if not (math.isfinite(y) and y > 0):
            raise InputError(f"years = {y!r}: give a positive number of years, e.g. 50")
    if many and (values.size == 0 or np.unique(values).size != values.size):
        raise InputError(f"years = {', '.join(f'{y:g}' for y in values) or 'none'}: give one or more periods, "
                         "each once, e.g. 50,2100")
    return values if many else float(values[0])


def periods(risk):
    """The periods [yr] of a risk Dataset's ``probability_in_period``, as a list (one or several)."""
    return [float(y) for y in np.atleast_1d(risk["years"].values)]


def in_period(cell, name, years):
    """``cell[name]`` at the period ``years`` [yr] (a Dataset with one period or several), as a float."""
    var = cell[name]
    return float(var.sel(years=years) if "years" in var.dims else var)


def _hazard_attrs(hazard):
    """The hazard curve's provenance: its file, or its code values, slopes and where it is extrapolated."""
    if hazard.format == "code":
        return dict(hazard_format=hazard.format, hazard_source=hazard.description,
                    hazard_code_values=hazard.source.removeprefix("code values "),
                    hazard_code_values_units="return period [year]:PGA [g]", hazard_slope_below=hazard.slope_below,
                    hazard_slope_beyond=hazard.slope_beyond, hazard_extrapolated=hazard.extrapolated,
                    hazard_imt=hazard.imt, hazard_level_units_in_file=hazard.file_units)
    return dict(hazard_file=os.path.basename(hazard.source), hazard_format=hazard.format, hazard_imt=hazard.imt,
                hazard_level_units_in_file=hazard.file_units, hazard_kind=hazard.kind,
                **({"hazard_investigation_time": hazard.investigation_time} if hazard.investigation_time else {}))


def _band(samples, confidence):
    """Percentile interval over the first axis (no interpolation; NaN replicates left out, inf kept)."""
    alpha = 0.5 * (1.0 - confidence)
    out = np.full((2,) + samples.shape[1:], np.nan)
    for index in np.ndindex(samples.shape[1:]):
        v = samples[(slice(None),) + index]
        v = v[~np.isnan(v)]
        if v.size:
            out[(slice(None),) + index] = np.quantile(v, [alpha, 1.0 - alpha], method="inverted_cdf")
    out[~np.isfinite(out)] = np.nan
    return out[0], out[1]


def _coords(frag, hazard, grid, years, im, units):
    acc = im in ("pga", "sa")
    coords = {
        "site": ("site", np.array(hazard.sites, dtype=object)),
        "site_longitude": ("site", np.asarray(hazard.lon, float)),
        "site_latitude": ("site", np.asarray(hazard.lat, float)),
        "site_depth": ("site", np.asarray(hazard.depth, float)),
        "state": ("state", frag["state"].values.astype(str).astype(object), {"long_name": "damage state"}),
        "column": ("column", frag["column"].values.astype(str).astype(object)),
        "model": ("model", frag["model"].values.astype(str).astype(object)),
        "intensity": ("intensity", grid, {"units": units}),
        "hazard_level": ("hazard_level", np.asarray(hazard.levels, float), {"units": units}),
        "years": ((), years) if np.ndim(years) == 0 else ("years", years),
    }
    if acc:
        coords["intensity_g"] = ("intensity", grid / G)
        coords["hazard_level_g"] = ("hazard_level", np.asarray(hazard.levels, float) / G)
    for name in ("state_measure", "state_threshold"):
        if name in frag.coords:
            coords[name] = ("state", frag[name].values, dict(frag[name].attrs))
    for name in ("column_R", "column_r", "column_h", "slenderness", "theta_crit", "column_beta", "latitude",
                 "longitude", *F.STRUCTURE_COORDS):
        if name in frag.coords and frag[name].dims == ("column",):
            coords[name] = ("column", frag[name].values, dict(frag[name].attrs))
    return coords


def _warn(hazard, frag, flag, median, curve_end, units):
    """One warning per site where the hazard curve ends before a fragility's median."""
    factor, unit = (1.0 / G, "g") if units == "m s-2" else (1.0, units)
    states, columns, models = (frag[d].values for d in ("state", "column", "model"))
    for s, site in enumerate(hazard.sites):
        cells = np.argwhere(flag[s] == RISK_MEDIAN_BEYOND)
        if not cells.size:
            continue
        named = [f"{columns[c]} {models[m]} {states[i]} (median {median[i, c, m] * factor:.3g} {unit})"
                 for i, c, m in cells[:3]]
        more = f" and {len(cells) - 3} more" if len(cells) > 3 else ""
        if hazard.format == "code":
            ends = (f"{hazard.source}: the largest PGA given is {curve_end[s] * factor:.3g} {unit}, below the fragility "
                    f"median of {', '.join(named)}{more}: that risk rests partly on the power law extrapolated beyond "
                    f"it (slope {hazard.slope_beyond:.3g})")
        else:
            ends = (f"{os.path.basename(hazard.source)}: the hazard curve of site {site} ends at "
                    f"{curve_end[s] * factor:.3g} {unit}, below the fragility median of {', '.join(named)}{more}: "
                    "that risk rests partly on the curve extended beyond its last level")
        warnings.warn(f"{ends}; see annual_frequency_lower/upper (risk_flag median_beyond_hazard_curve)",
                      HazardWarning, stacklevel=2)
