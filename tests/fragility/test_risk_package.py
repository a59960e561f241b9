"""``pipeline.risk`` as a package, one job a module (issue 47, item 7).

The module it replaced (1,245 lines at 089e2ab) defined the public names below; callers (the CLI, the
report, the figures, tests and studies) import them from ``pipeline.risk``, so each must stay there.
"""

import ast
from pathlib import Path

import pytest

import pipeline.risk as R

PACKAGE = Path(R.__file__).parent

#: Every public name ``pipeline/risk.py`` defined at 089e2ab (functions, classes, constants).
FORMER_NAMES = (
    "DEFAULT_YEARS", "OPENQUAKE_UNITS", "LEVEL_UNITS", "SI_UNITS", "MAX_LEVEL", "RISK_OK", "RISK_MEDIAN_BEYOND",
    "RISK_NO_EXCEEDANCE", "RISK_ALL_EXCEED", "RISK_NO_FIT", "RISK_OVERFLOW", "RISK_FLAGS", "RISK_SHARES", "LIMITS",
    "HazardCurve", "describe_im", "annual_rate", "probability_in", "parse_imt", "read_hazard_curve",
    "read_openquake_csv", "read_plain_csv", "usable_curve", "hazard_rate_at", "segment_integral", "RiskParts",
    "risk_integral", "open_fragility", "fragility_im", "check_im", "return_period", "site_risk", "CSV_DIGITS",
    "risk_rows", "write_csv", "write", "one_in", "percent", "years_words", "no_risk_reason",
)


@pytest.mark.parametrize("name", FORMER_NAMES)
def test_every_name_of_the_former_module_is_still_importable(name):
    assert hasattr(R, name), f"pipeline.risk.{name} is gone"
    assert name in R.__all__


def test_the_package_is_small_modules_each_saying_its_job():
    """No module above 600 lines (the brief's bound; the module was 1,245), each opening with a docstring."""
    modules = sorted(PACKAGE.glob("*.py"))
    assert PACKAGE.name == "risk" and (PACKAGE / "__init__.py").is_file() and len(modules) >= 6, modules
    for path in modules:
        text = path.read_text(encoding="utf-8")
        assert len(text.splitlines()) <= 600, f"{path.name}: {len(text.splitlines())} lines"
        assert ast.get_docstring(ast.parse(text)), f"{path.name} does not say its job"
