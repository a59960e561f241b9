"""Fixed-step semi-implicit integrator of the compliant models (a monolith, a drum column, a colonnade).

The integrator of DEM codes (3DEC, PFC) written for the joint law of
:mod:`pipeline.dynamics.compliant.joint` and the assemblies of :mod:`pipeline.dynamics.compliant.assembly`,
whose state layout, tables, monitor and statistics it shares. One step of size h:

1. **Forces at the configuration q_n** (one evaluation per step): the elastic normal force of
   every contact point, ``A s k_n d``; its shear spring, returned onto the Coulomb cone first
   (elastic-perfectly plastic: if ``k_s A |u| > mu f_el`` the state is scaled back to the cone,
   and the spring energy it loses is booked as friction); the pull of a patch running off an
   edge; weights and the field ``-m a_g(t_n)``; the gyroscopic couple.
2. **Velocities, dashpots implicit**: the normal and shear dashpots are linear in the bodies'
   velocities, so ``(M + h C) V_{n+1} = M V_n + h F`` with C the dashpots' matrix at q_n. C is
   sparse in 6 x 6 blocks (a joint couples its two bodies) and is assembled per joint from sums
   over its points (weights, first and second moments of the lever arms), not per point. The
   system is solved by a block Cholesky factorisation in a fixed order that fills in nothing
   (each column's chain into its capital, then the capitals and blocks along the row: linear
   in the number of bodies; the joints' linear algebra is
   :mod:`pipeline.dynamics.compliant.linear_system`). A point whose
   normal force would pull (``f_el + c_n d' < 0``, the clipped joint) is taken out of the
   system (no elastic force, no dashpot) and the step solved again (an active set, at most
   :data:`MAX_PASSES` solves). The shear dashpot of a sticking point gets the share of the
   joint law that keeps the shear force within the cone, from the velocities at the step's
   start; a slipping point has none.
3. **Positions** with the new velocities (symplectic Euler): centres ``c += h v``, orientation
   by the exact rotation of the body-frame angular velocity over h; shear states
   ``u += h v_t`` (the relative tangential velocity in the frame of the face below); a spring
   without normal force relaxes by ``exp(-h / tau)`` until it is spent (:data:`SPENT`).

**The springs at the step's end** (joint column J_IMPLICIT, numerics ``springs = "implicit"``, the
default): the spring force a pressed point will have at the step's end, ``k (d + h d')`` with d'
at the new velocities, is the one of step 1 plus a dashpot ``h k``; so the solve of step 2 takes
``c_n -> c_n + h k_n`` (normal, every pressed point) and ``c_s -> c_s + h k_s`` (shear, a sticking
point, within the share that keeps the cone). That is backward Euler on the springs, linearised
about the step's lever arms: stable at any step on the linear joint, where the explicit springs
(symplectic Euler, ``springs = "explicit"``) are stable for ``h omega < 2`` on the stiffest undamped
mode only. Its price is the scheme's own damping of the joint modes, ``h k`` against the dashpot c
(on the paper's bed ``c / k`` = 1.9 ms against a step of 0.2-0.5 ms: the dashpots there are critical
or more already), and a point is now clipped when its spring would pull at the step's end
(``f_el + c_n d' < 0`` with the spring's share in c_n).

The step: :func:`pipeline.dynamics.compliant.linear_system.stiffest_frequency` finds the explicit
springs' limit ``2 / omega_max`` (the generalised eigenvalue of the joints' springs, every point
pressed, against the bodies' masses), and the default step is ``step_safety`` times it
(``pipeline.compliant``): 1 with the springs at the step's end (chosen for accuracy: the fragility
against the explicit scheme, studies/colonnade/springs.toml), below 1 (0.5) with them at its start.

Energy is booked with the discrete scheme: work of the field ``-m a_g . v_{n+1} h``, damping
``h V^T C V`` at the new velocities (plus the elastic energy a clipped point releases without
work; the springs' share ``h k`` of C with it: backward Euler takes ``h^2 k d'^2`` a step out of a
vibration on average, the share's power), friction as the spring energy lost in each return to
the cone and in the relaxation of unloaded springs. What remains of the budget is the scheme's error (first order in h; the
summary states it).

Kernel layer: dimensionless floats and arrays as in :mod:`pipeline.dynamics.compliant.layout`.
"""

import math

import numpy as np
from numba import njit

from pipeline.dynamics.compliant import assembly as sk
from pipeline.dynamics.compliant import joint as jl
from pipeline.dynamics.compliant import linear_system as ls
from pipeline.dynamics.compliant import statistics as st
from pipeline.dynamics.compliant.layout import (
    A_DAMPING, A_FRICTION, A_WORK, B_HOLD, B_IX, B_IY, B_IZ, B_MASS, GROUND, JW_O, J_AREA, J_BAND, J_CN, J_DELTA,
    J_FA, J_FB, J_IMPLICIT, J_KN, J_KS, J_LOWER, J_MU, J_SHAPE, J_TAU, J_UPPER, M_AREA, M_COP_BX, M_COP_BY, M_COP_X,
    M_COP_Y, M_ELASTIC, M_NORMAL, M_NORMAL_EL, M_TX, M_TY, NB, N_ACC, P_AREA, P_U, P_V, P_X, P_Y, P_Z, QW, QX, QY, QZ,
    SHAPE_DISC, STATUS_COLLAPSED, S_END_TIME, S_NFEV, S_OVERTURN_BODY, S_OVERTURN_TIME, S_STATUS, S_STEPS, VX, VY,
    VZ, W_F, W_OM, W_T, WX, WY, WZ, X, Y, Z,
)
from pipeline.dynamics.compliant.unsigned import ix
from pipeline.dynamics.excitation import ground_acceleration

# Solves of one step's active set of clipped points at most (one when no point changes).
MAX_PASSES = 4

# Per-point scratch columns (one row per contact point).
# Q_PX, Q_PY: the pull of a patch running off an edge (part of Q_FX, Q_FY); Q_S: the overlap s.
# The rows are kept for the points in contact only (the others' are stale): every pass after
# :func:`_point_forces` goes through its list of the points in contact (scratch ``contacts``).
(Q_RX, Q_RY, Q_RZ, Q_FEL, Q_CN, Q_CT, Q_FX, Q_FY, Q_ACTIVE, Q_VTX, Q_VTY,
 Q_DDOT, Q_PX, Q_PY, Q_S) = range(15)
