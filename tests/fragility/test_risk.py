"""Site risk (issue 27): the risk integral, the hazard curve readers and the risk dataset.

Independent checks: Kennedy's closed form lambda = H(median) exp(k^2 beta^2 / 2) for a power-law
hazard (Kennedy & Short 1994; Cornell et al. 2002, Eq. 11), brute-force quadrature on a curved
hazard curve, the OpenQuake engine's own file layout written out byte for byte, and the bounds
for the part beyond the curve's last level bracketing the truth.
"""

import math
import warnings

import numpy as np
import pytest
import xarray as xr
from fragility_synthetic import make_results
from hazard_files import (EXAMPLE_LEVELS_G, example_openquake_text, fixed_fragility, openquake_text, plain_text,
                          power_law_text, quadratic_curve)
from scipy.special import log_ndtr, ndtr

from pipeline import fragility as F
from pipeline import risk as R
from pipeline.errors import HazardWarning, InputError
from pipeline.units import G


def _write(tmp_path, name, text):
    path = tmp_path / name
    path.write_bytes(text.encode("utf-8"))
    return path


def _kennedy(k0, k, median, beta):
    return k0 * median ** -k * math.exp(0.5 * (k * beta) ** 2)


# -- the integral ---------------------------------------------------------------------------------

@pytest.mark.parametrize("k0, k, median_g, beta", [
    (1e-4, 2.0, 0.3, 0.3), (1e-4, 3.5, 0.6, 0.6), (2e-3, 1.5, 0.1, 0.8), (1e-5, 6.0, 1.0, 0.5), (5e-4, 3.0, 0.45, 0.2),
])
def test_kennedy_closed_form_for_a_power_law_hazard(tmp_path, k0, k, median_g, beta):
    """A power law H = k0 a^-k (a in m/s^2) read from a plain CSV in g, 40 levels from 1e-3 x median to 20 g.

    Tolerance 0.5 % (the issue's): the closed form per segment is exact for a power law, so what is
    left is the g <-> m/s^2 round trip of the levels written with repr (17 digits), ~1e-15.
    """
    median = median_g * G
    curve = R.read_hazard_curve(_write(tmp_path, "h.csv", power_law_text(k0, k, median)))
    levels, rates = R.usable_curve(curve, 0)
    parts = R.risk_integral(levels, rates, median, beta)
    exact = _kennedy(k0, k, median, beta)
    assert float(parts.central) == pytest.approx(exact, rel=5e-3)
    assert float(parts.lower) <= exact * (1 + 1e-12) and float(parts.upper) >= exact * (1 - 1e-12)


@pytest.mark.parametrize("k, beta", [(2.0, 0.4), (4.0, 0.6)])
def test_bounds_bracket_the_truth_when_the_curve_stops_before_the_median(k, beta):
    """A power law cut at 0.6 median: the lower and upper bounds hold Kennedy's value, the central recovers it."""
    k0, median = 1e-4, 8.0
    a = np.geomspace(0.05, 0.6 * median, 15)
    parts = R.risk_integral(a, k0 * a ** -k, median, beta)
    exact = _kennedy(k0, k, median, beta)
    assert float(parts.lower) < exact < float(parts.upper)
    assert float(parts.central) == pytest.approx(exact, rel=1e-9)  # the last segment is the same power law
    # the part beyond the cut against a trapezoid of P k H over ln a, to where H has fallen by e^-40
    x = np.linspace(math.log(a[-1]), math.log(a[-1]) + 40.0 / k, 400_001)
    brute = np.trapezoid(ndtr((x - math.log(median)) / beta) * k * k0 * np.exp(-k * x), x)
    assert float(parts.beyond) == pytest.approx(brute, rel=1e-6)
    assert float(parts.beyond) > 0.05 * exact


