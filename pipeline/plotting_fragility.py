"""Figures of study results and fragility curves (PNG and PDF).

Companion of :mod:`pipeline.plotting` (one response); this module draws what a
study gives: fragility curves with their data and bootstrap bands, the IDA
view, overturning probability over slenderness and conicity, over incidence
angle (polar) and contact-point paths of chosen runs. Every function writes
``<stem>.png`` and ``<stem>.pdf`` and returns the two paths.

Accelerations are drawn in g with m/s^2 on a second axis; velocities in m/s.
"""

import math
import os
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from pipeline.models import DEFAULT, REGISTRY, base_of, flag, planar_pair  # noqa: E402
from pipeline.models import style as _style  # noqa: E402  (each model's line, marker and band: its registry entry)
from pipeline.models import title as model_title  # noqa: E402
from pipeline.units import G  # noqa: E402

# A study's variants of a model (``[models.NAME]``) are drawn apart from it and from each other.
_VARIANT_LINES = ("-.", (0, (1, 1)), (0, (5, 1)), (0, (3, 1, 1, 1, 1, 1)))
_VARIANT_MARKERS = "dv<>"


def model_style(ds, name):
    """How plots draw a dataset's model: its registry entry's style, a variant's its own."""
    base = base_of(ds, name)
    style = _style(base)
    if base != name:
        variants = [str(m) for m in ds["model"].values if base_of(ds, str(m)) != str(m)]
        k = variants.index(name)
        style.update(ls=_VARIANT_LINES[k % len(_VARIANT_LINES)], marker=_VARIANT_MARKERS[k % len(_VARIANT_MARKERS)])
    return style


_STATE_COLORS = ["k", "C2", "C1", "C4", "C5", "C6"]


def _save(fig, stem):
    from pipeline.figfile import save_figure

    paths = [f"{os.fspath(stem)}.png", f"{os.fspath(stem)}.pdf"]
    for i, path in enumerate(paths):
        save_figure(fig, path, dpi=130, close=i == len(paths) - 1)
    return paths


def im_axis(im, units):
    """(factor, label, secondary) to draw an IM: accelerations in g, others as stored."""
    name = {"pga": "PGA", "pgv": "PGV", "sa": "Sa(T)"}.get(im, im)
    if units in ("m s-2", "m/s^2", "m/s2"):
        return 1.0 / G, f"{name} [g]", (f"{name} [m/s²]", G)
    if units in ("m s-1", "m/s"):
        return 1.0, f"{name} [m/s]", None
    return 1.0, f"{name} [{units}]", None


def _plain_log(axis):
    """Log axis with plain numbers (0.2, 0.5, 1, 2) instead of powers of ten."""
    from matplotlib.ticker import FuncFormatter, LogLocator

    fmt = FuncFormatter(lambda v, _: f"{v:g}")
    axis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
    axis.set_major_formatter(fmt)
    axis.set_minor_formatter(FuncFormatter(lambda v, _: ""))


def _secondary(ax, secondary):
    if secondary:
        label, factor = secondary
        top = ax.secondary_xaxis("top", functions=(lambda v: v * factor, lambda v: v / factor))
        top.set_xlabel(label)
        if ax.get_xscale() == "log":
            _plain_log(top.xaxis)


def _state_text(state, cell):
    """How a legend names a damage state (by the measure it is a threshold on)."""
    if state == "overturning":
        return "overturning"
    threshold = float(cell["state_threshold"])
    if "state_measure" in cell.coords and str(cell["state_measure"].values) == "dislocation_ratio":
        return f"joint slip/D ≥ {threshold:g}"
    return f"θ/θ_crit ≥ {threshold:g}"


