"""Hazard curves from code values (issue 48, item 1): PGAs at return periods, power laws between and beyond them.

Independent checks: Kennedy's closed form lambda = H(m) exp(k^2 beta^2 / 2) for a single power law
H(a) = H0 (a/a0)^-k and a lognormal fragility (Kennedy & Short 1994; Cornell et al. 2002, Eq. 11),
evaluated with mpmath at 40 digits; for curves of several slopes, mpmath's quadrature of
P(DS | a) |dH/d ln a| over ln a, piece by piece.
"""

import itertools
import math
import warnings

import mpmath as mp
import numpy as np
import pytest
import xarray as xr
from fragility_synthetic import make_results
from hazard_files import fixed_fragility

from pipeline import fragility as F
from pipeline import risk as R
from pipeline.errors import HazardWarning, InputError
from pipeline.units import G

EPS = np.finfo(float).eps


def _kennedy(T0, a0_g, k, median_g, beta):
    """H(m) exp(k^2 beta^2 / 2) with H(a) = (1/T0) (a / a0)^-k, at 40 digits (mpmath) [1/yr]."""
    with mp.workdps(40):
        return float(mp.mpf(1) / T0 * (mp.mpf(median_g) / mp.mpf(a0_g)) ** -k * mp.exp(mp.mpf(k * beta) ** 2 / 2))


def _round_off(n_pieces, T0, a0_g, k, median_g, beta):
    """What the closed form's round-off may reach, relative: per piece, the exp of a sum of logs y (ln H0,
    k ln(m/a0), k^2 beta^2 / 2) loses an ulp of |y|, so |y| eps; 2 eps per piece covers the other operations
    (measured over T0 1-1e5 yr, a0 0.05-0.5 g, k 0.5-10, m 0.02-5 g, beta 1e-4-1: at most 1.05 eps (1 + |y|))."""
    return 2 * n_pieces * EPS * (1 + math.log(T0) + k * abs(math.log(median_g / a0_g)) + (k * beta) ** 2 / 2)


def _central(curve, median_g, beta):
    levels, rates = R.usable_curve(curve, 0)
    return float(R.risk_integral(levels, rates, median_g * G, beta, curve.tails).central)


def _quadrature(curve, median_g, beta):
    """mpmath's quadrature of P(DS | a) k H(a) d ln a over the curve's pieces (breakpoints at its levels)."""
    levels, rates = R.usable_curve(curve, 0)
    x = [mp.log(mp.mpf(v)) for v in levels]
    ln_h = [mp.log(mp.mpf(v)) for v in rates]
    k = [curve.slope_below] + [(ln_h[i] - ln_h[i + 1]) / (x[i + 1] - x[i]) for i in range(len(x) - 1)]
    k += [curve.slope_beyond]
    mu = mp.log(mp.mpf(median_g * G))

    def piece(i):
        at = max(i - 1, 0)
        return lambda u: mp.ncdf((u - mu) / beta) * k[i] * mp.exp(ln_h[at] - k[i] * (u - x[at]))

    edges = [-mp.inf] + x + [mp.inf]
    with mp.workdps(30):
        return float(sum(mp.quad(piece(i), [edges[i], edges[i + 1]]) for i in range(len(edges) - 1)))


# -- the closed form ------------------------------------------------------------------------------

@pytest.mark.parametrize("T0, a0_g, k, median_g, beta", list(itertools.product(
    [475, 2475], [0.16, 0.24], [2.0, 3.0, 4.0], [0.1, 0.5, 1.5], [0.2, 0.5])) + [(1e5, 0.05, 10.0, 2.0, 1.0),
                                                                                  (1.0, 0.5, 0.5, 0.02, 0.05)])
def test_one_value_is_kennedys_closed_form_to_round_off(T0, a0_g, k, median_g, beta):
    """One code value and a slope: H = (1/T0) (a/a0)^-k at every level, so lambda is Kennedy's closed form;
    the integral's two pieces (below and beyond the value) sum to it within their round-off."""
    curve = R.code_hazard_curve([(T0, a0_g)], slope=k)
    assert curve.tails == (k, k) and curve.rate[0, 0] == 1.0 / T0 and curve.levels[0] == a0_g * G
    exact = _kennedy(T0, a0_g, k, median_g, beta)
    assert _central(curve, median_g, beta) == pytest.approx(exact, rel=_round_off(2, T0, a0_g, k, median_g, beta),
                                                            abs=0)


