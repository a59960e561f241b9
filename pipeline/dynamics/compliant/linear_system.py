"""The joints' linear algebra of the fixed-step integrator (:mod:`pipeline.dynamics.compliant.semi_implicit`).

A joint's dashpots (or springs) act on the relative velocity (displacement) of its points,
which is linear in its two bodies' velocities; summed over the points, a joint's 6 x 6 matrix
needs only the sums and first and second moments of the points' lever arms
(:func:`joint_matrix`, :func:`joint_matrix_z`). A joint couples its two bodies, so ``M + h C``
of an assembly is sparse in 6 x 6 blocks with the joints' pattern (:func:`assemble_system`);
it is solved by a block Cholesky factorisation in a fixed elimination order
(:func:`sparse_block_solve`, its pattern from :func:`elimination`): a column's chain of drums
eliminated from the ground up into its capital, then the capitals and the epistyle blocks
along the row, which fills in nothing, so the work is linear in the number of bodies (for a
single column it is the block-tridiagonal solve). The same matrices with the springs give the
stiffest mode of the assembly, which bounds the fixed step (:func:`stiffest_frequency`).

Kernel layer: dimensionless floats and arrays as in :mod:`pipeline.dynamics.compliant.layout`.
"""

import math

import numpy as np
from numba import njit

from pipeline.dynamics.compliant import assembly as sk
from pipeline.dynamics.compliant.layout import B_IX, B_IY, B_IZ, B_MASS, GROUND, J_KN, J_KS, J_LOWER, J_UPPER, NB, \
    P_AREA
from pipeline.dynamics.compliant.unsigned import ix

__all__ = ["sparse_block_solve", "elimination", "joint_matrix", "joint_matrix_z", "turned_joint_matrix_z",
           "add_moments", "assemble_system", "stiffest_frequency", "stiffest_mode", "spring_matrices"]


@njit(cache=True, inline="always")
def _cholesky6(a, n):
    """Lower Cholesky factor of the symmetric positive definite 6 x 6 matrix ``a[n]``, in place (its
    lower triangle is read)."""
    for i in range(6):
        for j in range(i + 1):
            s = a[n, i, j]
            for k in range(j):
                s -= a[n, i, k] * a[n, j, k]
            if i == j:
                a[n, i, i] = math.sqrt(s)
            else:
                a[n, i, j] = s / a[n, j, j]
        for j in range(i + 1, 6):
            a[n, i, j] = 0.0


