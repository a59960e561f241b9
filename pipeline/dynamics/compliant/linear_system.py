"""The joints' linear algebra of the fixed-step integrator (:mod:`pipeline.dynamics.compliant.semi_implicit`).

A joint's dashpots (or springs) act on the relative velocity (displacement) of its points,
which is linear in the two bodies' velocities; summed over the points, a joint's 6 x 6 matrix
needs only the sums and first and second moments of the points' lever arms
(:func:`joint_matrix`, :func:`joint_matrix_z`). A joint couples two neighbouring bodies, so
``M + h C`` of a stack is block-tridiagonal (:func:`assemble_system`) and is solved by a block
Cholesky factorisation (:func:`block_tridiagonal_solve`). The same matrices with the springs
give the stiffest mode of the stack, which bounds the fixed step (:func:`stiffest_frequency`).

Kernel layer: dimensionless floats and arrays as in :mod:`pipeline.dynamics.compliant.stack`.
"""

import math

import numpy as np
from numba import njit

from pipeline.dynamics.compliant import stack as sk

__all__ = ["block_tridiagonal_solve", "joint_matrix", "joint_matrix_z", "turned_joint_matrix_z", "add_moments",
           "assemble_system", "stiffest_frequency"]


@njit(cache=True)
def _cholesky6(a, b, out):
    """Lower Cholesky factor ``out[b]`` of the symmetric positive definite 6 x 6 matrix ``a``."""
    for i in range(6):
        for j in range(i + 1):
            s = a[i, j]
            for k in range(j):
                s -= out[b, i, k] * out[b, j, k]
            if i == j:
                out[b, i, i] = math.sqrt(s)
            else:
                out[b, i, j] = s / out[b, j, j]
        for j in range(i + 1, 6):
            out[b, i, j] = 0.0


@njit(cache=True)
def block_tridiagonal_solve(diag, off, rhs, fac, coup, tmp):
    """Solve a symmetric positive definite block-tridiagonal system in place.

    Block Cholesky: ``L_b L_b^T = D_b - C_b C_b^T`` with ``C_b = O_b L_{b-1}^{-T}``, then
    forward and back substitution.

    Parameters
    ----------
    diag : float64[n, 6, 6]
        Diagonal blocks (body b).
    off : float64[n, 6, 6]
        ``off[b]`` couples body b (rows) with body b - 1 (columns); ``off[0]`` unused.
    rhs : float64[n, 6]
        Right-hand side, overwritten by the solution.
    fac, coup : float64[n, 6, 6]
        Scratch: Cholesky factors of the Schur complements and the coupling factors.
    tmp : float64[6, 6]
        Scratch.
    """
    n = diag.shape[0]
    for b in range(n):
        if b == 0:
            _cholesky6(diag[0], 0, fac)
        else:
            # C_b: row i solves L_{b-1} x = O_b[i, :]
            for i in range(6):
                for k in range(6):
                    s = off[b, i, k]
                    for m in range(k):
                        s -= fac[b - 1, k, m] * coup[b, i, m]
                    coup[b, i, k] = s / fac[b - 1, k, k]
            for i in range(6):
                for j in range(i + 1):
                    s = diag[b, i, j]
                    for k in range(6):
                        s -= coup[b, i, k] * coup[b, j, k]
                    tmp[i, j] = s
                    tmp[j, i] = s
            _cholesky6(tmp, b, fac)
            for i in range(6):
                s = rhs[b, i]
                for k in range(6):
                    s -= coup[b, i, k] * rhs[b - 1, k]
                rhs[b, i] = s
        for i in range(6):  # L_b w = rhs_b
            s = rhs[b, i]
            for k in range(i):
                s -= fac[b, i, k] * rhs[b, k]
            rhs[b, i] = s / fac[b, i, i]
    for b in range(n - 1, -1, -1):
        if b < n - 1:
            for i in range(6):
                s = rhs[b, i]
                for k in range(6):
                    s -= coup[b + 1, k, i] * rhs[b + 1, k]
                rhs[b, i] = s
        for i in range(5, -1, -1):  # L_b^T x = w
            s = rhs[b, i]
            for k in range(i + 1, 6):
                s -= fac[b, k, i] * rhs[b, k]
            rhs[b, i] = s / fac[b, i, i]


