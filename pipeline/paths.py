"""Where results go, checked before any computing.

A run that can only fail at its end (a results path that is a folder, the
file-system root, a folder nobody may write, a plot format matplotlib does not
have) is refused at its start, naming the path and the fix.

No output ever replaces an input or a file of the user's: every command
names its inputs and the kind of file it writes, and :func:`check_output_file`
refuses an output that is one of the inputs, or an existing file that is not
a file of that kind written by this project. A file of the same kind written
by this project is overwritten, as a rerun expects. How an existing file is
recognised, reading little of it:

- a netCDF result (:data:`KINDS`): its global attributes and dimensions
  (:func:`result_kind`);
- a CSV table (:data:`CSV_HEADERS`): the start of its header row, because a
  CSV has no place for a mark that every reader skips;
- any other file (figures, animations, a report's Markdown, HTML and
  GeoJSON): the words :data:`MARK`, which every such file carries in its
  format's metadata (:func:`pipeline.figfile.mark_savefig_kwargs`) or text,
  found within :data:`MARK_WINDOW` bytes of either end
  (:func:`written_by_frustum`). A format that cannot carry it (``.pgf``,
  ``.raw``, ``.rgba``) is never recognised: an existing file of such a name
  is refused, always.

These checks are made by the commands, on the paths a user gives, before any
computing. The writers themselves (:func:`pipeline.figfile.save_figure`,
:func:`pipeline.report.write_report`, :func:`pipeline.animate.animate`) do not
refuse an existing file, so the project's own study scripts still regenerate
the figures and reports committed under ``studies/`` before the mark existed
(they write them under names they own, and mark them from then on).
"""

import glob
import os
import secrets
import zlib

from pipeline.atomic import PARTIAL_PREFIX
from pipeline.errors import InputError

__all__ = ["CSV_HEADERS", "KINDS", "MARK", "MARK_WINDOW", "MARKED", "check_output_file", "check_output_folder",
           "check_plot_file", "mark_text", "result_kind", "written_by_frustum"]

#: The kinds of netCDF result this project writes, and how the messages name them.
KINDS = {
    "histories": "histories file of 'frustum simulate'",
    "study": "results file of 'frustum study run'",
    "fragility": "fragility file of 'frustum fragility'",
    "risk": "risk file of 'frustum risk'",
    "comparison": "model comparison of 'frustum report'",
}

#: CSV tables this project writes: how the messages name them and how their header row starts.
CSV_HEADERS = {
    "risk-csv": ("CSV written by 'frustum risk'", "site,site_longitude,site_latitude,column,model,state,"),
    "summary-csv": ("summary.csv written by 'frustum report'", "column,model,R_m,r_m,"),
    "comparison-csv": ("comparison.csv written by 'frustum report'", "column,reference,model,"),
}

#: The words every other file this project writes carries (see :func:`mark_text`).
MARK = "written by frustum-pipeline"
#: Bytes read at each end of a file to find :data:`MARK` [bytes]: a figure's metadata sits near its start
#: (PNG, SVG, JPEG, GIF, TIFF, PostScript) or its end (PDF, WebP, MP4), whatever the size of the file.
MARK_WINDOW = 256 * 1024
#: The ``kind`` of :func:`check_output_file` for a file recognised by :data:`MARK`.
MARKED = "marked"


def mark_text():
    """What a file written by this project carries to be recognised: :data:`MARK` and the version."""
    from pipeline import __version__

    return f"{MARK} {__version__}"


def written_by_frustum(path):
    """Whether the file at ``path`` carries :data:`MARK` (within :data:`MARK_WINDOW` bytes of either end).

    A gzip-compressed file (``.svgz``) is searched in the start of its
    decompressed text. False for a file that cannot be read.
    """
    mark = MARK.encode()
    try:
        with open(path, "rb") as fh:
            head = fh.read(MARK_WINDOW)
            size = fh.seek(0, os.SEEK_END)
            fh.seek(max(0, size - MARK_WINDOW))  # overlaps the head in a small file: no mark cut in two
            tail = fh.read(MARK_WINDOW)
    except OSError:
        return False
    if head.startswith(b"\x1f\x8b"):  # gzip (.svgz): the mark is in the text it compresses
        try:
            head = zlib.decompressobj(wbits=31).decompress(head, MARK_WINDOW)
        except zlib.error:
            return False
    return mark in head or mark in tail


