"""Provenance of ground motions: the processing log kept on every trace.

ObsPy logs its own operations in ``stats.processing``; the steps this package takes
itself (loading, rotation, scaling, synthesis, the processing steps it writes by
hand) are logged there too, by :func:`log_step`. It lives apart from the motion
type (:mod:`.record`) and the processing steps (:mod:`.processing`) so that both,
and every source, can log without importing one another.
"""

from pipeline import __version__

__all__ = ["log_step"]


def log_step(trace, text):
    """Append a processing line (``frustum <version>: text``) to a trace."""
    trace.stats.setdefault("processing", []).append(f"frustum {__version__}: {text}")
