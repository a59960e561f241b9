"""The README's examples are true on a fresh clone (issue 38, item 5).

Every ``frustum`` command of the README's ``sh`` blocks parses with the real command line, and
every file it reads is in the repository or written by a command before it (run from the
checkout root, as the README says). Before, the README read ``RSN6_ELC180.AT2``,
``elcentro.g3`` and ``hazard_curve-mean-PGA_1.csv``, which no clone holds, and
``out/quickstart-fragility.nc``, which ``frustum fragility`` in its own help names
``out/quickstart_fragility.nc``. The example files load as the commands read them, and every
repository path the README's text names exists.
"""

import os
import re
import shlex
import subprocess
from pathlib import Path

import pytest

from pipeline.cli import build_parser

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
#: Options whose value is a file or folder a command writes.
OUTPUTS = ("out", "plot", "csv", "animate")
#: Where the README's text names files of the repository (``out/`` is written, not held).
REPOSITORY_FOLDERS = (".ci", "pipeline", "studies", "docs", "records", "tests", "benchmarks", "workflows", "examples")


def _commands(text=None):
    """The README's ``frustum`` commands in order, each as its argv (continuation lines joined, comments dropped)."""
    text = README.read_text(encoding="utf-8") if text is None else text
    commands = []
    for block in re.findall(r"```sh\n(.*?)```", text, re.S):
        for line in block.replace("\\\n", " ").splitlines():
            argv = shlex.split(line, comments=True)
            if argv and argv[0] == "frustum":
                commands.append(argv[1:])
    return commands


def _in_repository():
    """Paths git holds (a fresh clone has these and no others); without git, what is on disk."""
    try:
        listed = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    files = set(listed.splitlines())
    return files | {str(Path(f).parent) for f in files}


def _section(title):
    """The README's text under ``## title`` up to the next ``## `` heading."""
    text = README.read_text(encoding="utf-8")
    match = re.search(rf"^## {re.escape(title)}\n(.*?)(?=^## |\Z)", text, re.S | re.M)
    assert match, f"README.md has no section '## {title}'"
    return match.group(1)


def _written_before(path, written):
    """Whether ``path`` or a folder holding it was written by an earlier command (``frustum report --out DIR``
    writes ``DIR/fragility.nc``, as its help says)."""
    path = os.path.normpath(path)
    return any(p in written for p in [path, *map(str, Path(path).parents)] if p != ".")


def _held(path, held):
    path = os.path.normpath(path)
    return (ROOT / path).exists() if held is None else path in held


def _looks_like_a_path(value):
    return "/" in value or re.search(r"\.[A-Za-z][A-Za-z0-9]*$", value) is not None


def _reads_and_writes(args):
    """(files read, files written) of a parsed command, as given on its command line."""
    reads, writes = [], []
    for name, value in vars(args).items():
        values = value if isinstance(value, list) else [value]
        for one in values:
            if not isinstance(one, str):
                continue
            parts = one.split(",") if name == "record" else [one]  # --record X,Y[,Z]: files of one record
            for part in parts:
                if name in OUTPUTS:  # a file or a folder (frustum report --out DIR)
                    writes.append(part)
                elif _looks_like_a_path(part):
                    reads.append(part)
    if args.command == "study" and getattr(args, "study_command", None) == "run" and args.out is None:
        from pipeline.study.studyfile import load_study

        output = load_study(ROOT / args.file, load_records=False).output  # where the study file says it writes
        writes.append(os.path.relpath(output, ROOT))
    return reads, writes


def _parse(argv):
    """``argv`` parsed by the real command line, or the error argparse would print (it exits)."""
    import contextlib
    import io

    parser, err = build_parser(), io.StringIO()
    try:
        with contextlib.redirect_stderr(err):
            return parser.parse_args(argv)
    except SystemExit:
        return "frustum " + shlex.join(argv) + ": " + err.getvalue().strip().splitlines()[-1]


@pytest.fixture(scope="module")
def commands():
    parsed = [_parse(argv) for argv in _commands() if "--help" not in argv]
    assert len(parsed) >= 15  # the premise: the README's examples were found
    assert [p for p in parsed if isinstance(p, str)] == []  # every one parses
    return parsed


def test_every_command_of_using_it_parses_with_the_real_command_line():
    """Each ``frustum`` line of "Using it" (continuation lines joined) is a command ``frustum`` accepts."""
    argvs = [argv for argv in _commands(_section("Using it")) if "--help" not in argv]
    assert len(argvs) >= 25  # the premise: the single column's block and the colonnades' block
    assert [p for p in map(_parse, argvs) if isinstance(p, str)] == []


