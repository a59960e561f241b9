"""Compiled kernel of the compliant-contact models: rigid bodies on a list of joints of points.

One kernel for every structure the model runs: a monolith (one body on the ground), a column of
drums and its capital (a chain: each body on the one below), a colonnade (columns whose
capitals carry epistyle blocks, the blocks touching head to head). The tables and the state are
laid out in :mod:`pipeline.dynamics.compliant.layout`; a joint is a face of its lower body (or
of the ground), of any orientation, and the contact points of its upper body on it, each
carrying the joint law of :mod:`pipeline.dynamics.compliant.joint` in the face's frame. The
equations are written in the frame of the ground, which accelerates: on every body act its
weight and the uniform field ``-m a_g(t)``, with the record linear between samples.

Here: the kinematics (bodies' rotations, joints' faces), the points' geometry, the joints'
forces and the right-hand side of the adaptive integrators, the energy, the events, the
dislocations. The statistics and history rows every integrator shares are
:mod:`pipeline.dynamics.compliant.statistics`; the integrators,
:mod:`pipeline.dynamics.compliant.adaptive` (the reference) and
:mod:`pipeline.dynamics.compliant.semi_implicit` (the default).

Exact rest: the loads that hold each body in the rest state (its weight, and round-off) are set
to the joints' net force and torque there (:func:`set_static_loads`), so that at rest every
derivative is exactly zero and a structure under no excitation stays exactly still. The rest
state itself, the static equilibrium of the joints' springs, is found by the layer above
(:mod:`pipeline.compliant`); the points come in mirror pairs where a face allows, so that on a
symmetric joint the moments of equal forces cancel exactly.
"""

import math

import numpy as np
from numba import njit

from pipeline.dynamics.compliant import joint as jl
from pipeline.dynamics.compliant.layout import (
    A_DAMPING, A_FRICTION, A_WORK, B_COS_LIE, B_HOLD, B_IX, B_IY, B_IZ, B_MASS, B_SUPPORT, B_Z_FALL, GROUND, JW_O,
    J_AREA, J_BAND, J_CN, J_DELTA, J_F, J_FA, J_FB, J_G, J_KN, J_KS, J_LOWER, J_MU, J_OX, J_OY, J_OZ, J_SHAPE, J_TAU,
    J_UFLOOR, J_UPPER, J_UX, J_UY, J_UZ, M_AREA, M_COP_BX, M_COP_BY, M_COP_X, M_COP_Y, M_ELASTIC, M_NORMAL,
    M_NORMAL_EL, M_TX, M_TY, NB, N_ACC, N_JWORK, N_MON, N_WORK, P_AREA, P_U, P_V, P_X, P_Y, P_Z, QW, QX, QY, QZ, VX,
    VY, VZ, W_F, W_OM, W_T, WX, WY, WZ, X, Y, Z,
)
from pipeline.dynamics.excitation import ground_acceleration

@njit(cache=True)
def rotation_entries(qw, qx, qy, qz):
    """The 9 entries (row-major) of the rotation matrix of a quaternion, normalised; exactly I at
    (1, 0, 0, 0)."""
    s = 2.0 / (qw * qw + qx * qx + qy * qy + qz * qz)
    return (1.0 - s * (qy * qy + qz * qz), s * (qx * qy - qw * qz), s * (qx * qz + qw * qy),
            s * (qx * qy + qw * qz), 1.0 - s * (qx * qx + qz * qz), s * (qy * qz - qw * qx),
            s * (qx * qz - qw * qy), s * (qy * qz + qw * qx), 1.0 - s * (qx * qx + qy * qy))


@njit(cache=True, inline="always")
def rotation_matrix(qw, qx, qy, qz, out):
    """Rotation matrix (row-major, 9) of a quaternion, normalised, into ``out``
    (:func:`rotation_entries`)."""
    e = rotation_entries(qw, qx, qy, qz)
    for k in range(9):
        out[k] = e[k]