N_Q = 15

# [length^2] An unloaded spring whose squared state falls below this is spent: set to zero, its
# energy booked as friction at once. Its state is then 1e-40 of the length unit, some 1e-34 of
# an elastic shear displacement, so nothing it adds to survives rounding; without the floor a
# spring relaxes (a factor of about 0.9 a step) for thousands of steps, through products too
# small for normal floats, the slowest arithmetic a processor has (issue 37, speed).
SPENT = 1e-80


# The helpers below index the kernel's 2D tables by row (``jwork[j, k]``) rather than taking row
# views (``jwork[j]``): a view is an array with a reference count, taken and dropped by two calls
# into numba's runtime each time, and on a row of 6 those calls were a sixth of the step.
# For the same reason the helpers called once a joint or a body with tables as arguments are
# inlined (``inline="always"``, here and in the linear system and assembly modules): an array
# passed to a call is counted in and out of it; inlined, the frame of 2 runs 6 % faster, to the bit.

@njit(cache=True, inline="always")
def _joint_frame(y, j, joints, work, jwork, frames):
    """Joint j's upper body seen from its face.

    ``frames[j]``: ``P = F^T R_u`` (9, row-major) and ``q`` (3), the upper centre in the face's
    frame (origin at its centre), so a point p of the upper body (body axes) lies at
    ``xi = P p + q`` with lever arm ``r = P p`` from the upper centre (both in the face's
    frame); F is the face's axes in the ground frame (:func:`pipeline.dynamics.compliant.assembly.face_frame`).
    """
    u = int(joints[j, J_UPPER])
    o = NB * u
    for r in range(3):
        for c in range(3):
            frames[j, 3 * r + c] = (jwork[j, r] * work[u, c] + jwork[j, 3 + r] * work[u, 3 + c]
                                    + jwork[j, 6 + r] * work[u, 6 + c])
    dx = y[o + X] - jwork[j, JW_O]
    dy = y[o + Y] - jwork[j, JW_O + 1]
    dz = y[o + Z] - jwork[j, JW_O + 2]
    frames[j, 9] = jwork[j, 0] * dx + jwork[j, 3] * dy + jwork[j, 6] * dz
    frames[j, 10] = jwork[j, 1] * dx + jwork[j, 4] * dy + jwork[j, 7] * dz
    frames[j, 11] = jwork[j, 2] * dx + jwork[j, 5] * dy + jwork[j, 8] * dz


@njit(cache=True, inline="always")
def _relative_motion(jwork, j, vx, vy, vz, wx, wy, wz, lvx, lvy, lvz, lwx, lwy, lwz, motion):
    """(a', b') of :func:`_joint_motion_of_state` from the two bodies' velocities (ground frame)
    and the centres' offset ``motion[j, 6:9]``, turned into the frame of joint j's face."""
    ex, ey, ez = motion[j, 6], motion[j, 7], motion[j, 8]
    ax = vx - lvx - (lwy * ez - lwz * ey)
    ay = vy - lvy - (lwz * ex - lwx * ez)
    az = vz - lvz - (lwx * ey - lwy * ex)
    bx, by, bz = wx - lwx, wy - lwy, wz - lwz
    motion[j, 0] = jwork[j, 0] * ax + jwork[j, 3] * ay + jwork[j, 6] * az
    motion[j, 1] = jwork[j, 1] * ax + jwork[j, 4] * ay + jwork[j, 7] * az
    motion[j, 2] = jwork[j, 2] * ax + jwork[j, 5] * ay + jwork[j, 8] * az
    motion[j, 3] = jwork[j, 0] * bx + jwork[j, 3] * by + jwork[j, 6] * bz
    motion[j, 4] = jwork[j, 1] * bx + jwork[j, 4] * by + jwork[j, 7] * bz
    motion[j, 5] = jwork[j, 2] * bx + jwork[j, 5] * by + jwork[j, 8] * bz


@njit(cache=True, inline="always")
def _joint_motion_of_state(y, j, joints, work, jwork, motion):
    """Relative motion (a', b') of joint j in its face's frame, ``g' = a' + b' x r``, into ``motion[j]``.

    ``a'`` is the velocity of the upper centre relative to the lower body's material point
    there, ``b'`` the relative angular velocity, both in the face's frame, at the velocities of
    the state y (and the angular velocities of the scratch). ``motion[j, 6:9]`` keeps the
    centres' offset for :func:`_joint_motion_of_bodies`.
    """
    u, lower = int(joints[j, J_UPPER]), int(joints[j, J_LOWER])
    o = NB * u
    vx, vy, vz = y[o + VX], y[o + VY], y[o + VZ]
    wx, wy, wz = work[u, W_OM], work[u, W_OM + 1], work[u, W_OM + 2]
    if lower == GROUND:
        motion[j, 6], motion[j, 7], motion[j, 8] = 0.0, 0.0, 0.0
        _relative_motion(jwork, j, vx, vy, vz, wx, wy, wz, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, motion)
        return
    lo = NB * lower
    motion[j, 6] = y[o + X] - y[lo + X]
    motion[j, 7] = y[o + Y] - y[lo + Y]
    motion[j, 8] = y[o + Z] - y[lo + Z]
    _relative_motion(jwork, j, vx, vy, vz, wx, wy, wz, y[lo + VX], y[lo + VY], y[lo + VZ],
                     work[lower, W_OM], work[lower, W_OM + 1], work[lower, W_OM + 2], motion)


@njit(cache=True, inline="always")
def _joint_motion_of_bodies(vel, j, joints, jwork, motion):
    """(a', b') of joint j at the solved body velocities (rows of ``vel``, ground frame)."""
    u, lower = int(joints[j, J_UPPER]), int(joints[j, J_LOWER])
    if lower == GROUND:
        _relative_motion(jwork, j, vel[u, 0], vel[u, 1], vel[u, 2], vel[u, 3], vel[u, 4], vel[u, 5],
                         0.0, 0.0, 0.0, 0.0, 0.0, 0.0, motion)
        return
    _relative_motion(jwork, j, vel[u, 0], vel[u, 1], vel[u, 2], vel[u, 3], vel[u, 4], vel[u, 5],
                     vel[lower, 0], vel[lower, 1], vel[lower, 2], vel[lower, 3], vel[lower, 4], vel[lower, 5], motion)


