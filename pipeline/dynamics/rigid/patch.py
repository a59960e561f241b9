"""The contact patch under the rim of a rigid column on a compliant base (compiled).

Kernel layer, dimensionless (lengths per R, forces per m g). The rigid models put
the whole contact force at one rim point P. A real base of stone on stone is a
flat face pressed into a compliant joint: the compliant model of
:mod:`pipeline.dynamics.compliant.assembly` takes it as a Winkler bed, a normal stiffness
k_n per unit area with a dashpot c_n per unit area beside it. Tilted by theta
about its rim, a disc pressed into such a bed touches over a circular segment
of height w (from the rim inwards), with pressure ``k_n theta (w - s)`` at the
distance s from the rim's tangent. The load fixes w:

    N / (m g) = (theta / theta_k) F(w) / pi,  F(w) = w A(w) - S1(w),

with A the segment's area, S1 its first moment about the tangent and
``theta_k = m g / (k_n pi R^2 R)`` the tilt at which a disc under its own
weight just loses full contact (w = 2: the whole base). From the patch the
rigid models take two couples (:mod:`pipeline.dynamics.rigid.phases3d`):

* **rolling damping**: the dashpots under a patch turning with the body at
  the horizontal angular velocity (omega_xi, omega_n) dissipate
  ``c_n (J_n omega_xi^2 + J_x omega_n^2)``, with ``J_n`` and ``J_x`` the
  patch's second moments about its own centroid across and along the rim
  (the spring forces change little as it rolls, ``int k_n d' dA ~ 0``, so
  the patch's points sink and rise about its centroid, not about P): a
  couple ``-c_n (J_n omega_xi, J_x omega_n)``. It is the moment of a
  redistribution of the contact pressure, which stays compressive: it can be
  no larger than the normal force times the patch's extent from P (its depth
  w across the rim, its half-chord along it), and is capped there;
* **drilling friction**: turning about the vertical through P slides the
  patch on the ground, which Coulomb friction resists with the couple
  ``mu N r_d`` at most, ``r_d = int p |x| dA / N`` the pressure-weighted
  lever (the patch is long along the rim and short across it, so |x| is the
  distance from P to within the patch's depth w).

``tests/dynamics/test_patch.py`` checks the closed forms against quadrature.
"""

import math

from numba import njit

FULL = 2.0  # segment height of the whole base [R]
_NEWTON_STEPS = 8


@njit(cache=True)
def segment(w):
    """Integrals over the segment of the unit disc within w of a rim point's tangent.

    Parameters
    ----------
    w : float
        Segment height [R], clipped to [0, 2].

    Returns
    -------
    tuple of float
        ``(A, S1, J_n, J_x, L)``: area, first and second moments of the
        distance s from the tangent, second moment of the distance x along
        it, and ``L = int (w - s) |x| dA`` (the lever integral of drilling).
    """
    w = min(max(w, 0.0), FULL)
    c = 1.0 - w  # cos of the segment's half angle
    s = math.sqrt(max(0.0, 1.0 - c * c))
    alpha = math.acos(c)
    area = alpha - s * c
    y1 = 2.0 / 3.0 * s**3  # int y dA, y from the centre towards P
    y2 = 0.25 * (alpha - s * c + 2.0 * s**3 * c)  # int y^2 dA
    x2 = (alpha - s * c) / 4.0 - s**3 * c / 6.0  # int x^2 dA
    s1 = area - y1
    jn = area - 2.0 * y1 + y2
    lever = w**3 / 3.0 - w**4 / 12.0
    return area, s1, jn, x2, lever


@njit(cache=True)
def depth(load, theta, theta_k):
    """Segment height w [R] of the patch carrying ``load`` [m g] at tilt theta [rad].

    Solves ``(theta / theta_k) F(w) / pi = load`` (F increasing, F' = A) by
    Newton from the small-w form ``F ~ (8 sqrt 2 / 15) w^(5/2)``; a load the
    whole base takes at that tilt gives w = 2.
    """
    if load <= 0.0:
        return 0.0
    if theta <= 0.0:
        return FULL
    target = math.pi * load * theta_k / theta
    if target >= math.pi:  # F(2) = 2 pi - pi
        return FULL
    w = min(FULL, (target / _SMALL) ** 0.4)
    for _i in range(_NEWTON_STEPS):
        area, s1 = _area_moment(w)
        if area <= 0.0:
            break
        step = (w * area - s1 - target) / area
        w = min(FULL, max(0.5 * w, w - step))
        if abs(step) <= 1e-13 * w:
            break
    return w


_SMALL = 8.0 * math.sqrt(2.0) / 15.0  # F(w) ~ _SMALL w^(5/2) for a shallow segment


@njit(cache=True)
def _area_moment(w):
    """Area and first moment about the tangent of the segment of height w (see :func:`segment`)."""
    c = 1.0 - w
    s = math.sqrt(max(0.0, 1.0 - c * c))
    area = math.acos(c) - s * c
    return area, area - 2.0 / 3.0 * s**3


@njit(cache=True)
def couples(load, theta, theta_k, damping, mu, omega_xi, omega_n):
    """Rolling-damping couple and drilling capacity of the patch.

    Parameters
    ----------
    load : float
        Normal force N [m g].
    theta : float
        Tilt [rad].
    theta_k : float
        Tilt of lost full contact under the weight, m g / (k_n pi R^3) [rad].
    damping : float
        c_n R^3 / (m sqrt(g R)), the dashpots per unit area [1].
    mu : float
        Friction coefficient [1].
    omega_xi, omega_n : float
        Horizontal angular velocity along the line of nodes and along n [1/tau].

    Returns
    -------
    tuple of float
        ``(M_xi, M_n, drill)``: the damping couple [m g R] and the largest
        drilling couple friction can give, ``mu N r_d`` [m g R].
    """
    if load <= 0.0 or theta_k <= 0.0:
        return 0.0, 0.0, 0.0
    w = depth(load, theta, theta_k)
    area, s1, jn, jx, lever = segment(w)
    f = w * area - s1
    drill = mu * load * lever / f if f > 0.0 else 0.0
    if area > 0.0:
        jn -= s1 * s1 / area  # about the centroid (x = 0 is the patch's own axis already)
    half_chord = math.sqrt(max(0.0, w * (2.0 - w))) if w < 1.0 else 1.0
    m_xi = -math.copysign(min(damping * jn * abs(omega_xi), load * w), omega_xi)
    m_n = -math.copysign(min(damping * jx * abs(omega_n), load * half_chord), omega_n)
    return m_xi, m_n, drill


__all__ = ["segment", "depth", "couples", "FULL"]