@njit(cache=True, inline="always")
def face_frame(y, joints, j, work, jwork):
    """The face of joint j in the ground frame: its axes (``jwork[j, 0:9]``, row-major, columns the
    face's x, y and normal) and its centre (``jwork[j, 9:12]``), from its lower body's pose (the
    rotation in ``work``) or, on the ground, as given. The tables are indexed by row, not taken
    as row views (a view costs two calls into numba's runtime for its reference count)."""
    lower = int(joints[j, J_LOWER])
    if lower == GROUND:
        for k in range(9):
            jwork[j, k] = joints[j, J_F + k]
        jwork[j, JW_O], jwork[j, JW_O + 1], jwork[j, JW_O + 2] = joints[j, J_OX], joints[j, J_OY], joints[j, J_OZ]
        return
    for r in range(3):
        for c in range(3):
            jwork[j, 3 * r + c] = work[lower, 3 * r] * joints[j, J_F + c] + \
                work[lower, 3 * r + 1] * joints[j, J_F + 3 + c] + work[lower, 3 * r + 2] * joints[j, J_F + 6 + c]
    lo = NB * lower
    ox, oy, oz = joints[j, J_OX], joints[j, J_OY], joints[j, J_OZ]
    jwork[j, JW_O] = y[lo + X] + (work[lower, 0] * ox + work[lower, 1] * oy + work[lower, 2] * oz)
    jwork[j, JW_O + 1] = y[lo + Y] + (work[lower, 3] * ox + work[lower, 4] * oy + work[lower, 5] * oz)
    jwork[j, JW_O + 2] = y[lo + Z] + (work[lower, 6] * ox + work[lower, 7] * oy + work[lower, 8] * oz)


@njit(cache=True)
def _kinematics(y, params):
    """Rotation matrices and ground-frame angular velocities of the bodies, the joints' faces;
    zero the joint forces."""
    bodies, points, joint_start, joints, record, dt, work, mon, jwork = params[:9]
    for b in range(bodies.shape[0]):
        o = NB * b
        e = rotation_entries(y[o + QW], y[o + QX], y[o + QY], y[o + QZ])
        for k in range(9):
            work[b, k] = e[k]
        wx, wy, wz = y[o + WX], y[o + WY], y[o + WZ]
        work[b, W_OM] = e[0] * wx + e[1] * wy + e[2] * wz
        work[b, W_OM + 1] = e[3] * wx + e[4] * wy + e[5] * wz
        work[b, W_OM + 2] = e[6] * wx + e[7] * wy + e[8] * wz
        for k in range(6):
            work[b, W_F + k] = 0.0
    for j in range(joints.shape[0]):
        face_frame(y, joints, j, work, jwork)


@njit(cache=True, inline="always")
def face_overlap(xi_x, xi_y, shape, half_a, half_b, band):
    """Fraction of a point's patch over its joint's face, and its gradient in the face's plane.

    A disc runs off radially, a rectangle along each side (the product of the two overlaps);
    :func:`pipeline.dynamics.compliant.joint.overlap` is the run-off of one edge.

    Parameters
    ----------
    xi_x, xi_y : float
        The point's position on the face [L].
    shape, half_a, half_b, band : float
        The face's ``J_SHAPE``, ``J_FA``, ``J_FB`` and ``J_BAND`` (its joint's row). Inlined: a
        quarter of the points in contact lie on the edge of a face of their own radius (a drum's rim
        on the drum below, a block's bearing on the abacus' edge) and come here at every step; as a
        call, the point pass kept its many live numbers on the stack around it.

    Returns
    -------
    tuple of float
        ``(s, ds/dxi_x, ds/dxi_y)``.
    """
    if shape == 0.0:
        rho = math.sqrt(xi_x * xi_x + xi_y * xi_y)
        s, ds = jl.overlap(rho, half_a, band)
        if ds == 0.0:
            return s, 0.0, 0.0
        return s, ds * xi_x / rho, ds * xi_y / rho
    sx, dsx = jl.overlap(abs(xi_x), half_a, band)
    sy, dsy = jl.overlap(abs(xi_y), half_b, band)
    return sx * sy, dsx * math.copysign(1.0, xi_x) * sy, sx * dsy * math.copysign(1.0, xi_y)


