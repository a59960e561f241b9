"""The compiled kernels of a study's models: loaded, or compiled once, before any worker starts.

numba compiles a model's kernels on first use and caches them on disk; a study checks that
cache (:func:`kernels_cached`) and warms it in the driving process (:func:`prepare_kernels`), so
that a cold or stale cache is compiled once rather than by every worker, and the user is told
once that it happens.
"""

import os
import sys
import time

from pipeline.models import REGISTRY
from pipeline.settings import Excitation, ModelSettings
from pipeline.simulate import simulate


def warm_up(models):
    """Run a tiny simulation per model (names) so the compiled kernels are loaded (or compiled once).

    Called in the driving process before workers start, so that a stale numba
    cache is rebuilt once rather than by every worker; workers call it too so
    that loading the cache is not counted inside the first task.
    """
    from pipeline.groundmotion.synthesis import one_sine_pulse
    from pipeline.structures.kinds import example

    motion = one_sine_pulse(5.0, 0.2, dt=0.01, duration=0.3, record_id="warm-up")
    for model in models:
        # the first kind of structure it runs (the paper's column, or a small colonnade)
        simulate(example(REGISTRY[model].bodies[0]), motion, Excitation(), ModelSettings(model=model, tail=0.2),
                 histories=False)
    return True


#: What the first run on a machine is told: compiling the quickstart's kernels (3d and 2d) took 206 s and 311 s
#: in fresh clones on the project's 2-core machine under loads of 1.5 to 3 (README.md); later runs load them from
#: numba's cache in about 2 s.
COMPILE_NOTICE = ("frustum: compiling the simulation kernels for this machine, once (a few minutes on two cores); "
                  "later runs load them from the cache")
#: Without a readable cache index (another numba version), a load this long [s] is taken for a compile.
COMPILE_NOTICE_AFTER = 10.0

def kernels_cached(models):
    """Whether numba's cache holds the compiled kernels of every model (None: cannot tell).

    Reads the cache index of each model's compiled entry points (``Model.entry_points`` of the
    registry; numba's ``FunctionCache``; an index of a changed source counts as missing).
    """
    import importlib

    try:
        return all(bool(getattr(importlib.import_module(module), name)._cache._cache_file._load_index())
                   for model in models for module, name in REGISTRY[model].entry_points)
    except (AttributeError, OSError, EOFError, ValueError):
        return None


def prepare_kernels(models, stream=None):
    """Load the compiled kernels in this process, compiling them first if numba's cache is cold or stale.

    Called before any Dask worker starts, so that the compile happens once,
    here, and the workers load the result from the cache. With a cold cache
    the other models' kernels compile at the same time in a helper process
    each (one per core), and, when ``stream`` is given, one line says that
    the kernels compile once and about how long, and one when they are ready.

    Parameters
    ----------
    models : sequence of str
    stream : file, optional
        Where to say it (e.g. ``sys.stderr``); None: silent.

    Returns
    -------
    float
        Seconds spent [s].
    """
    import subprocess
    import threading

    models = tuple(models)
    t0 = time.monotonic()
    cached = kernels_cached(models)
    said = threading.Event()

    def say():
        said.set()
        if stream is not None:
            print(COMPILE_NOTICE, file=stream, flush=True)

    helpers = []
    if cached is False:
        say()
        code = "from pipeline.study.kernels import warm_up; warm_up(({!r},))"
        helpers = [subprocess.Popen([sys.executable, "-c", code.format(m)],
                                    stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                   for m in models[1:] if os.cpu_count() and os.cpu_count() > 1]
    notice = threading.Timer(COMPILE_NOTICE_AFTER, say) if cached is None else None
    if notice is not None:
        notice.daemon = True
        notice.start()
    try:
        warm_up(models[:1])
    finally:
        if notice is not None:
            notice.cancel()
        for helper in helpers:
            helper.wait()  # whatever a helper failed to cache, the next line compiles here
    warm_up(models[1:])
    seconds = time.monotonic() - t0
    if said.is_set() and stream is not None:
        print(f"frustum: kernels ready after {seconds:.0f} s", file=stream, flush=True)
    return seconds
