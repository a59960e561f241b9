"""``frustum risk`` and ``frustum report --hazard`` end to end on small synthetic inputs (issue 27).

Every refusal: exit status 2, one line naming the option or file and the fix, no traceback, the
user's files byte-identical.
"""

import csv
import math
import shutil
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from cli_files import snapshot, unchanged
from hazard_files import example_openquake_text, fixed_fragility, openquake_text, plain_text

from pipeline.cli import main
from pipeline.paths import result_kind


def _err(capsys):
    err = capsys.readouterr().err
    assert "Traceback" not in err
    return err


@pytest.fixture(scope="module")
def inputs(results_nc, tmp_path_factory):
    """(fragility.nc with 20 bootstrap replicates, an OpenQuake PGA curve of two sites, an SA(1.0) curve)."""
    folder = tmp_path_factory.mktemp("risk-inputs")
    frag = folder / "frag.nc"
    assert main(["fragility", str(results_nc), "--out", str(frag), "--bootstrap", "20"]) == 0
    pga = folder / "hazard_curve-mean-PGA_1.csv"
    pga.write_bytes(example_openquake_text().encode())
    sa = folder / "hazard_curve-mean-SA(1.0)_1.csv"
    sa.write_bytes(openquake_text([0.05, 0.2, 0.8], [[0.3, 0.05, 0.002]], [(1.0, 2.0)], imt="SA(1.0)").encode())
    return frag, pga, sa


