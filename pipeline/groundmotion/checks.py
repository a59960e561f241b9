"""Warnings about records that look unprocessed: an offset, or a velocity that does not come back to rest.

A record with an offset (a mean far from zero) or a drifting baseline drives
the column with a spurious steady push: its velocity and displacement grow
without bound, and the column may rock or overturn on the artefact alone.
Nothing is changed here (processing is explicit); the warning names the fix.

Thresholds, set against the 78 FEMA P695 records (processed by PEER), which
must not warn: the mean of every component is at most 0.01 % of its peak
(limit 1 %), and the velocity at the end at most 2.6 % of the peak velocity
(FEMA-FF-15 y; limit 10 %).
"""

import warnings

import numpy as np

from pipeline.errors import RecordWarning
from pipeline.groundmotion import intensity as im
from pipeline.groundmotion.options import how_to_give

__all__ = ["MEAN_LIMIT", "DRIFT_LIMIT", "baseline_problems", "warn_if_unprocessed"]

#: |mean| / peak above which a component has an offset [1].
MEAN_LIMIT = 0.01
#: |velocity at the end| / peak velocity above which a component drifts [1].
DRIFT_LIMIT = 0.10


def baseline_problems(gm):
    """Lines describing the offsets and velocity drifts of a record's components (empty if none).

    Parameters
    ----------
    gm : GroundMotion
    """
    out = []
    largest = max(float(np.max(np.abs(gm.component(name)))) for name in gm.components)
    for name in gm.components:
        a = gm.component(name)
        peak = float(np.max(np.abs(a)))
        if peak <= 1e-9 * largest:  # zero but for rounding (e.g. a demeaned y = 0)
            continue
        mean = float(np.mean(a))
        if abs(mean) > MEAN_LIMIT * peak:
            out.append(f"component {name} has an offset: mean {mean:.4g} m/s^2 is {100 * abs(mean) / peak:.3g} % "
                       f"of its peak {peak:.4g} m/s^2")
            continue
        v = im.velocity(a, gm.dt)
        pgv = float(np.max(np.abs(v)))
        if abs(v[-1]) > DRIFT_LIMIT * pgv:
            out.append(f"component {name}: velocity drifts, it ends at {v[-1]:.4g} m/s, "
                       f"{100 * abs(v[-1]) / pgv:.3g} % of its peak {pgv:.4g} m/s")
    return out


def warn_if_unprocessed(gm):
    """Warn (:class:`pipeline.errors.RecordWarning`) if the record has an offset or drifts; returns ``gm``."""
    problems = baseline_problems(gm)
    if problems:
        warnings.warn(f"{gm.record_id}: {'; '.join(problems)}; it looks unprocessed: correct the baseline "
                      f"first with baseline_correct: {how_to_give('baseline')}", RecordWarning, stacklevel=3)  # at the caller of load()
    return gm
