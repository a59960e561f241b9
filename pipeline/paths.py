"""Where results go, checked before any computing.

A run that can only fail at its end (a results path that is a folder, the
file-system root, a folder nobody may write, a plot format matplotlib does not
have) is refused at its start, naming the path and the fix.
"""

import os
import secrets

from pipeline.atomic import PARTIAL_PREFIX
from pipeline.errors import InputError

__all__ = ["check_output_file", "check_plot_file"]


def _writable_folder(folder):
    """(nearest existing ancestor of ``folder`` or None if we may not write there, that ancestor).

    An existing folder is probed by creating and removing a file in it: the
    permission bits do not tell (root, read-only mounts, /proc).
    """
    probe = os.path.abspath(folder)
    while not os.path.exists(probe):
        parent = os.path.dirname(probe)
        if parent == probe:
            break
        probe = parent
    if not os.path.isdir(probe):
        return None, probe
    test = os.path.join(probe, f"{PARTIAL_PREFIX}probe-{secrets.token_hex(4)}")
    try:
        os.close(os.open(test, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600))
        os.unlink(test)
    except OSError:
        return None, probe
    return probe, probe


def check_output_file(path, label):
    """Refuse a results path that cannot be written; returns it absolute.

    The checkpoint folder of a study, ``PATH.checkpoint``, lies beside the
    file, so a path with a file name keeps it inside the output's folder.

    Parameters
    ----------
    path : str or os.PathLike
    label : str
        How the user gave it (``"--out"``, ``"field output"``), for the message.
    """
    text = os.fspath(path)
    full = os.path.abspath(text)
    name = os.path.basename(full)
    if not text or text.endswith(("/", os.sep)) or not name or os.path.isdir(full):
        raise InputError(f"{label} {text!r} is a folder; give the path of a file, e.g. out/results.nc")
    folder = os.path.dirname(full)
    ok, nearest = _writable_folder(folder)
    if ok is None:
        why = "is not a folder" if os.path.exists(nearest) and not os.path.isdir(nearest) else "cannot be written"
        raise InputError(f"{label} {text!r}: {nearest} {why} (read-only or no permission); "
                         "choose a folder you may write in")
    return full


def check_plot_file(path, label):
    """Refuse a figure path whose format matplotlib cannot write, or that cannot be written; returns it."""
    from matplotlib.backend_bases import FigureCanvasBase

    text = os.fspath(path)
    formats = FigureCanvasBase.get_supported_filetypes()
    suffix = os.path.splitext(text)[1].lower().lstrip(".")
    if suffix not in formats:
        raise InputError(f"{label} {text!r}: not a figure format matplotlib writes; end the name in one of "
                         f"{', '.join('.' + f for f in sorted(formats))} (e.g. .png)")
    return check_output_file(text, label)