def plot_fragility(frag, stem, column=None, states=None, models=None, title=None):
    """Fragility curves of one column: fitted curves, bootstrap bands and the stripe data.

    Writes :func:`fragility_figure` as ``<stem>.png`` and ``<stem>.pdf`` and returns the two paths.

    Parameters
    ----------
    frag : xarray.Dataset
        From :func:`pipeline.fragility.fragility`.
    stem : str
        Output path without suffix (``.png`` and ``.pdf`` are written).
    column, states, models, title
        As :func:`fragility_figure`.
    """
    return _save(fragility_figure(frag, column=column, states=states, models=models, title=title), stem)


def fragility_figure(frag, column=None, states=None, models=None, title=None):
    """The figure of :func:`plot_fragility`, not saved (a ``matplotlib.figure.Figure``).

    The legend sits below the axes, never over the curves, and the title and the legend's
    longer entries are wrapped to the figure's width, which grows with the legend: any number
    of models and states fits without the layout engine giving up.

    Parameters
    ----------
    frag : xarray.Dataset
        From :func:`pipeline.fragility.fragility`.
    column : str, optional
        Column label (default: the first).
    states : list of str, optional
        Damage states to draw (default: all).
    models : list of str, optional
        Models to draw (default: all in ``frag``).
    title : str, optional
        Title (default: the column's name); the bootstrap band's note is added to it.
    """
    from matplotlib.lines import Line2D

    column = str(frag["column"].values[0]) if column is None else column
    states = [str(s) for s in frag["state"].values] if states is None else states
    models = [str(m) for m in frag["model"].values] if models is None else models
    im = frag.attrs.get("intensity_measure", "pga")
    factor, xlabel, secondary = im_axis(im, frag["median"].attrs.get("units", ""))
    grid = frag["im_level"].values * factor
    fig, ax = plt.subplots(figsize=(_WIDTH, 5.5), constrained_layout=True)
    level = frag.attrs.get("confidence_level")
    # One state and several models (the report's overturning figure): the state's one colour
    # would leave only line styles, which repeat past four variants, to tell the models apart.
    by_model = len(states) == 1 and len(models) > 1
    entries = []  # ((state index, model index), handle, label)
    for i, state in list(enumerate(states))[::-1]:  # overturning drawn last, on top
        width = 1.4 if state == "overturning" else 2.4
        for k, m in enumerate(models):
            color = f"C{k}" if by_model else _STATE_COLORS[i % len(_STATE_COLORS)]
            cell = frag.sel(state=state, column=column, model=m)
            style = model_style(frag, m)
            med = float(cell["median"])
            bet = float(cell["beta"])
            if np.isfinite(med) and np.isfinite(bet):
                fit_text = f"median {med * factor:.3g}, β = {bet:.2f}"
            else:
                fit_text = str(cell["fit_status"].attrs.get("flag_meanings", "").split()[int(cell["fit_status"])]) \
                    if "flag_meanings" in cell["fit_status"].attrs else "no fit"
            ax.plot(grid, cell["probability"].values, color=color, ls=style["ls"], lw=width, zorder=3 if i == 0 else 2)
            if "probability_lower" in frag:
                ax.fill_between(grid, cell["probability_lower"].values, cell["probability_upper"].values,
                                color=color, alpha=style["band_alpha"], lw=0)
            frac = cell["stripe_fraction"].values
            ok = np.isfinite(frac)
            marker = dict(marker=style["marker"], mfc=color if style["filled"] else "none", mec=color, ms=5)
            ax.plot(frag["stripe_im"].values[ok] * factor, frac[ok], ls="none", **marker)
            # the legend's sample shows the line and the model's marker together: no separate key of markers
            entries.append(((i, k), Line2D([], [], color=color, ls=style["ls"], lw=width, **marker),
                            f"{_state_text(state, cell)}, {m.upper()}: {fit_text}"))
    ax.set_xscale("log")
    _plain_log(ax.xaxis)
    ax.set_xlabel(xlabel)
    _secondary(ax, secondary)
    ax.set_ylabel("probability of reaching the damage state [1]")
    ax.set_ylim(-0.02, 1.02)
    ax.grid(True, which="both", alpha=0.3)
    entries.sort(key=lambda e: e[0])
    handles = [e[1] for e in entries]
    labels = [e[2] for e in entries]
    band = f"; shaded: {100 * level:g} % bootstrap band over records" if level and "probability_lower" in frag else ""
    unit = xlabel.split("[")[-1][:-1]
    legend_title = f"lines: lognormal fit (median in {unit}); markers: observed fraction per scale stripe"
    fit_below(fig, (title or f"Fragility of column '{column}'") + band, handles, labels, legend_title)
    return fig


