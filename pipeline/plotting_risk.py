"""The figure of a site risk (:mod:`pipeline.risk`): the hazard curve, the fragility and the risk integrand.

Three panels over one intensity axis (in g for accelerations, m/s^2 on the top axis): the hazard
curve H(a) [1/yr] as read (points) and as integrated (log-log interpolation, dotted where it is
extended beyond the curve's levels; for code values, the values given and the power laws, dotted
where extrapolated); the fragility P(DS | a) of each model; and the integrand
P(DS | a) |dH/d ln a| [1/yr per unit ln a], whose area over a log axis is the mean annual
frequency, so the figure shows which shaking levels carry the risk.
"""

import numpy as np

from pipeline.plotting_fragility import _plain_log, _secondary, _style, im_axis, plt
from pipeline.risk import RISK_FLAGS, describe_im, in_period, one_in, percent, periods


def _draw(risk, axes, site, column, state, models):
    im = risk.attrs.get("intensity_measure", "pga")
    units = risk["intensity"].attrs.get("units", "m s-2")
    factor, xlabel, secondary = im_axis(im, units)
    x = risk["intensity"].values * factor
    end = float(risk["hazard_curve_end"].sel(site=site))
    first = float(risk["hazard_level"].values[np.isfinite(risk["hazard_rate"].sel(site=site).values)
                                              & (risk["hazard_rate"].sel(site=site).values > 0)][0])
    ax_h, ax_p, ax_i = axes
    ax_h.set_yscale("log")
    h = risk["hazard_rate_interpolated"].sel(site=site).values
    levels = risk["hazard_level"].values * factor
    rate = risk["hazard_rate"].sel(site=site).values
    # rates drawn within 1e-30..1e30 /yr (no hazard curve leaves them), on whole decades set rather than
    # autoscaled: matplotlib's margins and log ticks overflow on absurd rates (1e300 /yr)
    h = np.where((h >= 1e-30) & (h <= 1e30), h, np.nan)
    ok = np.isfinite(rate) & (rate >= 1e-30) & (rate <= 1e30)
    drawn = np.concatenate([h[np.isfinite(h)], rate[ok]])
    if drawn.size:  # before plotting: the limits set, matplotlib no longer autoscales
        lo, hi = np.floor(np.log10(drawn.min())), np.ceil(np.log10(drawn.max()))
        ax_h.set_ylim(10.0 ** lo, 10.0 ** max(hi, lo + 1))
    inside = (risk["intensity"].values >= first) & (risk["intensity"].values <= end)
    code = risk.attrs.get("hazard_format") == "code"
    if inside.sum() > 1:  # one code value: no curve between values, all of it extrapolated
        ax_h.plot(x[inside], h[inside], color="C0", lw=1.6,
                  label="power law between the values" if code else "log-log interpolation")
    ax_h.plot(np.where(inside, np.nan, x), np.where(inside, np.nan, h), color="C0", lw=1.2, ls=":",
              label=_extended_label(risk) if code else "extended by the end segments")
    ax_h.plot(levels[ok], rate[ok], "o", color="C0", ms=4,
              label=(f"code values (T:PGA {risk.attrs.get('hazard_code_values', '')})" if code else
                     f"hazard curve ({risk.attrs.get('hazard_file', '')})"))
    ax_h.set_ylabel("annual rate of exceedance\nH(a) [1/yr]")
    ax_h.legend(fontsize="small", loc="lower left")
    years = periods(risk)
    lines = []
    for j, m in enumerate(models):
        cell = risk.sel(site=site, column=column, model=m, state=state)
        style = _style(m)
        color = f"C{j + 1}"
        med = float(cell["fragility_median"])
        ax_p.plot(x, cell["fragility_probability"].values, color=color, ls=style["ls"], lw=1.6,
                  label=f"{m.upper()}: median {med * factor:.3g}" if np.isfinite(med) else f"{m.upper()}: no median")
        dens = cell["risk_integrand"].values
        dens = np.where(dens <= 1e30, dens, np.nan)  # the window of the hazard panel: ticks overflow beyond
        lam = float(cell["annual_frequency"])
        p = [in_period(cell, "probability_in_period", y) for y in years]
        flag = RISK_FLAGS[int(cell["risk_flag"])]
        more = "".join(f", {y:g} yr: {percent(q)}" for y, q in zip(years[1:], p[1:]))
        text = (f"{m.upper()}: λ = {lam:.3g} /yr, {years[0]:g} yr: {percent(p[0])} ({one_in(p[0])}){more}"
                if np.isfinite(lam) else f"{m.upper()}: not computed ({flag.replace('_', ' ')})")
        if flag == "median_beyond_hazard_curve":
            text += " - median beyond the values given" if code else " - median beyond the curve"
        ax_i.plot(x, dens, color=color, ls=style["ls"], lw=1.6, label=text)
        lines.append(text)
        for ax in (ax_h, ax_p, ax_i):
            if np.isfinite(med):
                ax.axvline(med * factor, color=color, lw=0.8, ls=style["ls"], alpha=0.6)
    ax_p.set_ylabel(f"P({state} | a) [1]")
    ax_p.set_ylim(-0.02, 1.02)
    ax_p.legend(fontsize="small", loc="upper left", title="fragility (vertical lines: medians)",
                title_fontsize="small")
    ax_i.set_ylabel("risk integrand\nP |dH/d ln a| [1/yr]")
    ax_i.legend(fontsize="small", loc="upper left")
    for ax in axes:
        ax.axvline(end * factor, color="0.4", lw=1.0, ls="--")
        ax.set_xscale("log")
        ax.grid(True, which="both", alpha=0.3)
    ax_i.text(end * factor, 0.98, " largest value given" if code else " last level",
              transform=ax_i.get_xaxis_transform(), fontsize="small", va="top", color="0.3")
    meds = risk["fragility_median"].sel(column=column, state=state, model=models).values
    bets = np.nan_to_num(risk["fragility_beta"].sel(column=column, state=state, model=models).values)
    reach = [float(v) for v in meds * np.exp(2.5 * bets) if np.isfinite(v)]
    ax_i.set_xlim(first * factor / 1.5, min(max([end * 1.5] + reach), float(risk["intensity"].max())) * factor)
    _plain_log(ax_i.xaxis)
    ax_i.set_xlabel(xlabel)
    _secondary(ax_h, secondary)
    return describe_im(im, risk.attrs.get("intensity_measure_period"))


