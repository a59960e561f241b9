"""The compliant-contact model: a column of rigid drums on joints of contact points.

Friendly layer over :mod:`pipeline.dynamics.compliant.stack`: builds the dimensionless tables of a
monolith or of a multi-drum column (:class:`pipeline.structures.drums.DrumColumn`), sets the normal
damping from a target coefficient of restitution (:func:`calibrated_damping`), runs the
compiled kernel and returns a :class:`pipeline.response.Response` with the rigid models'
summary keys and history names (docs/model.md, "The compliant-contact model").
"""

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.optimize import brentq

from pipeline.structures.drums import DrumColumn
from pipeline.dynamics.compliant import joint as jl
from pipeline.dynamics.compliant import linear_system
from pipeline.dynamics.compliant import semi_implicit as si
from pipeline.dynamics.compliant import stack as sk
from pipeline.errors import InputError
from pipeline.structures.column import Column
from pipeline.models.compliant import COMPLIANT_DRUMS
from pipeline.response import Response
from pipeline.settings import Excitation, ModelSettings, check_column, housner_restitution
from pipeline.units import G


@dataclass(frozen=True)
class Assembly:
    """Dimensionless tables of one column for the kernel, and the reference scales.

    Attributes
    ----------
    bodies, points, joint_start, joints : numpy.ndarray
        Tables of :mod:`pipeline.dynamics.compliant.stack` (weights not yet set).
    length : float
        Reference length L, the base radius [m].
    mass : float
        Total mass M [kg].
    time : float
        sqrt(L/g) [s].
    body_lie : tuple of float
        Lying tilt of each body [rad].
    barrier : float
        The lowest overturning barrier [M g L] (:func:`overturning_barriers`).
    critical : numpy.ndarray
        Critical tilt of the part above each body's joint [rad].
    """

    bodies: np.ndarray
    points: np.ndarray
    joint_start: np.ndarray
    joints: np.ndarray
    length: float
    mass: float
    time: float
    body_lie: tuple
    barrier: float
    critical: np.ndarray

    @property
    def n_bodies(self):
        return self.bodies.shape[0]

    def params(self, record=None, dt=1.0):
        """Kernel parameters with a record (n, 3) [g] sampled every dt [tau]."""
        record = np.zeros((0, 3)) if record is None else record
        return sk.make_params(self.bodies.copy(), self.points, self.joint_start, self.joints, record, dt)


def lying_tilt(R, r, h):
    """Tilt at which the side of a frustum (R, r, h) touches the ground [rad].

    Pivoting on its rim, the generator through the pivot leans inwards by atan((R - r)/h)
    when upright, so it reaches the ground at ``pi/2 + atan((R - r)/h)`` (91.43 deg for
    R = 0.5, r = 0.4, h = 4 m; 90 deg for a cylinder or a block).
    """
    return 0.5 * math.pi + math.atan((R - r) / h)


def overturning_barriers(masses, heights, centres, radii):
    """The lowest overturning barrier of a stack and the critical tilt of the part above each joint.

    The part of the stack above joint b (bodies b to the top) tips as one block about the
    rim of the joint's face (radius a_b) when its centre of mass, z_b above the joint, passes
    over it: at the tilt atan(a_b / z_b), its weight risen by ``M_b (sqrt(a_b^2 + z_b^2) - z_b)``.
    The lowest of these rises is the energy a column must gain to overturn by any part
    tipping as a block (a mechanism with several joints open at once is taken to need no less).

    Parameters
    ----------
    masses, heights, centres, radii : sequence of float, one per body bottom first
        Mass, height, centre of mass above its base, radius of its joint's face, in the
        same units of mass and length.

    Returns
    -------
    barrier : float
        In those units of mass times length (times g: an energy per g).
    critical : numpy.ndarray
        [rad], per joint.
    """
    n = len(masses)
    base = np.concatenate([[0.0], np.cumsum(heights)[:-1]])  # each body's base above the ground
    rises, critical = [], np.empty(n)
    for b in range(n):
        mass = float(np.sum(masses[b:]))
        z = float(np.dot(masses[b:], base[b:] + np.asarray(centres[b:]))) / mass - base[b]
        critical[b] = math.atan2(radii[b], z)
        rises.append(mass * (math.hypot(radii[b], z) - z))
    return min(rises), critical


def as_stack(column):
    """A :class:`DrumColumn` from a Column (the monolith) or a DrumColumn."""
    if isinstance(column, DrumColumn):
        return column
    if isinstance(column, Column):
        return DrumColumn(column)
    raise InputError(f"column must be a Column or a DrumColumn, got {type(column).__name__}")


def _per_joint(value, n, name, default):
    """One value per bed joint (n of them) from None, a number or a sequence."""
    if value is None:
        return [default] * n
    if isinstance(value, (int, float)):
        return [float(value)] * n
    values = [float(v) for v in value]
    if len(values) != n:
        raise InputError(f"{name} has {len(values)} values for {n} bed joint(s): give one number, or one per joint")
    return values


