"""Issue 26, part A: no output replaces an input or a user's file; reports and animations are atomic; failures
that looked like success say so.

Every refusal is checked for its exit status, its one line naming the option
and the fix, and the user's files byte-identical afterwards.
"""

import os
import shutil

import pytest
from cli_files import TINY_STUDY, snapshot, unchanged

from pipeline.cli import main
from pipeline.paths import result_kind, written_by_frustum


def _err(capsys):
    err = capsys.readouterr().err
    assert "Traceback" not in err
    return err


def _no_partials(folder):
    return not [p for p in os.listdir(folder) if p.startswith(".partial-")]


# -- what a file is ------------------------------------------------------------------------------

def test_result_kind_tells_the_projects_netcdf_files_apart(results_nc, histories_nc, user_files, tmp_path):
    assert result_kind(results_nc) == "study"
    assert result_kind(histories_nc) == "histories"
    assert result_kind(user_files["notes.txt"]) is None and result_kind(user_files["study.toml"]) is None
    truncated = tmp_path / "cut.nc"
    truncated.write_bytes(results_nc.read_bytes()[:2000])
    assert result_kind(truncated) is None
    assert result_kind(tmp_path / "missing.nc") is None


# -- fragility -----------------------------------------------------------------------------------

def test_fragility_refuses_to_write_over_its_results_file(results_nc, tmp_path, capsys):
    results = tmp_path / "quickstart.nc"
    shutil.copy(results_nc, results)
    before = snapshot(results)
    assert main(["fragility", str(results), "--out", str(results)]) == 2
    err = _err(capsys)
    assert "--out" in err and "is the results file this command reads" in err
    assert unchanged(before)


@pytest.mark.parametrize("name", ["notes.txt", "study.toml", "record.txt"])
def test_fragility_refuses_to_write_over_a_users_file(results_nc, user_files, capsys, name):
    before = snapshot(*user_files.values())
    assert main(["fragility", str(results_nc), "--out", str(user_files[name])]) == 2
    err = _err(capsys)
    assert "exists and is not a netCDF result written by frustum" in err
    assert "give another file name or remove it" in err
    assert unchanged(before)


def test_fragility_refuses_another_kind_of_result_and_overwrites_its_own(results_nc, histories_nc, tmp_path,
                                                                         capsys):
    other = tmp_path / "h.nc"
    shutil.copy(histories_nc, other)
    before = snapshot(other)
    assert main(["fragility", str(results_nc), "--out", str(other)]) == 2
    assert "is a histories file of 'frustum simulate'" in _err(capsys)
    assert unchanged(before)
    out = tmp_path / "frag.nc"
    assert main(["fragility", str(results_nc), "--out", str(out)]) == 0
    assert main(["fragility", str(results_nc), "--out", str(out), "--states", "0.5"]) == 0  # a rerun replaces it
    assert result_kind(out) == "fragility"


# -- study run -----------------------------------------------------------------------------------

def test_study_run_refuses_to_write_over_its_study_file(user_files, capsys):
    study = user_files["study.toml"]
    before = snapshot(*user_files.values())
    assert main(["study", "run", str(study), "--out", str(study), "--serial"]) == 2
    assert "is the study file this command reads" in _err(capsys)
    assert unchanged(before)
    assert not os.path.exists(f"{study}.checkpoint")


def test_study_output_field_naming_a_users_file_is_refused(user_files, tmp_path, capsys):
    study = tmp_path / "s.toml"
    study.write_text(TINY_STUDY.replace('output = "tiny.nc"', 'output = "notes.txt"'), encoding="utf-8")
    before = snapshot(*user_files.values())
    for command in ("check", "run"):
        assert main(["study", command, str(study)]) == 2
        err = _err(capsys)
        assert "field output" in err and "exists and is not a netCDF result written by frustum" in err
    assert unchanged(before)


def test_study_run_refuses_a_histories_file(histories_nc, user_files, capsys):
    before = snapshot(histories_nc)
    assert main(["study", "run", str(user_files["study.toml"]), "--out", str(histories_nc), "--serial"]) == 2
    assert "is a histories file of 'frustum simulate'" in _err(capsys)
    assert unchanged(before)


