"""Writing a matplotlib figure to a file: any format matplotlib writes, atomically, marked as this project's.

Every figure of the package goes through :func:`save_figure`, so that a plot
path ending in ``.png``, ``.pdf``, ``.svg``, ``.eps``, ``.jpg``, ... works
everywhere (:func:`pipeline.paths.check_plot_file` refuses the others, before
any computing where a command calls it first), an interrupted run leaves
no half-written figure, and the file carries :func:`pipeline.paths.mark_text`
in its format's metadata (:func:`mark_savefig_kwargs`), by which a rerun
recognises a figure it may replace (:func:`pipeline.paths.written_by_frustum`).
"""

import os

from pipeline.paths import check_plot_file, mark_text

#: Where each format keeps the mark: matplotlib's ``metadata`` key, or a keyword of Pillow's writer
#: (``pil_kwargs``) for the raster formats matplotlib hands to Pillow without metadata.
_MARK_PLACES = {
    "png": ("metadata", "Software"),  # a tEXt chunk before the image data
    "pdf": ("metadata", "Creator"),  # the document information dictionary, near the end
    "svg": ("metadata", "Creator"),  # <metadata> near the start
    "svgz": ("metadata", "Creator"),
    "eps": ("metadata", "Creator"),  # the %%Creator comment of the header
    "ps": ("metadata", "Creator"),
    "jpg": ("pil_kwargs", "comment"),  # a COM segment
    "jpeg": ("pil_kwargs", "comment"),
    "gif": ("pil_kwargs", "comment"),  # a comment extension
    "tif": ("pil_kwargs", "software"),  # the Software tag
    "tiff": ("pil_kwargs", "software"),
    "webp": ("pil_kwargs", "xmp"),  # an XMP chunk
    "avif": ("pil_kwargs", "xmp"),
}


def mark_savefig_kwargs(fmt):
    """Keywords of ``Figure.savefig`` that put the project's mark into a file of format ``fmt``.

    Empty for the formats that cannot carry one (``pgf``, ``raw``, ``rgba``):
    such a file is written unmarked, so an existing one is never replaced by
    a command (:func:`pipeline.paths.check_output_file`).
    """
    place = _MARK_PLACES.get(fmt)
    if place is None:
        return {}
    where, key = place
    text = mark_text()
    if where == "metadata":
        return {"metadata": {key: text}}
    return {"pil_kwargs": {key: text.encode() if key == "xmp" else text}}


def save_figure(fig, path, dpi=110, option="--plot", close=True):
    """Save ``fig`` to ``path`` in the format its suffix names (temporary name, then rename), marked.

    An existing file at ``path`` is replaced: the commands refuse a user's file
    before computing (:func:`pipeline.paths.check_plot_file`); the study
    scripts regenerate the figures they own, marked or not.

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

    path = check_plot_file(path, option, kind=None)  # the format and the folder; the file was checked by the command
    fmt = os.path.splitext(path)[1].lower().lstrip(".")
    try:
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=dpi, format=fmt, **mark_savefig_kwargs(fmt))
    finally:
        if close:
            plt.close(fig)
    return path


__all__ = ["mark_savefig_kwargs", "save_figure"]