def elimination(n_bodies, lowers, uppers, order, interleave=True):
    """The static pattern of a block Cholesky factorisation of an assembly's joints.

    Parameters
    ----------
    n_bodies : int
    lowers, uppers : sequence of int
        Each joint's lower body (-1: the ground, which couples nothing) and upper body.
    order : sequence of int
        The bodies in elimination order.
    interleave : bool
        Run the eliminations that do not wait for each other side by side (:func:`_interleaved`):
        the same operations on every block in the same sequence, so the same factors and solution
        to the bit, in another order of independent work. False: the eliminations one by one in
        ``order``.

    Returns
    -------
    tuple of numpy.ndarray
        ``(order, position, edges, down_start, down, up_start, up, update_start, updates,
        joint_edge)``: ``order`` the bodies by position (the order of the work), ``position`` its
        inverse; ``edges[e] = (row, col)`` positions with row > col (the joints' couplings
        and any fill the order makes); ``down[down_start[k]:down_start[k + 1]]`` the edges below
        position k (col k), ``up[...]`` those left of it (row k); ``updates[...]`` for the
        elimination of k, rows ``(e1, e2, target)``: subtract ``C_e1 C_e2^T`` from edge
        ``target``, or from the diagonal block of e1's row when ``target = -1`` (then e1 = e2);
        ``joint_edge[j]`` the edge of joint j (-1 on the ground).
    """
    pairs = [(a, b) for a, b in zip(lowers, uppers) if a != GROUND]
    order = np.asarray(order, dtype=np.int64)
    if sorted(order.tolist()) != list(range(n_bodies)):
        raise ValueError("the elimination order must name every body once")
    position = np.empty(n_bodies, dtype=np.int64)
    position[order] = np.arange(n_bodies)
    adjacent = [set() for _ in range(n_bodies)]  # by position
    for a, b in pairs:
        pa, pb = position[a], position[b]
        if pa == pb:
            raise ValueError(f"a joint couples body {a} with itself")
        adjacent[pa].add(pb)
        adjacent[pb].add(pa)
    edges, index = [], {}

    def edge(r, c):
        if (r, c) not in index:
            index[(r, c)] = len(edges)
            edges.append((r, c))
        return index[(r, c)]

    for k in range(n_bodies):  # the couplings, then the fill of each elimination in turn
        for r in sorted(adjacent[k]):
            if r > k:
                edge(r, k)
    updates_by = []
    for k in range(n_bodies):
        later = sorted(r for r in adjacent[k] if r > k)
        rows = []
        for i, r1 in enumerate(later):
            for r2 in later[:i + 1]:
                if r1 == r2:
                    rows.append((edge(r1, k), edge(r1, k), -1))
                else:  # fill: r1 and r2 become neighbours
                    adjacent[r1].add(r2)
                    adjacent[r2].add(r1)
                    rows.append((edge(r1, k), edge(r2, k), edge(r1, r2)))
        updates_by.append(rows)
    down = [[e for e, (r, c) in enumerate(edges) if c == k] for k in range(n_bodies)]
    up = [[e for e, (r, c) in enumerate(edges) if r == k] for k in range(n_bodies)]
    # the work in the order it is done: position k does the elimination of step[k] of the sequence above
    step = _interleaved(n_bodies, edges, updates_by) if interleave else list(range(n_bodies))
    moved = np.empty(n_bodies, dtype=np.int64)
    moved[step] = np.arange(n_bodies)
    edges = np.array([(moved[r], moved[c]) for r, c in edges], dtype=np.int64).reshape(-1, 2)

    def csr(lists, width=None):
        start = np.zeros(len(lists) + 1, dtype=np.int64)
        start[1:] = np.cumsum([len(x) for x in lists])
        flat = [item for x in lists for item in x]
        shape = (len(flat),) if width is None else (len(flat), width)
        return start, np.array(flat, dtype=np.int64).reshape(shape)

    down_start, down = csr([down[k] for k in step])
    up_start, up = csr([up[k] for k in step])
    update_start, updates = csr([updates_by[k] for k in step], 3)
    joint_edge = np.array([-1 if a == GROUND else index[(max(position[a], position[b]), min(position[a], position[b]))]
                           for a, b in zip(lowers, uppers)], dtype=np.int64)
    order = order[step]
    position[order] = np.arange(n_bodies)
    return order, position, edges, down_start, down, up_start, up, update_start, updates, joint_edge


def _interleaved(n, edges, updates_by):
    """An order of the n eliminations of a sequence (its positions 0..n-1) that runs independent ones
    side by side and does the same operations on every block in the same sequence.

    Elimination k must follow every elimination that updates a block it reads (its row's diagonal
    block and its couplings, ``edges`` with row or column k), and two eliminations that update the same
    block keep their order (a block's updates are subtractions, whose sum depends on their order). Among
    what is free to go, the earliest level first (the longest chain of waits before it), the sequence's
    order within a level: the columns of a colonnade, each a chain of drums into its capital, are
    eliminated level by level side by side (the bottom drum of every column, then the second ...), so a
    processor overlaps their work, which one column after another left waiting on each elimination's
    square roots and divisions (issue 48, speed).
    """
    after = [set() for _ in range(n)]  # after[k]: the eliminations k must follow
    last = {}  # block -> the last elimination that updated it so far
    for k in range(n):
        for e1, e2, target in updates_by[k]:
            block = ("diag", edges[e1][0]) if target < 0 else ("edge", target)
            if block in last:
                after[k].add(last[block])
            last[block] = k
            # the body whose block it is waits for this update before its own elimination
            row = edges[e1][0] if target < 0 else edges[target][1]
            after[row].add(k)
    level = [0] * n
    for k in range(n):  # every wait is on an earlier elimination of the sequence
        level[k] = max((level[i] + 1 for i in after[k]), default=0)
    return sorted(range(n), key=lambda k: (level[k], k))


