"""--worker-wait (issue 38, item 3): checked, passed to the cluster by `study run` and by workflows, and a run
that stops for want of workers exits 75 with one line, its checkpoint kept. No cluster starts here: the
cluster is a stand-in that reports the workers gone (tests/study/test_cluster_faults.py has the real ones)."""

import textwrap

import pytest

from pipeline.cli import main
from pipeline.study import cluster as study_cluster


class NoWorkers(study_cluster.Cluster):
    """A cluster whose workers never come: it records how long it was told to wait."""

    made = []

    def __init__(self, scheduler=None, workers=None, worker_wait=None):
        super().__init__(scheduler, workers, worker_wait)
        NoWorkers.made.append(self.worker_wait)

    def start(self, prepare=None, when=None):
        pass

    def ready(self, tick=None):
        raise study_cluster.WorkersGone(f"no workers for {self.worker_wait:g} s (--worker-wait "
                                        f"{self.worker_wait:g}): stopped")


@pytest.fixture
def no_workers(monkeypatch):
    NoWorkers.made = []
    monkeypatch.setattr(study_cluster, "Cluster", NoWorkers)
    import pipeline.study

    monkeypatch.setattr(pipeline.study, "Cluster", NoWorkers)  # where workflows take it from
    return NoWorkers.made


@pytest.mark.parametrize("argv, wait", [([], study_cluster.WORKER_WAIT), (["--worker-wait", "12.5"], 12.5),
                                        (["--worker-wait", "0"], 0.0)])
def test_a_run_that_stops_waiting_for_workers_exits_75_with_one_line(write_study, no_workers, capsys, argv, wait):
    path = write_study()
    assert main(["study", "run", str(path), "--workers", "2", "--quiet", *argv]) == 75
    assert no_workers == [wait]
    err = capsys.readouterr().err.splitlines()
    assert err[-1] == (f"frustum: no workers for {wait:g} s (--worker-wait {wait:g}): stopped; no task had "
                       "finished: run the same command again later")
    assert sorted(p.name for p in path.parent.iterdir()) == ["study.toml"]  # nothing to keep: no empty folder


@pytest.mark.parametrize("argv, message", [
    (["--worker-wait", "-5"], "--worker-wait -5: give the seconds to wait for workers, 0 or more (default 600)"),
    (["--worker-wait", "nan"], "--worker-wait nan: give the seconds to wait for workers, 0 or more (default 600)"),
    (["--worker-wait", "5", "--serial"], "--worker-wait: a --serial run has no workers to wait for; drop one of "
                                         "the two"),
])
def test_a_worker_wait_that_cannot_be_is_refused(write_study, capsys, argv, message):
    path = write_study()
    assert main(["study", "run", str(path), *argv]) == 2
    assert capsys.readouterr().err.splitlines() == [f"frustum: error: {message}"]
    assert sorted(p.name for p in path.parent.iterdir()) == ["study.toml"]


def _workflow(tmp_path, execution):
    from study_files import SMALL_STUDY

    (tmp_path / "small.toml").write_text(SMALL_STUDY, encoding="utf-8")
    wf = tmp_path / "wf.toml"
    wf.write_text(textwrap.dedent(f"""\
        log = "wf.log"
        [execution]
        workers = 2
        {execution}
        [[steps]]
        study = "small.toml"
        output = "small.nc"
    """), encoding="utf-8")
    return wf


@pytest.mark.parametrize("execution, argv, wait", [("", [], study_cluster.WORKER_WAIT),
                                                   ("worker_wait = 42", [], 42.0),
                                                   ("worker_wait = 42", ["--worker-wait", "7"], 7.0)])
def test_a_workflow_passes_the_wait_on_and_stops_with_75(tmp_path, no_workers, capsys, execution, argv, wait):
    wf = _workflow(tmp_path, execution)
    assert main(["workflow", "run", "--quiet", str(wf), *argv]) == 75
    assert no_workers == [wait]
    err = capsys.readouterr().err.splitlines()  # quiet, but a stopped step is worth a word
    assert err[-2].startswith(f"step 1: {tmp_path / 'small.toml'}: stopped: no workers for {wait:g} s")
    assert err[-1] == f"workflow {wf}: stopped at step 1 (exit 75: try again later)"
    assert "Traceback" not in (tmp_path / "wf.log").read_text()


@pytest.mark.parametrize("value, message", [("-1", "-1: give the seconds to wait for workers, 0 or more (default 600)"),
                                            ('"soon"', "must be a number of seconds, got 'soon'")])
def test_a_workflow_refuses_a_worker_wait_that_cannot_be(tmp_path, capsys, value, message):
    wf = _workflow(tmp_path, f"worker_wait = {value}")
    assert main(["workflow", "run", str(wf)]) == 2
    assert capsys.readouterr().err.splitlines() == [f"frustum: error: {wf}: field execution.worker_wait: {message}"]


@pytest.mark.parametrize("command", [["study", "run"], ["workflow", "run"]])
def test_the_help_states_the_default_and_the_status(command, capsys):
    """The help's numbers are written out (the parser does not import the study modules): they are the code's."""
    with pytest.raises(SystemExit):
        main([*command, "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert f"exit status {study_cluster.EXIT_NO_WORKERS}" in text or f"exit {study_cluster.EXIT_NO_WORKERS}" in text
    assert f"default {study_cluster.WORKER_WAIT:g} s" in text
    if command[0] == "study":
        assert f"after {study_cluster.NOTICE_AFTER:g} s" in text
