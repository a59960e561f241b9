"""Maximum-likelihood lognormal fragility (Baker 2015): recovery, independent fit, degenerate data."""

import math

import numpy as np
import pytest
from scipy.optimize import minimize
from scipy.stats import norm

from pipeline.fragility import (
    FIT_ALL_EXCEED,
    FIT_NO_DATA,
    FIT_NO_EXCEEDANCE,
    FIT_OK,
    FIT_SEPARATED,
    fit_lognormal,
    probability,
)

TRUE_MEDIAN = 3.0  # [m/s^2]
TRUE_BETA = 0.45
LEVELS = TRUE_MEDIAN * np.exp(np.linspace(-1.2, 1.2, 9))  # nine stripes over +-2.7 beta
RUNS = 40  # per stripe


def draw(rng, n=RUNS, median=TRUE_MEDIAN, beta=TRUE_BETA, levels=LEVELS):
    p = norm.cdf(np.log(levels / median) / beta)
    return rng.binomial(n, p)


def independent_fit(levels, n, k):
    """Baker (2015) Eq. 11 written out again and minimised by Nelder-Mead on (ln median, beta)."""
    x = np.log(levels)

    def nll(params):
        ln_median, beta = params
        if beta <= 0:
            return np.inf
        p = norm.cdf((x - ln_median) / beta)
        p = np.clip(p, 1e-300, 1 - 1e-16)
        return -np.sum(k * np.log(p) + (n - k) * np.log1p(-p))

    res = minimize(nll, [np.log(np.median(levels)), 0.5], method="Nelder-Mead",
                   options={"xatol": 1e-10, "fatol": 1e-13, "maxiter": 20000, "maxfev": 40000})
    assert res.success
    return math.exp(res.x[0]), res.x[1]


def expected_se(n=RUNS, median=TRUE_MEDIAN, beta=TRUE_BETA, levels=LEVELS):
    """Standard errors of (ln median, beta) from the expected Fisher information of the binomial model."""
    eta = np.log(levels / median) / beta
    p, d = norm.cdf(eta), norm.pdf(eta)
    w = n * d**2 / (p * (1 - p))
    grad = np.stack([-np.ones_like(eta) / beta, -eta / beta])  # d eta / d(ln median, beta)
    info = (w * grad) @ grad.T
    return np.sqrt(np.diag(np.linalg.inv(info)))


def test_agrees_with_independent_scipy_fit_to_1e_4():
    rng = np.random.default_rng(2015)
    for _ in range(5):
        k = draw(rng)
        fit = fit_lognormal(LEVELS, np.full(LEVELS.size, RUNS), k)
        assert fit.status == FIT_OK
        median, beta = independent_fit(LEVELS, RUNS, k)
        assert fit.median == pytest.approx(median, rel=1e-4)
        assert fit.beta == pytest.approx(beta, rel=1e-4)
        # and our optimum is at least as good (Newton converges to machine precision)
        assert abs(fit.median / median - 1) < 1e-6 and abs(fit.beta / beta - 1) < 1e-6


def test_recovers_truth_within_sampling_error_over_many_seeds():
    """Over 300 data sets the z-scores (fit - truth)/SE have mean ~0 and spread ~1.

    SE from the expected Fisher information at the truth: ln median 0.043, beta 0.050
    here. The mean of 300 z-scores has standard error 1/sqrt(300) = 0.058, so
    |mean| < 0.25 is a 4-sigma bound (plus O(1/n) MLE bias, small at 360 runs);
    their standard deviation has relative sampling error 1/sqrt(600) = 4 %, so
    [0.8, 1.2] allows 5 sigma and the asymptotic approximation.
    """
    rng = np.random.default_rng(11)
    se_ln_median, se_beta = expected_se()
    z_median, z_beta = [], []
    for _ in range(300):
        k = draw(rng)
        fit = fit_lognormal(LEVELS, np.full(LEVELS.size, RUNS), k)
        assert fit.status == FIT_OK
        z_median.append((math.log(fit.median) - math.log(TRUE_MEDIAN)) / se_ln_median)
        z_beta.append((fit.beta - TRUE_BETA) / se_beta)
    z_median, z_beta = np.array(z_median), np.array(z_beta)
    assert abs(z_median.mean()) < 0.25
    assert abs(z_beta.mean()) < 0.25
    assert 0.8 < z_median.std() < 1.2
    assert 0.8 < z_beta.std() < 1.2