def test_unreachable_scheduler_leaves_no_checkpoint(user_files, tmp_path, capsys):
    out = tmp_path / "out" / "tiny.nc"
    status = main(["study", "run", str(user_files["study.toml"]), "--out", str(out),
                   "--scheduler", "tcp://127.0.0.1:9", "--quiet"])
    assert status == 2
    assert "--scheduler tcp://127.0.0.1:9: cannot connect" in _err(capsys)
    assert not os.path.exists(f"{out}.checkpoint") and not out.exists()


def test_study_in_which_every_cell_failed_exits_non_zero(user_files, tmp_path, capsys, monkeypatch):
    from pipeline.study import orchestrate
    from pipeline.study import run as task_run

    def fails(*args, **kwargs):
        raise ValueError("found no rebound peak")

    monkeypatch.setattr(task_run, "simulate", fails)
    monkeypatch.setattr(orchestrate, "prepare_kernels", lambda *a, **k: 0.0)
    out = tmp_path / "tiny.nc"
    assert main(["study", "run", str(user_files["study.toml"]), "--out", str(out), "--serial", "--quiet"]) == 1
    err = _err(capsys)
    line = [x for x in err.splitlines() if x.startswith("frustum: error:")]
    assert len(line) == 1 and "all 1 cells of the study failed" in line[0]
    assert "ValueError: found no rebound peak" in line[0]


# -- simulate ------------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["notes.txt", "study.toml"])
def test_simulate_refuses_to_write_over_a_users_file(user_files, capsys, name):
    before = snapshot(*user_files.values())
    assert main(["simulate", "--column", "0.5,0.4,4", "--record", "SYN-RICKER", "--out", str(user_files[name])]) == 2
    assert "exists and is not a netCDF result written by frustum" in _err(capsys)
    assert unchanged(before)


def test_simulate_refuses_to_write_over_its_record_file(user_files, capsys):
    record = user_files["record.txt"]
    before = snapshot(record)
    assert main(["simulate", "--column", "0.5,0.4,4", "--record", str(record), "--units", "g", "--dt", "0.01",
                 "--missing-y", "zero", "--out", str(record)]) == 2
    assert "is the record file this command reads" in _err(capsys)
    assert unchanged(before)


# -- report --------------------------------------------------------------------------------------

def test_report_refuses_a_file_as_its_folder(results_nc, tmp_path, capsys):
    results = tmp_path / "r.nc"
    shutil.copy(results_nc, results)
    before = snapshot(results)
    assert main(["report", str(results), "--out", str(results), "--bootstrap", "0"]) == 2
    assert "is a file, not a folder" in _err(capsys)
    assert unchanged(before)


def test_report_refuses_a_folder_where_it_would_replace_its_input(results_nc, tmp_path, capsys):
    folder = tmp_path / "rep"
    folder.mkdir()
    results = folder / "fragility.nc"  # the name of the report's own fragility file
    shutil.copy(results_nc, results)
    before = snapshot(results)
    assert main(["report", str(results), "--out", str(folder), "--bootstrap", "0"]) == 2
    assert "is the results file this command reads" in _err(capsys)
    assert unchanged(before)


def test_report_of_a_study_whose_every_cell_failed_leaves_nothing(failed_results_nc, tmp_path, capsys):
    out = tmp_path / "rep"
    assert main(["report", str(failed_results_nc), "--out", str(out), "--bootstrap", "0"]) == 2
    err = _err(capsys)
    assert "simulations failed (status 1), so there is nothing to report" in err
    assert not out.exists() and _no_partials(tmp_path)


def test_a_report_that_fails_half_way_leaves_the_folder_as_it_was(results_nc, tmp_path, monkeypatch):
    from pipeline import report

    out = tmp_path / "study"
    out.mkdir()
    (out / "study.toml").write_text(TINY_STUDY, encoding="utf-8")
    (out / "report.md").write_text("the old report\n", encoding="utf-8")
    before = snapshot(out / "study.toml", out / "report.md")

    def broken(*args, **kwargs):
        raise ValueError("Data cannot be log-scaled because all values are <= 0.")

    monkeypatch.setattr(report, "_write_csv", broken)  # after the figures and fragility.nc are written
    with pytest.raises(ValueError):
        report.write_report(report.F.open_results(results_nc), out, bootstrap=0)
    assert unchanged(before) and sorted(os.listdir(out)) == ["report.md", "study.toml"]
    assert _no_partials(tmp_path)