@njit(cache=True)
def _penetration(y, p, j, params):
    """Penetration of contact point p of joint j into its face, and its overlap s.

    The cheap part of :func:`_point_geometry`: most points of a rocking column are out of
    contact, and for them nothing else is needed.
    """
    points, joints, work, jwork = params[1], params[3], params[6], params[8]
    u = int(joints[j, J_UPPER])
    o = NB * u
    px, py, pz = points[p, P_X], points[p, P_Y], points[p, P_Z]
    dx = y[o + X] + (work[u, 0] * px + work[u, 1] * py + work[u, 2] * pz) - jwork[j, JW_O]
    dy = y[o + Y] + (work[u, 3] * px + work[u, 4] * py + work[u, 5] * pz) - jwork[j, JW_O + 1]
    dz = y[o + Z] + (work[u, 6] * px + work[u, 7] * py + work[u, 8] * pz) - jwork[j, JW_O + 2]
    xi_z = jwork[j, 2] * dx + jwork[j, 5] * dy + jwork[j, 8] * dz
    if -xi_z <= 0.0:
        return -xi_z, 1.0
    xi_x = jwork[j, 0] * dx + jwork[j, 3] * dy + jwork[j, 6] * dz
    xi_y = jwork[j, 1] * dx + jwork[j, 4] * dy + jwork[j, 7] * dz
    return -xi_z, face_overlap(xi_x, xi_y, joints[j, J_SHAPE], joints[j, J_FA], joints[j, J_FB], joints[j, J_BAND])[0]


@njit(cache=True)
def _point_geometry(y, p, j, params):
    """Where contact point p of joint j is on its face, and how it moves.

    Returns the lever arms from the upper and lower centres of mass (ground frame; from the
    ground's origin for the ground), the position on the face (xi_x, xi_y), the penetration d,
    the tangential relative velocity (face frame), d' and the overlap (s, ds/dxi_x, ds/dxi_y).
    """
    points, joints, work, jwork = params[1], params[3], params[6], params[8]
    u = int(joints[j, J_UPPER])
    lower = int(joints[j, J_LOWER])
    o = NB * u
    px, py, pz = points[p, P_X], points[p, P_Y], points[p, P_Z]
    rux = work[u, 0] * px + work[u, 1] * py + work[u, 2] * pz
    ruy = work[u, 3] * px + work[u, 4] * py + work[u, 5] * pz
    ruz = work[u, 6] * px + work[u, 7] * py + work[u, 8] * pz
    xp = y[o + X] + rux
    yp = y[o + Y] + ruy
    zp = y[o + Z] + ruz
    rlx, rly, rlz = xp, yp, zp
    lgx, lgy, lgz = 0.0, 0.0, 0.0  # the velocity of the lower body's material point there (the ground's: 0)
    if lower != GROUND:
        lo = NB * lower
        rlx = xp - y[lo + X]
        rly = yp - y[lo + Y]
        rlz = zp - y[lo + Z]
        lwx, lwy, lwz = work[lower, W_OM], work[lower, W_OM + 1], work[lower, W_OM + 2]
        lgx = y[lo + VX] + lwy * rlz - lwz * rly
        lgy = y[lo + VY] + lwz * rlx - lwx * rlz
        lgz = y[lo + VZ] + lwx * rly - lwy * rlx
    # y and work read after the branch: a table whose last use is inside it keeps numba's reference
    # counting (8 calls into its runtime a point, most of this function's cost); x - 0.0 is x to the bit
    wx, wy, wz = work[u, W_OM], work[u, W_OM + 1], work[u, W_OM + 2]
    gx = (y[o + VX] + wy * ruz - wz * ruy) - lgx
    gy = (y[o + VY] + wz * rux - wx * ruz) - lgy
    gz = (y[o + VZ] + wx * ruy - wy * rux) - lgz
    dx, dy, dz = xp - jwork[j, JW_O], yp - jwork[j, JW_O + 1], zp - jwork[j, JW_O + 2]
    xi_x = jwork[j, 0] * dx + jwork[j, 3] * dy + jwork[j, 6] * dz
    xi_y = jwork[j, 1] * dx + jwork[j, 4] * dy + jwork[j, 7] * dz
    xi_z = jwork[j, 2] * dx + jwork[j, 5] * dy + jwork[j, 8] * dz
    vlx = jwork[j, 0] * gx + jwork[j, 3] * gy + jwork[j, 6] * gz
    vly = jwork[j, 1] * gx + jwork[j, 4] * gy + jwork[j, 7] * gz
    vlz = jwork[j, 2] * gx + jwork[j, 5] * gy + jwork[j, 8] * gz
    s, sx, sy = face_overlap(xi_x, xi_y, joints[j, J_SHAPE], joints[j, J_FA], joints[j, J_FB], joints[j, J_BAND])
    return rux, ruy, ruz, rlx, rly, rlz, xi_x, xi_y, -xi_z, vlx, vly, -vlz, s, sx, sy


