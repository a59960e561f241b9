"""The risk in words, as the command, the figure and the report print it: :func:`one_in`,
:func:`percent`, :func:`years_words`, and why a cell has no number (:func:`no_risk_reason`)."""

import math

import numpy as np

from pipeline import fragility as F
from pipeline.risk.integral import risk_integral
from pipeline.risk.risk_dataset import RISK_FLAGS
from pipeline.units import G


def one_in(p):
    """A probability in plain words: ``"about 1 in 250"``, ``"about 6 in 10"``, ``"less than 1 in a million"``."""
    if not np.isfinite(p):
        return "unknown"
    if p <= 0:
        return "practically no"
    if p < 1e-6:
        return "less than 1 in a million"
    if p >= 0.95:
        return "almost certain (more than 19 in 20)"
    if p >= 0.3:
        return f"about {round(10 * p)} in 10"
    n = 1.0 / p
    digits = 2 if n >= 10 else 1
    n = float(f"{n:.{digits}g}")
    return f"about 1 in {n:,.0f}"


def percent(p):
    """A probability in percent as the command, the figure and the report print it, never rounded to a
    certainty it is not.

    Two significant digits (``2.4 %``, ``0.059 %``, ``99 %``); from 99.5 % on, the decimals that keep it
    below 100 (``99.7 %``, ``99.97 %``), and ``> 99.99 %`` beyond; ``< 0.0001 %`` below 1e-6; ``0 %``
    for 0 and ``n/a`` for NaN.
    """
    if not np.isfinite(p):
        return "n/a"
    if p <= 0:
        return "0 %"
    if p < 1e-6:
        return "< 0.0001 %"
    if p < 0.995:
        return f"{float(f'{100 * p:.2g}'):g} %"
    for digits in (1, 2):
        text = f"{100 * p:.{digits}f}"
        if float(text) < 100:
            return f"{text} %"
    return "> 99.99 %"


def years_words(period):
    """A return period [yr] in words: ``2,100 years`` (two significant digits, as :func:`one_in`),
    ``more than a million years``, ``never`` (infinite), ``n/a`` (NaN)."""
    if np.isnan(period):
        return "n/a"
    if period == np.inf:
        return "never"
    if period > 1e6:
        return "more than a million years"
    if period < 1e-3:
        return "less than 0.001 years"
    r = float(f"{period:.2g}")
    text = f"{r:,.0f}" if r >= 10 else f"{r:g}"
    return f"{text} year{'' if r == 1 else 's'}"


def no_risk_reason(risk, site, column, model, state):
    """Why a cell of :func:`site_risk` has no annual frequency, in words; None when it has one.

    The reason follows ``risk_flag``: the fragility has no median (no run, or every run, reached the
    state), was not fitted (its ``fit_status``), or the integral is beyond the largest float (which
    part of the hazard curve makes it so, and the lower bound that remains).
    """
    cell = risk.sel(site=site, column=column, model=model, state=state)
    if np.isfinite(float(cell["annual_frequency"])):
        return None
    flag = RISK_FLAGS[int(cell["risk_flag"])]
    if flag == "no_median_no_exceedance_observed":
        return f"no run reached {state}, so the fragility has no median to integrate"
    if flag == "no_median_every_run_exceeds":
        return f"every run reached {state}, so the fragility has no median to integrate"
    if flag == "no_fit":
        return f"the fragility was not fitted ({F.FIT_STATUS.get(int(cell['fit_status']), '?').replace('_', ' ')})"
    if flag != "integral_overflows":
        return f"the risk integral is not a number (risk_flag {flag})"
    factor, unit = (1.0 / G, "g") if risk["intensity"].attrs.get("units") == "m s-2" else (1.0, "m/s")
    rate = risk["hazard_rate"].sel(site=site).values
    keep = np.isfinite(rate) & (rate > 0)
    levels, rates = risk["hazard_level"].values[keep], rate[keep]
    tails = tuple(risk.attrs.get(f"hazard_slope_{end}") for end in ("below", "beyond"))  # code values give them
    parts = risk_integral(levels, rates, float(cell["fragility_median"]), float(cell["fragility_beta"]), tails)
    lower = f"{float(cell['annual_frequency_lower']):.3g} /yr"
    if np.isfinite(parts.below) or levels.size < 2:  # beyond the largest rate: not met in practice
        return f"the risk integral is beyond the largest number a float holds (at least {lower})"
    k = (math.log(rates[0]) - math.log(rates[1])) / math.log(levels[1] / levels[0])  # a ratio may overflow
    a0, a1 = (f"{v * factor:.3g}" for v in levels[:2])
    return (f"the hazard curve's first segment ({a0} to {a1} {unit}) falls as a^-{float(f'{k:.3g}'):g}; extended "
            f"below {a0} {unit}, as the central value extends it, it carries the risk integral beyond the largest "
            "number a float holds (1.8e308 /yr); hazard curves flatten towards weak shaking (slopes of a few): check "
            f"the rates of the first levels, or give lower levels (shaking above {a0} {unit} alone gives at least "
            f"{lower})")
