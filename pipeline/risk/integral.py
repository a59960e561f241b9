"""The risk integral of a tabulated hazard curve against a lognormal fragility, in closed form per segment.

The mean annual frequency of a damage state is the risk integral (Cornell 1968)::

    lambda_DS = integral P(DS | a) |dH/da| da                                       [1/yr]

Between its levels the hazard curve is interpolated log-log (a power law H = H_i (a/a_i)^-k_i on
each segment), and with a lognormal fragility each segment's integral has a closed form
(:func:`segment_integral`; integration by parts, then the Gaussian integral), so no quadrature
error enters. Over one segment extended from 0 to infinity it is Kennedy's closed form
``lambda = H(median) exp(k^2 beta^2 / 2)`` (Kennedy & Short 1994, Cornell et al. 2002).

Beyond the curve's last level a_L the hazard is unknown. :func:`risk_integral` returns three
numbers, so the part beyond is bounded and stated rather than silently dropped:

* ``lower``: shaking beyond a_L (rate H(a_L)) counted at P(a_L), the least probability it can
  have (P grows with a), and nothing below the first level a_0;
* ``upper``: shaking beyond a_L counted with P = 1, plus the part below a_0 as ``central``;
* ``central``: the last segment's power law extended beyond a_L, the first one's below a_0.

``central`` lies between the bounds. Occurrences are Poisson: the probability in T years is
:func:`probability_in`, the mean return period :func:`return_period`.
"""

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import log_ndtr

from pipeline import fragility as F


#: Shares of the risk at which the intensity is stated (``intensity_risk_05`` ...): 5, 50, 95 %.
RISK_SHARES = (0.05, 0.5, 0.95)


def probability_in(rate, years):
    """Probability of at least one occurrence in ``years`` of a Poisson process of ``rate`` [1/yr]: 1 - exp(-rate T).

    ``rate`` and ``years`` broadcast together.
    """
    with np.errstate(over="ignore"):  # rate T beyond the largest float is inf, and the probability 1
        return -np.expm1(-np.asarray(rate, float) * np.asarray(years, float))


def return_period(annual_frequency):
    """Mean return period 1/lambda [yr]: ``inf`` where lambda is 0, NaN where it is NaN.

    Where 1/lambda is beyond the largest float (lambda subnormal) it is ``inf`` as well, without
    numpy's overflow warning.
    """
    lam = np.asarray(annual_frequency, float)
    out = np.where(np.isnan(lam), np.nan, np.inf)
    return np.divide(1.0, lam, out=out, where=lam > 1.0 / np.finfo(float).max)


def _log_ndtr_diff(a, b):
    """log(Phi(b) - Phi(a)) for a <= b, stable in both tails (-inf where b <= a)."""
    a, b = np.broadcast_arrays(np.asarray(a, float), np.asarray(b, float))
    upper = a > 0  # both in the upper tail: Phi(b) - Phi(a) = Phi(-a) - Phi(-b)
    big = np.where(upper, log_ndtr(-a), log_ndtr(b))
    small = np.where(upper, log_ndtr(-b), log_ndtr(a))
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.asarray(big + np.log1p(-np.exp(small - big)), float)
    return np.where(~(b > a) | np.isneginf(big), -np.inf, out)