@njit(cache=True)
def _point_forces(y, h, params, pts, pcols, frames, motion, fric_slip, mats, contacts, n_contact, kept):
    """Geometry and explicit forces of every point at the step's start (step 1 of the module).

    Fills the point scratch ``pts`` (one row per quantity: lever arm r and forces in the frame of
    the joint's face, elastic normal force, dashpot coefficients, active flag; not the relative
    velocity, which the law reads at the step's start and :func:`_update_active_set` stores at the
    new velocities after every solve), the list of the points in contact
    (``contacts[start:start + n_contact[j]]`` for joint j's points from ``start``, in their order),
    the joint frames and motions, and returns the friction the returns to the cone dissipate;
    ``fric_slip[j]`` gets the joint's area-weighted plastic slip of this step. Shear states are
    returned onto the cone in y. Then the joints' sums (kept in ``kept`` for a later solve), loads
    and dashpot matrices with the active set at the step's start (as :func:`_joint_loads`).

    One pass over a joint's points: the penetration of each, and for those in contact their lever
    arm, velocity and law; then the joint's sums over its points in contact (:func:`_joint_sums`),
    in a loop of their own: their 22 running sums in the point loop kept its other numbers on the
    stack (issue 48: the front's point pass 6 % cheaper so). Split further (the geometry of every
    point, then the law) the step of a 10-drum stack cost 30 % more: the passes did not vectorise,
    and they worked on the many points of a rocking column that are out of contact. Made to run in
    SIMD lanes (each joint's rows as slices indexed from 0, the law's branches as selects, in
    loops of few enough arrays for LLVM's run-time overlap checks) it cost more still: on a row
    of 6 mid-record the pass took 134 us against 77 us, the geometry alone of 44 joints of 48
    points 15.5 us in lanes against 6.8 us scalar (slices and overlap checks cost more than the
    lanes save on so few points; docs/model.md, "Where a step's time goes").
    """
    bodies, joint_start, joints, work, jwork = params[0], params[2], params[3], params[6], params[8]
    n_bodies = bodies.shape[0]
    _clear_loads(params)
    sh = NB * n_bodies
    friction = 0.0
    PX, PY, PZ, AREA = pcols[P_X], pcols[P_Y], pcols[P_Z], pcols[P_AREA]
    RX, RY, RZ = pts[Q_RX], pts[Q_RY], pts[Q_RZ]
    FEL, CN, CT, FX, FY = pts[Q_FEL], pts[Q_CN], pts[Q_CT], pts[Q_FX], pts[Q_FY]
    PULLX, PULLY, S, ACTIVE = pts[Q_PX], pts[Q_PY], pts[Q_S], pts[Q_ACTIVE]
    for j in range(joints.shape[0]):
        kn, ks, mu, cn, tau = joints[j, J_KN], joints[j, J_KS], joints[j, J_MU], joints[j, J_CN], joints[j, J_TAU]
        delta = joints[j, J_DELTA]
        # [time] the springs at the step's end: k (d + h d') = k d + (h k) d', a dashpot h k in the solve
        lag = h * joints[j, J_IMPLICIT]
        disc = joints[j, J_SHAPE] == SHAPE_DISC
        # within it a point is over the face (s = 1): the disc's radius squared, the rectangle's half sides
        edge_a = joints[j, J_FA] * (1.0 + jl.EDGE_TOL)
        edge_b = joints[j, J_FB] * (1.0 + jl.EDGE_TOL)
        edge2 = edge_a * edge_a
        decay = math.exp(-h / tau)
        shear_dashpot = ks / kn * cn  # [per area] the normal dashpot's ratio to the stiffness
        _joint_frame(y, j, joints, work, jwork, frames)
        _joint_motion_of_state(y, j, joints, work, jwork, motion)
        start, stop = joint_start[j], joint_start[j + 1]
        # the frame and motion in locals: the stores into pts below would make the compiler read
        # them again from memory at every point
        p00, p01, p02 = frames[j, 0], frames[j, 1], frames[j, 2]
        p10, p11, p12 = frames[j, 3], frames[j, 4], frames[j, 5]
        p20, p21, p22 = frames[j, 6], frames[j, 7], frames[j, 8]
        qx, qy, qz = frames[j, 9], frames[j, 10], frames[j, 11]
        vx_rel, vy_rel, vz_rel = motion[j, 0], motion[j, 1], motion[j, 2]
        wx_rel, wy_rel, wz_rel = motion[j, 3], motion[j, 4], motion[j, 5]
        slip = 0.0
        n_in = 0
        for point in range(start, stop):
            p = ix(point)
            iu = ix(sh + 2 * point)
            iv = iu + ix(1)
            # the lever arm r = P p (face frame) and the penetration; the rest only in contact
            px, py, pz = PX[p], PY[p], PZ[p]
            rz = p20 * px + p21 * py + p22 * pz
            d = -(rz + qz)
            s, sx, sy = 1.0, 0.0, 0.0
            if d > 0.0:
                rx = p00 * px + p01 * py + p02 * pz
                ry = p10 * px + p11 * py + p12 * pz
                RX[p], RY[p], RZ[p] = rx, ry, rz
                xi_x, xi_y = rx + qx, ry + qy
                if (xi_x * xi_x + xi_y * xi_y > edge2) if disc else (abs(xi_x) > edge_a or abs(xi_y) > edge_b):
                    s, sx, sy = sk.face_overlap(xi_x, xi_y, joints[j, J_SHAPE], joints[j, J_FA], joints[j, J_FB],
                                                   joints[j, J_BAND])
            if d <= 0.0 or s <= 0.0:
                ux, uy = y[iu], y[iv]
                uu = ux * ux + uy * uy
                if uu >= SPENT:  # an unloaded spring relaxes; its energy goes as friction
                    friction += 0.5 * ks * AREA[p] * uu * (1.0 - decay * decay)
                    y[iu] = ux * decay
                    y[iv] = uy * decay
                elif uu > 0.0:  # spent (see SPENT): what is left of its energy goes at once
                    friction += 0.5 * ks * AREA[p] * uu
                    y[iu] = y[iv] = 0.0
                continue
            vtx = vx_rel + wy_rel * rz - wz_rel * ry
            vty = vy_rel + wz_rel * rx - wx_rel * rz
            d_dot = -(vz_rel + wx_rel * ry - wy_rel * rx)
            area = AREA[p]
            f_el = area * s * kn * d
            engage = min(1.0, d / delta)
            # the dashpot first, as it was before the springs' share: with lag 0 the sum adds an exact 0 and
            # the explicit scheme's runs stay the same to the bit
            c_n = area * s * cn * engage + area * s * lag * kn
            k_area = ks * area
            cap = mu * f_el
            ux, uy = y[iu], y[iv]
            uu = ux * ux + uy * uy
            c_t = 0.0
            if k_area * k_area * uu > cap * cap:  # on the cone: return the state to it, Coulomb's force
                ur = math.sqrt(uu)
                scale = cap / (k_area * ur)
                # Coulomb's mu f_el times the plastic slip: what the step's slip took from the
                # bodies (the spring's overshoot past the cone, 1/2 k_s A slip^2, never came
                # from them: the drift put it there)
                friction += cap * ur * (1.0 - scale)
                slip += area * ur * (1.0 - scale)
                ux *= scale
                uy *= scale
                y[iu] = ux
                y[iv] = uy
            else:  # sticking: the shear dashpot, with the share that keeps it within the cone
                c_full = shear_dashpot * area * s * engage + lag * k_area
                c_t = c_full * jl._viscous_share(k_area * ux, k_area * uy, c_full * vtx, c_full * vty, cap)
            pull_x = pull_y = 0.0
            if sx != 0.0 or sy != 0.0:  # the pull of a patch running off the edge of the face
                pull = -0.5 * kn * area * d * d
                pull_x, pull_y = pull * sx, pull * sy
            PULLX[p], PULLY[p], S[p] = pull_x, pull_y, s
            fx = -k_area * ux + pull_x
            fy = -k_area * uy + pull_y
            FEL[p] = f_el
            CN[p] = c_n
            CT[p] = c_t
            FX[p] = fx
            FY[p] = fy
            contacts[ix(start + n_in)] = point
            n_in += 1
            # the clipped joint: active if the normal force at the current velocities pushes
            active = f_el + c_n * d_dot >= 0.0
            ACTIVE[p] = 1.0 if active else 0.0
        n_contact[j] = n_in
        sums = _joint_sums(pts, contacts, start, start + n_in)
        _keep_sums(kept, j, sums)
        _close_joint(y, j, joints, work, jwork, sums, mats, True)
        fric_slip[j] = slip / joints[j, J_AREA]
    return friction