def test_one_value_takes_eurocode_8s_slope_3_unless_given():
    curve = R.code_hazard_curve("475:0.16")
    assert curve.tails == (R.DEFAULT_SLOPE, R.DEFAULT_SLOPE) == (3.0, 3.0)
    assert "slope 3 (the default: Eurocode 8's k is about 3)" in curve.description
    assert curve.extrapolated == "at every PGA but 0.16 g (return period 475 years): the power law of slope 3"
    assert _central(curve, 0.5, 0.4) == pytest.approx(_kennedy(475, 0.16, 3.0, 0.5, 0.4),
                                                      rel=_round_off(2, 475, 0.16, 3.0, 0.5, 0.4), abs=0)
    assert "slope 2.5 (given)" in R.code_hazard_curve("475:0.16", slope=2.5).description


@pytest.mark.parametrize("text, T1, a1, T2, a2", [("475:0.16,2475:0.30", 475, 0.16, 2475, 0.30),
                                                   ("2475:0.36,475:0.24", 475, 0.24, 2475, 0.36)])
@pytest.mark.parametrize("median_g, beta", [(0.2, 0.3), (0.6, 0.5), (1.5, 0.4)])
def test_two_values_are_one_power_law_of_their_own_slope(text, T1, a1, T2, a2, median_g, beta):
    """H = 1/T at each value, so ln H1 - ln H2 = ln(T2/T1) and the slope between them is
    k = ln(T2/T1) / ln(a2/a1); extended beyond both by that slope the curve is one power law, and the risk is
    Kennedy's closed form with H through the values (three pieces of round-off), wherever the median lies."""
    curve = R.code_hazard_curve(text)
    k = math.log(T2 / T1) / math.log(a2 / a1)
    assert curve.tails[0] == curve.tails[1] == pytest.approx(k, rel=4 * EPS)
    np.testing.assert_array_equal(curve.rate[0], [1 / T1, 1 / T2])  # sorted by return period, rate exactly 1/T
    exact = _kennedy(T1, a1, k, median_g, beta)
    assert _central(curve, median_g, beta) == pytest.approx(exact, rel=_round_off(3, T1, a1, k, median_g, beta), abs=0)
    assert "the power law through them (slope" in curve.description


def test_three_values_are_integrated_piece_by_piece():
    """Slopes 2.25 and 2.63 between 100, 475 and 2,475 years: the closed forms per piece against mpmath's
    quadrature (30 digits) to 1e-12, far above the round-off (~1e-14) and far below any choice of the user's."""
    curve = R.code_hazard_curve("100:0.08,475:0.16,2475:0.30")
    ks = [math.log(475 / 100) / math.log(2), math.log(2475 / 475) / math.log(0.30 / 0.16)]
    assert curve.tails == pytest.approx((ks[0], ks[1]), rel=4 * EPS)
    assert curve.extrapolated == ("below 0.08 g and beyond 0.3 g (return periods under 100 or over 2475 years): "
                                  "power laws of the end segments' slopes, 2.25 below and 2.63 beyond")
    for median_g, beta in [(0.05, 0.3), (0.12, 0.5), (0.7, 0.4)]:
        assert _central(curve, median_g, beta) == pytest.approx(_quadrature(curve, median_g, beta), rel=1e-12)


def test_a_slope_given_extends_two_values_on_both_sides():
    """--hazard-slope with two values: between them their own power law, below and beyond the slope given."""
    curve = R.code_hazard_curve("475:0.16,2475:0.30", slope=4.0)
    assert curve.tails == (4.0, 4.0)
    a = np.array([0.05, 0.16, 0.2, 0.30, 1.0]) * G
    h = R.hazard_rate_at(curve, 0, a)
    k = math.log(2475 / 475) / math.log(0.30 / 0.16)
    expected = [(1 / 475) * (0.05 / 0.16) ** -4, 1 / 475, (1 / 475) * (0.2 / 0.16) ** -k, 1 / 2475,
                (1 / 2475) * (1.0 / 0.30) ** -4]
    np.testing.assert_allclose(h, expected, rtol=1e-14)
    assert "extended with the slope given, 4" in curve.description
    for median_g, beta in [(0.1, 0.4), (0.9, 0.5)]:
        assert _central(curve, median_g, beta) == pytest.approx(_quadrature(curve, median_g, beta), rel=1e-12)


# -- refusals -------------------------------------------------------------------------------------