@njit(cache=True)
def _contacts(y, params, dydt, rates, monitor):
    """Forces of every joint on its bodies (into the scratch), and the joint-state rates.

    ``rates``: write u', the slip-path rates and return the dissipation rates (for the
    right-hand side). ``monitor``: fill the per-joint monitor (normal force, tangential
    resultant, centres of pressure, area in contact, elastic energy).

    Returns
    -------
    tuple of float
        Friction and damping dissipation rates.
    """
    bodies, points, joint_start, joints, record, dt, work, mon, jwork = params[:9]
    n_bodies, n_joints = bodies.shape[0], joints.shape[0]
    sh = NB * n_bodies
    slip = sh + 2 * points.shape[0] + N_ACC
    d_fric = 0.0
    d_damp = 0.0
    for j in range(n_joints):
        kn, ks, mu, cn, tau = joints[j, J_KN], joints[j, J_KS], joints[j, J_MU], joints[j, J_CN], joints[j, J_TAU]
        lower = int(joints[j, J_LOWER])
        slip_rate = 0.0
        if monitor:
            for k in range(N_MON):
                mon[j, k] = 0.0
        u = int(joints[j, J_UPPER])
        for p in range(joint_start[j], joint_start[j + 1]):
            d, s = _penetration(y, p, j, params)
            if d <= 0.0 or s <= 0.0:
                # out of contact: no force, and the shear spring relaxes (its energy stays in
                # the budget until it has: joint.unloaded_spring)
                dux, duy, e_shear, p_fric = jl.unloaded_spring(y[sh + 2 * p], y[sh + 2 * p + 1],
                                                               ks * points[p, P_AREA], tau)
                if rates:
                    dydt[sh + 2 * p] = dux
                    dydt[sh + 2 * p + 1] = duy
                    d_fric += p_fric
                if monitor:
                    mon[j, M_ELASTIC] += e_shear
                continue
            (rux, ruy, ruz, rlx, rly, rlz, xi_x, xi_y, d, vtx, vty, d_dot, s, sx, sy) = _point_geometry(
                y, p, j, params)
            area = points[p, P_AREA]
            f_n, f_el, p_damp = jl.normal_force(area, kn, cn, joints[j, J_DELTA], s, d, d_dot)
            cap = mu * f_el
            cap_rate = 0.0
            if f_el > 0.0:
                cap_rate = mu * area * kn * (s * d_dot + d * (sx * vtx + sy * vty))
            ux, uy = y[sh + 2 * p], y[sh + 2 * p + 1]
            # the shear dashpot: the normal one's ratio to the stiffness, engaged as it is
            c_shear = ks / kn * cn * area * s * min(1.0, d / joints[j, J_DELTA])
            dux, duy, fx, fy, e_shear, p_fric, p_visc, lam = jl.shear_law(
                ux, uy, vtx, vty, cap, cap_rate, ks * area, c_shear, tau, joints[j, J_UFLOOR])
            friction_x, friction_y = fx, fy  # within the point's cone: what the monitor sums
            # the pull of a patch running off the edge of the face (from 1/2 k A s d^2)
            if (sx != 0.0 or sy != 0.0) and d > 0.0:
                pull = -0.5 * kn * area * d * d
                fx += pull * sx
                fy += pull * sy
            if rates:
                dydt[sh + 2 * p] = dux
                dydt[sh + 2 * p + 1] = duy
                d_fric += p_fric
                d_damp += p_damp + p_visc
                slip_rate += area * lam
            if monitor:
                mon[j, M_NORMAL] += f_n
                mon[j, M_NORMAL_EL] += f_el
                mon[j, M_TX] += friction_x
                mon[j, M_TY] += friction_y
                mon[j, M_COP_BX] += f_n * points[p, P_U]
                mon[j, M_COP_BY] += f_n * points[p, P_V]
                mon[j, M_COP_X] += f_n * xi_x
                mon[j, M_COP_Y] += f_n * xi_y
                if f_n > 0.0:
                    mon[j, M_AREA] += area * s
                mon[j, M_ELASTIC] += 0.5 * f_el * (d if d > 0.0 else 0.0) + e_shear
            # ground-frame force on the upper body at the point, reaction on the lower one
            Fx = jwork[j, 0] * fx + jwork[j, 1] * fy + jwork[j, 2] * f_n
            Fy = jwork[j, 3] * fx + jwork[j, 4] * fy + jwork[j, 5] * f_n
            Fz = jwork[j, 6] * fx + jwork[j, 7] * fy + jwork[j, 8] * f_n
            if lower != GROUND:
                work[lower, W_F] -= Fx
                work[lower, W_F + 1] -= Fy
                work[lower, W_F + 2] -= Fz
                work[lower, W_T] -= rly * Fz - rlz * Fy
                work[lower, W_T + 1] -= rlz * Fx - rlx * Fz
                work[lower, W_T + 2] -= rlx * Fy - rly * Fx
            work[u, W_F] += Fx
            work[u, W_F + 1] += Fy
            work[u, W_F + 2] += Fz
            work[u, W_T] += ruy * Fz - ruz * Fy
            work[u, W_T + 1] += ruz * Fx - rux * Fz
            work[u, W_T + 2] += rux * Fy - ruy * Fx
        if rates:
            dydt[slip + j] = slip_rate / joints[j, J_AREA]
        if monitor and mon[j, M_NORMAL] > 0.0:
            for k in (M_COP_BX, M_COP_BY, M_COP_X, M_COP_Y):
                mon[j, k] /= mon[j, M_NORMAL]
        if monitor:
            mon[j, M_AREA] /= joints[j, J_AREA]
    return d_fric, d_damp


