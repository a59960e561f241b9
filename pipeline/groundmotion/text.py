"""Acceleration from plain text and CSV files (the OpenSees ``Path`` style included).

Layouts, after comment lines (``#``) and an optional row of column names
(``time``/``t``, ``x``/``acc_x``, ``y``/``acc_y``, ``z``/``acc_z``):

* columns ``[time,] x[, y[, z]]``: with ``dt`` [s] the columns are
  x[, y[, z]], without it the first is time [s] (uniform to 1e-3 of its step);
* one series wrapped over rows, read row by row (OpenSees ``Path`` files,
  the body of a PEER file): with ``dt`` and no names, when the rows hold more
  than 3 numbers or only the last row is shorter than the others. A series
  wrapped 2 or 3 to a row with a full last row cannot be told from columns:
  write it one number per line.

Samples may be separated by commas, semicolons or white space; Fortran
exponents (``1.0D-03``) are read.
"""

import re
from pathlib import Path

import numpy as np
from obspy import Stream, Trace

from pipeline.errors import InputError
from pipeline.groundmotion.components import select_components
from pipeline.groundmotion.options import how_to_give
from pipeline.groundmotion.provenance import log_step
from pipeline.groundmotion.record import GroundMotion
from pipeline.groundmotion.units import to_ms2_factor

__all__ = ["read_text", "is_plain_numbers", "TEXT_SUFFIXES"]

#: File name endings read as plain text / CSV rather than through ObsPy.
TEXT_SUFFIXES = (".txt", ".csv", ".dat", ".tsv", ".acc")

_TIME_NAMES = {"t", "time", "time_s", "t_s"}
_COLUMN_NAMES = {
    "x": {"x", "acc_x", "ax", "ground_acc_x", "h1"},
    "y": {"y", "acc_y", "ay", "ground_acc_y", "h2"},
    "z": {"z", "acc_z", "az", "ground_acc_z", "v", "up"},
}
_NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eEdD][-+]?\d+)?$|^[-+]?(nan|inf|infinity)$", re.IGNORECASE)


def _fields(line, delimiter=None):
    sep = delimiter or ("," if "," in line else (";" if ";" in line else None))
    return [f.strip() for f in (line.split(sep) if sep else line.split())]


def is_plain_numbers(path, probe=65536):
    """True if the file's first lines are rows of numbers (after comments and a row of names).

    Used to read extension-less plain acceleration files (OpenSees inputs
    such as ``elcentro.g3`` or ``GM1.th``) as text rather than through ObsPy,
    none of whose formats is bare numbers.
    """
    try:
        with open(path, "rb") as fh:
            head = fh.read(probe)
        text = head.decode("ascii")
    except (OSError, UnicodeDecodeError):
        return False
    lines = [ln.strip() for ln in text.splitlines()[:-1 if len(head) == probe else None]]
    lines = [ln for ln in lines if ln and not ln.startswith("#")]
    numeric = [all(_NUMBER.match(f) for f in _fields(ln)) for ln in lines[:50]]
    return len(numeric) >= 2 and all(numeric[1:]) and (numeric[0] or len(numeric) > 2)


def _read_rows(path, where, delimiter):
    rows, linenos, names = [], [], None
    with open(path, "r", encoding="utf-8", errors="replace") as fh:
        for lineno, line in enumerate(fh, 1):
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            fields = _fields(line, delimiter)
            if not all(_NUMBER.match(f) for f in fields):
                if names is None and not rows:
                    names = [f.lower() for f in fields]
                    continue
                raise InputError(f"{where}, line {lineno}: not a row of numbers: {line[:60]!r} (corrupt file?)")
            rows.append([float(f.replace("d", "e").replace("D", "E")) for f in fields])
            linenos.append(lineno)
    return rows, linenos, names