@pytest.mark.parametrize("points, slope, words", [
    ("475", None, "'475' is not a return period and a PGA; give T:a pairs, e.g. 475:0.16"),
    ("475:0.16:3", None, "'475:0.16:3' is not a return period and a PGA"),
    ("475:abc", None, "'475:abc' is not a return period and a PGA"),
    ("", None, "no return period and PGA given; give T:a pairs"),
    ("475:0.16,", None, "'' is not a return period and a PGA"),
    ("-475:0.16", None, "-475:0.16: the return period -475 is not a positive number of years"),
    ("inf:0.16", None, "inf:0.16: the return period inf is not a positive number of years"),
    ("475:0", None, "475:0: the PGA 0 is not a positive number of g"),
    ("475:nan", None, "475:nan: the PGA nan is not a positive number of g"),
    ("475:160", None, "475:160: a level of 160 g is beyond any ground motion (the strongest recorded: PGA 4.36 g"),
    ("0.16:475", None, "0.16:475: a level of 475 g is beyond any ground motion"),
    ("475:0.16,475:0.24", None, "the return period 475 years is given twice (475:0.16, 475:0.24); give each once"),
    ("475:0.24,2475:0.16", None, "the PGA at 2475 years (0.16 g) is not above that at 475 years (0.24 g); shaking "
                                 "exceeded less often is stronger"),
    ("475:0.16,2475:0.16", None, "the PGA at 2475 years (0.16 g) is not above that at 475 years (0.16 g)"),
    ("475:0.16,2475:0.17", None, "the slope between 475:0.16 and 2475:0.17 is 27.2; slopes of a hazard curve's power "
                                 "law lie between 0.5 and 10"),
    ("475:0.01,2475:0.5", None, "the slope between 475:0.01 and 2475:0.5 is 0.422"),
    ("475:0.16", 0.3, "the slope given is 0.3; slopes of a hazard curve's power law lie between 0.5 and 10 (Eurocode "
                      "8's k is about 3, 2 to 4 across Europe; at 0.5 a 2,475-year PGA would be 27 times the 475-year "
                      "one, at 10 only 18 % above it): give one inside, e.g. 3"),
    ("475:0.16", 12.0, "the slope given is 12"),
    ("475:0.16", math.inf, "the slope given is inf"),
])
def test_bad_code_values_are_refused_by_value(points, slope, words):
    with pytest.raises(InputError) as info:
        R.code_hazard_curve(points, slope=slope, where="--hazard-pga: ")
    message = str(info.value)
    assert message.startswith("--hazard-pga: ") and words in message, message


def test_the_slope_range_says_what_its_ends_mean():
    """The reason given for 0.5-10: a 2,475-year PGA 5.21^(1/k) times the 475-year one."""
    assert R.SLOPE_RANGE == (0.5, 10.0)
    assert (2475 / 475) ** (1 / 0.5) == pytest.approx(27, rel=0.01)
    assert (2475 / 475) ** (1 / 10) == pytest.approx(1.18, rel=0.01)


@pytest.fixture(scope="module")
def frag():
    ds, _ = make_results(columns=("paper",), n_records=8, angles=(0.0,), scales=(0.25, 0.5, 1.0, 1.5, 2.0),
                         models=("3d",), true_median={("paper", "3d"): 0.6 * G}, true_beta={("paper", "3d"): 0.4})
    return F.fragility(ds, bootstrap=20, seed=3)


def test_a_fragility_not_against_pga_is_refused(frag):
    sa = frag.assign_attrs(intensity_measure="sa", intensity_measure_period=1.0)
    with pytest.raises(InputError) as info:
        R.site_risk(sa, R.code_hazard_curve("475:0.16"))
    message = str(info.value)
    assert message.startswith("code values 475:0.16: the hazard curve is for PGA but the fragility")
    assert "is against Sa(T = 1 s)" in message and "'frustum fragility --im pga'" in message
    with pytest.raises(InputError, match="code values are accelerations in g"):
        R.code_hazard_curve("475:0.16", im="PGV")


# -- the dataset, its files and its figure --------------------------------------------------------

