"""Lognormal fragility curves from study results (maximum likelihood, Baker 2015).

A fragility curve gives the probability that a column reaches a damage state
at a ground-motion intensity ``x``::

    P(DS | IM = x) = Phi( ln(x / median) / beta )

with ``median`` in the units of the intensity measure (IM) and ``beta`` the
lognormal dispersion [1]. Both are fitted by maximum likelihood to the
multiple-stripe data of a study (Baker J.W., Efficient analytical fragility
function fitting using dynamic structural analysis data, Earthquake Spectra
31(1), 2015, 579-599, Eqs. 11-12): at each distinct IM level ``x_j`` the
``n_j`` runs give ``z_j`` exceedances, binomially distributed with the
probability above. Records and incidence angles are pooled at every scale
stripe; a study that scales each record by a factor (rather than to a target
level) gives one IM level per record and stripe, and the same binomial
likelihood applies to those levels. A study of imperfect drums (dimension
``seed``) pools its seeds as it pools angles: the runs of every seed of a
column and model are samples of the imperfect structure's population, and a
model that runs perfect drums (``seeded`` 0: one run repeated along the seeds)
is counted once.

The fit is a probit regression ``P = Phi(a + b ln x)`` (``beta = 1/b``,
``median = exp(-a/b)``) solved by Newton's method. Its log-likelihood is
concave in ``(a, b)``, so Newton converges to the unique maximum whenever one
exists. The cases without a finite maximum are reported, not hidden
(:data:`FIT_STATUS`): no exceedance at all, every run exceeding, or the data
perfectly separated by the IM (every exceedance above every non-exceedance,
``beta -> 0``).

Damage states: ``overturning`` (the run overturned; for a column of drums, any
drum lay down or fell: collapse), for each threshold ``s`` (defaults 0.25, 0.5,
1) ``theta_ratio_s``: "peak theta / theta_crit >= s or overturned", and, where
the results hold the compliant model's joints, the dislocation states
``dislocation_s`` (defaults :data:`DISLOCATION_STATES`): "the largest residual
slip of a bed joint reaches s times the joint's diameter, or overturned". Every
state is a boolean per run (:func:`exceedance`) fitted by the same likelihood.

Confidence bounds come from a bootstrap over records (each replicate draws
the study's records with replacement, keeping all angles, seeds and scales of a
record together, seeded and reproducible) and are percentile intervals at a
stated confidence level.

Public functions: :func:`fit_lognormal`, :func:`fragility`,
:func:`probability`, :func:`exceedance`, :func:`intensity`, :func:`ida`,
:func:`open_results`, :func:`write`.
"""

import math
import os
from dataclasses import dataclass

import numpy as np
import xarray as xr
from scipy.special import log_ndtr, ndtr

from pipeline import dataset
from pipeline.dataset import annotate, append_history, write_netcdf
from pipeline.errors import InputError
from pipeline.models import DEFAULT, of_results
from pipeline.structures.description import DIMENSIONS
from pipeline.undecided import DEFAULT_UNDECIDED, UNDECIDED_CHOICES

#: What a fragility file carries of the structures of its results, per column (and, as text, in its
#: ``structures`` attribute); a risk file carries them on.
STRUCTURE_COORDS = ("structure", "structure_source") + tuple(name for name, _unit, _value in DIMENSIONS)


def structures_title(what, attrs):
    """A file's title naming the structures of the study it comes from (``attrs["structures"]``): ``"Lognormal
    fragility curves: row: a colonnade of 6 columns ..."``; a file from before they were named: "of columns"."""
    return f"{what}: {attrs['structures']}" if "structures" in attrs else f"{what} of free-standing columns"

DEFAULT_STATES = (0.25, 0.5, 1.0)

#: Dislocation damage states DS1, DS2, DS3: thresholds on ``dislocation_ratio``, the largest
#: residual slip s of a bed joint over the joint's diameter D [1] (configurable: the
#: ``dislocations`` of :func:`fragility`, ``--dislocations`` of ``frustum fragility``).
#:
#: Why these values. A drum slid by s on the one below carries everything above it on a lever
#: arm shortened from D/2 to D/2 - s towards the side it slid to, so the static overturning
#: resistance of the part above, about that edge, drops by the fraction 2 s/D, and its bearing
#: area by about (4/pi) s/D (two discs of diameter D offset by s, to first order):
#:
#: * DS1, s >= 1 % of D (19 mm on a Parthenon drum of 1.9 m): a dislocation the eye sees, the
#:   flutes out of line; the resistance 2 % lower, nothing to repair for stability.
#: * DS2, s >= 5 % of D: resistance 10 % lower, bearing area 6 % smaller; the drums need
#:   re-setting.
#: * DS3, s >= 10 % of D: resistance 20 % lower, bearing area 13 % smaller: the column stands
#:   markedly weakened for the next earthquake.
#:
#: Residual drum dislocation over the diameter as the measure of damage follows the
#: performance-based assessment of classical columns of "Seismic reliability assessment of
#: classical columns subjected to near-fault ground motions" (Earthquake Engineering &
#: Structural Dynamics, 2013); the thresholds are this project's round values, not that paper's.
#: Collapse, any drum lying down or falling, is the ``overturning`` state, and it counts as
#: reaching every dislocation state.
DISLOCATION_STATES = (0.01, 0.05, 0.10)
DEFAULT_CONFIDENCE = 0.90
RESULT_DIMS = ("column", "record", "angle", "scale", "model")
IM_NAMES = ("pga", "pgv", "sa")
IM_DEFAULT_UNITS = {"pga": "m s-2", "pgv": "m s-1", "sa": "m s-2"}
IM_LONG_NAMES = {
    "pga": "peak ground acceleration",
    "pgv": "peak ground velocity",
    "sa": "spectral acceleration",
}

