"""The joint law of the compliant-contact models, written once.

A joint (the base of a column on the ground, or a bed joint between two drums) is a set of
contact points, each standing for a patch of area A of the upper body's bed face
(:func:`contact_points`). Each point carries, in the frame of the lower face:

* **normal**: a spring-dashpot in compression only (the linear joint of DEM codes such as
  3DEC), ``f_n = A s (k_n d + c_n d' min(1, d/delta))`` for a penetration ``d > 0``,
  clipped at zero: the joint never pulls. The dashpot engages over the first ``delta`` of
  penetration (the caller passes the joint's static penetration, microns): a dashpot at
  full strength from d = 0+ would make the force jump when a point touches, and a point
  pressed lightly against the face would then chatter on d = 0 (a sliding mode of the
  discontinuous force that an adaptive integrator follows with steps of nanoseconds).
  ``s`` in [0, 1] is the fraction of the patch that lies over the lower face
  (:func:`overlap`): 1 inside, running off to 0 as a smoothstep across a narrow band past
  the face's edge, so that a drum sliding off the one below loses its support continuously
  and without a jump in the force (the band's width is a numerical choice:
  ``numerics["edge_band"]`` of :mod:`pipeline.models.compliant`).
* **shear**: an elastic spring with memory, capped by Coulomb friction (the joint of 3DEC
  and other DEM codes: shear force accumulated from the relative tangential velocity, limited
  to mu times the normal force, unloading elastic at once). Its state is the shear
  displacement ``u`` (two components in the face plane). Inside the cone,
  ``k_s A |u| < mu f_el``, the point sticks: ``u' = v_t`` and the force on the upper body is
  ``-k_s A u - c_s A v_t``, a spring-dashpot as in the normal direction (the shear dashpot
  has the normal one's ratio to the stiffness, as stiffness-proportional damping in DEM
  codes; without it the column rattles on its undamped shear springs while it sticks, and
  enters a slip with the rattle's velocity). The dashpot gives no more than keeps the whole
  shear force within ``mu f_el``. On the cone it slips: the force is ``-mu f_el n`` with ``n = u/|u|``, exactly
  Coulomb's, and ``u' = v_t - lambda n`` with the slip rate ``lambda`` taking up the outward
  push ``g = n.v_t - (mu f_el)'/(k_s A)`` (the consistency condition of
  elastic-perfectly plastic friction). The cap uses the elastic normal force
  ``f_el = A s k_n d``, whose rate is known in closed form; the dashpot does not add to it.
  ``f_el`` is the friction limit of the elastic joint of DEM codes, and the friction of the
  impact itself is carried by the stiff spring, not the dashpot.

  Why this form, for an adaptive integrator: a state that had to stay *on* the cone would
  chatter across it (the field points into the cone from both sides, the sliding mode of a
  discontinuous right-hand side; steps of nanoseconds). Here the state leaves the cone
  outwards (only ``1 - ETA`` of the push is taken up) and is held a relative ``EPS`` beyond
  it by a return on the time scale ``tau``; beyond the cone the force is the cap whatever
  the state, so this costs a dead band of ``EPS`` of the elastic displacement (plus
  ``ETA tau g``) when the slip reverses, microns at most. The spring turns towards a new
  slip direction at the rate ``|v_t| / |u|``, which a nearly unloaded point makes stiff
  without bound; below ``u_floor`` (the elastic displacement at the cap under the joint's
  mean pressure) it turns as a spring of that length would. A point without normal force
  carries no shear; its spring relaxes with time constant ``tau``.

Energy: the elastic energy of a point is ``1/2 k_n A s d^2`` plus ``1/2 k_s A |u|^2``, the
shear spring's own energy, in contact or not: a smooth function of the state. The damping
and friction dissipation rates returned here are exactly what the forces take out of kinetic
plus elastic energy (``(f_n - f_el) d'``, ``c_s A |v_t|^2``; friction ``mu f_el v_n`` less
what the spring stores, ``k_s A |u| (v_n - lambda)``, while it slips, and ``k_s A |u|^2 / tau``
while an unloaded spring relaxes), whatever the state does inside the dead band; this is
what makes the energy budget of the models close to the integration error. In steady slip
the friction rate is Coulomb's ``mu f_el |v_t|``; the spring holds the dead band's energy
(microjoules) and gives it back as friction when the slip reverses. (While the friction limit
grows past a state inside the dead band the friction rate is slightly negative,
``-(k_s A |u| - mu f_el) v_n``: the dead band's own energy.)

Why the spring's energy and not the capped force's ``1/2 (mu f_el)^2 / (k_s A)``: that one
has a kink on the cone, and friction then a jump in its rate wherever a slipping point
unloads back into the cone (every slip reversal) with no jump in any state's rate. The
integrator accumulates friction by quadrature, and a Runge-Kutta quadrature across a jump is
off by ~0.1-0.3 of the step times the jump while its embedded error estimate sees 10-150
times less: the budget of a ten-drum stack missed 1e-6 of the work whatever the tolerance.
With a smooth energy, the jumps left (the shear dashpot switching on, the slip rate at the
start of a slip) are in the states' rates too, and the budget's error is the integrator's.

Kernel layer: floats and arrays in, floats out; units are the caller's (the stack kernel
passes dimensionless values).
"""