@njit(cache=True, inline="always")
def _row6(a, n, r):
    """``a[n, r, :6]`` as six numbers (indexed, not a view: a view costs two calls into numba's runtime)."""
    return a[n, r, 0], a[n, r, 1], a[n, r, 2], a[n, r, 3], a[n, r, 4], a[n, r, 5]


@njit(cache=True, inline="always")
def _less6(s, x, a, n, r):
    """The six numbers s less ``x a[n, r, :6]``, lane by lane (one multiply-subtract each: the lanes are
    independent, so LLVM's SLP vectoriser, when on, does them in vector lanes)."""
    return (s[0] - x * a[n, r, 0], s[1] - x * a[n, r, 1], s[2] - x * a[n, r, 2],
            s[3] - x * a[n, r, 3], s[4] - x * a[n, r, 4], s[5] - x * a[n, r, 5])


@njit(cache=True, inline="always")
def _store6(a, n, r, s):
    """``a[n, r, :6] = s``."""
    a[n, r, 0], a[n, r, 1], a[n, r, 2], a[n, r, 3], a[n, r, 4], a[n, r, 5] = s


@njit(cache=True)
def sparse_block_solve(pattern, diag, blocks, rhs, tmp):
    """Solve a symmetric positive definite system of 6 x 6 blocks in place, by block Cholesky.

    Parameters
    ----------
    pattern : tuple
        :func:`elimination` of the system's graph.
    diag : float64[n, 6, 6]
        Diagonal blocks by position (the factors on return).
    blocks : float64[n_edges, 6, 6]
        ``blocks[e]`` couples row position ``edges[e, 0]`` with column position ``edges[e, 1]``,
        stored transposed: ``blocks[e, m, i]`` is entry (i, m) of the coupling (the coupling factors
        on return, likewise; fill edges must come in as zero).
    rhs : float64[n, 6]
        Right-hand side by body (not position), overwritten by the solution.
    tmp : float64[6]
        Scratch.

    Notes
    -----
    Transposed, a coupling's column is a contiguous row of six numbers, and the factorisation's
    updates and the forward substitution work on whole such rows: six independent multiply-subtracts
    for each term, every entry's terms in the textbook's order (the same numbers to the bit as the
    entry-by-entry loops), which the processor overlaps and which fill vector lanes where the
    compiler vectorises (issue 48, speed).
    """
    order, position, edges, down_start, down, up_start, up, update_start, updates = pattern[:9]
    n = diag.shape[0]
    for k in range(n):
        _cholesky6(diag, k)
        for q in range(down_start[k], down_start[k + 1]):
            e = ix(down[q])
            # C = A L^-T: every row i of C solves L x = A[i, :]; column c of C for all rows at once
            for c in range(6):
                s = _row6(blocks, e, c)
                for m in range(c):
                    s = _less6(s, diag[k, c, m], blocks, e, m)
                inv = diag[k, c, c]
                _store6(blocks, e, c, (s[0] / inv, s[1] / inv, s[2] / inv, s[3] / inv, s[4] / inv, s[5] / inv))
        for q in range(update_start[k], update_start[k + 1]):
            e1, e2, target = ix(updates[q, 0]), ix(updates[q, 1]), updates[q, 2]
            if target < 0:  # D -= C C^T, whole rows: row i's entry j is C[j, :] C[i, :], as its mirror
                d = ix(edges[e1, 0])
                for i in range(6):
                    s = _row6(diag, d, i)
                    for m in range(6):
                        s = _less6(s, blocks[e1, m, i], blocks, e1, m)
                    _store6(diag, d, i, s)
            else:  # T -= C1 C2^T, stored transposed: row j of the store less C2[j, m] C1[:, m]
                t = ix(target)
                for j in range(6):
                    s = _row6(blocks, t, j)
                    for m in range(6):
                        s = _less6(s, blocks[e2, m, j], blocks, e1, m)
                    _store6(blocks, t, j, s)
    for k in range(n):  # forward: L w = rhs
        b = ix(order[k])
        for q in range(up_start[k], up_start[k + 1]):
            e = ix(up[q])
            src = ix(order[edges[e, 1]])
            s = rhs[b, 0], rhs[b, 1], rhs[b, 2], rhs[b, 3], rhs[b, 4], rhs[b, 5]
            # w[b] -= C w[src], all of b's six rows at once, term m after term m as the textbook's
            for m in range(6):
                s = _less6(s, rhs[src, m], blocks, e, m)
            rhs[b, 0], rhs[b, 1], rhs[b, 2], rhs[b, 3], rhs[b, 4], rhs[b, 5] = s
        for i in range(6):
            s1 = rhs[b, i]
            for m in range(i):
                s1 -= diag[k, i, m] * rhs[b, m]
            rhs[b, i] = s1 / diag[k, i, i]
    for k in range(n - 1, -1, -1):  # backward: L^T x = w
        b = ix(order[k])
        for q in range(down_start[k], down_start[k + 1]):
            e = ix(down[q])
            src = ix(order[edges[e, 0]])
            for i in range(6):
                s1 = rhs[b, i]
                for m in range(6):
                    s1 -= blocks[e, i, m] * rhs[src, m]
                rhs[b, i] = s1
        for i in range(5, -1, -1):
            s1 = rhs[b, i]
            for m in range(i + 1, 6):
                s1 -= diag[k, m, i] * rhs[b, m]
            tmp[i] = s1 / diag[k, i, i]
            rhs[b, i] = tmp[i]


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