def assemble(column, settings, damping):
    """Dimensionless tables of a column for :mod:`pipeline.dynamics.compliant.stack`.

    Parameters
    ----------
    column : pipeline.structures.column.Column or pipeline.structures.drums.DrumColumn
    settings : pipeline.settings.ModelSettings
        Joint stiffness, ratio, friction, contact points, anathyrosis.
    damping : float
        Normal damping per unit area c_n [Pa s/m] of the base; a bed joint of another
        stiffness gets the same damping ratio, c_n sqrt(k_joint / k_n).

    Returns
    -------
    Assembly
    """
    stack = as_stack(column)
    edge_band = numerics(settings)["edge_band"]
    density = stack.density
    drums = stack.drums()
    L = stack.column.R
    # bodies: (mass [kg], transverse and axial central inertia [kg m^2], z_cm, top height,
    # top radius, contact radius of the base [m], lying tilt)
    rows = []
    for d in drums:
        m = density * d.volume
        a, c = d.central_inertia_hat
        rows.append((m, a * m * d.R**2, c * m * d.R**2, d.z_cm, d.h, d.r, d.R, lying_tilt(d.R, d.r, d.h)))
    if stack.capital is not None:
        cap = stack.capital
        it, ia = cap.inertia(density)
        rows.append((cap.mass(density), it, ia, 0.5 * cap.height, cap.height, 0.5 * cap.side, drums[-1].r,
                     0.5 * math.pi))
    M = sum(r[0] for r in rows)
    T = math.sqrt(L / G)
    n = len(rows)
    bodies = np.zeros((n, sk.N_BODY_COLS))
    for b, (m, it, ia, zc, top, top_r, _base_r, lie) in enumerate(rows):
        bodies[b, sk.B_MASS] = m / M
        bodies[b, sk.B_IT] = it / (M * L * L)
        bodies[b, sk.B_IA] = ia / (M * L * L)
        bodies[b, sk.B_ZC] = zc / L
        bodies[b, sk.B_TOP] = top / L
        bodies[b, sk.B_TOP_R] = top_r / L
        bodies[b, sk.B_WEIGHT] = m / M
        bodies[b, sk.B_COS_LIE] = math.cos(lie)
    friction = [settings.friction] + _per_joint(settings.joint_friction, n - 1, "joint_friction", settings.friction)
    inner = [settings.base_anathyrosis] + _per_joint(settings.anathyrosis, n - 1, "anathyrosis", 0.0)
    force = M * G  # force unit
    # the base on the ground, then the bed joints (their own stiffness if given); the damping
    # keeps its ratio to the stiffness, as the calibrated c_n has at the base
    stiffness = [settings.normal_stiffness] + [settings.joint_stiffness or settings.normal_stiffness] * (n - 1)
    points, starts = [], [0]
    joints = np.zeros((n, sk.N_JOINT_COLS))
    above = np.cumsum(bodies[::-1, sk.B_MASS])[::-1]
    for b, row in enumerate(rows):
        radius = row[6] / L
        kn = stiffness[b] * L**3 / force
        ks = settings.stiffness_ratio * kn
        cn = damping * math.sqrt(stiffness[b] / settings.normal_stiffness) * L**3 / (force * T)
        pts = jl.contact_points(radius, inner[b] * radius, settings.contact_rings, settings.contact_sectors)
        table = np.zeros((len(pts), sk.N_POINT_COLS))
        table[:, sk.P_X], table[:, sk.P_Y], table[:, sk.P_AREA] = pts[:, 0], pts[:, 1], pts[:, 2]
        table[:, sk.P_Z] = -bodies[b, sk.B_ZC]
        points.append(table)
        starts.append(starts[-1] + len(pts))
        area = sum(pts[:, 2].tolist())  # summed in the kernel's order: full contact is exactly 1
        ring_radii = np.unique(np.round(np.hypot(pts[:, 0], pts[:, 1]), 9))  # one radius per ring
        joints[b, sk.J_KN] = kn
        joints[b, sk.J_KS] = ks
        joints[b, sk.J_MU] = friction[b]
        joints[b, sk.J_CN] = cn
        # returns to the friction cone on the time scale of the joint's own shear vibration
        joints[b, sk.J_TAU] = math.sqrt(above[b] / (ks * area))
        # the rim patch runs off the face below over edge_band spacings of the outer rings
        spacing = ring_radii[-1] - ring_radii[-2] if len(ring_radii) > 1 else radius
        joints[b, sk.J_BAND] = edge_band * spacing
        joints[b, sk.J_AREA] = area
        # rocking on the rim: the centre of pressure beyond the chord joining the neighbours
        # of a rim point (any share of the load among a pivot point and its two neighbours,
        # which a compliant pivot presses in too); landed again: back inside half the radius
        joints[b, sk.J_RIM] = radius * math.cos(2.0 * math.pi / settings.contact_sectors)
        joints[b, sk.J_LAND] = 0.5 * radius
        joints[b, sk.J_DELTA] = above[b] / (kn * area)  # the static penetration
        # the elastic shear displacement at the cap under the joint's mean pressure
        joints[b, sk.J_UFLOOR] = friction[b] * joints[b, sk.J_DELTA] / settings.stiffness_ratio
    barrier, critical = overturning_barriers(bodies[:, sk.B_MASS], bodies[:, sk.B_TOP], bodies[:, sk.B_ZC],
                                            [r[6] / L for r in rows])
    return Assembly(bodies, np.concatenate(points), np.array(starts, dtype=np.int64), joints, L, M, T,
                    tuple(r[7] for r in rows), barrier, critical)


# -- damping from a coefficient of restitution -------------------------------------------------

# Largest damping the calibration considers: critical damping of the column bouncing on its
# full base. Beyond it the restitution hardly changes (docs/model.md) and the stiff dashpot
# only shortens the steps.
MAX_DAMPING_RATIO = 1.0
RELEASE_TILT = 0.3  # release tilt of the calibration, per theta_crit


