"""The paper is cited right everywhere: Stefanou, Vardoulakis & Mavraganis (2011).

Earlier versions named other authors. This test reads every file git tracks
(code, docs, study files, committed reports) for those names, and checks that
the places that cite the paper in full carry the one reference of
:mod:`pipeline.citation`. That every output file and report carries it is
checked where they are made (tests/test_netcdf_convention.py,
tests/fragility/test_cli_report.py).
"""

import subprocess
from pathlib import Path

import pytest

from pipeline.citation import AUTHORS_SHORT, REFERENCE

ROOT = Path(__file__).resolve().parents[1]
# spelled in two parts so that this file does not match itself
WRONG = ("Psych" + "aris", "Georgo" + "poulos")


def _tracked_text_files():
    try:
        names = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        pytest.fail("tests/test_citation.py reads the files git tracks: run it in a git checkout")
    for name in names.splitlines():
        path = ROOT / name
        if path.is_file() and path.suffix not in (".png", ".pdf", ".gif", ".mp4", ".nc", ".npz", ".AT2", ".xml"):
            yield path


def test_no_file_names_the_wrong_authors():
    offenders = []
    for path in _tracked_text_files():
        text = path.read_text(encoding="utf-8", errors="replace")
        offenders += [f"{path.relative_to(ROOT)}: {w}" for w in WRONG if w in text]
    assert not offenders, "wrong authors of the paper (use pipeline.citation): " + ", ".join(offenders)


@pytest.mark.parametrize("name", ["README.md", "docs/model.md", "docs/misprints.md", "studies/paper/README.md"])
def test_documents_give_the_full_reference(name):
    assert REFERENCE in (ROOT / name).read_text(encoding="utf-8")


def test_the_paper_column_names_its_source():
    import tomllib

    with open(ROOT / "pipeline" / "data" / "columns.toml", "rb") as fh:
        paper = tomllib.load(fh)["paper"]
    assert paper["source"].startswith(REFERENCE)


def test_the_reference_is_the_paper():
    assert REFERENCE.startswith("Stefanou I., Vardoulakis I., Mavraganis A. (2011), Dynamic motion of a conical "
                                "frustum over a rough horizontal plane")
    assert "International Journal of Non-Linear Mechanics 46(1), 114-124" in REFERENCE
    assert AUTHORS_SHORT == "Stefanou, Vardoulakis & Mavraganis"