def test_closed_form_matches_quadrature_on_a_curved_hazard_curve():
    """ln H quadratic in ln a (slopes 1.3 to 5.5), log-log interpolated: the segment sums equal a
    400 001-point trapezoid of P |dH/d ln a| over the same interpolated curve to 1e-6 (the trapezoid's
    error at this step is ~1e-9 relative; the derivative is evaluated per segment, exactly)."""
    levels_g = EXAMPLE_LEVELS_G[2:]
    rates = quadratic_curve(levels_g, [(0.01, 0.2), (0.25, 1 / 475), (0.5, 1 / 2475)])
    a = levels_g * G
    for median, beta in [(5.0, 0.5), (2.0, 0.3), (12.0, 0.7)]:
        parts = R.risk_integral(a, rates, median, beta)
        x = np.linspace(np.log(a[0]), np.log(a[-1]), 400_001)
        seg = np.clip(np.searchsorted(np.log(a), x, side="right") - 1, 0, a.size - 2)
        k = -np.diff(np.log(rates)) / np.diff(np.log(a))
        h = rates[seg] * np.exp(-k[seg] * (x - np.log(a[seg])))
        brute = np.trapezoid(ndtr((x - math.log(median)) / beta) * k[seg] * h, x)
        assert float(parts.inside) == pytest.approx(brute, rel=1e-6)


def test_steep_segments_do_not_overflow():
    """k beta = 60: exp(k^2 beta^2 / 2) alone would overflow; the log-space form matches quadrature."""
    value = float(R.segment_integral(0.0, math.log(2.0), 0.0, 0.0, 80.0, 1.5, 0.75))
    x = np.linspace(0.0, math.log(2.0), 400_001)
    brute = np.trapezoid(ndtr((x - math.log(1.5)) / 0.75) * 80.0 * np.exp(-80.0 * x), x)
    assert np.isfinite(value) and value == pytest.approx(brute, rel=1e-6)


def test_degenerate_fragilities():
    """A step (beta 0) gives H(median); never reached gives 0; NaN stays NaN."""
    a = np.geomspace(0.1, 20.0, 12)
    rates = 1e-3 * a ** -2.5
    parts = R.risk_integral(a, rates, np.array([4.0, np.inf, np.nan]), np.array([0.0, np.nan, 0.4]))
    assert parts.central[0] == pytest.approx(1e-3 * 4.0 ** -2.5, rel=1e-12)
    assert parts.central[1] == 0.0 and np.isnan(parts.central[2])


# -- hazard curves --------------------------------------------------------------------------------

#: Two sites as the OpenQuake engine exports them (the manual's "Outputs from Classical PSHA" listing:
#: comment row with one field per column, %.7f IMLs, %.5f coordinates, %.6E PoE, CRLF line ends).
OQ_TWO_SITES = (
    b'#,,,,,"generated_by=\'OpenQuake engine 3.18.0\', start_date=\'2023-10-03T06:09:08\', checksum=2107362341, '
    b'kind=\'mean\', investigation_time=50.0, imt=\'PGA\'"\r\n'
    b"lon,lat,depth,poe-0.1000000,poe-0.4000000,poe-0.6000000\r\n"
    b"23.72700,37.97200,-0.10000,4.553860E-01,5.754042E-02,6.354511E-03\r\n"
    b"22.88000,37.90500,-0.10000,1.522632E-01,3.037810E-03,0.000000E+00\r\n"
)


def test_openquake_csv_two_sites_read_into_sites_and_levels(tmp_path):
    path = tmp_path / "hazard_curve-mean-PGA_42.csv"
    path.write_bytes(OQ_TWO_SITES)
    curve = R.read_hazard_curve(path)
    assert curve.format == "openquake" and curve.im == "pga" and curve.period is None and curve.kind == "mean"
    assert curve.investigation_time == 50.0 and curve.file_units == "g"
    assert curve.sites == ("site-0", "site-1")
    np.testing.assert_allclose(curve.levels, np.array([0.1, 0.4, 0.6]) * G, rtol=1e-15)
    np.testing.assert_array_equal(curve.lon, [23.727, 22.88])
    np.testing.assert_array_equal(curve.lat, [37.972, 37.905])
    np.testing.assert_array_equal(curve.poe[1], [1.522632e-01, 3.037810e-03, 0.0])
    np.testing.assert_allclose(curve.rate[0], -np.log1p(-np.array([4.553860E-01, 5.754042E-02, 6.354511E-03])) / 50)
    assert curve.rate[1, 2] == 0.0  # PoE 0: the level is left out of the integral
    levels, rates = R.usable_curve(curve, 1)
    assert levels.size == 2 and rates[-1] == pytest.approx(-math.log1p(-3.037810e-03) / 50)


