"""Helpers of the command-line tests (a module of its own: ``conftest`` is a name several test folders use)."""

import textwrap
from pathlib import Path

# One column, one 2-s Ricker wavelet, one angle, one scale, the 3D model: one task, one simulation.
TINY_STUDY = textwrap.dedent("""\
    title = "tiny study"
    output = "tiny.nc"
    models = ["3d"]

    [[columns]]
    named = "paper"

    [records]
    synthetic = [{generator = "ricker_wavelet", id = "ricker", ap = 4.0, fp = 2.0, dt = 0.01}]

    [excitation]
    angles = [0.0]
    scales = [1.0]

    [options]
    tail = 0.5
""")


def snapshot(*paths):
    """{path: bytes} of files, to assert they are byte-identical after a command."""
    return {Path(p): Path(p).read_bytes() for p in paths}


def unchanged(before):
    """Whether every file of a :func:`snapshot` still has its bytes."""
    return all(p.is_file() and p.read_bytes() == data for p, data in before.items())