#: Width of the fragility figures [in]; their height follows the legend below the axes.
_WIDTH = 8.5
#: Height of the axes and their labels, without the title and the legend [in].
_PLOT_HEIGHT = 4.8


def fit_below(fig, title, handles, labels, legend_title):
    """Give ``fig`` a title and a legend below its axes, both wrapped to the figure's width.

    The figure's height becomes the axes' height plus what the title and the legend need, so
    that constrained layout always has room (it gives up, with the warning "constrained_layout
    not applied", when decorations leave the axes no height) and nothing is cut at the edges.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        One with constrained layout.
    title : str
        Its title (one paragraph; wrapped here).
    handles, labels : list
        The legend's entries.
    legend_title : str
        The legend's title (wrapped here).
    """
    renderer = fig.canvas.get_renderer()
    room = 0.96 * fig.bbox.width  # [pixels] the layout's margins take the rest
    text = fig.suptitle(title, fontsize="medium")
    _wrap(text, title, room, renderer)
    legend = None
    for ncols in ((2, 1) if len(labels) > 3 else (1,)):
        if legend is not None:
            legend.remove()
        legend = fig.legend(handles, [textwrap.fill(lab, 60) for lab in labels], loc="outside lower center",
                            ncols=ncols, fontsize="small", title=legend_title, title_fontsize="small")
        _wrap(legend.get_title(), legend_title, room - 20, renderer)
        if legend.get_window_extent(renderer).width <= room:
            break
    dpi = fig.dpi
    fig.set_figheight(_PLOT_HEIGHT + (legend.get_window_extent(renderer).height
                                      + text.get_window_extent(renderer).height) / dpi + 0.3)


def _wrap(text, words, room, renderer):
    """Wrap a text artist's ``words`` onto as many lines as it needs to be at most ``room`` pixels wide."""
    width = len(words)
    text.set_text(words)
    while text.get_window_extent(renderer).width > room and width > 20:
        width = int(width * 0.9)
        text.set_text(textwrap.fill(words, width))


def plot_ida(view, stem, title=None, units="m s-2", im="pga"):
    """IDA view: peak theta/theta_crit against the IM, one line per record.

    Parameters
    ----------
    view : xarray.Dataset
        From :func:`pipeline.fragility.ida` (dims record, scale).
    """
    factor, ylabel, _ = im_axis(im, units)
    fig, ax = plt.subplots(figsize=(7.5, 5.5), constrained_layout=True)
    cap = 1.6
    for rec in view["record"].values:
        one = view.sel(record=rec)
        order = np.argsort(one[im].values)
        r = one["peak_theta_ratio"].values[order]
        y = one[im].values[order] * factor
        shown = np.where(np.isinf(r), cap, r)
        ax.plot(shown, y, lw=0.8, alpha=0.7, marker=".", ms=3)
        ov = np.isinf(r)
        if ov.any():
            ax.plot(np.full(ov.sum(), cap), y[ov], "x", color="C3", ms=5)
    ax.axvline(1.0, color="k", ls="--", lw=1)
    ax.text(1.0, 1.0, " θ = θ_crit", transform=ax.get_xaxis_transform(), va="top", fontsize="small")
    ax.plot([], [], color="0.5", lw=0.8, marker=".", label=f"one line per record ({view.sizes['record']})")
    ax.plot([], [], "x", color="C3", label=f"overturned (drawn at {cap})")
    ax.set_xlim(0, cap + 0.1)
    ax.set_xlabel("peak inclination over critical inclination θ_max/θ_crit [1]")
    ax.set_ylabel(ylabel)
    ax.set_yscale("log")
    _plain_log(ax.yaxis)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="lower right", fontsize="small")
    ax.set_title(title or "Incremental dynamic analysis: one line per record", fontsize="medium")
    return _save(fig, stem)


