"""The compliant kernel of an assembly of bodies on joints: exact rest, the energy identity, kinematics."""

import math

import numpy as np
import pytest

from pipeline.compliant import as_stack, assemble, critical_damping, released_state, rest_state
from pipeline.dynamics.compliant import adaptive
from pipeline.dynamics.compliant import assembly as sk
from pipeline.dynamics.compliant import layout as ly
from pipeline.settings import ModelSettings
from pipeline.structures.colonnade import Colonnade
from pipeline.structures.column import Column
from pipeline.structures.drums import Capital, DrumColumn

PAPER = Column(0.5, 0.4, 4.0)
STACKS = {
    "monolith": (PAPER, ModelSettings(model="3d-compliant")),
    "annulus base": (PAPER, ModelSettings(model="3d-compliant", base_anathyrosis=0.7, contact_sectors=16)),
    "drums and capital": (
        DrumColumn(Column(0.9, 0.7, 8.0), (2.0, 4.5, 6.0), Capital(2.0, 0.6)),
        ModelSettings(model="3d-compliant", anathyrosis=0.6, joint_friction=(0.6, 0.7, 0.8, 0.9))),
    # three columns of two drums and a capital carrying two epistyle blocks (a head joint between them)
    "colonnade": (Colonnade(DrumColumn.equal(PAPER, 2, Capital(1.1, 0.3)), 3, 2.5, 0.8),
                  ModelSettings(model="3d-compliant", contact_sectors=8, joint_friction=0.6)),
}


def _params(column, settings, damping_ratio=0.5, record=None, dt=1.0):
    c = damping_ratio * critical_damping(column, settings)
    asm = assemble(column, settings, c)
    return asm, asm.params(record, dt)


@pytest.mark.parametrize("name", list(STACKS))
def test_at_rest_every_derivative_is_exactly_zero(name):
    column, settings = STACKS[name]
    asm, params = _params(column, settings)
    y0 = rest_state(asm, params, "dopri5")
    dydt = np.full_like(y0, np.nan)
    sk.rhs(0.0, y0, params, dydt)
    assert np.all(dydt == 0.0)  # not small: zero, so a structure left alone stays exactly still
    # the weights are the spring forces of the static state: m g up to the rest state's rounding
    # (~1e-5 L penetrations, heights ~10 L: 1e-16 * 1e6 = 1e-10 relative), and the torques that
    # hold it are round-off of the weights' moments (|W| L 1e-9). The horizontal loads are zero
    # for a column (its rest is upright); a colonnade's bodies rest tilted by up to 5e-6 rad (an
    # end block bears on a whole abacus and half of the next), and the normal forces tilted with
    # them, which the shear springs (unloaded at rest) do not hold, are held as its weight: up to
    # 1e-5 of it (pipeline.compliant.rest)
    weights = asm.bodies[:, ly.B_MASS]
    holds = params[0][:, ly.B_HOLD:ly.B_HOLD + 6]
    np.testing.assert_allclose(holds[:, 2], weights, rtol=1e-9)
    assert np.max(np.abs(holds[:, :2]) / weights[:, None]) < (1e-5 if name == "colonnade" else 1e-15)
    assert np.max(np.abs(holds[:, 3:]) / weights[:, None]) < 1e-9
    if name == "colonnade":
        return
    # a column's joint is pressed in uniformly by the weight above it: W / (k_n A)
    sk._kinematics(y0, params)
    above = np.cumsum(asm.bodies[::-1, ly.B_MASS])[::-1]
    for j in range(asm.n_bodies):
        d = [sk._penetration(y0, p, j, params)[0] for p in range(asm.joint_start[j], asm.joint_start[j + 1])]
        np.testing.assert_allclose(d, above[j] / (asm.joints[j, ly.J_KN] * asm.joints[j, ly.J_AREA]), rtol=1e-9)


def test_a_column_under_no_ground_motion_never_moves():
    column, settings = STACKS["drums and capital"]
    asm, params = _params(column, settings, record=np.zeros((400, 3)), dt=0.05)
    y0 = rest_state(asm, params, "dopri5")
    raw = _run(asm, params, y0, 8.0)
    assert np.array_equal(raw[-1], y0)


