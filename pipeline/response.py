"""What one simulation returns, whatever the model: :class:`Response`.

Its own module, below the models that fill it (:mod:`pipeline.simulate` for the rigid
models, :mod:`pipeline.compliant` for the compliant one), so that neither imports the other
for it.
"""

from dataclasses import dataclass, field

import numpy as np
import xarray as xr

__all__ = ["Response", "outcome"]


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


def outcome(summary):
    """The outcome of a run in words: "overturned at 5.75 s", "undecided" or "stands".

    Parameters
    ----------
    summary : dict
        :attr:`Response.summary` of a run with a record (``overturned``, ``overturn_time`` [s];
        ``undecided``, where the model reports it).
    """
    if summary.get("overturned"):
        return f"overturned at {summary['overturn_time']:.2f} s"
    if summary.get("undecided"):
        return "undecided (it could still overturn at the end of the settle limit)"
    return "stands"
