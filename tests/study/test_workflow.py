"""`frustum workflow run`: ordered studies, idempotent, logged, non-zero exit on failure."""

import os
import textwrap

from pipeline.cli import main

from study_files import SMALL_STUDY


def _workflow(tmp_path, study_name="small.toml", extra=""):
    (tmp_path / "small.toml").write_text(SMALL_STUDY, encoding="utf-8")
    wf = tmp_path / "wf.toml"
    wf.write_text(textwrap.dedent(f"""\
        title = "test workflow"
        log = "logs/wf.log"
        [[steps]]
        study = "{study_name}"
        output = "out/small.nc"
        plot = "out/small.png"
        {extra}
    """), encoding="utf-8")
    return wf


def test_second_run_recomputes_nothing(tmp_path, monkeypatch):
    import pipeline.study
    from pipeline.study import orchestrate

    calls = []
    real = orchestrate.run_task
    monkeypatch.setattr(orchestrate, "run_task", lambda task, motion: calls.append(task.index) or real(task, motion))
    # the test runs the studies in-process (serial) to count tasks; the workflow's own default is a local cluster
    real_run = pipeline.study.run_study
    monkeypatch.setattr(pipeline.study, "run_study", lambda *a, **k: real_run(*a, **dict(k, serial=True)))

    wf = _workflow(tmp_path)
    assert main(["workflow", "run", str(wf)]) == 0
    out, png = tmp_path / "out" / "small.nc", tmp_path / "out" / "small.png"
    assert out.is_file() and png.is_file() and len(calls) == 4
    stamp = os.stat(out).st_mtime_ns, os.stat(png).st_mtime_ns

    assert main(["workflow", "run", str(wf)]) == 0
    assert len(calls) == 4  # nothing recomputed
    assert (os.stat(out).st_mtime_ns, os.stat(png).st_mtime_ns) == stamp  # nothing rewritten
    log = (tmp_path / "logs" / "wf.log").read_text()
    assert "4 task(s) computed" in log and "up to date" in log and log.count("done") == 2

    # a changed study is recomputed
    (tmp_path / "small.toml").write_text(SMALL_STUDY.replace("tail = 2.0", "tail = 1.5"), encoding="utf-8")
    assert main(["workflow", "run", str(wf)]) == 0
    assert len(calls) == 8

    # a deleted plot is redrawn from the file, without recomputing
    png.unlink()
    assert main(["workflow", "run", str(wf)]) == 0
    assert png.is_file() and len(calls) == 8


def test_failing_step_exits_non_zero_and_logs(tmp_path):
    (tmp_path / "bad.toml").write_text(SMALL_STUDY.replace("tail = 2.0", "tail = -1.0"), encoding="utf-8")
    wf = _workflow(tmp_path, "bad.toml")
    assert main(["workflow", "run", str(wf)]) == 1
    log = (tmp_path / "logs" / "wf.log").read_text()
    assert "FAILED" in log and "options" in log and "failed at step 1" in log
    assert not (tmp_path / "out" / "small.nc").exists()


def test_bad_workflow_file_names_the_field(tmp_path, capsys):
    wf = _workflow(tmp_path, extra='colour = "blue"')
    assert main(["workflow", "run", str(wf)]) == 2
    assert "field steps[0].colour" in capsys.readouterr().err


def test_shipped_workflow_and_units_only_call_frustum_workflow_run(tmp_path, capsys):
    from pathlib import Path

    from pipeline.cli.workflow import load_workflow

    root = Path(__file__).parents[2]
    wf = load_workflow(root / "workflows" / "nightly.toml")
    assert wf["steps"][0]["study"].endswith("studies/quickstart.toml")
    commands = [line for line in (root / "workflows" / "cron" / "frustum.cron").read_text().splitlines()
                if line.strip() and not line.startswith("#")]
    assert len(commands) == 1 and "frustum workflow run --quiet workflows/nightly.toml" in commands[0]
    # the units are templates on the checkout path, written by a command
    assert main(["workflow", "install-units", "--checkout", str(root), "--dir", str(tmp_path)]) == 0
    service = (tmp_path / "frustum-workflow.service").read_text()
    execs = [line for line in service.splitlines() if line.startswith("Exec")]
    assert len(execs) == 1 and execs[0].startswith("ExecStart=/") and \
        execs[0].endswith("/frustum workflow run --quiet workflows/nightly.toml")
    assert f"WorkingDirectory={root.resolve()}" in service and "{" not in service
    assert "Wants=network-online.target" in service and "After=network-online.target" in service
    assert "SuccessExitStatus=75" in service
    assert "OnCalendar=" in (tmp_path / "frustum-workflow.timer").read_text()
    assert f"cd {root.resolve()} && " in capsys.readouterr().out