#: fit_status values and their meaning (CF flag_values / flag_meanings).
FIT_OK, FIT_NO_EXCEEDANCE, FIT_ALL_EXCEED, FIT_SEPARATED, FIT_NO_DATA, FIT_DECREASING = range(6)
FIT_STATUS = {
    FIT_OK: "ok",
    FIT_NO_EXCEEDANCE: "no_exceedance_observed",
    FIT_ALL_EXCEED: "every_run_exceeds",
    FIT_SEPARATED: "perfectly_separated",
    FIT_NO_DATA: "no_valid_runs",
    FIT_DECREASING: "probability_decreases_with_im",
}

_LOG_SQRT_2PI = 0.5 * math.log(2.0 * math.pi)


@dataclass(frozen=True)
class LognormalFit:
    """A fitted lognormal fragility function.

    Attributes
    ----------
    median : float
        IM at 50 % probability, units of the IM. ``inf`` when no run
        exceeded, ``0`` when every run did (see ``status``).
    beta : float
        Lognormal dispersion [1]; ``0`` for perfectly separated data, ``nan``
        when undefined (no exceedance, every run exceeding, no data).
    status : int
        One of :data:`FIT_STATUS`.
    loglik : float
        Maximum binomial log-likelihood (without the constant binomial
        coefficients) [1].
    covariance : numpy.ndarray
        Asymptotic covariance of ``(ln median, beta)`` from the observed
        Fisher information (2x2), ``nan`` unless ``status == FIT_OK``.
    """

    median: float
    beta: float
    status: int
    loglik: float
    covariance: np.ndarray

    @property
    def ok(self):
        return self.status == FIT_OK


def probability(im, median, beta):
    """Lognormal fragility ``Phi(ln(im/median)/beta)`` [1].

    Handles the degenerate fits: ``beta == 0`` is a step at ``median``;
    ``median == inf`` is 0 everywhere; ``median == 0`` is 1 everywhere;
    ``nan`` parameters give ``nan``.

    Parameters
    ----------
    im : array_like
        Intensity, units of the IM (> 0).
    median, beta : float or array_like
        Broadcast against ``im``.
    """
    im, median, beta = np.broadcast_arrays(np.asarray(im, float), np.asarray(median, float),
                                           np.asarray(beta, float))
    out = np.full(im.shape, np.nan)
    with np.errstate(divide="ignore", invalid="ignore"):
        regular = np.isfinite(median) & (median > 0) & (beta > 0)
        out[regular] = ndtr(np.log(im[regular] / median[regular]) / beta[regular])
        step = (beta == 0) & np.isfinite(median) & (median > 0)
        out[step] = (im[step] >= median[step]).astype(float)
    out[np.isposinf(median)] = 0.0
    out[median == 0] = 1.0
    return out


def fitted_probability(im, median, beta, fit_status):
    """:func:`probability` of stored fits, whose degenerate cases keep a NaN median.

    ``fit_status`` FIT_NO_EXCEEDANCE gives 0 and FIT_ALL_EXCEED gives 1 at every
    intensity, as the fits that produced them say.
    """
    status = np.asarray(fit_status)
    median = np.where(status == FIT_NO_EXCEEDANCE, np.inf, np.where(status == FIT_ALL_EXCEED, 0.0, median))
    return probability(im, median, beta)


def _group(im, n, k):
    """Sum runs and exceedances at each distinct IM level."""
    im = np.asarray(im, float).ravel()
    n = np.asarray(n, float).ravel()
    k = np.asarray(k, float).ravel()
    keep = n > 0
    levels, inverse = np.unique(im[keep], return_inverse=True)
    return levels, np.bincount(inverse, n[keep], len(levels)), np.bincount(inverse, k[keep], len(levels))


def _loglik_terms(eta, n, k):
    return k * log_ndtr(eta) + (n - k) * log_ndtr(-eta)


def _mills(eta):
    """phi(eta)/Phi(eta), stable in both tails."""
    return np.exp(-0.5 * eta**2 - _LOG_SQRT_2PI - log_ndtr(eta))


def _probit_newton(x, n, k, a, b, max_iter=100):
    """Maximise sum k ln Phi(a+bx) + (n-k) ln Phi(-a-bx) by damped Newton."""
    def loglik(a, b):
        return float(np.sum(_loglik_terms(a + b * x, n, k)))

    current = loglik(a, b)
    for _ in range(max_iter):
        eta = a + b * x
        lp, lm = _mills(eta), _mills(-eta)
        d1 = k * lp - (n - k) * lm  # d loglik / d eta
        d2 = -k * lp * (eta + lp) - (n - k) * lm * (-eta + lm)  # <= 0 (log-concave)
        grad = np.array([d1.sum(), (d1 * x).sum()])
        hess = np.array([[d2.sum(), (d2 * x).sum()], [(d2 * x).sum(), (d2 * x * x).sum()]])
        try:
            step = -np.linalg.solve(hess, grad)
        except np.linalg.LinAlgError:
            break
        t = 1.0
        while t > 1e-10:
            trial = loglik(a + t * step[0], b + t * step[1])
            if trial >= current - 1e-12 * abs(current):
                break
            t *= 0.5
        a, b = a + t * step[0], b + t * step[1]
        current = loglik(a, b)
        if abs(t * step[0]) < 1e-13 * (1 + abs(a)) and abs(t * step[1]) < 1e-13 * (1 + abs(b)):
            break
    return a, b, current, hess


_LN_FLOAT_MAX = math.log(np.finfo(float).max)  # ln of the largest float, about 709.8


