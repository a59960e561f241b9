"""The fixed-step semi-implicit integrator of the compliant models (pipeline.dynamics.compliant.semi_implicit).

Its pieces against independent dense constructions, its stability limit against the growth
it prevents, and the guarantees a user relies on (refusal of an unstable step, a run in
pieces equal to a run in one). The physics it integrates is checked by the compliant and drum
tests, which run it as the default.
"""

import math

import numpy as np
import pytest

from pipeline import compliant as cp
from pipeline.dynamics.compliant import assembly as sk
from pipeline.dynamics.compliant import layout as ly
from pipeline.dynamics.compliant import linear_system as ls
from pipeline.dynamics.compliant import semi_implicit as si
from pipeline.errors import InputError
from pipeline.structures.colonnade import Colonnade
from pipeline.structures.drums import Capital, DrumColumn
from pipeline.structures.column import Column
from pipeline.groundmotion import one_sine_pulse
from pipeline.settings import Excitation, ModelSettings

PAPER = Column(0.5, 0.4, 4.0)


def _cross(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def test_joint_matrix_from_moments_is_the_sum_over_points():
    """sum_p H_p^T D_p H_p (H = [I, -[r]x], D = alpha I + beta n n^T) from the 20 moments equals
    the per-point sum to round-off (1e-13 relative)."""
    rng = np.random.default_rng(7)
    n = rng.normal(size=3)
    n /= np.linalg.norm(n)
    mom = np.zeros(20)
    dense = np.zeros((6, 6))
    for _ in range(9):
        alpha, normal = rng.uniform(0.0, 2.0), rng.uniform(0.0, 3.0)
        r = rng.normal(size=3)
        ls.add_moments(mom, alpha, normal - alpha, *r)
        D = alpha * np.eye(3) + (normal - alpha) * np.outer(n, n)
        H = np.hstack([np.eye(3), -_cross(r)])
        dense += H.T @ D @ H
    out = np.zeros((6, 6))
    ls.joint_matrix(mom, *n, out)
    np.testing.assert_allclose(out, dense, rtol=0, atol=1e-13 * np.abs(dense).max())


def test_joint_matrix_in_the_face_frame_and_turned_is_the_sum_over_points():
    """The integrator's joint matrix: summed in the frame of the face below (n = e_z,
    :func:`ls.joint_matrix_z`) and turned to the ground's by that face's rotation R
    (:func:`ls.turned_joint_matrix_z`, T K T^T with T = diag(R, R)), against the per-point sum
    with the lever arms and the normal turned first (R r, R e_z); round-off, 1e-13 relative."""
    rng = np.random.default_rng(11)
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    w, x, y, z = q
    R = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                  [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                  [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
    mom = np.zeros(20)
    local, turned = np.zeros((6, 6)), np.zeros((6, 6))
    n_local, n = np.array([0.0, 0.0, 1.0]), R @ np.array([0.0, 0.0, 1.0])
    for _ in range(9):
        alpha, normal = rng.uniform(0.0, 2.0), rng.uniform(0.0, 3.0)
        r = rng.normal(size=3)
        ls.add_moments(mom, alpha, normal - alpha, *r)
        for dense, arm, nn in ((local, r, n_local), (turned, R @ r, n)):
            D = alpha * np.eye(3) + (normal - alpha) * np.outer(nn, nn)
            H = np.hstack([np.eye(3), -_cross(arm)])
            dense += H.T @ D @ H
    # the moments the integrator keeps: with n = e_z the beta moments in z do not enter
    kept = [mom[k] for k in (0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 14, 15, 17)]
    out = np.full((6, 6), np.nan)
    ls.joint_matrix_z(*kept, out)
    np.testing.assert_allclose(out, local, rtol=0, atol=1e-13 * np.abs(local).max())
    out = np.full((1, 6, 6), np.nan)
    ls.turned_joint_matrix_z(*kept, R.reshape(1, 9), 0, out)
    np.testing.assert_allclose(out[0], turned, rtol=0, atol=1e-13 * np.abs(turned).max())


def _random_blocks(pattern, n, rng):
    """A random symmetric positive definite system with a pattern's blocks, and its dense form."""
    order, position, edges = pattern[:3]
    diag = np.zeros((n, 6, 6))
    blocks = np.zeros((len(edges), 6, 6))
    dense = np.zeros((6 * n, 6 * n))
    for e, (r, c) in enumerate(edges):
        blocks[e] = rng.normal(size=(6, 6))
        br, bc = order[r], order[c]
        # stored transposed (sparse_block_solve): blocks[e, m, i] is entry (i, m) of the coupling
        dense[6 * br:6 * br + 6, 6 * bc:6 * bc + 6] = blocks[e].T
        dense[6 * bc:6 * bc + 6, 6 * br:6 * br + 6] = blocks[e]
    for k in range(n):
        x = rng.normal(size=(6, 6))
        diag[k] = x @ x.T + 6.0 * (1 + len(edges)) * np.eye(6)  # diagonally dominant: positive definite
        b = order[k]
        dense[6 * b:6 * b + 6, 6 * b:6 * b + 6] = diag[k]
    return diag, blocks, dense


@pytest.mark.parametrize("shape", ["chain", "colonnade", "fill"])
def test_sparse_block_solve_matches_a_dense_solve(shape):
    """The block Cholesky of the joints' pattern equals a dense solve (1e-12): a chain (one column,
    the block-tridiagonal case), a colonnade's pattern in its order (chains into capitals, then
    capitals and blocks along the row: no fill), and an order that fills in (a row's blocks
    first), whose fill edges the pattern adds."""
    rng = np.random.default_rng(3)
    if shape == "chain":
        n, lowers, uppers, order = 5, [-1, 0, 1, 2, 3], [0, 1, 2, 3, 4], range(5)
    else:
        # 3 columns of a drum and a capital (bodies 0-5: d, c, d, c, d, c), blocks 6 and 7
        n = 8
        lowers = [-1, 0, -1, 2, -1, 4, 1, 3, 3, 5, 6]
        uppers = [0, 1, 2, 3, 4, 5, 6, 6, 7, 7, 7]
        order = [0, 2, 4, 1, 6, 3, 7, 5] if shape == "colonnade" else [6, 7, 0, 2, 4, 1, 3, 5]
    pattern = ls.elimination(n, lowers, uppers, order)
    coupled = sum(1 for lo in lowers if lo >= 0)
    assert (len(pattern[2]) == coupled) == (shape != "fill")  # fill edges only where the order makes them
    diag, blocks, dense = _random_blocks(pattern, n, rng)
    rhs = rng.normal(size=(n, 6))
    x = rhs.copy()
    ls.sparse_block_solve(pattern, diag, blocks, x, np.zeros(6))
    np.testing.assert_allclose(x.ravel(), np.linalg.solve(dense, rhs.ravel()), rtol=0, atol=1e-12)


def test_interleaved_elimination_is_the_sequential_one_to_the_bit():
    """The solve runs the eliminations that do not wait for each other side by side (the columns'
    chains level by level: issue 48, speed) and gives the sequential order's solution to the bit,
    not only to round-off: every block gets the same operations in the same sequence. Three columns
    of two drums and a capital under two blocks, their chains one after another in the order given."""
    rng = np.random.default_rng(7)
    n = 11  # column c: drums 3c, 3c + 1 and capital 3c + 2; blocks 9 and 10
    lowers = [-1, 0, 1, -1, 3, 4, -1, 6, 7, 2, 5, 5, 8, 9]
    uppers = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 9, 10, 10, 10]
    order = [0, 1, 3, 4, 6, 7, 2, 9, 5, 10, 8]
    one_by_one = ls.elimination(n, lowers, uppers, order, interleave=False)
    side_by_side = ls.elimination(n, lowers, uppers, order)
    assert list(one_by_one[0]) == order
    assert list(side_by_side[0][:6]) == [0, 3, 6, 1, 4, 7]  # the bottom drums, then the second ones
    diag, blocks, dense = _random_blocks(one_by_one, n, rng)
    diag_moved = np.empty_like(diag)
    diag_moved[side_by_side[1][one_by_one[0]]] = diag  # the same system: diagonal blocks by position
    rhs = rng.normal(size=(n, 6))
    x, x_moved = rhs.copy(), rhs.copy()
    ls.sparse_block_solve(one_by_one, diag, blocks.copy(), x, np.zeros(6))
    ls.sparse_block_solve(side_by_side, diag_moved, blocks.copy(), x_moved, np.zeros(6))
    assert np.array_equal(x.view(np.uint64), x_moved.view(np.uint64))
    np.testing.assert_allclose(x.ravel(), np.linalg.solve(dense, rhs.ravel()), rtol=0, atol=1e-12)


def _stack_params(column, settings=ModelSettings(model="3d-compliant"), damping=0.0, record=None, dt=1.0):
    asm = cp.assemble(column, settings, damping)
    params = asm.params(record, dt)
    return asm, params, cp.rest_state(asm, params, settings.integrator)


def _dense_stiffness(asm, params, y):
    """Springs of every point (k_n A normal, k_s A shear) as a dense 6N x 6N matrix, point by
    point from each point's Jacobian, and the bodies' mass matrix (in the state's poses; each
    joint's springs in its face's frame, turned to the ground's by its lower body's rotation)."""
    bodies, points, starts, joints = params[:4]
    n = bodies.shape[0]
    K, M = np.zeros((6 * n, 6 * n)), np.zeros((6 * n, 6 * n))
    rot = []
    for b in range(n):
        R = np.empty(9)
        sk.rotation_matrix(*y[ly.NB * b + ly.QW:ly.NB * b + ly.QZ + 1], R)
        R = R.reshape(3, 3)
        rot.append(R)
        m = bodies[b, ly.B_MASS]
        M[6 * b:6 * b + 3, 6 * b:6 * b + 3] = m * np.eye(3)
        M[6 * b + 3:6 * b + 6, 6 * b + 3:6 * b + 6] = R @ np.diag(bodies[b, ly.B_IX:ly.B_IZ + 1]) @ R.T
    centres = [y[ly.NB * b:ly.NB * b + 3] for b in range(n)]
    for j in range(joints.shape[0]):
        u, lower = int(joints[j, ly.J_UPPER]), int(joints[j, ly.J_LOWER])
        F = (np.eye(3) if lower < 0 else rot[lower]) @ joints[j, ly.J_F:ly.J_F + 9].reshape(3, 3)
        D = F @ np.diag([joints[j, ly.J_KS]] * 2 + [joints[j, ly.J_KN]]) @ F.T
        for p in range(starts[j], starts[j + 1]):
            x = centres[u] + rot[u] @ points[p, :3]
            J = np.zeros((3, 6 * n))
            J[:, 6 * u:6 * u + 3] = np.eye(3)
            J[:, 6 * u + 3:6 * u + 6] = -_cross(x - centres[u])
            if lower >= 0:
                J[:, 6 * lower:6 * lower + 3] = -np.eye(3)
                J[:, 6 * lower + 3:6 * lower + 6] = _cross(x - centres[lower])
            K += points[p, ly.P_AREA] * J.T @ D @ J
    return K, M


COLONNADE = Colonnade(DrumColumn.equal(PAPER, 2, Capital(1.1, 0.3)), 3, 2.5, 0.8)


@pytest.mark.parametrize("drums", [1, 3, "colonnade"])
def test_stiffest_frequency_matches_a_dense_point_by_point_model(drums):
    """The generalised eigenvalue of the joints' springs, from the moments and block assembly,
    equals that of an independent point-by-point dense stiffness (1e-9 relative), for a column
    and for a colonnade (bearing and head joints, the heads' faces vertical); for the monolith it
    is at least the vertical bounce sqrt(k_n A / m), a mode on its own."""
    from scipy.linalg import eigh

    column = {1: PAPER, 3: DrumColumn.equal(PAPER, 3), "colonnade": COLONNADE}[drums]
    asm, params, y = _stack_params(column)
    K, M = _dense_stiffness(asm, params, y)
    dense = math.sqrt(eigh(K, M, eigvals_only=True).max())
    assert ls.stiffest_frequency(params, y) == pytest.approx(dense, rel=1e-9)
    if drums == 1:
        bounce = math.sqrt(asm.joints[0, ly.J_KN] * asm.joints[0, ly.J_AREA] / asm.bodies[0, ly.B_MASS])
        assert dense >= bounce
        assert np.any(np.isclose(np.sqrt(eigh(K, M, eigvals_only=True)), bounce, rtol=1e-9))


EXPLICIT = ModelSettings(model="3d-compliant", numerics=(("springs", "explicit"), ("step_safety", 0.5)))


def _kinetic(y, bodies):
    """Kinetic energy of the bodies in the state y (body-frame angular velocities, principal axes)."""
    total = 0.0
    for b in range(bodies.shape[0]):
        o = ly.NB * b
        total += 0.5 * bodies[b, ly.B_MASS] * float(np.sum(y[o + ly.VX:o + ly.VZ + 1] ** 2))
        total += 0.5 * float(np.sum(bodies[b, ly.B_IX:ly.B_IZ + 1] * y[o + ly.WX:o + ly.WZ + 1] ** 2))
    return total


def _free_vibration_growth(column, factor, steps=3000, settings=EXPLICIT, kinetic=False):
    """Energy after undamped free vibration from a tiny random kick, over the kick's energy (or the
    kinetic energy over the kick's: free of the round-off of the total's difference from rest)."""
    asm, params, y = _stack_params(column, settings)
    h = factor * 2.0 / ls.stiffest_frequency(params, y)
    rng = np.random.default_rng(11)
    e0 = sk.energy(y, params)
    for b in range(asm.n_bodies):
        o = ly.NB * b
        y[o + ly.VX:o + ly.VZ + 1] = 1e-7 * rng.normal(size=3)
        y[o + ly.WX:o + ly.WZ + 1] = 1e-7 * rng.normal(size=3)
    kick = _kinetic(y, params[0]) if kinetic else sk.energy(y, params) - e0
    scratch = si.make_scratch(params, asm.pattern)
    for k in range(steps):
        si.step(k * h, y, h, params, scratch)
    return (_kinetic(y, params[0]) if kinetic else sk.energy(y, params) - e0) / kick


@pytest.mark.parametrize("drums", [1, 3])
def test_the_stability_limit_is_where_undamped_joints_start_to_grow(drums):
    """With the springs at the step's start and without dashpots, 3000 steps at 0.97 of 2 / omega_max
    keep a small vibration's energy within a factor 3 of the kick (symplectic Euler's bounded error:
    measured 1.7 and 1.8), and at 1.03 of it the stiffest mode grows by more than 1e3 (measured 8e8
    and 6e8: geometric growth): the limit that scheme's step is a fraction of, and above which its
    step is refused, is real."""
    column = PAPER if drums == 1 else DrumColumn.equal(PAPER, drums)
    assert _free_vibration_growth(column, 0.97) < 3.0
    assert _free_vibration_growth(column, 1.03) > 1e3


@pytest.mark.parametrize("drums", [1, 3, "colonnade"])
def test_springs_at_the_step_end_damp_a_vibration_at_any_step(drums):
    """With the springs at the step's end (the default) and without dashpots, the same kick decays at
    1.03, 2 and 8 times the explicit springs' limit, where the explicit springs grow it by 1e8 in
    as many steps: backward Euler on a linear joint takes energy out of every mode,
    ``1 / (1 + (h omega)^2)`` a step on the stiffest (0.2 at the limit, 0.004 at 8 times it).
    Kinetic energy after 300 steps over the kick's, measured: 1 drum 8e-7 / 6e-16 / 4e-23, 3 drums
    3.4e-2 / 2.4e-5 / 3e-21, a row of 3 columns 9.3e-3 / 1.9e-3 / 5e-7 (the slow modes, rocking on
    the compliant joints, decay least at the smallest step); the bound 0.1 is three times the
    largest. A step is the scheme's own choice of accuracy, not of stability."""
    column = {1: PAPER, 3: DrumColumn.equal(PAPER, 3), "colonnade": COLONNADE}[drums]
    implicit = ModelSettings(model="3d-compliant")
    for factor in (1.03, 2.0, 8.0):
        assert _free_vibration_growth(column, factor, steps=300, settings=implicit, kinetic=True) < 0.1
    assert _free_vibration_growth(column, 1.03, steps=300, kinetic=True) > 1e3


def test_an_unstable_step_is_refused_before_computing():
    """With the springs at the step's start a step at or above the limit is refused, given as a step
    or as step_safety; with them at its end (the default) it runs (the stability test above), up to
    twice the limit (beyond, the scheme's own damping is refused as inaccurate)."""
    pulse = one_sine_pulse(3.0, 0.5, dt=0.01, duration=1.0)
    asm, params, y = _stack_params(DrumColumn.equal(PAPER, 4))
    limit = 2.0 / ls.stiffest_frequency(params, y) * asm.time
    from pipeline.simulate import simulate

    explicit = (("springs", "explicit"),)
    with pytest.raises(InputError, match=r"step = .* at or above the stability limit .* springs = explicit"):
        simulate(DrumColumn.equal(PAPER, 4), pulse, Excitation(),
                 ModelSettings(model="3d-compliant", step=1.05 * limit, numerics=explicit), histories=False)
    with pytest.raises(InputError, match=r"step_safety = 1 .* at or above the stability limit"):
        simulate(DrumColumn.equal(PAPER, 4), pulse, Excitation(),
                 ModelSettings(model="3d-compliant", numerics=explicit + (("step_safety", 1.0),)), histories=False)
    s = simulate(DrumColumn.equal(PAPER, 4), pulse, Excitation(),
                 ModelSettings(model="3d-compliant", step=1.05 * limit, tail=0.0), histories=False).summary
    assert s["step"] == pytest.approx(1.05 * limit, rel=1e-12)
    with pytest.raises(InputError, match=r"step = .* is above twice the stability limit .* at most"):
        simulate(DrumColumn.equal(PAPER, 4), pulse, Excitation(),
                 ModelSettings(model="3d-compliant", step=2.1 * limit), histories=False)
    with pytest.raises(InputError, match="step_safety"):
        ModelSettings(model="3d-compliant", numerics=(("step_safety", 2.5),))
    with pytest.raises(InputError, match="springs = 'backward' is unknown"):
        ModelSettings(model="3d-compliant", numerics=(("springs", "backward"),))
    with pytest.raises(InputError, match="fixed step of the semi-implicit"):
        ModelSettings(model="3d-compliant", integrator="dopri5", step=1e-4)


def test_a_run_in_pieces_is_the_run_in_one():
    """The progress line's pieces change nothing: the same summary and histories, bit for bit."""
    pulse = one_sine_pulse(3.0, 0.5, dt=0.01, duration=1.0)
    settings = ModelSettings(model="3d-compliant", tail=1.5)
    stack = DrumColumn.equal(PAPER, 2)
    calls = []
    whole = cp.simulate_compliant(stack, pulse, Excitation(), settings)
    pieces = cp.simulate_compliant(stack, pulse, Excitation(), settings, progress=lambda d, t: calls.append((d, t)))
    assert len(calls) >= 3 and calls[-1][0] == pytest.approx(calls[-1][1]) == pytest.approx(2.5)
    assert all(a[0] < b[0] for a, b in zip(calls, calls[1:]))
    for key, value in whole.summary.items():
        np.testing.assert_array_equal(pieces.summary[key], value, err_msg=key)
    for name in whole.histories.data_vars:
        np.testing.assert_array_equal(pieces.histories[name].values, whole.histories[name].values, err_msg=name)


def test_the_output_grid_changes_neither_the_steps_nor_the_statistics():
    """The steps follow the stability limit, not the samples, and the statistics are taken at
    every step: any output_step that divides the run's 2.5 s (a run ends on its grid) gives the
    same summary, bit for bit (only the history grid differs). Its rows are interpolated between the two steps around each sample: a row at a
    time the finer grid also has is the same state to the interpolation's round-off, and the
    time where the tilt peaks on a 1 ms grid lies within one step of the step statistics'.
    Before, the step was shortened to divide the sampling interval, so another output_step was
    another trajectory."""
    pulse = one_sine_pulse(3.0, 0.5, dt=0.01, duration=1.0)
    stack = DrumColumn.equal(PAPER, 2)
    runs = {o: cp.simulate_compliant(stack, pulse, Excitation(), ModelSettings(model="3d-compliant", tail=1.5,
                                                                                  output_step=o))
            for o in (0.001, 0.01, 0.05)}
    fine, coarse = runs[0.001], runs[0.01]
    step = fine.summary["step"]
    assert step == coarse.summary["step"] == runs[0.05].summary["step"]
    assert 0.001 % step > 1e-6 and 0.01 % step > 1e-6  # divides neither grid: every row is interpolated
    for r in runs.values():
        for key, value in fine.summary.items():
            np.testing.assert_array_equal(r.summary[key], value, err_msg=key)
    same = fine.histories.sel(time=coarse.histories.time.values, method="nearest")
    np.testing.assert_allclose(coarse.histories.drum_theta.values, same.drum_theta.values, rtol=1e-12, atol=1e-15)
    peak_row = float(fine.histories.time[int(np.argmax(fine.histories.theta.values))])
    assert abs(peak_row - fine.summary["peak_time"]) <= step + 0.001
    assert fine.summary["peak_theta"] >= float(fine.histories.theta.max())


def test_unsigned_index_is_the_index():
    """The kernels' unsigned index (issue 48, speed) reads the same element as the signed one, from an
    integer or from a table's float, and is unsigned in compiled code (no wrap-around test)."""
    from numba import njit, types

    from pipeline.dynamics.compliant.unsigned import ix

    @njit
    def read(a, i, f):
        return a[ix(i)], a[ix(f)], ix(i)

    a = np.arange(10.0) * 1.5
    assert read(a, 7, 3.0)[:2] == (a[7], a[3])
    assert read.nopython_signatures[0].return_type[2] == types.uint64


def test_a_second_solve_sums_again_only_the_joints_that_changed():
    """A step whose active set changes solves again with the joints' loads and matrices from their
    points (issue 48, speed: only the joints whose clipping changed are summed again, the others keep
    their sums): at every such step of a stack set rocking, the kept sums of every joint are, to the
    bit, what summing its points gives, and the loads and matrices they give the same as summing every
    joint again. The stack must give such steps (measured: 70 of 400 steps of 3 drums kicked into rocking)."""
    asm, params, y = _stack_params(DrumColumn.equal(PAPER, 3), damping=1e-3)
    h = 2.0 / ls.stiffest_frequency(params, y)
    top = ly.NB * (asm.n_bodies - 1)
    y[top + ly.WX] = 0.3  # a kick about a horizontal axis: the top drum rocks, its bed joint clips
    s = si.make_scratch(params, asm.pattern)
    pts, mats, contacts, n_contact, kept = s[0], s[1], s[13], s[14], s[15]
    joint_start, work = params[2], params[6]
    checked = 0
    for k in range(400):
        solves = si.step(k * h, y, h, params, s)
        if not 1 < solves < si.MAX_PASSES:
            continue
        checked += 1
        for j in range(params[3].shape[0]):
            fresh = si._joint_sums(pts, contacts, joint_start[j], joint_start[j] + n_contact[j])
            assert np.array_equal(np.array(fresh).view(np.uint64), kept[j].view(np.uint64))
        # the loads of the kept sums (no joint changed) and of every joint summed again, in the same state
        si._joint_loads(y, params, pts, mats, contacts, n_contact, kept, np.zeros(len(n_contact), dtype=np.int64))
        loads, matrices = work[:, ly.W_F:ly.W_T + 3].copy(), mats.copy()
        si._joint_loads(y, params, pts, mats, contacts, n_contact, kept, np.ones(len(n_contact), dtype=np.int64))
        assert np.array_equal(work[:, ly.W_F:ly.W_T + 3], loads) and np.array_equal(mats, matrices)
    assert checked >= 10
