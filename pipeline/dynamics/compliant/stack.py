"""Compiled kernel of the compliant-contact models: N stacked rigid bodies on joints of points.

One kernel for the monolith (N = 1, the model ``"3d-compliant"``) and for multi-drum columns
(N > 1): rigid bodies with six degrees of freedom each, stacked bottom (0) to top. The base
of body 0 stands on the ground plane; the base of body i stands on the top face of body
i - 1, a plane moving with it, and its points count only over that face. Every joint is a
set of contact points carrying the joint law of :mod:`pipeline.dynamics.compliant.joint`.

Everything is dimensionless: lengths per a reference length L (the base radius of the
column), time per sqrt(L/g), masses per the total mass M, forces per M g, energies per
M g L, stiffnesses per unit area per M g / L^3, damping per unit area per
M g sqrt(L/g) / L^3. The equations are written in the frame of the ground, which
accelerates: on every body act its weight and the uniform field ``-m a_g(t)`` (as in the
rigid kernels), with the record linear between samples.

State vector (length :func:`state_size`), in this order:

* per body (13): centre of mass x, y, z; orientation quaternion w, x, y, z (body to
  ground; normalised where it is used, so its norm needs no constraint); velocity of the
  centre of mass (ground frame); angular velocity in body axes;
* per contact point (2): elastic shear displacement in the frame of the lower face;
* work of the ground motion, friction dissipation, damping dissipation;
* per joint: the slip path, the area-weighted mean of the points' plastic slip [L].

Body axes are principal: the axis of the drum is z, the inertia is I_t about x and y and
I_a about z (drums and square capitals alike).

Exact rest: the weights used in the equations are the spring forces of the static state
(:func:`set_static_weights`), and the points come in mirror pairs
(:func:`pipeline.dynamics.compliant.joint.contact_points`), so that at rest every derivative is
exactly zero and a column under no excitation stays exactly still.
"""

import math

import numpy as np
from numba import njit

from pipeline.dynamics.compliant import joint as jl
from pipeline.dynamics.excitation import ground_acceleration
from pipeline.dynamics.integrators.dop853 import dop853
from pipeline.dynamics.integrators.dopri5 import dopri5

# Columns of the body table (one row per body).
B_MASS, B_IT, B_IA, B_ZC, B_TOP, B_TOP_R, B_WEIGHT, B_COS_LIE = range(8)
N_BODY_COLS = 8
# Columns of the point table (one row per contact point, joint by joint).
P_X, P_Y, P_Z, P_AREA = range(4)
N_POINT_COLS = 4
# Columns of the joint table (joint j is the base of body j).
J_KN, J_KS, J_MU, J_CN, J_TAU, J_BAND, J_AREA, J_RIM, J_DELTA, J_UFLOOR, J_LAND = range(11)
N_JOINT_COLS = 11

# Per-body state.
X, Y, Z, QW, QX, QY, QZ, VX, VY, VZ, WX, WY, WZ = range(13)
NB = 13
# Accumulators after the shear states.
A_WORK, A_FRICTION, A_DAMPING = range(3)
N_ACC = 3

# Scratch columns per body (params[6]): rotation matrix (row-major), angular velocity in
# the ground frame, force and torque (ground frame) from the joints.
W_R, W_OM, W_F, W_T = 0, 9, 12, 15
N_WORK = 18

# Columns of the per-joint monitor (params[7]).
# M_NORMAL_EL: the elastic part of the normal force, which the friction cap uses: the mobilised
# friction |F_t| / N_el never exceeds mu (the dashpot's part of N would let a separating
# joint's ratio pass it). M_TX, M_TY: the resultant of the points' friction forces (shear
# spring and dashpot, each within its cone), not of the pull of a patch running off an edge,
# which is the band's normal reaction, not friction.
(M_NORMAL, M_TX, M_TY, M_COP_BX, M_COP_BY, M_COP_X, M_COP_Y, M_AREA, M_ELASTIC, M_NORMAL_EL) = range(10)
N_MON = 10

# Summary of a run.
# S_UNDECIDED: 1 if the run reached its settle limit after the tail with the column still able to fall.
(S_STATUS, S_PEAK_THETA, S_PEAK_TIME, S_OVERTURN_TIME, S_OVERTURN_BODY, S_NFEV, S_STEPS,
 S_REJECTED, S_CALLS, S_END_TIME, S_ENERGY_START, S_ENERGY_END, S_UNDECIDED) = range(13)
N_SUMMARY = 13
# Per-body statistics: peak tilt and its time, unwrapped rotation about the vertical.
BS_PEAK, BS_PEAK_TIME, BS_ROTATION = range(3)
N_BODY_STATS = 3
# Per-joint statistics.
(JS_UPLIFT_TIME, JS_RETURNS, JS_MIN_NORMAL, JS_PEAK_MU, JS_MIN_AREA, JS_ON_RIM,
 JS_SLIDE_TIME, JS_FLIGHT_TIME) = range(8)  # JS_RETURNS: landings, from the rim back into the base