def segment_integral(x1, x2, x_ref, ln_h_ref, k, median, beta):
    """Integral of P(DS | a) |dH/da| da over one power-law segment of a hazard curve [1/yr].

    On the segment ``x1 <= ln a <= x2`` the hazard is ``ln H = ln_h_ref - k (ln a - x_ref)`` and the
    fragility is lognormal, ``P = Phi((ln a - ln median) / beta)``. Integrating by parts and then the
    Gaussian integral gives, with ``z = (x - ln median) / beta``::

        H(x1) Phi(z1) - H(x2) Phi(z2) + H(median) exp(k^2 beta^2 / 2) [Phi(z2 + k beta) - Phi(z1 + k beta)]

    (the last term evaluated in logs, so steep segments do not overflow). From 0 to infinity it is
    Kennedy's ``H(median) exp(k^2 beta^2 / 2)``.

    Parameters
    ----------
    x1, x2 : array_like
        Ends of the segment, ln of the intensity in the fragility's units (``x1`` may be -inf,
        ``x2`` +inf).
    x_ref, ln_h_ref : array_like
        A point of the segment's power law: ln intensity and ln H [ln(1/yr)].
    k : array_like
        Slope -d ln H / d ln a [1], >= 0.
    median : array_like
        Fragility median, units of the intensity; ``inf`` gives P = 0, ``0`` gives P = 1.
    beta : array_like
        Dispersion [1]; 0 is a step at the median.

    Returns
    -------
    numpy.ndarray
        [1/yr], broadcast over the arguments; NaN where ``median`` is NaN or ``beta`` is NaN for a
        finite positive median.
    """
    x1, x2, x_ref, ln_h_ref, k, median, beta = np.broadcast_arrays(
        *(np.asarray(v, float) for v in (x1, x2, x_ref, ln_h_ref, k, median, beta)))
    out = np.full(x1.shape, np.nan)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        mu = np.log(median)

        def ln_h(x):
            return ln_h_ref - k * (x - x_ref)

        def h(x):  # H at a segment's end (0 at +inf, inf at -inf for k > 0)
            return np.where(np.isposinf(x), 0.0, np.where(np.isneginf(x), np.inf, np.exp(ln_h(x))))

        flat = k == 0
        never = np.isposinf(mu)  # P = 0
        always = np.isneginf(mu)  # P = 1
        step = np.isfinite(mu) & (beta == 0)
        smooth = np.isfinite(mu) & (beta > 0)

        # P = 1: every exceedance counts
        out = np.where(always, h(x1) - h(x2), out)
        out = np.where(never, 0.0, out)
        # a step at the median: H(max(x1, mu)) - H(x2) where the median lies below x2
        lo = np.maximum(x1, mu)
        out = np.where(step, np.where(mu < x2, h(lo) - h(x2), 0.0), out)
        # lognormal: the closed form
        z1 = (x1 - mu) / beta
        z2 = (x2 - mu) / beta
        t1 = np.where(np.isneginf(x1), 0.0, np.exp(ln_h(x1) + log_ndtr(z1)))
        t2 = np.where(np.isposinf(x2), 0.0, np.exp(ln_h(x2) + log_ndtr(z2)))
        kb = k * beta
        t3 = np.exp(ln_h(mu) + 0.5 * kb**2 + _log_ndtr_diff(z1 + kb, z2 + kb))
        out = np.where(smooth, np.maximum(t1 - t2 + t3, 0.0), out)
        out = np.where(flat & (smooth | step | never | always), 0.0, out)
    return out


@dataclass(frozen=True)
class RiskParts:
    """The risk integral of one hazard curve against fragilities, with the parts outside the curve.

    Attributes (arrays broadcast over the fragilities given), all [1/yr] except the shares:
    ``central``, ``lower``, ``upper`` (module docstring), ``inside`` (between the first and last
    level), ``below`` (below the first level, first segment extended), ``beyond`` (beyond the last
    level, last segment extended), ``h_last`` (H at the last level), ``p_last`` (P at the last
    level [1]).
    """

    central: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    inside: np.ndarray
    below: np.ndarray
    beyond: np.ndarray
    h_last: float
    p_last: np.ndarray


def _pieces(levels, rates, tails=(None, None)):
    """ln a and ln H at a curve's L levels, and the slopes k = -d ln H / d ln a [1] of its L + 1 pieces.

    Piece 0 lies below the first level, piece i between levels i - 1 and i, piece L beyond the last.
    The two outer pieces take the slopes ``tails`` = (below, beyond) where given, else the end
    segments' own (a curve of one level needs both).
    """
    x = np.log(np.asarray(levels, float))
    ln_h = np.log(np.asarray(rates, float))
    k = np.maximum(-np.diff(ln_h) / np.diff(x), 0.0)
    below, beyond = tails
    if k.size == 0 and (below is None or beyond is None):
        raise ValueError("a hazard curve of one level needs its slopes below and beyond it (tails)")
    below = k[0] if below is None else float(below)
    beyond = k[-1] if beyond is None else float(beyond)
    return x, ln_h, np.concatenate([[below], k, [beyond]])


def ln_rate(x, ln_h, k, g):
    """ln H [ln(1/yr)] at ln intensities ``g`` on the pieces of :func:`_pieces`, and the piece of each."""
    piece = np.searchsorted(x, g, side="right")
    at = np.maximum(piece - 1, 0)  # the level each piece's power law is anchored at
    return ln_h[at] - k[piece] * (g - x[at]), piece


