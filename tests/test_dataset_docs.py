"""docs/variables.md is the variable catalog, not a copy that drifts."""

from pathlib import Path

from pipeline.dataset import FLAGS, STUDY_VARIABLES, catalog_markdown


def test_variables_page_equals_the_catalog():
    page = Path(__file__).resolve().parents[1] / "docs" / "variables.md"
    assert page.read_text() == catalog_markdown(), "regenerate: python -m pipeline.dataset > docs/variables.md"


def test_every_catalog_entry_has_units_and_a_long_name():
    for name, entry in STUDY_VARIABLES.items():
        assert entry.units and entry.long_name, name
    for name, (values, meanings, long_name) in FLAGS.items():
        assert len(values) == len(meanings.split()) and long_name, name