def _run(asm, params, y0, tau_end, n=200):
    """States at n + 1 times up to tau_end (the kernel's integrator, tight tolerances)."""
    out = np.empty((n, y0.size))
    t_out = np.linspace(tau_end / n, tau_end, n)
    res = adaptive._integrate(params, 0.0, y0, tau_end, t_out, out, np.ones(2 * asm.n_bodies),
                        np.arange(params[4].shape[0]) * params[5], 1e-11, np.full(y0.size, 1e-14), np.inf, 0.0)
    assert res.status == 0
    return np.vstack([y0, out])


def test_free_rocking_without_damping_loses_energy_only_to_friction():
    """No dashpots: kinetic + potential + elastic energy plus the friction loss is constant.

    Friction cannot be switched off by a high coefficient: a point that lifts off sheds its
    loaded shear spring by slipping as its normal force (and so its friction limit) goes to
    zero, and the column vibrates on its undamped springs, so points touch and leave while
    sliding. What is lost that way is booked; the sum is conserved.
    """
    settings = ModelSettings(model="3d-compliant", friction=5.0, integrator="dopri5")  # the continuous kernel
    asm, params = _params(PAPER, settings, damping_ratio=0.0)
    y0 = released_state(asm, params, 0.3 * PAPER.critical_tilt, settings.integrator)
    states = _run(asm, params, y0, 12.0)  # ~2.7 s: two landings
    acc = ly.NB + 2 * asm.points.shape[0]
    total = np.array([sk.energy(y, params) for y in states]) + states[:, acc + ly.A_FRICTION]
    assert np.all(states[:, acc + ly.A_DAMPING] == 0.0)
    # DOP853 at rtol 1e-11 through two landings on contact springs: ~1e-11 of E
    assert np.max(np.abs(total - total[0])) < 1e-9 * total[0]
    tilt = [sk.tilt_and_rotation(y, 0)[0] for y in states]
    assert min(tilt) < 1e-3 < max(tilt[len(tilt) // 2:])  # it landed and rocked up again


@pytest.mark.parametrize("name", list(STACKS))
def test_energy_rate_is_ground_power_minus_dissipation(name):
    """dE/dt along the right-hand side equals the work rate minus both dissipation rates.

    Random moving states (bodies displaced, tilted, spinning, shear springs loaded), a record
    under way: the identity the energy budget rests on, checked by a central difference.
    """
    column, settings = STACKS[name]
    rng = np.random.default_rng(11)
    record = rng.normal(0.0, 0.3, (50, 3))
    asm, params = _params(column, settings, record=record, dt=0.2)
    y0 = rest_state(asm, params, "dopri5")
    n_b, n_p = asm.n_bodies, asm.points.shape[0]
    for trial in range(20):
        y = y0.copy()
        for b in range(n_b):
            o = ly.NB * b
            y[o:o + 3] += rng.normal(0, 3e-5, 3) + np.array([0, 0, -2e-5])
            axis = rng.normal(0, 1, 3)
            angle = rng.normal(0, 2e-4) if trial % 2 else rng.normal(0, 0.05)
            q = np.concatenate([[math.cos(angle / 2)], math.sin(angle / 2) * axis / np.linalg.norm(axis)])
            y[o + ly.QW:o + ly.QZ + 1] = q
            y[o + ly.VX:o + ly.WZ + 1] = rng.normal(0, 0.02, 6)
        y[ly.NB * n_b:ly.NB * n_b + 2 * n_p] = rng.normal(0, 1e-6, 2 * n_p)
        t = rng.uniform(0.0, 9.0)
        f = np.empty_like(y)
        sk.rhs(t, y, params, f)
        acc = ly.NB * n_b + 2 * n_p
        rate = f[acc + ly.A_WORK] - f[acc + ly.A_FRICTION] - f[acc + ly.A_DAMPING]
        # central difference: truncation O(h^2), round-off ~1e-16 E / h (1e-10 at h = 1e-6 for a column).
        # A colonnade's energy sums a thousand points' and eleven bodies' terms of both signs: its
        # round-off is ~2e-14 E (measured: the difference at h = 1e-5 ... 1e-8 scatters as 2e-12 / h
        # about the rate, E ~ 100 M g L), which the bound below allows
        h = 1e-6
        plus, minus = sk.energy(y + h * f, params), sk.energy(y - h * f, params)
        de = (plus - minus) / (2 * h)
        scale = abs(f[acc + ly.A_FRICTION]) + abs(f[acc + ly.A_DAMPING]) + abs(f[acc + ly.A_WORK]) + 1e-3
        roundoff = 4e-14 * max(abs(plus), abs(minus)) / h
        assert de == pytest.approx(rate, abs=1e-6 * scale + roundoff), trial
        assert f[acc + ly.A_FRICTION] >= -1e-12 and f[acc + ly.A_DAMPING] >= 0.0


def test_tilt_and_rotation_of_euler_angles():
    """Z-X-Z Euler angles (phi, theta, psi): tilt theta, rotation about the vertical phi + psi."""
    phi, theta, psi = 0.7, 0.3, -1.9
    # quaternion of Rz(phi) Rx(theta) Rz(psi)
    def qz(a):
        return np.array([math.cos(a / 2), 0, 0, math.sin(a / 2)])

    def qx(a):
        return np.array([math.cos(a / 2), math.sin(a / 2), 0, 0])

    def mul(p, q):
        w1, x1, y1, z1 = p
        w2, x2, y2, z2 = q
        return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                         w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])

    y = np.zeros(ly.NB)
    y[ly.QW:ly.QZ + 1] = 3.0 * mul(mul(qz(phi), qx(theta)), qz(psi))  # any norm: normalised inside
    tilt, rotation = sk.tilt_and_rotation(y, 0)
    assert tilt == pytest.approx(theta, abs=1e-15)
    assert rotation == pytest.approx(phi + psi, abs=1e-15)
    R = np.empty(9)
    sk.rotation_matrix(*y[ly.QW:ly.QZ + 1], R)
    R = R.reshape(3, 3)
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-15)
    # the axis leans towards (sin phi, -cos phi), the paper's convention
    np.testing.assert_allclose(R[:, 2], [math.sin(phi) * math.sin(theta), -math.cos(phi) * math.sin(theta),
                                         math.cos(theta)], atol=1e-15)


