"""Explicit processing steps: each returns a new GroundMotion.

Nothing here runs unless asked: a record is used as stored. ObsPy does the
signal processing where it has the operation (detrend, taper, filter,
resample/interpolate, trim) and logs it in ``stats.processing``; rotation and
scaling are logged by :class:`GroundMotion` itself.

Steps can also be given as data (study files) and run by :func:`apply`::

    apply(gm, [{"step": "baseline", "type": "linear"},
               {"step": "taper", "max_percentage": 0.05},
               {"step": "bandpass", "freqmin": 0.1, "freqmax": 25.0}])
"""

import math

from pipeline.errors import InputError
from pipeline.groundmotion import intensity as im
from pipeline.groundmotion.provenance import log_step

__all__ = ["baseline_correct", "taper", "bandpass", "resample", "trim_arias", "rotate", "one_component", "scale",
           "scale_to", "apply", "STEPS"]


def baseline_correct(gm, type="linear", order=None):
    """Remove a baseline with ``Trace.detrend``.

    Parameters
    ----------
    type : {'demean', 'linear', 'polynomial'}
        ObsPy detrend type ('polynomial' needs ``order``).
    """
    if type not in ("demean", "linear", "polynomial", "simple", "constant"):
        raise InputError(f"{gm.record_id}: baseline type {type!r}; use 'demean', 'linear' or 'polynomial'")
    if type == "polynomial" and order is None:
        raise InputError(f"{gm.record_id}: baseline type 'polynomial' needs order=")
    st = gm.stream
    kwargs = {"order": int(order)} if type == "polynomial" else {}
    st.detrend(type, **kwargs)
    return gm.with_stream(st)


def taper(gm, max_percentage=0.05, type="hann"):
    """Taper both ends with ``Stream.taper`` (fraction ``max_percentage`` per side)."""
    st = gm.stream
    st.taper(max_percentage=float(max_percentage), type=type)
    return gm.with_stream(st)


def bandpass(gm, freqmin, freqmax, corners=4, zerophase=True):
    """Butterworth band-pass [Hz] with ``Stream.filter('bandpass', ...)``.

    ``zerophase=True`` runs the filter forwards and backwards (no phase shift;
    effective order doubled).
    """
    nyquist = 0.5 / gm.dt
    if not (0 < freqmin < freqmax):
        raise InputError(f"{gm.record_id}: band-pass needs 0 < freqmin < freqmax [Hz], got {freqmin!r}, {freqmax!r}")
    if freqmax >= nyquist:
        raise InputError(f"{gm.record_id}: freqmax={freqmax!r} Hz is at or above the Nyquist frequency {nyquist!r} Hz")
    st = gm.stream
    st.filter("bandpass", freqmin=float(freqmin), freqmax=float(freqmax), corners=int(corners), zerophase=bool(zerophase))
    return gm.with_stream(st)


def resample(gm, dt, method="lanczos", a=20):
    """Change the time step to ``dt`` [s].

    ``method='fft'`` uses ``Trace.resample`` (Fourier; ObsPy low-passes first
    when downsampling); ``'lanczos'``, ``'linear'`` etc. use
    ``Trace.interpolate`` (for upsampling; ``a`` is the Lanczos window width).
    The number of samples follows from the record's duration.
    """
    if not (math.isfinite(dt) and dt > 0):
        raise InputError(f"{gm.record_id}: resample dt={dt!r}; give a positive step [s]")
    st = gm.stream
    rate = 1.0 / dt
    if method == "fft":
        st.resample(rate)
    else:
        npts = int(math.floor(gm.duration / dt + 1e-9)) + 1
        kwargs = {"a": a} if method == "lanczos" else {}
        st.interpolate(rate, method=method, npts=npts, **kwargs)
    return gm.with_stream(st)


def trim_arias(gm, lower=0.05, upper=0.95):
    """Keep the window between ``lower`` and ``upper`` of the Arias intensity.

    Arias intensity of the horizontal pair (sum of both components) decides
    the window, so both components keep one time axis; ``Stream.trim`` cuts at
    the nearest samples. The time axis restarts at 0.
    """
    if not (0.0 <= lower < upper <= 1.0):
        raise InputError(f"{gm.record_id}: trim fractions must satisfy 0 <= lower < upper <= 1, got {lower!r}, {upper!r}")
    husid = im.arias_husid(gm.acc_x, gm.dt) + im.arias_husid(gm.acc_y, gm.dt)
    if husid[-1] <= 0:
        raise InputError(f"{gm.record_id}: zero Arias intensity; nothing to trim to")
    t_lo, t_hi = im.husid_window(husid, gm.dt, lower, upper)
    st = gm.stream
    t0 = st[0].stats.starttime
    st.trim(t0 + t_lo, t0 + t_hi, nearest_sample=True)
    for tr in st:
        log_step(tr, f"trim_arias(lower={lower!r}, upper={upper!r}): kept {t_lo:.4f}-{t_hi:.4f} s of the original")
    return gm.with_stream(st)