def test_openquake_variants_older_comment_custom_site_ids_and_sa(tmp_path):
    old = tmp_path / "hazard_curve-PGA.csv"  # the engine's QA file of classical/case_1, older layout
    old.write_text("# source_model_tree_path=('b1',), gsim_tree_path=('b1',), investigation_time=1.0,imt=\"PGA\"\n"
                   "lon,lat,depth,poe-0.1,poe-0.4,poe-0.6\n0.00000,0.00000,-0.10000,4.528811E-01,5.589804E-02,"
                   "5.585141E-03\n")
    curve = R.read_hazard_curve(old)
    assert curve.investigation_time == 1.0 and curve.im == "pga" and curve.rate[0, 0] == pytest.approx(
        -math.log(1 - 0.4528811))
    sa = tmp_path / "hazard_curve-mean-SA(1.0)_7.csv"
    text = openquake_text([0.05, 0.2, 0.8], [[0.3, 0.05, 0.002]], [(1.0, 2.0)], imt="SA(1.0)")
    sa.write_text(text.replace("lon,lat", "custom_site_id,lon,lat").replace("1.00000,2.00000", "temple,1.00000,2.00000")
                  .replace("#,", "#,,", 1), newline="")
    curve = R.read_hazard_curve(sa)
    assert curve.im == "sa" and curve.period == 1.0 and curve.sites == ("temple",)


def test_example_file_is_the_engines_layout_byte_for_byte():
    """The committed example (tests/data/hazard) is what hazard_files.example_openquake_text writes."""
    from pathlib import Path

    path = Path(__file__).parents[1] / "data" / "hazard" / "hazard_curve-mean-PGA_1.csv"
    data = path.read_bytes()
    assert data == example_openquake_text().encode()
    lines = data.split(b"\r\n")
    assert lines[0].startswith(b"#" + b"," * (3 + EXAMPLE_LEVELS_G.size - 1) + b'"generated_by=')
    assert lines[1].startswith(b"lon,lat,depth,poe-0.0050000,poe-0.0100000,")
    assert R.read_hazard_curve(path).sites == ("site-0", "site-1")


def test_poe_in_50_years_equals_annual_rates(tmp_path):
    """The same curve as PoE in 50 years (OpenQuake and plain) and as annual rates gives the same rates and risk.

    Tolerance: the engine's %.6E PoE carries 7 digits; away from PoE ~ 1 the rate keeps them (1e-6).
    """
    rates = quadratic_curve(EXAMPLE_LEVELS_G, [(0.01, 0.2), (0.25, 1 / 475), (0.5, 1 / 2475)])
    poe = -np.expm1(-50.0 * rates)
    as_rates = R.read_hazard_curve(_write(tmp_path, "r.csv", plain_text(EXAMPLE_LEVELS_G, rates)))
    as_poe = R.read_hazard_curve(_write(tmp_path, "p.csv", plain_text(EXAMPLE_LEVELS_G, poe, "PGA [g],poe in 50 years")))
    as_oq = R.read_hazard_curve(_write(tmp_path, "hazard_curve-mean-PGA_1.csv",
                                       openquake_text(EXAMPLE_LEVELS_G, [poe], [(0.0, 0.0)])))
    np.testing.assert_allclose(as_poe.rate, as_rates.rate, rtol=1e-12)
    ok = poe < 0.99
    np.testing.assert_allclose(as_oq.rate[0, ok], as_rates.rate[0, ok], rtol=1e-6)
    for median in (3.0, 6.0, 12.0):
        lam = [float(R.risk_integral(*R.usable_curve(c, 0), median, 0.5).central) for c in (as_rates, as_poe, as_oq)]
        assert lam[1] == pytest.approx(lam[0], rel=1e-12) and lam[2] == pytest.approx(lam[0], rel=1e-5)


