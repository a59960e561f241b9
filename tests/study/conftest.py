"""Shared fixtures of the study tests: small studies on synthetic records, a warm numba cache.

The studies here are small on purpose (a few short synthetic records, a few
columns): every test of the folder together stays well under three minutes on
two cores, cluster start-ups included.
"""

import sys
import textwrap
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))

from study_files import DRUM_STUDY, SMALL_STUDY  # noqa: E402


@pytest.fixture(scope="session", autouse=True)
def warm_numba_cache():
    """Load (or, if stale, compile once) the kernels before any worker starts."""
    from pipeline.study.kernels import warm_up

    warm_up(("3d", "2d"))


@pytest.fixture
def write_study(tmp_path):
    """Write a study file in a temporary folder; returns its path."""

    def write(text=SMALL_STUDY, name="study.toml"):
        path = tmp_path / name
        path.write_text(textwrap.dedent(text), encoding="utf-8")
        return path

    return write


@pytest.fixture(scope="session")
def small_reference(tmp_path_factory):
    """The small study run serially once: (study file, results Dataset)."""
    from pipeline.study import load_study, run_study

    folder = tmp_path_factory.mktemp("reference")
    path = folder / "study.toml"
    path.write_text(SMALL_STUDY, encoding="utf-8")
    report = run_study(load_study(path), serial=True, progress=False)
    return path, report.dataset


@pytest.fixture(scope="session")
def drum_reference(tmp_path_factory):
    """The drum study run serially once: (study file, results Dataset)."""
    from pipeline.study import load_study, run_study

    folder = tmp_path_factory.mktemp("drum-reference")
    path = folder / "drums.toml"
    path.write_text(DRUM_STUDY, encoding="utf-8")
    report = run_study(load_study(path), serial=True, progress=False)
    return path, report.dataset


@pytest.fixture(scope="session")
def same_results():
    """The comparison of two results Datasets (see :func:`assert_same_results`)."""
    return assert_same_results


def assert_same_results(a, b):
    """Identical numbers in every data variable and numeric coordinate (NaN == NaN)."""
    import numpy as np

    assert set(a.data_vars) == set(b.data_vars)
    for name in list(a.data_vars) + [n for n in a.coords if a[n].dtype.kind in "fiu"]:
        x, y = a[name].values, b[name].values
        assert x.dtype == y.dtype, name
        assert np.array_equal(x, y, equal_nan=x.dtype.kind == "f"), name
    for name in ("column", "record", "model", "record_sha256"):
        assert list(a[name].values) == list(b[name].values), name