def plot_geometry_map(frag, stem, im_value, model=DEFAULT, state="overturning", title=None):
    """Probability of a damage state at one IM level over slenderness h/R and conicity r/R.

    Each column is a point coloured by the fitted probability at ``im_value``
    (units of the IM); where the columns span a grid (3 or more distinct
    values on both axes) the probability is also contoured.

    Parameters
    ----------
    im_value : float
        IM at which to evaluate the curves, in the dataset's units (m/s^2 for PGA).
    """
    from pipeline.fragility import fitted_probability

    sub = frag.sel(model=model, state=state)
    slender = frag["slenderness"].values
    conicity = frag["column_beta"].values if "column_beta" in frag.coords else np.full(slender.size, np.nan)
    p = fitted_probability(im_value, sub["median"].values, sub["beta"].values, sub["fit_status"].values)
    factor, label, _ = im_axis(frag.attrs.get("intensity_measure", "pga"), frag["median"].attrs.get("units", ""))
    fig, ax = plt.subplots(figsize=(7.5, 5.5), constrained_layout=True)
    levels = np.linspace(0, 1, 11)
    ok = np.isfinite(p)
    if len(np.unique(slender[ok])) >= 3 and len(np.unique(conicity[ok])) >= 3:
        cs = ax.tricontourf(slender[ok], conicity[ok], p[ok], levels=levels, cmap="viridis", alpha=0.8)
    else:
        cs = None
    sc = ax.scatter(slender, conicity, c=p, cmap="viridis", vmin=0, vmax=1, s=120, edgecolor="k", zorder=3)
    for x, y, v, name in zip(slender, conicity, p, frag["column"].values):
        ax.annotate(f"{name}\nP = {v:.2f}" if np.isfinite(v) else f"{name}\nno fit", (x, y),
                    textcoords="offset points", xytext=(8, 6), fontsize="small")
    fig.colorbar(cs if cs is not None else sc, ax=ax, label=f"probability of {state.replace('_', ' ')} [1]")
    ax.set_xlabel("slenderness h/R [1]")
    ax.set_ylabel("conicity r/R [1]")
    ax.margins(0.25)
    ax.set_title(title or f"{model_title(model)}: probability of {state.replace('_', ' ')} "
                 f"at {label.split(' [')[0]} = {im_value * factor:.3g} {label.split('[')[-1][:-1]}",
                 fontsize="medium")
    return _save(fig, stem)


