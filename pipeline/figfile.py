"""Writing a matplotlib figure to a file: any format matplotlib writes, atomically.

Every figure of the package goes through :func:`save_figure`, so that a plot
path ending in ``.png``, ``.pdf``, ``.svg``, ``.eps``, ``.jpg``, ... works
everywhere, a wrong suffix fails before any computing with a message naming
the formats, and an interrupted run leaves no half-written figure.
"""

import os

from pipeline.errors import InputError


def formats():
    """File suffixes matplotlib writes here (``png``, ``pdf``, ``svg``, ...), sorted."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    return sorted(FigureCanvasAgg(Figure()).get_supported_filetypes())


def check_figure_path(path, option="--plot"):
    """The suffix of ``path`` without its dot, if matplotlib writes it; else an InputError naming the formats."""
    suffix = os.path.splitext(os.fspath(path))[1].lower().lstrip(".")
    known = formats()
    if suffix not in known:
        raise InputError(f"{option} {path}: matplotlib cannot write '.{suffix}' files; end the name with one of "
                         + ", ".join(f".{s}" for s in known))
    return suffix


def save_figure(fig, path, dpi=110, option="--plot", close=True):
    """Save ``fig`` to ``path`` in the format its suffix names (temporary name, then rename).

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    path : str or os.PathLike
        Its folder is created if needed.
    dpi : float
        Resolution of raster formats [dots per inch].
    option : str
        How the caller names the path in an error message.
    close : bool
        Close the figure afterwards (False to save it in another format too).

    Returns
    -------
    str
        ``path``.
    """
    import matplotlib.pyplot as plt

    from pipeline.atomic import atomic_path

    path = os.fspath(path)
    fmt = check_figure_path(path, option)
    try:
        with atomic_path(path, suffix=f".{fmt}") as tmp:
            fig.savefig(tmp, dpi=dpi, format=fmt)
    finally:
        if close:
            plt.close(fig)
    return path


__all__ = ["formats", "check_figure_path", "save_figure"]