def test_a_report_into_a_study_folder_keeps_the_folders_other_files(results_nc, tmp_path, capsys):
    out = tmp_path / "study"
    out.mkdir()
    (out / "study.toml").write_text(TINY_STUDY, encoding="utf-8")
    before = snapshot(out / "study.toml")
    assert main(["report", str(results_nc), "--out", str(out), "--bootstrap", "0"]) == 0
    assert f"wrote {out / 'report.md'}" in capsys.readouterr().out
    assert unchanged(before)
    assert {"report.md", "report.html", "summary.csv", "fragility.nc", "figures"} <= set(os.listdir(out))
    assert "](figures/" in (out / "report.md").read_text()
    assert _no_partials(tmp_path) and _no_partials(out)
    # every file it wrote says so, and a rerun replaces them
    assert all(written_by_frustum(p) for p in [out / "report.md", out / "report.html", *(out / "figures").iterdir()])
    assert main(["report", str(results_nc), "--out", str(out), "--bootstrap", "0", "--title", "again"]) == 0
    assert "# again" in (out / "report.md").read_text()


@pytest.mark.parametrize("name, data, words", [
    ("report.md", b"# my own notes\n", "report.md exists and was not written by frustum"),
    ("report.html", b"<html>my page</html>", "report.html exists and was not written by frustum"),
    ("figures/site.pdf", b"%PDF-1.4 my drawing", "site.pdf exists and was not written by frustum"),
    ("summary.csv", b"column,model\nA,3d\n", "summary.csv exists and is not a summary.csv written by 'frustum report'"),
])
def test_report_refuses_a_folder_holding_a_users_file_it_would_replace(results_nc, tmp_path, capsys, name, data,
                                                                       words):
    out = tmp_path / "mine"
    (out / name).parent.mkdir(parents=True)
    (out / name).write_bytes(data)
    before = snapshot(out / name)
    assert main(["report", str(results_nc), "--out", str(out), "--bootstrap", "0"]) == 2
    err = _err(capsys)
    assert f"--out {str(out)!r}: " in err and words in err and "give another folder or remove that file" in err
    assert unchanged(before) and sorted(p.name for p in out.rglob("*")) == sorted(name.split("/"))


# -- figures and animations: a user's file of the same suffix -----------------------------------------

def test_a_plot_is_replaced_by_a_rerun_but_a_users_picture_is_not(tmp_path, capsys):
    fig = tmp_path / "ricker.png"
    assert main(["records", "plot", "SYN-RICKER", "--out", str(fig)]) == 0
    assert written_by_frustum(fig)
    assert main(["records", "plot", "SYN-RICKER", "--out", str(fig)]) == 0  # a rerun replaces its own figure
    photo = tmp_path / "site.png"
    photo.write_bytes(b"\x89PNG\r\n\x1a\n my photo of the site")
    before = snapshot(photo)
    assert main(["records", "plot", "SYN-RICKER", "--out", str(photo)]) == 2
    err = _err(capsys)
    assert f"--out {str(photo)!r} exists and was not written by frustum; give another file name or remove it" in err
    assert unchanged(before)


def test_an_animation_is_replaced_by_a_rerun_but_a_users_gif_is_not(histories_nc, tmp_path, capsys):
    gif = tmp_path / "m.gif"
    for _ in range(2):  # the second replaces the first
        assert main(["animate", str(histories_nc), "--out", str(gif), "--fps", "1", "--dpi", "20"]) == 0
    assert written_by_frustum(gif)
    mine = tmp_path / "mine.gif"
    mine.write_bytes(b"GIF89a my animation")
    before = snapshot(mine)
    assert main(["animate", str(histories_nc), "--out", str(mine), "--fps", "1", "--dpi", "20"]) == 2
    assert f"--out {str(mine)!r} exists and was not written by frustum" in _err(capsys)
    assert unchanged(before) and _no_partials(tmp_path)


# -- animate -------------------------------------------------------------------------------------

def test_animate_of_a_truncated_file_is_one_line(histories_nc, tmp_path, capsys):
    cut = tmp_path / "cut.nc"
    cut.write_bytes(histories_nc.read_bytes()[:5000])
    out = tmp_path / "m.gif"
    assert main(["animate", str(cut), "--out", str(out)]) == 2
    err = _err(capsys)
    assert f"{cut}: cannot be read as netCDF" in err and "run it again" in err
    assert not out.exists()