def test_the_dataset_says_where_the_curve_is_extrapolated(frag, tmp_path):
    """The risk of code values: the attributes name the values, slopes and where the curve is extrapolated;
    the netCDF keeps them; the central value is Kennedy's closed form through the fragility's fit."""
    f = fixed_fragility(frag, 0.5, 0.4)
    curve = R.code_hazard_curve("475:0.16")
    with pytest.warns(HazardWarning, match=r"code values 475:0.16: the largest PGA given is 0.16 g, below the "
                                           r"fragility median of paper 3d overturning \(median 0.5 g\).*power law "
                                           r"extrapolated beyond it \(slope 3\)"):
        risk = R.site_risk(f, curve, years=50)
    cell = risk.sel(site="site-0", column="paper", model="3d", state="overturning")
    lam = float(cell["annual_frequency"])
    assert lam == pytest.approx(_kennedy(475, 0.16, 3.0, 0.5, 0.4), rel=_round_off(2, 475, 0.16, 3.0, 0.5, 0.4),
                                abs=0)
    assert R.RISK_FLAGS[int(cell["risk_flag"])] == "median_beyond_hazard_curve"
    assert float(cell["share_below_first_level"]) + float(cell["share_beyond_last_level"]) == pytest.approx(1, rel=1e-12)
    path = R.write(risk, tmp_path / "risk.nc")
    with xr.open_dataset(path) as back:
        attrs = back.attrs
        assert attrs["hazard_format"] == "code" and attrs["hazard_code_values"] == "475:0.16"
        assert attrs["hazard_slope_below"] == attrs["hazard_slope_beyond"] == 3.0
        assert attrs["hazard_extrapolated"] == curve.extrapolated
        assert attrs["hazard_source"] == curve.description and "hazard_file" not in attrs
        assert "extrapolated at every PGA but 0.16 g" in attrs["limits"]
        assert back["hazard_rate"].attrs["comment"] == "1 / return period of the code values"
        assert float(back["years"]) == 50.0 and back["years"].dims == ()  # one period: as before


def test_several_periods_in_one_dataset_and_csv(frag, tmp_path):
    """years = [50, 2100]: probability_in_period over a dimension years, 1 - exp(-lambda T) for each, and the
    chance of standing 2,100 years exp(-2100 lambda) its complement; a CSV column per period."""
    f = fixed_fragility(frag, 0.5, 0.4)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", HazardWarning)  # the median beyond 0.3 g, tested above
        risk = R.site_risk(f, R.code_hazard_curve("475:0.16,2475:0.30"), years=[50, 2100])
    assert risk["years"].dims == ("years",) and R.periods(risk) == [50.0, 2100.0]
    cell = risk.sel(site="site-0", column="paper", model="3d", state="overturning")
    lam = float(cell["annual_frequency"])
    for T in (50.0, 2100.0):
        assert R.in_period(cell, "probability_in_period", T) == pytest.approx(-math.expm1(-T * lam), rel=1e-14)
    assert 1 - R.in_period(cell, "probability_in_period", 2100.0) == pytest.approx(math.exp(-2100 * lam), rel=1e-12)
    rows = R.risk_rows(risk)
    row = next(r for r in rows if r["state"] == "overturning")
    assert row["probability_in_50_yr"] == R.in_period(cell, "probability_in_period", 50.0)
    assert row["probability_in_2100_yr_upper"] == R.in_period(cell, "probability_in_period_upper", 2100.0)
    assert row["hazard_code_values"] == "475:0.16,2475:0.3"
    assert row["hazard_extrapolated"].startswith("below 0.16 g and beyond 0.3 g (return periods under 475 or over "
                                                 "2475 years)")
    assert row["share_below_first_level"] == float(cell["share_below_first_level"])
    with open(R.write_csv(risk, tmp_path / "risk.csv"), encoding="utf-8") as fh:
        assert "probability_in_2100_yr_band_upper" in fh.readline()
    for bad, words in (([50, 50], "give one or more periods, each once"), ([50, -1], "years = -1.0: give a positive"),
                       ([], "give one or more periods")):
        with pytest.raises(InputError, match=words):
            R.site_risk(f, R.code_hazard_curve("475:0.16"), years=bad)


@pytest.mark.parametrize("points, words", [
    ("475:0.16", ["extrapolated: power law, slope 3", "code values (T:PGA 475:0.16)"]),  # no curve between values
    ("475:0.16,2475:0.30", ["power law between the values", "extrapolated: power law, slope 2.63",
                            "code values (T:PGA 475:0.16,2475:0.3)"]),
])
def test_the_figure_says_where_the_curve_is_extrapolated(frag, points, words):
    from pipeline.plotting_risk import figure, plt

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", HazardWarning)
        risk = R.site_risk(fixed_fragility(frag, 0.5, 0.4), R.code_hazard_curve(points), years=[50, 2100])
    fig = figure(risk)
    try:
        hazard_panel, _, integrand_panel = fig.axes[:3]
        legend = [t.get_text() for t in hazard_panel.get_legend().get_texts()]
        assert legend == words
        texts = [t.get_text() for t in integrand_panel.texts]
        assert " largest value given" in texts
        lines = [t.get_text() for t in integrand_panel.get_legend().get_texts()]
        assert lines[0].startswith("3D: λ = ") and ", 2100 yr: " in lines[0]
        assert lines[0].endswith(" - median beyond the values given")
    finally:
        plt.close(fig)