N_JOINT_STATS = 8
# History diagnostics of the base joint (and the whole column).
(D_NORMAL, D_TANGENTIAL, D_MU, D_COP_X, D_COP_Y, D_AREA, D_ENERGY, D_AX, D_AY, D_AZ, D_ON_RIM) = range(11)
N_DIAG = 11
# Per-body history: centre displacement x, y, tilt, rotation about the vertical (unwrapped).
H_DX, H_DY, H_TILT, H_ROT = range(4)
N_HBODY = 4

# A joint mobilises its friction when |F_t| reaches this fraction of mu N (sliding onset).
SLIDE_FRACTION = 0.999
MAX_STEPS = 50_000_000
CHUNK = 64  # monitor samples per integrator call
STATUS_COLLAPSED = 2  # summary status: a body fell off the one below (below the ground)
# Integrators of :func:`run`: the joint law's kinks waste DOP853's order (pipeline.dynamics.integrators.dopri5)
METHOD_DOPRI5, METHOD_DOP853 = 0, 1
METHODS = {"dopri5": METHOD_DOPRI5, "dop853": METHOD_DOP853}


def state_size(n_bodies, n_points):
    """Length of the state vector."""
    return NB * n_bodies + 2 * n_points + N_ACC + n_bodies


def kept_size(n_bodies):
    """Length of a history row of states: bodies, accumulators, slip paths (no shear states)."""
    return NB * n_bodies + N_ACC + n_bodies


@njit(cache=True)
def rotation_matrix(qw, qx, qy, qz, out):
    """Rotation matrix (row-major, 9) of a quaternion, normalised; exactly I at (1, 0, 0, 0)."""
    s = 2.0 / (qw * qw + qx * qx + qy * qy + qz * qz)
    out[0] = 1.0 - s * (qy * qy + qz * qz)
    out[1] = s * (qx * qy - qw * qz)
    out[2] = s * (qx * qz + qw * qy)
    out[3] = s * (qx * qy + qw * qz)
    out[4] = 1.0 - s * (qx * qx + qz * qz)
    out[5] = s * (qy * qz - qw * qx)
    out[6] = s * (qx * qz - qw * qy)
    out[7] = s * (qy * qz + qw * qx)
    out[8] = 1.0 - s * (qx * qx + qy * qy)


@njit(cache=True)
def _kinematics(y, bodies, work):
    """Rotation matrices and ground-frame angular velocities; zero the joint forces."""
    for b in range(bodies.shape[0]):
        o = NB * b
        R = work[b]
        rotation_matrix(y[o + QW], y[o + QX], y[o + QY], y[o + QZ], R)
        wx, wy, wz = y[o + WX], y[o + WY], y[o + WZ]
        R[W_OM] = R[0] * wx + R[1] * wy + R[2] * wz
        R[W_OM + 1] = R[3] * wx + R[4] * wy + R[5] * wz
        R[W_OM + 2] = R[6] * wx + R[7] * wy + R[8] * wz
        for k in range(6):
            R[W_F + k] = 0.0


@njit(cache=True)
def _penetration(y, p, j, params):
    """Penetration of contact point p of joint j into the face below, and its overlap s.

    The cheap part of :func:`_point_geometry`: most points of a rocking column are out of
    contact, and for them nothing else is needed.
    """
    bodies, points, joint_start, joints, record, dt, work, mon = params
    Ru = work[j]
    o = NB * j
    px, py, pz = points[p, P_X], points[p, P_Y], points[p, P_Z]
    zp = y[o + Z] + Ru[6] * px + Ru[7] * py + Ru[8] * pz
    if j == 0:
        return -zp, 1.0
    lo = NB * (j - 1)
    Rl = work[j - 1]
    h = bodies[j - 1, B_TOP] - bodies[j - 1, B_ZC]
    dx = y[o + X] + Ru[0] * px + Ru[1] * py + Ru[2] * pz - y[lo + X] - Rl[2] * h
    dy = y[o + Y] + Ru[3] * px + Ru[4] * py + Ru[5] * pz - y[lo + Y] - Rl[5] * h
    dz = zp - y[lo + Z] - Rl[8] * h
    xi_x = Rl[0] * dx + Rl[3] * dy + Rl[6] * dz
    xi_y = Rl[1] * dx + Rl[4] * dy + Rl[7] * dz
    xi_z = Rl[2] * dx + Rl[5] * dy + Rl[8] * dz
    s = jl.overlap(math.sqrt(xi_x * xi_x + xi_y * xi_y), bodies[j - 1, B_TOP_R], joints[j, J_BAND])[0]
    return -xi_z, s