# A joint's sums as one tuple: the ten alpha moments of :func:`ls._weighted_moments`, the six beta
# moments :func:`ls.joint_matrix_z` reads (beta, beta rx, beta ry, beta rx^2, beta ry^2, beta rx ry),
# then the force and torque in the frame of its face.
N_SUMS = 22


@njit(cache=True, inline="always")
def _add_point(sums, rx, ry, rz, f_n, fx, fy, alpha, beta):
    """``sums`` (:data:`N_SUMS`, a tuple) with one point in contact added: lever arm r, normal force
    f_n (0 if clipped), shear force (fx, fy), shear dashpot alpha and beta = normal dashpot - alpha.
    Inlined: the caller's accumulators stay in registers."""
    (a0, a1, a2, a3, a4, a5, a6, a7, a8, a9, b0, b1, b2, b3, b4, b5, sfx, sfy, sfz, stx, sty, stz) = sums
    # alpha = 0 (a slipping point) adds zeros, which leave the sums as they are (a sum that starts at +0
    # is never -0): no branch to mispredict between the sticking and slipping points of a joint
    a0 += alpha
    a1 += alpha * rx
    a2 += alpha * ry
    a3 += alpha * rz
    a4 += alpha * rx * rx
    a5 += alpha * ry * ry
    a6 += alpha * rz * rz
    a7 += alpha * rx * ry
    a8 += alpha * rx * rz
    a9 += alpha * ry * rz
    b0 += beta
    b1 += beta * rx
    b2 += beta * ry
    b3 += beta * rx * rx
    b4 += beta * ry * ry
    b5 += beta * rx * ry
    sfx += fx
    sfy += fy
    sfz += f_n
    stx += ry * f_n - rz * fy
    sty += rz * fx - rx * f_n
    stz += rx * fy - ry * fx
    return (a0, a1, a2, a3, a4, a5, a6, a7, a8, a9, b0, b1, b2, b3, b4, b5, sfx, sfy, sfz, stx, sty, stz)


ZERO_SUMS = (0.0,) * N_SUMS


@njit(cache=True, inline="always")
def _joint_sums(pts, contacts, start, stop):
    """The sums (:data:`N_SUMS`) of a joint's points in contact, ``contacts[start:stop]``: their dashpot
    moments and explicit forces and torques, in the points' order (point pairs next to each other, so
    that at rest a symmetric joint's moments cancel exactly). Inlined, called once a joint: the table is
    indexed by row and point, not taken as row views (each a reference count taken and dropped)."""
    sums = ZERO_SUMS
    for k in range(start, stop):
        p = ix(contacts[k])
        active = pts[Q_ACTIVE, p] > 0.0
        ct = pts[Q_CT, p]
        sums = _add_point(sums, pts[Q_RX, p], pts[Q_RY, p], pts[Q_RZ, p], pts[Q_FEL, p] if active else 0.0,
                          pts[Q_FX, p], pts[Q_FY, p], ct, (pts[Q_CN, p] if active else 0.0) - ct)
    return sums


