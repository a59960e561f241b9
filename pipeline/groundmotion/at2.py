"""PEER NGA ``.AT2`` acceleration files as an ObsPy waveform plugin.

Registered through the entry points in ``pyproject.toml`` so that
``obspy.read("x.AT2")`` and ``stream.write("x.AT2", format="AT2")`` work.

The format (PEER NGA database, both the NGA-West1 and NGA-West2 flavours):

.. code-block:: text

    PEER NGA STRONG MOTION DATABASE RECORD
    Northridge-01, 1/17/1994, Beverly Hills - 12520 Mulhol, 9
    ACCELERATION TIME SERIES IN UNITS OF G
    NPTS=  2999, DT=   .0100 SEC
      .1234567E-02  -.2345678E-02 ...

NGA-West1 files write the fourth line as ``  2999    0.0100    NPTS, DT``.
One file holds one component, in units of g.

Convention shared with ObsPy's K-NET and Kinemetrics readers: the samples are
stored as in the file (g) and ``stats.calib`` converts them to m/s^2, so
``trace.data * trace.stats.calib`` is the acceleration in m/s^2.  The writer
uses the same convention: it writes ``data * calib / g``.
"""

import io
import math
import os
import re

import numpy as np
from obspy import Stream, Trace
from obspy.core.util import AttribDict

from pipeline.atomic import atomic_open
from pipeline.errors import InputError
from pipeline.units import G

__all__ = ["is_at2", "read_at2", "write_at2", "component_orientation"]

_NPTS_DT_WEST2 = re.compile(
    r"NPTS\s*=\s*(?P<npts>\d+)\s*,?\s*DT\s*=\s*(?P<dt>[-+0-9.EeDd]+)", re.IGNORECASE
)
_NPTS_DT_WEST1 = re.compile(
    r"^\s*(?P<npts>\d+)\s+(?P<dt>[-+0-9.EeDd]+)\s+NPTS\s*,\s*DT", re.IGNORECASE
)
_SAMPLE = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[EeDd][-+]?\d+)?")


def _name(source):
    return getattr(source, "name", None) or str(source)


def _head_lines(filename, n=4):
    """First ``n`` lines of a file or file object as text (or None if binary)."""
    if hasattr(filename, "read"):
        pos = filename.tell()
        raw = filename.read(4096)
        filename.seek(pos)
    else:
        with open(filename, "rb") as fh:
            raw = fh.read(4096)
    if isinstance(raw, str):
        raw = raw.encode("latin-1", "replace")
    if b"\x00" in raw:
        return None
    return raw.decode("latin-1").splitlines()[:n]


def is_at2(filename):
    """Return True if ``filename`` looks like a PEER NGA acceleration file.

    Called by ``obspy.read`` on every file whose format is not given, so it
    never raises: anything unreadable is simply "not AT2".
    """
    try:
        lines = _head_lines(filename)
    except Exception:  # noqa: BLE001 - format sniffing must not raise
        return False
    if not lines or len(lines) < 4:
        return False
    return "PEER" in lines[0].upper() and "ACCELERATION" in lines[2].upper()


def _parse_npts_dt(line, name):
    match = _NPTS_DT_WEST2.search(line) or _NPTS_DT_WEST1.search(line)
    if match is None:
        raise InputError(
            f"{name}: line 4 of the AT2 header gives no sampling (expected "
            f"'NPTS= n, DT= dt SEC', got {line.strip()!r}); fix the header or load the "
            "samples as text with an explicit dt"
        )
    npts = int(match.group("npts"))
    dt = float(match.group("dt").replace("D", "E").replace("d", "e"))
    if not (math.isfinite(dt) and dt > 0):
        raise InputError(f"{name}: AT2 header gives DT={dt!r}; the time step must be a positive number of seconds")
    return npts, dt