@njit(cache=True, inline="always")
def _row(R, j, i, x, y, z):
    """Row i of the 3 x 3 matrix ``R[j, :9]`` (row-major) times (x, y, z)."""
    return R[j, 3 * i] * x + R[j, 3 * i + 1] * y + R[j, 3 * i + 2] * z


@njit(cache=True, inline="always")
def _turn_block(R, j, k00, k01, k02, k10, k11, k12, k20, k21, k22, out, r0, c0, symmetric):
    """``out[j, r0:r0 + 3, c0:c0 + 3] = R K R^T`` for the 3 x 3 block K (row-major arguments) and
    the rotation ``R[j, :9]``, and the mirror block ``out[j, c0:c0 + 3, r0:r0 + 3]`` its transpose.
    Summed as ``(R K) R^T``, each entry in the order of ``_row``; a symmetric block takes its
    lower triangle (i >= k) for both halves. Rows are indexed, not taken as views (a view costs
    two calls into numba's runtime for its reference count)."""
    t00, t01, t02 = _row(R, j, 0, k00, k10, k20), _row(R, j, 0, k01, k11, k21), _row(R, j, 0, k02, k12, k22)
    t10, t11, t12 = _row(R, j, 1, k00, k10, k20), _row(R, j, 1, k01, k11, k21), _row(R, j, 1, k02, k12, k22)
    t20, t21, t22 = _row(R, j, 2, k00, k10, k20), _row(R, j, 2, k01, k11, k21), _row(R, j, 2, k02, k12, k22)
    v00, v10, v20 = _row(R, j, 0, t00, t01, t02), _row(R, j, 0, t10, t11, t12), _row(R, j, 0, t20, t21, t22)
    v11, v21, v22 = _row(R, j, 1, t10, t11, t12), _row(R, j, 1, t20, t21, t22), _row(R, j, 2, t20, t21, t22)
    if symmetric:
        v01, v02, v12 = v10, v20, v21
    else:
        v01, v02, v12 = _row(R, j, 1, t00, t01, t02), _row(R, j, 2, t00, t01, t02), _row(R, j, 2, t10, t11, t12)
    out[j, r0, c0], out[j, r0, c0 + 1], out[j, r0, c0 + 2] = v00, v01, v02
    out[j, r0 + 1, c0], out[j, r0 + 1, c0 + 1], out[j, r0 + 1, c0 + 2] = v10, v11, v12
    out[j, r0 + 2, c0], out[j, r0 + 2, c0 + 1], out[j, r0 + 2, c0 + 2] = v20, v21, v22
    if not symmetric:
        out[j, c0, r0], out[j, c0 + 1, r0], out[j, c0 + 2, r0] = v00, v01, v02
        out[j, c0, r0 + 1], out[j, c0 + 1, r0 + 1], out[j, c0 + 2, r0 + 1] = v10, v11, v12
        out[j, c0, r0 + 2], out[j, c0 + 1, r0 + 2], out[j, c0 + 2, r0 + 2] = v20, v21, v22


