"""Intensity measures of an acceleration history (plain arrays, SI units).

All functions take acceleration ``acc`` [m/s^2] sampled at a uniform step
``dt`` [s]. Velocity and displacement are integrated with the trapezoidal rule
from rest (v(0) = 0, u(0) = 0), which is exact for the piecewise-linear
acceleration that the spectral solution also assumes; no baseline correction
is applied here (do it explicitly with :mod:`~pipeline.groundmotion.processing`).
"""

import math

import numpy as np
from scipy.integrate import cumulative_trapezoid, trapezoid
from scipy.linalg import expm
from scipy.signal import lfilter

from pipeline.units import G

__all__ = [
    "velocity",
    "displacement",
    "pga",
    "pgv",
    "pgd",
    "arias_intensity",
    "arias_husid",
    "cav",
    "significant_duration",
    "spectral_acceleration",
    "sdof_response",
    "rotd",
    "rotd50",
    "rotd100",
]

#: Points per natural period at which the SDOF response is evaluated at least.
#: The piecewise-linear solution is exact at any instant; evaluating it on a
#: finer grid only finds the peak between samples (error <= 1 - cos(pi/50),
#: 0.2 %, for a nearly harmonic response).
MIN_POINTS_PER_PERIOD = 50


def _as_array(acc):
    return np.asarray(acc, dtype=np.float64)


def velocity(acc, dt):
    """Ground velocity [m/s] by trapezoidal integration from rest."""
    return cumulative_trapezoid(_as_array(acc), dx=dt, initial=0.0)


def displacement(acc, dt):
    """Ground displacement [m] by two trapezoidal integrations from rest."""
    return cumulative_trapezoid(velocity(acc, dt), dx=dt, initial=0.0)


def pga(acc):
    """Peak ground acceleration max|a| [m/s^2]."""
    return float(np.max(np.abs(_as_array(acc))))


def pgv(acc, dt):
    """Peak ground velocity [m/s] (trapezoidal velocity, no correction)."""
    return float(np.max(np.abs(velocity(acc, dt))))


def pgd(acc, dt):
    """Peak ground displacement [m] (trapezoidal, no correction)."""
    return float(np.max(np.abs(displacement(acc, dt))))


def arias_intensity(acc, dt):
    """Arias intensity pi/(2 g) * integral of a^2 dt [m/s] (trapezoidal rule)."""
    return float(math.pi / (2.0 * G) * trapezoid(_as_array(acc) ** 2, dx=dt))


def arias_husid(acc, dt):
    """Cumulative Arias intensity over time [m/s] (the Husid curve times I_A)."""
    return math.pi / (2.0 * G) * cumulative_trapezoid(_as_array(acc) ** 2, dx=dt, initial=0.0)


def cav(acc, dt):
    """Cumulative absolute velocity, integral of |a| dt [m/s] (no threshold)."""
    return float(trapezoid(np.abs(_as_array(acc)), dx=dt))


def significant_duration(acc, dt, lower=0.05, upper=0.95):
    """Significant duration D5-95 [s]: time between 5 % and 95 % of Arias intensity.

    The crossing times are interpolated linearly on the cumulative curve.
    Returns ``(duration, t_lower, t_upper)`` [s].
    """
    husid = arias_husid(acc, dt)
    if husid[-1] <= 0.0:
        return 0.0, 0.0, 0.0
    t_lo, t_hi = husid_window(husid, dt, lower, upper)
    return t_hi - t_lo, t_lo, t_hi


def husid_window(husid, dt, lower, upper):
    """Times [s] at which a cumulative Arias curve (positive total) reaches ``lower`` and ``upper`` of its total.

    Interpolated linearly between samples ``dt`` [s] apart, from t = 0.
    """
    frac = husid / husid[-1]
    t = np.arange(frac.size) * dt
    return float(np.interp(lower, frac, t)), float(np.interp(upper, frac, t))


