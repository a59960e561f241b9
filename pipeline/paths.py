"""Where results go, checked before any computing.

A run that can only fail at its end (a results path that is a folder, the
file-system root, a folder nobody may write, a plot format matplotlib does not
have) is refused at its start, naming the path and the fix.

No output ever replaces an input or a file of the user's: every command
names its inputs and the kind of result it writes (:data:`KINDS`), and
:func:`check_output_file` refuses an output that is one of the inputs, or an
existing file that is not a result of that kind written by this project
(:func:`result_kind` reads only the netCDF file's global attributes and
dimensions). A result of the same kind is overwritten, as a rerun expects.
"""

import os
import secrets

from pipeline.atomic import PARTIAL_PREFIX
from pipeline.errors import InputError

__all__ = ["KINDS", "check_output_file", "check_output_folder", "check_plot_file", "result_kind"]

#: The kinds of netCDF result this project writes, and how the messages name them.
KINDS = {
    "histories": "histories file of 'frustum simulate'",
    "study": "results file of 'frustum study run'",
    "fragility": "fragility file of 'frustum fragility'",
    "risk": "risk file of 'frustum risk'",
}


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


def _check_folder_writable(text, folder, label):
    """The one "cannot be written" refusal of every output (file or folder)."""
    ok, nearest = _writable_folder(folder)
    if ok is None:
        why = "is not a folder" if os.path.exists(nearest) and not os.path.isdir(nearest) else "cannot be written"
        raise InputError(f"{label} {text!r}: {nearest} {why} (read-only or no permission); "
                         "choose a folder you may write in")


def _same_file(a, b):
    """Whether two paths name one file (links and relative spellings included)."""
    try:
        return os.path.samefile(a, b)
    except OSError:  # one does not exist (yet): compare the resolved names
        return os.path.realpath(a) == os.path.realpath(b)


def _check_not_input(text, full, label, inputs):
    for what, path in inputs:
        if path is not None and _same_file(full, os.fspath(path)):
            raise InputError(f"{label} {text!r} is the {what} this command reads; an output never replaces an "
                             "input: give another file name")


def result_kind(path):
    """The kind of result (a key of :data:`KINDS`) in a netCDF file written by this project, else None.

    Only the global attributes and dimensions are read. None for any other
    file: not netCDF, unreadable or truncated, written by other software, or
    a netCDF of this project that is none of the kinds.
    """
    try:
        import netCDF4

        with netCDF4.Dataset(os.fspath(path), "r") as nc:
            attrs = set(nc.ncattrs())
            source = str(nc.getncattr("source")) if "source" in attrs else ""
            dims = set(nc.dimensions)
            names = set(nc.variables)
    except (OSError, RuntimeError, ValueError, UnicodeError):  # not netCDF, truncated, no permission
        return None
    if not source.startswith("frustum-pipeline"):
        return None
    if "site" in dims and "annual_frequency" in names:
        return "risk"
    if "intensity_measure" in attrs or ("state" in dims and "median" in names):
        return "fragility"
    if "time" in dims:
        return "histories"
    if {"column", "record", "angle", "scale"} <= dims:
        return "study"
    return None


def check_output_file(path, label, *, kind=None, inputs=()):
    """Refuse a results path that cannot be written or would replace an input or a user's file; returns it absolute.

    The checkpoint folder of a study, ``PATH.checkpoint``, lies beside the
    file, so a path with a file name keeps it inside the output's folder.

    Parameters
    ----------
    path : str or os.PathLike
    label : str
        How the user gave it (``"--out"``, ``"field output"``), for the message.
    kind : str, optional
        A key of :data:`KINDS`: the netCDF result the command writes. An
        existing file at ``path`` is then overwritten only if it is a result
        of that kind written by this project (:func:`result_kind`).
    inputs : iterable of (str, path)
        What the command reads (``("study file", "s.toml")``); ``path`` may
        name none of them.
    """
    text = os.fspath(path)
    full = os.path.abspath(text)
    name = os.path.basename(full)
    if not text or text.endswith(("/", os.sep)) or not name or os.path.isdir(full):
        raise InputError(f"{label} {text!r} is a folder; give the path of a file, e.g. out/results.nc")
    _check_not_input(text, full, label, inputs)
    if kind is not None and os.path.lexists(full) and result_kind(full) != kind:
        found = result_kind(full)
        what = f"a {KINDS[found]}" if found else "not a netCDF result written by frustum"
        raise InputError(f"{label} {text!r} exists and is {what}; frustum overwrites only a {KINDS[kind]}: "
                         "give a new file name (or move that file away)")
    _check_folder_writable(text, os.path.dirname(full), label)
    return full


def check_output_folder(path, label, *, writes=(), kinds=None, inputs=()):
    """Refuse an output folder that cannot be written or whose files would replace an input; returns it absolute.

    Parameters
    ----------
    path : str or os.PathLike
        The folder (created if missing; an existing one keeps its other files).
    label : str
        How the user gave it (``"--out"``).
    writes : iterable of str
        Names, relative to the folder, of the files the command writes there.
    kinds : dict, optional
        ``{name: kind}`` for the netCDF results among ``writes`` (see :func:`check_output_file`).
    inputs : iterable of (str, path)
        What the command reads.
    """
    text = os.fspath(path)
    full = os.path.abspath(text)
    if not text:
        raise InputError(f"{label} '': give the path of a folder, e.g. out/report")
    if os.path.lexists(full) and not os.path.isdir(full):
        raise InputError(f"{label} {text!r} is a file, not a folder; give the path of a folder, e.g. out/report "
                         "(a folder is written, never over a file)")
    _check_not_input(text, full, label, inputs)
    for name in writes:
        inner = os.path.join(full, name)
        _check_not_input(os.path.join(text, name), inner, label, inputs)
        kind = (kinds or {}).get(name)
        if os.path.lexists(inner) and kind is not None and result_kind(inner) != kind:
            raise InputError(f"{label} {text!r}: {inner} exists and is not a {KINDS[kind]}; give another folder "
                             "(or move that file away)")
    _check_folder_writable(text, full, label)
    return full


def check_plot_file(path, label, *, inputs=()):
    """Refuse a figure path whose format matplotlib cannot write, that cannot be written or is an input; returns it."""
    from matplotlib.backend_bases import FigureCanvasBase

    text = os.fspath(path)
    formats = FigureCanvasBase.get_supported_filetypes()
    suffix = os.path.splitext(text)[1].lower().lstrip(".")
    if suffix not in formats:
        raise InputError(f"{label} {text!r}: not a figure format matplotlib writes; end the name in one of "
                         f"{', '.join('.' + f for f in sorted(formats))} (e.g. .png)")
    return check_output_file(text, label, inputs=inputs)