@njit(cache=True, inline="always")
def _close_joint(y, j, joints, work, jwork, sums, mats, matrix):
    """Joint j's dashpot matrix (``mats[j]``, ground frame; if ``matrix``, else it stands) and its force
    on both bodies (scratch W_F, W_T) from its running ``sums`` (:func:`_joint_sums`, frame of its face)."""
    (a0, a1, a2, a3, a4, a5, a6, a7, a8, a9, b0, b1, b2, b3, b4, b5,
     sfx, sfy, sfz, stx, sty, stz) = sums
    if matrix:
        ls.turned_joint_matrix_z(a0, a1, a2, a3, a4, a5, a6, a7, a8, a9, b0, b1, b2, b3, b4, b5, jwork, j, mats)
    f0, f1, f2, f3, f4, f5 = jwork[j, 0], jwork[j, 1], jwork[j, 2], jwork[j, 3], jwork[j, 4], jwork[j, 5]
    f6, f7, f8 = jwork[j, 6], jwork[j, 7], jwork[j, 8]
    Fx = f0 * sfx + f1 * sfy + f2 * sfz
    Fy = f3 * sfx + f4 * sfy + f5 * sfz
    Fz = f6 * sfx + f7 * sfy + f8 * sfz
    Tx = f0 * stx + f1 * sty + f2 * stz
    Ty = f3 * stx + f4 * sty + f5 * stz
    Tz = f6 * stx + f7 * sty + f8 * stz
    u, lower = int(joints[j, J_UPPER]), int(joints[j, J_LOWER])
    # the centres' offset read whatever the lower body (body 0 stands in for the ground, its offset
    # unused): a table whose last use lies in a branch keeps its reference count taken and dropped
    # (atomic calls into numba's runtime) at every joint
    up, lo = NB * u, NB * max(lower, 0)
    ex = y[up + X] - y[lo + X]
    ey = y[up + Y] - y[lo + Y]
    ez = y[up + Z] - y[lo + Z]
    if lower != GROUND:
        # the reaction on the lower body, its moment about the lower centre
        work[lower, W_F] -= Fx
        work[lower, W_F + 1] -= Fy
        work[lower, W_F + 2] -= Fz
        work[lower, W_T] -= Tx + (ey * Fz - ez * Fy)
        work[lower, W_T + 1] -= Ty + (ez * Fx - ex * Fz)
        work[lower, W_T + 2] -= Tz + (ex * Fy - ey * Fx)
    work[u, W_F] += Fx
    work[u, W_F + 1] += Fy
    work[u, W_F + 2] += Fz
    work[u, W_T] += Tx
    work[u, W_T + 1] += Ty
    work[u, W_T + 2] += Tz


@njit(cache=True)
def _clear_loads(params):
    """Zero the bodies' joint forces (scratch W_F, W_T)."""
    work = params[6]
    for b in range(work.shape[0]):
        for k in range(6):
            work[b, W_F + k] = 0.0


@njit(cache=True)
def _joint_loads(y, params, pts, mats, contacts, n_contact, kept, changed):
    """Explicit joint forces on the bodies (scratch W_F, W_T) and each joint's dashpot matrix,
    from the points' scratch as it stands (:func:`_point_forces` does the same in its point pass).

    Summed per joint in the frame of its face, point pairs next to each other, so that at rest
    the moments of a symmetric joint cancel exactly. A joint none of whose points changed its
    clipping (``changed[j]`` 0, :func:`_update_active_set`) has the sums it had (``kept``, the same
    numbers: the same points' same values in the same order) and its matrix: only the points of
    the joints that changed are summed again (issue 48, speed).
    """
    joint_start, joints, work, jwork = params[2], params[3], params[6], params[8]
    _clear_loads(params)
    for j in range(joints.shape[0]):
        if changed[j] > 0:
            start = joint_start[j]
            sums = _joint_sums(pts, contacts, start, start + n_contact[j])
            _keep_sums(kept, j, sums)
            _close_joint(y, j, joints, work, jwork, sums, mats, True)
        else:
            _close_joint(y, j, joints, work, jwork, _kept_sums(kept, j), mats, False)


@njit(cache=True, inline="always")
def _keep_sums(kept, j, sums):
    """Joint j's sums (:data:`N_SUMS`) into row j of ``kept``."""
    for k in range(N_SUMS):
        kept[j, k] = sums[k]


@njit(cache=True, inline="always")
def _kept_sums(kept, j):
    """The sums :func:`_keep_sums` kept for joint j, as the tuple :func:`_joint_sums` returns."""
    r = kept
    return (r[j, 0], r[j, 1], r[j, 2], r[j, 3], r[j, 4], r[j, 5], r[j, 6], r[j, 7], r[j, 8], r[j, 9], r[j, 10],
            r[j, 11], r[j, 12], r[j, 13], r[j, 14], r[j, 15], r[j, 16], r[j, 17], r[j, 18], r[j, 19], r[j, 20],
            r[j, 21])


@njit(cache=True)
def set_static_loads(y, h, params, s):
    """Each body's holding load set to the joints' net force and torque on it in the rest state y,
    as this integrator sums them: at rest its velocity update is then exactly zero."""
    bodies, work = params[0], params[6]
    pts, mats, frames, motion, slip, pcols, contacts, n_contact = s[0], s[1], s[10], s[11], s[8], s[12], s[13], s[14]
    kept = s[15]
    sk._kinematics(y, params)
    _point_forces(y, h, params, pts, pcols, frames, motion, slip, mats, contacts, n_contact, kept)
    for b in range(bodies.shape[0]):
        for k in range(6):
            bodies[b, B_HOLD + k] = work[b, W_F + k]


@njit(cache=True)
def _momentum(y, bodies, work, h, ax, ay, az, rhs):
    """``M V_n + h (F - gyroscopic)`` per body, ground frame (after :func:`_joint_loads`)."""
    for b in range(bodies.shape[0]):
        o = NB * b
        m = bodies[b, B_MASS]
        # the joints' sum first, then the holding load: at rest this is exactly zero (as in assembly.rhs)
        fx = (work[b, W_F] - bodies[b, B_HOLD]) - m * ax
        fy = (work[b, W_F + 1] - bodies[b, B_HOLD + 1]) - m * ay
        fz = (work[b, W_F + 2] - bodies[b, B_HOLD + 2]) - m * az
        rhs[b, 0] = m * y[o + VX] + h * fx
        rhs[b, 1] = m * y[o + VY] + h * fy
        rhs[b, 2] = m * y[o + VZ] + h * fz
        # I_g w = R diag(I) R^T w, from the body-frame angular velocity; gyroscopic w x I_g w
        wx, wy, wz = work[b, W_OM], work[b, W_OM + 1], work[b, W_OM + 2]
        bx, by, bz = y[o + WX], y[o + WY], y[o + WZ]
        cx, cy, cz = bodies[b, B_IX] * bx, bodies[b, B_IY] * by, bodies[b, B_IZ] * bz
        lx = work[b, 0] * cx + work[b, 1] * cy + work[b, 2] * cz
        ly = work[b, 3] * cx + work[b, 4] * cy + work[b, 5] * cz
        lz = work[b, 6] * cx + work[b, 7] * cy + work[b, 8] * cz
        rhs[b, 3] = lx + h * ((work[b, W_T] - bodies[b, B_HOLD + 3]) - (wy * lz - wz * ly))
        rhs[b, 4] = ly + h * ((work[b, W_T + 1] - bodies[b, B_HOLD + 4]) - (wz * lx - wx * lz))
        rhs[b, 5] = lz + h * ((work[b, W_T + 2] - bodies[b, B_HOLD + 5]) - (wx * ly - wy * lx))