def _discrete_sdof(omega, damping, h):
    """Exact one-step map of the SDOF for input linear over a step ``h``.

    Relative motion x'' + 2 z w x' + w^2 x = -a(t). With a(t) linear between
    samples the solution over a step is exact (Nigam & Jennings 1969); the
    coefficients are obtained here from the matrix exponential of the
    augmented system (first-order hold), the same recurrence in matrix form.
    Returns (Phi, Gamma0, Gamma1) with x_{k+1} = Phi x_k + Gamma0 a_k + Gamma1 a_{k+1}.
    """
    a_c = np.array([[0.0, 1.0], [-omega * omega, -2.0 * damping * omega]])
    b_c = np.array([[0.0], [-1.0]])
    m = np.zeros((4, 4))
    m[:2, :2] = a_c * h
    m[:2, 2:3] = b_c * h
    m[2, 3] = 1.0  # input slope: u(t) = u_k + (t/h) (u_{k+1} - u_k)
    e = expm(m)
    phi = e[:2, :2]
    gam1 = e[:2, 3:4]
    gam0 = e[:2, 2:3] - gam1
    return phi, gam0[:, 0], gam1[:, 0]


def _upsample(acc, dt, period):
    """Linear interpolation to a step giving MIN_POINTS_PER_PERIOD per period.

    The input model is piecewise linear, so this does not change the
    excitation, only where the (exact) response is evaluated.
    """
    k = max(1, math.ceil(MIN_POINTS_PER_PERIOD * dt / period))
    if k == 1:
        return acc, dt
    n = acc.size
    fine_t = np.arange((n - 1) * k + 1) / k
    return np.interp(fine_t, np.arange(n), acc), dt / k


def sdof_response(acc, dt, period, damping=0.05):
    """Histories of a linear SDOF under ground acceleration ``acc``.

    Parameters
    ----------
    acc : array_like
        Ground acceleration [m/s^2], uniform step ``dt`` [s].
    period : float
        Natural period [s] (> 0).
    damping : float
        Damping ratio [1].

    Returns
    -------
    dt_out : float
        Step of the returned histories [s] (dt, or dt/k when refined).
    disp, vel, abs_acc : ndarray
        Relative displacement [m], relative velocity [m/s] and absolute
        acceleration [m/s^2] of the oscillator, starting at rest.
    """
    acc = _as_array(acc)
    if period <= 0:
        raise ValueError(f"period must be > 0 s, got {period!r}")
    a, h = _upsample(acc, dt, period)
    omega = 2.0 * math.pi / period
    phi, g0, g1 = _discrete_sdof(omega, damping, h)
    # State-space form with a direct term: x_k = s_k + g1 a_k turns the
    # two-input recurrence into a standard one, s_{k+1} = Phi s_k + (Phi g1 + g0) a_k,
    # which scipy's lfilter runs in compiled code.
    bd = phi @ g1 + g0
    # transfer function of (Phi, bd, c, d): H(z) = d + c (zI - Phi)^-1 bd, with
    # (zI - Phi)^-1 = (z I - adj) / den(z)
    tr = np.trace(phi)
    den = np.array([1.0, -tr, np.linalg.det(phi)])
    adj = np.array([[phi[1, 1], -phi[0, 1]], [-phi[1, 0], phi[0, 0]]])
    # lfilter from a zero state means an input ramping up from zero over the step
    # before t = 0. At rest at t = 0 means s_0 = -g1 a_0 instead: its free response
    # c Phi^k s_0 obeys the same denominator and enters as lfilter's initial state
    # (direct form II transposed: zi = [y_0, y_1 - tr y_0] gives outputs y_0, y_1).
    s0 = -g1 * a[0]
    outputs = []
    for c in (np.array([1.0, 0.0]), np.array([0.0, 1.0])):
        d = float(c @ g1)
        num = d * den + np.array([0.0, float(c @ bd), float(-c @ adj @ bd)])
        y0, y1 = float(c @ s0), float(c @ phi @ s0)
        y, _ = lfilter(num, den, a, zi=np.array([y0, y1 - tr * y0]))
        outputs.append(y)
    disp, vel = outputs
    abs_acc = -(omega * omega * disp + 2.0 * damping * omega * vel)
    return h, disp, vel, abs_acc