@njit(cache=True)
def joint_matrix(mom, nx, ny, nz, out):
    """Dashpot matrix of one joint in the velocities (a, b) of the upper body's centre.

    The relative velocity at a point with lever arm rho from the upper centre is
    ``g = a + b x rho`` and its dashpot force on the upper body ``-D g`` with
    ``D = alpha I + beta n n^T`` (alpha the shear coefficient, alpha + beta the normal one, n
    the normal of the face below). Summed over the points, ``sum H^T D H`` (H = [I, -[rho]x])
    needs only the moments ``mom``: for alpha and for beta, the sum, the first moment (3) and
    the second moment (xx, yy, zz, xy, xz, yz) of the lever arms.

    Parameters
    ----------
    mom : float64[20]
        ``[S_a, S_a rho (3), S_a rho rho (6), S_b, S_b rho (3), S_b rho rho (6)]``.
    nx, ny, nz : float
        Unit normal of the face below (ground frame).
    out : float64[6, 6]
        The matrix, in the order (a, b).
    """
    sa = mom[0]
    ax, ay, az = mom[1], mom[2], mom[3]
    axx, ayy, azz, axy, axz, ayz = mom[4], mom[5], mom[6], mom[7], mom[8], mom[9]
    sb = mom[10]
    bx, by, bz = mom[11], mom[12], mom[13]
    bxx, byy, bzz, bxy, bxz, byz = mom[14], mom[15], mom[16], mom[17], mom[18], mom[19]
    n = (nx, ny, nz)
    # A11 = S_a I + S_b n n^T
    for i in range(3):
        for j in range(3):
            out[i, j] = sb * n[i] * n[j]
        out[i, i] += sa
    # A12 = -([S_a rho]x + n n^T [S_b rho]x)
    # [v]x = [[0, -vz, vy], [vz, 0, -vx], [-vy, vx, 0]]
    cx = ((0.0, -bz, by), (bz, 0.0, -bx), (-by, bx, 0.0))
    for i in range(3):
        for j in range(3):
            nc = n[0] * cx[0][j] + n[1] * cx[1][j] + n[2] * cx[2][j]  # (n^T [S_b rho]x)_j
            out[i, 3 + j] = -(n[i] * nc)
    out[0, 4] += az
    out[0, 5] -= ay
    out[1, 3] -= az
    out[1, 5] += ax
    out[2, 3] += ay
    out[2, 4] -= ax
    for i in range(3):
        for j in range(3):
            out[3 + j, i] = out[i, 3 + j]
    # A22 = tr(Sa_rr) I - Sa_rr + [n]x Sb_rr [n]x^T
    tr = axx + ayy + azz
    sarr = ((axx, axy, axz), (axy, ayy, ayz), (axz, ayz, azz))
    sbrr = ((bxx, bxy, bxz), (bxy, byy, byz), (bxz, byz, bzz))
    nxm = ((0.0, -nz, ny), (nz, 0.0, -nx), (-ny, nx, 0.0))
    for i in range(3):
        for j in range(3):
            s = 0.0
            for k in range(3):
                for m in range(3):
                    s += nxm[i][k] * sbrr[k][m] * nxm[j][m]
            out[3 + i, 3 + j] = s - sarr[i][j]
        out[3 + i, 3 + i] += tr


