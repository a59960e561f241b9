"""Figure of a ground motion: acceleration, velocity, displacement, response spectrum."""

import numpy as np

from pipeline.groundmotion import intensity as im

__all__ = ["plot_motion"]

_COLOURS = {"x": "tab:blue", "y": "tab:orange", "z": "tab:green"}


def plot_motion(gm, out, periods=None, damping=0.05):
    """Draw the histories and the response spectrum of ``gm`` to a file.

    Parameters
    ----------
    gm : GroundMotion
    out : str or path-like
        Figure file, in any format matplotlib writes (by suffix: .png, .pdf,
        .svg, ...), written under a temporary name, then renamed.
    periods : array_like, optional
        Spectrum periods [s]; default 100 log-spaced from 0.02 to 5 s.
    damping : float
        Damping ratio of the spectrum [1].
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    periods = np.geomspace(0.02, 5.0, 100) if periods is None else np.asarray(periods)
    t = gm.time
    fig = plt.figure(figsize=(10, 8), constrained_layout=True)
    grid = fig.add_gridspec(3, 2)
    axes = [fig.add_subplot(grid[i, 0]) for i in range(3)]
    spec = fig.add_subplot(grid[:, 1])
    for name in gm.components:
        a = gm.component(name)
        colour = _COLOURS[name]
        axes[0].plot(t, a, lw=0.7, color=colour, label=f"{name}  (PGA {im.pga(a):.3g} m/s²)")
        axes[1].plot(t, im.velocity(a, gm.dt), lw=0.8, color=colour, label=f"{name}  (PGV {im.pgv(a, gm.dt):.3g} m/s)")
        axes[2].plot(t, im.displacement(a, gm.dt), lw=0.8, color=colour, label=f"{name}  (PGD {im.pgd(a, gm.dt):.3g} m)")
        spec.loglog(periods, im.spectral_acceleration(a, gm.dt, periods, damping), color=colour, label=name)
    for ax, title, unit in zip(axes, ("Acceleration", "Velocity", "Displacement"), ("m/s²", "m/s", "m")):
        ax.set_title(f"{title} (trapezoidal integration, no correction)" if title != "Acceleration" else title, fontsize=10)
        ax.set_ylabel(f"{title.lower()} [{unit}]")
        ax.axhline(0.0, color="0.6", lw=0.5)
        ax.legend(fontsize=8, loc="upper right")
        ax.grid(alpha=0.3)
    axes[2].set_xlabel("time [s]")
    spec.set_title(f"Response spectrum, {100 * damping:g} % damping", fontsize=10)
    spec.set_xlabel("period T [s]")
    spec.set_ylabel("spectral acceleration Sa [m/s²]")
    spec.grid(alpha=0.3, which="both")
    spec.legend(fontsize=8)
    meta = gm.metadata
    subtitle = ", ".join(str(meta[k]) for k in ("event", "year", "station") if meta.get(k))
    fig.suptitle(f"{gm.record_id}" + (f" — {subtitle}" if subtitle else "") + f"   (dt = {gm.dt:g} s, {gm.npts} samples)")
    from pipeline.figfile import save_figure

    return save_figure(fig, out, dpi=110, option="--out")