def spectral_acceleration(acc, dt, periods, damping=0.05, kind="absolute"):
    """Response spectrum of a ground acceleration history.

    Parameters
    ----------
    acc : array_like
        Ground acceleration [m/s^2].
    dt : float
        Time step [s].
    periods : float or array_like
        Natural periods [s], > 0.
    damping : float
        Damping ratio [1] (0.05 = 5 %).
    kind : {'absolute', 'pseudo'}
        ``'absolute'``: peak absolute acceleration of the oscillator;
        ``'pseudo'``: omega^2 times peak relative displacement.

    Returns
    -------
    float or ndarray
        Sa [m/s^2], same shape as ``periods``.

    Notes
    -----
    Exact for acceleration linear between samples (Nigam & Jennings 1969),
    from rest; the response is evaluated at least ``MIN_POINTS_PER_PERIOD``
    times per period so that peaks between samples are not missed.
    """
    if kind not in ("absolute", "pseudo"):
        raise ValueError(f"kind must be 'absolute' or 'pseudo', got {kind!r}")
    scalar = np.ndim(periods) == 0
    periods = np.atleast_1d(np.asarray(periods, dtype=np.float64))
    out = np.empty_like(periods)
    for i, period in enumerate(periods):
        _, disp, _, abs_acc = sdof_response(acc, dt, period, damping)
        if kind == "absolute":
            out[i] = np.max(np.abs(abs_acc))
        else:
            out[i] = (2.0 * math.pi / period) ** 2 * np.max(np.abs(disp))
    return float(out[0]) if scalar else out


def _pair_histories(acc_x, acc_y, dt, measure, period, damping):
    if measure == "pga":
        return _as_array(acc_x), _as_array(acc_y)
    if measure == "pgv":
        return velocity(acc_x, dt), velocity(acc_y, dt)
    if measure == "pgd":
        return displacement(acc_x, dt), displacement(acc_y, dt)
    if measure == "sa":
        if period is None:
            raise ValueError("measure 'sa' needs a period [s]")
        return sdof_response(acc_x, dt, period, damping)[3], sdof_response(acc_y, dt, period, damping)[3]
    raise ValueError(f"measure must be 'pga', 'pgv', 'pgd' or 'sa', got {measure!r}")


def rotd(acc_x, acc_y, dt, percentile=50.0, measure="pga", period=None, damping=0.05, n_angles=180):
    """Orientation-independent peak measure RotDnn (Boore 2010).

    The horizontal pair is projected on ``n_angles`` directions in [0, 180)
    degrees (a peak of |.| makes 180-360 redundant); the peak of each projected
    history is taken and the ``percentile`` over angles returned (50: RotD50,
    100: RotD100 = the maximum over directions).

    Parameters
    ----------
    acc_x, acc_y : array_like
        Horizontal accelerations [m/s^2].
    dt : float
        Time step [s].
    measure : {'pga', 'pgv', 'pgd', 'sa'}
        Which history is projected: acceleration, velocity, displacement, or
        the oscillator's absolute acceleration (needs ``period``). Projection
        commutes with the linear SDOF, so Sa histories are rotated directly.

    Returns
    -------
    float
        The measure in SI units ([m/s^2], [m/s] or [m]).
    """
    hx, hy = _pair_histories(acc_x, acc_y, dt, measure, period, damping)
    theta = np.arange(n_angles) * (math.pi / n_angles)
    peaks = np.empty(n_angles)
    for i, th in enumerate(theta):
        peaks[i] = np.max(np.abs(hx * math.cos(th) + hy * math.sin(th)))
    return float(np.percentile(peaks, percentile))


def rotd50(acc_x, acc_y, dt, measure="pga", period=None, damping=0.05):
    """RotD50: median over directions of the peak (see :func:`rotd`)."""
    return rotd(acc_x, acc_y, dt, 50.0, measure, period, damping)


def rotd100(acc_x, acc_y, dt, measure="pga", period=None, damping=0.05):
    """RotD100: maximum over directions of the peak (see :func:`rotd`)."""
    return rotd(acc_x, acc_y, dt, 100.0, measure, period, damping)
