"""Shared fixtures of the study tests: small studies on synthetic records, a warm numba cache.

The studies here are small on purpose (a few short synthetic records, a few
columns): every test of the folder together stays well under three minutes on
two cores, cluster start-ups included.
"""

import textwrap

import pytest

# A small study: two short synthetic records (a Ricker wavelet and Kanai-Tajimi
# noise), a named column, an explicit column and a 2-column grid, 3 angles,
# 3 scales, both models. 4 x 2 x 3 x 3 x 2 = 144 results, 96 simulations.
SMALL_STUDY = """\
title = "small test study"
output = "small.nc"
models = ["3d", "2d"]

[[columns]]
named = "paper"

[[columns]]
name = "squat"
R = 0.6
r = 0.5
h = 3.0

[column_grid]
R = 0.4
slenderness = [7.0, 9.0]
beta = 0.9

[records]
synthetic = [
  {generator = "ricker_wavelet", id = "ricker", ap = 4.0, fp = 2.0, dt = 0.01},
  {generator = "kanai_tajimi", id = "kt-1", seed = 1, duration = 6.0, dt = 0.01, pga = 3.0},
]

[excitation]
angles = [0.0, 30.0, 90.0]
scales = [0.5, 1.0, 2.0]

[options]
tail = 2.0

[execution]
block_columns = 2
"""


# A small study of the compliant model: a monolith and the same column as two drums, a 1.5-s
# Ricker wavelet, 2 angles: 2 tasks (one column each) of 2 compliant runs (~1 s each) and one 3d run.
DRUM_STUDY = """\
title = "drums on a cluster"
output = "drums.nc"
models = ["3d", "3d-compliant"]

[[columns]]
named = "paper"

[[columns]]
name = "two-drums"
R = 0.5
r = 0.4
h = 4.0
drums = 2

[records]
synthetic = [{generator = "ricker_wavelet", id = "ricker", ap = 8.0, fp = 2.0, dt = 0.01, duration = 1.5}]

[excitation]
angles = [0.0, 30.0]
scales = [1.0]

[options]
tail = 0.5
contact_sectors = 16
joint_friction = 0.4

[execution]
block_columns = 1
"""


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