@njit(cache=True, inline="always")
def turned_joint_matrix_z(sa, ax, ay, az, axx, ayy, azz, axy, axz, ayz, sb, bx, by, bxx, byy, bxy, R, j, out):
    """:func:`joint_matrix_z` of these moments turned from the frame of the face below to the ground's,
    into ``out[j]``: ``T K T^T`` with T = diag(R, R), R that face's rotation (``R[j, :9]``,
    row-major), block by block ``R K_b R^T`` (a joint on the ground takes :func:`joint_matrix_z` itself)."""
    (k00, k22, k04, k05, k13, k15, k23, k24, k33, k44, k55, k34, k35, k45) = _joint_matrix_z_entries(
        sa, ax, ay, az, axx, ayy, azz, axy, axz, ayz, sb, bx, by, bxx, byy, bxy)
    _turn_block(R, j, k00, 0.0, 0.0, 0.0, k00, 0.0, 0.0, 0.0, k22, out, 0, 0, True)
    _turn_block(R, j, 0.0, k04, k05, k13, 0.0, k15, k23, k24, 0.0, out, 0, 3, False)
    _turn_block(R, j, k33, k34, k35, k34, k44, k45, k35, k45, k55, out, 3, 3, True)


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


@njit(cache=True, inline="always")
def _ground_inertia(bodies, b, work, i, k):
    """Entry (i, k) of body b's inertia in the ground frame, ``R diag(I_x, I_y, I_z) R^T`` (R its
    rotation, row-major in ``work[b]``)."""
    return work[b, 3 * i] * bodies[b, B_IX] * work[b, 3 * k] + work[b, 3 * i + 1] * bodies[b, B_IY] * \
        work[b, 3 * k + 1] + work[b, 3 * i + 2] * bodies[b, B_IZ] * work[b, 3 * k + 2]


@njit(cache=True)
def body_inertia(bodies, b, work, out, r0):
    """Body b's mass and inertia in the ground frame into ``out[r0:r0 + 6, r0:r0 + 6]``: m I, then
    :func:`_ground_inertia` (R its rotation, ``work[b]``)."""
    m = bodies[b, B_MASS]
    for i in range(3):
        for k in range(3):
            out[r0 + i, r0 + k] = 0.0
        out[r0 + i, r0 + i] = m
    for i in range(3):
        for k in range(i + 1):
            s = _ground_inertia(bodies, b, work, i, k)
            out[r0 + 3 + i, r0 + 3 + k] = s
            out[r0 + 3 + k, r0 + 3 + i] = s
    for i in range(3):
        for k in range(3):
            out[r0 + i, r0 + 3 + k] = 0.0
            out[r0 + 3 + i, r0 + k] = 0.0