@njit(cache=True)
def _joint_matrix_z_entries(sa, ax, ay, az, axx, ayy, azz, axy, axz, ayz, sb, bx, by, bxx, byy, bxy):
    """The entries of :func:`joint_matrix` with the normal n = e_z (a joint in the frame of its face
    below) that are not zero or repeated, from the moments (``mom`` without its zeros):
    ``(k00, k22, k04, k05, k13, k15, k23, k24, k33, k44, k55, k34, k35, k45)`` with k11 = k00 and
    the matrix symmetric. With n = e_z, ``[n]x M [n]x^T = [[M_yy, -M_xy, 0], [-M_xy, M_xx, 0], [0, 0, 0]]``.
    """
    tr = axx + ayy + azz
    # A12 = -([S_a rho]x + e_z e_z^T [S_b rho]x)
    return (sa, sa + sb, az, -ay, -az, ax, ay + by, -(ax + bx),
            tr - axx + byy, tr - ayy + bxx, tr - azz, -axy - bxy, -axz, -ayz)


@njit(cache=True)
def joint_matrix_z(sa, ax, ay, az, axx, ayy, azz, axy, axz, ayz, sb, bx, by, bxx, byy, bxy, out):
    """:func:`joint_matrix` with the normal n = e_z (a joint in the frame of its face below),
    written out (:func:`_joint_matrix_z_entries`), from the moments of ``mom`` that are not zero
    with n = e_z (no S_b rho_z term)."""
    (k00, k22, k04, k05, k13, k15, k23, k24, k33, k44, k55, k34, k35, k45) = _joint_matrix_z_entries(
        sa, ax, ay, az, axx, ayy, azz, axy, axz, ayz, sb, bx, by, bxx, byy, bxy)
    for i in range(6):
        for k in range(6):
            out[i, k] = 0.0
    out[0, 0] = out[1, 1] = k00
    out[2, 2] = k22
    out[0, 4] = out[4, 0] = k04
    out[0, 5] = out[5, 0] = k05
    out[1, 3] = out[3, 1] = k13
    out[1, 5] = out[5, 1] = k15
    out[2, 3] = out[3, 2] = k23
    out[2, 4] = out[4, 2] = k24
    out[3, 3] = k33
    out[4, 4] = k44
    out[5, 5] = k55
    out[3, 4] = out[4, 3] = k34
    out[3, 5] = out[5, 3] = k35
    out[4, 5] = out[5, 4] = k45


@njit(cache=True)
def _row(R, i, x, y, z):
    """Row i of the 3 x 3 matrix R (row-major) times (x, y, z)."""
    return R[3 * i] * x + R[3 * i + 1] * y + R[3 * i + 2] * z


@njit(cache=True)
def _turn_block(R, k00, k01, k02, k10, k11, k12, k20, k21, k22, out, r0, c0, symmetric):
    """``out[r0:r0 + 3, c0:c0 + 3] = R K R^T`` for the 3 x 3 block K (row-major arguments), and the
    mirror block ``out[c0:c0 + 3, r0:r0 + 3]`` its transpose. Summed as ``(R K) R^T``, each entry
    in the order of ``_row``; a symmetric block takes its lower triangle (i >= k) for both halves."""
    t00, t01, t02 = _row(R, 0, k00, k10, k20), _row(R, 0, k01, k11, k21), _row(R, 0, k02, k12, k22)
    t10, t11, t12 = _row(R, 1, k00, k10, k20), _row(R, 1, k01, k11, k21), _row(R, 1, k02, k12, k22)
    t20, t21, t22 = _row(R, 2, k00, k10, k20), _row(R, 2, k01, k11, k21), _row(R, 2, k02, k12, k22)
    v00, v10, v20 = _row(R, 0, t00, t01, t02), _row(R, 0, t10, t11, t12), _row(R, 0, t20, t21, t22)
    v11, v21, v22 = _row(R, 1, t10, t11, t12), _row(R, 1, t20, t21, t22), _row(R, 2, t20, t21, t22)
    if symmetric:
        v01, v02, v12 = v10, v20, v21
    else:
        v01, v02, v12 = _row(R, 1, t00, t01, t02), _row(R, 2, t00, t01, t02), _row(R, 2, t10, t11, t12)
    out[r0, c0], out[r0, c0 + 1], out[r0, c0 + 2] = v00, v01, v02
    out[r0 + 1, c0], out[r0 + 1, c0 + 1], out[r0 + 1, c0 + 2] = v10, v11, v12
    out[r0 + 2, c0], out[r0 + 2, c0 + 1], out[r0 + 2, c0 + 2] = v20, v21, v22
    if not symmetric:
        out[c0, r0], out[c0 + 1, r0], out[c0 + 2, r0] = v00, v01, v02
        out[c0, r0 + 1], out[c0 + 1, r0 + 1], out[c0 + 2, r0 + 1] = v10, v11, v12
        out[c0, r0 + 2], out[c0 + 1, r0 + 2], out[c0 + 2, r0 + 2] = v20, v21, v22


