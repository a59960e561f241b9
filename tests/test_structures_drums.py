"""Multi-drum columns on the compliant kernel: the acceptance points of issue 13."""

import math

import numpy as np
import pytest

from pipeline.cli import main
from pipeline.structures.drums import Capital, DrumColumn, named_drum_column
from pipeline.errors import InputError
from pipeline.structures.column import Column
from pipeline.groundmotion import clough_penzien, one_sine_pulse, rectangular_pulse
from pipeline.settings import Excitation, ModelSettings
from pipeline.simulate import simulate
from pipeline.units import G

from test_compliant import first_peak  # noqa: E402

PAPER = Column(0.5, 0.4, 4.0)


def compliant(**options):
    return ModelSettings(model="3d-compliant", **options)


@pytest.mark.parametrize("pulse", ["rectangular", "one-sine"])
def test_four_glued_drums_rock_like_the_monolith(pulse):
    """Joint friction 10 and bed joints 100 times stiffer than the base: the top drum's first
    rocking peak is the monolith's within 2 % (measured +0.02 % under the rectangular pulse;
    with joints only 10 times stiffer than the base +0.17 %: their own compliance).

    The first peak, before any landing: at a landing the drums of a stack, whose joints carry
    no tension, rattle on one another and lose more than the monolith (the second peak of the
    response to a one-sine pulse of 1.5 a_up is 18 % lower): that is the multi-drum physics, not glue.
    """
    a_up, p = PAPER.uplift_acceleration(), PAPER.frequency_parameter()
    if pulse == "rectangular":
        record = rectangular_pulse(1.5 * a_up, round(1.0 / p, 2), dt=0.001, duration=3 * round(1.0 / p, 2))
    else:
        record = one_sine_pulse(2.0 * a_up, round(math.pi / p, 2), dt=0.001, duration=1.5 * round(math.pi / p, 2))
    options = dict(friction=2.0, tail=0.0, contact_sectors=16, output_step=0.001)
    mono = simulate(PAPER, record, Excitation(), compliant(**options)).histories
    stack = simulate(DrumColumn.equal(PAPER, 4), record, Excitation(),
                     compliant(joint_friction=10.0, joint_stiffness=1e12, **options))
    reference = first_peak(mono.theta.values)
    assert reference > 0.3 * PAPER.critical_tilt
    assert first_peak(stack.histories.theta.values) == pytest.approx(reference, rel=0.02)
    for drum in range(4):
        assert first_peak(stack.histories.drum_theta.values[:, drum]) == pytest.approx(reference, rel=0.02)


def test_top_drum_slides_on_a_drum_that_stays_put():
    """Two squat drums (R = r = 1 m, 1 m each), base friction 0.8, joint friction 0.3, 0.6 g for
    0.5 s: the top drum slides A (A - mu g) t_d^2 / (2 mu g) = 0.7355 m on the bottom one
    (measured 0.7399, +0.6 %: +0.2 % from the record's linear edges, the rest the joint's elastic
    shear and the top drum's rim running off the edge of the one below, whose band of support
    pulls it back a little), within 2 %; the bottom drum (0.9 m g of demand on 1.6 m g of friction) moves only
    elastically."""
    A, mu, td = 0.6 * G, 0.3, 0.5
    pulse = rectangular_pulse(A, td, dt=0.001, duration=1.5)
    r = simulate(DrumColumn.equal(Column(1.0, 1.0, 2.0), 2), pulse, Excitation(),
                 compliant(friction=0.8, joint_friction=mu, tail=0.5))
    s, h = r.summary, r.histories
    expected = A * (A - mu * G) * td**2 / (2 * mu * G)
    assert s["joint_slip"][1] == pytest.approx(expected, rel=0.02)
    assert abs(h.drum_dx.values[-1, 1]) == pytest.approx(expected, rel=0.02)
    assert s["residual_displacement"] < 1e-5 and s["slip"] < 1e-5
    assert s["joint_slip"][0] == s["residual_displacement"]  # joint 0: the base on the ground
    assert abs(s["joint_twist"][1]) < 1e-9 and s["joint_opening"][1] < 1e-5
    # the dislocation measure: the bed joint's slip over its diameter, 2 m
    assert s["dislocation_ratio"] == s["joint_slip"][1] / s["joint_diameter"][1]
    np.testing.assert_allclose(s["joint_diameter"], [2.0, 2.0], rtol=1e-15)
    assert not s["uplifted"]


