"""Ground motions from files: anything ``obspy.read`` knows, AT2, text and CSV.

Units. ObsPy's K-NET, Kinemetrics EVT and this package's AT2 readers carry a
physical calibration: ``data * stats.calib`` is acceleration in m/s^2 (ObsPy's
EVT reader uses g = 9.81 m/s^2 in that factor). Every other format (MiniSEED,
SAC, GSE2, ...) stores numbers whose meaning the header does not say reliably,
so the caller must state ``units``; without them the load fails.

Components. Traces are mapped to x, y, z by the orientation code (the last
letter of the channel): ``E``/``X``/``1`` -> x, ``N``/``Y``/``2`` -> y,
``Z``/``U``/``3`` -> z (east-north-up is right-handed), K-NET's ``EW``, ``NS``,
``UD`` likewise. Files given as a list whose traces carry no orientation code
(AT2 components named by azimuth) are taken in the order of the list. Anything
else needs ``components=(x, y[, z])`` naming channels or trace ids.
"""

import re
import warnings
from pathlib import Path

import numpy as np
import obspy
from obspy import Stream, Trace

from pipeline.errors import InputError
from pipeline.groundmotion.record import GroundMotion, log_step
from pipeline.groundmotion.units import to_ms2_factor

__all__ = ["read_file", "read_text", "TEXT_SUFFIXES", "CALIBRATED_FORMATS"]

#: Formats whose reader leaves ``data * calib`` in m/s^2.
CALIBRATED_FORMATS = {"KNET": "ObsPy K-NET reader (header scale factor, gal -> m/s^2)",
                      "KINEMETRICS_EVT": "ObsPy Kinemetrics EVT reader (full scale and sensitivity, g = 9.81)",
                      "AT2": "PEER NGA AT2 (units of g)"}

#: File name endings read as plain text / CSV rather than through ObsPy.
TEXT_SUFFIXES = (".txt", ".csv", ".dat", ".tsv", ".acc")

_ORIENTATION = {"E": "x", "X": "x", "1": "x", "N": "y", "Y": "y", "2": "y", "Z": "z", "U": "z", "3": "z"}
_KNET_CHANNELS = {"EW": "x", "NS": "y", "UD": "z", "EW1": "x", "NS1": "y", "UD1": "z", "EW2": "x", "NS2": "y", "UD2": "z"}
# Warnings by which ObsPy reports a damaged file while still returning data.
_DAMAGE = re.compile(r"corrupt|truncat|not enough|skipp|inconsistent|invalid", re.IGNORECASE)


def _one_line(exc):
    return " ".join(str(exc).split())