@njit(cache=True)
def _point_geometry(y, p, j, params):
    """Where contact point p of joint j is, relative to the face below, and how it moves.

    Returns the lever arms from the upper and lower centres of mass (ground frame), the
    position on the lower face (xi_x, xi_y), the penetration d, the tangential relative
    velocity (lower-face frame), d' and the overlap (s, ds/drho).
    """
    bodies, points, joint_start, joints, record, dt, work, mon = params
    Ru = work[j]
    o = NB * j
    px, py, pz = points[p, P_X], points[p, P_Y], points[p, P_Z]
    rux = Ru[0] * px + Ru[1] * py + Ru[2] * pz
    ruy = Ru[3] * px + Ru[4] * py + Ru[5] * pz
    ruz = Ru[6] * px + Ru[7] * py + Ru[8] * pz
    xp = y[o + X] + rux
    yp = y[o + Y] + ruy
    zp = y[o + Z] + ruz
    wx, wy, wz = Ru[W_OM], Ru[W_OM + 1], Ru[W_OM + 2]
    vx = y[o + VX] + wy * ruz - wz * ruy
    vy = y[o + VY] + wz * rux - wx * ruz
    vz = y[o + VZ] + wx * ruy - wy * rux
    if j == 0:  # the ground: its frame is the reference frame
        return rux, ruy, ruz, 0.0, 0.0, 0.0, xp, yp, -zp, vx, vy, -vz, 1.0, 0.0
    lo = NB * (j - 1)
    Rl = work[j - 1]
    h = bodies[j - 1, B_TOP] - bodies[j - 1, B_ZC]
    rlx = xp - y[lo + X]
    rly = yp - y[lo + Y]
    rlz = zp - y[lo + Z]
    dx = rlx - Rl[2] * h  # from the centre of the lower body's top face
    dy = rly - Rl[5] * h
    dz = rlz - Rl[8] * h
    xi_x = Rl[0] * dx + Rl[3] * dy + Rl[6] * dz
    xi_y = Rl[1] * dx + Rl[4] * dy + Rl[7] * dz
    xi_z = Rl[2] * dx + Rl[5] * dy + Rl[8] * dz
    lwx, lwy, lwz = Rl[W_OM], Rl[W_OM + 1], Rl[W_OM + 2]
    gx = vx - (y[lo + VX] + lwy * rlz - lwz * rly)
    gy = vy - (y[lo + VY] + lwz * rlx - lwx * rlz)
    gz = vz - (y[lo + VZ] + lwx * rly - lwy * rlx)
    vlx = Rl[0] * gx + Rl[3] * gy + Rl[6] * gz
    vly = Rl[1] * gx + Rl[4] * gy + Rl[7] * gz
    vlz = Rl[2] * gx + Rl[5] * gy + Rl[8] * gz
    rho = math.sqrt(xi_x * xi_x + xi_y * xi_y)
    s, ds = jl.overlap(rho, bodies[j - 1, B_TOP_R], joints[j, J_BAND])
    return rux, ruy, ruz, rlx, rly, rlz, xi_x, xi_y, -xi_z, vlx, vly, -vlz, s, ds


@njit(cache=True)
def _contacts(y, params, dydt, rates, monitor):
    """Forces of every joint on the bodies (into the scratch), and the joint-state rates.

    ``rates``: write u', the slip-path rates and return the dissipation rates (for the
    right-hand side). ``monitor``: fill the per-joint monitor (normal force, tangential
    resultant, centres of pressure, area in contact, elastic energy).

    Returns
    -------
    tuple of float
        Friction and damping dissipation rates.
    """
    bodies, points, joint_start, joints, record, dt, work, mon = params
    n_bodies = bodies.shape[0]
    sh = NB * n_bodies
    slip = sh + 2 * points.shape[0] + N_ACC
    d_fric = 0.0
    d_damp = 0.0
    for j in range(n_bodies):
        kn, ks, mu, cn, tau = joints[j, J_KN], joints[j, J_KS], joints[j, J_MU], joints[j, J_CN], joints[j, J_TAU]
        slip_rate = 0.0
        if monitor:
            for k in range(N_MON):
                mon[j, k] = 0.0
        Ru = work[j]
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
            (rux, ruy, ruz, rlx, rly, rlz, xi_x, xi_y, d, vtx, vty, d_dot, s, ds) = _point_geometry(y, p, j, params)
            area = points[p, P_AREA]
            f_n, f_el, p_damp = jl.normal_force(area, kn, cn, joints[j, J_DELTA], s, d, d_dot)
            cap = mu * f_el
            cap_rate = 0.0
            if f_el > 0.0:
                rho = math.sqrt(xi_x * xi_x + xi_y * xi_y)
                rho_dot = (xi_x * vtx + xi_y * vty) / rho if ds != 0.0 else 0.0
                cap_rate = mu * area * kn * (s * d_dot + d * ds * rho_dot)
            ux, uy = y[sh + 2 * p], y[sh + 2 * p + 1]
            # the shear dashpot: the normal one's ratio to the stiffness, engaged as it is
            c_shear = ks / kn * cn * area * s * min(1.0, d / joints[j, J_DELTA])
            dux, duy, fx, fy, e_shear, p_fric, p_visc, lam = jl.shear_law(
                ux, uy, vtx, vty, cap, cap_rate, ks * area, c_shear, tau, joints[j, J_UFLOOR])
            friction_x, friction_y = fx, fy  # within the point's cone: what the monitor sums
            # the pull of a patch running off the edge of the face below (from 1/2 k A s d^2)
            if ds != 0.0 and d > 0.0:
                rho = math.sqrt(xi_x * xi_x + xi_y * xi_y)
                push = -0.5 * kn * area * d * d * ds / rho
                fx += push * xi_x
                fy += push * xi_y
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
                mon[j, M_COP_BX] += f_n * points[p, P_X]
                mon[j, M_COP_BY] += f_n * points[p, P_Y]
                mon[j, M_COP_X] += f_n * xi_x
                mon[j, M_COP_Y] += f_n * xi_y
                if f_n > 0.0:
                    mon[j, M_AREA] += area * s
                mon[j, M_ELASTIC] += 0.5 * f_el * (d if d > 0.0 else 0.0) + e_shear
            # ground-frame force on the upper body at the point, reaction on the lower one
            if j == 0:
                Fx, Fy, Fz = fx, fy, f_n
            else:
                Rl = work[j - 1]
                Fx = Rl[0] * fx + Rl[1] * fy + Rl[2] * f_n
                Fy = Rl[3] * fx + Rl[4] * fy + Rl[5] * f_n
                Fz = Rl[6] * fx + Rl[7] * fy + Rl[8] * f_n
                Rl[W_F] -= Fx
                Rl[W_F + 1] -= Fy
                Rl[W_F + 2] -= Fz
                Rl[W_T] -= rly * Fz - rlz * Fy
                Rl[W_T + 1] -= rlz * Fx - rlx * Fz
                Rl[W_T + 2] -= rlx * Fy - rly * Fx
            Ru[W_F] += Fx
            Ru[W_F + 1] += Fy
            Ru[W_F + 2] += Fz
            Ru[W_T] += ruy * Fz - ruz * Fy
            Ru[W_T + 1] += ruz * Fx - rux * Fz
            Ru[W_T + 2] += rux * Fy - ruy * Fx
        if rates:
            dydt[slip + j] = slip_rate / joints[j, J_AREA]
        if monitor and mon[j, M_NORMAL] > 0.0:
            for k in (M_COP_BX, M_COP_BY, M_COP_X, M_COP_Y):
                mon[j, k] /= mon[j, M_NORMAL]
        if monitor:
            mon[j, M_AREA] /= joints[j, J_AREA]
    return d_fric, d_damp