def _quaternion(axis, angle):
    """(w, x, y, z) of a rotation by ``angle`` [rad] about a unit axis."""
    return np.concatenate([[math.cos(0.5 * angle)], math.sin(0.5 * angle) * np.asarray(axis, dtype=float)])


def _product(p, q):
    """Quaternion product p q (rotation q first)."""
    w1, v1, w2, v2 = p[0], p[1:], q[0], q[1:]
    return np.concatenate([[w1 * w2 - v1 @ v2], w1 * v2 + w2 * v1 + np.cross(v1, v2)])


def _matrix(q):
    from scipy.spatial.transform import Rotation

    return Rotation.from_quat([q[1], q[2], q[3], q[0]]).as_matrix()


def test_joint_dislocations_of_a_known_state():
    """Two drums of the paper's column placed by hand: drum 0 shifted, turned and tilted on the
    ground, drum 1 slid, twisted, tilted and lifted on drum 0 (in drum 0's frame). Every measure
    is the closed form of that placement, to round-off (1e-12 m and rad)."""
    from pipeline.compliant import assemble, dislocation_ratio, joint_dislocations, rest_state
    from pipeline.dynamics.compliant import layout as sk

    asm = assemble(DrumColumn.equal(PAPER, 2), compliant(), damping=0.0)
    params = asm.params()
    y = rest_state(asm, params, "dopri5")
    L = asm.length
    delta = asm.joints[0, sk.J_DELTA] * L  # static penetration of the base [m]
    shift0, turn0, tilt0 = np.array([0.03, -0.02]), 0.4, 0.05  # drum 0 on the ground [m], [rad]
    slip, twist, tilt, lift = np.array([0.05, 0.012]), math.radians(15.0), 0.1, 0.002  # drum 1 on drum 0
    q0 = _product(_quaternion([0, 0, 1], turn0), _quaternion([1, 0, 0], tilt0))
    R0 = _matrix(q0)
    base0 = np.array([shift0[0], shift0[1], -delta]) / L
    y[sk.X:sk.Z + 1] = base0 + R0 @ [0.0, 0.0, asm.bodies[0, sk.B_ZC]]
    y[sk.QW:sk.QZ + 1] = q0
    q1 = _product(q0, _product(_quaternion([1, 0, 0], tilt), _quaternion([0, 0, 1], twist)))
    R1 = _matrix(q1)
    base1 = base0 + R0 @ [0.0, 0.0, asm.bodies[0, sk.B_HEIGHT]] + R0 @ np.array([slip[0], slip[1], lift]) / L
    o = sk.NB
    y[o + sk.X:o + sk.Z + 1] = base1 + R1 @ [0.0, 0.0, asm.bodies[1, sk.B_ZC]]
    y[o + sk.QW:o + sk.QZ + 1] = q1
    d = joint_dislocations(asm, params, y)
    np.testing.assert_allclose(d["joint_slip"], [np.hypot(*shift0), np.hypot(*slip)], rtol=0, atol=1e-12)
    np.testing.assert_allclose(d["joint_twist"], [turn0, twist], rtol=0, atol=1e-12)
    np.testing.assert_allclose(d["joint_tilt"], [tilt0, tilt], rtol=0, atol=1e-12)
    # the widest gaps: drum 0's rim point at 90 deg, raised by R sin(tilt0) from its penetration;
    # drum 1's rim point the twist brings to the tilt's high side (75 deg of 24 sectors + 15 deg)
    r1 = PAPER.R + (PAPER.r - PAPER.R) * 0.5  # radius at the cut, 2 m up [m]
    np.testing.assert_allclose(d["joint_opening"], [PAPER.R * math.sin(tilt0) - delta, lift + r1 * math.sin(tilt)],
                               rtol=0, atol=1e-12)
    diameters = DrumColumn.equal(PAPER, 2).joint_diameters()
    np.testing.assert_allclose(diameters, [2 * PAPER.R, 2 * r1], rtol=1e-15)
    assert dislocation_ratio(d["joint_slip"], diameters) == pytest.approx(np.hypot(*slip) / (2 * r1), rel=1e-12)
    assert dislocation_ratio([0.1], [1.0]) == 0.0  # a monolith has no bed joint to dislocate


