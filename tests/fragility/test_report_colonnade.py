"""The report of a colonnade: what falls first, what the standing ones keep, damage by drum dislocation
(issue 48, item 3). Synthetic results of a row of 4 columns (fragility_synthetic.make_colonnade_results)
whose every number the tests recompute from the dataset by their own reading of the labels."""

import csv
import re
from collections import Counter

import numpy as np
import pytest
from fragility_synthetic import make_colonnade_results

from pipeline import fragility as F
from pipeline import report_colonnade as RC
from pipeline.report import _fmt, write_report

N_COLUMNS = 4


@pytest.fixture(scope="module")
def reported(tmp_path_factory):
    ds, _ = make_colonnade_results(n_columns=N_COLUMNS, n_records=10, angles=(0.0, 90.0),
                                   scales=(0.25, 0.5, 1.0, 1.5, 2.0), failed=6)
    out = write_report(ds, tmp_path_factory.mktemp("colonnade") / "report", bootstrap=20, seed=2)
    return ds, out, open(out["report"], encoding="utf-8").read()


def _table(text, title):
    """The rows of the first Markdown table after the heading ``title``, as lists of cells."""
    section = text[text.index(title):]
    lines = section.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("| "))
    rows = []
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        rows.append([cell.strip() for cell in line.strip("|").split("|")])
    return rows


def _where_it_began(label):
    """The test's own reading of a label: end column, inner column, epistyle block or as one body."""
    if label.startswith("epistyle block"):
        return "epistyle block"
    column = re.match(r"column (\d+) ", label)
    if column is None:
        return "as one body"
    return "end column" if int(column.group(1)) in (1, N_COLUMNS) else "inner column"


def _expected_first(ds, model, angle=None):
    one = ds.sel(column="row", model=model, **({} if angle is None else {"angle": angle}))
    fell = ((one["status"] == 0) & (one["overturned"] == 1)).values
    labels = one["overturn_body"].values[fell]
    counts = Counter(_where_it_began(str(b)) for b in labels)
    parts = Counter(re.sub(r"^column \d+ ", "", str(b)) for b in labels if not str(b).startswith("the "))
    top = max(parts.values(), default=0)
    often = [p for p, n in parts.items() if n == top and top]
    return len(labels), counts, often, top


def test_what_falls_first_is_counted_from_the_labels_of_the_runs_that_fell(reported):
    ds, out, text = reported
    rows = _table(text, "## What falls first, and what the standing ones keep")
    # the row run as a row: by the compliant model and the frame, every angle pooled and each angle; not the 3d
    # model (it ran each column alone) nor the column alone 'paper'
    assert [(r[0], r[1], r[2]) for r in rows] == [("row", m, a) for m in ("3d-compliant", "2d-frame")
                                                   for a in ("all", "0", "90")]
    for r in rows:
        n, counts, often, top = _expected_first(ds, r[1], None if r[2] == "all" else float(r[2]))
        assert int(r[3]) == n and n > 0
        assert [int(v) for v in r[4:8]] == [counts[k] for k in ("end column", "inner column", "epistyle block",
                                                               "as one body")]
        assert sum(int(v) for v in r[4:8]) == n  # every fall begins somewhere
        if r[1] == "2d-frame":
            assert r[8] == "n/a" and int(r[7]) == n  # the frame falls as one
        else:
            assert r[8].startswith(", ".join(often)) and f"({top}" in r[8]
    assert int(rows[0][4]) > 0 and int(rows[0][5]) > 0 and int(rows[0][6]) > 0  # the synthetic labels reach all
    # the failed runs (status 1) are left out: the direct count above reads status 0 only
    assert int((ds["status"] != 0).sum()) == 6