def test_animate_frames_beyond_the_limit_are_refused_before_drawing(histories_nc, tmp_path, capsys):
    out = tmp_path / "m.gif"
    assert main(["animate", str(histories_nc), "--out", str(out), "--speed", "1e-9"]) == 2
    err = _err(capsys)
    assert "--fps 10 and --speed 1e-09" in err and "lower --fps or raise --speed" in err
    assert not out.exists() and _no_partials(tmp_path)


# -- records -------------------------------------------------------------------------------------

def test_units_on_a_catalog_record_are_refused_not_ignored(capsys):
    assert main(["records", "show", "SYN-RICKER", "--units", "g"]) == 2
    err = _err(capsys)
    assert "--units: SYN-RICKER is a catalog record" in err and "drop --units" in err


# -- workflow ------------------------------------------------------------------------------------

def _workflow(tmp_path, steps, log="logs/wf.log"):
    (tmp_path / "tiny.toml").write_text(TINY_STUDY, encoding="utf-8")
    wf = tmp_path / "wf.toml"
    wf.write_text(f'log = "{log}"\n' + "".join(f"[[steps]]\n{s}\n" for s in steps), encoding="utf-8")
    return wf


def test_workflow_refuses_two_steps_with_one_output_before_computing(tmp_path, capsys):
    wf = _workflow(tmp_path, ['study = "tiny.toml"\noutput = "out/a.nc"', 'study = "tiny.toml"\noutput = "out/a.nc"'])
    assert main(["workflow", "run", str(wf)]) == 2
    err = _err(capsys)
    assert "field steps[1].output" in err and "is also written by steps[0].output" in err
    assert not (tmp_path / "out").exists() and not (tmp_path / "logs").exists()


def test_workflow_refuses_a_default_output_two_steps_share(tmp_path, capsys):
    wf = _workflow(tmp_path, ['study = "tiny.toml"', 'study = "tiny.toml"\noutput = "tiny.nc"'])
    assert main(["workflow", "run", str(wf)]) == 2
    assert "is also written by the study of steps[0] (its output field)" in _err(capsys)


def test_workflow_refuses_an_output_that_is_a_study(tmp_path, capsys):
    wf = _workflow(tmp_path, ['study = "tiny.toml"\noutput = "tiny.toml"'])
    before = snapshot(tmp_path / "tiny.toml")
    assert main(["workflow", "run", str(wf)]) == 2
    assert "is the study file of steps[0] this command reads" in _err(capsys)
    assert unchanged(before)


def test_workflow_log_that_cannot_be_written_is_refused(tmp_path, capsys):
    wf = _workflow(tmp_path, ['study = "tiny.toml"\noutput = "out/a.nc"'], log="/proc/frustum-test/wf.log")
    assert main(["workflow", "run", str(wf)]) == 2
    err = _err(capsys)
    assert "field log '/proc/frustum-test/wf.log': /proc cannot be written" in err


def test_workflow_log_may_not_be_an_input(tmp_path, capsys):
    wf = _workflow(tmp_path, ['study = "tiny.toml"\noutput = "out/a.nc"'], log="tiny.toml")
    before = snapshot(tmp_path / "tiny.toml")
    assert main(["workflow", "run", str(wf)]) == 2
    assert "field log" in _err(capsys)
    assert unchanged(before)


def test_quiet_workflow_is_silent_when_the_lock_is_held(tmp_path, capsys):
    from pipeline.locking import try_lock

    wf = _workflow(tmp_path, ['study = "tiny.toml"\noutput = "out/a.nc"'])
    (tmp_path / "logs").mkdir()
    held = try_lock(tmp_path / "logs" / "wf.log.lock")
    try:
        assert main(["workflow", "run", "--quiet", str(wf)]) == 75
        assert capsys.readouterr() == ("", "")
        assert main(["workflow", "run", str(wf)]) == 75  # not quiet: it says so
        assert "another run holds" in capsys.readouterr().err
    finally:
        held.release()
    assert "another run holds" in (tmp_path / "logs" / "wf.log").read_text()