@njit(cache=True)
def rhs(t, y, params, dydt):
    """Right-hand side for the compiled integrator; ``params`` as :func:`make_params`."""
    bodies, points, joint_start, joints, record, dt, work, mon = params
    ax, ay, az = ground_acceleration(t, record, dt)
    _kinematics(y, bodies, work)
    d_fric, d_damp = _contacts(y, params, dydt, True, False)
    n_bodies = bodies.shape[0]
    acc = NB * n_bodies + 2 * points.shape[0]
    power = 0.0
    for b in range(n_bodies):
        o = NB * b
        R = work[b]
        m = bodies[b, B_MASS]
        it = bodies[b, B_IT]
        ia = bodies[b, B_IA]
        # the joints' sum first, then the weight: at rest this is exactly zero
        fx = R[W_F] - m * ax
        fy = R[W_F + 1] - m * ay
        fz = (R[W_F + 2] - bodies[b, B_WEIGHT]) - m * az
        vx, vy, vz = y[o + VX], y[o + VY], y[o + VZ]
        dydt[o + X] = vx
        dydt[o + Y] = vy
        dydt[o + Z] = vz
        dydt[o + VX] = fx / m
        dydt[o + VY] = fy / m
        dydt[o + VZ] = fz / m
        power -= m * (ax * vx + ay * vy + az * vz)
        qw, qx, qy, qz = y[o + QW], y[o + QX], y[o + QY], y[o + QZ]
        wx, wy, wz = y[o + WX], y[o + WY], y[o + WZ]
        dydt[o + QW] = -0.5 * (qx * wx + qy * wy + qz * wz)
        dydt[o + QX] = 0.5 * (qw * wx + qy * wz - qz * wy)
        dydt[o + QY] = 0.5 * (qw * wy + qz * wx - qx * wz)
        dydt[o + QZ] = 0.5 * (qw * wz + qx * wy - qy * wx)
        tx, ty, tz = R[W_T], R[W_T + 1], R[W_T + 2]
        bx = R[0] * tx + R[3] * ty + R[6] * tz  # torque in body axes
        by = R[1] * tx + R[4] * ty + R[7] * tz
        bz = R[2] * tx + R[5] * ty + R[8] * tz
        # Euler's equations with I_x = I_y = it, I_z = ia
        dydt[o + WX] = (bx + (it - ia) * wy * wz) / it
        dydt[o + WY] = (by + (ia - it) * wz * wx) / it
        dydt[o + WZ] = bz / ia
    dydt[acc + A_WORK] = power
    dydt[acc + A_FRICTION] = d_fric
    dydt[acc + A_DAMPING] = d_damp


@njit(cache=True)
def _events(t, y, params, g):
    """Per body: its tilt reaches the lying tilt; its centre of mass falls below the ground."""
    bodies = params[0]
    n_bodies = bodies.shape[0]
    for b in range(n_bodies):
        o = NB * b
        qw, qx, qy, qz = y[o + QW], y[o + QX], y[o + QY], y[o + QZ]
        r33 = 1.0 - 2.0 * (qx * qx + qy * qy) / (qw * qw + qx * qx + qy * qy + qz * qz)
        g[b] = bodies[b, B_COS_LIE] - r33
        g[n_bodies + b] = -y[o + Z]


@njit(cache=True)
def _integrate(params, t0, y0, t_end, t_out, y_out, event_direction, t_breaks, rtol, atol, max_step, h0):
    return dop853(rhs, _events, params, t0, y0, t_end, t_out, y_out, 0, event_direction,
                  t_breaks, rtol, atol, max_step, h0, MAX_STEPS)