import functools
import math

import numpy as np
from numba import njit

# A point exactly on the edge of the lower face (a rim point of a drum on a drum of the same
# radius) counts as over the face: its radius is the face radius to within rounding.
EDGE_TOL = 1e-9


@njit(cache=True, inline="always")
def overlap(rho, face_radius, band):
    """Fraction of a contact patch over the lower face, and its derivative in radius.

    Parameters
    ----------
    rho : float
        Distance of the contact point from the axis of the lower face [length].
    face_radius : float
        Radius of the lower face [length]; ``inf`` for the ground.
    band : float
        Width of the band past the edge over which the patch runs off the face [length].

    Returns
    -------
    tuple of float
        ``(s, ds/drho)``: 1 and 0 over the face, then linear down to 0 at
        ``face_radius + band``.
    """
    edge = face_radius * (1.0 + EDGE_TOL)
    if rho <= edge:
        return 1.0, 0.0
    x = (rho - edge) / band
    if x >= 1.0:
        return 0.0, 0.0
    # smoothstep: s and ds/drho are continuous at both ends of the band, so the pull of the
    # band (from 1/2 k A s d^2) does not jump where a point leaves it
    return 1.0 - x * x * (3.0 - 2.0 * x), -6.0 * x * (1.0 - x) / band


@njit(cache=True)
def normal_force(area, kn, cn, delta, s, d, d_dot):
    """Normal force of one contact point, compression only.

    Parameters
    ----------
    area : float
        Area of the point's patch [length^2].
    kn : float
        Normal stiffness per unit area [force/length^3].
    cn : float
        Normal damping per unit area [force time/length^3].
    delta : float
        Penetration over which the dashpot engages [length], > 0.
    s : float
        Fraction of the patch over the lower face [1] (:func:`overlap`).
    d, d_dot : float
        Penetration [length] (> 0 in contact) and its rate [length/time].

    Returns
    -------
    tuple of float
        ``(f_n, f_elastic, dissipation)``: the force (>= 0), its elastic part
        ``A s k_n d`` and the power the dashpot takes out, ``(f_n - f_elastic) d'`` (>= 0:
        ``A s c_n min(1, d/delta) d'^2`` in contact, and while the clipped joint separates
        faster than the spring relaxes, the elastic energy it releases without doing work).
    """
    if d <= 0.0 or s <= 0.0:
        return 0.0, 0.0, 0.0
    f_el = area * s * kn * d
    f = f_el + area * s * cn * d_dot * min(1.0, d / delta)
    if f < 0.0:
        f = 0.0
    return f, f_el, (f - f_el) * d_dot