def _obspy_read(path, format=None, **kwargs):
    """``obspy.read`` that turns damage warnings and read errors into InputError."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            st = obspy.read(str(path), format=format, **kwargs)
        except InputError:
            raise
        except TypeError as exc:
            if "Unknown format" in str(exc):
                raise InputError(
                    f"{path}: not a waveform format ObsPy knows (corrupt file?); for text or CSV "
                    f"use a name ending in {', '.join(TEXT_SUFFIXES)} or format='text'"
                ) from None
            raise InputError(f"{path}: could not be read ({_one_line(exc)}); the file may be truncated or corrupt") from None
        except Exception as exc:  # noqa: BLE001 - every reader has its own exceptions
            raise InputError(f"{path}: could not be read ({type(exc).__name__}: {_one_line(exc)}); the file may be truncated or corrupt") from None
    for w in caught:
        if _DAMAGE.search(str(w.message)):
            raise InputError(f"{path}: damaged file, ObsPy says: {_one_line(w.message)} (truncated or corrupt; re-export it)")
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    return st


def _orientation(trace):
    channel = (trace.stats.channel or "").upper()
    if channel in _KNET_CHANNELS:
        return _KNET_CHANNELS[channel]
    if len(channel) in (1, 3) and channel[-1:] in _ORIENTATION:
        return _ORIENTATION[channel[-1]]
    return None


def _match(stream, selector, where):
    hits = [tr for tr in stream if selector in (tr.id, tr.stats.channel)]
    if len(hits) != 1:
        available = ", ".join(f"{tr.id!r}" for tr in stream)
        raise InputError(f"{where}: component selector {selector!r} matches {len(hits)} traces; choose one of {available}")
    return hits[0]


def _zero_like(trace, where):
    zero = trace.copy()
    zero.data = np.zeros(trace.stats.npts)
    zero.stats.channel = (trace.stats.channel[:-1] + "0") if trace.stats.channel else "y0"
    log_step(zero, f"missing_y='zero': {where} has one horizontal component; y set to 0")
    return zero


def select_components(stream, where, components=None, missing_y="error", ordered=False):
    """Order the traces of ``stream`` as x, y[, z] (see the module notes)."""
    if missing_y not in ("error", "zero"):
        raise InputError(f"{where}: missing_y must be 'error' or 'zero', got {missing_y!r}")
    ids = [tr.id for tr in stream]
    if len(set(ids)) != len(ids):
        dup = sorted({i for i in ids if ids.count(i) > 1})
        raise InputError(f"{where}: trace {dup[0]} comes in several pieces (gaps or overlaps: non-uniform sampling); merge or trim it first")
    if components is not None:
        comps = list(components)
        if len(comps) not in (2, 3) or comps[0] is None:
            raise InputError(f"{where}: components must name x, y[, z] (y may be None for 'y = 0'), got {components!r}")
        x = _match(stream, comps[0], where)
        y = _zero_like(x, where) if comps[1] is None else _match(stream, comps[1], where)
        picked = [x, y] + ([_match(stream, comps[2], where)] if len(comps) == 3 and comps[2] is not None else [])
        return Stream(picked)
    roles = {}
    for tr in stream:
        role = _orientation(tr)
        if role is None:
            roles = None
            break
        if role in roles:
            raise InputError(f"{where}: two traces ({roles[role].id}, {tr.id}) look like component {role}; give components=(x, y[, z])")
        roles[role] = tr
    if roles is None:
        if ordered and len(stream) in (1, 2, 3):
            roles = dict(zip(("x", "y", "z"), stream))
        else:
            raise InputError(
                f"{where}: cannot tell which trace is x, y or z ({', '.join(ids)}); "
                "give components=(x, y[, z]) with channel codes or trace ids"
            )
    if "x" not in roles and "y" in roles:
        raise InputError(f"{where}: only a y-like horizontal trace ({roles['y'].id}); give components=(x, None) to use it as x")
    if "x" not in roles:
        raise InputError(f"{where}: no horizontal component among {', '.join(ids)}")
    if "y" not in roles:
        if missing_y != "zero":
            raise InputError(
                f"{where}: only one horizontal component ({roles['x'].id}); load its pair too "
                "(a list of files) or set y = 0 with missing_y='zero' (--missing-y zero on the command line)"
            )
        roles["y"] = _zero_like(roles["x"], where)
    return Stream([roles[k] for k in ("x", "y", "z") if k in roles])


def _metadata_from_stats(stream, path):
    st0 = stream[0].stats
    meta = {"station": st0.station or None, "source": str(path), "licence": "unknown (user file)",
            "format": st0.get("_format")}
    if "knet" in st0:
        k = st0.knet
        meta.update(magnitude=k.get("mag"), event_latitude=k.get("evla"), event_longitude=k.get("evlo"),
                    event_depth_km=k.get("evdp"))
        if all(v is not None for v in (k.get("evla"), k.get("evlo"), k.get("stla"), k.get("stlo"))):
            from obspy.geodetics import gps2dist_azimuth

            meta["distance_km"] = gps2dist_azimuth(k.evla, k.evlo, k.stla, k.stlo)[0] / 1000.0
        meta["event"] = f"K-NET event {k.get('evot', '')}".strip()
    if "at2" in st0:
        a = st0.at2
        meta.update(event=a.get("event") or None, date=a.get("date") or None, station=a.get("station") or None)
    if "sac" in st0:
        s = st0.sac
        meta.update(event=s.get("kevnm"), magnitude=s.get("mag"), distance_km=s.get("dist"))
    if "kinemetrics_evt" in st0:
        e = st0.kinemetrics_evt
        meta.update(station=e.get("stnid"), instrument=e.get("instrument"))
    return {k: v for k, v in meta.items() if v is not None}


def read_file(path, *, units=None, components=None, missing_y="error", format=None, record_id=None, metadata=None, **read_kwargs):
    """Read one file, or a list of files forming one record, into a GroundMotion.

    Parameters
    ----------
    path : str or path-like or list of them
        Waveform file(s). Text and CSV (names ending in ``TEXT_SUFFIXES`` or
        ``format='text'``) go to :func:`read_text`.
    units : str, optional
        Units of ``data * calib`` for formats without a physical calibration
        (required for them). For calibrated formats (K-NET, EVT, AT2) it may
        only repeat 'm/s^2'.
    components : sequence, optional
        Channel codes or trace ids for x, y[, z]; y may be None (y = 0).
    missing_y : {'error', 'zero'}
        What to do if only one horizontal component is present.
    format : str, optional
        ObsPy format name, or 'text'.
    record_id : str, optional
        Id of the motion (default: the file name).
    metadata : dict, optional
        Extra metadata (overrides what the header gives).
    """
    paths = [Path(p) for p in path] if isinstance(path, (list, tuple)) else [Path(path)]
    where = ", ".join(str(p) for p in paths)
    for p in paths:
        if not p.is_file():
            raise InputError(f"{p}: no such file; check the path or use a catalog id (`frustum records list`)")
    is_text = (format or "").lower() == "text" or (format is None and all(p.suffix.lower() in TEXT_SUFFIXES for p in paths))
    if is_text:
        if len(paths) != 1:
            raise InputError(f"{where}: give one text file holding all components as columns")
        return read_text(paths[0], units=units, missing_y=missing_y, record_id=record_id, metadata=metadata, **read_kwargs)

    stream = Stream()
    for p in paths:
        stream += _obspy_read(p, format=format, **read_kwargs)
    formats = {tr.stats.get("_format") for tr in stream}
    calibrated = formats <= set(CALIBRATED_FORMATS)
    if calibrated:
        if units is not None and to_ms2_factor(units, where) != 1.0:
            raise InputError(
                f"{where}: format {'/'.join(sorted(formats))} carries its own calibration to m/s^2; "
                f"drop units={units!r}"
            )
        factor = 1.0
        how = "header calibration: " + "; ".join(CALIBRATED_FORMATS[f] for f in sorted(formats))
    else:
        factor = to_ms2_factor(units, where)
        how = f"stated units {units!r} x {factor!r} -> m/s^2"
    stream = select_components(stream, where, components, missing_y, ordered=len(paths) > 1)
    for tr in stream:
        tr.stats.calib = float(tr.stats.calib) * factor
        log_step(tr, f"loaded {tr.stats.get('_format', '?')} from {where}; {how}")
    meta = _metadata_from_stats(stream, where)
    meta.update(metadata or {})
    return GroundMotion(stream, record_id=record_id or paths[0].name, metadata=meta, source=where)


_TIME_NAMES = {"t", "time", "time_s", "t_s"}
_COLUMN_NAMES = {
    "x": {"x", "acc_x", "ax", "ground_acc_x", "h1"},
    "y": {"y", "acc_y", "ay", "ground_acc_y", "h2"},
    "z": {"z", "acc_z", "az", "ground_acc_z", "v", "up"},
}
_NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eEdD][-+]?\d+)?$|^[-+]?(nan|inf|infinity)$", re.IGNORECASE)


def read_text(path, *, units, dt=None, missing_y="error", record_id=None, metadata=None, delimiter=None):
    """Read acceleration columns from a plain text or CSV file.

    Layout: lines starting with ``#`` are comments; an optional first row of
    column names (``time``/``t``, ``x``/``acc_x``, ``y``/``acc_y``,
    ``z``/``acc_z``); then numbers separated by commas or whitespace. Without
    names: if ``dt`` [s] is given the columns are x[, y[, z]], otherwise the
    first column is time [s] and the rest x[, y[, z]]. A time column must be
    uniform to 1e-3 of its step (text rounding), else the load fails.

    Parameters
    ----------
    units : str
        Units of the acceleration columns (required: text states none).
    """
    where = str(path)
    factor = to_ms2_factor(units, where)
    rows, names = [], None
    with open(path, "r", encoding="utf-8", errors="replace") as fh:
        for lineno, line in enumerate(fh, 1):
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            sep = delimiter or ("," if "," in line else (";" if ";" in line else None))
            fields = [f.strip() for f in (line.split(sep) if sep else line.split())]
            if not all(_NUMBER.match(f) for f in fields):
                if names is None and not rows:
                    names = [f.lower() for f in fields]
                    continue
                raise InputError(f"{where}, line {lineno}: not a row of numbers: {line[:60]!r} (corrupt file?)")
            if rows and len(fields) != len(rows[0]):
                raise InputError(
                    f"{where}, line {lineno}: {len(fields)} columns where earlier rows have {len(rows[0])} "
                    "(truncated row or components of different lengths)"
                )
            rows.append([float(f.replace("d", "e").replace("D", "E")) for f in fields])
    if len(rows) < 2:
        raise InputError(f"{where}: fewer than 2 rows of samples (empty or truncated file)")
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
    else:
        ncol = table.shape[1]
        first = 0 if dt is not None else 1
        if ncol - first not in (1, 2, 3):
            raise InputError(f"{where}: {ncol} columns; expected [time,] x[, y[, z]]")
        cols = dict(zip(("x", "y", "z"), table[:, first:].T))
        if dt is None:
            cols["time"] = table[:, 0]
    if "time" in cols:
        t = cols.pop("time")
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
        dt = float(step)
    if dt is None:
        raise InputError(f"{where}: no sampling: give dt [s] or a time column")
    traces = []
    for name in ("x", "y", "z"):
        if name in cols:
            tr = Trace(data=cols[name] * factor)
            tr.stats.delta = float(dt)
            tr.stats.channel = f"HN{name.upper()}"
            log_step(tr, f"loaded text column {name} from {where}; stated units {units!r} -> m/s^2")
            traces.append(tr)
    stream = select_components(Stream(traces), where, None, missing_y)
    meta = {"source": where, "licence": "unknown (user file)", "format": "text"}
    meta.update(metadata or {})
    return GroundMotion(stream, record_id=record_id or Path(path).name, metadata=meta, source=where)