def plot_angle_polar(results, stem, column, model=None, scales=None, title=None):
    """Fraction of records that overturn the column at each incidence angle (polar).

    A planar model sees the record turned by the angle; angle and angle + 180
    deg are the same planar excitation mirrored, so the data are drawn on both.
    ``model``: the results' model to draw (default: the first planar one); the model it is the
    planar counterpart of, if in the results, is drawn as dotted rings (it does not depend on
    the angle).

    Parameters
    ----------
    results : xarray.Dataset
        Study results (dims column, record, angle, scale, model).
    scales : list of float, optional
        Scale stripes to draw (default: all where some run overturned).
    """
    names = [str(m) for m in results["model"].values]
    if model is None:
        model = next((m for m in names if flag(results, m, "planar")), names[0])
    one = results.sel(column=column, model=model)
    valid = one["status"] == 0 if "status" in one else True
    pool = [d for d in ("record", "seed") if d in one.dims]  # the seeds of imperfect drums pooled as records
    frac = (one["overturned"].where(valid) > 0).where(valid).mean(pool)  # (angle, scale)
    angles = one["angle"].values
    if scales is None:
        scales = [s for s in one["scale"].values if np.nanmax(frac.sel(scale=s).values) > 0]
    fig = plt.figure(figsize=(7.5, 9.0))
    ax = fig.add_axes([0.12, 0.22, 0.76, 0.64], projection="polar")  # room for title and legend
    cmap = plt.get_cmap("viridis")
    units = results["scale"].attrs.get("units", "1")
    reference = None
    spatial = getattr(REGISTRY.get(base_of(results, model)), "planar_of", None)
    if spatial in names:
        ref = results.sel(column=column, model=spatial).isel(angle=0)
        ok = ref["status"] == 0 if "status" in ref else True
        reference = (ref["overturned"].where(ok) > 0).where(ok).mean(pool)  # (scale,)
    ring = np.linspace(0, 2 * np.pi, 181)
    for i, s in enumerate(scales):
        color = cmap(i / max(len(scales) - 1, 1))
        f = frac.sel(scale=s).values
        a = np.concatenate([angles, angles + 180.0])
        v = np.concatenate([f, f])
        order = np.argsort(a % 360)
        a, v = a[order] % 360, v[order]
        a, v = np.append(a, a[0] + 360), np.append(v, v[0])
        label = f"PGA {s / G:.2g} g" if units == "m s-2" else f"scale {s:g}"
        ax.plot(np.radians(a), v, marker="o", ms=3, color=color, label=f"{label}, 2D")
        if reference is not None:
            ax.plot(ring, np.full(ring.size, float(reference.sel(scale=s))), color=color, ls=":", lw=1.2)
    if reference is not None:
        ax.plot([], [], color="0.3", ls=":", label="3D: dotted ring, same colour")
    ax.set_rlim(0, 1)
    ax.set_rlabel_position(100)

    fig.legend(*ax.get_legend_handles_labels(), loc="lower center", bbox_to_anchor=(0.5, 0.01), ncol=3,
               fontsize="small", title="target PGA of the records" if units == "m s-2" else "record scale factor")
    fig.suptitle((title or f"{model_title(model)}, column '{column}': overturning by incidence angle")
                 + "\nangle: incidence angle [deg]; radius: fraction of records that overturn the column [1]",
                 fontsize="medium", y=0.985)
    return _save(fig, stem)


def plot_trajectories(runs, stem, title=None):
    """Contact-point and base-centre paths on the ground of chosen runs.

    Parameters
    ----------
    runs : list of (label, xarray.Dataset)
        Histories from ``simulate(..., histories=True)``.
    """
    n = len(runs)
    fig, axes = plt.subplots(1, n, figsize=(5.0 * n, 5.2), constrained_layout=True, squeeze=False)
    for ax, (label, ds) in zip(axes[0], runs):
        R = ds.attrs["column_R_m"] * 100
        ax.plot(ds["x_p"].values * 100, ds["y_p"].values * 100, lw=0.5, color="C0", label="contact point P")
        if "x_b" in ds:
            ax.plot(ds["x_b"].values * 100, ds["y_b"].values * 100, lw=1.4, color="C1", label="base centre B")
        circle = np.linspace(0, 2 * np.pi, 200)
        ax.plot(R * np.cos(circle), R * np.sin(circle), color="0.5", ls="--", lw=0.8, label="base at start")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("X [cm]")
        ax.set_ylabel("Y [cm]")
        ax.grid(True, alpha=0.3)
        ax.set_title(label, fontsize="small")
        ax.legend(loc="upper right", fontsize="x-small")
    if title:
        fig.suptitle(title)
    return _save(fig, stem)