def risk_integral(levels, rates, median, beta, tails=(None, None)):
    """Mean annual frequency of a damage state: the risk integral over a tabulated hazard curve.

    Parameters
    ----------
    levels : array_like
        Intensity levels of the hazard curve, increasing, in the units of ``median`` (SI:
        [m/s^2] for PGA and Sa).
    rates : array_like
        Annual rate of exceedance at each level [1/yr], positive, non-increasing.
    median, beta : array_like
        Lognormal fragility: median [units of ``levels``] (``inf``: never reached, ``0``:
        always) and dispersion [1] (0: a step). Broadcast together.
    tails : (float or None, float or None)
        Slopes k [1] of the power laws below the first and beyond the last level; None: the end
        segment's own (a code-value curve gives its own, :mod:`pipeline.risk.hazard_code`).

    Returns
    -------
    RiskParts
        ``central`` = below + inside + beyond; ``lower`` = inside + P(a_L) H(a_L); ``upper`` =
        below + inside + H(a_L).
    """
    x, ln_h, k = _pieces(levels, rates, tails)
    median, beta = np.broadcast_arrays(np.asarray(median, float), np.asarray(beta, float))
    shape = median.shape
    m = median[..., None]
    b = beta[..., None]
    inside = segment_integral(x[:-1], x[1:], x[:-1], ln_h[:-1], k[1:-1], m, b).sum(axis=-1)
    below = segment_integral(-np.inf, x[0], x[0], ln_h[0], k[0], median, beta)
    beyond = segment_integral(x[-1], np.inf, x[-1], ln_h[-1], k[-1], median, beta)
    h_last = float(np.exp(ln_h[-1]))
    p_last = F.probability(np.exp(x[-1]), np.where(np.isnan(median), np.nan, median),
                           np.where(np.isfinite(median) & (median > 0), beta, 1.0)).reshape(shape)
    lower = inside + p_last * h_last
    upper = below + inside + h_last
    # a flat last segment never releases H(a_L): count it at P(a_L) at least
    central = below + inside + np.maximum(beyond, p_last * h_last)
    return RiskParts(central=central, lower=lower, upper=upper, inside=inside, below=below, beyond=beyond,
                     h_last=h_last, p_last=p_last)


def _log_probability(im, median, beta):
    """ln P(DS | im) of a lognormal fragility (:func:`pipeline.fragility.probability`), from ``log_ndtr``
    where it is smooth, so that the far lower tail stays a number where P itself underflows to 0."""
    im, median, beta = np.broadcast_arrays(*(np.asarray(v, float) for v in (im, median, beta)))
    with np.errstate(divide="ignore"):  # P = 0 (a step not reached, a median never reached): ln P = -inf
        out = np.log(F.probability(im, median, beta))
    smooth = np.isfinite(median) & (median > 0) & (beta > 0)
    out[smooth] = log_ndtr(np.log(im[smooth] / median[smooth]) / beta[smooth])
    return out


def _integrand(grid, levels, rates, median, beta, tails=(None, None)):
    """P(DS | a) |dH/d ln a| on ``grid`` [1/yr per unit ln a], and H(a) on it (curve extended by its end segments).

    The product is taken in logs: where the first segment, extended below the curve, gives a rate
    beyond the largest float, P there is far below the smallest, and their product may be either.
    """
    x, ln_h, k = _pieces(levels, rates, tails)
    ln_hg, piece = ln_rate(x, ln_h, k, np.log(grid))
    b = np.where(np.isfinite(median) & (median > 0), beta, 1.0)[..., None]
    p = F.probability(grid, median[..., None], b)
    with np.errstate(divide="ignore"):  # a flat segment (k = 0) adds nothing: ln k = -inf
        ln_k = np.log(k[piece])
    with np.errstate(over="ignore"):  # beyond the largest float the value is inf (risk_flag integral_overflows)
        return np.exp(_log_probability(grid, median[..., None], b) + ln_k + ln_hg), np.exp(ln_hg), p


def _shares(grid, density, below, total, shares=RISK_SHARES):
    """Intensities below which the given shares of ``total`` accrue (NaN where the grid does not reach them)."""
    g = np.log(grid)
    with np.errstate(over="ignore", invalid="ignore"):  # sums beyond the largest float: inf, skipped below
        steps = (0.5 * density[..., 1:] + 0.5 * density[..., :-1]) * np.diff(g)
        cum = np.concatenate([np.zeros(density.shape[:-1] + (1,)), np.cumsum(steps, axis=-1)], axis=-1)
        cum = cum + below[..., None]
    out = np.full(density.shape[:-1] + (len(shares),), np.nan)
    for index in np.ndindex(density.shape[:-1]):
        t = total[index]
        if not (np.isfinite(t) and t > 0 and np.all(np.isfinite(cum[index]))):
            continue
        frac = cum[index] / t
        for j, s in enumerate(shares):
            above = np.nonzero(frac >= s)[0]
            if above.size and above[0] > 0:
                i = above[0]
                w = (s - frac[i - 1]) / (frac[i] - frac[i - 1])
                out[index + (j,)] = math.exp(g[i - 1] + w * (g[i] - g[i - 1]))
    return out