@njit(cache=True)
def _viscous_share(ax, ay, bx, by, cap):
    """Largest share in [0, 1] of the dashpot force b that keeps |a + share b| <= cap.

    Friction limits the joint's whole shear resistance, spring and dashpot: a sudden load on
    a sticking point must not draw more than mu N from its dashpot. At the cone (|a| = cap,
    b outwards) the share is 0, so the force does not jump when the point starts to slip.
    """
    bb = bx * bx + by * by
    if bb == 0.0:
        return 1.0
    ab = ax * bx + ay * by
    room = cap * cap - (ax * ax + ay * ay)  # > 0 inside the cone
    if (ax + bx) ** 2 + (ay + by) ** 2 <= cap * cap:
        return 1.0
    return max(0.0, (-ab + math.sqrt(ab * ab + bb * room)) / bb)


# Slip on the cone: the share of the outward push that the state keeps (it leaves the cone),
# and the relative distance beyond the cone at which the return holds it.
ETA = 0.05
EPS = 1e-3


@njit(cache=True)
def shear_law(ux, uy, vx, vy, cap, cap_rate, k_area, c_area, tau, u_floor):
    """Shear force of one point, the rate of its state, its energy and dissipation.

    Parameters
    ----------
    ux, uy : float
        Shear displacement (the state) [length], in the frame of the lower face.
    vx, vy : float
        Tangential velocity of the upper point relative to the lower face [length/time].
    cap : float
        Friction limit ``mu f_el`` [force]; 0 when the point carries no elastic force.
    cap_rate : float
        Its time derivative [force/time].
    k_area : float
        Shear stiffness of the point, ``k_s A`` [force/length].
    c_area : float
        Shear dashpot of the point while it sticks [force time/length] (the caller gives it
        the normal dashpot's ratio to the stiffness, engaged as the normal one).
    tau : float
        Time of the return to the cone and of the relaxation of an unloaded spring [time].
    u_floor : float
        Length below which the spring turns no faster than one of this length [length].

    Returns
    -------
    tuple of float
        ``(ux', uy', fx, fy, energy, friction, damping, slip rate)``: the force on the upper
        body (fx, fy) [force], the elastic energy ``1/2 k_s A |u|^2`` of the spring, the
        power friction takes out (``mu f_el v_n - k_s A |u| (v_n - lambda)`` on the cone,
        ``k_s A |u|^2 / tau`` without normal force, 0 inside the cone), the power of the
        dashpot ``c A |v_t|^2`` and the slip rate ``lambda`` [length/time].
    """
    if cap <= 0.0:
        dux, duy, energy, friction = unloaded_spring(ux, uy, k_area, tau)
        return dux, duy, 0.0, 0.0, energy, friction, 0.0, 0.0
    ur = math.sqrt(ux * ux + uy * uy)
    if k_area * ur < cap:  # stick (and elastic unloading)
        c = c_area * _viscous_share(k_area * ux, k_area * uy, c_area * vx, c_area * vy, cap)
        return (vx, vy, -k_area * ux - c * vx, -k_area * uy - c * vy, 0.5 * k_area * ur * ur, 0.0,
                c * (vx * vx + vy * vy), 0.0)
    nx = ux / ur
    ny = uy / ur
    vn = nx * vx + ny * vy
    g = vn - cap_rate / k_area
    lam = (1.0 - ETA) * max(g, 0.0) + max(ur - (1.0 + EPS) * cap / k_area, 0.0) / tau
    turn = min(1.0, ur / u_floor)
    dux = vn * nx + turn * (vx - vn * nx) - lam * nx
    duy = vn * ny + turn * (vy - vn * ny) - lam * ny
    # the spring stores 1/2 k |u|^2 (d/dt: k |u| (vn - lam)), the capped force takes cap vn out
    # of the bodies: friction is the rest, cap vn - k |u| (vn - lam), written so that the
    # dead band's small (k |u| - cap) is not the difference of two large terms
    friction = k_area * ur * lam - (k_area * ur - cap) * vn
    return dux, duy, -cap * nx, -cap * ny, 0.5 * k_area * ur * ur, friction, 0.0, lam