def test_energy_budget_of_a_stack():
    """Three drums with anathyrosis and their own friction under a two-component record: with the
    adaptive reference (DOPRI5) the stack's energy budget closes to 1e-6 of the work (measured -8e-10) while drums rock and slide.
    (The capital's terms are checked by the energy-rate identity, tests/dynamics/compliant/test_stack.py.)
    """
    motion = clough_penzien(3, duration=3.0, dt=0.01, pga=0.45 * G, omega_f=3.0)
    s = simulate(DrumColumn.equal(PAPER, 3), motion, Excitation(angle=23.0),
                 compliant(joint_friction=(0.5, 0.6), anathyrosis=0.6, contact_sectors=16, tail=0.5,
                           integrator="dopri5"),
                 histories=False).summary
    assert s["n_drums"] == 3 and len(s["drum_peak_theta"]) == 3
    assert s["energy_friction"] > 0 and s["energy_damping"] > 0 and max(s["joint_slip"]) > 1e-4
    assert abs(s["energy_balance_error"]) < 1e-6 * s["work_ground"]


def test_fixed_step_energy_budget_of_a_stack():
    """The same stack with the springs at the step's start (the default before issue 37's speed
    work, numerics springs = "explicit", step_safety 0.5): the budget's error is the scheme's, first
    order in the step. Measured -2.7e-3 of the work at the default step (0.361 ms), then
    -2.2e-3, -1.24e-3 and -6.5e-4 at a half, a quarter and an eighth of it: the ratios 0.57
    and 0.53 of the last two halvings are first order (0.5); the first one's, 0.81, is not the
    scheme's alone (at two thirds of the step the error is -2.7e-3 again: the stack's rocking
    and slip differ a little from run to run at coarse steps). Asserted: within 1 % of the work
    at the default step (a guard on the measured value), and the two finer halvings' ratios in
    0.35-0.7."""
    motion = clough_penzien(3, duration=3.0, dt=0.01, pga=0.45 * G, omega_f=3.0)
    stack = DrumColumn.equal(PAPER, 3)
    options = dict(joint_friction=(0.5, 0.6), anathyrosis=0.6, contact_sectors=16, tail=0.5,
                   numerics=(("springs", "explicit"), ("step_safety", 0.5)))
    first = simulate(stack, motion, Excitation(angle=23.0), compliant(**options), histories=False).summary
    assert first["energy_friction"] > 0 and first["energy_damping"] > 0 and max(first["joint_slip"]) > 1e-4
    assert abs(first["energy_balance_error"]) < 0.01 * first["work_ground"]
    errors = []
    for fraction in (0.5, 0.25, 0.125):
        s = simulate(stack, motion, Excitation(angle=23.0), compliant(step=fraction * first["step"], **options),
                     histories=False).summary
        errors.append(s["energy_balance_error"] / s["work_ground"])
    assert 0.35 < errors[1] / errors[0] < 0.7
    assert 0.35 < errors[2] / errors[1] < 0.7


def test_energy_budget_of_a_stack_has_no_floor():
    """The budget of a three-drum stack closes to the adaptive integrator's own error, 1e-8 of the work.

    Drums rock and slip back and forth on their joints, so shear springs keep leaving the
    friction cone and unloading into it. Booked as the capped force's 1/2 (mu f)^2/k_s beyond
    the cone, the elastic energy had a kink there and friction a jump in its rate at every
    slip reversal, which the integrator's accumulator missed by up to 1e-9 M g L each whatever
    the tolerance (1.2e-7 of the work here; a 10-drum column under FEMA-FF-01 missed the
    issue's 1e-6 with 2.6e-6). With the spring's own 1/2 k_s |u|^2, a smooth function of the
    state, this run closes to 2.7e-10 of the work at the default tolerances (and the error
    now follows them: 2.5e-8 of the work at atol 1e-11 on a stack), so 1e-8 leaves a factor
    ~40 for other platforms' round-off in a chaotic run and fails the old booking by ~12.
    """
    motion = clough_penzien(3, duration=3.0, dt=0.01, pga=0.45 * G, omega_f=3.0)
    s = simulate(DrumColumn.equal(PAPER, 3), motion, Excitation(angle=23.0),
                 compliant(joint_friction=0.6, contact_sectors=16, tail=0.5, integrator="dopri5"),
                 histories=False).summary
    assert s["energy_friction"] > 0.05 * s["work_ground"] and max(s["joint_slip"][1:]) > 1e-3
    assert abs(s["energy_balance_error"]) < 1e-8 * s["work_ground"]