def critical_damping(column, settings):
    """Normal damping per unit area [Pa s/m] that critically damps the monolith's bounce.

    ``2 sqrt(k_n A M) / A`` for the column (mass M) on its full base (area A).
    """
    stack = as_stack(column)
    c = stack.column
    mass = stack.density * c.volume + (stack.capital.mass(stack.density) if stack.capital else 0.0)
    area = math.pi * c.R**2 * (1.0 - settings.base_anathyrosis**2)
    return 2.0 * math.sqrt(settings.normal_stiffness * mass / area)


def rest_state(params, settings):
    """The upright state of static equilibrium (:func:`pipeline.dynamics.compliant.stack.rest_state`),
    with the bodies' weights set to the joints' net forces as the settings' integrator sums
    them, so that a column left alone stays exactly still under either."""
    y = sk.rest_state(params)
    if settings.integrator == "semi-implicit":
        si.set_static_weights(y, 1.0, params, si.make_scratch(params[0].shape[0], params[1].shape[0]))
    return y


def released_state(asm, params, theta, settings):
    """A monolith tilted by theta [rad] towards +x, still, on its rim point at (R, 0).

    The pivot point is pressed in by the whole weight (its static penetration); the rest of
    the base is in the air.
    """
    y = rest_state(params, settings)
    bodies = params[0]
    q = (math.cos(0.5 * theta), 0.0, math.sin(0.5 * theta), 0.0)
    rot = np.empty(9)
    sk.rotation_matrix(*q, rot)
    rot = rot.reshape(3, 3)
    radius = float(np.max(np.hypot(asm.points[:, sk.P_X], asm.points[:, sk.P_Y])))
    pivot = rot @ np.array([radius, 0.0, -bodies[0, sk.B_ZC]])
    rim = int(np.argmax(asm.points[:, sk.P_X]))  # the rim point on the +x axis
    sink = bodies[0, sk.B_WEIGHT] / (asm.joints[0, sk.J_KN] * asm.points[rim, sk.P_AREA])
    y[sk.QW:sk.QZ + 1] = q
    y[sk.X] = -pivot[0]
    y[sk.Z] = -pivot[2] - sink
    return y


def planar_restitution(column, settings, damping, amplitude=RELEASE_TILT):
    """Coefficient of restitution of planar rocking of the compliant monolith [1].

    The column is released still, tilted by ``amplitude`` theta_crit towards a rim point; it
    falls, lands on its base and rocks up on the other side. As in the rigid model,
    ``theta'_after = e theta'_before``; the rebound peak theta_1 gives it through the energy
    of rocking: ``e^2 = (cos(a - theta_1) - cos a) / (cos(a - theta_0) - cos a)``,
    a = theta_crit.

    Parameters
    ----------
    column : pipeline.structures.column.Column or pipeline.structures.drums.DrumColumn
        Its outline is used, as one body.
    settings : pipeline.settings.ModelSettings
    damping : float
        Normal damping per unit area c_n [Pa s/m].
    amplitude : float
        Release tilt per theta_crit [1].

    Returns
    -------
    float
    """
    outline = as_stack(column).column
    outline = Column(outline.R, outline.r, outline.h, density=as_stack(column).density)
    asm = assemble(outline, settings, damping)
    params = asm.params()
    alpha = outline.critical_tilt
    theta0 = amplitude * alpha
    y0 = released_state(asm, params, theta0, settings)
    # the rigid column falls in (1/p) acosh(alpha / (alpha - theta0)) (linearised rocking)
    fall = math.acosh(alpha / (alpha - theta0)) / outline.frequency_parameter()
    tilt, _raw = _run_free(asm, params, y0, 2.6 * fall, monitor=min(2e-4, fall / 200.0), settings=settings)
    low = int(np.argmax(tilt < 0.5 * theta0))
    bottom = low + int(np.argmax(np.diff(tilt[low:]) > 0.0))
    top = bottom + int(np.argmax(np.diff(tilt[bottom:]) < 0.0))
    if top <= bottom or top >= len(tilt) - 1:
        raise InputError(_unmeasurable(outline, settings, "the released column did not rock back up "
                                                          "(no rebound peak)"))
    theta1 = _parabola_peak(tilt[top - 1:top + 2])
    drop = math.cos(alpha - theta0) - math.cos(alpha)
    return math.sqrt(max(0.0, math.cos(alpha - theta1) - math.cos(alpha)) / drop)


def _unmeasurable(outline, settings, what):
    """The message of a damping calibration that cannot measure a planar restitution."""
    sink = outline.density * outline.volume * G / (settings.normal_stiffness * math.pi * outline.R ** 2)
    return (f"normal_stiffness = {settings.normal_stiffness:g} Pa/m: the damping calibration could not measure a "
            f"rocking restitution on this bed ({what}; the column sinks {1e3 * sink:.3g} mm under its weight): "
            "give the joints' damping yourself, contact_damping [Pa s/m] (--contact-damping), or a stiffer bed "
            "(1e9 Pa/m and stiffer calibrate for the paper's column)")


def _parabola_peak(three):
    """Peak of the parabola through three equally spaced samples around a maximum."""
    a, b, c = three
    curv = a - 2.0 * b + c
    return b if curv >= 0.0 else b - 0.125 * (c - a) ** 2 / curv