@njit(cache=True)
def _integrate5(params, t0, y0, t_end, t_out, y_out, event_direction, t_breaks, rtol, atol, max_step, h0):
    return dopri5(rhs, _events, params, t0, y0, t_end, t_out, y_out, 0, event_direction,
                  t_breaks, rtol, atol, max_step, h0, MAX_STEPS)


@njit(cache=True)
def energy(y, params):
    """Kinetic + potential (weights) + elastic energy of the joints [M g L].

    Uses (and overwrites) the scratch and the monitor of ``params``.
    """
    bodies, points, joint_start, joints, record, dt, work, mon = params
    _kinematics(y, bodies, work)
    _contacts(y, params, y, False, True)
    e = 0.0
    for b in range(bodies.shape[0]):
        o = NB * b
        vx, vy, vz = y[o + VX], y[o + VY], y[o + VZ]
        wx, wy, wz = y[o + WX], y[o + WY], y[o + WZ]
        e += 0.5 * bodies[b, B_MASS] * (vx * vx + vy * vy + vz * vz)
        e += 0.5 * (bodies[b, B_IT] * (wx * wx + wy * wy) + bodies[b, B_IA] * wz * wz)
        e += bodies[b, B_WEIGHT] * y[o + Z]
        e += mon[b, M_ELASTIC]
    return e


@njit(cache=True)
def set_static_weights(y, params):
    """Set each body's weight to the net joint force on it in the state y (the rest state).

    The rest state is built with the penetrations of static equilibrium; the weights equal
    ``m g`` to round-off, and with them the right-hand side at rest is exactly zero.
    """
    bodies = params[0]
    work = params[6]
    _kinematics(y, bodies, work)
    _contacts(y, params, y, False, False)
    for b in range(bodies.shape[0]):
        bodies[b, B_WEIGHT] = work[b, W_F + 2]


@njit(cache=True)
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
def stands_for_good(y, params, energy_rest, barrier, critical):
    """Whether a column on still ground can no longer fall, its top's swing under way past its peak.

    The compliant counterpart of :func:`pipeline.dynamics.rigid.loop.stands_for_good`. With the
    ground still the energy (kinetic, weights, joints' springs) can only fall. Every body b is
    on the near side of the hill of the part of the column above its joint, which tips about
    that joint's rim (its tilt below ``critical[b]``), and the energy above the rest state is
    below ``barrier``, the lowest rise of the weights over which any such part tips. The top
    body's tilt must not be rising: its swing's peak is then booked.

    Parameters
    ----------
    y : float64[n]
        State.
    params : tuple
        :func:`make_params` (its scratch is overwritten).
    energy_rest : float
        Energy of the rest state [M g L] (``S_ENERGY_START`` of a run from rest).
    barrier : float
        The lowest overturning barrier [M g L].
    critical : float64[n_bodies]
        Critical tilt of the part above each body's joint [rad].
    """
    n_bodies = params[0].shape[0]
    for b in range(n_bodies):
        if tilt_and_rotation(y, b)[0] >= critical[b]:
            return False
    if energy(y, params) - energy_rest >= barrier:
        return False
    # the top axis a = R e_z turns at omega x a (ground frame): its tilt rises while a_z falls
    R = params[6][n_bodies - 1]  # the rotation and angular velocity energy() left in the scratch
    return R[W_OM] * R[5] - R[W_OM + 1] * R[2] >= 0.0


@njit(cache=True)
def _unwrap(previous, angle):
    """``angle`` shifted by a multiple of 2 pi to lie within pi of ``previous``."""
    return angle + 2.0 * math.pi * round((previous - angle) / (2.0 * math.pi))


@njit(cache=True)
def _on_rim(mon, joints, j):
    """Joint j rocks on its rim: its centre of pressure lies beyond ``J_RIM`` from the axis
    (only a rim point and its neighbours carry it), or it carries nothing (flight)."""
    if mon[j, M_NORMAL] <= 0.0:
        return True
    return _cop_radius(mon, j) >= joints[j, J_RIM]


@njit(cache=True)
def _cop_radius(mon, j):
    """Distance of joint j's centre of pressure from the axis of its upper body."""
    return math.sqrt(mon[j, M_COP_BX] ** 2 + mon[j, M_COP_BY] ** 2)


@njit(cache=True)
def _monitor(t, y, params, theta_commit, summary, body_stats, joint_stats, joint_committed, update):
    """Statistics of one monitor sample (if ``update``); returns the top body's tilt.

    Leaves the per-joint monitor of ``params`` filled for the history row.
    """
    _kinematics(y, params[0], params[6])
    _contacts(y, params, y, False, True)
    return update_statistics(t, y, params, theta_commit, summary, body_stats, joint_stats, joint_committed,
                             update)