@njit(cache=True)
def _update_active_set(params, pts, vel, motion, contacts, n_contact, joint_changed):
    """Relative velocities of the points in contact at the new body velocities (stored in ``pts``),
    and the clipped joint: points whose normal force would pull are clipped, those that push
    are not. Returns the number of points that changed (``joint_changed[j]``: joint j's). Points out
    of contact are not on the lists (they stay clipped: their elastic force and dashpot are zero).
    """
    joint_start, joints, jwork = params[2], params[3], params[8]
    RX, RY, RZ = pts[Q_RX], pts[Q_RY], pts[Q_RZ]
    VTX, VTY, DDOT = pts[Q_VTX], pts[Q_VTY], pts[Q_DDOT]
    FEL, CN, ACTIVE = pts[Q_FEL], pts[Q_CN], pts[Q_ACTIVE]
    changed = 0
    for j in range(joints.shape[0]):
        _joint_motion_of_bodies(vel, j, joints, jwork, motion)
        vx_rel, vy_rel, vz_rel = motion[j, 0], motion[j, 1], motion[j, 2]  # (as above)
        wx_rel, wy_rel, wz_rel = motion[j, 3], motion[j, 4], motion[j, 5]
        start = joint_start[j]
        before = changed
        for k in range(start, start + n_contact[j]):
            p = ix(contacts[k])
            rx, ry, rz = RX[p], RY[p], RZ[p]
            d_dot = -(vz_rel + wx_rel * ry - wy_rel * rx)
            VTX[p] = vx_rel + wy_rel * rz - wz_rel * ry
            VTY[p] = vy_rel + wz_rel * rx - wx_rel * rz
            DDOT[p] = d_dot
            push = 1.0 if FEL[p] + CN[p] * d_dot >= 0.0 else 0.0
            if push != ACTIVE[p]:
                ACTIVE[p] = push
                changed += 1
        joint_changed[j] = changed - before
    return changed


@njit(cache=True)
def _implicit_excess(bodies, work, vel, impulse):
    """What the implicit dashpots take beyond their power at the new velocities.

    With ``M v* = M v_n + h F`` (the explicit update) and ``(M + h C) v = M v*``, the dashpot
    stage takes ``1/2 v*^T M v* - 1/2 v^T M v = h v^T C v + 1/2 P^T M^-1 P`` out of the
    kinetic energy, P = h C v the dashpots' impulse (``impulse`` holds M v* on entry). The
    second term is backward Euler's own dissipation, as real in the discrete model as the
    first: booked as damping, so that the budget closes on the scheme's other errors.
    """
    excess = 0.0
    for b in range(bodies.shape[0]):
        m = bodies[b, B_MASS]
        px = impulse[b, 0] - m * vel[b, 0]
        py = impulse[b, 1] - m * vel[b, 1]
        pz = impulse[b, 2] - m * vel[b, 2]
        excess += 0.5 * (px * px + py * py + pz * pz) / m
        # the angular impulse in body axes, R^T (impulse - I_g w), with I_g w = R diag(I) R^T w
        wx, wy, wz = vel[b, 3], vel[b, 4], vel[b, 5]
        bx = work[b, 0] * wx + work[b, 3] * wy + work[b, 6] * wz
        by = work[b, 1] * wx + work[b, 4] * wy + work[b, 7] * wz
        bz = work[b, 2] * wx + work[b, 5] * wy + work[b, 8] * wz
        ix, iy, iz = bodies[b, B_IX], bodies[b, B_IY], bodies[b, B_IZ]
        qx = (work[b, 0] * impulse[b, 3] + work[b, 3] * impulse[b, 4] + work[b, 6] * impulse[b, 5]) - ix * bx
        qy = (work[b, 1] * impulse[b, 3] + work[b, 4] * impulse[b, 4] + work[b, 7] * impulse[b, 5]) - iy * by
        qz = (work[b, 2] * impulse[b, 3] + work[b, 5] * impulse[b, 4] + work[b, 8] * impulse[b, 5]) - iz * bz
        excess += 0.5 * (qx * qx / ix + qy * qy / iy + qz * qz / iz)
    return excess


