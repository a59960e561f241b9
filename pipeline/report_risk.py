"""The report's section on the risk at a site (:func:`risk_section`): how likely each column is to reach a damage
state there in the period, from a fragility and a site's hazard curve (:mod:`pipeline.risk`), in plain words."""

import os

import numpy as np

from pipeline import models as MD
from pipeline.units import G

__all__ = ["risk_section", "RISK_SENTENCES_MAX"]

#: Site-and-column cells described in sentences under "Risk at the site" (the table has them all).
RISK_SENTENCES_MAX = 8


def risk_section(risk, hazard, frag, fmt):
    """The "Risk at the site" section: the chance of overturning in the period, in plain words (``fmt(value,
    digits)`` writes a number as the report does)."""
    from pipeline import risk as R

    years = float(risk["years"])
    yrs = f"{years:g} years"
    state = "overturning"
    sites = [str(s) for s in risk["site"].values]
    source = ("the OpenQuake engine's export" + (f" ({hazard.kind} curve)" if hazard.kind else "")
              + f", probabilities of exceedance in {hazard.investigation_time:g} years turned into annual rates"
              if hazard.format == "openquake" else "annual rates" if hazard.investigation_time is None
              else f"probabilities of exceedance in {hazard.investigation_time:g} years turned into annual rates")
    level = f"{100 * float(risk.attrs['confidence_level']):g} %"
    lines = ["## Risk at the site", ""]
    lines.append(f"The fragility above says how likely the column is to overturn *given* a shaking. The site's hazard "
                 f"curve (`{os.path.basename(hazard.source)}`, {source}) says how often each shaking happens there. "
                 "Together (the risk integral, docs/fragility.md) they give how likely the column is to overturn "
                 f"at its site in the next {yrs}, assuming earthquakes occur at random in time (Poisson) and the "
                 "column stands undamaged before each one.")
    lines.append("")
    lines.append(f"| site | column | model | chance of overturning in {yrs} | in words | on average once in | "
                 f"bootstrap band ({level}) | 90 % of the risk from PGA between |")
    lines.append("|---|---|---|---|---|---|---|---|")
    sentences, notes = [], []
    for site in sites:
        for c in risk["column"].values:
            for m in risk["model"].values:
                cell = risk.sel(site=site, column=c, model=m, state=state)
                p = float(cell["probability_in_period"])
                flag = R.RISK_FLAGS[int(cell["risk_flag"])]
                if R.no_risk_reason(risk, site, c, m, state) is not None:
                    lines.append(f"| {site} | {c} | {m.upper()} | n/a | {flag.replace('_', ' ')} | | | |")
                    notes.append(_risk_no_median(risk, hazard, frag, site, str(c), str(m), flag, years, fmt, state))
                    continue
                band = (f"{R.percent(float(cell['probability_in_period_band_lower']))} to "
                        f"{R.percent(float(cell['probability_in_period_band_upper']))}"
                        if np.isfinite(float(cell["probability_in_period_band_lower"])) else "n/a")
                a05, a95 = (float(cell[f"intensity_risk_{q}"]) / G for q in ("05", "95"))
                span = f"{fmt(a05, 2)} and {fmt(a95, 2)} g" if np.isfinite(a05) and np.isfinite(a95) else "n/a"
                once = R.years_words(float(cell["return_period"]))
                mark = " (extrapolated)" if flag == "median_beyond_hazard_curve" else ""
                lines.append(f"| {site} | {c} | {m.upper()} | {R.percent(p)}{mark} | {R.one_in(p)} | {once} | {band} | "
                             f"{span} |")
                if len(sentences) < RISK_SENTENCES_MAX:
                    where = _site_where(cell)
                    text = (f"- At site {site}{where}, column '{c}' ({MD.results_title(frag, str(m))}): **{R.one_in(p)} chance of "
                            f"overturning in {yrs}** ({R.percent(p)}"
                            + (f"; bootstrap band {band}" if band != "n/a" else "")
                            + f"), on average once in {once}.")
                    if span != "n/a":
                        text += f" 90 % of this risk comes from shaking with a PGA between {span}."
                    if flag == "median_beyond_hazard_curve":
                        lo, hi = (float(cell[f"probability_in_period_{b}"]) for b in ("lower", "upper"))
                        text += (f" **Extrapolated:** the hazard curve stops at "
                                 f"{fmt(float(risk['hazard_curve_end'].sel(site=site)) / G)} g, below this column's "
                                 f"median PGA of overturning ({fmt(float(cell['fragility_median']) / G)} g); the "
                                 f"number extends the curve beyond its last level, and whatever the curve does there "
                                 f"the chance lies between {R.percent(lo)} and {R.percent(hi)}.")
                    sentences.append(text)
    lines.append("")
    lines += sentences + notes
    if sentences or notes:
        lines.append("")
    lines.append("Limits: the fragility's PGA is the peak of the horizontal acceleration vector of the record; hazard "
                 "curves are usually for a component average (RotD50 or the geometric mean), some 10-20 % lower for "
                 "the same shaking, and no conversion is applied, so these chances are somewhat low. The bootstrap "
                 "band covers the records' scatter, not the hazard's uncertainty (use the engine's quantile curves "
                 "for that). Every damage state, model and site is in `risk.csv` and `risk.nc`.")
    lines.append("")
    return lines


def _site_where(cell):
    lon, lat = float(cell["site_longitude"]), float(cell["site_latitude"])
    if not (np.isfinite(lon) and np.isfinite(lat)):
        return ""
    return f" ({abs(lat):.3f}° {'N' if lat >= 0 else 'S'}, {abs(lon):.3f}° {'E' if lon >= 0 else 'W'})"


def _risk_no_median(risk, hazard, frag, site, column, model, flag, years, fmt, state="overturning"):
    """The sentence for a column without a risk: its fragility has no median, or the integral has no number."""
    from pipeline import risk as R

    if flag != "no_median_no_exceedance_observed" or "im_simulated_max" not in frag:
        return (f"- At site {site}, column '{column}' ({model.upper()}): no risk is stated: "
                f"{R.no_risk_reason(risk, site, column, model, state)}.")
    top = float(frag["im_simulated_max"].sel(column=column, model=model))
    index = [str(s) for s in risk["site"].values].index(site)
    p_top = float(R.probability_in(R.hazard_rate_at(hazard, index, top), years))
    return (f"- At site {site}, column '{column}' ({model.upper()}): no run overturned, up to a PGA of "
            f"{fmt(top / G)} g, so the fragility has no median and these runs cannot give the risk. For scale: "
            f"shaking stronger than {fmt(top / G)} g has {R.one_in(p_top)} chance ({R.percent(p_top)}) of happening "
            f"there in {years:g} years; run stronger shaking to learn whether it would overturn the column.")