def rotate(gm, angle):
    """Rotate the horizontal pair by an incidence angle [degree] (see GroundMotion.rotated)."""
    return gm.rotated(angle)


def one_component(gm, keep="x"):
    """Keep one horizontal component, the other set to zero (see GroundMotion.one_component)."""
    return gm.one_component(keep)


def scale(gm, factor):
    """Multiply all components by ``factor`` [1]."""
    return gm.scaled(factor)


def _measure(gm, measure, combine, period, damping):
    x, y, dt = gm.acc_x, gm.acc_y, gm.dt
    if combine in ("rotd50", "rotd100"):
        if measure == "arias":
            raise InputError(f"{gm.record_id}: RotD is defined for peak measures, not for Arias intensity")
        return im.rotd(x, y, dt, 50.0 if combine == "rotd50" else 100.0, measure, period, damping)

    def one(a):
        if measure == "pga":
            return im.pga(a)
        if measure == "pgv":
            return im.pgv(a, dt)
        if measure == "pgd":
            return im.pgd(a, dt)
        if measure == "arias":
            return im.arias_intensity(a, dt)
        if measure == "sa":
            if period is None:
                raise InputError(f"{gm.record_id}: measure 'sa' needs period= [s]")
            return im.spectral_acceleration(a, dt, period, damping)
        raise InputError(f"{gm.record_id}: unknown measure {measure!r}; use pga, pgv, pgd, arias or sa")

    if combine == "x":
        return one(x)
    vx, vy = one(x), one(y)
    if combine == "max":
        return max(vx, vy)
    if combine == "geomean":
        return math.sqrt(vx * vy)
    raise InputError(f"{gm.record_id}: unknown combine {combine!r}; use max, geomean, x, rotd50 or rotd100")


def scale_to(gm, measure, target, combine="max", period=None, damping=0.05):
    """Scale so that an intensity measure of the record equals ``target``.

    Parameters
    ----------
    measure : {'pga', 'pgv', 'pgd', 'arias', 'sa'}
        Measure in SI units ([m/s^2], [m/s], [m], [m/s], [m/s^2]).
    target : float
        Wanted value, same units.
    combine : {'max', 'geomean', 'x', 'rotd50', 'rotd100'}
        How the two horizontal components make one number.
    period, damping
        For ``'sa'`` [s], [1].

    Notes
    -----
    Peak measures are linear in the scale factor; Arias intensity is
    quadratic, so its factor is sqrt(target / value).
    """
    value = _measure(gm, measure, combine, period, damping)
    if not value > 0:
        raise InputError(f"{gm.record_id}: {measure} is {value!r}; a zero record cannot be scaled to a target")
    factor = target / value
    if measure == "arias":
        factor = math.sqrt(factor)
    out = gm.scaled(factor)
    st = out.stream
    for tr in st:
        log_step(tr, f"scale_to(measure={measure!r}, target={target!r}, combine={combine!r}, period={period!r}): "
                     f"value {value!r} -> factor {factor!r}")
    return out.with_stream(st)


#: Step names accepted by :func:`apply`.
STEPS = {
    "baseline": baseline_correct,
    "taper": taper,
    "bandpass": bandpass,
    "resample": resample,
    "trim_arias": trim_arias,
    "rotate": rotate,
    "one_component": one_component,
    "scale": scale,
    "scale_to": scale_to,
}


def apply(gm, steps):
    """Run processing steps given as data, in order.

    Each step is ``{"step": name, **kwargs}`` or ``(name, kwargs)`` with a name
    from :data:`STEPS`.
    """
    for i, step in enumerate(steps):
        if isinstance(step, dict):
            kwargs = dict(step)
            name = kwargs.pop("step", None)
        else:
            name, kwargs = step[0], dict(step[1] if len(step) > 1 else {})
        if name not in STEPS:
            raise InputError(f"{gm.record_id}: processing step {i + 1} is {name!r}; use one of {', '.join(STEPS)}")
        try:
            gm = STEPS[name](gm, **kwargs)
        except TypeError as exc:
            raise InputError(f"{gm.record_id}: processing step {i + 1} ({name}): {exc}") from None
    return gm
