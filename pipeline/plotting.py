"""Figures people look at: one response, and (later) study results.

matplotlib with the non-interactive Agg backend; every axis carries its unit.
"""

import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from pipeline.models import DEFAULT  # noqa: E402
from pipeline.models import title as model_title  # noqa: E402
from pipeline.response import outcome  # noqa: E402
from pipeline.units import G  # noqa: E402


def plot_response(ds, summary, path, friction=0.7):
    """The panels of one simulation, saved to ``path`` (any format matplotlib writes, by suffix).

    theta(t) against theta_crit, the path of the contact point and of the base
    centre on the ground, the mobilized friction coefficient against the
    friction coefficient, and the ground acceleration (a free motion has
    none: three panels then). Nothing is drawn after the column overturned
    (a dotted line marks the time); the title names the record, the
    incidence angle and the scale factor.

    Parameters
    ----------
    ds : xarray.Dataset
        Histories of one run: :func:`pipeline.simulate.simulate`, or
        :func:`pipeline.dataset.one_run` of a histories file.
    summary : dict
        Its summary (``peak_theta``; ``overturned`` and ``overturn_time`` when
        it has a record).
    path : str or os.PathLike
    friction : float
        Friction coefficient drawn on the mu_mob panel [1].
    """
    from pipeline.figfile import save_figure

    return save_figure(response_figure(ds, summary, friction), path, dpi=110)


def response_figure(ds, summary, friction=0.7):
    """The figure of :func:`plot_response`, not saved (a ``matplotlib.figure.Figure``)."""
    t = ds.time.values
    until_over, upright = _before_overturning(ds, summary)
    ground = [(name, label) for name, label in (("ground_acc_x", "X"), ("ground_acc_y", "Y"), ("ground_acc_z", "Z"))
              if name in ds and np.any(np.nan_to_num(ds[name].values))]
    shape = (2, 2) if ground else (1, 3)
    fig, axes = plt.subplots(*shape, figsize=(12, 8) if ground else (16, 4.8), constrained_layout=True)
    axes = axes.ravel()
    over = bool(summary.get("overturned"))

    ax = axes[0]
    theta_crit = math.degrees(ds.attrs["theta_crit_rad"])
    ax.plot(t[until_over], np.degrees(ds.theta.values[until_over]), lw=0.8, label=r"$\theta$")
    ax.axhline(theta_crit, color="C3", ls="--", lw=1, label=rf"$\theta_{{crit}}$ = {theta_crit:.1f}°")
    if over:
        ax.axvline(summary["overturn_time"], color="k", lw=0.8, ls=":", label="overturned")
        ax.set_ylim(0, 1.5 * theta_crit)
    ax.set_xlim(t[0], t[-1])
    ax.set_xlabel("time [s]")
    ax.set_ylabel("inclination θ [deg]")
    ax.set_title("Inclination of the column axis")
    ax.legend(loc="upper right")

    ax = axes[1]
    ax.plot(ds.x_p.values[upright] * 100, ds.y_p.values[upright] * 100, lw=0.5, label="contact point")
    if "x_b" in ds and np.any(np.isfinite(ds.x_b.values)):
        ax.plot(ds.x_b.values[upright] * 100, ds.y_b.values[upright] * 100, lw=1.2, color="C1", label="base centre")
    R = ds.attrs["column_R_m"] * 100
    circle = np.linspace(0, 2 * np.pi, 200)
    ax.plot(R * np.cos(circle), R * np.sin(circle), color="0.6", lw=0.8, ls="--", label="base at start")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("X [cm]")
    ax.set_ylabel("Y [cm]")
    ax.set_title("Paths on the ground (plane of the base)" + (", until the final fall" if over else ""))
    ax.legend(loc="upper right", fontsize="small")

    ax = axes[2]
    ax.semilogy(t[upright], np.clip(ds.mu_mob.values[upright], 1e-4, None), lw=0.6, label=r"$\mu_{mob}$")
    ax.axhline(friction, color="C3", ls="--", lw=1, label=f"friction coefficient {friction:g}")
    if over:
        ax.axvline(summary["overturn_time"], color="k", lw=0.8, ls=":", label="overturned")
    ax.set_xlim(t[0], t[-1])
    ax.set_xlabel("time [s]")
    ax.set_ylabel(r"mobilized friction $|F_t|/N$ [1]")
    ax.set_title("Friction the contact must supply")
    ax.legend(loc="upper right")

    if ground:
        ax = axes[3]
        for name, label in ground:
            ax.plot(t, ds[name].values / G, lw=0.6, label=label)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("ground acceleration [g]")
        ax.set_title("Excitation")
        ax.legend(loc="upper right")

    words = f" ({outcome(summary)})" if "overturned" in summary else ""
    fig.suptitle(f"{run_title(ds)}: peak θ = {math.degrees(summary['peak_theta']):.2f}°{words}")
    return fig


