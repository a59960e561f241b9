"""What a run may ask for, checked before anything is computed: memory, tolerances.

A run that cannot fit in memory is refused with its size, not started to die
allocating (``--duration 1e9`` once asked for 745 GiB; a grid of 1.44e9
results passed ``study check``). The estimates are deliberately simple: the
arrays the run must hold at once, counted generously; they are compared with
the memory the system says is available now (``psutil``, a dependency of
Dask's distributed).
"""

import math

from pipeline.errors import InputError

__all__ = ["available_memory", "check_fits", "history_bytes", "results_bytes", "check_tolerance", "size_text",
           "RTOL_RANGE", "ATOL_RANGE"]

# A time-history row: the state and diagnostics the kernel fills (18 floats), the ~35 variables of the
# histories Dataset, and as much again for temporaries and the netCDF writer: 128 float64.
HISTORY_ROW_BYTES = 128 * 8
# A results cell: 10 float64, 1 int32 and 5 int8 variables (89 B), held by the run and copied once
# while the file is written.
RESULT_CELL_BYTES = 2 * 89
# A task in the plan (its dataclass, tuples of factors and columns, its place in the queues).
TASK_BYTES = 1024
# Python, NumPy, ObsPy, numba kernels and Dask loaded in the driving process.
BASE_BYTES = 300 * 2**20

#: Relative tolerance the integrator can meet: below ~1e-14 (50 machine epsilons) its steps
#: shrink to nothing; above 0.1 the result means nothing.
RTOL_RANGE = (1e-14, 0.1)
#: Absolute tolerance on the dimensionless state (angles [rad], rates per tau).
ATOL_RANGE = (1e-300, 0.01)


def available_memory():
    """Memory the system can give now [bytes]."""
    import psutil

    return int(psutil.virtual_memory().available)


def size_text(nbytes):
    """``"745 GiB"``: a byte count in binary units, 3 significant digits."""
    for unit, scale in (("TiB", 2**40), ("GiB", 2**30), ("MiB", 2**20), ("KiB", 2**10)):
        if nbytes >= scale:
            return f"{nbytes / scale:.3g} {unit}"
    return f"{nbytes:.0f} B"


def check_fits(nbytes, what, fix):
    """Raise InputError if ``nbytes`` exceed the available memory.

    Parameters
    ----------
    nbytes : float
        Estimated memory of the run [bytes].
    what : str
        What is that big, e.g. ``"the results grid of 1,440,000,000 cells"``.
    fix : str
        How to make it smaller.
    """
    free = available_memory()
    if not nbytes < free:
        raise InputError(f"{what} needs about {size_text(nbytes)} of memory; this machine has "
                         f"{size_text(free)} available: {fix}")


def history_bytes(duration, output_step):
    """Memory of one simulation's time histories [bytes]: ``duration`` [s] sampled every ``output_step`` [s]."""
    rows = math.floor(duration / output_step) + 1
    return BASE_BYTES + rows * HISTORY_ROW_BYTES


def results_bytes(n_cells, n_tasks, extra_cell_bytes=0):
    """Memory of a study's run [bytes]: its results grid and its plan of tasks.

    ``extra_cell_bytes``: what a cell holds beyond the rigid models' variables (the compliant
    model's per-joint dislocations, :func:`pipeline.study.grid.memory_estimate`), held and copied
    once as the rest.
    """
    return BASE_BYTES + n_cells * (RESULT_CELL_BYTES + extra_cell_bytes) + n_tasks * TASK_BYTES


def check_tolerance(name, value, label):
    """Refuse a tolerance the integrator cannot meet or that means nothing.

    Parameters
    ----------
    name : {"rtol", "atol"}
    value : float
    label : str
        How the user gave it, for the message (``"--rtol"``, ``"options.rtol"``).
    """
    lo, hi = RTOL_RANGE if name == "rtol" else ATOL_RANGE
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not (lo <= value <= hi):
        why = "below 1e-14 the integrator's steps shrink to nothing" if name == "rtol" else "0 is no tolerance"
        raise InputError(f"{label} {value!r}: give a number in [{lo:g}, {hi:g}] ({why})")
    return float(value)
