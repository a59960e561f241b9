"""The first run on a machine says, in one line, that the kernels compile once; a warm run says nothing."""

import io
import time

from pipeline.study import kernels, orchestrate, progress


def test_a_cold_cache_is_announced_once_and_the_other_model_compiles_beside(monkeypatch):
    import subprocess

    started = []

    class FakeHelper:
        def __init__(self, argv, **kwargs):
            started.append(argv)

        def wait(self):
            return 0

    calls = []
    monkeypatch.setattr(kernels, "kernels_cached", lambda models: False)
    monkeypatch.setattr(kernels, "warm_up", lambda models: calls.append(tuple(models)))
    monkeypatch.setattr(subprocess, "Popen", FakeHelper)
    monkeypatch.setattr(kernels.os, "cpu_count", lambda: 2)
    out = io.StringIO()
    seconds = kernels.prepare_kernels(("3d", "2d"), out)
    lines = out.getvalue().splitlines()
    assert lines == [kernels.COMPILE_NOTICE, f"frustum: kernels ready after {seconds:.0f} s"]
    assert "once" in lines[0] and "a few minutes" in lines[0]
    assert len(started) == 1 and "warm_up(('2d',))" in started[0][-1]  # 2D compiles in a helper meanwhile
    assert calls == [("3d",), ("2d",)]  # then this process loads 2D from the cache


def test_the_cache_index_tells_cold_from_warm(tmp_path):
    import subprocess
    import sys

    from pipeline.study.kernels import kernels_cached

    assert kernels_cached(("3d", "2d")) is True  # the session's fixture loaded them
    # the compliant model too (its kernels were not listed: a cold cache read as warm, so its
    # studies compiled in every worker, unannounced)
    probe = ("from pipeline.study.kernels import kernels_cached; "
             "print(kernels_cached(('3d', '2d')), kernels_cached(('3d-compliant',)))")
    env = {**__import__("os").environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, env=env, timeout=120)
    assert out.stdout.strip() == "False False", out.stderr


def test_an_unreadable_index_falls_back_to_the_clock(monkeypatch):
    monkeypatch.setattr(kernels, "kernels_cached", lambda models: None)
    monkeypatch.setattr(kernels, "COMPILE_NOTICE_AFTER", 0.05)
    monkeypatch.setattr(kernels, "warm_up", lambda models: time.sleep(0.3) if models else None)
    out = io.StringIO()
    kernels.prepare_kernels(("3d",), out)
    assert out.getvalue().splitlines()[0] == kernels.COMPILE_NOTICE


def test_a_warm_cache_says_nothing(monkeypatch):
    calls = []
    monkeypatch.setattr(kernels, "kernels_cached", lambda models: True)
    monkeypatch.setattr(kernels, "warm_up", lambda models: calls.append(tuple(models)))
    out = io.StringIO()
    kernels.prepare_kernels(("3d", "2d"), out)
    assert out.getvalue() == "" and calls == [("3d",), ("2d",)]


def test_the_study_loads_the_kernels_before_the_workers_and_the_progress_bar(monkeypatch, tmp_path):
    """Order of events in run_study: kernels, then the progress bar's clock, then the cluster."""
    from study_files import SMALL_STUDY

    from pipeline.study import load_study

    events = []
    monkeypatch.setattr(orchestrate, "prepare_kernels", lambda models, stream: events.append(("kernels", tuple(models))))
    real_progress = orchestrate.Progress
    monkeypatch.setattr(orchestrate, "Progress", lambda *a, **k: events.append(("progress",)) or real_progress(*a, **k))
    monkeypatch.setattr(orchestrate, "run_on_cluster", lambda tasks, *a, **k: events.append(("cluster", len(tasks))))
    path = tmp_path / "study.toml"
    path.write_text(SMALL_STUDY, encoding="utf-8")
    report = orchestrate.run_study(load_study(path), progress=False)
    assert report.failed == report.grid_size  # the faked cluster computed nothing: every cell failed
    assert events == [("kernels", ("3d", "2d")), ("progress",), ("cluster", 4)]


def test_the_eta_counts_computing_not_starting_the_cluster():
    import re

    class Terminal(io.StringIO):
        def isatty(self):
            return True  # a line per task

    out = Terminal()
    bar = progress.Progress(20, stream=out)
    bar.start -= 60.0  # a minute of cluster start-up and kernel loading
    bar.restart()
    bar.advance()
    eta = float(re.findall(r"eta\s+([0-9.]+) s", out.getvalue())[-1])
    assert eta < 5.0  # not 19 x 60 s