def test_the_epistyle_of_the_runs_that_stood_median_and_90th_percentile_per_stripe_and_pooled(reported):
    ds, out, text = reported
    rows = _table(text, "Of the runs that stood")
    one = ds.sel(column="row", model="3d-compliant")
    stood = (one["status"] == 0) & (one["overturned"] == 0)
    expected = []
    groups = [({"scale": s}, f"x {_fmt(float(s))}", "all") for s in ds["scale"].values] + [({}, "all", "all")]
    groups += [({"angle": a}, "all", _fmt(float(a))) for a in ds["angle"].values]
    for sel, stripe, angle in groups:
        mask = stood.sel(sel).values
        values = [1e3 * one[name].sel(sel).values[mask] for name in ("epistyle_slip", "epistyle_opening")]
        stats = [_fmt(float(np.percentile(v, q))) if v.size else "n/a" for v in values for q in (50, 90)]
        expected.append(["row", "3d-compliant", stripe, angle, str(int(mask.sum())), *stats])
        kept = RC.epistyle_kept(F.resolve_undecided(ds), "row", "3d-compliant", sel.get("scale"), sel.get("angle"))
        if mask.any():
            assert kept["slip_90"] == pytest.approx(float(np.percentile(values[0], 90)) / 1e3, rel=1e-12)
    assert rows == expected  # the frame has no epistyle of its own to slide (NaN): no rows
    assert int(rows[-3][4]) > 20 and rows[2][4] != "0"


def test_the_summary_csv_carries_the_pooled_numbers(reported):
    ds, out, text = reported
    with open(out["csv"], newline="", encoding="utf-8") as fh:
        rows = {(r["column"], r["model"]): r for r in csv.DictReader(fh)}
    n, counts, often, _ = _expected_first(ds, "3d-compliant")
    row = rows[("row", "3d-compliant")]
    assert [int(row[f"first_{k}"]) for k in ("end_column", "inner_column", "epistyle_block", "as_one_body")] == \
        [counts[k] for k in ("end column", "inner column", "epistyle block", "as one body")]
    assert row["first_most_often"] == " / ".join(often)
    one = ds.sel(column="row", model="3d-compliant")
    mask = ((one["status"] == 0) & (one["overturned"] == 0)).values
    assert float(row["epistyle_opening_90_mm"]) == pytest.approx(
        float(np.percentile(1e3 * one["epistyle_opening"].values[mask], 90)), rel=5e-4)  # 4 significant digits
    assert int(row["epistyle_runs_stood"]) == int(mask.sum())
    assert rows[("row", "2d-frame")]["first_as_one_body"] == str(n_frame := _expected_first(ds, "2d-frame")[0])
    assert n_frame > 0 and rows[("row", "2d-frame")]["epistyle_slip_50_mm"] == ""
    for other in (("row", "3d"), ("paper", "3d-compliant")):  # a column alone: nothing of a row
        assert all(rows[other][k] == "" for k in ("first_end_column", "epistyle_slip_50_mm"))


def test_damage_states_by_drum_dislocation_are_tabled_with_their_words(reported):
    ds, out, text = reported
    frag = out["frag"]
    rows = _table(text, "## Damage states by drum dislocation")
    head = text[text.index("## Damage states by drum dislocation"):].split("\n| structure")[1].splitlines()[0]
    assert "DS1: slip >= 1 % of D | DS2: slip >= 5 % of D | DS3: slip >= 10 % of D" in head
    assert "a dislocation the eye sees" in text and "drums need re-setting" in text
    assert [(r[0], r[1]) for r in rows] == [("row", "3d-compliant"), ("paper", "3d-compliant")]  # models of drums
    for r in rows:
        for cell, s in zip(r[2:], F.DISLOCATION_STATES):
            fit = frag.sel(state=f"dislocation_{s:g}", column=r[0], model="3d-compliant")
            one = ds.sel(column=r[0], model="3d-compliant")
            ok = (one["status"] == 0).values
            reached = (((one["dislocation_ratio"] >= s) | (one["overturned"] == 1)).values & ok).sum()
            assert cell.endswith(f"; {reached} / {ok.sum()}")
            assert int(fit["fit_status"]) == F.FIT_OK and cell.startswith(_fmt(float(fit["median"]) / 9.80665) + " (")