def test_drum_geometry_and_bad_input():
    stack = DrumColumn.from_heights(PAPER, [1.0, 1.5, 1.5])
    assert stack.cuts == (1.0, 2.5) and stack.n_drums == 3
    drums = stack.drums()
    assert drums[0].R == 0.5 and drums[-1].r == 0.4 and drums[1].R == drums[0].r == pytest.approx(0.475)
    # the bearing faces are the kernel's: its contact points reach the rim of each (capital included)
    from pipeline.compliant import assemble
    from pipeline.dynamics.compliant import layout as sk

    capped = DrumColumn(PAPER, stack.cuts, Capital(1.2, 0.5))
    asm = assemble(capped, compliant(), damping=0.0)
    rims = [2 * np.hypot(asm.points[a:b, sk.P_X], asm.points[a:b, sk.P_Y]).max() * asm.length
            for a, b in zip(asm.joint_start[:-1], asm.joint_start[1:])]
    np.testing.assert_allclose(capped.joint_diameters(), rims, rtol=1e-14)
    np.testing.assert_allclose(capped.joint_diameters(), [1.0, 0.95, 0.875, 0.8], rtol=1e-14)
    with pytest.raises(InputError, match="add up to 3.5 m"):
        DrumColumn.from_heights(PAPER, [1.0, 2.5])
    with pytest.raises(InputError, match="increase strictly"):
        DrumColumn(PAPER, (2.0, 1.0))
    with pytest.raises(InputError, match="whole number"):
        DrumColumn.equal(PAPER, 0)
    with pytest.raises(InputError, match="capital side"):
        Capital(-1.0, 0.5)


def test_named_parthenon_column_has_drums_and_a_capital():
    stack = named_drum_column("parthenon-peristyle")
    assert stack.n_drums == 11 and stack.capital is not None and stack.n_bodies == 12
    assert stack.column.h + stack.capital.height == pytest.approx(10.43)
    assert named_drum_column("paper").n_drums == 1


def test_cli_runs_drums(tmp_path):
    out = tmp_path / "drums.nc"
    assert main(["simulate", "--column", "1,1,2", "--model", "3d-compliant", "--drums", "2", "--friction", "0.8",
                 "--joint-friction", "0.3", "--record", "FEMA-FF-01", "--scale", "0.5", "--tail", "0",
                 "--out", str(out)]) == 0
    import xarray as xr

    with xr.open_dataset(out) as ds:
        assert ds.drum_theta.dims[-2:] == ("time", "drum") and ds.drum.size == 2
        assert ds.drum_dx.attrs["units"] == "m" and ds.attrs["n_drums"] == 2
    assert main(["simulate", "--column", "1,1,2", "--drums", "2", "--record", "FEMA-FF-01", "--out",
                 str(out)]) == 2  # a rigid model cannot take drums


def test_fixed_step_energy_budget_of_a_stack_with_the_springs_at_the_step_end():
    """The same stack with the default scheme (the springs at the step's end, at the explicit limit,
    0.722 ms here). Measured +1.1e-3 of the work at the default step, then -2.8e-3, -2.3e-3, -1.6e-3
    and -8.0e-4 at a half, a quarter, an eighth and a sixteenth of it: first order from the quarter
    on (ratios 0.67 and 0.51; the coarse steps' rocking and slip differ a little from run to run,
    as with the springs at the start). Asserted: within 1 % of the work at the default step (a guard
    on the measured value), and the error at a sixteenth of the step 0.1-0.6 of the error at a
    quarter (first order 0.25, measured 0.34)."""
    motion = clough_penzien(3, duration=3.0, dt=0.01, pga=0.45 * G, omega_f=3.0)
    stack = DrumColumn.equal(PAPER, 3)
    options = dict(joint_friction=(0.5, 0.6), anathyrosis=0.6, contact_sectors=16, tail=0.5)
    first = simulate(stack, motion, Excitation(angle=23.0), compliant(**options), histories=False).summary
    assert first["energy_friction"] > 0 and first["energy_damping"] > 0 and max(first["joint_slip"]) > 1e-4
    assert abs(first["energy_balance_error"]) < 0.01 * first["work_ground"]
    errors = [simulate(stack, motion, Excitation(angle=23.0), compliant(step=fraction * first["step"], **options),
                       histories=False).summary for fraction in (0.25, 0.0625)]
    assert 0.1 < (errors[1]["energy_balance_error"] / errors[1]["work_ground"]) / (
        errors[0]["energy_balance_error"] / errors[0]["work_ground"]) < 0.6
