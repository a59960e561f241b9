"""Ground motions from files and ObsPy streams: anything ``obspy.read`` knows, AT2, plain text.

Units. ObsPy's K-NET, Kinemetrics EVT and this package's AT2 readers carry a
physical calibration: ``data * stats.calib`` is acceleration in m/s^2 (ObsPy's
EVT reader uses g = 9.81 m/s^2 in that factor). Every other format (MiniSEED,
SAC, GSE2, ...) stores numbers whose meaning the header does not say reliably,
so the caller must state ``units``; without them the load fails.

K-NET and KiK-net. NIED's ASCII records carry the recorder's offset; NIED
computes the header's ``Max. Acc.`` after subtracting the mean of the whole
record, and so does the loader (``Trace.detrend("demean")``, logged), so the
record's PGA is the header's.

Components: :mod:`pipeline.groundmotion.components`. Plain text and files of
bare numbers (OpenSees inputs, whatever their name): :mod:`pipeline.groundmotion.text`.
"""

import re
import warnings
from pathlib import Path

import obspy
from obspy import Stream, Trace

from pipeline.errors import InputError
from pipeline.groundmotion.components import select_components
from pipeline.groundmotion.provenance import log_step
from pipeline.groundmotion.record import GroundMotion
from pipeline.groundmotion.text import TEXT_SUFFIXES, is_plain_numbers, read_text
from pipeline.groundmotion.units import to_ms2_factor

__all__ = ["read_file", "read_stream", "read_text", "select_components", "TEXT_SUFFIXES", "CALIBRATED_FORMATS"]

#: Formats whose reader leaves ``data * calib`` in m/s^2.
CALIBRATED_FORMATS = {"KNET": "ObsPy K-NET reader (header scale factor, gal -> m/s^2)",
                      "KINEMETRICS_EVT": "ObsPy Kinemetrics EVT reader (full scale and sensitivity, g = 9.81)",
                      "AT2": "PEER NGA AT2 (units of g)"}

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
                    f"{path}: not a waveform format ObsPy knows, nor rows of numbers (corrupt file?); "
                    f"plain text with a header of its own is read from names ending in {', '.join(TEXT_SUFFIXES)}"
                ) from None
            raise InputError(f"{path}: could not be read ({_one_line(exc)}); the file may be truncated or corrupt") from None
        except Exception as exc:  # noqa: BLE001 - every reader has its own exceptions
            raise InputError(f"{path}: could not be read ({type(exc).__name__}: {_one_line(exc)}); the file may be truncated or corrupt") from None
    for w in caught:
        if _DAMAGE.search(str(w.message)):
            raise InputError(f"{path}: damaged file, ObsPy says: {_one_line(w.message)} (truncated or corrupt; re-export it)")
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    return st


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


def _remove_knet_offset(trace):
    """Subtract the mean of the whole record, as NIED does before computing Max. Acc. (logged)."""
    mean = float(trace.data.mean()) * float(trace.stats.calib)
    trace.detrend("demean")  # ObsPy logs the step in stats.processing
    accmax = (trace.stats.get("knet") or {}).get("accmax")
    peak = float(abs(trace.data).max()) * float(trace.stats.calib)
    log_step(trace, f"K-NET/KiK-net offset {mean:.6g} m/s^2 removed (mean of the whole record, NIED's definition): "
                    f"PGA {100 * peak:.4g} gal" + (f", header Max. Acc. {accmax:g} gal" if accmax is not None else ""))


def read_stream(stream, *, where, units=None, components=None, missing_y="error", ordered=False, record_id=None,
                metadata=None):
    """A GroundMotion from ObsPy traces (a copy; the caller's stream is not changed).

    Parameters
    ----------
    stream : obspy.Stream or obspy.Trace
        Traces as ``obspy.read`` returns them. Traces read from K-NET, EVT or
        AT2 carry their calibration; any other needs ``units``.
    where : str
        The record's name in messages (file names, or the id).
    units, components, missing_y
        See :func:`read_file`.
    ordered : bool
        The traces come from a list of files in x, y[, z] order.
    record_id : str, optional
        Default: ``where``.
    metadata : dict, optional

    Returns
    -------
    GroundMotion
    """
    stream = Stream([stream]) if isinstance(stream, Trace) else stream
    if not isinstance(stream, Stream) or not len(stream):
        raise InputError(f"{where}: expected an obspy Stream or Trace with data, got {stream!r}")
    stream = stream.copy()
    formats = {tr.stats.get("_format") for tr in stream}
    if formats <= set(CALIBRATED_FORMATS):
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
    stream = select_components(stream, where, components, missing_y, ordered=ordered)
    for tr in stream:
        if tr.stats.get("_format") == "KNET":
            _remove_knet_offset(tr)
        tr.stats.calib = float(tr.stats.calib) * factor
        log_step(tr, f"loaded {tr.stats.get('_format', 'ObsPy trace')} from {where}; {how}")
    meta = _metadata_from_stats(stream, where)
    meta.update(metadata or {})
    return GroundMotion(stream, record_id=record_id or where, metadata=meta, source=where)


def read_file(path, *, units=None, components=None, missing_y="error", format=None, dt=None, record_id=None,
              metadata=None, **read_kwargs):
    """Read one file, or a list of files forming one record, into a GroundMotion.

    Parameters
    ----------
    path : str or path-like or list of them
        Waveform file(s). Plain text (names ending in ``TEXT_SUFFIXES``,
        ``format='text'``, or any file of bare numbers) goes to
        :func:`pipeline.groundmotion.text.read_text`.
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
    dt : float, optional
        Time step [s] of a text file without a time column. A waveform file
        states its own; a ``dt`` that disagrees with it is an error.
    record_id : str, optional
        Id of the motion (default: the file name).
    metadata : dict, optional
        Extra metadata (overrides what the header gives).
    """
    paths = [Path(p) for p in path] if isinstance(path, (list, tuple)) else [Path(path)]
    where = ", ".join(str(p) for p in paths)
    if not 1 <= len(paths) <= 3:
        raise InputError(f"{where or 'no file'}: a record is one file, or 2 or 3 files (x, y[, z])")
    for p in paths:
        if not p.is_file():
            raise InputError(f"{p}: no such file; check the path or use a catalog id (`frustum records list`)")
    if (format or "").lower() == "text" or (
            format is None and all(p.suffix.lower() in TEXT_SUFFIXES or is_plain_numbers(p) for p in paths)):
        if len(paths) != 1:
            raise InputError(f"{where}: give one text file holding all components as columns")
        return read_text(paths[0], units=units, dt=dt, missing_y=missing_y, record_id=record_id, metadata=metadata,
                         **read_kwargs)
    stream = Stream()
    for p in paths:
        stream += _obspy_read(p, format=format, **read_kwargs)
    if dt is not None:
        steps = sorted({tr.stats.delta for tr in stream})
        if any(abs(step - dt) > 1e-9 * dt for step in steps):
            raise InputError(f"{where}: dt={dt!r} s, but the file states its own time step "
                             f"({', '.join(f'{s!r}' for s in steps)} s); drop dt (it is for text files without time)")
    return read_stream(stream, where=where, units=units, components=components, missing_y=missing_y,
                       ordered=len(paths) > 1, record_id=record_id or paths[0].name, metadata=metadata)