def plot_model_comparison(frag, stem, state="overturning", title=None):
    """Median IM of a damage state, 3D against 2D, per column, with bootstrap bounds.

    The 3D model and its planar counterpart (:func:`pipeline.models.planar_pair`). Points above
    the diagonal: 2D needs a stronger motion than 3D to overturn the column, i.e. the 2D
    analysis is unconservative there.
    """
    factor, label, _ = im_axis(frag.attrs.get("intensity_measure", "pga"), frag["median"].attrs.get("units", ""))
    sub = frag.sel(state=state)
    pair = planar_pair([str(m) for m in frag["model"].values])
    if pair is None:
        return []  # no 3D model with its planar counterpart: nothing to compare
    spatial, planar = pair
    m3 = sub["median"].sel(model=spatial).values * factor
    m2 = sub["median"].sel(model=planar).values * factor
    if not np.any(np.isfinite(m3) & np.isfinite(m2) & (m3 > 0) & (m2 > 0)):
        return []  # no column has a median under both models (e.g. nothing overturned): nothing to draw
    fig, ax = plt.subplots(figsize=(7.0, 6.0), constrained_layout=True)
    many = m3.size > 5 and "slenderness" in frag.coords and "column_beta" in frag.coords
    if "median_lower" in frag:
        xerr = np.nan_to_num([m3 - sub["median_lower"].sel(model=spatial).values * factor,
                              sub["median_upper"].sel(model=spatial).values * factor - m3])
        yerr = np.nan_to_num([m2 - sub["median_lower"].sel(model=planar).values * factor,
                              sub["median_upper"].sel(model=planar).values * factor - m2])
        ax.errorbar(m3, m2, xerr=xerr, yerr=yerr, fmt="none", ecolor="0.6", capsize=2, lw=0.8,
                    label=f"{100 * frag.attrs.get('confidence_level', 0.9):g} % bootstrap bounds")
    if many:
        # many columns: colour = slenderness, marker = conicity (labels would overlap)
        slender = frag["slenderness"].values
        conicity = np.round(frag["column_beta"].values, 6)
        markers = "osD^v<>p*h"
        norm = plt.Normalize(slender.min(), slender.max())
        for i, b in enumerate(np.unique(conicity)):
            sel = conicity == b
            sc = ax.scatter(m3[sel], m2[sel], c=slender[sel], cmap="viridis", norm=norm, s=45,
                            marker=markers[i % len(markers)], edgecolor="k", zorder=3, label=f"r/R = {b:g}")
        fig.colorbar(sc, ax=ax, label="slenderness h/R [1]")
    else:
        ax.plot(m3, m2, "o", zorder=3, label="median")
        for i, (x, y, name) in enumerate(zip(m3, m2, frag["column"].values)):
            if np.isfinite(x) and np.isfinite(y):  # alternate below/above so neighbours' labels do not collide
                ax.annotate(str(name), (x, y), textcoords="offset points", xytext=(6, -14 if i % 2 == 0 else 8),
                            fontsize="small")
    finite = np.concatenate([m3, m2])
    if "median_lower" in frag:
        finite = np.concatenate([finite] + [sub[v].values.ravel() * factor for v in ("median_lower", "median_upper")])
    finite = finite[np.isfinite(finite) & (finite > 0)]
    if finite.size:
        lo, hi = finite.min() / 1.5, finite.max() * 1.5
        ax.plot([lo, hi], [lo, hi], "k--", lw=1, label="2D = 3D")
        ax.fill_between([lo, hi], [lo, hi], [hi, hi], color="C3", alpha=0.08, label="2D unconservative (above)")
        ax.set_xlim(lo, hi)
        ax.set_ylim(lo, hi)
    ax.set_xscale("log")
    ax.set_yscale("log")
    _plain_log(ax.xaxis)
    _plain_log(ax.yaxis)
    unit = label.split("[")[-1][:-1]
    ax.set_xlabel(f"median {label.split(' [')[0]} of {state}, 3D model [{unit}]")
    ax.set_ylabel(f"median {label.split(' [')[0]} of {state}, 2D model [{unit}]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="upper left", fontsize="small")
    ax.set_title(title or "Median intensity of overturning: 2D against 3D", fontsize="medium")
    return _save(fig, stem)


def plot_model_medians(comparison, stem, columns=None, title=None):
    """Median intensity of overturning of every model with its bootstrap band, per column.

    One panel per column (at most six): a row per model, the reference first, its band shaded
    across the panel so that a model whose median falls inside it is seen at once.

    Parameters
    ----------
    comparison : xarray.Dataset
        From :func:`pipeline.comparison.compare_models`.
    stem : str
        Path without extension.
    columns : list of str, optional
        Columns drawn (default: the first six).
    """
    factor, label, _ = im_axis(comparison.attrs.get("intensity_measure", "pga"),
                               comparison["median"].attrs.get("units", ""))
    columns = [str(c) for c in comparison["column"].values][:6] if columns is None else columns
    reference = comparison.attrs["reference_model"]
    models = [str(m) for m in comparison["model"].values]
    names = [reference] + models
    fig, axes = plt.subplots(len(columns), 1, figsize=(7.0, 1.0 + 0.45 * len(names) * len(columns)),
                             constrained_layout=True, squeeze=False)
    for ax, c in zip(axes[:, 0], columns):
        cell = comparison.sel(column=c)
        ref = [float(cell[f"median_reference{k}"].values[0]) * factor for k in ("", "_lower", "_upper")]
        rows = [ref] + [[float(cell[f"median{k}"].sel(model=m)) * factor for k in ("", "_lower", "_upper")]
                        for m in models]
        if np.isfinite(ref[1]) and np.isfinite(ref[2]):
            ax.axvspan(ref[1], ref[2], color="C0", alpha=0.12, label="reference's band")
        for y, (name, (med, lo, hi)) in enumerate(zip(names, rows)):
            if np.isfinite(med):
                err = [[med - lo if np.isfinite(lo) else 0.0], [hi - med if np.isfinite(hi) else 0.0]]
                ax.errorbar([med], [y], xerr=err, fmt="o", color="C0" if y == 0 else "k", capsize=3)
            else:
                ax.annotate("no median (none or all overturned)", (0.02, y), xycoords=("axes fraction", "data"),
                            va="center", fontsize="small", color="0.4")
        ax.set_yticks(range(len(names)), [model_title(n) for n in names], fontsize="small")
        ax.set_ylim(len(names) - 0.5, -0.5)
        ax.set_title(f"column '{c}'", fontsize="small", loc="left")
        ax.grid(True, axis="x", alpha=0.3)
    axes[-1, 0].set_xlabel(f"median {label} of overturning, {100 * comparison.attrs.get('confidence_level', 0.9):g} % "
                           "bootstrap band over records")
    fig.suptitle(title or f"Median intensity of overturning: every model against '{reference}'", fontsize="medium")
    return _save(fig, stem)


def plot_column_grid(frag, values, stem, label, title, cmap="viridis", vmin=None, vmax=None, fmt="{:.2f}",
                     missing_text="n/a"):
    """A value per column drawn over slenderness h/R and conicity r/R (cells of the study grid).

    Parameters
    ----------
    frag : xarray.Dataset
        Fragility dataset (for the columns' ``slenderness`` and ``column_beta``).
    values : array_like
        One value per column (NaN: drawn grey with ``missing_text``).
    label : str
        Colour-bar label, with units.
    """
    slender = np.asarray(frag["slenderness"].values, float)
    conicity = np.asarray(frag["column_beta"].values, float)
    values = np.asarray(values, float)
    xs, ys = np.unique(np.round(slender, 9)), np.unique(np.round(conicity, 9))
    table = np.full((ys.size, xs.size), np.nan)
    for x, y, v in zip(slender, conicity, values):
        table[np.searchsorted(ys, round(y, 9)), np.searchsorted(xs, round(x, 9))] = v
    fig, ax = plt.subplots(figsize=(1.3 * xs.size + 3.5, 1.0 * ys.size + 2.5), constrained_layout=True)
    mesh = ax.pcolormesh(np.arange(xs.size + 1) - 0.5, np.arange(ys.size + 1) - 0.5,
                         np.ma.masked_invalid(table), cmap=cmap, vmin=vmin, vmax=vmax, shading="flat")
    ax.set_facecolor("0.85")
    for i in range(ys.size):
        for j in range(xs.size):
            v = table[i, j]
            if np.isfinite(v):
                r, g, b, _ = mesh.cmap(mesh.norm(v))
                color = "w" if 0.299 * r + 0.587 * g + 0.114 * b < 0.5 else "k"  # text readable on the cell
            else:
                color = "k"
            ax.text(j, i, fmt.format(v) if np.isfinite(v) else missing_text, ha="center", va="center",
                    fontsize="medium", color=color)
    ax.set_xticks(range(xs.size), [f"{x:g}" for x in xs])
    ax.set_yticks(range(ys.size), [f"{y:g}" for y in ys])
    ax.set_xlabel("slenderness h/R [1]")
    ax.set_ylabel("conicity r/R [1]")
    fig.colorbar(mesh, ax=ax, label=label)
    ax.set_title(title, fontsize="medium")
    return _save(fig, stem)


def plot_curve_comparison(frags, stem, column, state="overturning", model=DEFAULT, title=None):
    """Fitted curves of one column and state from several fragility datasets (e.g. options).

    Parameters
    ----------
    frags : dict
        Legend label -> fragility Dataset (same IM).
    """
    first = next(iter(frags.values()))
    factor, xlabel, secondary = im_axis(first.attrs.get("intensity_measure", "pga"),
                                        first["median"].attrs.get("units", ""))
    fig, ax = plt.subplots(figsize=(8.5, 5.5), constrained_layout=True)
    for i, (label, frag) in enumerate(frags.items()):
        cell = frag.sel(state=state, column=column, model=model)
        grid = frag["im_level"].values * factor
        med, bet = float(cell["median"]), float(cell["beta"])
        fit = f"median {med * factor:.3g}, β = {bet:.2f}" if np.isfinite(med) else "no fit"
        ax.plot(grid, cell["probability"].values, color=f"C{i}", lw=1.8, label=f"{label}: {fit}")
        if "probability_lower" in frag:
            ax.fill_between(grid, cell["probability_lower"].values, cell["probability_upper"].values,
                            color=f"C{i}", alpha=0.12, lw=0)
        frac = cell["stripe_fraction"].values
        ok = np.isfinite(frac)
        ax.plot(frag["stripe_im"].values[ok] * factor, frac[ok], "o", color=f"C{i}", ms=4)
    ax.set_xscale("log")
    _plain_log(ax.xaxis)
    ax.set_xlabel(xlabel)
    _secondary(ax, secondary)
    ax.set_ylabel(f"probability of {state.replace('_', ' ')} [1]")
    ax.set_ylim(-0.02, 1.02)
    ax.grid(True, which="both", alpha=0.3)
    ax.plot([], [], "o", color="0.3", ms=4, label="observed fraction per stripe")
    ax.legend(fontsize="small", loc="upper left", title=f"lognormal fit (median in {xlabel.split('[')[-1][:-1]})",
              title_fontsize="small")
    fig.suptitle(title or f"Column '{column}', {model.upper()} model", fontsize="medium")
    return _save(fig, stem)


__all__ = [
    "im_axis",
    "plot_fragility",
    "fragility_figure",
    "plot_ida",
    "plot_geometry_map",
    "plot_angle_polar",
    "plot_trajectories",
    "plot_model_comparison",
    "plot_column_grid",
    "plot_curve_comparison",
]