def run_title(ds):
    """What one run is, for titles: record, incidence angle, scale, model and column."""
    model = model_title(ds.attrs.get("model", DEFAULT))
    column = (f"column R = {ds.attrs['column_R_m']:g} m, r = {ds.attrs['column_r_m']:g} m, "
              f"h = {ds.attrs['column_h_m']:g} m")
    if "record_id" not in ds.attrs or ds.attrs["record_id"] == "free-motion":
        return f"free motion, {model}, {column}"
    angle = math.degrees(float(ds.attrs.get("incidence_angle_rad", 0.0))) if "angle" not in ds.coords \
        else float(ds["angle"])
    scale = float(ds.attrs.get("scale", 1.0)) if "scale" not in ds.coords else float(ds["scale"])
    return f"{ds.attrs['record_id']} at {angle:g}°, × {scale:g}, {model}, {column}"


def _before_overturning(ds, summary):
    """Rows to draw: (up to the overturning time, up to the start of the final fall).

    The final fall starts when the column passes theta_crit for the last time
    (as the summary's peaks count it): friction and the contact path after
    that describe a column going over, not one standing. Both masks are all
    True when the column stands.
    """
    t = ds.time.values
    everything = np.ones(t.shape, dtype=bool)
    if not (summary.get("overturned") and math.isfinite(summary.get("overturn_time", math.nan))):
        return everything, everything
    until = t <= summary["overturn_time"]
    below = np.flatnonzero(until & (np.nan_to_num(ds.theta.values) <= ds.attrs["theta_crit_rad"]))
    return until, np.arange(t.size) <= (below[-1] if below.size else -1)


def plot_study(ds, path):
    """Summary of a study's results, saved to ``path`` (any format matplotlib writes, by suffix).

    Left: peak inclination over theta_crit against the PGA of the scaled
    record (peak of the horizontal vector), one marker per record, angle and
    scale, per model, for the first column; overturned runs are drawn at the
    top. Right: fraction of overturned runs (over records and angles) against
    the scale level (a target PGA in g, as on the left), one line per column
    and model.

    Parameters
    ----------
    ds : xarray.Dataset
        Results of :func:`pipeline.study.run_study` (or
        :func:`pipeline.dataset.open_results`).
    path : str or os.PathLike
    """
    from pipeline.figfile import save_figure

    return save_figure(study_figure(ds), path, dpi=120)


def study_figure(ds):
    """The figure of :func:`plot_study`, not saved (a ``matplotlib.figure.Figure``)."""
    ok = ds.status == 0
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5), constrained_layout=True)
    first = ds.isel(column=0)
    markers = "os^vD"
    standing = first.peak_theta_ratio.where((first.status == 0) & (first.overturned == 0))
    top = float(standing.max()) if standing.notnull().any() else 1.0
    for mi, model in enumerate(ds.model.values):
        sub = first.sel(model=model)
        cells = sub.peak_theta_ratio  # (record, angle, scale[, seed]): the seeds of imperfect drums as angles
        pga = sub.pga.broadcast_like(cells).transpose(*cells.dims).values
        ratio = cells.values
        over = sub.overturned.broadcast_like(cells).transpose(*cells.dims).values == 1
        good = sub.status.broadcast_like(cells).transpose(*cells.dims).values == 0
        ax1.scatter((pga / G)[good & ~over], ratio[good & ~over], s=14, marker=markers[mi % 5], alpha=0.7,
                    label=f"{model}: stands")
        if (good & over).any():
            ax1.scatter((pga / G)[good & over], np.full((good & over).sum(), max(1.05, 1.05 * top)), s=22,
                        marker=markers[mi % 5], facecolors="none", edgecolors="k", label=f"{model}: overturned")
    ax1.axhline(1.0, color="0.5", lw=0.8, ls="--")
    ax1.set_xlabel("PGA of the scaled record (horizontal vector) [g]")
    ax1.set_ylabel(r"peak $\theta$ / $\theta_{crit}$ [1] (overturned: drawn at the top)")
    ax1.set_ylim(0, max(1.12, 1.12 * top))
    ax1.set_title(str(first.column.values.item()), fontsize=10)  # its label: a column or a colonnade
    ax1.legend(fontsize=8)
    frac = (ds.overturned.where(ok)).mean(dim=("record", "angle") + (("seed",) if "seed" in ds.dims else ()))
    xlabel, levels = "scale factor on the record [1]", ds.scale.values
    units = ds.scale.attrs.get("units", "1")
    if units != "1":  # target levels: an acceleration in g, as on the left and in reports
        words = ds.scale.attrs.get("long_name", "target level").split("(")[0].strip()
        words = words.replace("pga", "PGA").replace("pgv", "PGV")
        if units == "m s-2":
            xlabel, levels = f"{words} [g]", levels / G
        else:
            xlabel = f"{words} [{units}]"
    for column in ds.column.values[:6]:
        for model in ds.model.values:
            ax2.plot(levels, frac.sel(column=column, model=model).values, marker="o",
                     label=f"{column} ({model})")
    ax2.set_xlabel(xlabel)
    ax2.set_ylabel("fraction overturned (records x angles) [1]")
    ax2.set_ylim(-0.03, 1.03)
    ax2.legend(fontsize=8)
    fig.suptitle(ds.attrs.get("title", "study"), fontsize=11)
    return fig