def _extended_label(risk):
    """The legend of a code curve's extrapolated part: which slopes, below and beyond the values."""
    below, beyond = (float(risk.attrs[f"hazard_slope_{end}"]) for end in ("below", "beyond"))
    slopes = f"slope {below:.3g}" if f"{below:.3g}" == f"{beyond:.3g}" else f"slopes {below:.3g} and {beyond:.3g}"
    return f"extrapolated: power law, {slopes}"


def figure(risk, site=None, column=None, state="overturning", models=None, title=None):
    """The three-panel figure of one site and column (every model), as a matplotlib Figure."""
    site = str(risk["site"].values[0]) if site is None else site
    column = str(risk["column"].values[0]) if column is None else column
    models = [str(m) for m in risk["model"].values] if models is None else models
    fig, axes = plt.subplots(3, 1, figsize=(8.5, 9.5), sharex=True, constrained_layout=True)
    name = _draw(risk, axes, site, column, state, models)
    fig.suptitle(title or f"Risk of {state} of column '{column}' at site {site} ({name})", fontsize="medium")
    return fig


def plot_risk(risk, path, site=None, column=None, state="overturning", models=None, title=None):
    """Draw :func:`figure` to ``path`` (any format matplotlib writes, atomically); returns ``path``."""
    from pipeline.figfile import save_figure

    return save_figure(figure(risk, site, column, state, models, title), path)


def plot_risk_stem(risk, stem, **kwargs):
    """Draw :func:`figure` to ``<stem>.png`` and ``<stem>.pdf`` (the report's figures); returns both paths."""
    from pipeline.plotting_fragility import _save

    return _save(figure(risk, **kwargs), stem)


__all__ = ["figure", "plot_risk", "plot_risk_stem"]