def fit_lognormal(im, n, k):
    """Maximum-likelihood lognormal fragility from counts at IM levels (Baker 2015, Eq. 11).

    Parameters
    ----------
    im : array_like
        IM level of each group of runs, units of the IM (> 0, finite).
        Levels may repeat; runs at equal levels are pooled.
    n : array_like
        Number of runs at each level [1].
    k : array_like
        Number of those runs that reached the damage state [1], ``0 <= k <= n``.

    Returns
    -------
    LognormalFit
    """
    im = np.asarray(im, float).ravel()
    n = np.asarray(n, float).ravel()
    k = np.asarray(k, float).ravel()
    if not (im.shape == n.shape == k.shape):
        raise InputError(f"fit_lognormal: im, n and k must have the same length ({im.size}, {n.size}, {k.size})")
    if np.any(~np.isfinite(im) | (im <= 0)):
        raise InputError("fit_lognormal: every intensity level must be a positive finite number "
                         "(a record with zero PGA cannot be placed on a lognormal curve)")
    if np.any((k < 0) | (k > n)):
        raise InputError("fit_lognormal: need 0 <= k <= n at every level")
    nan_cov = np.full((2, 2), np.nan)
    levels, n, k = _group(im, n, k)
    if n.sum() == 0:
        return LognormalFit(np.nan, np.nan, FIT_NO_DATA, np.nan, nan_cov)
    if k.sum() == 0:
        return LognormalFit(np.inf, np.nan, FIT_NO_EXCEEDANCE, 0.0, nan_cov)
    if k.sum() == n.sum():
        return LognormalFit(0.0, np.nan, FIT_ALL_EXCEED, 0.0, nan_cov)
    x = np.log(levels)
    below = x[(n - k) > 0].max()  # highest level with a run that did not exceed
    above = x[k > 0].min()  # lowest level with an exceedance
    if below <= above:
        # the likelihood grows without bound as beta -> 0 with the median between the two
        return LognormalFit(float(np.exp(0.5 * (below + above))), 0.0, FIT_SEPARATED, 0.0, nan_cov)
    # start: median at the weighted mean level, beta from the spread of the levels
    weights = n / n.sum()
    mean = float(np.sum(weights * x))
    spread = float(np.sqrt(np.sum(weights * (x - mean) ** 2))) or 0.5
    b0 = 1.0 / max(spread, 0.1)
    a, b, loglik, hess = _probit_newton(x, n, k, -b0 * mean, b0)
    if not (np.isfinite(a) and np.isfinite(b)) or b <= 0 or abs(a / b) > _LN_FLOAT_MAX:
        # b <= 0: the probability falls with the IM; b -> 0+ with a != 0: it is flat (the same share at every
        # level, e.g. 2 of 22 at both of two stripes), the median beyond any float: no increasing curve either
        return LognormalFit(np.nan, np.nan, FIT_DECREASING, loglik, nan_cov)
    median, beta = math.exp(-a / b), 1.0 / b
    # delta method: (ln median, beta) = (-a/b, 1/b)
    jac = np.array([[-1.0 / b, a / b**2], [0.0, -1.0 / b**2]])
    try:
        cov = jac @ np.linalg.inv(-hess) @ jac.T
    except np.linalg.LinAlgError:
        cov = nan_cov
    return LognormalFit(median, beta, FIT_OK, loglik, cov)


# --------------------------------------------------------------------------- results datasets


def open_results(path):
    """Open a study results file and check it has the dimensions fragility needs.

    Parameters
    ----------
    path : str or os.PathLike
        netCDF written by ``frustum study run``.

    Returns
    -------
    xarray.Dataset
        Loaded into memory; ``source_file`` attribute set to ``path``.
    """
    path = os.fspath(path)
    ds = dataset.open_results_file(path, "frustum study run")
    ds.attrs["source_file"] = path
    return _normalise(ds, path)


def _normalise(results, where="results"):
    if "model" not in results.dims:
        model = str(results.attrs.get("model", DEFAULT))
        results = results.expand_dims(model=[model])
    missing = [d for d in RESULT_DIMS if d not in results.dims]
    if missing:
        raise InputError(f"{where}: dimension(s) {', '.join(missing)} missing; a study results file has "
                         f"dims {', '.join(RESULT_DIMS)} (see 'frustum study run')")
    return results


def _where(results):
    return results.attrs.get("source_file", "results dataset")


def _require(results, name, why):
    if name not in results.variables:
        raise InputError(f"{_where(results)}: variable '{name}' is missing ({why}); "
                         "re-run the study with a version of 'frustum study run' that writes it")
    return results[name]


def in_stripes(results):
    """Whether the study scaled every record to stated PGAs (its scales are in m s-2, not factors)."""
    return results["scale"].attrs.get("units", "1") == "m s-2"


def undecided_choice(results):
    """How ``results`` count their undecided runs (:data:`UNDECIDED_CHOICES`): the ``undecided_runs``
    attribute :func:`resolve_undecided` sets, else :data:`DEFAULT_UNDECIDED`."""
    return results.attrs.get("undecided_runs", DEFAULT_UNDECIDED)


def resolve_undecided(results, choice=DEFAULT_UNDECIDED):
    """The results with their undecided runs counted as ``choice`` (a stated choice, never silent).

    Parameters
    ----------
    results : xarray.Dataset
        Study results (an ``undecided`` flag per run, where the model reports it).
    choice : str
        ``"standing"``: an undecided run counts as a run that stood, with the peaks it reached (its
        ``overturned`` flag cleared);
        ``"overturned"``: as one that overturned (its ``overturned`` flag set, so it also reaches
        every other damage state); ``"excluded"``: left out of every fit and count.

    Returns
    -------
    xarray.Dataset
        A copy; its attribute ``undecided_runs`` names the choice (fits, reports and comparisons
        read it through :func:`_valid` and :func:`undecided_choice`).
    """
    if choice not in UNDECIDED_CHOICES:
        raise InputError(f"undecided = {choice!r}: count the runs still able to fall at their settle limit as "
                         f"one of {', '.join(UNDECIDED_CHOICES)}")
    out = results.copy()
    out.attrs["undecided_runs"] = choice
    if choice != "excluded" and "undecided" in out.variables and "overturned" in out.variables:
        undecided = _ok(out) & (out["undecided"].fillna(0) > 0)
        flag = out["overturned"]
        out["overturned"] = flag.where(~undecided, int(choice == "overturned")).astype(flag.dtype)
        out["overturned"].attrs = dict(flag.attrs)
    return out