@pytest.mark.parametrize("text, words", [
    ("PGA,annual_rate\n0.1,1e-2\n0.2,1e-3\n", "name the intensity measure and its unit"),
    ("PGA [furlongs],rate\n0.1,1e-2\n0.2,1e-3\n", "unit 'furlongs' unknown"),
    ("PGA [g],poe\n0.1,0.1\n0.2,0.01\n", "needs its time"),
    ("PGA [g],rate\n0.2,1e-2\n0.1,1e-3\n", "positive and increasing"),
    ("PGA [g],rate\n0.1,1e-3\n0.2,1e-2\n", "never rises"),
    ("PGA [g],rate\n0.1,1e-3\n", "at least two levels"),
    ("AvgSA [g],rate\n0.1,1e-2\n0.2,1e-3\n", "name the intensity measure"),
    # issue 38, item 2: what is wrong, by name
    ("PGA [g];annual_rate [1/yr]\n0,1;1e-2\n0,2;1e-3\n", "the fields are separated by ';'"),
    ("PGA [g]\tannual_rate [1/yr]\n0.1\t1e-2\n0.2\t1e-3\n", "the fields are separated by tabs"),
    ("PGA [g],annual_rate [1/yr],\n0.1,1e-2,\n0.2,1e-3,\n",
     "the header ends in an empty column (a trailing comma after 'annual_rate [1/yr]')"),
    ("PGA [g],annual_rate [1/yr]\n0.1,1e-2\n0.2,1e-3,\n", "line 3 ends in 1 empty field(s) beyond the 2 of the header"),
    ("PGA [g],annual_rate [1/yr]\n0.1,1e-2\n500,1e-3\n", "line 3: a level of 500 g is beyond any ground motion"),
    ("PGA [cm/s2],annual_rate [1/yr]\n100,1e-2\n50000,1e-3\n", "line 3: a level of 50000 cm/s2 is beyond"),
    ("PGV [cm/s],annual_rate [1/yr]\n10,1e-2\n5000,1e-3\n",
     "line 3: a level of 5000 cm/s is beyond any ground motion (the strongest recorded: PGV 3.18 m/s; levels up to "
     "3000 cm/s are accepted)"),
])
def test_bad_plain_curves_are_refused_by_name(tmp_path, text, words):
    path = _write(tmp_path, "bad.csv", text)
    with pytest.raises(InputError, match="bad.csv") as info:
        curve = R.read_hazard_curve(path)
        R.usable_curve(curve, 0)
    assert words in str(info.value)


# -- against a fragility --------------------------------------------------------------------------

@pytest.fixture(scope="module")
def frag():
    ds, _ = make_results(columns=("paper",), n_records=8, angles=(0.0,), scales=(0.25, 0.5, 1.0, 1.5, 2.0),
                         models=("3d", "2d"), true_median={("paper", "3d"): 0.6 * G, ("paper", "2d"): 0.9 * G},
                         true_beta={("paper", "3d"): 0.4, ("paper", "2d"): 0.5})
    return F.fragility(ds, bootstrap=40, seed=3)


def test_mismatched_intensity_measure_is_refused(tmp_path, frag):
    sa = R.read_hazard_curve(_write(tmp_path, "hazard_curve-mean-SA(1.0)_3.csv",
                                    openquake_text([0.05, 0.2, 0.8], [[0.3, 0.05, 0.002]], [(1, 2)], imt="SA(1.0)")))
    with pytest.raises(InputError) as info:
        R.site_risk(frag, sa)
    message = str(info.value)
    assert "is for Sa(T = 1 s)" in message and "against PGA" in message and "--im sa" in message
    sa_frag = frag.assign_attrs(intensity_measure="sa", intensity_measure_period=0.3)
    with pytest.raises(InputError, match=r"Sa\(T = 1 s\).*against Sa\(T = 0.3 s\)"):
        R.site_risk(sa_frag, sa)
    with warnings.catch_warnings():  # this short curve ends below the 2D median: warned elsewhere
        warnings.simplefilter("ignore", HazardWarning)
        R.site_risk(frag.assign_attrs(intensity_measure="sa", intensity_measure_period=1.0), sa)  # same T: accepted


def test_sa_period_read_from_an_older_fragility_files_long_name(frag):
    old = frag.assign_attrs(intensity_measure="sa")
    old["median"].attrs["long_name"] = "median spectral acceleration (period 0.5 s) of the lognormal fragility curve"
    assert R.fragility_im(old)[:2] == ("sa", 0.5)