@njit(cache=True)
def step(t, y, h, params, s):
    """Advance the state y (in place) from t by one step h; returns the number of solves.

    ``s`` is the scratch tuple of :func:`make_scratch`. The per-joint monitor of ``params`` is
    filled from the step's forces, as :func:`pipeline.dynamics.compliant.assembly.update_statistics` reads
    it: the normal force as the step applied it at the new velocities (elastic and dashpot of
    a pressed point, none of a clipped one) and its elastic part; the tangential resultant of
    each point's shear spring and, sticking, its dashpot at the new velocities, held within
    the point's cone ``mu f_el`` (the implicit dashpot's share is taken at the step's start,
    so in the step in which a point starts to slip its force at the new velocities can pass
    the cone, until the next step's return; the joint law never lets it, and the monitor does
    not either: the mobilised friction never exceeds mu; the pull of a patch running off an
    edge is not friction and is left out, as in the adaptive model's monitor); centres of
    pressure and the area in contact. The elastic energy is left NaN: not a quantity of the
    step (history rows and the energy budget evaluate the joint law).
    """
    bodies, points, joint_start, joints, record, dt, work, mon = params[:8]
    pts, mats, diag, blocks, tmp66, tmp6, pattern, vel, slip, impulse, frames, motion, pcols, contacts, n_contact, \
        kept, changed = s
    n_bodies = bodies.shape[0]
    ax, ay, az = ground_acceleration(t, record, dt)
    sk._kinematics(y, params)
    friction = _point_forces(y, h, params, pts, pcols, frames, motion, slip, mats, contacts, n_contact, kept)
    solves = 0
    while True:
        if solves > 0:  # the active set changed: the loads again
            _joint_loads(y, params, pts, mats, contacts, n_contact, kept, changed)
        ls.assemble_system(y, bodies, joints, mats, h, work, pattern, diag, blocks, tmp66)
        _momentum(y, bodies, work, h, ax, ay, az, vel)
        impulse[:, :] = vel
        ls.sparse_block_solve(pattern, diag, blocks, vel, tmp6)
        solves += 1
        if _update_active_set(params, pts, vel, motion, contacts, n_contact, changed) == 0 or solves >= MAX_PASSES:
            break
    # bookings at the new velocities, the monitor, then the shear states
    sh = NB * n_bodies
    damping = 0.0
    U, V, AREA = pcols[P_U], pcols[P_V], pcols[P_AREA]
    RX, RY, VTX, VTY, DDOT = pts[Q_RX], pts[Q_RY], pts[Q_VTX], pts[Q_VTY], pts[Q_DDOT]
    FEL, CN, CT, FX, FY = pts[Q_FEL], pts[Q_CN], pts[Q_CT], pts[Q_FX], pts[Q_FY]
    PULLX, PULLY, S, ACTIVE = pts[Q_PX], pts[Q_PY], pts[Q_S], pts[Q_ACTIVE]
    for j in range(joints.shape[0]):
        mu = joints[j, J_MU]
        normal = normal_el = tx = ty = bx = by = cx = cy = area = 0.0
        start = joint_start[j]
        for k in range(start, start + n_contact[j]):
            p = ix(contacts[k])
            vtx, vty, d_dot = VTX[p], VTY[p], DDOT[p]
            f_el, ct = FEL[p], CT[p]
            f_n = 0.0
            # the springs' share of the dashpots (h k, springs at the step's end) is booked with them: it is
            # backward Euler's dissipation, h^2 k d'^2 a step on average over a vibration (module doc)
            if ACTIVE[p] > 0.0:
                damping += h * CN[p] * d_dot * d_dot
                f_n = f_el + CN[p] * d_dot
            else:  # clipped: the spring's energy goes without work as the point separates
                damping -= h * f_el * d_dot
            damping += h * ct * (vtx * vtx + vty * vty)
            iu = ix(sh + 2 * contacts[k])
            y[iu] += h * vtx
            y[iu + ix(1)] += h * vty
            # the monitor: shear spring and dashpot held within the point's cone (see above)
            sx = FX[p] - PULLX[p] - ct * vtx
            sy = FY[p] - PULLY[p] - ct * vty
            cap = mu * f_el
            st2 = sx * sx + sy * sy
            if st2 > cap * cap:
                scale = cap / math.sqrt(st2)
                sx *= scale
                sy *= scale
            tx += sx
            ty += sy
            normal += f_n
            normal_el += f_el
            if f_n > 0.0:
                bx += f_n * U[p]
                by += f_n * V[p]
                cx += f_n * (RX[p] + frames[j, 9])
                cy += f_n * (RY[p] + frames[j, 10])
                area += AREA[p] * S[p]
        if normal > 0.0:
            bx, by, cx, cy = bx / normal, by / normal, cx / normal, cy / normal
        mon[j, M_NORMAL] = normal
        mon[j, M_NORMAL_EL] = normal_el
        mon[j, M_TX] = tx
        mon[j, M_TY] = ty
        mon[j, M_COP_BX] = bx
        mon[j, M_COP_BY] = by
        mon[j, M_COP_X] = cx
        mon[j, M_COP_Y] = cy
        mon[j, M_AREA] = area / joints[j, J_AREA]
        mon[j, M_ELASTIC] = math.nan
    damping += _implicit_excess(bodies, work, vel, impulse)
    power = 0.0
    for b in range(n_bodies):
        o = NB * b
        m = bodies[b, B_MASS]
        vx, vy, vz = vel[b, 0], vel[b, 1], vel[b, 2]
        power -= m * (ax * vx + ay * vy + az * vz)
        y[o + VX], y[o + VY], y[o + VZ] = vx, vy, vz
        y[o + X] += h * vx
        y[o + Y] += h * vy
        y[o + Z] += h * vz
        # body-frame angular velocity, and the exact rotation by it over h
        wx = work[b, 0] * vel[b, 3] + work[b, 3] * vel[b, 4] + work[b, 6] * vel[b, 5]
        wy = work[b, 1] * vel[b, 3] + work[b, 4] * vel[b, 4] + work[b, 7] * vel[b, 5]
        wz = work[b, 2] * vel[b, 3] + work[b, 5] * vel[b, 4] + work[b, 8] * vel[b, 5]
        y[o + WX], y[o + WY], y[o + WZ] = wx, wy, wz
        w = math.sqrt(wx * wx + wy * wy + wz * wz)
        if w > 0.0:
            half = 0.5 * w * h
            c = math.cos(half)
            sn = math.sin(half) / w
            px, py, pz = sn * wx, sn * wy, sn * wz
            qw, qx, qy, qz = y[o + QW], y[o + QX], y[o + QY], y[o + QZ]
            nw = qw * c - qx * px - qy * py - qz * pz
            nx = qw * px + qx * c + qy * pz - qz * py
            ny = qw * py - qx * pz + qy * c + qz * px
            nz = qw * pz + qx * py - qy * px + qz * c
            norm = 1.0 / math.sqrt(nw * nw + nx * nx + ny * ny + nz * nz)
            y[o + QW], y[o + QX], y[o + QY], y[o + QZ] = nw * norm, nx * norm, ny * norm, nz * norm
    acc = sh + 2 * points.shape[0]
    y[acc + A_WORK] += h * power
    y[acc + A_FRICTION] += friction
    y[acc + A_DAMPING] += damping
    for j in range(joints.shape[0]):
        y[acc + N_ACC + j] += slip[j]
    return solves


def make_scratch(params, pattern):
    """Scratch arrays of :func:`step` (one set per simulation), for an assembly's kernel parameters
    and the pattern of its solve (:func:`pipeline.dynamics.compliant.linear_system.elimination`)."""
    n_bodies, n_points, n_joints = params[0].shape[0], params[1].shape[0], params[3].shape[0]
    n_edges = pattern[2].shape[0]
    # points (one row per quantity); joint matrices; diagonal and coupling blocks of the solve;
    # scratch; the pattern; velocities; joints' plastic slips; momenta before the dashpots; joint
    # frames and motions; the point table, one row per column (the passes over points read it so);
    # the points in contact, listed joint by joint, and their count per joint; the joints' sums
    # (:func:`_keep_sums`) and the count of each joint's points whose clipping the last solve changed
    return (np.zeros((N_Q, n_points)), np.zeros((n_joints, 6, 6)), np.zeros((n_bodies, 6, 6)),
            np.zeros((n_edges, 6, 6)), np.zeros((6, 6)), np.zeros(6), pattern, np.zeros((n_bodies, 6)),
            np.zeros(n_joints), np.zeros((n_bodies, 6)), np.zeros((n_joints, 12)), np.zeros((n_joints, 9)),
            np.ascontiguousarray(params[1].T), np.zeros(n_points, dtype=np.int64), np.zeros(n_joints, dtype=np.int64),
            np.zeros((n_joints, N_SUMS)), np.zeros(n_joints, dtype=np.int64))