def test_using_it_shows_colonnades_imperfect_drums_one_component_and_code_hazard():
    """Issue 47 item 6 and issue 48: "Using it" runs the rigid frame, a compliant row with its capitals,
    interaxial and epistyle, a named colonnade, animates a frame and a row from the files they wrote, runs a
    colonnade study driven by one component and reports on it, runs imperfect drums from a seed, and a risk
    from a code's 475-year PGA over 50 and 2,100 years."""
    from pipeline.study.studyfile import load_study

    runs = [_parse(argv) for argv in _commands(_section("Using it")) if "--help" not in argv]
    simulated = {a.out: a for a in runs if a.command == "simulate"}
    rows = [a for a in simulated.values() if a.colonnade]
    assert any(a.model == "2d-frame" and a.colonnade.isdigit() and a.interaxial and a.epistyle for a in rows)
    assert any(a.model == "3d-compliant" and a.colonnade.isdigit() and a.capital and a.interaxial and a.epistyle
               for a in rows)
    assert any(a.colonnade == "parthenon-east" for a in rows)
    animated = [simulated[a.result] for a in runs if a.command == "animate" and a.result in simulated]
    assert {a.model for a in animated if a.colonnade} >= {"2d-frame", "3d-compliant"}
    assert any(a.imperfections and a.seed is not None for a in simulated.values())
    studies = [a for a in runs if a.command == "study" and a.study_command == "run"]
    one_component = [load_study(ROOT / a.file, load_records=False) for a in studies]
    one_component = [st for st in one_component if st.components == "x" and any(c.colonnade for c in st.columns)]
    assert one_component, "no colonnade study driven by one component"
    reported = {os.path.normpath(f) for a in runs if a.command == "report" for f in a.results}
    assert {os.path.relpath(st.output, ROOT) for st in one_component} & reported
    assert any(a.command == "risk" and a.hazard_pga == "475:0.16" and a.hazard_slope == 3
               and a.years == "50,2100" for a in runs)


def test_the_readme_names_every_study_folder():
    """Each folder of ``studies/`` a clone holds is named in the README (before, ``studies/colonnade/``
    and ``studies/imperfections/`` were not)."""
    held = _in_repository()
    if held is None:  # without git, what is on disk
        held = {str(p.relative_to(ROOT)) for p in (ROOT / "studies").rglob("*") if p.is_file()}
    folders = sorted({Path(p).parts[1] for p in held if p.startswith("studies/") and len(Path(p).parts) > 2})
    assert len(folders) >= 10  # the premise
    text = README.read_text(encoding="utf-8")
    assert [f for f in folders if f"`studies/{f}/`" not in text] == []


def test_every_file_a_readme_command_reads_is_in_the_repository_or_written_before(commands):
    held = _in_repository()
    written, missing = set(), []
    for args in commands:
        reads, writes = _reads_and_writes(args)
        missing += [f"frustum {args.command}: {path}" for path in reads
                    if not _written_before(path, written) and not _held(path, held)]
        written.update(os.path.normpath(path) for path in writes)
    assert missing == [], "\n".join(missing)
    assert {"out/quickstart.nc", "out/drums_vs_rigid/paper.nc"} <= written  # the premise: studies' outputs found


def _help_examples(parser):
    """The examples of every ``frustum`` command's ``--help`` (their epilogs), as one text."""
    texts = [parser.epilog or ""]
    for action in parser._actions:
        if isinstance(getattr(action, "choices", None), dict):
            texts += [_help_examples(sub) for sub in action.choices.values()]
    return "\n".join(texts)


def test_the_readme_names_each_output_as_the_help_or_its_study_file_does(commands):
    """A file under ``out/`` has one name: the one a study file writes or a command's --help uses (before,
    the README wrote out/quickstart-fragility.nc, the help of frustum fragility and risk
    out/quickstart_fragility.nc)."""
    examples = _help_examples(build_parser())
    studies = set()
    named = []
    for args in commands:
        reads, writes = _reads_and_writes(args)
        if args.command == "study":
            studies.update(os.path.normpath(w) for w in writes if w.endswith(".nc"))
        named += [os.path.normpath(p) for p in reads + writes if os.path.normpath(p).startswith("out" + os.sep)]
    assert len(named) >= 6  # the premise
    assert [p for p in named if p not in studies and not re.search(rf"(?<![\w/-]){re.escape(p)}(?![\w.-])",
                                                                     examples)] == []