@njit(cache=True)
def turned_joint_matrix_z(sa, ax, ay, az, axx, ayy, azz, axy, axz, ayz, sb, bx, by, bxx, byy, bxy, R, out):
    """:func:`joint_matrix_z` of these moments turned from the frame of the face below to the ground's:
    ``out = T K T^T`` with T = diag(R, R), R that face's rotation (9, row-major), block by block
    ``R K_b R^T`` (a joint on the ground takes :func:`joint_matrix_z` itself)."""
    (k00, k22, k04, k05, k13, k15, k23, k24, k33, k44, k55, k34, k35, k45) = _joint_matrix_z_entries(
        sa, ax, ay, az, axx, ayy, azz, axy, axz, ayz, sb, bx, by, bxx, byy, bxy)
    _turn_block(R, k00, 0.0, 0.0, 0.0, k00, 0.0, 0.0, 0.0, k22, out, 0, 0, True)
    _turn_block(R, 0.0, k04, k05, k13, 0.0, k15, k23, k24, 0.0, out, 0, 3, False)
    _turn_block(R, k33, k34, k35, k34, k44, k45, k35, k45, k55, out, 3, 3, True)


@njit(cache=True)
def _weighted_moments(mom, o, w, rx, ry, rz):
    """Add weight w's sum, first and second moments of (rx, ry, rz) to ``mom[o:o + 10]``."""
    mom[o] += w
    mom[o + 1] += w * rx
    mom[o + 2] += w * ry
    mom[o + 3] += w * rz
    mom[o + 4] += w * rx * rx
    mom[o + 5] += w * ry * ry
    mom[o + 6] += w * rz * rz
    mom[o + 7] += w * rx * ry
    mom[o + 8] += w * rx * rz
    mom[o + 9] += w * ry * rz


@njit(cache=True)
def add_moments(mom, alpha, beta, rx, ry, rz):
    """A point's shear (alpha) and normal-less-shear (beta) dashpot weights into the moments."""
    _weighted_moments(mom, 0, alpha, rx, ry, rz)
    _weighted_moments(mom, 10, beta, rx, ry, rz)