def _csv_header_starts(path, start):
    """Whether the first line of the text file at ``path`` starts with ``start``."""
    try:
        with open(path, encoding="utf-8") as fh:
            return fh.readline(4096).startswith(start)
    except (OSError, UnicodeError):
        return False


def _not_ours(full, kind):
    """Why the existing file at ``full`` may not be replaced by a ``kind`` (see :func:`check_output_file`), or None."""
    if kind is None or not os.path.lexists(full):
        return None
    if kind in KINDS:
        found = result_kind(full)
        if found == kind:
            return None
        what = f"a {KINDS[found]}" if found else "not a netCDF result written by frustum"
        return f"is {what} (frustum overwrites only a {KINDS[kind]})"
    if kind in CSV_HEADERS:
        what, start = CSV_HEADERS[kind]
        return None if _csv_header_starts(full, start) else f"is not a {what}"
    if kind == MARKED:
        return None if written_by_frustum(full) else "was not written by frustum"
    raise ValueError(f"unknown kind of output {kind!r}")


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
    if "reference_model" in attrs:
        return "comparison"
    if "intensity_measure" in attrs or ("state" in dims and "median" in names):
        return "fragility"
    if "time" in dims:
        return "histories"
    if {"column", "record", "angle", "scale"} <= dims:
        return "study"
    return None


def check_output_file(path, label, *, kind=MARKED, inputs=()):
    """Refuse a results path that cannot be written or would replace an input or a user's file; returns it absolute.

    The checkpoint folder of a study, ``PATH.checkpoint``, lies beside the
    file, so a path with a file name keeps it inside the output's folder.

    Parameters
    ----------
    path : str or os.PathLike
    label : str
        How the user gave it (``"--out"``, ``"field output"``), for the message.
    kind : str or None
        What an existing file at ``path`` must be for the command to replace
        it: a key of :data:`KINDS` (a netCDF result of that kind written by
        this project, :func:`result_kind`), a key of :data:`CSV_HEADERS`, or
        :data:`MARKED` (the default: any other file this project wrote,
        :func:`written_by_frustum`). None: not checked here (a log the
        command appends to; a caller comparing two paths).
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
    why = _not_ours(full, kind)
    if why:
        raise InputError(f"{label} {text!r} exists and {why}; give another file name or remove it")
    _check_folder_writable(text, os.path.dirname(full), label)
    return full


def check_output_folder(path, label, *, writes=(), kinds=None, inputs=()):
    """Refuse an output folder that cannot be written or whose files would replace an input or a user's file;
    returns it absolute.

    Parameters
    ----------
    path : str or os.PathLike
        The folder (created if missing; an existing one keeps its other files).
    label : str
        How the user gave it (``"--out"``).
    writes : iterable of str
        Names, relative to the folder, of the files the command writes there;
        a name with wildcards (``"figures/*.png"``) stands for every existing
        file it matches, for files whose names depend on the data.
    kinds : dict, optional
        ``{name: kind}`` among ``writes`` (see :func:`check_output_file`); a
        name not in it is :data:`MARKED`.
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
        kind = (kinds or {}).get(name, MARKED)
        matches = ([os.path.relpath(p, full) for p in sorted(glob.glob(os.path.join(glob.escape(full), name)))]
                   if any(c in name for c in "*?[") else [name])
        for match in matches:
            inner = os.path.join(full, match)
            _check_not_input(os.path.join(text, match), inner, label, inputs)
            why = _not_ours(inner, kind)
            if why:
                raise InputError(f"{label} {text!r}: {inner} exists and {why}; give another folder or remove "
                                 "that file")
    _check_folder_writable(text, full, label)
    return full


def check_plot_file(path, label, *, inputs=(), kind=MARKED):
    """Refuse a figure path whose format matplotlib cannot write, that cannot be written, is an input or would
    replace a file this project did not write (:func:`check_output_file`, ``kind``); returns it absolute."""
    from matplotlib.backend_bases import FigureCanvasBase

    text = os.fspath(path)
    formats = FigureCanvasBase.get_supported_filetypes()
    suffix = os.path.splitext(text)[1].lower().lstrip(".")
    if suffix not in formats:
        raise InputError(f"{label} {text!r}: not a figure format matplotlib writes; end the name in one of "
                         f"{', '.join('.' + f for f in sorted(formats))} (e.g. .png)")
    return check_output_file(text, label, kind=kind, inputs=inputs)