@njit(cache=True)
def body_rates(y, b, bodies, work, ax, ay, az, dydt):
    """Body b's rates from the joints' force and torque on it (its scratch row ``work[b]``); returns
    the power of the field ``-m a_g`` on it. The joints' sum first, then the holding load: at rest
    this is exactly zero. The tables are indexed, not taken as row views (:func:`face_frame`)."""
    o = NB * b
    m = bodies[b, B_MASS]
    fx = (work[b, W_F] - bodies[b, B_HOLD]) - m * ax
    fy = (work[b, W_F + 1] - bodies[b, B_HOLD + 1]) - m * ay
    fz = (work[b, W_F + 2] - bodies[b, B_HOLD + 2]) - m * az
    vx, vy, vz = y[o + VX], y[o + VY], y[o + VZ]
    dydt[o + X] = vx
    dydt[o + Y] = vy
    dydt[o + Z] = vz
    dydt[o + VX] = fx / m
    dydt[o + VY] = fy / m
    dydt[o + VZ] = fz / m
    qw, qx, qy, qz = y[o + QW], y[o + QX], y[o + QY], y[o + QZ]
    wx, wy, wz = y[o + WX], y[o + WY], y[o + WZ]
    dydt[o + QW] = -0.5 * (qx * wx + qy * wy + qz * wz)
    dydt[o + QX] = 0.5 * (qw * wx + qy * wz - qz * wy)
    dydt[o + QY] = 0.5 * (qw * wy + qz * wx - qx * wz)
    dydt[o + QZ] = 0.5 * (qw * wz + qx * wy - qy * wx)
    tx = work[b, W_T] - bodies[b, B_HOLD + 3]
    ty = work[b, W_T + 1] - bodies[b, B_HOLD + 4]
    tz = work[b, W_T + 2] - bodies[b, B_HOLD + 5]
    bx = work[b, 0] * tx + work[b, 3] * ty + work[b, 6] * tz  # torque in body axes
    by = work[b, 1] * tx + work[b, 4] * ty + work[b, 7] * tz
    bz = work[b, 2] * tx + work[b, 5] * ty + work[b, 8] * tz
    ix, iy, iz = bodies[b, B_IX], bodies[b, B_IY], bodies[b, B_IZ]
    # Euler's equations in principal axes
    dydt[o + WX] = (bx + (iy - iz) * wy * wz) / ix
    dydt[o + WY] = (by + (iz - ix) * wz * wx) / iy
    dydt[o + WZ] = (bz + (ix - iy) * wx * wy) / iz
    return -m * (ax * vx + ay * vy + az * vz)