@njit(cache=True)
def assemble_system(y, bodies, joint_matrices, h, work, diag, off):
    """``M + h C`` as blocks (ground-frame velocities and angular velocities of each body).

    ``joint_matrices[j]``: the dashpot matrix of joint j (:func:`joint_matrix`); ``work``
    holds each body's rotation matrix (:func:`pipeline.dynamics.compliant.stack._kinematics`).
    """
    n = bodies.shape[0]
    for b in range(n):
        R = work[b]
        m, it, ia = bodies[b, sk.B_MASS], bodies[b, sk.B_IT], bodies[b, sk.B_IA]
        for i in range(6):
            for k in range(6):
                diag[b, i, k] = 0.0
                off[b, i, k] = 0.0
        diag[b, 0, 0] = m
        diag[b, 1, 1] = m
        diag[b, 2, 2] = m
        # inertia in the ground frame: it I + (ia - it) a a^T, a the body axis
        a = (R[2], R[5], R[8])
        for i in range(3):
            for k in range(3):
                diag[b, 3 + i, 3 + k] = (ia - it) * a[i] * a[k]
            diag[b, 3 + i, 3 + i] += it
    for j in range(n):
        K = joint_matrices[j]
        for i in range(6):
            for k in range(6):
                diag[j, i, k] += h * K[i, k]
        if j == 0:
            continue
        # off = h K E, lower diagonal += h E^T K E, with E = [[-I, [e]x], [0, -I]] written out
        o, lo = sk.NB * j, sk.NB * (j - 1)
        ex = y[o + sk.X] - y[lo + sk.X]
        ey = y[o + sk.Y] - y[lo + sk.Y]
        ez = y[o + sk.Z] - y[lo + sk.Z]
        KE = off[j]
        for i in range(6):
            k0, k1, k2 = K[i, 0], K[i, 1], K[i, 2]
            KE[i, 0] = -h * k0
            KE[i, 1] = -h * k1
            KE[i, 2] = -h * k2
            # row of K[:, :3] [e]x, less K[:, 3:]
            KE[i, 3] = h * (k1 * ez - k2 * ey - K[i, 3])
            KE[i, 4] = h * (k2 * ex - k0 * ez - K[i, 4])
            KE[i, 5] = h * (k0 * ey - k1 * ex - K[i, 5])
        D = diag[j - 1]
        for k in range(6):
            a0, a1, a2 = KE[0, k], KE[1, k], KE[2, k]
            D[0, k] -= a0
            D[1, k] -= a1
            D[2, k] -= a2
            # -[e]x (KE)[:3] - (KE)[3:]
            D[3, k] -= (ey * a2 - ez * a1) + KE[3, k]
            D[4, k] -= (ez * a0 - ex * a2) + KE[4, k]
            D[5, k] -= (ex * a1 - ey * a0) + KE[5, k]


def stiffest_frequency(params, y):
    """Highest angular frequency of the joints' springs, every point pressed [1/tau].

    The generalised eigenvalue problem ``K x = omega^2 M x`` of the stack in the state y (the
    rest state), with every contact point carrying its normal spring ``k_n A`` and its shear
    spring ``k_s A`` (whole faces in contact: the stiffest the joints get). Symplectic Euler
    is stable on it for ``h < 2 / omega``.
    """
    from scipy.linalg import eigh

    bodies, points, joint_start, joints = params[:4]
    work = params[6]
    n = bodies.shape[0]
    sk._kinematics(y, bodies, work)
    mats = np.zeros((n, 6, 6))
    mom = np.zeros(20)
    for j in range(n):
        mom[:] = 0.0
        kn, ks = joints[j, sk.J_KN], joints[j, sk.J_KS]
        for p in range(joint_start[j], joint_start[j + 1]):
            geo = sk._point_geometry(y, p, j, params)
            area = points[p, sk.P_AREA]
            add_moments(mom, ks * area, (kn - ks) * area, geo[0], geo[1], geo[2])
        R = work[j - 1] if j > 0 else np.array([0, 0, 0, 0, 0, 0, 0, 0, 1.0])
        joint_matrix(mom, R[2], R[5], R[8], mats[j])
    diag = np.zeros((n, 6, 6))
    off = np.zeros((n, 6, 6))
    # with h = 1 the assembled blocks are M + K, without joints M alone: K is their difference
    assemble_system(y, bodies, mats, 1.0, work, diag, off)
    mass = np.zeros((n, 6, 6))
    assemble_system(y, bodies, np.zeros((n, 6, 6)), 1.0, work, mass, np.zeros((n, 6, 6)))
    K = np.zeros((6 * n, 6 * n))
    M = np.zeros((6 * n, 6 * n))
    for b in range(n):
        M[6 * b:6 * b + 6, 6 * b:6 * b + 6] = mass[b]
        K[6 * b:6 * b + 6, 6 * b:6 * b + 6] = diag[b] - mass[b]
        if b > 0:
            K[6 * b:6 * b + 6, 6 * (b - 1):6 * b] = off[b]
            K[6 * (b - 1):6 * b, 6 * b:6 * b + 6] = off[b].T
    values = eigh(0.5 * (K + K.T), M, eigvals_only=True)
    return math.sqrt(max(values.max(), 0.0))

