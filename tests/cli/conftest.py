"""Shared files of the command-line tests: a tiny study, study results, a histories file, a user's files.

Study results are synthetic (:mod:`fragility_synthetic`, written by the
project's writer so they carry its global attributes); the one histories
file comes from a short ``frustum simulate`` run, made once per session.
"""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parents[1] / "fragility"))  # the synthetic study results
sys.path.insert(0, str(Path(__file__).parent))

from cli_files import TINY_STUDY  # noqa: E402


@pytest.fixture(scope="session")
def results_nc(tmp_path_factory):
    """A study results file written by the project (synthetic values)."""
    from fragility_synthetic import make_results

    from pipeline.dataset import write_results

    ds, _ = make_results(columns=("paper",), n_records=6, angles=(0.0,), scales=(0.5, 1.0, 2.0), models=("3d",))
    return Path(write_results(ds, tmp_path_factory.mktemp("results") / "results.nc"))


@pytest.fixture(scope="session")
def failed_results_nc(tmp_path_factory):
    """Study results in which every cell failed (status 1, NaN): nothing can be fitted or drawn."""
    import numpy as np
    from fragility_synthetic import make_results

    from pipeline.dataset import write_results

    ds, _ = make_results(columns=("paper",), n_records=6, angles=(0.0,), scales=(0.5, 1.0), models=("3d",))
    ds["status"][:] = 1
    for name, var in ds.data_vars.items():
        if var.dtype.kind == "f" and name not in ("pga", "pgv", "sa"):
            var[:] = np.nan
    return Path(write_results(ds, tmp_path_factory.mktemp("failed") / "failed.nc"))


@pytest.fixture(scope="session")
def foreign_labels_nc(tmp_path_factory):
    """Study results of a colonnade whose ``overturn_body`` names a body in words this project does not write
    ("column 2 pillar"), as another program might."""
    import numpy as np
    from fragility_synthetic import make_colonnade_results

    from pipeline.dataset import write_results

    ds, _ = make_colonnade_results(columns=("row",), n_records=6, angles=(0.0,), scales=(0.5, 1.0, 2.0),
                                   models=("3d-compliant",))
    bodies = ds["overturn_body"].values.copy()
    bodies.flat[np.flatnonzero(bodies != "")[0]] = "column 2 pillar"
    ds["overturn_body"] = (ds["overturn_body"].dims, bodies)
    return Path(write_results(ds, tmp_path_factory.mktemp("foreign") / "foreign.nc"))


@pytest.fixture(scope="session")
def old_frame_nc(tmp_path_factory):
    """A histories file of the rigid frame (2d-frame, 2 columns, SYN-RICKER and 0.5 s of tail) as written before files
    recorded their structure: without its ``n_columns`` attribute."""
    import netCDF4

    from pipeline.cli import main

    path = tmp_path_factory.mktemp("frame") / "frame.nc"
    assert main(["simulate", "--column", "0.5,0.4,4", "--model", "2d-frame", "--colonnade", "2", "--interaxial", "2",
                 "--epistyle", "0.5", "--record", "SYN-RICKER", "--tail", "0.5", "--output-step", "0.02", "--out",
                 str(path)]) == 0
    with netCDF4.Dataset(path, "a") as nc:
        nc.delncattr("n_columns")
    return path


@pytest.fixture(scope="session")
def histories_nc(tmp_path_factory):
    """A histories file of ``frustum simulate`` (3D model, SYN-RICKER and 0.5 s of tail)."""
    from pipeline.cli import main

    path = tmp_path_factory.mktemp("histories") / "histories.nc"
    assert main(["simulate", "--column", "0.5,0.4,4", "--record", "SYN-RICKER", "--tail", "0.5",
                 "--output-step", "0.02", "--out", str(path)]) == 0
    return path


@pytest.fixture
def user_files(tmp_path):
    """A user's files that no command may replace: {name: path}, and their bytes to compare afterwards."""
    files = {
        "notes.txt": b"my notes\n",
        "study.toml": TINY_STUDY.encode(),
        "record.txt": b"0.0\n0.1\n-0.1\n0.0\n",
    }
    paths = {}
    for name, data in files.items():
        paths[name] = tmp_path / name
        paths[name].write_bytes(data)
    return paths
