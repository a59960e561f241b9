"""The first run on a machine says, in one line, that the kernels compile once; a warm run says nothing."""

import io
import time

from pipeline import sweep


def test_a_slow_load_is_announced_once(monkeypatch):
    monkeypatch.setattr(sweep, "COMPILE_NOTICE_AFTER", 0.05)
    monkeypatch.setattr(sweep, "warm_up", lambda models: time.sleep(0.3))  # stands for a compile
    out = io.StringIO()
    seconds = sweep.prepare_kernels(("3d",), out)
    lines = out.getvalue().splitlines()
    assert lines[0] == sweep.COMPILE_NOTICE and "once" in lines[0] and "about a minute" in lines[0]
    assert lines[1] == f"frustum: kernels ready after {seconds:.0f} s" and len(lines) == 2


def test_a_warm_cache_says_nothing(monkeypatch):
    calls = []
    monkeypatch.setattr(sweep, "warm_up", lambda models: calls.append(models))
    out = io.StringIO()
    sweep.prepare_kernels(("3d", "2d"), out)
    assert out.getvalue() == "" and calls == [("3d", "2d")]


def test_the_study_loads_the_kernels_before_the_workers_and_the_progress_bar(monkeypatch, tmp_path):
    """Order of events in run_study: kernels, then the progress bar's clock, then the cluster."""
    from conftest import SMALL_STUDY

    from pipeline.study import load_study

    events = []
    monkeypatch.setattr(sweep, "prepare_kernels", lambda models, stream: events.append(("kernels", tuple(models))))
    real_progress = sweep.Progress
    monkeypatch.setattr(sweep, "Progress", lambda *a, **k: events.append(("progress",)) or real_progress(*a, **k))
    monkeypatch.setattr(sweep, "_run_dask", lambda pending, *a, **k: events.append(("cluster", len(pending))))
    path = tmp_path / "study.toml"
    path.write_text(SMALL_STUDY, encoding="utf-8")
    report = sweep.run_study(load_study(path), progress=False)
    assert report.failed == report.grid_size  # the faked cluster computed nothing: every cell failed
    assert events == [("kernels", ("3d", "2d")), ("progress",), ("cluster", 4)]
