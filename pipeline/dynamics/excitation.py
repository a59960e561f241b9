"""The ground motion as every kernel family reads it: acceleration between samples.

Every kernel takes the record the same way: samples of (a_X, a_Y, a_Z) [g]
at times 0, dt, 2 dt, ... (dimensionless time or seconds, as the family
counts it), linear between samples. The samples are therefore the break
points of the forcing: the integrators are given the sample times as
``t_breaks`` so that no step straddles a kink.

Shared by the rigid family (:mod:`pipeline.dynamics.rigid`) and the
compliant one (:mod:`pipeline.dynamics.compliant`).
"""

from numba import njit


@njit(cache=True)
def ground_acceleration(t, record, dt):
    """Ground acceleration at time t by linear interpolation of a record.

    Parameters
    ----------
    t : float
        Time [tau].
    record : numpy.ndarray, shape (n, 3)
        Samples of (a_X, a_Y, a_Z) [g] at times 0, dt, 2 dt, ...
    dt : float
        Sampling interval [tau].

    Returns
    -------
    tuple of float
        (a_X, a_Y, a_Z) [g]; zero before 0 and after the last sample.
    """
    n = record.shape[0]
    x = t / dt
    if x < 0.0 or n == 0:
        return 0.0, 0.0, 0.0
    k = int(x)
    if k >= n - 1:
        if k == n - 1 and x == k:
            return record[k, 0], record[k, 1], record[k, 2]
        return 0.0, 0.0, 0.0
    w = x - k
    return (
        record[k, 0] + w * (record[k + 1, 0] - record[k, 0]),
        record[k, 1] + w * (record[k + 1, 1] - record[k, 1]),
        record[k, 2] + w * (record[k + 1, 2] - record[k, 2]),
    )