# Component names of the vertical, and horizontal directions named by letters (azimuth, degree
# clockwise from north). FN/FP (fault normal/parallel) and L/T (longitudinal/transverse) name
# no compass direction.
_VERTICAL = {"UP", "DWN", "DOWN", "V", "VER", "VERT", "UD", "Z"}
_LETTERS = {"N": 0.0, "NS": 0.0, "E": 90.0, "EW": 90.0, "S": 180.0, "W": 270.0}
_TRAILING_AZIMUTH = re.compile(r"(?<!\d)(\d{1,3})$")


def component_orientation(component):
    """What an AT2 header's component name says about its direction.

    PEER names components by azimuth (``"090"``, ``"360"``, or the
    NGA-West1 station-and-azimuth ``"HOS090"``), by letters after the
    station (``"CHY101-N"``, ``"TCU065-E"``) or as vertical (``"UP"``,
    ``"DWN"``, ``"V"``).

    Parameters
    ----------
    component : str

    Returns
    -------
    tuple
        ``("vertical", None)``, ``("horizontal", azimuth)`` with the
        azimuth [degree] clockwise from north in [0, 360), or
        ``(None, None)`` when the name gives no direction (``"FN"``, ``"L"``).
    """
    token = re.split(r"[-_ ]", (component or "").strip().upper())[-1]
    if token in _VERTICAL:
        return "vertical", None
    if token in _LETTERS:
        return "horizontal", _LETTERS[token]
    match = _TRAILING_AZIMUTH.search(token)
    if match and int(match.group(1)) <= 360:
        return "horizontal", float(int(match.group(1)) % 360)
    return None, None


def _parse_title(line):
    """Split the second header line into event, date, station and component."""
    parts = [p.strip() for p in line.split(",")]
    fields = {"event": "", "date": "", "station": "", "component": ""}
    if len(parts) >= 4:  # NGA-West2: event, date, station, component
        fields.update(event=parts[0], date=parts[1], station=", ".join(parts[2:-1]), component=parts[-1])
    elif len(parts) == 3:  # NGA-West1: "EVENT DATE TIME", station, component
        fields.update(event=parts[0], station=parts[1], component=parts[2])
    elif parts:
        fields.update(event=parts[0])
    return fields


def read_at2(filename, headonly=False, **kwargs):
    """Read a PEER NGA ``.AT2`` file into an ObsPy Stream with one trace.

    Parameters
    ----------
    filename : str or path-like or file object
        The AT2 file.
    headonly : bool
        Read the header only (ObsPy's convention).

    Returns
    -------
    obspy.Stream
        One trace: samples in g (as stored), ``stats.calib`` = g [m/s^2 per g],
        ``stats.at2`` with the header fields (``title``, ``event``, ``date``,
        ``station``, ``component``, ``units``) and what the component name
        says of its direction: ``orientation`` ("horizontal", "vertical" or
        None) and ``azimuth`` [degree from north] (:func:`component_orientation`).

    Raises
    ------
    InputError
        If the header is incomplete, the file holds velocity or displacement,
        a sample is not a finite number, or the sample count differs from NPTS.
    """
    name = _name(filename)
    if hasattr(filename, "read"):
        text = filename.read()
        if isinstance(text, bytes):
            text = text.decode("latin-1")
    else:
        with open(filename, "r", encoding="latin-1") as fh:
            text = fh.read()
    lines = text.splitlines()
    if len(lines) < 4:
        raise InputError(f"{name}: an AT2 file needs a 4-line header; this one has {len(lines)} lines (truncated file?)")
    kind = lines[2].upper()
    if "ACCELERATION" not in kind:
        raise InputError(f"{name}: line 3 says {lines[2].strip()!r}; only acceleration files (.AT2) are read, not velocity (.VT2) or displacement (.DT2)")
    if not re.search(r"UNITS OF G\b", kind):
        raise InputError(f"{name}: line 3 says {lines[2].strip()!r}; AT2 samples must be in units of g")
    npts, dt = _parse_npts_dt(lines[3], name)

    title = _parse_title(lines[1])
    header = {
        "delta": dt,
        "npts": npts,
        "calib": G,
        "station": title["station"],
        "channel": title["component"],
        "at2": AttribDict(title=lines[0].strip(), units="g", **title,
                          **dict(zip(("orientation", "azimuth"), component_orientation(title["component"])))),
    }
    if headonly:
        return Stream([Trace(header=header)])

    body = " ".join(lines[4:])
    tokens = _SAMPLE.findall(body)
    leftovers = _SAMPLE.sub(" ", body).split()
    if leftovers:
        raise InputError(f"{name}: unreadable sample text {leftovers[0]!r} in the AT2 body (corrupt file?)")
    if len(tokens) != npts:
        raise InputError(
            f"{name}: header says NPTS={npts} but the file holds {len(tokens)} samples "
            "(truncated or corrupt file); re-export the record"
        )
    data = np.array([float(t.replace("D", "E").replace("d", "e")) for t in tokens], dtype=np.float64)
    header.pop("npts")
    return Stream([Trace(data=data, header=header)])