def test_site_risk_dataset(tmp_path, frag):
    curve = R.read_hazard_curve(_write(tmp_path, "hazard_curve-mean-PGA_1.csv", example_openquake_text()))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the example curve reaches both medians: no warning
        risk = R.site_risk(frag, curve, years=50)
    assert risk["annual_frequency"].dims == ("site", "state", "column", "model")
    path = R.write(risk, tmp_path / "risk.nc")
    with xr.open_dataset(path) as back:  # plain xarray selects by label
        cell = back.sel(site="site-1", column="paper", model="3d", state="overturning")
        lam = float(cell["annual_frequency"])
        assert back["annual_frequency"].attrs["units"] == "year-1"
        assert back["intensity_risk_50"].attrs["units"] == "m s-2"
        for name, var in back.data_vars.items():
            assert "long_name" in var.attrs, name
    levels, rates = R.usable_curve(curve, 1)
    one = frag.sel(column="paper", model="3d", state="overturning")
    assert lam == pytest.approx(float(R.risk_integral(levels, rates, float(one["median"]), float(one["beta"])).central))
    c = risk.sel(site="site-1", column="paper", model="3d", state="overturning")
    assert float(c["probability_in_period"]) == pytest.approx(1 - math.exp(-50 * lam), rel=1e-12)
    assert float(c["return_period"]) == pytest.approx(1 / lam)
    assert float(c["annual_frequency_lower"]) <= lam <= float(c["annual_frequency_upper"])
    assert float(c["annual_frequency_band_lower"]) < lam < float(c["annual_frequency_band_upper"])
    assert int(c["risk_flag"]) == R.RISK_OK
    # the integrand's area over ln a is the frequency (grid of 301 points: trapezoid within 1 %)
    dens = c["risk_integrand"].values
    area = np.trapezoid(dens, np.log(risk["intensity"].values))
    assert area == pytest.approx(lam, rel=1e-2)
    a05, a50, a95 = (float(c[f"intensity_risk_{p}"]) for p in ("05", "50", "95"))
    assert a05 < a50 < a95
    # the higher-hazard site carries the higher risk
    assert float(risk["annual_frequency"].sel(site="site-0", column="paper", model="3d", state="overturning")) > lam


def test_no_overturning_is_flagged_not_crashed(tmp_path):
    """Medians far beyond the data (no run overturned): NaN risk with its flag, the other states computed."""
    ds, _ = make_results(columns=("paper",), n_records=6, angles=(0.0,), scales=(0.25, 0.5, 1.0), models=("3d",),
                         true_median={("paper", "3d"): 40 * G}, true_beta={("paper", "3d"): 0.3})
    frag = F.fragility(ds, states=(0.01,), bootstrap=10)
    assert int(frag["fit_status"].sel(state="overturning", column="paper", model="3d")) == F.FIT_NO_EXCEEDANCE
    curve = R.read_hazard_curve(_write(tmp_path, "hazard_curve-mean-PGA_1.csv", example_openquake_text()))
    risk = R.site_risk(frag, curve)
    cell = risk.sel(site="site-0", column="paper", model="3d", state="overturning")
    assert np.isnan(float(cell["annual_frequency"])) and np.isnan(float(cell["annual_frequency_band_upper"]))
    assert np.isnan(float(cell["return_period"]))  # not "never": unknown (issue 38)
    assert R.no_risk_reason(risk, "site-0", "paper", "3d", "overturning") == (
        "no run reached overturning, so the fragility has no median to integrate")
    assert R.RISK_FLAGS[int(cell["risk_flag"])] == "no_median_no_exceedance_observed"
    assert R.write(risk, tmp_path / "risk.nc")
    assert R.write_csv(risk, tmp_path / "risk.csv")


def test_median_beyond_the_curve_warns_and_flags(tmp_path, frag):
    short = openquake_text([0.01, 0.05, 0.1, 0.2, 0.3], [[0.9, 0.3, 0.1, 0.02, 0.006]], [(0, 0)])
    curve = R.read_hazard_curve(_write(tmp_path, "hazard_curve-mean-PGA_2.csv", short))
    with pytest.warns(HazardWarning, match=r"ends at 0.3 g, below the fragility median of paper 3d overturning"):
        risk = R.site_risk(frag, curve)
    cell = risk.sel(site="site-0", column="paper", model="3d", state="overturning")
    assert R.RISK_FLAGS[int(cell["risk_flag"])] == "median_beyond_hazard_curve"
    assert float(cell["share_beyond_last_level"]) > 0.5
    assert float(cell["annual_frequency_lower"]) < float(cell["annual_frequency"]) < float(cell["annual_frequency_upper"])