def _run_free(asm, params, y0, duration, monitor, settings):
    """Run without ground motion; the top body's tilt every ``monitor`` seconds, and the raw run.

    The adaptive integrators run at rtol 1e-9, atol 1e-12 whatever the settings say; the
    fixed-step one at the settings' step (the calibration then matches the discrete model).
    """
    from dataclasses import replace

    raw = _integrate(asm, params, y0, duration, monitor, 1, replace(settings, rtol=1e-9, atol=1e-12),
                     histories=True)
    return raw.hist_body[:, -1, sk.H_TILT], raw


@lru_cache(maxsize=256)
def _calibrated(outline, settings_key, target):
    settings = _settings_from_key(settings_key)
    critical = critical_damping(outline, settings)

    def e(ratio):
        return planar_restitution(outline, settings, ratio * critical)

    e_most = e(MAX_DAMPING_RATIO)
    if not 0.0 < e_most <= 1.0:
        raise InputError(_unmeasurable(outline, settings, f"with critical damping it measured {e_most:.3g}"))
    if target <= e_most:
        return MAX_DAMPING_RATIO * critical, e_most
    e_none = e(0.0)
    if not e_most <= e_none <= 1.0 + 1e-2:
        # less damping must not lose more: the bed is too soft for a rocking measurement
        raise InputError(_unmeasurable(outline, settings, f"undamped it measured {e_none:.3g}, critically "
                                                          f"damped {e_most:.3g}"))
    if target >= e_none:
        return 0.0, e_none
    ratio = brentq(lambda z: e(z) - target, 0.0, MAX_DAMPING_RATIO, xtol=1e-5, rtol=1e-6)
    return ratio * critical, e(ratio)


_CALIBRATION_FIELDS = ("normal_stiffness", "stiffness_ratio", "friction", "contact_rings", "contact_sectors",
                       "base_anathyrosis", "integrator", "step", "numerics")


def _settings_key(settings):
    return tuple(getattr(settings, name) for name in _CALIBRATION_FIELDS)


def _settings_from_key(key):
    return ModelSettings(model=COMPLIANT_DRUMS.name, **dict(zip(_CALIBRATION_FIELDS, key)))


def calibrated_damping(column, settings, target=None):
    """Normal damping per unit area that gives the column a planar restitution, and that restitution.

    Root-finding (Brent) on :func:`planar_restitution` of the column's outline as a monolith,
    for the joint stiffness, friction and contact points of ``settings``, between no damping
    and :data:`MAX_DAMPING_RATIO` of :func:`critical_damping`. A target outside what the
    compliant contact can give is met as closely as it can: a column landing flat on a disc
    of contact points spreads the impact over the landing side, so it loses less energy than
    the rigid model's point impulse at the opposite rim point (docs/model.md); the returned
    restitution says what was reached. Cached per process (outline, joint parameters, target).

    Parameters
    ----------
    column : pipeline.structures.column.Column or pipeline.structures.drums.DrumColumn
    settings : pipeline.settings.ModelSettings
    target : float, optional
        Target restitution [1]; default ``settings.restitution``, or else the rigid model's
        own ``1 - 2 / I_y_hat`` (:func:`pipeline.settings.housner_restitution`).

    Returns
    -------
    tuple of float
        ``(c_n [Pa s/m], restitution reached [1])``.
    """
    stack = as_stack(column)
    outline = Column(stack.column.R, stack.column.r, stack.column.h, density=stack.density)
    if target is None:
        target = settings.restitution if settings.restitution is not None else housner_restitution(outline)
    return _calibrated(outline, _settings_key(settings), float(target))


# -- running -----------------------------------------------------------------------------------

@dataclass
class _Raw:
    """Dimensionless arrays of one kernel run."""

    t_mon: np.ndarray
    stride: int
    hist_y: np.ndarray
    hist_diag: np.ndarray
    hist_body: np.ndarray
    summary: np.ndarray
    body_stats: np.ndarray
    joint_stats: np.ndarray
    joint_committed: np.ndarray
    y0: np.ndarray
    y_end: np.ndarray
    step: float = math.nan  # fixed step [s] (semi-implicit), NaN for the adaptive integrators


def fixed_step(asm, params, y, settings):
    """The semi-implicit integrator's step for a column [s], and its stability limit [s].

    The limit is ``2 / omega_max`` of the stiffest joint mode in the state y
    (:func:`pipeline.dynamics.compliant.linear_system.stiffest_frequency`); the step is
    ``settings.step`` if given (refused if above the limit), else ``step_safety`` times the limit.

    Raises
    ------
    InputError
        A given step above the stability limit, before anything is computed.
    """
    limit = 2.0 / linear_system.stiffest_frequency(params, y) * asm.time
    if settings.step is not None:
        if settings.step > limit:
            raise InputError(
                f"step = {settings.step:g} s is above the stability limit {limit:.3g} s of the semi-implicit "
                f"integrator for this column (2 / omega of its stiffest joint, k_n = {settings.normal_stiffness:g} "
                f"Pa/m): give a step of at most {limit:.3g} s, or omit step for {numerics(settings)['step_safety']:g} "
                "of the limit")
        return float(settings.step), limit
    return numerics(settings)["step_safety"] * limit, limit


def numerics(settings):
    """The compliant model's numerical choices: the defaults of its registry entry
    (:data:`pipeline.models.compliant.COMPLIANT_DRUMS`), the settings' overrides."""
    return {**COMPLIANT_DRUMS.numerics, **dict(settings.numerics)}


