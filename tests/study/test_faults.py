"""Faults get one clear answer and lose nothing (issue 11): damaged checkpoints, grids too big for
memory, outputs that cannot be written, full disks, Ctrl-C."""

import errno
import os
import textwrap
import time

import pytest
import xarray as xr

from pipeline.cli import main
from pipeline.dataset import open_results
from pipeline.errors import InputError
from pipeline.study import load_study, run_study

from study_files import SMALL_STUDY

N_TASKS = 4  # SMALL_STUDY: 4 columns in blocks of 2 x 2 records


def _task_files(checkpoint):
    return sorted(p for p in os.listdir(checkpoint) if p.startswith("task-")) if os.path.isdir(checkpoint) else []


def test_a_truncated_checkpoint_costs_one_recomputed_task(write_study, small_reference, same_results, capsys):
    path = write_study()
    checkpoint = str(path.parent / "small.nc") + ".checkpoint"
    run_study(load_study(path), serial=True, progress=False, keep_checkpoint=True)
    damaged = os.path.join(checkpoint, "task-000002.npz")
    data = open(damaged, "rb").read()
    with open(damaged, "wb") as fh:
        fh.write(data[: len(data) // 2])  # as a full disk or a crash of the file system leaves it
    capsys.readouterr()

    report = run_study(load_study(path), serial=True, progress=False)
    assert report.computed == [2] and report.skipped == [0, 1, 3]
    err = capsys.readouterr().err
    assert f"checkpoint file {damaged} is damaged (BadZipFile" in err and "its task is computed again" in err
    same_results(report.dataset, small_reference[1])


def _grid_study(n_angles, n_scales):
    angles = ", ".join(f"{0.1 * i:.1f}" for i in range(n_angles))
    scales = ", ".join(f"{1 + 0.001 * i:.3f}" for i in range(n_scales))
    slender = ", ".join(f"{4 + 0.1 * i:.1f}" for i in range(100))
    synthetic = ",\n  ".join(f'{{generator = "ricker_wavelet", id = "r{i}", ap = 4.0, fp = 2.0, dt = 0.01}}'
                             for i in range(10))
    return textwrap.dedent(f"""\
        title = "too big"
        [column_grid]
        R = 0.5
        slenderness = [{slender}]
        beta = 0.8
        [records]
        synthetic = [
          {synthetic}
        ]
        [excitation]
        angles = [{angles}]
        scales = [{scales}]
    """)


def test_a_grid_that_cannot_fit_is_refused_with_its_size(write_study, capsys, monkeypatch):
    from pipeline import limits, study as study_module

    monkeypatch.setattr(limits, "available_memory", lambda: 16 * 2**30)
    loaded = []
    monkeypatch.setattr(study_module, "load_motions", lambda s: loaded.append(s) or [])
    path = write_study(_grid_study(1000, 1000))  # 100 columns x 10 records x 1000 x 1000 = 1e9 results
    t0 = time.monotonic()
    for command in (["study", "check", str(path)], ["study", "run", str(path), "--serial", "--quiet"]):
        assert main(command) == 2
        err = capsys.readouterr().err
        assert ("the results grid of 1,000,000,000 cells (100 columns x 10 records x 1,000 angles x 1,000 scales "
                "x 1 models, 1,000 tasks) needs about 166 GiB of memory; this machine has 16 GiB available: split "
                "the study") in err, err
    assert time.monotonic() - t0 < 10.0 and loaded == []  # refused before the records were loaded
    assert not (path.parent / "study.nc.checkpoint").exists()
    with pytest.raises(InputError, match="needs about 166 GiB"):
        run_study(load_study(path, load_records=False), serial=True, progress=False)
    # the small study fits and says how much it needs
    assert main(["study", "check", str(write_study(name="small.toml"))]) == 0
    assert "memory: about 300 MiB (16 GiB available)" in capsys.readouterr().out


@pytest.mark.parametrize("output, message", [
    ('"/"', "field output: '/' is a folder; give the path of a file"),
    ('"results/"', "field output: 'results/' is a folder"),
    ('"/proc/small.nc"', "field output '/proc/small.nc': /proc cannot be written"),
])
def test_bad_outputs_are_refused_before_computing(write_study, capsys, monkeypatch, output, message):
    from pipeline.study import orchestrate

    monkeypatch.setattr(orchestrate, "run_task", lambda *a: pytest.fail("computed before refusing"))
    path = write_study(SMALL_STUDY.replace('output = "small.nc"', f"output = {output}"))
    for command in (["study", "check", str(path)], ["study", "run", str(path), "--serial", "--quiet"]):
        if "/proc" in output and command[1] == "check":
            continue  # check reads the study; only run writes
        assert main(command) == 2
        err = capsys.readouterr().err
        assert message in err and len(err.splitlines()) == 1, err
    assert not os.path.exists("/.checkpoint") and not os.path.exists("/proc/small.nc.checkpoint")
    assert sorted(os.listdir(path.parent)) == ["study.toml"]


def test_plot_and_out_are_checked_before_computing(write_study, capsys, monkeypatch, tmp_path):
    from pipeline.study import orchestrate

    monkeypatch.setattr(orchestrate, "run_task", lambda *a: pytest.fail("computed before refusing"))
    path = write_study()
    for extra, message in [(["--plot", "x.txt"], "--plot 'x.txt': not a figure format"),
                           (["--out", str(tmp_path)], f"--out '{tmp_path}' is a folder")]:
        assert main(["study", "run", str(path), "--serial", "--quiet", *extra]) == 2
        assert message in capsys.readouterr().err


def test_a_full_disk_keeps_the_checkpoint_and_the_rerun_finishes(write_study, small_reference, same_results,
                                                                  capsys, monkeypatch):
    path = write_study()
    out = path.parent / "small.nc"
    real = xr.Dataset.to_netcdf

    def full(self, *args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", full)
    assert main(["study", "run", str(path), "--serial", "--quiet"]) == 2
    err = capsys.readouterr().err.splitlines()
    assert err[-1] == (f"frustum: error: {out}: cannot write (No space left on device); the {N_TASKS} finished "
                       f"task(s) are kept in {out}.checkpoint: free space (or give another --out) and run the same "
                       "command again")
    assert len(_task_files(f"{out}.checkpoint")) == N_TASKS and not out.exists()

    monkeypatch.setattr(xr.Dataset, "to_netcdf", real)  # space freed
    assert main(["study", "run", str(path), "--serial", "--quiet"]) == 0
    assert f"0 task(s) computed, {N_TASKS} from the checkpoint" in capsys.readouterr().out
    same_results(open_results(out), small_reference[1])


def test_a_full_disk_while_checkpointing_keeps_what_was_saved(write_study, capsys, monkeypatch):
    from pipeline.study.checkpoint import Checkpoint

    path = write_study()
    checkpoint = str(path.parent / "small.nc") + ".checkpoint"
    real_save = Checkpoint.save
    saved = []

    def save(self, result):
        if len(saved) == 2:
            raise OSError(errno.ENOSPC, "No space left on device")
        saved.append(result["index"])
        real_save(self, result)

    monkeypatch.setattr(Checkpoint, "save", save)
    assert main(["study", "run", str(path), "--serial", "--quiet"]) == 2
    err = capsys.readouterr().err.splitlines()
    assert err[-1] == (f"frustum: error: {checkpoint}: cannot write the checkpoint (No space left on device); the 2 "
                       "task(s) finished before are kept there: free space and run the same command again")
    assert len(_task_files(checkpoint)) == 2


def test_ctrl_c_prints_one_line_exits_130_and_keeps_the_checkpoint(write_study, capsys, monkeypatch):
    from pipeline.study import orchestrate

    calls = []
    real = orchestrate.run_task

    def interrupted(task, motion):
        calls.append(task.index)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return real(task, motion)

    monkeypatch.setattr(orchestrate, "run_task", interrupted)
    path = write_study()
    capsys.readouterr()
    assert main(["study", "run", str(path), "--serial", "--quiet"]) == 130
    err = capsys.readouterr().err.splitlines()
    # after the lines that say what it computes (what stands and which models run it, then the grid)
    assert err[0].startswith("small test study: ") and err[1].startswith("4 column(s) x 2 record(s)")
    assert err[2:] == ["frustum: interrupted: run again to resume"]
    assert len(_task_files(str(path.parent / "small.nc") + ".checkpoint")) == 2

    monkeypatch.setattr(orchestrate, "run_task", real)
    report = run_study(load_study(path), serial=True, progress=False)
    assert len(report.computed) == N_TASKS - 2