@njit(cache=True)
def update_statistics(t, y, params, theta_commit, summary, body_stats, joint_stats, joint_committed, update):
    """The statistics of :func:`_monitor` from the per-joint monitor of ``params`` as filled.

    Reads the monitor's normal forces (whole and elastic), tangential resultant, centre of
    pressure in the upper body's axes and area in contact; returns the top body's tilt. The
    fixed-step integrator fills the monitor from its own step and calls this every step.
    """
    bodies, points, joint_start, joints, record, dt, work, mon = params
    n_bodies = bodies.shape[0]
    top = 0.0
    for b in range(n_bodies):
        tilt, rot = tilt_and_rotation(y, b)
        if update:
            body_stats[b, BS_ROTATION] = _unwrap(body_stats[b, BS_ROTATION], rot)
            if tilt > body_stats[b, BS_PEAK]:
                body_stats[b, BS_PEAK] = tilt
                body_stats[b, BS_PEAK_TIME] = t
        top = tilt
    if not update:
        return top
    if top > summary[S_PEAK_THETA]:
        summary[S_PEAK_THETA] = top
        summary[S_PEAK_TIME] = t
    for j in range(n_bodies):
        normal = mon[j, M_NORMAL]
        tangential = math.sqrt(mon[j, M_TX] ** 2 + mon[j, M_TY] ** 2)
        if normal < joint_stats[j, JS_MIN_NORMAL]:
            joint_stats[j, JS_MIN_NORMAL] = normal
        if normal <= 0.0 and math.isnan(joint_stats[j, JS_FLIGHT_TIME]):
            joint_stats[j, JS_FLIGHT_TIME] = t
        if mon[j, M_AREA] < joint_stats[j, JS_MIN_AREA]:
            joint_stats[j, JS_MIN_AREA] = mon[j, M_AREA]
        if normal > 0.0 and mon[j, M_NORMAL_EL] > 0.0:
            mu_mob = tangential / mon[j, M_NORMAL_EL]
            if mu_mob > joint_stats[j, JS_PEAK_MU]:
                joint_stats[j, JS_PEAK_MU] = mu_mob
            if mu_mob >= SLIDE_FRACTION * joints[j, J_MU] and math.isnan(joint_stats[j, JS_SLIDE_TIME]):
                joint_stats[j, JS_SLIDE_TIME] = t
        if _on_rim(mon, joints, j):
            joint_stats[j, JS_ON_RIM] = 1.0
            if math.isnan(joint_stats[j, JS_UPLIFT_TIME]):
                joint_stats[j, JS_UPLIFT_TIME] = t
        elif joint_stats[j, JS_ON_RIM] > 0.0 and _cop_radius(mon, j) < joints[j, J_LAND]:
            # back from the rim well into the base: a landing (the hysteresis keeps a column
            # rolling from one rim point to the next, whose centre of pressure grazes the
            # rim threshold between them, from counting landings)
            joint_stats[j, JS_RETURNS] += 1.0
            joint_stats[j, JS_ON_RIM] = 0.0
    if top <= theta_commit:
        # peaks before any final fall past theta_crit (the summary uses these if it overturns)
        joint_committed[:, :] = joint_stats
    return top


@njit(cache=True)
def _history_row(t, y, params, k, hist_y, hist_diag, hist_body, body_stats, y0):
    """Write history row k from the state y and the filled per-joint monitor."""
    bodies, points, joint_start, joints, record, dt, work, mon = params
    n_bodies = bodies.shape[0]
    nb = NB * n_bodies
    tail = nb + 2 * points.shape[0]
    hist_y[k, :nb] = y[:nb]
    hist_y[k, nb:] = y[tail:]
    normal = mon[0, M_NORMAL]
    tangential = math.sqrt(mon[0, M_TX] ** 2 + mon[0, M_TY] ** 2)
    ax, ay, az = ground_acceleration(t, record, dt)
    hist_diag[k, D_NORMAL] = normal
    hist_diag[k, D_TANGENTIAL] = tangential
    elastic = mon[0, M_NORMAL_EL]
    hist_diag[k, D_MU] = tangential / elastic if normal > 0.0 and elastic > 0.0 else math.nan
    hist_diag[k, D_COP_X] = mon[0, M_COP_X] if normal > 0.0 else math.nan
    hist_diag[k, D_COP_Y] = mon[0, M_COP_Y] if normal > 0.0 else math.nan
    hist_diag[k, D_AREA] = mon[0, M_AREA]
    hist_diag[k, D_AX] = ax
    hist_diag[k, D_AY] = ay
    hist_diag[k, D_AZ] = az
    hist_diag[k, D_ON_RIM] = 1.0 if _on_rim(mon, joints, 0) else 0.0
    for b in range(n_bodies):
        o = NB * b
        tilt, rot = tilt_and_rotation(y, b)
        hist_body[k, b, H_DX] = y[o + X] - y0[o + X]
        hist_body[k, b, H_DY] = y[o + Y] - y0[o + Y]
        hist_body[k, b, H_TILT] = tilt
        hist_body[k, b, H_ROT] = _unwrap(body_stats[b, BS_ROTATION], rot)
    hist_diag[k, D_ENERGY] = energy(y, params)  # last: it reuses the monitor