def test_the_readme_example_files_load_as_its_commands_read_them(commands):
    """The record files through the loader of --record with the command's own options, without a warning
    (they are processed as a recording would be); the hazard curve through pipeline.risk's reader."""
    import warnings

    import numpy as np

    from pipeline.cli.records import load_record
    from pipeline.errors import RecordWarning
    from pipeline.risk import read_hazard_curve
    from pipeline.units import G

    records = {}
    hazard = None
    with warnings.catch_warnings():
        warnings.simplefilter("error", RecordWarning)
        for args in commands:
            if args.command == "simulate" and args.record and _looks_like_a_path(args.record):
                records[args.record] = load_record(args)
            if args.command == "risk" and args.hazard:  # a hazard curve file (not --hazard-pga's code values)
                hazard = read_hazard_curve(args.hazard)
    assert len(records) == 2 and hazard is not None  # the AT2 pair, the record in g, the hazard curve
    pair = next(gm for name, gm in records.items() if "," in name)
    column = next(gm for name, gm in records.items() if "," not in name)
    # examples/make_examples.py: 10 s at 0.01 s, the larger peak 0.3 g (AT2: 7 significant digits)
    for gm in (pair, column):
        assert gm.dt == pytest.approx(0.01) and gm.duration == pytest.approx(10.0)
    assert max(np.abs(pair.acc_x).max(), np.abs(pair.acc_y).max()) / G == pytest.approx(0.3, rel=1e-6)
    # the record in g is the pair's x component (6 decimals of g: within 5e-7 g), its y given as zero
    np.testing.assert_allclose(column.acc_x / G, pair.acc_x / G, rtol=0, atol=5.1e-7)
    assert not np.any(column.acc_y) and np.abs(pair.acc_y).max() > 0.1 * G
    assert hazard.im == "pga" and hazard.investigation_time == 50.0 and len(hazard.sites) == 1
    assert hazard.levels.size == 18 and np.all(np.diff(hazard.rate[0]) < 0)  # rates fall as the PGA rises


def test_every_repository_path_the_readme_names_exists():
    held = _in_repository()
    text = README.read_text(encoding="utf-8")
    named = [token for token in re.findall(r"`([^`\s]+)`", text)
             if token.split("/")[0] in REPOSITORY_FOLDERS and "/" in token]
    assert len(named) >= 10  # the premise
    assert [path for path in named if not _held(path.rstrip("/"), held)] == []


def test_the_licence_is_an_spdx_expression_and_the_build_asks_for_a_setuptools_that_reads_it():
    """``license = { text = "MIT" }`` made setuptools (>= 77, which pip picks for the build) print a
    deprecation warning twice on every install; an SPDX string needs setuptools >= 77 to be read.
    Checked by hand: in a fresh venv with pip upgraded (26.3, as ``make`` does), ``pip install -e .``
    printed it three times before and no longer prints it."""
    import tomllib

    data = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    assert data["project"]["license"] == "MIT"
    (setuptools,) = [r for r in data["build-system"]["requires"] if r.startswith("setuptools")]
    minimum = re.fullmatch(r"setuptools>=(\d+)(?:\.\d+)*", setuptools.replace(" ", ""))
    assert minimum and int(minimum.group(1)) >= 77, setuptools


def test_every_file_a_help_example_reads_is_in_the_repository_or_a_placeholder():
    """A ``--help`` example reads files a clone holds (``examples/``, ``studies/``), files an earlier example
    writes (``out/``), or a placeholder in capitals (``YOUR_STATION.mseed``) a reader sees is theirs to supply.
    Before, they read RSN6_ELC180.AT2, elcentro.g3, quake.mseed and hazard_curve-mean-PGA_12.csv (issue 38,
    item 5)."""
    held = _in_repository()
    examples = _help_examples(build_parser()).replace("\\\n", " ")
    parser = build_parser()
    parsed = [parser.parse_args(shlex.split(line.strip(), comments=True)[1:]) for line in examples.splitlines()
              if line.strip().startswith("frustum ") and "--help" not in line]  # not a caption
    written = {os.path.normpath(p) for args in parsed for p in _reads_and_writes(args)[1]}
    missing, checked = [], 0
    for args in parsed:
        for path in _reads_and_writes(args)[0]:
            if path.startswith("tcp://") or path in ("m/s2", "m/s", "cm/s2"):
                continue  # a scheduler's address, a unit: not files
            checked += 1
            if not (_written_before(path, written) or path.startswith("out/")  # a study's (test above)
                    or os.path.basename(path).startswith("YOUR_")
                    or _held(path, held)):
                missing.append(f"frustum {args.command}: {path}")
    assert checked >= 10  # the premise: the examples' files were found
    assert missing == [], "\n".join(missing)
