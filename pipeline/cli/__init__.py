"""The ``frustum`` command.

Each command group lives in its own module and registers its sub-parser through
a ``register(subparsers)`` function; this module only assembles them.
"""

import argparse
import contextlib
import importlib
import os
import re
import signal
import sys
import threading
import warnings

from pipeline import __version__
from pipeline.errors import HazardWarning, InputError, RecordWarning

# Modules that provide ``register(subparsers)``; a module missing in a partial
# checkout is skipped so the rest of the command still works.
_COMMAND_MODULES = ("simulate", "records", "study", "workflow", "fragility", "risk", "report", "animate")


_DESCRIPTION = """\
Earthquake response of free-standing classical columns, drum stacks and colonnades: a column as a rigid
conical frustum rolling on the rim of its base (3d, the paper's model; 2d, planar rocking), a column of
drums with its capital on compliant joints (3d-compliant; the drums may be imperfect, their beds offset
and out of level within a tolerance drawn from a seed), and a colonnade, a row of such columns carrying
an epistyle (3d-compliant body by body, or 2d-frame, the rigid planar frame). Studies fan records,
angles and scales out with Dask; fragility, site risk, reports and animations follow from the files."""

_EXAMPLES = """\
examples (each command's --help has more):
  one column, a column of 4 drums with a capital, the same drums imperfect (2 mm, seed 7):
    frustum simulate --column 0.5,0.4,4 --record FEMA-FF-01 --out response.nc
    frustum simulate --column 0.5,0.4,4 --model 3d-compliant --drums 4 --capital 1.1,0.3 --record SYN-RICKER \\
        --out drums.nc
    frustum simulate --column 0.5,0.4,4 --model 3d-compliant --drums 4 --capital 1.1,0.3 --imperfections 0.002 \\
        --seed 7 --record SYN-RICKER --out imperfect.nc
  a colonnade of 3 of them under an epistyle 0.7 m high, axes 2.3 m apart (the rigid frame: --model 2d-frame),
  and the Parthenon's east front, a named colonnade, as that frame; then the row drawn moving:
    frustum simulate --column 0.5,0.4,4 --drums 3 --capital 1.1,0.3 --model 3d-compliant --colonnade 3 \\
        --interaxial 2.3 --epistyle 0.7 --record SYN-RICKER --scale 2 --out row.nc
    frustum simulate --model 2d-frame --colonnade parthenon-east --record FEMA-FF-01 --out parthenon.nc
    frustum animate row.nc --out row.gif
  a study, its report, and the risk at a site from a code's 475-year PGA:
    frustum study run studies/colonnade_quick.toml
    frustum report out/colonnade_quick.nc --out colonnade-report
    frustum risk colonnade-report/fragility.nc --hazard-pga 475:0.16 --years 50,2100 --out risk.nc
"""


class Parser(argparse.ArgumentParser):
    """An :class:`argparse.ArgumentParser` that reads every negative number as a value.

    argparse takes an argument that starts with ``-`` for an option unless it looks like a
    negative number, and before Python 3.14 only ``-5`` and ``-0.5`` do: ``--step -1e-5`` then
    ends in argparse's "expected one argument" instead of the option's own check. Python 3.14
    widened the test to any argument starting ``-<digit>`` or ``-.<digit>`` (argparse's
    ``_negative_number_matcher``, the one place argparse decides this); this class sets that
    test on every parser of the command, sub-commands included (``add_subparsers`` makes its
    parsers of the parent's class), and adds ``-inf`` and ``-nan``, which the options' checks
    refuse by name. No option of the command starts with ``-<digit>``, ``-inf`` or ``-nan``,
    which argparse requires for this reading (its "Arguments containing -" section).
    ``--step=-1e-5`` works on any Python.
    """

    #: Arguments read as a (negative) number, not as an option: Python 3.14's test, plus -inf and -nan.
    NEGATIVE_NUMBER = re.compile(r"-(?:\.?\d|inf(?:inity)?$|nan$)", re.IGNORECASE)

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = self.NEGATIVE_NUMBER


def build_parser():
    """Return the top-level argument parser with every available sub-command."""
    parser = Parser(
        prog="frustum",
        description=_DESCRIPTION,
        epilog=_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"frustum {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in _COMMAND_MODULES:
        try:
            module = importlib.import_module(f"pipeline.cli.{name}")
        except ModuleNotFoundError as exc:
            if exc.name == f"pipeline.cli.{name}":
                continue
            raise
        module.register(subparsers)
    return parser


def main(argv=None):
    """Entry point of the ``frustum`` console script; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "handler", None):
        parser.print_help()
        return 2
    try:
        with _warnings_as_lines(), _termination_as_interrupt():
            status = int(args.handler(args) or 0)
        sys.stdout.flush()  # a reader gone (`| head`) shows here, inside the handlers below, not at exit
        return status
    except InputError as exc:
        print(f"frustum: error: {exc}", file=sys.stderr)
        return 2
    except Terminated:  # a scheduler's stop (systemd, a batch system): the same clean way out as Ctrl-C
        print("frustum: terminated: run again to resume", file=sys.stderr)
        return 128 + signal.SIGTERM
    except KeyboardInterrupt:  # Ctrl-C: finished work is kept (checkpoints), no traceback
        print("frustum: interrupted: run again to resume", file=sys.stderr)
        return 130
    except BrokenPipeError:  # `frustum ... | head`: the reader has all it wanted; no traceback
        # Python flushes stdout again at exit: point it at devnull so that flush cannot raise once more
        # (the recipe of the signal module's documentation, "Note on SIGPIPE")
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 128 + signal.SIGPIPE


class Terminated(KeyboardInterrupt):
    """SIGTERM arrived: raised where the command is, so that it unwinds as from Ctrl-C (local
    clusters closed, temporary files removed, checkpoints kept)."""


@contextlib.contextmanager
def _termination_as_interrupt():
    """SIGTERM raises :class:`Terminated` while the command runs (Python's default would end the process
    on the spot, without a word and without closing what the command opened)."""
    if threading.current_thread() is not threading.main_thread():  # only the main thread may set handlers
        yield
        return

    def terminate(signum, frame):
        raise Terminated()

    previous = signal.signal(signal.SIGTERM, terminate)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


@contextlib.contextmanager
def _warnings_as_lines():
    """Print the package's own warnings as ``frustum: warning: ...`` lines (others as Python does)."""
    show = warnings.showwarning

    def one_line(message, category, filename, lineno, file=None, line=None):
        if issubclass(category, (RecordWarning, HazardWarning)):
            print(f"frustum: warning: {message}", file=sys.stderr)
        else:
            show(message, category, filename, lineno, file, line)

    warnings.showwarning = one_line
    try:
        yield
    finally:
        warnings.showwarning = show


if __name__ == "__main__":
    sys.exit(main())