@njit(cache=True)
def start_statistics(t0, y0, params, theta_commit, hist_y, hist_diag, hist_body, summary, body_stats, joint_stats,
                     joint_committed):
    """Initialise the summary and statistics of a run from its initial state y0 at t0, and its
    first history row (if any): what every integrator of this state layout does first."""
    summary[:] = 0.0
    summary[S_OVERTURN_TIME] = math.nan
    summary[S_OVERTURN_BODY] = -1.0
    body_stats[:, :] = 0.0
    joint_stats[:, :] = 0.0
    joint_stats[:, JS_UPLIFT_TIME] = math.nan
    joint_stats[:, JS_SLIDE_TIME] = math.nan
    joint_stats[:, JS_FLIGHT_TIME] = math.nan
    joint_stats[:, JS_MIN_NORMAL] = math.inf
    joint_stats[:, JS_MIN_AREA] = math.inf
    for b in range(params[0].shape[0]):
        body_stats[b, BS_ROTATION] = tilt_and_rotation(y0, b)[1]
    summary[S_ENERGY_START] = energy(y0, params)
    _monitor(t0, y0, params, theta_commit, summary, body_stats, joint_stats, joint_committed, True)
    joint_committed[:, :] = joint_stats
    if hist_y.shape[0] > 0:
        _history_row(t0, y0, params, 0, hist_y, hist_diag, hist_body, body_stats, y0)


@njit(cache=True, nogil=True)
def run(params, y0, t_mon, stride, t_breaks, rtol, atol, max_step, event_direction, theta_commit,
        hist_y, hist_diag, hist_body, summary, body_stats, joint_stats, joint_committed, y_end,
        k_decide, barrier, critical, method=METHOD_DOPRI5):
    """Integrate from rest (or y0) up to ``t_mon[-1]``, monitoring every sample of ``t_mon``.

    From sample ``k_decide`` on (the end of the record and its tail) the run stops as soon as
    the column stands for good (:func:`stands_for_good`, checked after every integrator call);
    if it has not by ``t_mon[-1]`` (the settle limit) it is undecided (``S_UNDECIDED``).

    Parameters
    ----------
    params : tuple
        From :func:`make_params` (dimensionless).
    y0 : float64[n]
        Initial state.
    t_mon : float64[m]
        Monitor times from 0 [tau]; the peaks, landings, uplift and friction statistics
        are taken on them (the steps follow the contact dynamics, the monitor only reads
        the dense output).
    stride : int
        Every ``stride``-th monitor sample is a history row.
    t_breaks : float64[b]
        Sample times of the record (no step crosses them).
    rtol : float
    atol : float64[n]
    event_direction : float64[2 N]
        +1 for every event (lying down, falling below the ground).
    theta_commit : float
        Tilt of the top body below which the joint statistics are committed (the values
        kept if it overturns) [rad].
    hist_y, hist_diag, hist_body : arrays
        History rows (filled for the rows reached; the rows after overturning hold the
        last state): states without shear (:func:`kept_size`), base-joint diagnostics
        (``D_*``), per-body displacement, tilt and rotation (``H_*``).
    summary, body_stats, joint_stats, joint_committed : arrays
        Filled (``S_*``, ``BS_*``, ``JS_*``).
    y_end : float64[n]
        The final state.
    k_decide : int
        Sample at which the record and its tail end.
    barrier, critical : float, float64[n_bodies]
        Of :func:`stands_for_good` [M g L], [rad].
    method : int
        ``METHOD_DOPRI5`` (default: 2.9x fewer right-hand sides on a three-drum stack at
        equal tolerances, :mod:`pipeline.dynamics.integrators.dopri5`) or ``METHOD_DOP853`` (the
        reference it was measured against).
    """
    bodies = params[0]
    n_bodies = bodies.shape[0]
    n = y0.shape[0]
    m = t_mon.shape[0]
    n_hist = hist_y.shape[0]
    y = y0.copy()
    start_statistics(t_mon[0], y, params, theta_commit, hist_y, hist_diag, hist_body, summary, body_stats,
                     joint_stats, joint_committed)
    scratch = np.empty((CHUNK, n))
    t = t_mon[0]
    h = 0.0
    i = 1
    ib = 0
    nb = t_breaks.shape[0]
    while i < m:
        stop = min(i + CHUNK, m)
        while ib < nb and t_breaks[ib] <= t:
            ib += 1
        if method == METHOD_DOP853:
            res = _integrate(params, t, y, t_mon[stop - 1], t_mon[i:stop], scratch[:stop - i],
                             event_direction, t_breaks[ib:], rtol, atol, max_step, h)
        else:
            res = _integrate5(params, t, y, t_mon[stop - 1], t_mon[i:stop], scratch[:stop - i],
                              event_direction, t_breaks[ib:], rtol, atol, max_step, h)
        summary[S_NFEV] += res.nfev
        summary[S_STEPS] += res.n_accepted
        summary[S_REJECTED] += res.n_rejected
        summary[S_CALLS] += 1
        for r in range(res.out_next):
            k = i + r
            _monitor(t_mon[k], scratch[r], params, theta_commit, summary, body_stats, joint_stats,
                     joint_committed, True)
            if k % stride == 0 and k // stride < n_hist:
                _history_row(t_mon[k], scratch[r], params, k // stride, hist_y, hist_diag, hist_body,
                             body_stats, y0)
        i += res.out_next
        y[:] = res.y
        t = res.t
        h = res.h_next
        if res.status < 0:
            summary[S_STATUS] = res.status
            break
        if res.status == 1:  # a body lies down or falls below the ground: the column is down
            b = res.event_index % n_bodies
            summary[S_OVERTURN_TIME] = t
            summary[S_OVERTURN_BODY] = b
            if res.event_index >= n_bodies:
                summary[S_STATUS] = STATUS_COLLAPSED
            _monitor(t, y, params, theta_commit, summary, body_stats, joint_stats, joint_committed, True)
            for k in range(i, m):  # frozen from here on
                if k % stride == 0 and k // stride < n_hist:
                    _monitor(t_mon[k], y, params, theta_commit, summary, body_stats, joint_stats,
                             joint_committed, False)
                    _history_row(t_mon[k], y, params, k // stride, hist_y, hist_diag, hist_body,
                                 body_stats, y0)
            break
        if i > k_decide and stands_for_good(y, params, summary[S_ENERGY_START], barrier, critical):
            break
    if (summary[S_STATUS] >= 0 and math.isnan(summary[S_OVERTURN_TIME])
            and not stands_for_good(y, params, summary[S_ENERGY_START], barrier, critical)):
        summary[S_UNDECIDED] = 1.0
    summary[S_END_TIME] = t
    summary[S_ENERGY_END] = energy(y, params)
    y_end[:] = y


