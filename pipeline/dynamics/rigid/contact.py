"""Contact transitions: uplift from full base contact and landing impacts.

Kernel layer, dimensionless (lengths per R, time per sqrt(R/g), accelerations
per g). The model, stated in ``docs/model.md``:

* At rest the column moves with the ground. It uplifts when the horizontal
  ground acceleration reaches ``|a_h| z_c = 1 + a_z`` (moments about the rim).
  It pivots on the rim point opposite the acceleration, i.e. it leans
  against the ground's acceleration.
* Rolling on the rim is modelled for ``theta >= theta_c``, the contact
  transition tilt: below it the base is taken to be in full contact (real
  joints are not flat to better than a few micrometres, and the rim-rolling
  model's mobilized friction diverges as theta -> 0, paper Section 2.2).
  Rolling starts at ``theta_c`` and a landing is theta falling to ``theta_c``.
* At a landing the pivot moves to the opposite rim point; the impulse acts
  there only, so the angular momentum about it is conserved (Housner's
  assumption, in three dimensions: the spin and precession carry over).
"""

import math

import numpy as np
from numba import njit

from pipeline.dynamics.rigid import frustum as fk


@njit(cache=True)
def uplift_demand(ax, ay, az, zc):
    """Overturning over restoring moment about the most loaded rim point [1].

    ``>= 1`` means the column lifts off its full base.
    """
    restoring = 1.0 + az
    if restoring <= 0.0:
        return math.inf  # the ground falls faster than gravity: lift-off
    return math.sqrt(ax * ax + ay * ay) * zc / restoring


@njit(cache=True)
def first_uplift(record, dt, zc, tau_start):
    """First time at or after ``tau_start`` when the column uplifts.

    The record is linear between samples, so within a segment the uplift
    condition ``(ax^2 + ay^2) zc^2 - (1 + az)^2 >= 0`` is a quadratic in
    time and is solved exactly.

    Parameters
    ----------
    record : numpy.ndarray, shape (n, 3)
        Ground acceleration (a_X, a_Y, a_Z) [g], samples at 0, dt, 2dt, ...
    dt : float
        Sampling interval [tau].
    zc : float
        Height of the centre of mass [R].
    tau_start : float
        Search from this time [tau].

    Returns
    -------
    float
        Uplift time [tau], or ``inf`` if the column stays at rest to the end
        of the record.
    """
    n = record.shape[0]
    if n == 0:
        return math.inf
    k0 = int(tau_start / dt)
    if k0 < 0:
        k0 = 0
    for k in range(k0, n - 1):
        t0 = k * dt
        a0x, a0y, a0z = record[k, 0], record[k, 1], record[k, 2]
        dx, dy, dz = record[k + 1, 0] - a0x, record[k + 1, 1] - a0y, record[k + 1, 2] - a0z
        # f(w) = zc^2 ((a0x + w dx)^2 + (a0y + w dy)^2) - (1 + a0z + w dz)^2, w in [0, 1]
        g0 = 1.0 + a0z
        qa = zc * zc * (dx * dx + dy * dy) - dz * dz
        qb = 2.0 * (zc * zc * (a0x * dx + a0y * dy) - g0 * dz)
        qc = zc * zc * (a0x * a0x + a0y * a0y) - g0 * g0
        w_lo = 0.0
        if t0 < tau_start:
            w_lo = (tau_start - t0) / dt
        w = _first_nonnegative(qa, qb, qc, w_lo)
        if w <= 1.0:
            return t0 + w * dt
    return math.inf


@njit(cache=True)
def _first_nonnegative(qa, qb, qc, w_lo):
    """Smallest w in [w_lo, 1] with qa w^2 + qb w + qc >= 0, or 2.0 if none."""
    f_lo = (qa * w_lo + qb) * w_lo + qc
    if f_lo >= 0.0:
        return w_lo
    roots = np.empty(2)
    nroots = 0
    if qa == 0.0:
        if qb != 0.0:
            roots[0] = -qc / qb
            nroots = 1
    else:
        disc = qb * qb - 4.0 * qa * qc
        if disc >= 0.0:
            sq = math.sqrt(disc)
            # numerically stable pair of roots
            q = -0.5 * (qb + math.copysign(sq, qb))
            r1 = q / qa
            r2 = qc / q if q != 0.0 else r1
            roots[0] = min(r1, r2)
            roots[1] = max(r1, r2)
            nroots = 2
    best = 2.0
    for i in range(nroots):
        r = roots[i]
        if w_lo <= r <= 1.0 and r < best:
            best = r
    if best <= 1.0:
        # round-off may leave f(best) a hair below zero; step to the next float
        while (qa * best + qb) * best + qc < 0.0 and best < 1.0:
            best = np.nextafter(best, 2.0)
    return best


