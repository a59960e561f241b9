"""What one simulation returns, whatever the model: :class:`Response`.

Its own module, below the models that fill it (:mod:`pipeline.simulate` for the rigid
models, :mod:`pipeline.compliant` for the compliant one), so that neither imports the other
for it.
"""

from dataclasses import dataclass, field

import numpy as np
import xarray as xr

__all__ = ["Response", "outcome", "SHOWN_DISPLACEMENT"]


@dataclass
class Response:
    """What one simulation returns.

    Attributes
    ----------
    summary : dict
        Scalar results (names of docs/variables.md), SI units.
    histories : xarray.Dataset or None
        Time histories, if asked for.
    """

    summary: dict
    histories: xr.Dataset | None = field(default=None, repr=False)
    impacts: np.ndarray | None = field(default=None, repr=False)


#: The smallest residual displacement of a base the outcome tells [m]: what its one decimal in mm shows.
SHOWN_DISPLACEMENT = 0.05e-3


def outcome(summary):
    """The outcome of a run in words: "overturned at 5.75 s", "undecided", "stands" or "stands, slid 40.2 mm".

    A structure of several bodies says which fell first ("overturned at 5.75 s, column 3 capital
    falling first"); one that stands says how far its base ended from where it stood (the largest of a
    colonnade's bases, the frame's) when that shows in tenths of a mm: "slid" if it slid on the
    ground (``sliding_onset``), else where its base is (the 3D frustum walks on its rim; a compliant
    base shears).

    Parameters
    ----------
    summary : dict
        :attr:`Response.summary` of a run with a record (``overturned``, ``overturn_time`` [s];
        ``undecided``, ``overturn_body``, ``n_bodies``, ``residual_displacement`` [m],
        ``sliding_onset``, where the model reports them).
    """
    if summary.get("overturned"):
        first = summary.get("overturn_body", "") if summary.get("n_bodies", 1) > 1 else ""
        return f"overturned at {summary['overturn_time']:.2f} s" + (f", {first} falling first" if first else "")
    if summary.get("undecided"):
        return "undecided (it could still overturn at the end of the settle limit)"
    moved = summary.get("residual_displacement", 0.0)
    if not moved >= SHOWN_DISPLACEMENT:  # NaN too: a run that does not report it
        return "stands"
    if summary.get("sliding_onset"):
        return f"stands, slid {moved * 1e3:.1f} mm"
    return f"stands, its base {moved * 1e3:.1f} mm from where it stood"