@njit(cache=True)
def dislocations(y, params, out):
    """Relative position of each bed joint's upper drum on the lower one, in the lower frame.

    ``out[j]`` (j >= 1; row 0 is the base on the ground): slip of the upper base centre from
    the lower top centre [L] (x, y), relative twist about the lower axis [rad], and the
    largest opening of the joint, the widest gap at a contact point [L].
    """
    bodies, points, joint_start, joints, record, dt, work, mon = params
    _kinematics(y, bodies, work)
    for j in range(bodies.shape[0]):
        u = NB * j
        Ru = work[j]
        zc = bodies[j, B_ZC]
        bx = y[u + X] - Ru[2] * zc  # base centre of the upper body
        by = y[u + Y] - Ru[5] * zc
        bz = y[u + Z] - Ru[8] * zc
        if j == 0:
            Rl = np.eye(3).ravel()
            ox, oy, oz = 0.0, 0.0, 0.0
        else:
            lo = NB * (j - 1)
            Rl = work[j - 1, :9]
            h = bodies[j - 1, B_TOP] - bodies[j - 1, B_ZC]
            ox = y[lo + X] + Rl[2] * h
            oy = y[lo + Y] + Rl[5] * h
            oz = y[lo + Z] + Rl[8] * h
        dx, dy, dz = bx - ox, by - oy, bz - oz
        out[j, 0] = Rl[0] * dx + Rl[3] * dy + Rl[6] * dz
        out[j, 1] = Rl[1] * dx + Rl[4] * dy + Rl[7] * dz
        # relative rotation Rl^T Ru: its twist about z
        r11 = Rl[0] * Ru[0] + Rl[3] * Ru[3] + Rl[6] * Ru[6]
        r12 = Rl[0] * Ru[1] + Rl[3] * Ru[4] + Rl[6] * Ru[7]
        r21 = Rl[1] * Ru[0] + Rl[4] * Ru[3] + Rl[7] * Ru[6]
        r22 = Rl[1] * Ru[1] + Rl[4] * Ru[4] + Rl[7] * Ru[7]
        out[j, 2] = math.atan2(r21 - r12, r11 + r22)
        gap = 0.0
        for p in range(joint_start[j], joint_start[j + 1]):
            d = _point_geometry(y, p, j, params)[8]
            if -d > gap:
                gap = -d
        out[j, 3] = gap


def make_params(bodies, points, joint_start, joints, record, dt):
    """Pack the kernel parameters, with fresh scratch arrays (one set per simulation)."""
    n_bodies = bodies.shape[0]
    return (np.ascontiguousarray(bodies, dtype=np.float64), np.ascontiguousarray(points, dtype=np.float64),
            np.ascontiguousarray(joint_start, dtype=np.int64), np.ascontiguousarray(joints, dtype=np.float64),
            np.ascontiguousarray(record, dtype=np.float64), float(dt),
            np.zeros((n_bodies, N_WORK)), np.zeros((n_bodies, N_MON)))


def rest_state(params):
    """The state of static equilibrium, upright and still; sets the bodies' weights to it.

    Every joint is compressed uniformly by the weight above it, ``d = W / (k_n A)``; the
    weights are then replaced by the joints' net forces in that state
    (:func:`set_static_weights`), so that the right-hand side there is exactly zero.
    """
    bodies, points, joint_start, joints = params[:4]
    n_bodies = bodies.shape[0]
    y = np.zeros(state_size(n_bodies, points.shape[0]))
    load = np.cumsum(bodies[::-1, B_MASS])[::-1]  # weight on each joint
    base = 0.0
    for b in range(n_bodies):
        if b > 0:
            base += bodies[b - 1, B_TOP]
        base -= load[b] / (joints[b, J_KN] * joints[b, J_AREA])
        y[NB * b + Z] = base + bodies[b, B_ZC]
        y[NB * b + QW] = 1.0
    set_static_weights(y, params)
    return y
