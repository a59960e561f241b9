"""The drums-vs-rigid comparison script (studies/drums_vs_rigid/compare.py): fits, tables, cache.

Fast: synthetic rows for the analysis, a fake ``simulate`` for the cache (no kernel runs).
"""

import importlib.util
import json
import math
import os

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "..", "studies", "drums_vs_rigid", "compare.py")


@pytest.fixture(scope="module")
def compare():
    spec = importlib.util.spec_from_file_location("drums_vs_rigid_compare", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _row(model, record, stripe, over, *, slip=None, drum=-1, wall=1.0):
    stack = model == "stack"
    return {"column": "paper", "model": model, "record": record, "stripe": stripe, "scale": 1.0,
            "n_bodies": 4 if stack else 1, "overturned": over, "collapsed": False, "peak_theta": 0.1,
            "residual_displacement": 0.0, "overturn_drum": (drum if over else -1) if model != "rigid" else None,
            "joint_slip": slip if stack else None, "joint_diameter": [1.0, 0.95, 0.9, 0.85] if stack else None,
            "dislocation_ratio": (max(s / d for s, d in zip(slip[1:], [0.95, 0.9, 0.85])) if stack else None),
            "wall": wall, "simulated": 10.0}


STRIPES = (0.2, 0.4, 0.6, 0.8)
RECORDS = ("A", "B", "C")


def _rows():
    """Rigid overturns from 0.6 g, monolith from 0.8 g; the stack like the monolith but record C at 0.6 g."""
    rows = []
    for rec in RECORDS:
        for s in STRIPES:
            rows.append(_row("rigid", rec, s, s >= 0.6, wall=0.1))
            rows.append(_row("monolith", rec, s, s >= 0.8, wall=1.0))
            over = s >= 0.8 or (rec == "C" and s == 0.6)
            rows.append(_row("stack", rec, s, over, slip=[0.01, 0.002 * s, 0.001, 0.0], drum=2 if rec == "A" else 0,
                             wall=10.0))
    return rows


def test_separated_medians_are_between_the_stripes(compare):
    med = compare.medians(_rows(), n_boot=50)
    # perfectly separated outcomes: the fit puts the median at the geometric mean of the two stripes
    assert med[("paper", "rigid")]["median"] == pytest.approx(math.sqrt(0.4 * 0.6))
    assert med[("paper", "monolith")]["median"] == pytest.approx(math.sqrt(0.6 * 0.8))
    assert med[("paper", "rigid")]["overturned"] == 6
    lo, hi = med[("paper", "stack")]["lo"], med[("paper", "stack")]["hi"]
    assert lo <= med[("paper", "stack")]["median"] <= hi


def test_a_models_band_does_not_depend_on_the_other_models_reported(compare):
    rows = _rows()
    # the stack alone, and after the rigid model and the monolith: the same resamples of its records
    alone = compare.medians([r for r in rows if r["model"] == "stack"], n_boot=50)[("paper", "stack")]
    together = compare.medians(rows, n_boot=50)[("paper", "stack")]
    assert (alone["lo"], alone["hi"]) == (together["lo"], together["hi"])
    assert alone["lo"] < alone["hi"]  # record C's 0.6 g overturning makes the resamples differ


def test_agreement_counts_which_way_models_disagree(compare):
    agree = compare.agreement(_rows())
    rm = agree[("paper", "rigid", "monolith")]
    assert rm == {"cells": 12, "same": 9, "a_only": 3, "b_only": 0}
    ms = agree[("paper", "monolith", "stack")]
    assert ms == {"cells": 12, "same": 11, "a_only": 0, "b_only": 1}


def test_stack_statistics(compare):
    st = compare.stack_stats(_rows())
    v = st[("paper", 0.4)]
    assert v["standing"] == 3 and v["overturned"] == 0
    assert v["slip_med"] == pytest.approx(0.001)  # largest bed-joint slip, the base (0.01 m) left out
    assert v["ratio_med"] == pytest.approx(0.001 / 0.9)
    u = st[("paper", 0.6)]
    assert u["standing"] == 2 and u["overturned"] == 1
    assert u["slip_med"] == pytest.approx(0.0012) and u["ratio_med"] == pytest.approx(0.0012 / 0.95)
    w = st[("paper", 0.8)]
    assert w["overturned"] == 3 and w["upper_first"] == 1 and math.isnan(w["slip_med"])


def test_report_and_findings(compare):
    text = compare.report(_rows(), STRIPES, RECORDS, {"beds": {"paper": (1e7, 0.96)}, "workers": 2})
    assert "| paper | rigid model | 12 | 6 | 0.490 |" in text
    assert "only the rigid model overturns in 3, only the monolith in 0" in text
    assert "in 1 of the stack's 4 overturnings an upper body lay down first" in text
    assert text.count("|---|") >= 4


def test_cache_resumes_without_running(compare, tmp_path, monkeypatch):
    class Motion:
        duration = 10.0

    calls = []

    class Response:
        summary = {"overturned": True, "peak_theta": 1.6, "residual_displacement": 0.0}

    def fake_simulate(*args, **kwargs):
        calls.append(args)
        return Response()

    monkeypatch.setattr(compare, "simulate", fake_simulate)
    monkeypatch.setattr(compare, "record_info", lambda record: (9.80665, 10.0))
    monkeypatch.setattr(compare, "load_record", lambda record: Motion())
    job = ("paper", "rigid", "X", 0.5)
    row = compare.run((str(tmp_path), job, 1e7, 0.96))
    assert row["overturned"] and row["scale"] == pytest.approx(0.5) and len(calls) == 1
    files = os.listdir(tmp_path)
    assert files == [os.path.basename(compare.cache_path(str(tmp_path), job))]  # no partial file left
    again = compare.run((str(tmp_path), job, 1e7, 0.96))
    assert again == json.loads((tmp_path / files[0]).read_text()) and len(calls) == 1


def test_estimate_prefers_measured_costs_and_schedules_longest_first(compare, monkeypatch):
    measured = compare.rates([_row("monolith", "A", 0.2, False, wall=2.0)])
    assert compare.rate_for("paper", "monolith", measured) == (0.2, "measured")
    assert compare.rate_for("parthenon", "monolith", measured)[1] == "prior (one run)"
    monkeypatch.setattr(compare, "PRIOR_RATE", {})
    stack = compare.rates([_row("stack", "A", 0.2, False, slip=[0.0] * 4, wall=4.0)])
    rate, source = compare.rate_for("parthenon", "stack", stack)
    assert rate == pytest.approx(0.4 * 3**compare.BODY_EXPONENT) and source == "scaled from paper"
    assert compare.makespan([2.0, 3.0, 2.0, 3.0, 2.0], 2) == pytest.approx(7.0)  # greedy, longest first
    assert compare.makespan([5.0, 1.0, 1.0], 1) == pytest.approx(7.0)


def test_tilt_ratios_use_only_cells_where_both_stood(compare):
    slip = [0.0] * 4
    rows = [_row("monolith", "A", 0.2, False), _row("stack", "A", 0.2, False, slip=slip),
            _row("monolith", "B", 0.2, False), _row("stack", "B", 0.2, True, slip=slip),  # the stack fell: left out
            _row("monolith", "C", 0.2, False), _row("stack", "C", 0.2, False, slip=slip)]
    rows[1]["peak_theta"], rows[5]["peak_theta"] = 0.15, 0.3  # 1.5 and 3 times the monolith's 0.1
    t = compare.tilt_ratios(rows)[("paper", "monolith", "stack")]
    assert t["cells"] == 2 and t["median"] == pytest.approx(2.25)
    assert t["p10"] == pytest.approx(1.65) and t["p90"] == pytest.approx(2.85)


def test_a_model_on_fewer_than_three_stripes_is_not_fitted(compare):
    rows = [r for r in _rows() if r["model"] != "stack" or r["stripe"] == 0.6]
    med = compare.medians(rows, n_boot=20)
    s = med[("paper", "stack")]
    assert s["status"] == "not fitted (1 stripe)" and math.isnan(s["median"]) and s["runs"] == 3
    assert s["overturned"] == 1 and not med[("paper", "monolith")]["status"].startswith("not fitted")
    text = compare.report(rows, STRIPES, RECORDS, {"beds": {}, "report_only": True})
    assert "| paper | 4-drum stack | 3 (A, B, C) | 0.6 | 3 |" in text  # the design actually run
    assert "not fitted (1 stripe) for the 4-drum stack" in text and "tabulated from the cache" in text


def test_models_on_different_cells_are_also_fitted_on_the_cells_they_share(compare):
    assert compare.common_cells(_rows()) == []  # same design for every model: nothing to add
    # the stack on the three lower stripes of records A and B only (as the Parthenon stack ran fewer)
    rows = [r for r in _rows() if r["model"] != "stack" or (r["stripe"] <= 0.6 and r["record"] != "C")]
    common = compare.common_cells(rows)
    assert {(r["model"], r["record"], r["stripe"]) for r in common} == {
        (m, rec, s) for m in ("rigid", "monolith", "stack") for rec in ("A", "B") for s in (0.2, 0.4, 0.6)}
    text = compare.report(rows, STRIPES, RECORDS, {"beds": {}, "report_only": True})
    # the monolith overturns from 0.8 g: on its full design the median lies between 0.6 and 0.8 g,
    # on the cells the stack ran it never overturns
    assert f"| paper | monolith | 12 | 3 | {math.sqrt(0.6 * 0.8):.3f} |" in text
    assert "on the cells every model ran" in text
    assert "| paper | monolith | 6 | 0 | > 0.8 (none overturned) |" in text
    assert "Fitted on the 6 record x stripe cells every model ran" in text


def test_report_only_tabulates_the_cache_and_runs_nothing(compare, monkeypatch, capsys):
    monkeypatch.setattr(compare, "all_cached", lambda out: _rows())
    monkeypatch.setattr(compare, "bed", lambda key: (1e7, 0.96))
    monkeypatch.setattr(compare, "simulate", lambda *a, **k: pytest.fail("--report-only must not simulate"))
    assert compare.main(["--report-only", "--columns", "paper"]) == 0
    text = capsys.readouterr().out
    assert "| paper | rigid model | 12 | 6 | 0.490 |" in text and "36 runs" in text
    monkeypatch.setattr(compare, "all_cached", lambda out: [])
    with pytest.raises(SystemExit, match="no run of paper"):
        compare.main(["--report-only", "--columns", "paper"])


def test_shuffle_is_a_seeded_order(compare, monkeypatch, capsys):
    monkeypatch.setattr(compare, "record_info", lambda record: (9.80665, float(record[-2:])))
    monkeypatch.setattr(compare, "all_cached", lambda out: [])
    args = ["--dry-run", "--columns", "paper", "--models", "stack", "--stripes", "1", "--out", "/nonexistent"]

    def order(extra):
        compare.main(args + extra)
        return [line.split()[2] for line in capsys.readouterr().out.splitlines() if line.startswith("  paper")]

    longest = order([])
    assert longest == [f"FEMA-FF-{i:02d}" for i in range(22, 0, -1)]  # the longest (here: highest id) first
    shuffled = order(["--shuffle"])
    assert sorted(shuffled) == sorted(longest) and shuffled != longest and order(["--shuffle"]) == shuffled


def test_a_change_of_the_joint_law_renews_only_the_stack_rows(compare, tmp_path):
    assert compare.digest("rigid") == compare.digest("monolith") == compare.digest()
    assert compare.digest("stack") != compare.digest()
    job = ("paper", "stack", "X", 0.5)
    assert compare.cache_path(str(tmp_path), job).endswith(f"-{compare.digest('stack')}.json")
    for model, tag in (("rigid", compare.digest()), ("stack", compare.digest()), ("stack", compare.digest("stack"))):
        (tmp_path / f"paper-{model}-X-0.5g-{tag}.json").write_text(json.dumps({"model": model, "tag": tag}))
    rows = compare.all_cached(str(tmp_path))  # the stale stack row (the shared digest) is not read
    assert sorted((r["model"], r["tag"]) for r in rows) == [("rigid", compare.digest()),
                                                            ("stack", compare.digest("stack"))]


def test_band_variants_have_their_own_rows_and_are_compared_with_the_stack(compare, tmp_path):
    narrow, wide = "stack-narrow", "stack-wide"
    assert compare.BAND_VARIANTS == {narrow: 0.25, wide: 1.0}  # half and twice the stack's 0.5 spacings
    tags = {m: compare.digest(m) for m in ("rigid", "stack", narrow, wide)}
    assert len(set(tags.values())) == 4  # a variant's rows never pass for the stack's, nor each other's
    for model in (narrow, wide):
        assert dict(compare.settings(model, 1e7, 0.96).numerics) == {"edge_band": compare.BAND_VARIANTS[model]}
        assert compare.n_bodies("paper", model) == 4
    assert compare.settings("stack", 1e7, 0.96).numerics == ()  # the stack's rows keep their digest and model
    slip = [0.0] * 4
    rows = [_row("monolith", r, 0.6, False) for r in RECORDS]
    rows += [_row("stack", r, 0.6, r == "C", slip=slip) for r in RECORDS]
    rows += [_row(narrow, r, 0.6, r in "BC", slip=slip) for r in RECORDS]  # B now overturns
    rows += [_row(wide, r, 0.6, False, slip=slip) for r in RECORDS]  # C now stands
    rows[6]["peak_theta"] = 0.12  # narrow on A: 1.2 times the stack's 0.1
    agree = compare.agreement(rows)
    # the variants are compared with the stack only, not with the monolith or each other
    assert sorted(agree) == [("paper", "monolith", "stack"), ("paper", "stack", narrow), ("paper", "stack", wide)]
    assert agree[("paper", "stack", narrow)] == {"cells": 3, "same": 2, "a_only": 0, "b_only": 1}
    assert agree[("paper", "stack", wide)] == {"cells": 3, "same": 2, "a_only": 1, "b_only": 0}
    tilts = compare.tilt_ratios(rows)
    assert tilts[("paper", "stack", narrow)]["cells"] == 1 and tilts[("paper", "stack", narrow)]["median"] == 1.2
    phrases = compare.band_phrases("paper", agree, tilts)
    assert phrases[0].startswith("halved (edge_band 0.25), it changes the stack's outcome in 1 of 3 cells "
                                 "(1 now overturn, 0 now stand)")
    assert phrases[1].startswith("doubled (edge_band 1), it changes the stack's outcome in 1 of 3 cells "
                                 "(0 now overturn, 1 now stand)")
    text = compare.report(rows, (0.6,), RECORDS, {"beds": {}, "report_only": True})
    assert "| paper | 4-drum stack | 4-drum stack, edge band 0.25 | 3 | 2 |" in text
    assert "The band past a bed joint's edge, a numerical choice: halved" in text
    for model, tag in tags.items():  # the cache reads every model's rows under its own digest
        (tmp_path / f"paper-{model}-X-0.6g-{tag}.json").write_text(json.dumps({"model": model}))
    assert sorted(r["model"] for r in compare.all_cached(str(tmp_path))) == sorted(tags)
