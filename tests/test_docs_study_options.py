"""docs/studies.md lists exactly the study options the code accepts, with the code's defaults."""

import dataclasses
import os
import re

from pipeline.study import studyfile
from pipeline.settings import ModelSettings

DOC = os.path.join(os.path.dirname(__file__), os.pardir, "docs", "studies.md")
HEADING = "### Model options (`[options]`)"


def _option_rows():
    """{option: (units, default)} of the options table of docs/studies.md."""
    with open(DOC, encoding="utf-8") as f:
        text = f.read()
    assert HEADING in text, f"docs/studies.md has no section {HEADING!r}"
    section = text.split(HEADING, 1)[1].split("\n#", 1)[0]
    rows = {}
    for line in section.splitlines():
        match = re.match(r"\|\s*`(\w+)`\s*\|([^|]*)\|([^|]*)\|", line)
        if match:
            name, units, default = match.groups()
            assert name not in rows, f"{name} is listed twice"
            rows[name] = (units.strip(), default.strip())
    return rows


def test_every_study_option_has_one_line_and_no_other():
    rows = _option_rows()
    missing = sorted(set(studyfile._OPTIONS) - set(rows))
    extra = sorted(set(rows) - set(studyfile._OPTIONS))
    assert not missing, f"study options missing from docs/studies.md: {missing}"
    assert not extra, f"docs/studies.md lists options a study file refuses: {extra}"


def test_numeric_defaults_are_the_code_s():
    defaults = {f.name: f.default for f in dataclasses.fields(ModelSettings)}
    for name, (_, default) in _option_rows().items():
        try:
            stated = float(default)
        except ValueError:  # a default named in words ("theta_k", "`friction`") is not a number to compare
            assert defaults.get(name) is None or not isinstance(defaults[name], (int, float)) \
                or isinstance(defaults[name], bool), f"{name}: the code's default is {defaults[name]!r}, the doc says {default!r}"
            continue
        assert stated == defaults[name], f"{name}: the doc's default is {default}, the code's {defaults[name]!r}"


def test_contact_tilt_is_in_degrees():
    # ModelSettings.contact_tilt is degrees (the CLI's --contact-tilt DEG); the doc once said rad, 1e-5
    assert _option_rows()["contact_tilt"][0] == "degree"


def test_the_models_of_each_option_are_the_ones_the_registry_says_read_it():
    """The "models" column (``all``: every model) names exactly the models whose registry entry reads
    the option, as a study checks it (an option no model of the study reads is refused, issue 38)."""
    from pipeline.models import REGISTRY

    with open(DOC, encoding="utf-8") as f:
        section = f.read().split(HEADING, 1)[1].split("\n#", 1)[0]
    rows = {m.group(1): m.group(2).strip() for m in
            re.finditer(r"^\|\s*`(\w+)`\s*\|[^|]*\|[^|]*\|([^|]*)\|", section, flags=re.MULTILINE)}
    assert set(rows) == set(studyfile._OPTIONS)
    for name, stated in rows.items():
        readers = [m.name for m in REGISTRY.values() if name in m.options]
        said = list(REGISTRY) if stated == "all" else [s.strip() for s in stated.split(",")]
        assert said == readers, f"{name}: docs/studies.md says {stated!r}, the registry {', '.join(readers)}"
