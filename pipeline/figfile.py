"""Writing a matplotlib figure to a file: any format matplotlib writes, atomically.

Every figure of the package goes through :func:`save_figure`, so that a plot
path ending in ``.png``, ``.pdf``, ``.svg``, ``.eps``, ``.jpg``, ... works
everywhere (:func:`pipeline.paths.check_plot_file` refuses the others, before
any computing where a command calls it first), and an interrupted run leaves
no half-written figure.
"""

import os

from pipeline.paths import check_plot_file


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

    path = check_plot_file(path, option)
    fmt = os.path.splitext(path)[1].lower().lstrip(".")
    try:
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=dpi, format=fmt)
    finally:
        if close:
            plt.close(fig)
    return path


__all__ = ["save_figure"]
