"""The ground-motion type: two horizontal components and an optional vertical.

A :class:`GroundMotion` wraps an :class:`obspy.Stream` whose traces are, in
order, the x and y horizontal components and optionally the vertical z, all
acceleration in m/s^2 (``stats.calib`` = 1), float64, with one common time
step. The time axis starts at 0 s at the first sample.  Every processing step
is logged in each trace's ``stats.processing`` (ObsPy does this for its own
methods; this package adds its own lines for rotation, scaling and synthesis).

Objects never change: each method returns a new motion.
"""

import hashlib
import math

import numpy as np
from obspy import Stream, Trace

from pipeline.errors import InputError
from pipeline.groundmotion.options import how_to_give
from pipeline.groundmotion.provenance import log_step
from pipeline.units import deg_to_rad

__all__ = ["GroundMotion", "COMPONENTS"]

#: Component names in stream order.
COMPONENTS = ("x", "y", "z")

# Relative tolerance on time steps of different components: they come from
# sampling rates stored as floats (1/dt), so exact equality is too strict.
_DT_RTOL = 1e-9


class GroundMotion:
    """A uniformly sampled ground acceleration record in m/s^2.

    Parameters
    ----------
    stream : obspy.Stream
        Two traces (x, y) or three (x, y, z), in that order, acceleration in
        m/s^2 (``data * stats.calib``), same length and time step.
    record_id : str
        Identifier (a catalog id such as ``FEMA-FF-01`` or a file name).
    metadata : dict, optional
        Event, magnitude, year, station, distance_km, source, licence, ...
    source : str, optional
        Where the samples came from (file or catalog id), used in messages.

    Raises
    ------
    InputError
        Wrong number of components, different lengths or time steps, missing
        sampling, or NaN/infinite samples.
    """

    __slots__ = ("_stream", "_record_id", "_metadata", "_acc", "_dt")

    def __init__(self, stream, record_id, metadata=None, source=None):
        where = source or record_id
        if not isinstance(stream, Stream):
            stream = Stream(list(stream))
        if len(stream) not in (2, 3):
            raise InputError(
                f"{where}: a ground motion needs 2 horizontal components (+ optional vertical), "
                f"got {len(stream)} traces ({', '.join(tr.id for tr in stream) or 'none'}); "
                f"select the components with {how_to_give('components')}"
            )
        traces = []
        for name, tr in zip(COMPONENTS, stream):
            rate = tr.stats.sampling_rate
            if not (math.isfinite(rate) and rate > 0):
                raise InputError(f"{where}: component {name} ({tr.id}) has no sampling rate (got {rate!r}); "
                                 "set the trace's stats.delta [s]")
            if tr.stats.npts < 2:
                raise InputError(f"{where}: component {name} ({tr.id}) has {tr.stats.npts} samples; a record needs at least 2")
            if np.ma.isMaskedArray(tr.data):
                raise InputError(f"{where}: component {name} ({tr.id}) has gaps (masked samples); fill or trim them first")
            data = np.ascontiguousarray(np.asarray(tr.data, dtype=np.float64) * float(tr.stats.calib))
            bad = ~np.isfinite(data)
            if bad.any():
                i = int(np.argmax(bad))
                raise InputError(
                    f"{where}: component {name} ({tr.id}) has {int(bad.sum())} NaN or infinite samples "
                    f"(first at index {i}, value {data[i]!r}); repair or trim the record"
                )
            new = tr.copy()
            new.data = data
            new.stats.calib = 1.0
            traces.append(new)
        npts = {tr.stats.npts for tr in traces}
        if len(npts) != 1:
            sizes = ", ".join(f"{n}={tr.stats.npts}" for n, tr in zip(COMPONENTS, traces))
            raise InputError(f"{where}: components have different lengths ({sizes}); trim them to a common window")
        dts = [tr.stats.delta for tr in traces]
        if max(dts) - min(dts) > _DT_RTOL * max(dts):
            steps = ", ".join(f"{n}={d!r}" for n, d in zip(COMPONENTS, dts))
            raise InputError(f"{where}: components have different time steps ({steps} s); resample them to one dt")
        for tr in traces[1:]:  # one time axis: same start for every component
            tr.stats.starttime = traces[0].stats.starttime
        self._stream = Stream(traces)
        self._record_id = str(record_id)
        self._metadata = dict(metadata or {})
        self._dt = float(dts[0])
        acc = []
        for tr in traces:
            view = tr.data.view()
            view.flags.writeable = False  # the samples are shared: nobody may edit them
            acc.append(view)
        self._acc = tuple(acc)

    # -- construction helpers -------------------------------------------------
    @classmethod
    def from_arrays(cls, acc_x, acc_y, dt, acc_z=None, *, record_id, metadata=None, processing=None, starttime=0):
        """Build a motion from arrays [m/s^2] and a time step ``dt`` [s].

        ``processing`` is a line (or list of lines) logged on every trace, e.g.
        the generator and its parameters.
        """
        if not (isinstance(dt, (int, float, np.floating)) and math.isfinite(dt) and dt > 0):
            raise InputError(f"{record_id}: time step dt={dt!r}; give a positive number of seconds")
        traces = []
        for name, arr in zip(COMPONENTS, (acc_x, acc_y, acc_z)):
            if arr is None:
                continue
            tr = Trace(data=np.array(arr, dtype=np.float64))
            tr.stats.delta = float(dt)
            tr.stats.starttime = starttime
            tr.stats.channel = f"HN{name.upper()}"
            for line in [processing] if isinstance(processing, str) else (processing or []):
                log_step(tr, line)
            traces.append(tr)
        return cls(Stream(traces), record_id=record_id, metadata=metadata)

    # -- properties --------------------------------------------------------------
    @property
    def record_id(self):
        """Identifier of the record (catalog id or file name)."""
        return self._record_id

    @property
    def dt(self):
        """Time step [s]."""
        return self._dt

    @property
    def npts(self):
        """Number of samples per component."""
        return self._acc[0].size

    @property
    def duration(self):
        """Duration (npts - 1) * dt [s]."""
        return (self.npts - 1) * self._dt

    @property
    def time(self):
        """Sample times [s], starting at 0."""
        return np.arange(self.npts, dtype=np.float64) * self._dt

    @property
    def metadata(self):
        """A copy of the metadata dict (event, magnitude, year, station, ...)."""
        return dict(self._metadata)

    @property
    def stream(self):
        """A copy of the underlying :class:`obspy.Stream` (x, y[, z] in m/s^2)."""
        return self._stream.copy()

    @property
    def acc_x(self):
        """Horizontal x acceleration [m/s^2] (read-only, float64, C-contiguous)."""
        return self._acc[0]

    @property
    def acc_y(self):
        """Horizontal y acceleration [m/s^2] (read-only, float64, C-contiguous)."""
        return self._acc[1]

    @property
    def acc_z(self):
        """Vertical acceleration [m/s^2], or None if the record has none."""
        return self._acc[2] if len(self._acc) == 3 else None

    @property
    def components(self):
        """Component names present, e.g. ``('x', 'y')``."""
        return COMPONENTS[: len(self._acc)]

    @property
    def processing(self):
        """Processing history of the x component (all components share it)."""
        return list(self._stream[0].stats.get("processing", []))

    def component(self, name):
        """Acceleration [m/s^2] of component ``'x'``, ``'y'`` or ``'z'``."""
        if name not in self.components:
            raise InputError(f"{self._record_id}: no component {name!r}; it has {', '.join(self.components)}")
        return self._acc[COMPONENTS.index(name)]

    # -- transformations (new objects) ------------------------------------------------
    def rotated(self, angle):
        """Rotate the horizontal motion by an incidence angle.

        The motion vector is turned counter-clockwise (x towards y) by
        ``angle`` [degree] in the fixed x-y frame of the column::

            x' = x cos(a) - y sin(a)
            y' = x sin(a) + y cos(a)

        so a record with motion on x only arrives along the direction at angle
        ``a`` from the x axis. The vertical is unchanged.
        """
        angle = float(angle)
        c, s = math.cos(deg_to_rad(angle)), math.sin(deg_to_rad(angle))
        st = self._stream.copy()
        x, y = self._acc[0], self._acc[1]
        st[0].data = c * x - s * y
        st[1].data = s * x + c * y
        for tr in st:
            log_step(tr, f"rotated(angle={angle!r} deg)")
        return self.with_stream(st)

    def one_component(self, keep="x"):
        """The motion with one horizontal component only: the other set to zero (the vertical unchanged).

        A drive in one direction (a shake table's, or a record's component turned along or across a
        colonnade by the incidence angle) from a pair: ``keep`` is ``"x"`` or ``"y"``, the component
        kept in its own place.
        """
        if keep not in ("x", "y"):
            raise InputError(f"{self._record_id}: one_component keep = {keep!r}; keep 'x' or 'y'")
        st = self._stream.copy()
        other = st[1] if keep == "x" else st[0]
        other.data = np.zeros_like(other.data)
        for tr in st:
            log_step(tr, f"one_component(keep={keep!r}): the {'y' if keep == 'x' else 'x'} component set to zero")
        return self.with_stream(st)

    def scaled(self, factor):
        """All components multiplied by ``factor`` [1]."""
        factor = float(factor)
        if not math.isfinite(factor):
            raise InputError(f"{self._record_id}: scale factor {factor!r} is not a finite number")
        st = self._stream.copy()
        for tr in st:
            tr.data = tr.data * factor
            log_step(tr, f"scaled(factor={factor!r})")
        return self.with_stream(st)

    def with_processing(self, *steps):
        """Apply processing steps in order (see :func:`pipeline.groundmotion.processing.apply`).

        Each step is a dict such as ``{"step": "bandpass", "freqmin": 0.1,
        "freqmax": 25.0}`` or a ``(name, kwargs)`` pair.
        """
        from pipeline.groundmotion.processing import apply

        return apply(self, steps)

    def with_stream(self, stream, **metadata_updates):
        """A new motion from a processed copy of :attr:`stream` (same id, metadata)."""
        return GroundMotion(stream, record_id=self._record_id, metadata=dict(self._metadata, **metadata_updates))

    # -- identity ----------------------------------------------------------------
    def sha256(self):
        """Digest of the samples and time step (hex).

        Hashes ``dt`` (as float64) and each component's float64
        little-endian samples in order x, y[, z]; independent of metadata
        and processing text, so it identifies what the dynamics will see.
        """
        h = hashlib.sha256()
        h.update(np.float64(self._dt).astype("<f8").tobytes())
        for name, arr in zip(COMPONENTS, self._acc):
            h.update(name.encode())
            h.update(np.asarray(arr, dtype="<f8").tobytes())
        return h.hexdigest()

    def write(self, filename, format="MSEED", **kwargs):
        """Write the motion with ObsPy (m/s^2; channels ``HNX``, ``HNY``, ``HNZ``).

        MiniSEED is written with FLOAT64 encoding so the samples survive
        exactly. Formats holding one trace per file (SAC, AT2) get one file per
        component, ``<stem>_HNX<suffix>`` etc. Each file is written under a
        temporary name and then renamed. Returns the list of paths written.
        """
        from pathlib import Path

        from pipeline.atomic import atomic_path

        st = self.stream
        for name, tr in zip(COMPONENTS, st):
            tr.stats.channel = f"HN{name.upper()}"
        fmt = format.upper()
        if fmt == "MSEED":
            kwargs.setdefault("encoding", "FLOAT64")
        target = Path(filename)
        if fmt in ("SAC", "SACXY", "AT2"):
            jobs = [(Stream([tr]), target.with_name(f"{target.stem}_{tr.stats.channel}{target.suffix}")) for tr in st]
        else:
            jobs = [(st, target)]
        written = []
        for part, path in jobs:
            with atomic_path(path) as tmp:
                part.write(tmp, format=format, **kwargs)
            written.append(path)
        return written

    def __repr__(self):
        comps = "".join(self.components)
        return f"GroundMotion({self._record_id!r}, components={comps!r}, npts={self.npts}, dt={self._dt!r} s)"

    def __eq__(self, other):
        return isinstance(other, GroundMotion) and self.sha256() == other.sha256() and self._record_id == other._record_id

    def __hash__(self):
        return hash((self._record_id, self.sha256()))