def _integrate(asm, params, y0, duration, monitor, stride, settings, histories, theta_commit=math.inf,
               step=None, progress=None, settle_limit=0.0):
    """Run the kernel for ``duration`` [s], sampling every ``monitor`` [s]; history every ``stride``.

    The integrator, its tolerances (adaptive) or step (fixed) come from ``settings``. The
    adaptive ones take their statistics at the samples; the fixed-step one at every step, its
    samples (history rows) interpolated between steps, so the grid never changes its steps.
    ``step`` [s] is the fixed step if already found (:func:`fixed_step`).
    ``progress(done, total)`` [s], if given, is called as the run goes on (the fixed-step
    integrator runs in pieces for it; the result is the same).

    If the column could still fall at ``duration`` (:func:`pipeline.dynamics.compliant.stack.stands_for_good`),
    the run goes on (the ground still after the record) until it stands for good or falls, at
    most ``settle_limit`` [s] more (then ``S_UNDECIDED``); the histories end with the run.
    """
    n_bodies = asm.n_bodies
    dtau = monitor / asm.time
    k_decide = int(math.ceil(duration / monitor - 1e-9))  # the sample that ends the record and its tail
    m = int(math.ceil((duration + settle_limit) / monitor - 1e-9)) + 1
    t_mon = np.arange(m) * dtau
    n_hist = (m - 1) // stride + 1 if histories else 0
    raw = _Raw(
        t_mon=t_mon, stride=stride,
        hist_y=np.full((n_hist, sk.kept_size(n_bodies)), np.nan),
        hist_diag=np.full((n_hist, sk.N_DIAG), np.nan),
        hist_body=np.full((n_hist, n_bodies, sk.N_HBODY), np.nan),
        summary=np.zeros(sk.N_SUMMARY), body_stats=np.zeros((n_bodies, sk.N_BODY_STATS)),
        joint_stats=np.zeros((n_bodies, sk.N_JOINT_STATS)), joint_committed=np.zeros((n_bodies, sk.N_JOINT_STATS)),
        y0=y0, y_end=np.zeros_like(y0))
    if settings.integrator == "semi-implicit":
        if step is None:
            step = fixed_step(asm, params, y0, settings)[0]
        raw.step = step
        y = y0.copy()
        scratch = si.make_scratch(n_bodies, asm.points.shape[0])
        between = np.empty((2, y0.shape[0]))
        # pieces of about a second of motion (a progress line; the same result as one piece), and
        # after the record and its tail, pieces of the same length between checks of the outcome
        second = max(1, int(round(1.0 / monitor)))
        piece = second if progress is not None else m
        k = 0
        while k < m:
            stop = min(k_decide + 1, max(k, 1) + piece) if k <= k_decide else min(m, k + second)
            k = si.run(params, y, t_mon, k, stop, step / asm.time, stride, theta_commit,
                       raw.hist_y, raw.hist_diag, raw.hist_body, raw.summary, raw.body_stats, raw.joint_stats,
                       raw.joint_committed, y0, between, scratch)
            if progress is not None and k <= k_decide + 1:  # the record and its tail (after them: deciding)
                progress(min(k - 1, k_decide) * monitor, k_decide * monitor)
            if k > k_decide and _stands_for_good(asm, params, y, raw):
                break
        if math.isnan(raw.summary[sk.S_OVERTURN_TIME]) and not _stands_for_good(asm, params, y, raw):
            raw.summary[sk.S_UNDECIDED] = 1.0
        raw.summary[sk.S_ENERGY_END] = sk.energy(y, params)
        raw.y_end[:] = y
        return _trimmed(raw, k_decide)
    record, dt = params[4], params[5]
    breaks = np.arange(record.shape[0]) * dt  # kinks of the linearly interpolated record
    atol = np.full(y0.shape[0], settings.atol)
    sk.run(params, y0, t_mon, stride, breaks, settings.rtol, atol, np.inf,
           np.ones(2 * n_bodies), theta_commit, raw.hist_y, raw.hist_diag, raw.hist_body, raw.summary,
           raw.body_stats, raw.joint_stats, raw.joint_committed, raw.y_end, k_decide, asm.barrier, asm.critical,
           sk.METHODS[settings.integrator])
    if raw.summary[sk.S_STATUS] < 0:
        raise RuntimeError(
            f"integration failed at t = {raw.summary[sk.S_END_TIME] * asm.time:.6g} s "
            f"(status {raw.summary[sk.S_STATUS]:.0f}); try other tolerances or joint parameters")
    return _trimmed(raw, k_decide)


def _stands_for_good(asm, params, y, raw):
    return sk.stands_for_good(y, params, raw.summary[sk.S_ENERGY_START], asm.barrier, asm.critical)


def _trimmed(raw, k_decide):
    """The run's samples and history rows up to its end (a column down has them all), at least up
    to the record and its tail (sample ``k_decide``)."""
    end = max(raw.t_mon[k_decide], raw.summary[sk.S_END_TIME])
    last = int(np.searchsorted(raw.t_mon, end * (1.0 + 1e-12), side="right")) - 1
    raw.t_mon = raw.t_mon[:last + 1]
    rows = last // raw.stride + 1
    raw.hist_y, raw.hist_diag, raw.hist_body = raw.hist_y[:rows], raw.hist_diag[:rows], raw.hist_body[:rows]
    return raw