def test_risk_end_to_end(inputs, tmp_path, capsys):
    frag, pga, _ = inputs
    out, table, fig = tmp_path / "risk.nc", tmp_path / "risk.csv", tmp_path / "risk.png"
    assert main(["risk", str(frag), "--hazard", str(pga), "--years", "50", "--out", str(out), "--csv", str(table),
                 "--plot", str(fig)]) == 0
    text = capsys.readouterr().out
    assert "site-0 paper 3d overturning:" in text and "in 50 yr" in text and "about 1 in" in text
    assert result_kind(out) == "risk"
    with xr.open_dataset(out) as ds:
        cell = ds.sel(site="site-0", column="paper", model="3d", state="overturning")
        lam = float(cell["annual_frequency"])
        assert 0 < lam < 1
        assert float(cell["probability_in_period"]) == pytest.approx(-math.expm1(-50 * lam), rel=1e-12)
        assert math.isfinite(float(cell["annual_frequency_band_lower"]))  # the 20 replicates gave a band
        assert ds.attrs["hazard_level_units_in_file"] == "g" and ds["hazard_level"].attrs["units"] == "m s-2"
    with open(table, encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 2 * 4  # 2 sites x 1 column x 1 model x 4 states
    assert float(rows[0]["annual_frequency_per_yr"]) == pytest.approx(lam, rel=1e-3)  # 4 significant digits
    assert fig.stat().st_size > 10_000
    # a rerun overwrites its own outputs
    assert main(["risk", str(frag), "--hazard", str(pga), "--out", str(out), "--csv", str(table), "--years", "100"]) == 0
    with xr.open_dataset(out) as ds:
        assert float(ds["years"]) == 100.0


def test_plain_two_column_curve(inputs, tmp_path):
    frag, _, _ = inputs
    curve = tmp_path / "site.csv"
    curve.write_text("# made-up site\nPGA [g],annual_rate [1/yr]\n0.05,0.05\n0.1,0.012\n0.3,0.0012\n0.6,0.00015\n"
                     "1.0,0.00002\n")
    assert main(["risk", str(frag), "--hazard", str(curve), "--out", str(tmp_path / "r.nc")]) == 0


@pytest.mark.parametrize("case, words", [
    ("sa", "the hazard curve is for Sa(T = 1 s) but the fragility"),
    ("missing", "no such file"),
    ("years", "--years -5: give a positive number of years"),
    ("badcurve", "name the intensity measure and its unit"),
    ("out-is-input", "is the fragility file this command reads"),
    ("out-over-user-file", "exists and is not a netCDF result written by frustum"),
    ("csv-over-user-file", "is not a CSV written by 'frustum risk'"),
    ("state", "--state 'collapse' is not in"),
    ("not-a-fragility", "not a fragility file"),
])
def test_risk_refuses_bad_input_in_one_line(inputs, results_nc, user_files, tmp_path, capsys, case, words):
    frag, pga, sa = inputs
    out = tmp_path / "risk.nc"
    bad = tmp_path / "bad.csv"
    bad.write_text("PGA,rate\n0.1,0.01\n0.2,0.001\n")
    args = {
        "sa": [str(frag), "--hazard", str(sa), "--out", str(out)],
        "missing": [str(frag), "--hazard", str(tmp_path / "nope.csv"), "--out", str(out)],
        "years": [str(frag), "--hazard", str(pga), "--out", str(out), "--years", "-5"],
        "badcurve": [str(frag), "--hazard", str(bad), "--out", str(out)],
        "out-is-input": [str(frag), "--hazard", str(pga), "--out", str(frag)],
        "out-over-user-file": [str(frag), "--hazard", str(pga), "--out", str(user_files["notes.txt"])],
        "csv-over-user-file": [str(frag), "--hazard", str(pga), "--out", str(out), "--csv",
                               str(user_files["notes.txt"])],
        "state": [str(frag), "--hazard", str(pga), "--out", str(out), "--state", "collapse"],
        "not-a-fragility": [str(results_nc), "--hazard", str(pga), "--out", str(out)],
    }[case]
    before = snapshot(frag, pga, sa, *user_files.values())
    assert main(["risk", *args]) == 2
    err = _err(capsys)
    assert words in err and len(err.strip().splitlines()) == 1, err
    assert unchanged(before)
    assert not out.exists()


def test_risk_refuses_to_replace_another_kind_of_result(inputs, results_nc, tmp_path, capsys):
    frag, pga, _ = inputs
    other = tmp_path / "study.nc"
    shutil.copy(results_nc, other)
    before = snapshot(other)
    assert main(["risk", str(frag), "--hazard", str(pga), "--out", str(other)]) == 2
    assert "is a results file of 'frustum study run'" in _err(capsys)
    assert unchanged(before)


def test_report_with_hazard_states_the_risk_in_plain_words(results_nc, inputs, tmp_path, capsys):
    _, pga, sa = inputs
    folder = tmp_path / "report"
    assert main(["report", str(results_nc), "--out", str(folder), "--hazard", str(pga), "--bootstrap", "10"]) == 0
    text = (folder / "report.md").read_text(encoding="utf-8")
    assert "## Risk at the site" in text
    assert "chance of overturning in 50 years**" in text and "on average once in" in text
    assert (folder / "risk.nc").is_file() and (folder / "risk.csv").is_file()
    assert result_kind(folder / "risk.nc") == "risk"
    assert "risk_paper" in text  # the figure
    # an Sa curve is refused before any fitting, naming both measures
    assert main(["report", str(results_nc), "--out", str(tmp_path / "r2"), "--hazard", str(sa)]) == 2
    err = _err(capsys)
    assert "Sa(T = 1 s)" in err and "against PGA" in err
    assert not (tmp_path / "r2").exists()
    assert main(["report", str(results_nc), "--out", str(tmp_path / "r3"), "--years", "20"]) == 2
    assert "give --hazard" in _err(capsys)


# -- issue 38, item 2: what frustum risk and report --hazard print -----------------------------------

@pytest.fixture(scope="module")
def fixed(inputs, tmp_path_factory):
    """{median [g]: the fragility of ``inputs`` with overturning at that median, beta 0.3, no replicates}."""
    from pipeline import fragility as F
    from pipeline import risk as R

    folder = tmp_path_factory.mktemp("fixed")
    frag = R.open_fragility(inputs[0])
    return {m: Path(F.write(fixed_fragility(frag, m, 0.3), folder / f"fixed-{m:g}.nc")) for m in (0.02, 1.9)}


def _risk_lines(argv, capsys):
    """stdout of ``frustum risk`` run in-process, with no numpy (or other Runtime) warning on the way."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert main(["risk", *argv]) == 0
    assert not [w for w in caught if issubclass(w.category, RuntimeWarning)], [str(w.message) for w in caught]
    return capsys.readouterr().out.splitlines()


def test_summary_near_certainty_is_a_percentage_not_1e02(fixed, inputs, tmp_path, capsys):
    """Median 0.02 g at the example's high site: 1 - exp(-50 lambda) = 99.69 %, printed '1e+02 %' before."""
    lines = _risk_lines([str(fixed[0.02]), "--hazard", str(inputs[1]), "--out", str(tmp_path / "r.nc")], capsys)
    with xr.open_dataset(tmp_path / "r.nc") as ds:
        p = float(ds["probability_in_period"].sel(site="site-0", column="paper", model="3d", state="overturning"))
    assert 0.9965 < p < 0.9975
    assert lines[:2] == [
        "site-0 paper 3d overturning: 0.115 /yr, once in 8.7 years on average; in 50 yr 99.7 % (almost certain (more "
        "than 19 in 20); curve-end bounds 99.7 % to 99.7 %)",
        "site-1 paper 3d overturning: 0.0463 /yr, once in 22 years on average; in 50 yr 90 % (about 9 in 10; "
        "curve-end bounds 90 % to 90 %)",
    ]


def test_summary_of_an_astronomical_return_period(fixed, tmp_path, capsys):
    """A curve that falls to 1e-300 /yr at 5 g: 4.25e-55 /yr, once in 2 followed by 54 digits years before."""
    curve = tmp_path / "far.csv"
    curve.write_text(plain_text(np.array([0.01, 0.02, 5.0]), (1e-2, 1e-3, 1e-300)))
    lines = _risk_lines([str(fixed[1.9]), "--hazard", str(curve), "--out", str(tmp_path / "r.nc")], capsys)
    assert lines[0] == ("site-0 paper 3d overturning: 4.25e-55 /yr, once in more than a million years on average; in "
                        "50 yr < 0.0001 % (less than 1 in a million; curve-end bounds < 0.0001 % to < 0.0001 %)")


def test_summary_says_the_integral_overflows_not_median_beyond_the_curve(fixed, tmp_path, capsys):
    """Rates of 1e300 to 1e100 /yr over 0.1-0.5 g: before, numpy's overflow warnings and "no risk computed
    (median beyond hazard curve)"; the median (0.02 g) lies below the curve's first level."""
    curve = tmp_path / "steep.csv"
    curve.write_text(plain_text(np.array([0.1, 0.2, 0.5]), (1e300, 1e200, 1e100)))
    lines = _risk_lines([str(fixed[0.02]), "--hazard", str(curve), "--out", str(tmp_path / "r.nc"), "--plot",
                         str(tmp_path / "r.png")], capsys)
    assert lines[0] == (
        "site-0 paper 3d overturning: no risk computed: the hazard curve's first segment (0.1 to 0.2 g) falls as "
        "a^-332; extended below 0.1 g, as the central value extends it, it carries the risk integral beyond the "
        "largest number a float holds (1.8e308 /yr); hazard curves flatten towards weak shaking (slopes of a few): "
        "check the rates of the first levels, or give lower levels (shaking above 0.1 g alone gives at least "
        "1e+300 /yr)")
    with xr.open_dataset(tmp_path / "r.nc") as ds:
        flag = ds["risk_flag"].sel(site="site-0", column="paper", model="3d", state="overturning")
        assert flag.attrs["flag_meanings"].split()[int(flag)] == "integral_overflows"


def test_report_hazard_section_in_the_same_words(fixed, inputs, tmp_path):
    """The report's "Risk at the site": 99.7 % (not 1e+02 %), once in 8.7 years; the overflow's reason."""
    from pipeline import report
    from pipeline import risk as R

    frag = R.open_fragility(fixed[0.02])
    pga = R.read_hazard_curve(inputs[1])
    text = "\n".join(report.risk_section(R.site_risk(frag, pga), pga, frag, report._fmt))
    assert "| site-0 | paper | 3D | 99.7 % | almost certain (more than 19 in 20) | 8.7 years | n/a |" in text
    steep = tmp_path / "steep.csv"
    steep.write_text(plain_text(np.array([0.1, 0.2, 0.5]), (1e300, 1e200, 1e100)))
    curve = R.read_hazard_curve(steep)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        text = "\n".join(report.risk_section(R.site_risk(frag, curve), curve, frag, report._fmt))
    assert "| site-0 | paper | 3D | n/a | integral overflows | | | |" in text
    assert ("- At site site-0, column 'paper' (3D): no risk is stated: the hazard curve's first segment (0.1 to "
            "0.2 g) falls as a^-332;") in text


def test_help_names_the_fragility_file_the_readme_writes(capsys):
    """`frustum fragility --help` writes, and `frustum risk --help` reads, out/quickstart_fragility.nc, as the
    README's quickstart does (it said out/quickstart-fragility.nc)."""
    readme = (Path(__file__).parents[2] / "README.md").read_text(encoding="utf-8")
    assert "--out out/quickstart_fragility.nc" in readme and "frustum risk out/quickstart_fragility.nc" in readme
    for command, words in (("fragility", "--out out/quickstart_fragility.nc"),
                           ("risk", "frustum risk out/quickstart_fragility.nc --hazard")):
        with pytest.raises(SystemExit) as done:
            main([command, "--help"])
        assert done.value.code == 0
        text = capsys.readouterr().out
        assert words in text and "quickstart-fragility" not in text, text


# -- issue 48, item 1: a hazard curve from code values ----------------------------------------------

@pytest.fixture(scope="module")
def half_g(inputs, tmp_path_factory):
    """(fragility of ``inputs`` with overturning at median 0.5 g, beta 0.4, no replicates; the same against Sa(1 s))."""
    from pipeline import fragility as F
    from pipeline import risk as R

    folder = tmp_path_factory.mktemp("half-g")
    frag = fixed_fragility(R.open_fragility(inputs[0]), 0.5, 0.4)
    sa = frag.assign_attrs(intensity_measure="sa", intensity_measure_period=1.0)
    return Path(F.write(frag, folder / "pga.nc")), Path(F.write(sa, folder / "sa.nc"))


def test_risk_from_one_code_value_in_50_and_2100_years(half_g, tmp_path, capsys):
    """--hazard-pga 475:0.16: H = (1/475) (a / 0.16 g)^-3, so lambda = H(0.5 g) exp(9 0.4^2 / 2) (Kennedy's
    closed form; to 1e-13, above the round-off of the integral's two pieces, 4 eps (1 + ln 475 + 3 ln(0.5/0.16)
    + 0.72) = 1e-14); the chance in 50 and in 2,100 years from one run, said where the curve is extrapolated."""
    from pipeline import risk as R

    out, table, fig = tmp_path / "risk.nc", tmp_path / "risk.csv", tmp_path / "risk.png"
    assert main(["risk", str(half_g[0]), "--hazard-pga", "475:0.16", "--years", "50,2100", "--out", str(out),
                 "--csv", str(table), "--plot", str(fig)]) == 0
    captured = capsys.readouterr()
    assert "frustum: warning: code values 475:0.16: the largest PGA given is 0.16 g, below the fragility median of " \
           "paper 3d overturning (median 0.5 g)" in captured.err
    lines = captured.out.splitlines()
    assert lines[0] == ("hazard: code values: PGA 0.16 g at 475 years; H(a) = (1/475) (a / 0.16 g)^-3, slope 3 (the "
                        "default: Eurocode 8's k is about 3); extrapolated at every PGA but 0.16 g (return period 475 "
                        "years): the power law of slope 3")
    exact = (1 / 475) * (0.5 / 0.16) ** -3 * math.exp(0.5 * (3 * 0.4) ** 2)
    with xr.open_dataset(out) as ds:
        assert result_kind(out) == "risk" and ds.attrs["hazard_format"] == "code"
        cell = ds.sel(site="site-0", column="paper", model="3d", state="overturning")
        lam = float(cell["annual_frequency"])
        assert lam == pytest.approx(exact, rel=1e-13)
        p = {T: float(cell["probability_in_period"].sel(years=T)) for T in (50.0, 2100.0)}
    assert p[50.0] == pytest.approx(-math.expm1(-50 * exact), rel=1e-12)
    assert 1 - p[2100.0] == pytest.approx(math.exp(-2100 * exact), rel=1e-12)  # standing 2,100 years
    line = next(text for text in lines if text.startswith("site-0 paper 3d overturning: "))
    assert line.startswith(f"site-0 paper 3d overturning: {lam:.3g} /yr, once in {R.years_words(1 / lam)} on average;")
    assert f"; in 50 yr {R.percent(p[50.0])} (" in line and f"; in 2100 yr {R.percent(p[2100.0])} (" in line
    with open(table, encoding="utf-8") as fh:
        rows = [row for row in csv.DictReader(fh) if row["state"] == "overturning"]
    assert float(rows[0]["probability_in_2100_yr"]) == pytest.approx(p[2100.0], rel=1e-3)  # 4 significant digits
    assert rows[0]["hazard_extrapolated"].startswith("at every PGA but 0.16 g")
    assert fig.stat().st_size > 10_000


def test_risk_from_two_code_values_and_a_slope(half_g, tmp_path, capsys):
    """Two values and --hazard-slope 3: their power law between them, slope 3 beyond; the share of the risk
    from the extrapolated curve printed; the integral the one of pipeline.risk with those tails."""
    from pipeline import risk as R
    from pipeline.units import G

    out = tmp_path / "risk.nc"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the median beyond 0.3 g, warned as above
        assert main(["risk", str(half_g[0]), "--hazard-pga", "475:0.16,2475:0.30", "--hazard-slope", "3", "--out",
                     str(out)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].endswith("extended with the slope given, 3; extrapolated below 0.16 g and beyond 0.3 g (return "
                             "periods under 475 or over 2475 years): power laws of the slope given, 3")
    with xr.open_dataset(out) as ds:
        cell = ds.sel(site="site-0", column="paper", model="3d", state="overturning")
        lam, share = float(cell["annual_frequency"]), float(cell["share_beyond_last_level"] + cell["share_below_first_level"])
        assert float(ds["years"]) == 50.0  # one period: the scalar coordinate of before
    expected = R.risk_integral(np.array([0.16, 0.30]) * G, [1 / 475, 1 / 2475], 0.5 * G, 0.4, (3.0, 3.0)).central
    assert lam == pytest.approx(float(expected), rel=1e-14)
    line = next(text for text in lines if text.startswith("site-0 paper 3d overturning: "))
    assert line.endswith(f"; {R.percent(share)} of it from the extrapolated curve") and 0.5 < share < 1


@pytest.mark.parametrize("argv, words", [
    (["--hazard-pga", "475:0.16"], "code values 475:0.16: the hazard curve is for PGA but the fragility"),
    (["--hazard-pga", "475;0.16"], "--hazard-pga: '475;0.16' is not a return period and a PGA"),
    (["--hazard-pga", "475:0.16", "--hazard-slope", "nan"], "--hazard-slope is nan"),
    (["--hazard-pga", "475:0.16,2475:0.17"], "--hazard-pga: the slope between 475:0.16 and 2475:0.17 is 27.2"),
    (["--hazard-pga", "475:0.16", "--years", "50,abc"], "--years 50,abc: 'abc' is not a number of years"),
])
def test_code_values_refused_in_one_line(half_g, tmp_path, capsys, argv, words):
    """Refusals of code values as of a file's: one line, the value and the fix; nothing written. The first runs
    the fragility against Sa(1 s), the others against PGA."""
    frag = half_g[1] if words.startswith("code values") else half_g[0]
    out = tmp_path / "risk.nc"
    before = snapshot(*half_g)
    assert main(["risk", str(frag), *argv, "--out", str(out)]) == 2
    err = _err(capsys)
    assert words in err and len(err.strip().splitlines()) == 1, err
    assert unchanged(before) and not out.exists()


def test_help_shows_code_values_with_examples(capsys):
    from pipeline.cli import main as run

    with pytest.raises(SystemExit) as done:
        run(["risk", "--help"])
    assert done.value.code == 0
    text = " ".join(capsys.readouterr().out.split())
    for words in ("--hazard-pga T:PGA[,T:PGA...]", "--hazard-slope K", "--years T[,T...]",
                  "frustum risk out/quickstart_fragility.nc --hazard-pga 475:0.16 --years 50,2100 --out risk.nc",
                  "--hazard-pga 475:0.16,2475:0.30 --hazard-slope 3"):
        assert words in text, words