@njit(cache=True)
def unloaded_spring(ux, uy, k_area, tau):
    """The shear spring of a point without normal force: it relaxes with time constant tau.

    Returns
    -------
    tuple of float
        ``(ux', uy', energy, friction)``: the state's rate, the spring's elastic energy
        ``1/2 k_s A |u|^2`` and the power its relaxation dissipates, ``k_s A |u|^2 / tau``
        (booked as friction: the joint lets go of its shear without doing work).
    """
    uu = ux * ux + uy * uy
    return -ux / tau, -uy / tau, 0.5 * k_area * uu, k_area * uu / tau


def lobatto_nodes(n):
    """Gauss-Lobatto nodes and weights on [-1, 1] (n >= 2 points, exact to degree 2n - 3)."""
    if n < 2:
        raise ValueError("Gauss-Lobatto needs at least 2 nodes")
    x, w = _lobatto(int(n))
    return np.array(x), np.array(w)


@functools.lru_cache(maxsize=None)
def _lobatto(n):
    """:func:`lobatto_nodes` as tuples, once per n: a structure asks for them at every joint (a
    colonnade's layout, twice a run, spent a third of its time in numpy's polynomials)."""
    inner = np.polynomial.legendre.Legendre.basis(n - 1).deriv().roots()
    x = np.concatenate([[-1.0], np.sort(inner.real), [1.0]])
    p = np.polynomial.legendre.Legendre.basis(n - 1)(x)
    w = 2.0 / (n * (n - 1) * p * p)
    return tuple(x.tolist()), tuple(w.tolist())


def contact_points(radius, inner_radius, rings, sectors):
    """Contact points of a disc or an annulus: rings x sectors, area and second moment exact.

    The radii are the ``rings`` Gauss-Lobatto nodes on [inner_radius, radius], so one ring
    lies on the rim itself (where the rigid model pivots) and, for an annulus, one on its
    inner edge. Each ring's area is its Lobatto weight times ``2 pi r``: the quadrature of
    ``int r dr`` and ``int r^3 dr`` is exact for ``rings >= 3``, so the points' total area
    and second moment of area equal the disc's (annulus's). A node at the centre carries no
    area and is dropped. The ``sectors`` points of a ring are equally spaced from the +x
    axis and share its area.

    The points come in pairs ``p, -p`` next to each other. Summed in this order the moments
    of equal forces cancel exactly after every pair, so that a column at rest under its
    weight feels no moment at all, not one of round-off size.

    Parameters
    ----------
    radius : float
        Outer radius [length].
    inner_radius : float
        Inner radius [length], 0 for a full disc.
    rings : int
        Gauss-Lobatto nodes in radius, >= 2 (>= 3 for an exact second moment).
    sectors : int
        Points per ring, even, >= 4.

    Returns
    -------
    numpy.ndarray
        Shape (n, 3): x, y [length] in the plane of the face, area [length^2].
    """
    if sectors < 4 or sectors % 2:
        raise ValueError(f"sectors = {sectors} must be an even number >= 4")
    if not 0.0 <= inner_radius < radius:
        raise ValueError(f"inner radius {inner_radius} must be in [0, {radius})")
    x, w = lobatto_nodes(rings)
    half = 0.5 * (radius - inner_radius)
    r = inner_radius + half * (x + 1.0)
    r[0], r[-1] = inner_radius, radius  # the edges exactly
    ring_area = 2.0 * math.pi * r * w * half
    rows = []
    for rk, ak in zip(r, ring_area):
        if ak <= 0.0:
            continue  # the centre of a full disc
        a = ak / sectors
        for k in range(sectors // 2):
            angle = 2.0 * math.pi * k / sectors
            c, s = math.cos(angle), math.sin(angle)
            if k == 0:
                c, s = 1.0, 0.0
            elif 4 * k == sectors:
                c, s = 0.0, 1.0
            rows.append((rk * c, rk * s, a))
            rows.append((-rk * c, -rk * s, a))
    return np.array(rows, dtype=np.float64)
