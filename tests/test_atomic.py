"""atomic_path: the file appears complete or not at all, with the permissions open() would give."""

import os
import stat

import pytest

from pipeline.atomic import atomic_path


def test_renamed_on_success_with_the_umask_permissions(tmp_path):
    old = os.umask(0o022)
    try:
        with atomic_path(tmp_path / "sub" / "out.txt") as tmp:
            assert os.path.dirname(tmp) == str(tmp_path / "sub")
            with open(tmp, "w") as fh:
                fh.write("done")
    finally:
        os.umask(old)
    target = tmp_path / "sub" / "out.txt"
    assert target.read_text() == "done"
    assert stat.S_IMODE(target.stat().st_mode) == 0o644  # not mkstemp's 0600
    assert os.listdir(tmp_path / "sub") == ["out.txt"]


def test_nothing_left_on_failure(tmp_path):
    with pytest.raises(RuntimeError), atomic_path(tmp_path / "out.nc", suffix=".nc") as tmp:
        assert tmp.endswith(".nc")
        open(tmp, "w").close()
        raise RuntimeError("disk full")
    assert os.listdir(tmp_path) == []