def _valid(results):
    """Runs to use: status 0 (ok), where a status variable exists; undecided runs (able to fall at their
    settle limit) too, unless the results leave them out (:func:`resolve_undecided`)."""
    ok = _ok(results)
    if "undecided" in results.variables and undecided_choice(results) == "excluded":
        ok = ok & (results["undecided"].fillna(0) == 0)
    return ok


def _ok(results):
    """Runs that computed: status 0, where a status variable exists."""
    if "status" in results.variables:
        return results["status"].fillna(1) == 0
    return xr.ones_like(results[_first_response(results)], dtype=bool)


def _first_response(results):
    for name in ("overturned", "peak_theta_ratio", "peak_theta"):
        if name in results.variables:
            return name
    raise InputError(f"{_where(results)}: neither 'overturned' nor 'peak_theta_ratio' is present; "
                     "this is not a study results file")


#: The result each kind of damage state is a threshold on (``state_measure`` of a fragility).
STATE_MEASURES = {"overturning": "overturned", "theta_ratio": "peak_theta_ratio",
                  "dislocation": "dislocation_ratio"}


def state_labels(states, dislocations=()):
    """Labels of the damage states: ``overturning``, ``theta_ratio_<s>``, then ``dislocation_<s>``."""
    return ["overturning"] + [f"theta_ratio_{s:g}" for s in states] + [f"dislocation_{s:g}" for s in dislocations]


def parse_state(state):
    """(kind, threshold) of a damage state: ``"overturning"`` (NaN), a number or ``"theta_ratio_<s>"``
    (a threshold on peak theta / theta_crit), or ``"dislocation_<s>"`` (on ``dislocation_ratio``)."""
    if isinstance(state, str):
        if state == "overturning":
            return "overturning", math.nan
        for kind in ("theta_ratio", "dislocation"):
            if state.startswith(kind + "_"):
                text = state[len(kind) + 1:]
                break
        else:
            kind, text = "theta_ratio", state
    else:
        kind, text = "theta_ratio", state
    try:
        s = float(text)
    except (TypeError, ValueError):
        raise InputError(f"damage state {state!r}: give 'overturning', a number (theta/theta_crit) or "
                         "'dislocation_<s>' (residual joint slip / diameter)") from None
    if not (math.isfinite(s) and s > 0):
        raise InputError(f"damage state {state!r}: a threshold must be a positive number")
    return kind, s


def exceedance(results, state):
    """Whether each run reached a damage state (bool DataArray over the result dims).

    Parameters
    ----------
    results : xarray.Dataset
    state : "overturning", float or str
        ``"overturning"``; a threshold on peak theta / theta_crit [1] (a number or
        ``"theta_ratio_<s>"``); or ``"dislocation_<s>"``, a threshold on the largest
        residual slip of a bed joint over its diameter [1] (:data:`DISLOCATION_STATES`).
        A threshold is reached when the measure reaches it or the column overturned. A run
        without bed joints (a monolith, a rigid model: ``dislocation_ratio`` 0 or NaN) reaches
        a dislocation state only by overturning.
    """
    kind, s = parse_state(state)
    if kind == "overturning":
        return _require(results, "overturned", "overturning fragility").fillna(0) > 0
    if kind == "dislocation":
        ratio = _require(results, "dislocation_ratio", f"damage state residual joint slip / diameter >= {s:g}; "
                         "it comes from a study with the model 3d-compliant").fillna(0.0)
    else:
        ratio = _require(results, "peak_theta_ratio", f"damage state theta/theta_crit >= {s:g}")
    over = results["overturned"].fillna(0) > 0 if "overturned" in results.variables else False
    return (ratio >= s) | over


def intensity(results, im="pga"):
    """The intensity measure of every run, broadcast over the result dims.

    Parameters
    ----------
    results : xarray.Dataset
    im : str
        Name of a coordinate or variable of ``results`` (``pga`` [m/s^2],
        ``pgv`` [m/s], ``sa`` [m/s^2], or any other).

    Returns
    -------
    xarray.DataArray
        With ``units`` and ``long_name`` attributes.
    """
    if im not in results.variables:
        have = [name for name in IM_NAMES if name in results.variables]
        raise InputError(f"{_where(results)}: intensity measure '{im}' is not in the dataset; "
                         f"available: {', '.join(have) or 'none'} (choose one with --im)")
    values = results[im]
    extra = [d for d in values.dims if d not in RESULT_DIMS]
    if extra:
        raise InputError(f"{_where(results)}: intensity measure '{im}' has extra dimension(s) "
                         f"{', '.join(extra)}; select one value (e.g. one period) before fitting")
    attrs = dict(values.attrs)
    attrs.setdefault("units", IM_DEFAULT_UNITS.get(im, "1"))
    attrs.setdefault("long_name", IM_LONG_NAMES.get(im, im))
    like = results[_first_response(results)]
    out = values.broadcast_like(like).transpose(*like.dims).astype(float)
    out.attrs = attrs
    out.name = im
    return out


def _sample_dims(results):
    """The result dims in the order the fits read them: with a ``seed`` dimension, it follows ``angle``."""
    return RESULT_DIMS[:3] + ("seed",) + RESULT_DIMS[3:] if "seed" in results.dims else RESULT_DIMS


def _pooled(values, results):
    """An array over :func:`_sample_dims` (any leading axes) with the seeds pooled into the angles: over
    (column, record, angle x seed, scale, model), the samples a record gives at a stripe."""
    if "seed" not in results.dims:
        return values
    *lead, c, r, a, n, k, m = values.shape
    return values.reshape(*lead, c, r, a * n, k, m)


