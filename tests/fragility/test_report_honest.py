"""The report says what the data support: extrapolated medians, too few records, bounds, digits, one HTML file."""

import base64
import csv
import re
from html.parser import HTMLParser

import numpy as np
import pytest
from fragility_synthetic import make_results

from pipeline.citation import REFERENCE
from pipeline.report import MIN_RECORDS, write_report
from pipeline.units import G


def _rows(out):
    with open(out["csv"], newline="") as fh:
        return list(csv.DictReader(fh))


@pytest.fixture(scope="module")
def beyond(tmp_path_factory):
    """A study whose 2D median lies above its strongest PGA (1 g): 12 records, stripes 0.25-1 g."""
    ds, _ = make_results(n_records=12, columns=("paper",), scales=(0.25, 0.5, 0.75, 1.0), seed=3,
                         true_median={("paper", "3d"): 0.6 * G, ("paper", "2d"): 1.6 * G},
                         true_beta={("paper", "3d"): 0.4, ("paper", "2d"): 0.5})
    out = write_report(ds, tmp_path_factory.mktemp("beyond") / "r", bootstrap=20)
    return ds, out


def test_a_median_beyond_the_strongest_shaking_is_marked_extrapolated(beyond):
    ds, out = beyond
    text = open(out["report"], encoding="utf-8").read()
    median_2d = float(out["frag"]["median"].sel(state="overturning", column="paper", model="2d"))
    median_3d = float(out["frag"]["median"].sel(state="overturning", column="paper", model="3d"))
    strongest = float(ds["pga"].max())
    assert median_2d > strongest > median_3d  # the premise of the test
    rows = {r["model"]: r for r in _rows(out)}
    assert rows["2d"]["median_extrapolated"] == "above" and rows["3d"]["median_extrapolated"] == ""
    assert float(rows["2d"]["pga_simulated_max_g"]) == pytest.approx(strongest / G, rel=5e-4)
    # in the probability table, the 2D-against-3D table and the text
    table_row = next(line for line in text.splitlines() if line.startswith("| paper | 2D |"))
    assert "(extrapolated)" in table_row
    assert re.search(r"\| paper \| [0-9.]+ \| [0-9.]+ \(extrapolated\) \|", text)
    assert (f"lies beyond the strongest shaking simulated ({strongest / G:.3g} g)") in text
    assert "the 2D median extrapolated beyond the shaking simulated" in text
    assert "| paper | 3D |" in text and "(extrapolated)" not in next(
        line for line in text.splitlines() if line.startswith("| paper | 3D |"))


def test_probabilities_carry_their_bootstrap_bounds(beyond):
    _, out = beyond
    row = next(r for r in _rows(out) if r["model"] == "3d")
    p, lo, hi = (float(row[f"p_overturning_at_0.5g{s}"]) for s in ("", "_lower", "_upper"))
    assert 0 <= lo <= p <= hi <= 1 and hi > lo
    text = open(out["report"], encoding="utf-8").read()
    row_3d = next(line for line in text.splitlines() if line.startswith("| paper | 3D |"))
    assert f"{100 * p:.1f} % ({100 * lo:.1f} to {100 * hi:.1f} %)" in row_3d


def test_csv_numbers_have_meaningful_digits(beyond):
    _, out = beyond
    for row in _rows(out):
        for key, value in row.items():
            if re.fullmatch(r"-?[0-9.]+(e[-+]?\d+)?", value) and "." in value:
                digits = value.split("e")[0].replace("-", "").replace(".", "").lstrip("0")
                assert len(digits) <= 4, (key, value)
        assert float(row["D_base_m"]) == pytest.approx(2 * float(row["R_m"]))
        assert float(row["D_top_m"]) == pytest.approx(2 * float(row["r_m"]))


def test_too_few_records_are_flagged(tmp_path):
    ds, _ = make_results(n_records=MIN_RECORDS - 1, columns=("paper",), models=("3d",), seed=5)
    out = write_report(ds, tmp_path / "r", bootstrap=10)
    text = open(out["report"], encoding="utf-8").read()
    assert f"'paper' ({MIN_RECORDS - 1}) has fewer than {MIN_RECORDS} records" in text
    assert f"| {MIN_RECORDS - 1} (too few) |" in text
    assert _rows(out)[0]["too_few_records"] == "true"
    ds, _ = make_results(n_records=MIN_RECORDS, columns=("paper",), models=("3d",), seed=5)
    out = write_report(ds, tmp_path / "r7", bootstrap=0)
    assert "Too few records" not in open(out["report"], encoding="utf-8").read()
    assert _rows(out)[0]["too_few_records"] == "false"


def test_a_study_where_nothing_overturns_is_reported(tmp_path):
    """Both models, nothing overturns: the 2D-against-3D figure used to crash ("Data cannot be log-scaled")."""
    ds, _ = make_results(n_records=8, columns=("paper", "slender"), scales=(0.01, 0.02), seed=2)
    assert int(ds["overturned"].sum()) == 0
    out = write_report(ds, tmp_path / "r", bootstrap=5)
    text = open(out["report"], encoding="utf-8").read()
    assert text.count("no exceedance observed") == 4  # 2 columns x 2 models
    strongest = float(ds["pga"].max()) / G
    assert f"'paper' (3D): no run overturned, up to a PGA of {strongest:.3g} g" in text
    assert not any("median_2d_vs_3d" in f for f in out["figures"])
    assert len(out["figures"]) >= 3


class _Images(HTMLParser):
    def __init__(self):
        super().__init__()
        self.sources = []

    def handle_starttag(self, tag, attrs):
        if tag == "img":
            self.sources.append(dict(attrs)["src"])


def test_html_report_is_one_file_with_its_figures_embedded(beyond):
    _, out = beyond
    page = open(out["html"], encoding="utf-8").read()
    assert page.startswith("<!DOCTYPE html>") and "<table>" in page
    assert REFERENCE in page and REFERENCE in open(out["report"], encoding="utf-8").read()
    parser = _Images()
    parser.feed(page)
    assert len(parser.sources) == len(out["figures"]) > 0
    for src, path in zip(parser.sources, out["figures"]):
        assert src.startswith("data:image/png;base64,")
        data = base64.b64decode(src.split(",", 1)[1])
        assert data.startswith(b"\x89PNG") and data == open(path, "rb").read()


def test_percentages_are_never_rounded_to_certainty():
    from pipeline.report import _pct

    assert _pct(0.99996) == "> 99.9 %" and _pct(1.0) == "100.0 %"
    assert _pct(0.00004) == "< 0.1 %" and _pct(0.0) == "0.0 %"
    assert _pct(np.nan) == "n/a"


def test_a_study_driven_by_one_component_says_so_in_its_assumptions(tmp_path):
    """components = "x" (results attr horizontal_components): the report must not claim both components drove."""
    ds, _ = make_results(n_records=6, columns=("paper",), scales=(0.25, 0.5, 1.0), seed=4)
    pair = open(write_report(ds, tmp_path / "pair", bootstrap=0)["report"], encoding="utf-8").read()
    ds.attrs["horizontal_components"] = ("the x component of each record alone (y set to zero before scaling), "
                                         "turned by the incidence angle")
    one = open(write_report(ds, tmp_path / "one", bootstrap=0)["report"], encoding="utf-8").read()
    assert "both horizontal components" in pair and "x component of each record alone" not in pair
    assert "x component of each record alone" in one and "both horizontal components" not in one