def test_stack_geometry_matches_the_outline():
    stack = as_stack(STACKS["drums and capital"][0])
    drums = stack.drums()
    assert sum(d.h for d in drums) == pytest.approx(8.0)
    assert sum(d.volume for d in drums) == pytest.approx(stack.column.volume, rel=1e-12)
    for lower, upper in zip(drums[:-1], drums[1:]):
        assert lower.r == upper.R  # the same float: a rim on the edge of the face below


def test_no_force_jumps_where_a_point_leaves_the_band_past_an_edge():
    """A drum pressed 1 cm into the one below and slid so that its rim point at 0 deg sits at the
    outer end of the band past the lower face's edge: drum 1's accelerations a nanometre inside
    and outside the band's end differ by 1e-7 of their size at most (measured 1.6e-9: the smooth
    change over 2 nm). With the linear ramp the band's pull (-1/2 k A d^2 ds/drho) jumped there
    by 1/2 k A d^2 / band, 9.4e-4 of the accelerations here, and a collapsing stack chattered on
    that jump with steps of nanoseconds."""
    from pipeline.dynamics.compliant import joint as jl

    asm, params = _params(DrumColumn.equal(Column(1.0, 1.0, 2.0), 2), ModelSettings(model="3d-compliant"))
    bodies, points, joint_start, joints = params[:4]
    y0 = rest_state(asm, params, "dopri5")
    rim = max(points[p, ly.P_X] for p in range(joint_start[1], joint_start[2]))
    end = joints[1, ly.J_FA] * (1.0 + jl.EDGE_TOL) + joints[1, ly.J_BAND]  # where s reaches 0
    rates = []
    for eps in (-1e-9, 1e-9):
        y = y0.copy()
        y[ly.NB + ly.X] += end - rim + eps
        y[ly.NB + ly.Z] -= 0.02  # 1 cm into the drum below (L = 0.5 m)
        dydt = np.empty_like(y)
        sk.rhs(0.0, y, params, dydt)
        rates.append(dydt[ly.NB + ly.VX:ly.NB + ly.WZ + 1].copy())
    jump = np.max(np.abs(rates[1] - rates[0]))
    assert jump < 1e-7 * np.max(np.abs(rates[0]))
