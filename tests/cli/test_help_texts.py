"""The help a new user reads names what the command runs: colonnades, drums and imperfect drums (issue 47,
item 6; issue 48).

Before, ``frustum --help`` said "columns modelled as rigid conical frustums" and nothing else,
``frustum animate --help`` showed no compliant row, and ``frustum simulate --help`` said a colonnade's
spacing need only be "at least the abacus side" while runs refuse spacings, epistyle heights and widths
beyond stated bounds. The examples' commands parse and read files a clone holds (``tests/test_readme.py``,
which also reads these epilogs).
"""

import re
import shlex

from pipeline.cli import build_parser
from pipeline.errors import InputError
from pipeline.structures.colonnade import Colonnade
from pipeline.structures.column import Column


def _subparser(parser, name):
    (choices,) = [a.choices for a in parser._actions if isinstance(getattr(a, "choices", None), dict)]
    return choices[name]


def _example_commands(epilog):
    """The ``frustum`` command lines of an epilog, continuation lines joined, each as its argv."""
    lines = epilog.replace("\\\n", " ").splitlines()
    return [shlex.split(line.strip())[1:] for line in lines if line.strip().startswith("frustum ")]


def _words(text):
    return " ".join(text.split())  # argparse rewraps; compare words


def test_frustum_help_names_colonnades_drums_and_imperfections_with_examples_that_parse():
    parser = build_parser()
    text = _words(parser.format_help())
    for word in ("colonnade", "drums", "epistyle", "imperfect", "2d-frame", "3d-compliant"):
        assert word in text, word
    examples = _example_commands(parser.epilog or "")
    parsed = [parser.parse_args(argv) for argv in examples]
    simulated = [a for a in parsed if a.command == "simulate"]
    # a colonnade given by its dimensions, a named one, imperfect drums; each example parses as given
    assert any(a.colonnade == "3" and a.interaxial and a.epistyle for a in simulated)
    assert any(a.colonnade == "parthenon-east" for a in simulated)
    assert any(a.imperfections and a.seed is not None for a in simulated)
    assert {a.command for a in parsed} >= {"simulate", "animate", "study", "report", "risk"}


def test_animate_help_draws_a_frame_and_a_compliant_row_with_an_example_of_each():
    """The help says a 2d-frame result is drawn as the frame and a compliant row body by body, and shows
    ``frustum animate`` of a file written by each model's colonnade run."""
    parser = build_parser()
    sub = _subparser(parser, "animate")
    text = _words(sub.format_help())
    assert "2d-frame result as the frame" in text and "3d-compliant row body by body" in text
    written, animated = {}, []
    for argv in _example_commands(sub.epilog):
        args = parser.parse_args(argv)
        if args.command == "simulate":
            written[args.out] = args
        else:
            animated.append(written[args.result])  # what the example animates, as an example before wrote it
    assert {args.model for args in animated if args.colonnade} == {"2d-frame", "3d-compliant"}


def _help_of(option):
    sub = _subparser(build_parser(), "simulate")
    (action,) = [a for a in sub._actions if option in a.option_strings]
    return _words(action.help)


def test_simulate_help_states_the_colonnade_bounds_that_runs_refuse():
    """The numbers the help of --interaxial and --epistyle states are where a colonnade is refused: just
    beyond each is refused (InputError naming the field), just within it is accepted (1 % either side)."""
    spacing = re.search(r"at most ([\d.]+) m and ([\d.]+) base diameters", _help_of("--interaxial"))
    epistyle = re.search(r"a height from 1/([\d.]+) of the interaxial to ([\d.]+) of the columns' height, "
                         r"a width ([\d.]+) to ([\d.]+) times the abacus side", _help_of("--epistyle"))
    assert spacing and epistyle, (_help_of("--interaxial"), _help_of("--epistyle"))
    metres, diameters = map(float, spacing.groups())
    span_depth, fraction, narrowest, widest = map(float, epistyle.groups())

    def refused(column, interaxial, height, width=None, field=""):
        try:
            Colonnade(column, 2, interaxial, height, width)
        except InputError as exc:
            assert field in str(exc)
            return True
        return False

    slim = Column(0.5, 0.4, 4.0)  # base diameter 1 m: the bound in diameters binds (5 m < 10 m)
    assert diameters * 1.0 < metres
    assert refused(slim, 1.01 * diameters, 1.0, field="interaxial")
    assert not refused(slim, 0.99 * diameters, 1.0)
    stout = Column(1.5, 1.2, 20.0)  # base diameter 3 m: the bound in metres binds
    assert refused(stout, 1.01 * metres, 2.0, field="interaxial")
    assert not refused(stout, 0.99 * metres, 2.0)
    # the epistyle on the slim column without capital: its abacus side 2 r = 0.8 m, its height 4 m
    assert refused(slim, 2.0, 0.99 * 2.0 / span_depth, field="epistyle_height")
    assert not refused(slim, 2.0, 1.01 * 2.0 / span_depth)
    assert refused(slim, 2.0, 1.01 * fraction * 4.0, field="epistyle_height")
    assert not refused(slim, 2.0, 0.99 * fraction * 4.0)
    assert refused(slim, 2.0, 0.5, 0.99 * narrowest * 0.8, field="epistyle_width")
    assert refused(slim, 2.0, 0.5, 1.01 * widest * 0.8, field="epistyle_width")
    assert not refused(slim, 2.0, 0.5, 1.01 * narrowest * 0.8)
    assert not refused(slim, 2.0, 0.5, 0.99 * widest * 0.8)


def test_the_one_line_help_of_simulate_says_it_runs_drums_and_colonnades():
    """``frustum --help`` lists each command with one line: simulate's said "one column" (animate's already
    said "column or colonnade")."""
    parser = build_parser()
    (action,) = [a for a in parser._actions if isinstance(getattr(a, "choices", None), dict)]
    (line,) = [c.help for c in action._choices_actions if c.dest == "simulate"]
    assert "drums" in line and "colonnade" in line