# -- issue 38, item 2: saturated levels, extreme rates, absurd levels and files, the words printed -

def test_saturated_levels_raise_no_warning_and_keep_the_risk(tmp_path, frag):
    """PoE = 1 at the lowest levels, common in real exports: no numpy warning, and the risk that the
    levels below saturation give, which for a power law H = k0 a^-k is Kennedy's closed form.

    Tolerance 1e-4: the engine's %.6E PoE carries 7 digits; at the first unsaturated level (PoE
    0.9972) -ln(1 - PoE) keeps them to 5e-7 / ((1 - PoE) |ln(1 - PoE)|) = 3e-5, felt only through the
    slope of the first segment; near the median the rates keep ~1e-6.
    """
    k0, k, median, beta = 2e-3, 2.5, 0.6 * G, 0.4
    poe = -np.expm1(-50.0 * k0 * (EXAMPLE_LEVELS_G * G) ** -k)
    text = openquake_text(EXAMPLE_LEVELS_G, [poe], [(0.0, 0.0)])
    assert text.count(",1.000000E+00") == 2  # 0.005 g and 0.01 g saturate in the engine's format
    f = fixed_fragility(frag, median / G, beta)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        curve = R.read_hazard_curve(_write(tmp_path, "hazard_curve-mean-PGA_5.csv", text))
        risk = R.site_risk(f, curve)
    assert np.isinf(curve.rate[0, :2]).all() and R.usable_curve(curve, 0)[0].size == EXAMPLE_LEVELS_G.size - 2
    lam = float(risk["annual_frequency"].sel(site="site-0", column="paper", model="3d", state="overturning"))
    assert lam == pytest.approx(_kennedy(k0, k, median, beta), rel=1e-4)
    # the same as the file without its saturated columns (same levels and rates, same sums)
    cut = R.read_hazard_curve(_write(tmp_path, "hazard_curve-mean-PGA_6.csv",
                                     openquake_text(EXAMPLE_LEVELS_G[2:], [poe[2:]], [(0.0, 0.0)])))
    assert lam == pytest.approx(float(R.risk_integral(*R.usable_curve(cut, 0), median, beta).central), rel=1e-14)


#: Curves that fall 100 (or 150) decades per level: extended below 0.1 g their rates leave the floats.
STEEP = [(1e300, 1e200, 1e100), (1e-100, 1e-200, 1e-300), (1e-3, 1e-150, 1e-300)]


@pytest.mark.parametrize("rates", STEEP)
def test_extreme_rates_say_the_integral_overflows_without_a_numpy_warning(tmp_path, frag, rates):
    """No numpy warning (integral, files, figure); risk_flag integral_overflows with the central value NaN,
    not "median beyond the curve"; the lower bound (the curve's own levels) still a number.

    The lower bound against a 400 001-point trapezoid of P |dH/d ln a| per segment, in logs, plus
    P(a_L) H(a_L): the steepest segment (k = 500) changes by k dx = 9e-4 per step, a trapezoid error of
    (k dx)^2 / 12 = 7e-8, so 1e-6.
    """
    from pipeline.plotting_risk import plot_risk

    levels_g, median, beta = np.array([0.1, 0.2, 0.5]), 0.6 * G, 0.4
    f = fixed_fragility(frag, median / G, beta)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        warnings.simplefilter("ignore", HazardWarning)  # medians beyond 0.5 g, rightly warned about
        risk = R.site_risk(f, R.read_hazard_curve(_write(tmp_path, "h.csv", plain_text(levels_g, rates))))
        R.write_csv(risk, tmp_path / "risk.csv")
        R.write(risk, tmp_path / "risk.nc")
        plot_risk(risk, tmp_path / "risk.png")
    cell = risk.sel(site="site-0", column="paper", model="3d", state="overturning")
    assert R.RISK_FLAGS[int(cell["risk_flag"])] == "integral_overflows"
    for name in ("annual_frequency", "probability_in_period", "return_period", "share_below_first_level"):
        assert np.isnan(float(cell[name])), name
    assert np.isposinf(float(cell["annual_frequency_upper"]))
    a, ln_h = levels_g * G, np.log(rates)
    lower = ndtr((math.log(a[-1]) - math.log(median)) / beta) * rates[-1]
    for i in range(2):
        x = np.linspace(math.log(a[i]), math.log(a[i + 1]), 400_001)
        k = (ln_h[i] - ln_h[i + 1]) / (x[-1] - x[0])
        ln_d = log_ndtr((x - math.log(median)) / beta) + math.log(k) + ln_h[i] - k * (x - x[0])
        lower += np.trapezoid(np.exp(ln_d - ln_d.max()), x) * math.exp(ln_d.max())
    assert float(cell["annual_frequency_lower"]) == pytest.approx(lower, rel=1e-6)
    reason = R.no_risk_reason(risk, "site-0", "paper", "3d", "overturning")
    assert reason.startswith("the hazard curve's first segment (0.1 to 0.2 g) falls as a^-")
    assert reason.endswith(f"(shaking above 0.1 g alone gives at least {lower:.3g} /yr)")