def counted(results):
    """1 for each run a fit counts, 0 for a repeat: an angle-invariant model's results do not depend on
    the incidence angle (axisymmetric column), a model of perfect drums (``seeded`` 0) on the seed; each
    is counted once. A DataArray over :func:`_sample_dims` (reports count runs with it as fits do)."""
    dims = _sample_dims(results)
    like = results[_first_response(results)].transpose(*dims)
    weight = xr.ones_like(like, dtype=float)
    invariant = [getattr(of_results(results, str(m)), "angle_invariant", False) for m in results["model"].values]
    weight = weight * xr.where((results["angle"] != results["angle"][0])
                               & xr.DataArray(invariant, dims="model"), 0.0, 1.0)
    if "seed" in results.dims:
        seeded = results["seeded"] if "seeded" in results.variables else xr.ones_like(results["model"], dtype=int)
        weight = weight * xr.where((results["seed"] != results["seed"][0]) & (seeded == 0), 0.0, 1.0)
    return weight.transpose(*dims)


def _once(results):
    """:func:`counted` as the fits read it: over :func:`_sample_dims`, seeds pooled (:func:`_pooled`)."""
    return _pooled(counted(results).values, results)


def _per_record(results, im, labels):
    """Arrays for fitting: im (column, record, angle, scale, model) and exceed (state, ...); the seeds of a
    study of imperfect drums pooled into the angles (:func:`_pooled`)."""
    dims = _sample_dims(results)
    like = results[_first_response(results)].transpose(*dims)
    x = _pooled(intensity(results, im).transpose(*dims).values, results)
    valid = _pooled(_valid(results).broadcast_like(like).transpose(*dims).values, results)
    bad_im = valid & ~(np.isfinite(x) & (x > 0))
    if bad_im.any():
        raise InputError(f"{_where(results)}: intensity measure '{im}' is zero, negative or missing for "
                         f"{int(bad_im.sum())} valid run(s); a lognormal fragility needs positive IM values")
    exceed = _pooled(np.stack([exceedance(results, s).broadcast_like(like).transpose(*dims).values
                               for s in labels]), results)
    weight = valid * _once(results)  # (column, record, angle, scale, model)
    return x, exceed, weight


def _undecided_runs(results):
    """Runs undecided at their settle limit, counted as the fits count runs: (column, model)."""
    if "undecided" not in results.variables:
        return np.zeros((results.sizes["column"], results.sizes["model"]), np.int32)
    dims = _sample_dims(results)
    like = results[_first_response(results)].transpose(*dims)
    undecided = (_ok(results) & (results["undecided"].fillna(0) > 0)).broadcast_like(like)
    undecided = _pooled(undecided.transpose(*dims).values.astype(float), results) * _once(results)
    return undecided.sum(axis=(1, 2, 3)).astype(np.int32)


def _fit_cell(x, exceed, weight):
    """Fit one (state, column, model): arrays over (record, angle, scale)."""
    w = weight.ravel()
    keep = w > 0
    return fit_lognormal(x.ravel()[keep], w[keep], (exceed.ravel() * w)[keep])


def _im_grid(x, weight, n=121):
    values = x[(weight > 0) & np.isfinite(x) & (x > 0)]
    if values.size == 0:
        return np.geomspace(0.1, 10.0, n)
    lo, hi = values.min() / 3.0, values.max() * 2.0
    return np.geomspace(lo, hi, n)


