"""The issue-6 study files validate, and the committed reports state the numbers of their datasets."""

import os
import re

import pytest

from pipeline import fragility as F
from pipeline.report import _fmt
from pipeline.units import G

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
STUDY_FILES = [
    "studies/fema_slenderness/fema_slenderness.toml",
    "studies/model_2d_vs_3d/model_2d_vs_3d.toml",
    "studies/damping/damping_nu0.toml",
    "studies/damping/damping_nu002.toml",
    "studies/damping/damping_nu01.toml",
    "studies/real_column/real_column.toml",
]


@pytest.mark.parametrize("path", STUDY_FILES)
def test_study_files_validate(path):
    study_mod = pytest.importorskip("pipeline.study")
    study = study_mod.load_study(os.path.join(ROOT, path))
    assert study.columns and study.records
    assert os.path.normpath(os.path.dirname(study.output)).endswith("out")


@pytest.mark.parametrize("name", ["model_2d_vs_3d", "real_column"])
def test_committed_2d_vs_3d_conclusions_are_the_dataset_numbers(name):
    """Rows of the 2D-against-3D table in studies/NAME/report.md equal a fresh fit of out/NAME.nc."""
    results_path = os.path.join(ROOT, "out", f"{name}.nc")
    report_path = os.path.join(ROOT, "studies", name, "report.md")
    if not os.path.exists(results_path):
        pytest.skip(f"{results_path} not computed here (frustum study run studies/{name}/{name}.toml)")
    frag = F.fragility(F.open_results(results_path))  # point estimates do not depend on the bootstrap
    text = open(report_path, encoding="utf-8").read()
    ratios = []
    for c in frag["column"].values:
        m3 = float(frag["median"].sel(state="overturning", column=c, model="3d"))
        m2 = float(frag["median"].sel(state="overturning", column=c, model="2d"))
        marked = r"( \(extrapolated\))?"  # a median beyond the strongest shaking simulated says so
        assert re.search(rf"\| {re.escape(c)} \| {re.escape(_fmt(m3 / G))}{marked} \| {re.escape(_fmt(m2 / G))}{marked} "
                         rf"\| {re.escape(_fmt(m2 / m3))} \|", text), c
        ratios.append(m2 / m3)
    summary = re.search(r"\*\*In short:\*\* 2D is unconservative for (\d+) of (\d+)", text)
    assert summary and int(summary.group(1)) == sum(r > 1 for r in ratios)
    assert f"{_fmt(min(ratios))} (" in text and f"{_fmt(max(ratios))} (" in text
