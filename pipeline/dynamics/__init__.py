"""Numerical kernels: equations of motion, contact maps, integrators, event-driven runs.

Floats and arrays in, arrays out; no units, no objects, no obspy/xarray/dask.

Compiled-code cache
-------------------
numba caches each ``cache=True`` function keyed on its own source file only,
but the kernels inline one another (the rigid runs inline the integrator and
the right-hand sides): editing ``rigid/frustum.py`` or ``excitation.py`` would leave a stale compiled
``rigid/run3d`` in the cache. So, unless the user sets ``NUMBA_CACHE_DIR``, the
cache lives in a folder named after a digest of every source file here and in
the family folders below (and the numba and Python versions): any edit gives a
fresh, consistent cache.
This must run before the kernel modules are imported, hence here.
"""

import hashlib
import os
import sys
from pathlib import Path


def _source_digest():
    import numba

    h = hashlib.sha256()
    here = Path(__file__).resolve().parent
    for path in sorted(here.rglob("*.py")):
        h.update(path.relative_to(here).as_posix().encode())
        h.update(path.read_bytes())
    h.update(f"{numba.__version__} {sys.version}".encode())
    return h.hexdigest()[:16]


def _configure_cache():
    if os.environ.get("NUMBA_CACHE_DIR"):
        return  # the user's choice wins
    import numba

    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "frustum-numba"
    folder = base / _source_digest()
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:
        return  # read-only home: numba falls back to its default locations
    numba.config.CACHE_DIR = str(folder)


_configure_cache()