@njit(cache=True)
def _sample_rows(t_mon, k, stop, t_limit, t, h, y_prev, y, y_int, stride, params, theta_commit, hist_y, hist_diag,
                 hist_body, summary, body_stats, joint_stats, joint_committed, y0):
    """History rows of the samples from k on that lie at or before ``t_limit`` (and before
    ``stop``), the state interpolated linearly between ``y_prev`` (at t - h) and ``y`` (at t)
    (quaternions renormalised); returns the next sample to do. The joint law is evaluated at
    the interpolated state, as the adaptive integrators' rows do at theirs."""
    bodies = params[0]
    n_hist = hist_y.shape[0]
    while k < stop and t_mon[k] <= t_limit:
        if k % stride == 0 and k // stride < n_hist:
            f = (t_mon[k] - (t - h)) / h
            if f >= 1.0:  # the sample is the step's end: its state exactly
                y_int[:] = y
            else:
                for i in range(y.shape[0]):
                    y_int[i] = y_prev[i] + f * (y[i] - y_prev[i])
                for b in range(bodies.shape[0]):
                    o = NB * b
                    norm = 1.0 / math.sqrt(y_int[o + QW] ** 2 + y_int[o + QX] ** 2 + y_int[o + QY] ** 2
                                           + y_int[o + QZ] ** 2)
                    for q in range(QW, QZ + 1):
                        y_int[o + q] *= norm
            st._monitor(t_mon[k], y_int, params, theta_commit, summary, body_stats, joint_stats, joint_committed,
                        False)
            st._history_row(t_mon[k], y_int, params, k // stride, hist_y, hist_diag, hist_body, body_stats, y0)
        summary[S_END_TIME] = t_mon[k]
        k += 1
    return k


@njit(cache=True, nogil=True)
def run(params, y, t_mon, start, stop, h, stride, theta_commit, hist_y, hist_diag, hist_body,
        summary, body_stats, joint_stats, joint_committed, y0, between, scratch):
    """Integrate with fixed steps h until the samples ``start`` to ``stop`` (exclusive) are done.

    The steps do not follow the samples: ``y`` is the state after ``summary[S_STEPS]`` steps
    (at that many h; the initial state with ``start = 0``, when the statistics are initialised)
    and is advanced in place. The statistics are taken at every step; the history rows every
    ``stride`` samples, from the state interpolated between the two steps around the sample
    (``between``: scratch (2, len(y)), the state before the last step and the interpolated one),
    so that neither the output grid nor the pieces change the steps. The statistics, histories
    and summary are those of :func:`pipeline.dynamics.compliant.assembly.run` (same arrays, same meaning),
    so a long run can be done in pieces (progress, interruption) with the same result as in one.

    Compiled with LLVM's SLP vectoriser, and everything it calls with it
    (:func:`pipeline.dynamics.compliant.vector_lanes.compile_with_slp`, called before the first piece
    by :mod:`pipeline.compliant.integrate`): the same numbers, the block solve's lanes side by side.

    Returns
    -------
    int
        The next sample to do: ``stop``, or ``len(t_mon)`` once the structure is down.
    """
    bodies = params[0]
    n_bodies = bodies.shape[0]
    m = t_mon.shape[0]
    n_hist = hist_y.shape[0]
    y_prev, y_int = between[0], between[1]
    if start == 0:
        st.start_statistics(t_mon[0], y, params, theta_commit, hist_y, hist_diag, hist_body, summary, body_stats,
                            joint_stats, joint_committed)
        start = 1
    g_old = np.empty(2 * n_bodies)
    g_new = np.empty(2 * n_bodies)
    sk.event_values(y, bodies, params[3], g_old)
    k = start
    while k < stop:
        t = summary[S_STEPS] * h  # the time of y (a count of steps: no drift)
        if t >= t_mon[k]:  # the last step passed sample k: its rows, interpolated
            k = _sample_rows(t_mon, k, stop, t, t, h, y_prev, y, y_int, stride, params, theta_commit, hist_y,
                             hist_diag, hist_body, summary, body_stats, joint_stats, joint_committed, y0)
            continue
        if t + h >= t_mon[k]:  # this step reaches sample k: keep the state before it
            y_prev[:] = y
        summary[S_NFEV] += step(t, y, h, params, scratch)
        summary[S_STEPS] += 1
        sk.event_values(y, bodies, params[3], g_new)
        down = -1
        frac = 1.0
        for e in range(2 * n_bodies):
            if g_new[e] >= 0.0 and g_old[e] < 0.0:
                f = -g_old[e] / (g_new[e] - g_old[e])  # linear: the crossing within the step
                if down < 0 or f < frac:
                    down = e
                    frac = f
            g_old[e] = g_new[e]
        if down >= 0:  # a body lies down or fell off its support: the structure is down
            t_down = t + frac * h
            b = down % n_bodies
            # the samples before the crossing, interpolated; from it on, frozen
            k = _sample_rows(t_mon, k, m, t_down, t + h, h, y_prev, y, y_int, stride, params, theta_commit, hist_y,
                             hist_diag, hist_body, summary, body_stats, joint_stats, joint_committed, y0)
            summary[S_OVERTURN_TIME] = t_down
            summary[S_OVERTURN_BODY] = b
            if down >= n_bodies:
                summary[S_STATUS] = STATUS_COLLAPSED
            summary[S_END_TIME] = t_down
            st._monitor(t_down, y, params, theta_commit, summary, body_stats, joint_stats, joint_committed, True)
            for kk in range(k, m):
                if kk % stride == 0 and kk // stride < n_hist:
                    st._monitor(t_mon[kk], y, params, theta_commit, summary, body_stats, joint_stats,
                                joint_committed, False)
                    st._history_row(t_mon[kk], y, params, kk // stride, hist_y, hist_diag, hist_body,
                                    body_stats, y0)
            return m
        # the statistics of every step, from its own forces (no sampling between steps)
        st.update_statistics(t + h, y, params, theta_commit, summary, body_stats, joint_stats, joint_committed,
                             True)
    return stop