def fragility(results, im="pga", states=DEFAULT_STATES, bootstrap=0, seed=0, confidence=DEFAULT_CONFIDENCE,
              dislocations=None, undecided=None):
    """Fit lognormal fragility curves to every column, model and damage state of a study.

    Parameters
    ----------
    results : xarray.Dataset
        Study results (dims column, record, angle, scale, model; see
        :func:`open_results`). Runs with ``status != 0`` are left out;
        undecided ones count as ``undecided`` says (counted in ``n_undecided``); 3D
        runs are counted once per record and scale (the angle changes no
        number in the 3D model).
    im : str
        Intensity measure: a coordinate or variable of ``results`` (``pga``
        [m/s^2], ``pgv`` [m/s], ``sa`` [m/s^2]).
    states : sequence of float
        Damage-state thresholds on peak theta / theta_crit [1]; overturning
        is always fitted first.
    bootstrap : int
        Number of bootstrap replicates over records (0: no bounds).
    seed : int
        Seed of the bootstrap (numpy ``default_rng``): same seed, same bounds.
    confidence : float
        Confidence level of the percentile bounds, in (0, 1).
    dislocations : sequence of float, optional
        Dislocation damage states: thresholds on the largest residual slip of a bed joint over
        its diameter [1], fitted after the others. Default :data:`DISLOCATION_STATES` when the
        results hold ``dislocation_ratio`` (a study with the compliant model), else none.
    undecided : str, optional
        How runs still able to fall at their settle limit count (:func:`resolve_undecided`);
        default: as the results say (:func:`undecided_choice`, ``"standing"`` unless resolved).

    Returns
    -------
    xarray.Dataset
        Dims ``state``, ``column``, ``model``, ``scale``, ``im_level``; the coordinates
        ``state_measure`` and ``state_threshold`` say what each state is a threshold on.
        Variables ``median`` [IM units], ``beta`` [1], ``fit_status`` (flag),
        ``n_runs``, ``n_exceed``, ``n_records``; with ``bootstrap > 0`` also
        ``median_lower``, ``median_upper``, ``beta_lower``, ``beta_upper``,
        ``probability_lower``, ``probability_upper`` and
        ``n_bootstrap_degenerate``; always ``probability`` (the fitted curve
        on the ``im_level`` grid), ``stripe_im`` (geometric mean IM of each
        scale stripe), ``stripe_runs`` and ``stripe_fraction`` (the data).
        The columns' conicity r/R is the coordinate ``column_beta`` (``beta``
        is the dispersion here).
    """
    results = _normalise(results, _where(results))
    results = resolve_undecided(results, undecided_choice(results) if undecided is None else undecided)
    try:
        states = tuple(sorted(float(s) for s in states))
    except (TypeError, ValueError):
        raise InputError(f"states {states!r}: give numbers (thresholds on theta/theta_crit), e.g. 0.25,0.5,1") from None
    for s in states:
        if not (math.isfinite(s) and s > 0):
            raise InputError(f"state threshold {s!r}: must be a positive number (theta/theta_crit)")
    if dislocations is None:
        dislocations = DISLOCATION_STATES if "dislocation_ratio" in results.variables else ()
    try:
        dislocations = tuple(sorted(float(s) for s in dislocations))
    except (TypeError, ValueError):
        raise InputError(f"dislocations {dislocations!r}: give numbers (residual joint slip / diameter), "
                         "e.g. 0.01,0.05,0.1") from None
    for s in dislocations:
        if not (math.isfinite(s) and s > 0):
            raise InputError(f"dislocation threshold {s!r}: must be a positive number (joint slip / diameter)")
    if not (0.0 < float(confidence) < 1.0):
        raise InputError(f"confidence = {confidence!r}: must be between 0 and 1 (e.g. 0.9)")
    bootstrap = int(bootstrap)
    if bootstrap < 0:
        raise InputError(f"bootstrap = {bootstrap}: must be 0 (no bounds) or a positive number of replicates")
    im_da = intensity(results, im)
    labels = state_labels(states, dislocations)
    x, exceed, weight = _per_record(results, im, labels)
    kinds = [parse_state(label)[0] for label in labels]
    nS, nC, nR, nA, nK, nM = exceed.shape
    grid = _im_grid(x, weight)

    median = np.full((nS, nC, nM), np.nan)
    beta = np.full((nS, nC, nM), np.nan)
    status = np.zeros((nS, nC, nM), np.int8)
    n_runs = np.zeros((nS, nC, nM), np.int32)
    n_exc = np.zeros((nS, nC, nM), np.int32)
    n_records = np.zeros((nC, nM), np.int32)
    curve = np.full((nS, nC, nM, grid.size), np.nan)
    stripe_runs = np.zeros((nC, nK, nM), np.int32)
    stripe_frac = np.full((nS, nC, nK, nM), np.nan)
    for c in range(nC):
        for m in range(nM):
            w = weight[c, :, :, :, m]
            n_records[c, m] = int(np.any(w > 0, axis=(1, 2)).sum())
            stripe_runs[c, :, m] = w.sum(axis=(0, 1))
            for s in range(nS):
                e = exceed[s, c, :, :, :, m]
                fit = _fit_cell(x[c, :, :, :, m], e, w)
                median[s, c, m] = fit.median if np.isfinite(fit.median) and fit.median > 0 else np.nan
                beta[s, c, m] = fit.beta
                status[s, c, m] = fit.status
                n_runs[s, c, m] = int(w.sum())
                n_exc[s, c, m] = int((e * w).sum())
                curve[s, c, m] = probability(grid, fit.median, fit.beta)
                with np.errstate(invalid="ignore", divide="ignore"):
                    stripe_frac[s, c, :, m] = (e * w).sum(axis=(0, 1)) / w.sum(axis=(0, 1))
    with np.errstate(divide="ignore", invalid="ignore"):
        logx = np.where(weight > 0, np.log(np.where(x > 0, x, 1.0)), 0.0)
        stripe_im = np.exp(logx.sum(axis=(0, 1, 2, 4)) / weight.sum(axis=(0, 1, 2, 4)))

    im_units = im_da.attrs["units"]
    im_long = im_da.attrs["long_name"]
    used = (weight > 0) & np.isfinite(x)
    im_min = np.where(used, x, np.inf).min(axis=(1, 2, 3))  # (column, model)
    im_max = np.where(used, x, -np.inf).max(axis=(1, 2, 3))
    im_min[~np.isfinite(im_min)] = np.nan
    im_max[~np.isfinite(im_max)] = np.nan
    dims3 = ("state", "column", "model")
    ds = xr.Dataset(
        {
            "median": (dims3, median, {"units": im_units,
                                       "long_name": f"median {im_long} of the lognormal fragility curve"}),
            "beta": (dims3, beta, {"units": "1", "long_name": "lognormal dispersion of the fragility curve "
                                   "(standard deviation of ln IM capacity)"}),
            "fit_status": (dims3, status, {
                "long_name": "outcome of the maximum-likelihood fit",
                "flag_values": np.arange(len(FIT_STATUS), dtype=np.int8),
                "flag_meanings": " ".join(FIT_STATUS.values()),
                "comment": "median and beta are NaN for no_exceedance_observed, every_run_exceeds, no_valid_runs and "
                           "probability_decreases_with_im; perfectly_separated: "
                           "beta = 0 and median between the highest IM without and the lowest with an exceedance",
            }),
            "n_runs": (dims3, n_runs, {"units": "1", "long_name": "number of runs in the fit"}),
            "n_undecided": (("column", "model"), _undecided_runs(results), {
                "units": "1", "long_name": "number of runs still able to fall when they reached their settle "
                "limit (undecided), counted in the fits as the attribute undecided_runs says"}),
            "n_exceed": (dims3, n_exc, {"units": "1", "long_name": "number of runs that reached the damage state"}),
            "n_records": (("column", "model"), n_records, {"units": "1", "long_name": "number of records with valid runs"}),
            "probability": (dims3 + ("im_level",), curve, {
                "units": "1", "long_name": "probability of reaching the damage state (fitted lognormal curve)"}),
            "stripe_runs": (("column", "scale", "model"), stripe_runs, {
                "units": "1", "long_name": "number of runs in the scale stripe"}),
            "stripe_fraction": (("state", "column", "scale", "model"), stripe_frac, {
                "units": "1", "long_name": "observed fraction of runs in the scale stripe that reached the damage state"}),
            "im_simulated_min": (("column", "model"), im_min, {
                "units": im_units, "long_name": f"weakest {im_long} of the runs in the fit"}),
            "im_simulated_max": (("column", "model"), im_max, {
                "units": im_units, "long_name": f"strongest {im_long} of the runs in the fit"}),
            "stripe_im": (("scale",), stripe_im, {
                "units": im_units, "long_name": f"geometric mean {im_long} of the runs in the scale stripe"}),
        },
        coords={
            "state": ("state", np.array(labels, dtype=object), {"long_name": "damage state"}),
            "state_threshold": ("state", np.array([np.nan, *states, *dislocations]), {
                "units": "1", "long_name": "threshold of the damage state on its measure, state_measure "
                "(NaN: overturning)"}),
            "state_measure": ("state", np.array([STATE_MEASURES[k] for k in kinds], dtype=object), {
                "long_name": "result the damage state is a threshold on: overturned (any body fell), "
                "peak_theta_ratio (peak theta / theta_crit) or dislocation_ratio (largest residual slip "
                "of a bed joint over its diameter)"}),
            "column": results["column"].values.astype(str).astype(object),
            "model": results["model"].values.astype(str).astype(object),
            "scale": ("scale", results["scale"].values.astype(float), {"units": "1", "long_name": "scale factor on the record"}),
            "im_level": ("im_level", grid, {"units": im_units, "long_name": f"{im_long} at which the curve is evaluated"}),
        },
    )
    for name in ("column_R", "column_r", "column_h", "slenderness", "theta_crit", "latitude", "longitude",
                 *STRUCTURE_COORDS):
        if name in results.coords and results[name].dims == ("column",):
            ds.coords[name] = ("column", results[name].values, dict(results[name].attrs))
    for name in ("base_model", "model_variant"):  # a study's variants: which model each is, and how
        if name in results.variables and results[name].dims == ("model",):
            ds.coords[name] = ("model", results[name].values, dict(results[name].attrs))
    if "beta" in results.variables and results["beta"].dims == ("column",):
        ds.coords["column_beta"] = ("column", results["beta"].values,
                                    {"units": "1", "long_name": "conicity r/R of the column"})

    if bootstrap:
        _bootstrap(ds, x, exceed, weight, grid, bootstrap, seed, confidence)
    if "seed" in results.dims:  # a study of imperfect drums: its seeds pooled
        ds.attrs["seeds_pooled"] = " ".join(str(int(v)) for v in results["seed"].values)
        for name in ("imperfection_tolerance_m", "imperfection_friction_range", "imperfection_models"):
            if name in results.attrs:
                ds.attrs[name] = results.attrs[name]
        if "seeded" in results.variables:
            ds.coords["seeded"] = ("model", results["seeded"].values, dict(results["seeded"].attrs))

    ds.attrs.update(
        title=structures_title("Lognormal fragility curves", results.attrs),
        summary="Maximum-likelihood lognormal fragility (median, dispersion) per damage state, column and model, "
                "from multiple-stripe study results (binomial likelihood on counts per IM level, records and "
                "angles pooled; 3D runs counted once per record and scale).",
        intensity_measure=im,
        intensity_measure_units=im_units,
        **({"intensity_measure_period": float(im_da.attrs["period"])} if "period" in im_da.attrs else {}),
        confidence_level=float(confidence),
        undecided_runs=f"{undecided_choice(results)}: runs still able to fall when they reached their settle limit "
                       "(n_undecided) count as runs that stood (standing), as runs that overturned (overturned) or "
                       "are left out (excluded)",
        bootstrap_replicates=bootstrap,
        bootstrap_seed=int(seed),
        bootstrap_method="records resampled with replacement (all angles, seeds and scales of a record "
                         "together); percentile intervals",
        method="Baker J.W. (2015) Efficient analytical fragility function fitting using dynamic structural "
               "analysis data, Earthquake Spectra 31(1) 579-599; probit regression solved by Newton's method",
        damage_states="overturning (for a column of drums: any drum lay down or fell); theta_ratio_s: peak "
                      "theta / theta_crit >= s or overturned; dislocation_s: largest residual slip of a bed joint "
                      ">= s times its diameter, or overturned",
    )
    for key in ("study", "study_digest", "source_file", "title"):
        if key in results.attrs:
            ds.attrs[f"results_{key}"] = str(results.attrs[key])
    if "structures" in results.attrs:
        ds.attrs["structures"] = str(results.attrs["structures"])
    own = {name: dict(var.attrs) for name, var in ds.variables.items()}
    annotate(ds)
    for name, attrs in own.items():  # the catalog must not relabel IM-dependent units
        ds[name].attrs = {**ds[name].attrs, **attrs}
    append_history(ds, f"pipeline.fragility im={im} states={','.join(f'{s:g}' for s in states)} "
                       f"dislocations={','.join(f'{s:g}' for s in dislocations)} bootstrap={bootstrap} seed={seed}")
    return ds


