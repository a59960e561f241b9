"""Shared by every test folder: under pytest-xdist, the models' kernels compile once, before the workers start.

numba compiles a kernel on its first call and caches it on disk (``cache=True``). In one
process that happens once; with ``-n N`` (``make test``) every worker that reaches a kernel
before another has cached it compiles it again (the 3D model's run takes minutes).
So the controlling process first does what a study does before its Dask workers start
(:func:`pipeline.study.kernels.prepare_kernels`: one model here, each other model in a helper
process beside it), and the workers load the registry's kernels from the cache. A warm cache
costs a few seconds here and nothing is compiled. Without xdist nothing changes: the tests
compile what they use, as they always did.
"""


def _is_xdist_controller(config):
    return (getattr(config, "workerinput", None) is None
            and getattr(config.option, "dist", "no") != "no" and bool(getattr(config.option, "tx", None))
            and not config.option.collectonly)


def pytest_sessionstart(session):
    """Compile (or load) every registry model's kernels before xdist starts its workers."""
    config = session.config
    if not _is_xdist_controller(config):
        return
    from pipeline.models import names
    from pipeline.study.kernels import prepare_kernels

    reporter = config.pluginmanager.get_plugin("terminalreporter")
    seconds = prepare_kernels(names(), stream=None)
    if reporter is not None and seconds > 10:
        reporter.write_line(f"compiled the models' kernels once for the workers in {seconds:.0f} s")