@njit(cache=True)
def assemble_system(y, bodies, joints, joint_matrices, h, work, pattern, diag, blocks, scratch):
    """``M + h C`` as blocks (ground-frame velocities and angular velocities of each body), in the
    elimination order of ``pattern`` (:func:`elimination`).

    ``joint_matrices[j]``: the dashpot matrix of joint j (:func:`joint_matrix`) in the upper
    body's velocities; ``work`` holds each body's rotation matrix
    (:func:`pipeline.dynamics.compliant.assembly._kinematics`). A joint between two bodies adds
    ``h K`` to its upper body's block, ``h E^T K E`` to its lower body's and ``h K E`` between
    them, with ``E = [[-I, [e]x], [0, -I]]``, e from the lower centre to the upper one.
    ``scratch``: a 6 x 6 array.
    """
    order, position, joint_edge = pattern[0], pattern[1], pattern[9]
    # blocks indexed, not taken as views (a view costs two calls into numba's runtime)
    for n in range(diag.shape[0]):
        b = order[n]
        m = bodies[b, B_MASS]
        for i in range(6):
            for k in range(6):
                diag[n, i, k] = 0.0
        for i in range(3):
            diag[n, i, i] = m
            for k in range(i + 1):
                s = _ground_inertia(bodies, b, work, i, k)
                diag[n, 3 + i, 3 + k] = s
                diag[n, 3 + k, 3 + i] = s
    for e in range(blocks.shape[0]):
        for i in range(6):
            for k in range(6):
                blocks[e, i, k] = 0.0
    K = joint_matrices
    for j in range(joints.shape[0]):
        u = int(joints[j, J_UPPER])
        lower = int(joints[j, J_LOWER])
        pu = position[u]
        for i in range(6):
            for k in range(6):
                diag[pu, i, k] += h * K[j, i, k]
        if lower == GROUND:
            continue
        o, lo = NB * u, NB * lower
        ex = y[o + sk.X] - y[lo + sk.X]
        ey = y[o + sk.Y] - y[lo + sk.Y]
        ez = y[o + sk.Z] - y[lo + sk.Z]
        pl = position[lower]
        KE = scratch
        for i in range(6):  # h K E, rows the upper body's, columns the lower's
            k0, k1, k2 = K[j, i, 0], K[j, i, 1], K[j, i, 2]
            KE[i, 0] = -h * k0
            KE[i, 1] = -h * k1
            KE[i, 2] = -h * k2
            # row of K[:, :3] [e]x, less K[:, 3:]
            KE[i, 3] = h * (k1 * ez - k2 * ey - K[j, i, 3])
            KE[i, 4] = h * (k2 * ex - k0 * ez - K[j, i, 4])
            KE[i, 5] = h * (k0 * ey - k1 * ex - K[j, i, 5])
        for k in range(6):
            a0, a1, a2 = KE[0, k], KE[1, k], KE[2, k]
            diag[pl, 0, k] -= a0
            diag[pl, 1, k] -= a1
            diag[pl, 2, k] -= a2
            # -[e]x (KE)[:3] - (KE)[3:]
            diag[pl, 3, k] -= (ey * a2 - ez * a1) + KE[3, k]
            diag[pl, 4, k] -= (ez * a0 - ex * a2) + KE[4, k]
            diag[pl, 5, k] -= (ex * a1 - ey * a0) + KE[5, k]
        e = joint_edge[j]  # with the later body's rows, stored transposed (sparse_block_solve)
        if pu > pl:
            for i in range(6):
                for k in range(6):
                    blocks[e, i, k] += KE[k, i]
        else:
            for i in range(6):
                for k in range(6):
                    blocks[e, i, k] += KE[i, k]


@njit(cache=True)
def _spring_moments(y, params, j, kn, ks, mom):
    """Add joint j's springs, every point pressed (``k_s A`` shear, ``(k_n - k_s) A`` the rest of the
    normal), to the moments ``mom`` (:func:`add_moments`), point by point in their order: compiled, as
    a loop of the layer above it cost a tenth of a second a structure of the Parthenon's size."""
    points, joint_start = params[1], params[2]
    for p in range(joint_start[j], joint_start[j + 1]):
        geo = sk._point_geometry(y, p, j, params)
        area = points[p, P_AREA]
        add_moments(mom, ks * area, (kn - ks) * area, geo[0], geo[1], geo[2])