@njit(cache=True)
def rhs(t, y, params, dydt):
    """Right-hand side for the compiled integrator; ``params`` as :func:`make_params`."""
    bodies, points, joint_start, joints, record, dt = params[:6]
    work = params[6]
    ax, ay, az = ground_acceleration(t, record, dt)
    _kinematics(y, params)
    d_fric, d_damp = _contacts(y, params, dydt, True, False)
    n_bodies = bodies.shape[0]
    acc = NB * n_bodies + 2 * points.shape[0]
    power = 0.0
    for b in range(n_bodies):
        power += body_rates(y, b, bodies, work, ax, ay, az, dydt)
    dydt[acc + A_WORK] = power
    dydt[acc + A_FRICTION] = d_fric
    dydt[acc + A_DAMPING] = d_damp


@njit(cache=True)
def event_values(y, bodies, joints, g):
    """Per body: its tilt reaches the lying tilt (``cos(lie) - R33 >= 0``); it has fallen off its
    support (``z_fall - d >= 0``, d its centre's distance from the supporting face along the face's
    normal, in the frame of the body below; a body on the ground: its height above the ground)."""
    n_bodies = bodies.shape[0]
    for b in range(n_bodies):
        o = NB * b
        qw, qx, qy, qz = y[o + QW], y[o + QX], y[o + QY], y[o + QZ]
        r33 = 1.0 - 2.0 * (qx * qx + qy * qy) / (qw * qw + qx * qx + qy * qy + qz * qz)
        g[b] = bodies[b, B_COS_LIE] - r33
        s = int(bodies[b, B_SUPPORT])
        if s < 0:
            g[n_bodies + b] = bodies[b, B_Z_FALL] - y[o + Z]
            continue
        lower = int(joints[s, J_LOWER])
        dx, dy, dz = y[o + X], y[o + Y], y[o + Z]
        if lower == GROUND:
            px, py, pz = dx, dy, dz
        else:
            ol = NB * lower
            # the entries as numbers (no scratch array to allocate and free at every step)
            rot = rotation_entries(y[ol + QW], y[ol + QX], y[ol + QY], y[ol + QZ])
            dx, dy, dz = dx - y[ol + X], dy - y[ol + Y], dz - y[ol + Z]
            # in the lower body's axes: R^T (x_b - x_lower)
            px = rot[0] * dx + rot[3] * dy + rot[6] * dz
            py = rot[1] * dx + rot[4] * dy + rot[7] * dz
            pz = rot[2] * dx + rot[5] * dy + rot[8] * dz
        # the face's normal: the third column of its axes (row-major)
        d = ((px - joints[s, J_OX]) * joints[s, J_F + 2] + (py - joints[s, J_OY]) * joints[s, J_F + 5]
             + (pz - joints[s, J_OZ]) * joints[s, J_F + 8])
        g[n_bodies + b] = bodies[b, B_Z_FALL] - d