@pytest.mark.parametrize("edit, message", [
    (lambda t: t.replace(",", ";"),
     "the fields are separated by ';' ('lon;lat;depth;poe-0.0050000;poe-0.010...'); a hazard curve CSV separates "
     "them by commas, with decimal points, as the OpenQuake engine writes it: export the curves again ('oq export "
     "hcurves') or save the file as comma-separated"),
    (lambda t: t.split("\r\n", 1)[1],
     "the first line is the header (lon,lat,...,poe-<IML>); the OpenQuake engine's export starts with a '#' row of "
     "metadata before it (kind='mean', investigation_time=50.0, imt='PGA'), without which the probabilities of "
     "exceedance cannot be turned into annual rates: restore that row from the engine's export ('oq export hcurves')"),
    (lambda t: t.replace("poe-2.0000000\r\n", "poe-2.0000000,\r\n"),
     "the header ends in an empty column (a trailing comma after 'poe-2.0000000'); remove the trailing comma (and "
     "any at the end of the rows)"),
    (lambda t: t.replace("\r\n22.88", ",\r\n22.88"),
     "line 3 ends in 1 empty field(s) beyond the 19 of the header (a trailing comma?); remove the trailing comma"),
    (lambda t: t.replace("poe-2.0000000", "poe-1e300"),
     "column 'poe-1e300': a level of 1e+300 g is beyond any ground motion (the strongest recorded: PGA 4.36 g; levels "
     "up to 30 g are accepted); give each level in g, as the OpenQuake engine writes it (poe-0.5000000 for 0.5 g)"),
    (lambda t: t.replace("poe-2.0000000", "poe-31.0000000"), "column 'poe-31.0000000': a level of 31 g is beyond"),
])
def test_bad_openquake_files_are_refused_saying_what_is_wrong(tmp_path, edit, message):
    """The engine's export edited as a spreadsheet or a hand would: the message names the fault, not
    "needs a header and at least two levels" or "unknown: "; a level no ground motion reaches is refused
    rather than narrowing the curve-end bounds to a false certainty (pipeline.risk.MAX_LEVEL)."""
    path = _write(tmp_path, "hazard_curve-mean-PGA_1.csv", edit(example_openquake_text()))
    with pytest.raises(InputError) as info:
        R.read_hazard_curve(path)
    assert str(info.value).startswith(f"{path}: {message}"), str(info.value)


def test_a_level_of_30_g_is_still_read(tmp_path):
    """The bound is MAX_LEVEL: 30 g, a level of an extreme hazard calculation, is accepted."""
    text = example_openquake_text().replace("poe-2.0000000", "poe-30.0000000")
    assert R.read_hazard_curve(_write(tmp_path, "hazard_curve-mean-PGA_1.csv", text)).levels[-1] == 30.0 * G