def turned_record(motion, excitation):
    """The record turned by the incidence angle and scaled: (n, 3) [g].

    The compliant column is not axisymmetric (its contact points are not), so it really
    feels the direction of the motion: the pair is turned counter-clockwise as
    :meth:`pipeline.groundmotion.GroundMotion.rotated` does.
    """
    gamma = excitation.angle_rad
    ax = np.asarray(motion.acc_x, dtype=np.float64) * excitation.scale
    ay = np.asarray(motion.acc_y, dtype=np.float64) * excitation.scale
    az = motion.acc_z
    az = np.zeros_like(ax) if (az is None or not excitation.vertical) else np.asarray(az) * excitation.scale
    c, s = math.cos(gamma), math.sin(gamma)
    return np.ascontiguousarray(np.stack([c * ax - s * ay, s * ax + c * ay, az], axis=1) / G)


def simulate_compliant(column, motion, excitation, settings, histories=True, progress=None):
    """Response of a column at rest (monolith or drums) to a ground motion, compliant contact.

    The run of the registry's compliant model (:mod:`pipeline.models.compliant`);
    same arguments and the same :class:`pipeline.response.Response`. ``progress(done, total)``
    [s of motion], if given, is called about every simulated second (fixed-step integrator).
    """
    stack = as_stack(column)
    check_column(stack.column)
    if not isinstance(excitation, Excitation):
        raise InputError(f"excitation must be an Excitation, got {type(excitation).__name__}")
    step, limit = None, math.nan
    if settings.integrator == "semi-implicit":  # an unstable step is refused before any computing
        probe = assemble(stack, settings, 0.0)
        probe_params = probe.params()
        step, limit = fixed_step(probe, probe_params, sk.rest_state(probe_params), settings)
    if settings.contact_damping is None:
        damping, restitution = calibrated_damping(stack, settings)
    else:
        damping, restitution = settings.contact_damping, math.nan
    asm = assemble(stack, settings, damping)
    params = asm.params(turned_record(motion, excitation), motion.dt / asm.time)
    y0 = rest_state(params, settings)
    if settings.integrator == "semi-implicit":  # its statistics come from every step: samples for histories only
        stride = 1
    else:
        stride = max(1, int(math.ceil(settings.output_step / settings.monitor_step - 1e-9)))
    raw = _integrate(asm, params, y0, motion.duration + settings.tail, settings.output_step / stride, stride,
                     settings, histories, stack.column.critical_tilt,
                     step=step, progress=progress, settle_limit=settings.settle_limit)
    summary = _summary(stack, asm, params, settings, raw, damping, restitution)
    summary.update(record_id=motion.record_id, angle=float(excitation.angle), scale=float(excitation.scale),
                   step=float(raw.step), step_limit=float(limit))
    ds = _histories(stack, asm, settings, raw, motion, excitation, damping) if histories else None
    return Response(summary, ds, np.empty((0, 4)))


# -- results -----------------------------------------------------------------------------------

def _summary(stack, asm, params, settings, raw, damping, restitution):
    """The rigid models' summary keys (SI, energies per unit weight [m]) and the compliant ones."""
    s, L, T = raw.summary, asm.length, asm.time
    n = asm.n_bodies
    overturned = not math.isnan(s[sk.S_OVERTURN_TIME])
    # peaks of friction and contact before any final fall past theta_crit
    stats = raw.joint_committed if overturned else raw.joint_stats
    acc = raw.y_end[sk.NB * n + 2 * asm.points.shape[0]:]
    work, friction, damping_loss = acc[sk.A_WORK], acc[sk.A_FRICTION], acc[sk.A_DAMPING]
    e0, e1 = s[sk.S_ENERGY_START], s[sk.S_ENERGY_END]
    uplift_times = raw.joint_stats[:, sk.JS_UPLIFT_TIME]
    uplift = float(np.nanmin(uplift_times)) if np.any(np.isfinite(uplift_times)) else math.nan
    joints = joint_dislocations(asm, params, raw.y_end)
    out = {
        "model": settings.model,
        "peak_theta": float(s[sk.S_PEAK_THETA]),
        "peak_theta_ratio": float(s[sk.S_PEAK_THETA] / stack.column.critical_tilt),
        "peak_time": float(s[sk.S_PEAK_TIME] * T),
        "overturned": overturned,
        "undecided": bool(s[sk.S_UNDECIDED]),
        "overturn_time": float(s[sk.S_OVERTURN_TIME] * T),
        "collapsed": bool(s[sk.S_STATUS] == sk.STATUS_COLLAPSED),
        "uplifted": bool(math.isfinite(uplift)),
        "uplift_time": uplift * T,
        "n_impacts": int(raw.joint_stats[0, sk.JS_RETURNS]),
        "peak_mu_mob": float(stats[0, sk.JS_PEAK_MU]),
        "sliding_onset": bool(math.isfinite(stats[0, sk.JS_SLIDE_TIME])),
        "sliding_time": float(raw.joint_stats[0, sk.JS_SLIDE_TIME] * T),
        "min_normal_force_hat": float(stats[0, sk.JS_MIN_NORMAL]),
        "lift_off": bool(math.isfinite(stats[0, sk.JS_FLIGHT_TIME])),
        "lift_off_time": float(stats[0, sk.JS_FLIGHT_TIME] * T),
        "residual_rotation": float(raw.body_stats[0, sk.BS_ROTATION]),
        "residual_displacement": float(joints["joint_slip"][0]),
        "slip": float(raw.y_end[-n] * L),
        "contact_area_fraction": float(stats[0, sk.JS_MIN_AREA]),
        "energy_initial": float(e0 * L),
        "work_ground": float(work * L),
        "energy_transitions": 0.0,
        "energy_dissipated": float((friction + damping_loss) * L),
        "energy_friction": float(friction * L),
        "energy_damping": float(damping_loss * L),
        "energy_final": float(e1 * L),
        "energy_balance_error": float(((e1 - e0) - (work - friction - damping_loss)) * L),
        "rhs_evaluations": int(s[sk.S_NFEV]),
        "steps": int(s[sk.S_STEPS]),
        "rejected_steps": int(s[sk.S_REJECTED]),
        "restitution": float(restitution),
        "contact_damping": float(damping),
        "n_drums": stack.n_drums,
        "drum_peak_theta": raw.body_stats[:, sk.BS_PEAK].copy(),
        "drum_residual_rotation": raw.body_stats[:, sk.BS_ROTATION].copy(),
        "overturn_drum": int(s[sk.S_OVERTURN_BODY]) if overturned else -1,
        **joints,
        "joint_diameter": np.array(stack.joint_diameters()),
        "dislocation_ratio": dislocation_ratio(joints["joint_slip"], stack.joint_diameters()),
        "joint_uplifted": np.isfinite(uplift_times),
        "joint_peak_mu_mob": stats[:, sk.JS_PEAK_MU].copy(),
    }
    return out