def _columns(rows, linenos, names, dt, where):
    """name -> samples: named or positional columns, or one series wrapped over rows."""
    widths = [len(r) for r in rows]
    wrapped = (names is None and dt is not None
               and (widths[0] > 3 or (len(set(widths[:-1])) == 1 and widths[-1] < widths[0])))
    if wrapped:
        first = np.array([r[0] for r in rows[:-1]] if len(rows) > 2 else [])
        if first.size > 2 and np.allclose(np.diff(first), dt, rtol=1e-3):
            raise InputError(f"{where}: the first column is a time axis with step dt = {dt!r} s; give no dt, "
                             "the time column sets it")
        if len(set(widths[:-1])) != 1 or widths[-1] > widths[0]:
            k = next(i for i, w in enumerate(widths) if w != widths[0])
            raise InputError(f"{where}, line {linenos[k]}: {widths[k]} numbers where earlier rows have "
                             f"{widths[0]} (a series wrapped over rows must fill every row but the last)")
        return {"x": np.array([v for r in rows for v in r])}, "one series wrapped over rows, read row by row"
    for k, w in enumerate(widths):
        if w != widths[0]:
            raise InputError(
                f"{where}, line {linenos[k]}: {w} columns where earlier rows have {widths[0]} "
                "(truncated row or components of different lengths)"
            )
    table = np.array(rows, dtype=np.float64)
    if names is not None:
        if len(names) != table.shape[1]:
            raise InputError(f"{where}: {len(names)} column names for {table.shape[1]} columns")
        cols = {}
        for i, n in enumerate(names):
            role = "time" if n in _TIME_NAMES else next((k for k, v in _COLUMN_NAMES.items() if n in v), None)
            if role is None:
                raise InputError(f"{where}: unknown column name {n!r}; use time, x, y, z (or acc_x, acc_y, acc_z)")
            cols[role] = table[:, i]
        return cols, "named columns " + ", ".join(names)
    ncol = table.shape[1]
    first = 0 if dt is not None else 1
    if ncol - first not in (1, 2, 3):
        raise InputError(f"{where}: {ncol} columns; expected [time,] x[, y[, z]] (with {how_to_give('dt')} "
                         "the columns are x[, y[, z]] and no time)")
    cols = dict(zip(("x", "y", "z"), table[:, first:].T))
    if dt is None:
        cols["time"] = table[:, 0]
    return cols, ("columns " + ", ".join(["time"] * (dt is None) + list(cols)[: ncol - first]))


def _time_step(t, dt, where):
    step = (t[-1] - t[0]) / (t.size - 1)
    if not np.all(np.isfinite(t)) or step <= 0:
        raise InputError(f"{where}: time column is not increasing; fix the file")
    dev = np.max(np.abs(t - (t[0] + step * np.arange(t.size))))
    if dev > 1e-3 * step:
        k = int(np.argmax(np.abs(np.diff(t) - step)))
        raise InputError(
            f"{where}: non-uniform sampling: time column steps from {float(t[k])!r} to {float(t[k + 1])!r} s "
            f"(mean step {float(step)!r} s); resample to a uniform step first"
        )
    if dt is not None and abs(dt - step) > 1e-3 * step:
        raise InputError(f"{where}: dt={dt!r} s disagrees with the time column's step {float(step)!r} s")
    return float(step)


def read_text(path, *, units, dt=None, missing_y="error", record_id=None, metadata=None, delimiter=None):
    """Read acceleration from a plain text or CSV file (layouts: module notes).

    Parameters
    ----------
    path : str or path-like
    units : str
        Units of the acceleration (required: text states none).
    dt : float, optional
        Time step [s] when the file has no time column.
    missing_y : {"error", "zero"}
        One acceleration column or series: an error, or y = 0.
    record_id : str, optional
    metadata : dict, optional
    delimiter : str, optional
        Column separator (default: comma, semicolon or white space).

    Returns
    -------
    GroundMotion
    """
    where = str(path)
    factor = to_ms2_factor(units, where)
    if dt is not None and not (isinstance(dt, (int, float)) and np.isfinite(dt) and dt > 0):
        raise InputError(f"{where}: dt={dt!r}; give the time step as a positive number of seconds")
    rows, linenos, names = _read_rows(path, where, delimiter)
    if len(rows) < 2 and not (rows and dt is not None and len(rows[0]) > 3):
        raise InputError(f"{where}: fewer than 2 rows of samples (empty or truncated file)")
    cols, layout = _columns(rows, linenos, names, dt, where)
    if "time" in cols:
        dt = _time_step(cols.pop("time"), dt, where)
    if dt is None:
        raise InputError(f"{where}: no sampling: give {how_to_give('dt')} or a time column")
    traces = []
    for name in ("x", "y", "z"):
        if name in cols:
            tr = Trace(data=cols[name] * factor)
            tr.stats.delta = float(dt)
            tr.stats.channel = f"HN{name.upper()}"
            log_step(tr, f"loaded text from {where} ({layout}); component {name}; stated units {units!r} "
                         f"-> m/s^2; dt = {dt!r} s")
            traces.append(tr)
    stream = select_components(Stream(traces), where, None, missing_y)
    meta = {"source": where, "licence": "unknown (user file)", "format": "text"}
    meta.update(metadata or {})
    return GroundMotion(stream, record_id=record_id or Path(path).name, metadata=meta, source=where)