def spring_matrices(params, y, per_joint=False):
    """The joints' springs of the assembly in the state y, every point pressed, as dense matrices.

    Every contact point carries its normal spring ``k_n A`` and its shear spring ``k_s A``
    (whole faces in contact: the stiffest the joints get). Returns ``(K, M, K_normal)``: the
    stiffness (6 n x 6 n, ground-frame velocities and angular velocities of each body), the mass
    matrix and the normal springs alone; with ``per_joint`` also each joint's share of K, as
    ``(bodies, 12 x 12 or 6 x 6 block)`` per joint.
    """
    bodies, joints = params[0], params[3]
    work, jwork = params[6], params[8]
    n = bodies.shape[0]
    sk._kinematics(y, params)
    K = np.zeros((6 * n, 6 * n))
    K_normal = np.zeros((6 * n, 6 * n))
    M = np.zeros((6 * n, 6 * n))
    for b in range(n):
        body_inertia(bodies, b, work, M, 6 * b)
    mat = np.zeros((6, 6))
    mom = np.zeros(20)
    shares = []
    for total, shear in ((K, True), (K_normal, False)):
        for j in range(joints.shape[0]):
            mom[:] = 0.0
            kn, ks = joints[j, J_KN], joints[j, J_KS]
            if not shear:
                ks = 0.0
            _spring_moments(y, params, j, kn, ks, mom)
            F = jwork[j]
            joint_matrix(mom, F[2], F[5], F[8], mat)
            u, lower = int(joints[j, J_UPPER]), int(joints[j, J_LOWER])
            rows = [(u, np.eye(6))]
            if lower != GROUND:
                e = y[NB * u:NB * u + 3] - y[NB * lower:NB * lower + 3]
                E = np.zeros((6, 6))
                E[:3, :3] = -np.eye(3)
                E[:3, 3:] = np.array([[0.0, -e[2], e[1]], [e[2], 0.0, -e[0]], [-e[1], e[0], 0.0]])
                E[3:, 3:] = -np.eye(3)
                rows.append((lower, E))
            H = np.hstack([Ea for _, Ea in rows])
            local = H.T @ mat @ H
            for i, (a, _) in enumerate(rows):
                for k, (c, _) in enumerate(rows):
                    total[6 * a:6 * a + 6, 6 * c:6 * c + 6] += local[6 * i:6 * i + 6, 6 * k:6 * k + 6]
            if shear:
                shares.append(([a for a, _ in rows], local))
    if per_joint:
        return K, M, K_normal, shares
    return K, M, K_normal


def stiffest_mode(params, y):
    """The stiffest mode of the joints' springs, every point pressed: its angular frequency [1/tau]
    and each joint's share of its elastic energy [1].

    The generalised eigenvalue problem ``K x = omega^2 M x`` of the assembly in the state y (the
    rest state), :func:`spring_matrices`. Symplectic Euler is stable on it for ``h < 2 / omega``;
    the joint with the largest share is the one that sets the limit.
    """
    from scipy.linalg import eigh

    K, M, _, shares = spring_matrices(params, y, per_joint=True)
    values, vectors = eigh(0.5 * (K + K.T), M)
    x = vectors[:, -1]
    energy = np.array([float(x[np.concatenate([np.arange(6 * b, 6 * b + 6) for b in bodies])] @ local
                             @ x[np.concatenate([np.arange(6 * b, 6 * b + 6) for b in bodies])])
                       for bodies, local in shares])
    return math.sqrt(max(values[-1], 0.0)), energy / energy.sum()


def stiffest_frequency(params, y):
    """Highest angular frequency of the joints' springs, every point pressed [1/tau] (:func:`stiffest_mode`)."""
    return stiffest_mode(params, y)[0]