def joint_dislocations(asm, params, y):
    """Dislocation of every joint of a column in the state y (the residual one at the end of a run).

    Joint k is the base of body k: joint 0 the base of drum 0 on the ground, joint k >= 1 the
    bed joint between body k - 1 and body k (the last one under a capital, if any). Measured in
    the frame of the face below (the ground's for joint 0), from the state the run started in:

    Parameters
    ----------
    asm : Assembly
    params : tuple
        The kernel parameters of ``asm`` (its scratch is overwritten).
    y : numpy.ndarray
        A state of :mod:`pipeline.dynamics.compliant.stack` (dimensionless).

    Returns
    -------
    dict of numpy.ndarray, one value per joint
        ``joint_slip`` [m]: horizontal offset of the centre of the upper base from the centre
        of the face below (joint 0: from where it stood); ``joint_twist`` [rad]: rotation of the
        upper body relative to the lower one about the lower one's axis, in (-pi, pi];
        ``joint_tilt`` [rad]: angle between the two axes (joint 0: the tilt of drum 0);
        ``joint_opening`` [m]: the widest gap between a contact point and the face below
        (0 while every point presses in).
    """
    n, L = asm.n_bodies, asm.length
    out = np.zeros((n, 4))
    sk.dislocations(y, params, out)
    rot = np.empty((n, 9))
    for b in range(n):
        o = sk.NB * b
        sk.rotation_matrix(y[o + sk.QW], y[o + sk.QX], y[o + sk.QY], y[o + sk.QZ], rot[b])
    rot = rot.reshape(n, 3, 3)
    lower = np.concatenate([np.eye(3)[None], rot[:-1]])
    relative = np.einsum("bji,bjk->bik", lower, rot)  # R_lower^T R_upper
    tilt = np.arctan2(np.hypot(relative[:, 0, 2], relative[:, 1, 2]), relative[:, 2, 2])
    return {
        "joint_slip": np.hypot(out[:, 0], out[:, 1]) * L,
        "joint_twist": out[:, 2].copy(),
        "joint_tilt": tilt,
        "joint_opening": out[:, 3] * L,
    }


def dislocation_ratio(joint_slip, joint_diameter):
    """Largest residual slip of a bed joint over that joint's diameter [1]; 0 without bed joints.

    The damage measure of :data:`pipeline.fragility.DISLOCATION_STATES`. The base (joint 0)
    is left out: the ground is an unbounded plane here, so a column's slide on it changes
    nothing of its stability, while a drum slid by s on the one below stands on a lever arm
    shortened from D/2 to D/2 - s towards the side it slid to (see the fragility module).

    Parameters
    ----------
    joint_slip, joint_diameter : array_like
        Per joint, base first [m] (:func:`joint_dislocations`).
    """
    slip = np.asarray(joint_slip, dtype=np.float64)[1:]
    diameter = np.asarray(joint_diameter, dtype=np.float64)[1:]
    return float(np.max(slip / diameter)) if slip.size else 0.0


def _body_shapes(stack):
    """(R, r, h [m], kind) of every body, bottom first: the drums (kind 0), a capital (kind 1, R = r
    half its side)."""
    shapes = [(d.R, d.r, d.h, 0) for d in stack.drums()]
    if stack.capital is not None:
        half = 0.5 * stack.capital.side
        shapes.append((half, half, stack.capital.height, 1))
    return shapes


def _euler_zxz(q):
    """(phi, psi) of the Z-X-Z Euler angles of quaternions q (rows w, x, y, z); NaN upright."""
    w, x, y, z = q.T
    s = 2.0 / (w * w + x * x + y * y + z * z)
    r13, r23 = s * (x * z + w * y), s * (y * z - w * x)
    r31, r32 = s * (x * z - w * y), s * (y * z + w * x)
    upright = (r13 == 0.0) & (r23 == 0.0)
    phi = np.where(upright, np.nan, np.arctan2(r13, -r23))
    psi = np.where(upright, np.nan, np.arctan2(r31, r32))
    return phi, psi, r13, r23


