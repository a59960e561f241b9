"""Unsigned array indices for the compiled loops of the compliant kernels.

numba gives a signed index Python's meaning: ``a[i]`` with ``i < 0`` counts from the end. So every
access with an index the compiler cannot prove non-negative (one read from a table, such as a
joint's bodies or the list of the points in contact, or a loop from ``start`` to ``stop``) carries a
test and a correction of the index, three to five instructions each time. In the loops over a
structure's contact points, which read and write some twenty columns per point, those instructions
were about as many as the arithmetic. An unsigned index has no such meaning and costs nothing: the
arithmetic and its results are unchanged to the bit (issue 48, speed).

Convert where the index is used, not before: numba types ``uint64 + int64`` as ``int64``, so an
index computed from an unsigned one is signed again. Never convert a value that may be negative
(``GROUND``, -1): test it first.
"""

import numpy as np
from numba import njit

__all__ = ["ix"]


@njit(cache=True, inline="always")
def ix(i):
    """The index i (an integer >= 0, or a float holding one) as an unsigned index."""
    return np.uint64(i)