def _fortran_e(values, digits):
    """Format numbers like Fortran ``E15.7``: ``  .1234567E-02``, ``-.1234567E+00``."""
    out = []
    for v in values:
        if v == 0.0:
            mantissa, exponent = "." + "0" * digits, 0
        else:
            s = f"{abs(v):.{digits - 1}E}"  # d.dddddE+xx, correctly rounded
            m, e = s.split("E")
            mantissa, exponent = "." + m.replace(".", ""), int(e) + 1
        sign = "-" if v < 0 else ""
        out.append(f"{sign}{mantissa}E{exponent:+03d}".rjust(digits + 8))
    return out


def _write_one(trace, target, digits, event, date):
    at2 = trace.stats.get("at2", {}) or {}
    event = event or at2.get("event") or "unknown event"
    date = date or at2.get("date") or trace.stats.starttime.strftime("%m/%d/%Y")
    station = at2.get("station") or trace.stats.station or "unknown station"
    component = at2.get("component") or trace.stats.channel or "unknown component"
    title = at2.get("title") or "PEER NGA STRONG MOTION DATABASE RECORD"
    acc_g = np.asarray(trace.data, dtype=np.float64) * float(trace.stats.calib) / G
    if not np.all(np.isfinite(acc_g)):
        raise InputError(f"trace {trace.id}: NaN or infinite samples cannot be written to AT2")
    dt = np.format_float_positional(trace.stats.delta, trim="-")
    lines = [
        title,
        f"{event}, {date}, {station}, {component}",
        "ACCELERATION TIME SERIES IN UNITS OF G",
        f"NPTS={trace.stats.npts:7d}, DT= {dt} SEC",
    ]
    fields = _fortran_e(acc_g, digits)
    for i in range(0, len(fields), 5):
        lines.append("".join(fields[i:i + 5]))
    text = "\n".join(lines) + "\n"
    if hasattr(target, "write"):
        target.write(text if isinstance(target, io.TextIOBase) else text.encode("latin-1"))
        return
    with atomic_open(target, "w", encoding="latin-1") as fh:  # never a half-written file under the real name
        fh.write(text)


def write_at2(stream, filename, digits=7, event=None, date=None, **kwargs):
    """Write each trace of ``stream`` as a PEER NGA ``.AT2`` file.

    Parameters
    ----------
    stream : obspy.Stream
        Traces with ``data * stats.calib`` in m/s^2 (the convention of the
        AT2, K-NET and Kinemetrics readers and of :class:`GroundMotion`).
    filename : str or path-like
        Target file. A stream with several traces is written as several files,
        numbered like ObsPy's SAC writer: ``name01.AT2``, ``name02.AT2``, ...
    digits : int
        Significant digits per sample; 7 is the PEER format (E15.7).
    event, date : str, optional
        Override the event name and date of the second header line.
    """
    if len(stream) == 1:
        _write_one(stream[0], filename, digits, event, date)
        return
    base, ext = os.path.splitext(str(filename))
    for i, trace in enumerate(stream):
        _write_one(trace, f"{base}{i:02d}{ext}", digits, event, date)