@njit(cache=True)
def _events(t, y, params, g):
    event_values(y, params[0], params[3], g)


@njit(cache=True)
def energy(y, params):
    """Kinetic + potential (the holding loads: the weights) + elastic energy of the joints [M g L].

    Uses (and overwrites) the scratch and the monitor of ``params``.
    """
    bodies, mon = params[0], params[7]
    _kinematics(y, params)
    _contacts(y, params, y, False, True)
    e = 0.0
    for b in range(bodies.shape[0]):
        o = NB * b
        vx, vy, vz = y[o + VX], y[o + VY], y[o + VZ]
        wx, wy, wz = y[o + WX], y[o + WY], y[o + WZ]
        e += 0.5 * bodies[b, B_MASS] * (vx * vx + vy * vy + vz * vz)
        e += 0.5 * (bodies[b, B_IX] * wx * wx + bodies[b, B_IY] * wy * wy + bodies[b, B_IZ] * wz * wz)
        # the holding load's potential: the weight's, and the lean a face resting tilted gives it (0 for a column)
        e += bodies[b, B_HOLD] * y[o + X] + bodies[b, B_HOLD + 1] * y[o + Y] + bodies[b, B_HOLD + 2] * y[o + Z]
    for j in range(params[3].shape[0]):
        e += mon[j, M_ELASTIC]
    return e


@njit(cache=True)
def set_static_loads(y, params):
    """Set each body's holding load to the joints' net force and torque on it in the state y (the
    rest state): its weight, m g to the rest state's round-off, and a torque of that size."""
    bodies, work = params[0], params[6]
    _kinematics(y, params)
    _contacts(y, params, y, False, False)
    for b in range(bodies.shape[0]):
        for k in range(6):
            bodies[b, B_HOLD + k] = work[b, W_F + k]


@njit(cache=True)
def joint_loads(y, params, out):
    """The joints' net force and torque on every body in the state y (``out``: n_bodies x 6, ground
    frame, torque about the centre), without the holding loads: the static solve of the layer
    above balances them against the weights."""
    bodies, work = params[0], params[6]
    _kinematics(y, params)
    _contacts(y, params, y, False, False)
    for b in range(bodies.shape[0]):
        for k in range(6):
            out[b, k] = work[b, W_F + k]


@njit(cache=True, inline="always")
def tilt_and_rotation(y, b):
    """Tilt of body b's axis from the vertical [rad] and its rotation about the vertical [rad].

    The rotation is phi + psi of the Z-X-Z Euler angles, ``atan2(R21 - R12, R11 + R22)``,
    defined at every tilt below pi; the tilt is ``atan2(|horizontal part of the axis|, R33)``,
    accurate down to the smallest angles. Both from the quaternion directly: with
    ``a = qx^2 + qy^2`` and ``c = qw^2 + qz^2``, the axis's horizontal part is ``2 sqrt(a c)``
    and ``R33 = c - a`` (over |q|^2, which cancels), and ``R21 - R12 = 4 qw qz``,
    ``R11 + R22 = 2 (qw^2 - qz^2)`` (called every step: no rotation matrix).
    """
    o = NB * b
    qw, qx, qy, qz = y[o + QW], y[o + QX], y[o + QY], y[o + QZ]
    a = qx * qx + qy * qy
    c = qw * qw + qz * qz
    return math.atan2(2.0 * math.sqrt(a * c), c - a), math.atan2(2.0 * qw * qz, qw * qw - qz * qz)