def _bootstrap(ds, x, exceed, weight, grid, n_boot, seed, confidence):
    nS, nC, nR, nA, nK, nM = exceed.shape
    rng = np.random.default_rng(seed)
    draws = rng.integers(0, nR, size=(n_boot, nR))
    med = np.full((n_boot, nS, nC, nM), np.nan)
    bet = np.full((n_boot, nS, nC, nM), np.nan)
    curves = np.full((n_boot, nS, nC, nM, grid.size), np.nan)
    for b, idx in enumerate(draws):
        for c in range(nC):
            for m in range(nM):
                w = weight[c, idx, :, :, m]
                xx = x[c, idx, :, :, m]
                for s in range(nS):
                    fit = _fit_cell(xx, exceed[s, c, idx, :, :, m], w)
                    med[b, s, c, m] = fit.median
                    bet[b, s, c, m] = fit.beta
                    curves[b, s, c, m] = probability(grid, fit.median, fit.beta)
    alpha = 0.5 * (1.0 - confidence)
    q = [alpha, 1.0 - alpha]

    def bounds(samples):
        # no interpolation between order statistics: inf (no exceedance) stays meaningful
        out = np.full((2,) + samples.shape[1:], np.nan)
        for index in np.ndindex(samples.shape[1:]):
            v = samples[(slice(None),) + index]
            v = v[~np.isnan(v)]
            if v.size:
                out[(slice(None),) + index] = np.quantile(v, q, method="inverted_cdf")
        return out

    mb, bb, pb = bounds(med), bounds(bet), bounds(curves)
    mb[~np.isfinite(mb)] = np.nan
    mb[mb == 0] = np.nan
    dims3 = ("state", "column", "model")
    level = f"{100 * confidence:g} %"
    units = ds["median"].attrs["units"]
    ds["median_lower"] = (dims3, mb[0], {"units": units, "long_name": f"lower bound of the median, {level} bootstrap interval"})
    ds["median_upper"] = (dims3, mb[1], {"units": units, "long_name": f"upper bound of the median, {level} bootstrap interval",
                                         "comment": "NaN where the bound is unbounded (replicates without exceedance)"})
    ds["beta_lower"] = (dims3, bb[0], {"units": "1", "long_name": f"lower bound of the dispersion, {level} bootstrap interval"})
    ds["beta_upper"] = (dims3, bb[1], {"units": "1", "long_name": f"upper bound of the dispersion, {level} bootstrap interval"})
    ds["probability_lower"] = (dims3 + ("im_level",), pb[0], {
        "units": "1", "long_name": f"lower bound of the probability, pointwise {level} bootstrap band"})
    ds["probability_upper"] = (dims3 + ("im_level",), pb[1], {
        "units": "1", "long_name": f"upper bound of the probability, pointwise {level} bootstrap band"})
    degenerate = np.sum(~(np.isfinite(med) & (med > 0) & np.isfinite(bet) & (bet > 0)), axis=0)
    ds["n_bootstrap_degenerate"] = (dims3, degenerate.astype(np.int32), {
        "units": "1", "long_name": "bootstrap replicates without a regular fit (no exceedance, all exceed or separated)"})
    # the replicates themselves, so that a quantity computed from the curve (the risk at a site,
    # pipeline.risk) gets its own interval rather than one built from these pointwise bounds
    ds["median_bootstrap"] = (("bootstrap",) + dims3, med, {
        "units": units, "long_name": "median of each bootstrap replicate's fit",
        "comment": "inf: the replicate has no exceedance; 0: every run of it exceeds; NaN: no valid runs"})
    ds["beta_bootstrap"] = (("bootstrap",) + dims3, bet, {
        "units": "1", "long_name": "dispersion of each bootstrap replicate's fit",
        "comment": "0: perfectly separated replicate (a step at its median); NaN where the median is inf, 0 or NaN"})