def test_single_fit_within_three_standard_errors_and_covariance_matches_fisher():
    rng = np.random.default_rng(5)
    k = draw(rng, n=200)
    fit = fit_lognormal(LEVELS, np.full(LEVELS.size, 200), k)
    se_ln_median, se_beta = expected_se(n=200)
    assert abs(math.log(fit.median / TRUE_MEDIAN)) < 3 * se_ln_median
    assert abs(fit.beta - TRUE_BETA) < 3 * se_beta
    # the observed-information covariance approximates the expected one (within 25 %: sampling of the Hessian)
    assert math.sqrt(fit.covariance[0, 0]) == pytest.approx(se_ln_median, rel=0.25)
    assert math.sqrt(fit.covariance[1, 1]) == pytest.approx(se_beta, rel=0.25)


def test_individual_runs_at_distinct_levels_give_the_same_fit_as_grouped_counts():
    """Records scaled by factors (one IM per run) use the same likelihood as stripes."""
    rng = np.random.default_rng(3)
    k = draw(rng, n=10)
    grouped = fit_lognormal(LEVELS, np.full(LEVELS.size, 10), k)
    im = np.repeat(LEVELS, 10)
    outcomes = np.concatenate([[1] * kk + [0] * (10 - kk) for kk in k])
    single = fit_lognormal(im, np.ones(im.size), outcomes)
    assert single.median == pytest.approx(grouped.median, rel=1e-10)
    assert single.beta == pytest.approx(grouped.beta, rel=1e-10)


def test_degenerate_data_give_documented_results_not_crashes():
    n = np.full(3, 10)
    levels = np.array([1.0, 2.0, 4.0])
    none = fit_lognormal(levels, n, [0, 0, 0])
    assert none.status == FIT_NO_EXCEEDANCE and none.median == np.inf and np.isnan(none.beta)
    every = fit_lognormal(levels, n, [10, 10, 10])
    assert every.status == FIT_ALL_EXCEED and every.median == 0
    sep = fit_lognormal(levels, n, [0, 0, 10])
    assert sep.status == FIT_SEPARATED and sep.beta == 0
    assert sep.median == pytest.approx(math.sqrt(2.0 * 4.0))  # geometric midpoint of the gap
    quasi = fit_lognormal(levels, n, [0, 4, 10])  # mixed only at one level: beta -> 0 at that level
    assert quasi.status == FIT_SEPARATED and quasi.median == pytest.approx(2.0)
    empty = fit_lognormal(levels, [0, 0, 0], [0, 0, 0])
    assert empty.status == FIT_NO_DATA
    # probability() of each degenerate fit
    assert np.all(probability(levels, none.median, none.beta) == 0)
    assert np.all(probability(levels, every.median, every.beta) == 1)
    assert list(probability(levels, sep.median, sep.beta)) == [0, 0, 1]


def test_bad_counts_rejected():
    from pipeline.errors import InputError

    with pytest.raises(InputError, match="positive finite"):
        fit_lognormal([0.0, 1.0], [1, 1], [0, 1])
    with pytest.raises(InputError, match="0 <= k <= n"):
        fit_lognormal([1.0, 2.0], [1, 1], [0, 2])


def test_the_same_share_at_every_level_is_no_increasing_curve_not_an_overflow():
    """2 of 22 at both of two stripes (a bootstrap resample of studies/parthenon/imperfect.toml did this):
    the likelihood's best curve is flat, b -> 0+ with a = probit(2/22) != 0, and exp(-a/b) overflowed."""
    from pipeline.fragility import FIT_DECREASING

    fit = fit_lognormal([5.88, 9.81], [22, 22], [2, 2])
    assert fit.status == FIT_DECREASING and np.isnan(fit.median) and np.isnan(fit.beta)
    rising = fit_lognormal([5.88, 9.81], [22, 22], [2, 3])  # one more at the higher level: a curve
    assert rising.status == FIT_OK and rising.median > 9.81 and rising.beta > 0