@njit(cache=True)
def dislocations(y, params, out):
    """Relative position of each joint's upper body on its face, in the face's frame.

    ``out[j]``: slip of the upper body's bearing face centre from the face's centre [L]
    (x, y), twist of the upper face about the face's normal [rad], and the widest opening of
    the joint, the largest gap at a contact point [L] (0 while every point presses in). For a
    joint on the ground the face's centre is where the body stood (the caller subtracts the
    rest state's).
    """
    joint_start, joints, work, jwork = params[2], params[3], params[6], params[8]
    _kinematics(y, params)
    for j in range(joints.shape[0]):
        u = int(joints[j, J_UPPER])
        Ru = work[u]
        o = NB * u
        cx, cy, cz = joints[j, J_UX], joints[j, J_UY], joints[j, J_UZ]
        F = jwork[j]
        dx = y[o + X] + (Ru[0] * cx + Ru[1] * cy + Ru[2] * cz) - F[JW_O]
        dy = y[o + Y] + (Ru[3] * cx + Ru[4] * cy + Ru[5] * cz) - F[JW_O + 1]
        dz = y[o + Z] + (Ru[6] * cx + Ru[7] * cy + Ru[8] * cz) - F[JW_O + 2]
        out[j, 0] = F[0] * dx + F[3] * dy + F[6] * dz
        out[j, 1] = F[1] * dx + F[4] * dy + F[7] * dz
        # the upper face's axes in the ground frame, Ru G, then in the face's frame: its x and y axes
        g = joints[j, J_G:J_G + 9]
        ux = np.empty(3)
        uy = np.empty(3)
        for r in range(3):
            ux[r] = Ru[3 * r] * g[0] + Ru[3 * r + 1] * g[3] + Ru[3 * r + 2] * g[6]
            uy[r] = Ru[3 * r] * g[1] + Ru[3 * r + 1] * g[4] + Ru[3 * r + 2] * g[7]
        r11 = F[0] * ux[0] + F[3] * ux[1] + F[6] * ux[2]
        r21 = F[1] * ux[0] + F[4] * ux[1] + F[7] * ux[2]
        r12 = F[0] * uy[0] + F[3] * uy[1] + F[6] * uy[2]
        r22 = F[1] * uy[0] + F[4] * uy[1] + F[7] * uy[2]
        out[j, 2] = math.atan2(r21 - r12, r11 + r22)
        gap = 0.0
        for p in range(joint_start[j], joint_start[j + 1]):
            d = _penetration(y, p, j, params)[0]
            if -d > gap:
                gap = -d
        out[j, 3] = gap


def make_params(bodies, points, joint_start, joints, record, dt, watched):
    """Pack the kernel parameters, with fresh scratch arrays (one set per simulation).

    ``watched``: the bodies whose largest tilt is the run's peak theta (a column's top).
    """
    n_bodies, n_joints = bodies.shape[0], joints.shape[0]
    return (np.ascontiguousarray(bodies, dtype=np.float64), np.ascontiguousarray(points, dtype=np.float64),
            np.ascontiguousarray(joint_start, dtype=np.int64), np.ascontiguousarray(joints, dtype=np.float64),
            np.ascontiguousarray(record, dtype=np.float64), float(dt),
            np.zeros((n_bodies, N_WORK)), np.zeros((n_joints, N_MON)), np.zeros((n_joints, N_JWORK)),
            np.ascontiguousarray(watched, dtype=np.int64))