@njit(cache=True)
def uplift_azimuth(ax, ay):
    """Precession angle phi of the pivot when the column uplifts under (ax, ay).

    The column leans against the ground acceleration: the horizontal
    direction from the pivot to the base centre, (-sin phi, cos phi), is the
    direction of the acceleration.
    """
    return math.atan2(-ax, ay)


@njit(cache=True)
def landing_impact(y, theta_c, c, y_out, slip_xi=0.0, slip_n=0.0):
    """Apply the landing impact at tilt ``theta_c``; write the new state to ``y_out``.

    ``theta_c`` is the tilt at which the landing was detected (the state's
    theta); the new pivot's state has the same tilt, mirrored.

    The pivot moves to the rim point opposite the landing pivot. The impulse
    acts at the new pivot only, so the angular momentum about it is
    conserved: ``I_P' w+ = I_C w- + r_P'C x (w- x r_PC)``, evaluated with the
    geometry of full contact (theta = 0), where the impact happens. In planar
    rocking this is ``theta'+ = -(1 - 2/I_y) theta'-``.

    ``slip_xi, slip_n`` is the velocity with which the landing pivot slides
    (along the line of nodes and towards the base centre), 0 when it rolls:
    it adds to the velocity of the centre of mass before the impact.

    Returns
    -------
    float
        Kinetic energy after the impact minus before [m g R] (<= 0).
    """
    Iy = c[fk.C_IY]
    Iz = c[fk.C_IZ]
    zc = c[fk.C_ZC]
    A = c[fk.C_A]
    C = Iz - 1.0
    s = math.sin(theta_c)
    # body components (xi, eta, zeta) before the impact (paper Eq. 3)
    w1 = y[fk.DTHETA]
    w2 = y[fk.DPHI] * s
    w3 = y[fk.OMEGA]
    # velocity of the centre of mass, v = w x r_PC with r_PC = (0, 1, zc)
    v1 = w2 * zc - w3 + slip_xi
    v2 = -w1 * zc + slip_n
    v3 = w1
    # angular momentum about the new pivot, r_P'C = (0, -1, zc)
    h1 = A * w1 + (-1.0 * v3 - zc * v2)
    h2 = A * w2 + (zc * v1 - 0.0 * v3)
    h3 = C * w3 + (0.0 * v2 + 1.0 * v1)
    # inertia about P': diag(A + 1 + zc^2, A + zc^2, C + 1) with eta-zeta term +zc
    i11 = A + 1.0 + zc * zc
    i22 = A + zc * zc
    i33 = C + 1.0
    i23 = zc  # -m (y z) with y = -1, z = zc
    u1 = h1 / i11
    det = i22 * i33 - i23 * i23
    u2 = (i33 * h2 - i23 * h3) / det
    u3 = (i22 * h3 - i23 * h2) / det
    ke_before = 0.5 * (A * (w1 * w1 + w2 * w2) + C * w3 * w3 + v1 * v1 + v2 * v2 + v3 * v3)
    # new frame: xi' = -xi, eta' = -eta, zeta' = zeta
    n1, n2, n3 = -u1, -u2, u3
    ke_after = 0.5 * (Iy * n1 * n1 + (Iy - 1.0) * n2 * n2 + Iz * n3 * n3) - zc * n2 * n3
    for i in range(y.shape[0]):
        y_out[i] = y[i]
    sph, cph = fk.sincos(y[fk.PHI])
    y_out[fk.XP] = y[fk.XP] - 2.0 * sph
    y_out[fk.YP] = y[fk.YP] + 2.0 * cph
    y_out[fk.PHI] = y[fk.PHI] - math.pi if y[fk.PHI] > 0.0 else y[fk.PHI] + math.pi
    y_out[fk.PSI] = y[fk.PSI] - math.pi
    y_out[fk.THETA] = theta_c
    y_out[fk.DTHETA] = n1
    # theta_c = 0 is allowed for planar motion only (n2 = 0 there)
    y_out[fk.DPHI] = n2 / s if s != 0.0 else (0.0 if n2 == 0.0 else math.nan)
    y_out[fk.OMEGA] = n3
    return ke_after - ke_before