def test_quiet_run_prints_nothing_on_success_and_the_log_on_failure(tmp_path, capsys, monkeypatch):
    import pipeline.study

    real_run = pipeline.study.run_study
    monkeypatch.setattr(pipeline.study, "run_study", lambda *a, **k: real_run(*a, **dict(k, serial=True)))
    wf = _workflow(tmp_path)
    assert main(["workflow", "run", "--quiet", str(wf)]) == 0
    printed = capsys.readouterr()
    assert printed.out == "" and printed.err == ""
    assert "done" in (tmp_path / "logs" / "wf.log").read_text()
    (tmp_path / "small.toml").write_text(SMALL_STUDY.replace("tail = 2.0", "tail = -1.0"), encoding="utf-8")
    assert main(["workflow", "run", "--quiet", str(wf)]) == 1
    err = capsys.readouterr().err
    assert "FAILED" in err and "failed at step 1" in err


def test_a_run_that_finds_the_lock_held_exits_75(tmp_path, capsys):
    from pipeline.locking import try_lock

    wf = _workflow(tmp_path)
    (tmp_path / "logs").mkdir()
    held = try_lock(tmp_path / "logs" / "wf.log.lock")
    try:
        assert main(["workflow", "run", "--quiet", str(wf)]) == 75
    finally:
        held.release()
    # --quiet is for cron, which mails whatever is printed: an overlap is expected, the log has it
    assert capsys.readouterr().err == ""
    assert "another run holds" in (tmp_path / "logs" / "wf.log").read_text()
    assert not (tmp_path / "out" / "small.nc").exists()


# Run in a fresh interpreter where `import fcntl` fails, as on Windows: every command must load,
# the workflow lock must still keep a second run out, and a released lock lets the next run in.
NO_FCNTL = textwrap.dedent("""\
    import sys
    sys.modules["fcntl"] = None  # `import fcntl` now raises ImportError
    from pipeline.cli import build_parser
    from pipeline.cli.workflow import run_workflow
    from pipeline.locking import try_lock
    build_parser()  # every command module imports
    held = try_lock(sys.argv[2])
    print(type(held).__name__)
    print("held:", run_workflow(sys.argv[1]))
    assert try_lock(sys.argv[2]) is None
    held.release()
    again = try_lock(sys.argv[2])
    print("after release:", again is not None)
""")


def test_workflow_lock_works_without_fcntl(tmp_path):
    import subprocess
    import sys

    wf = _workflow(tmp_path)
    (tmp_path / "logs").mkdir()
    lock = tmp_path / "logs" / "wf.log.lock"
    proc = subprocess.run([sys.executable, "-c", NO_FCNTL, str(wf), str(lock)], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.splitlines() == ["SoftFileLock", "held: 75", "after release: True"]
    assert "another run holds" in proc.stderr and str(lock) in proc.stderr


def test_a_plot_format_matplotlib_lacks_is_refused_before_computing(tmp_path, capsys):
    wf = _workflow(tmp_path)
    wf.write_text(wf.read_text().replace('plot = "out/small.png"', 'plot = "out/small.txt"'))
    assert main(["workflow", "run", str(wf)]) == 2
    err = capsys.readouterr().err
    assert "field steps[0].plot" in err and "small.txt': not a figure format matplotlib writes" in err
    assert not (tmp_path / "out").exists()
