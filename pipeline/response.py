"""What one simulation returns, whatever the model: :class:`Response`.

Its own module, below the models that fill it (:mod:`pipeline.simulate` for the rigid
models, :mod:`pipeline.compliant` for the compliant one), so that neither imports the other
for it.
"""

from dataclasses import dataclass, field

import numpy as np
import xarray as xr

__all__ = ["Response"]


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