def _histories(stack, asm, settings, raw, motion, excitation, damping):
    from pipeline.dataset import annotate, append_history

    L, T = asm.length, asm.time
    n = asm.n_bodies
    rows = raw.hist_y.shape[0]
    tau = raw.t_mon[::raw.stride][:rows]
    top = sk.NB * (n - 1)
    phi, psi, _, _ = _euler_zxz(raw.hist_y[:, top + sk.QW:top + sk.QZ + 1])
    _, _, e13, e23 = _euler_zxz(raw.hist_y[:, sk.QW:sk.QZ + 1])
    zc = asm.bodies[0, sk.B_ZC]
    diag = raw.hist_diag
    # the phase flags of the rigid models (pipeline.dataset.FLAGS): in contact 0, on the rim 1,
    # overturned 2, sliding flat 3, slipping on the rim 4, in flight 5
    sliding = diag[:, sk.D_MU] >= sk.SLIDE_FRACTION * settings.friction
    on_rim = diag[:, sk.D_ON_RIM] > 0.0
    phase = np.select([tau >= raw.summary[sk.S_OVERTURN_TIME], diag[:, sk.D_NORMAL] <= 0.0, on_rim & sliding,
                       on_rim, sliding], [2, 5, 4, 1, 3], 0).astype(np.int8)
    weight = asm.mass * G
    data = {
        "theta": raw.hist_body[:, -1, sk.H_TILT],
        "phi": phi,
        "psi": psi,
        "x_p": diag[:, sk.D_COP_X] * L,
        "y_p": diag[:, sk.D_COP_Y] * L,
        "x_b": (raw.hist_y[:, sk.X] - e13 * zc) * L,
        "y_b": (raw.hist_y[:, sk.Y] - e23 * zc) * L,
        "omega_zeta": raw.hist_y[:, top + sk.WZ] / T,
        "energy_hat": diag[:, sk.D_ENERGY],
        "work_ground_hat": raw.hist_y[:, sk.NB * n + sk.A_WORK],
        "normal_force_hat": diag[:, sk.D_NORMAL],
        "tangential_force_hat": diag[:, sk.D_TANGENTIAL],
        "mu_mob": diag[:, sk.D_MU],
        "ground_acc_x": diag[:, sk.D_AX] * G,
        "ground_acc_y": diag[:, sk.D_AY] * G,
        "ground_acc_z": diag[:, sk.D_AZ] * G,
        "slip": raw.hist_y[:, -n] * L,
        "contact_area_fraction": diag[:, sk.D_AREA],
    }
    data["normal_force"] = data["normal_force_hat"] * weight
    data["tangential_force"] = data["tangential_force_hat"] * weight
    data["energy"] = data["energy_hat"] * weight * L
    variables = {k: ("time", np.asarray(v, dtype=np.float64)) for k, v in data.items()}
    variables["phase"] = ("time", phase)
    for name, col, scale in (("drum_dx", sk.H_DX, L), ("drum_dy", sk.H_DY, L), ("drum_theta", sk.H_TILT, 1.0),
                             ("drum_rotation", sk.H_ROT, 1.0)):
        variables[name] = (("time", "drum"), raw.hist_body[:, :, col] * scale)
    # with the direction of each drum's tilt and its rise, a drum's pose is whole (the animation draws it)
    states = raw.hist_y[:, :sk.NB * n].reshape(rows, n, sk.NB)
    variables["drum_dz"] = (("time", "drum"), (states[:, :, sk.Z] - raw.y0[sk.Z:sk.NB * n:sk.NB]) * L)
    variables["drum_phi"] = (("time", "drum"), np.stack(
        [_euler_zxz(states[:, b, sk.QW:sk.QZ + 1])[0] for b in range(n)], axis=1))
    import xarray as xr

    shapes = _body_shapes(stack)
    coords = {"time": tau * T, "tau": ("time", tau), "drum": np.arange(n),
              # where each body's base stood at rest [m] (the joints' static penetration included)
              "drum_z": ("drum", (raw.y0[sk.Z:sk.NB * n:sk.NB] - asm.bodies[:, sk.B_ZC]) * L)}
    for k, name in enumerate(("drum_R", "drum_r", "drum_h")):
        coords[name] = ("drum", np.array([shape[k] for shape in shapes]))
    coords["drum_kind"] = ("drum", np.array([shape[3] for shape in shapes], dtype=np.int8))
    ds = xr.Dataset(variables, coords=coords)
    ds.attrs.update(
        title="Response of a free-standing column (rigid drums on compliant joints) to ground motion",
        model=settings.model,
        column_R_m=stack.column.R,
        column_r_m=stack.column.r,
        column_h_m=stack.column.h,
        n_drums=stack.n_drums,
        capital="none" if stack.capital is None else f"{stack.capital.side:g} x {stack.capital.height:g} m",
        density_kg_m3=stack.density,
        theta_crit_rad=stack.column.critical_tilt,
        normal_stiffness_Pa_m=settings.normal_stiffness,
        stiffness_ratio=settings.stiffness_ratio,
        contact_damping_Pa_s_m=damping,
        contact_points=f"{settings.contact_rings} Gauss-Lobatto rings x {settings.contact_sectors} sectors",
        friction=settings.friction,
        integrator=settings.integrator,
        **({"step_s": raw.step} if settings.integrator == "semi-implicit" else
           {"rtol": settings.rtol, "atol": settings.atol}),
        record_id=motion.record_id,
        record_sha256=motion.sha256(),
        incidence_angle_rad=excitation.angle_rad,
        scale=excitation.scale,
    )
    annotate(ds)
    append_history(ds, f"pipeline.compliant ({settings.model}, {stack.n_drums} drum(s))")
    return ds