def ida(results, im="pga", model=None, column=None, angle="max"):
    """Incremental dynamic analysis view: peak theta/theta_crit against the IM, per record.

    Parameters
    ----------
    results : xarray.Dataset
    im : str
        Intensity measure name.
    model, column : str, optional
        Select one model / column (default: the first).
    angle : "max", "median" or float
        How to reduce over incidence angles: the largest or median ratio over
        angles, or the angle [deg] nearest the given one (the seeds of imperfect
        drums with them: the largest or median over angles and seeds, the largest
        over the seeds at that angle).

    Returns
    -------
    xarray.Dataset
        Dims (record, scale): ``peak_theta_ratio`` [1] (``inf`` where the
        run overturned, NaN where it failed), ``overturned`` (bool) and the IM.
    """
    results = _normalise(results, _where(results))
    model = str(results["model"].values[0]) if model is None else model
    column = str(results["column"].values[0]) if column is None else column
    if model not in [str(m) for m in results["model"].values]:
        raise InputError(f"{_where(results)}: model {model!r} is not in the dataset")
    if column not in [str(c) for c in results["column"].values]:
        raise InputError(f"{_where(results)}: column {column!r} is not in the dataset")
    one = results.sel(model=model, column=column)
    ratio = _require(one, "peak_theta_ratio", "IDA view").where(_valid(one))
    over = exceedance(one, "overturning") & _valid(one)
    ratio = xr.where(over, np.inf, ratio)
    x = intensity(one, im)
    pool = ("angle", "seed") if "seed" in one.dims else "angle"  # the seeds of imperfect drums as angles
    if angle == "max":
        r, o, xi = ratio.max(pool), over.any(pool), x.max(pool)
    elif angle == "median":
        r, o, xi = ratio.median(pool), over.mean(pool) >= 0.5, x.median(pool)
    else:
        pick = dict(angle=float(angle), method="nearest")
        r, o, xi = ratio.sel(**pick), over.sel(**pick), x.sel(**pick)
        if "seed" in r.dims:  # the seeds at that angle: the largest
            r, o, xi = r.max("seed"), o.any("seed"), xi.max("seed")
    return xr.Dataset({"peak_theta_ratio": r, "overturned": o, im: xi})


def write(ds, path):
    """Write a fragility dataset to netCDF atomically, in the convention of :func:`pipeline.dataset.write_netcdf`."""
    return write_netcdf(ds, path)


__all__ = [
    "DEFAULT_STATES",
    "DISLOCATION_STATES",
    "UNDECIDED_CHOICES",
    "DEFAULT_UNDECIDED",
    "resolve_undecided",
    "undecided_choice",
    "parse_state",
    "FIT_STATUS",
    "LognormalFit",
    "fit_lognormal",
    "probability",
    "open_results",
    "exceedance",
    "intensity",
    "in_stripes",
    "fragility",
    "state_labels",
    "ida",
    "write",
]
