"""Files are written atomically with the permissions the umask allows (issue 11)."""

import os
import stat

import numpy as np
import pytest
import xarray as xr

from pipeline.atomic import PARTIAL_PREFIX, atomic_open


@pytest.fixture
def umask():
    """Set a umask for one test and restore the previous one."""
    previous = os.umask(0o022)

    def set_mask(mask):
        os.umask(mask)

    yield set_mask
    os.umask(previous)


def _mode(path):
    return stat.S_IMODE(os.stat(path).st_mode)


def _write_everything(folder):
    """One file of every kind the project writes; returns their paths."""
    from pipeline import report
    from pipeline.dataset import write_netcdf
    from pipeline.groundmotion import synthesis
    from pipeline.study.checkpoint import Checkpoint

    paths = [folder / "a.nc"]
    write_netcdf(xr.Dataset({"v": ("t", np.arange(3.0))}), paths[0])
    ckpt = Checkpoint(str(folder / "a.nc.checkpoint"), "key")
    ckpt.save({"index": 0, "record": 0, "start": 0, "stop": 1, "runs": 1, "seconds": 0.0, "errors": [],
               "arrays": {}})
    ckpt.release()
    paths += [folder / "a.nc.checkpoint" / "task-000000.npz", folder / "a.nc.checkpoint" / "manifest.json"]
    paths.append(folder / "summary.csv")
    report._write_csv([{"column": "paper", "p": 0.5}], paths[-1])
    gm = synthesis.one_sine_pulse(1.0, 0.5, dt=0.01, record_id="p")
    paths += gm.write(folder / "p.mseed")
    paths += gm.write(folder / "p.AT2", format="AT2")
    return paths


@pytest.mark.parametrize("mask, expected", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_files_get_the_permissions_of_the_umask(tmp_path, umask, mask, expected):
    umask(mask)
    paths = _write_everything(tmp_path)
    assert len(paths) == 7
    assert {p.name: oct(_mode(p)) for p in paths} == {p.name: oct(expected) for p in paths}
    leftovers = [p for p in tmp_path.rglob("*") if p.name.startswith(PARTIAL_PREFIX)]
    assert leftovers == []


def test_a_failed_write_leaves_nothing(tmp_path):
    target = tmp_path / "out.txt"
    target.write_text("old")
    with pytest.raises(RuntimeError, match="disk on fire"):
        with atomic_open(target, "w") as fh:
            fh.write("half")
            raise RuntimeError("disk on fire")
    assert target.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.txt"]