@pytest.mark.parametrize("p, text", [
    (0.024, "2.4 %"), (0.00059, "0.059 %"), (0.994, "99 %"), (0.995, "99.5 %"), (0.99689, "99.7 %"),
    (0.9995, "99.95 %"), (0.999949, "99.99 %"), (0.99995, "> 99.99 %"), (1.0, "> 99.99 %"), (5e-7, "< 0.0001 %"),
    (1.5e-6, "0.00015 %"), (0.0, "0 %"), (math.nan, "n/a"),
])
def test_percent_never_rounds_to_a_certainty(p, text):
    """The words of issue 38: '1e+02 %' was printed for 99.5 % and above."""
    assert R.percent(p) == text


@pytest.mark.parametrize("period, text", [
    (1e280, "more than a million years"), (1.5e6, "more than a million years"), (17544.0, "18,000 years"),
    (2134.0, "2,100 years"), (999_999.0, "1,000,000 years"), (12.3, "12 years"), (1.0, "1 year"), (0.5, "0.5 years"),
    (1e-5, "less than 0.001 years"), (math.inf, "never"), (math.nan, "n/a"),
])
def test_years_in_words(period, text):
    """A return period printed with 280 digits before issue 38."""
    assert R.years_words(period) == text


def test_fragility_file_keeps_replicates_and_the_sa_period(frag):
    assert frag["median_bootstrap"].dims == ("bootstrap", "state", "column", "model")
    assert frag.sizes["bootstrap"] == 40
    ds, _ = make_results(columns=("paper",), n_records=6, angles=(0.0,), scales=(0.5, 1.0, 2.0), models=("3d",))
    ds.coords["sa"] = (("record", "scale"), ds["pga"].values * 0.7,
                       {"units": "m s-2", "period": 1.0, "long_name": "spectral acceleration (period 1 s)"})
    sa = F.fragility(ds, im="sa")
    assert sa.attrs["intensity_measure_period"] == 1.0 and R.fragility_im(sa) == ("sa", 1.0, "m s-2")
    assert float(sa["im_simulated_max"].sel(column="paper", model="3d")) == pytest.approx(2 * 0.7 * G)


@pytest.mark.parametrize("p, words", [(0.024, "about 1 in 42"), (0.00356, "about 1 in 280"), (0.63, "about 6 in 10"),
                                      (0.0, "practically no"), (2e-7, "less than 1 in a million"),
                                      (0.15, "about 1 in 7")])
def test_one_in_words(p, words):
    assert R.one_in(p) == words


def test_risk_file_passes_the_cf_checker(tmp_path, frag):
    """As tests/test_netcdf_convention.py checks the other kinds: cfchecks 4.1 on a CF-1.8 copy, no error.

    Accepted warnings: column_R / column_r differ only by case (the project's schema), and CF 4.4's
    note that the UDUNITS 'year' (of `years` and `return_period`) is not a calendar year - these
    are durations, not dates.
    """
    import shutil
    import subprocess
    import sys
    from pathlib import Path

    import netCDF4

    checker = shutil.which("cfchecks", path=str(Path(sys.executable).parent))
    assert checker, "cfchecks is missing: it is in the test extra (pip install -e '.[test]')"
    tables = Path(__file__).parents[1] / "data" / "cf"
    curve = R.read_hazard_curve(_write(tmp_path, "hazard_curve-mean-PGA_1.csv", example_openquake_text()))
    path = R.write(R.site_risk(frag, curve), tmp_path / "risk.nc")
    with netCDF4.Dataset(path, "a") as nc:
        nc.Conventions = "CF-1.8"
    run = subprocess.run([checker, "-v", "1.8", "-s", str(tables / "cf-standard-name-table-subset.xml"),
                          "-a", str(tables / "cf-area-type-table-empty.xml"),
                          "-r", str(tables / "cf-region-names-empty.xml"), str(path)],
                         capture_output=True, text=True, timeout=120)
    out = run.stdout + run.stderr
    assert "ERRORS detected: 0" in out, out
    warned = [line for line in out.splitlines() if line.startswith("WARN:")]
    assert sorted(set(warned)) == ["WARN: (2.3): variable clash",
                                   "WARN: (4.4): The unit 'year', defined by udunits to be exactly 365.242198781 days, "
                                   "should be used with caution. It is not a calendar year."], out
