"""The compliant model on an assembly of bodies: a colonnade of drum columns carrying epistyle blocks (issue 37).

Each acceptance point of the issue's verification, with its tolerance from its source: exact
rest, the frame's uplift against the rigid frame's closed form, the row sliding as a Coulomb
block against an independent integration, two blocks pushing and letting go through their head
joint, the energy budget, and the glued frame against the rigid `2d-frame` model.
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pipeline.compliant import assemble, integrate, rest_state
from pipeline.compliant.parts import END_FACE, IDENTITY, KIND_BLOCK, Contact, Layout, Part
from pipeline.compliant.colonnade import rectangle_points
from pipeline.dynamics.compliant import layout as ly
from pipeline.dynamics.compliant.layout import GROUND, SHAPE_DISC, SHAPE_RECT
from pipeline.groundmotion import one_sine_pulse
from pipeline.groundmotion.record import GroundMotion
from pipeline.settings import Excitation, ModelSettings
from pipeline.simulate import simulate
from pipeline.structures.colonnade import Colonnade
from pipeline.structures.column import Column
from pipeline.structures.drums import Capital, DrumColumn
from pipeline.units import G

PAPER = Column(0.5, 0.4, 4.0)
CAPITAL = Capital(1.1, 0.3)


def frame(n_columns=2, drums=1, interaxial=2.5, epistyle=0.8):
    """The paper's column (with a capital) in a row carrying an epistyle."""
    return Colonnade(DrumColumn.equal(PAPER, drums, CAPITAL), n_columns, interaxial, epistyle)


def compliant(**kw):
    return ModelSettings(model="3d-compliant", **kw)


def record(acc_x, dt, acc_y=None):
    acc_x = np.asarray(acc_x, dtype=float)
    return GroundMotion.from_arrays(acc_x, np.zeros_like(acc_x) if acc_y is None else acc_y, dt, record_id="test")


def test_a_heavy_epistyle_at_rest_stays_exactly_still():
    """Ten seconds of no ground motion: every state of a 3-column row of 2 drums and a capital under
    two epistyle blocks 1.35 m high is bit for bit its rest state (the rest state is the joints'
    static equilibrium and the holding loads are its joints' forces as the integrator sums them:
    not small, zero; no creep of the epistyle's weight)."""
    colonnade = frame(3, drums=2, epistyle=1.35)
    settings = compliant(contact_damping=1e7)
    asm = assemble(colonnade, settings, 1e7)
    quiet = record(np.zeros(1001), 0.01)
    params = asm.params(np.zeros((1001, 3)), 0.01 / asm.time)
    y0 = rest_state(asm, params, settings.integrator)
    raw = integrate(asm, params, y0, quiet.duration, 0.01, 1, settings, histories=True)
    assert raw.t_mon[-1] * asm.time == pytest.approx(10.0)
    assert np.array_equal(raw.y_end, y0)
    # every history row too (its quaternions renormalised as the rows are: to the last bit, 1e-16)
    kept = np.concatenate([y0[:ly.NB * asm.n_bodies], y0[ly.NB * asm.n_bodies + 2 * asm.points.shape[0]:]])
    np.testing.assert_allclose(raw.hist_y, np.broadcast_to(kept, raw.hist_y.shape), rtol=0, atol=1e-15)


def test_the_frame_uplifts_at_g_tan_alpha_e():
    """Stiff joints (1e12 Pa/m) and high friction, an in-plane ramp from 0.9 to 1.1 g tan(alpha_e) over
    10 s (quasi-static: the joints vibrate at kHz, the frame rocks in seconds): the columns' bases
    reach their rims (the base's centre of pressure past the chord of a rim point's neighbours,
    the rigid models' uplift on a compliant base) within 2 % of the rigid frame's uplift
    acceleration g tan(alpha_e) = g (N m R + M (R + c)) / (N m z_c + M H_t) (docs/model.md, "The
    rigid frame"). The rim criterion is the chord of a rim point's neighbours, R cos(2 pi / S):
    with S = 48 sectors at most 0.9 % early quasi-statically (measured -1.0 %; with S = 24,
    -4.5 %, and the capitals, wider than the shafts' tops, rock on them at +0.8 % and +5.6 %)."""
    colonnade = frame()
    tan_e = math.tan(colonnade.frame.alpha)
    dt, ramp = 0.01, 10.0
    t = np.arange(0.0, ramp + 0.5 * dt, dt)
    acc = (0.9 + 0.2 * t / ramp) * tan_e * G
    s = simulate(colonnade, record(acc, dt), Excitation(), compliant(
        normal_stiffness=1e12, joint_stiffness=1e12, friction=10.0, joint_friction=10.0, tail=0.0, settle_limit=0.0,
        contact_sectors=48), histories=False).summary
    # the frame uplifts when both columns rock on their rims: before, the row's inertia loads the
    # leading column more, and the lighter trailing base reaches its rim first (measured 10 % early)
    bases = [j for j, label in enumerate(s["joint_label"]) if label.startswith("base")]
    assert len(bases) == 2 and s["uplifted"]
    at_uplift = (0.9 + 0.2 * np.max(s["joint_uplift_time"][bases]) / ramp) * tan_e
    assert at_uplift == pytest.approx(tan_e, rel=0.02)


def coulomb_block(acc, dt, mu, duration):
    """An independent Coulomb block on the shaking ground: its displacement relative to the ground [m].

    Sticking while |a_g| <= mu g, sliding at -a_g - mu g sign(v) otherwise; scipy's solve_ivp with
    events at the velocity's zero (where it sticks or reverses) and at the sticking limit."""
    t = np.arange(len(acc)) * dt

    def a_g(time):
        return np.interp(time, t, acc)

    state, now, out_t, out_u = np.zeros(2), 0.0, [0.0], [0.0]
    while now < duration - 1e-12:
        if state[1] == 0.0 and abs(a_g(now)) <= mu * G:  # stuck: until the ground asks more than mu g
            times = np.arange(now, duration, 1e-4)
            over = np.nonzero(np.abs(a_g(times)) > mu * G)[0]
            now = times[over[0]] if over.size else duration
            out_t.append(now)
            out_u.append(state[0])
            continue
        sense = -np.sign(a_g(now)) if state[1] == 0.0 else np.sign(state[1])

        def rhs(_t, y, sense=sense):
            return [y[1], -a_g(_t) - mu * G * sense]

        def stops(_t, y, sense=sense):
            return y[1] if abs(y[1]) > 0 else sense * 1e-300
        stops.terminal, stops.direction = True, -sense
        sol = solve_ivp(rhs, (now, duration), state, events=stops, rtol=1e-10, atol=1e-12, max_step=dt)
        now = sol.t[-1]
        state = np.array([sol.y[0, -1], 0.0 if sol.status == 1 else sol.y[1, -1]])
        out_t += list(sol.t[1:])
        out_u += list(sol.y[0, 1:])
    return np.array(out_t), np.array(out_u)


def test_on_low_ground_friction_the_whole_row_slides_as_the_coulomb_block():
    """Ground friction 0.1, the joints between stones 10, all of them stiff (1e11 Pa/m): a 1-Hz sine of
    0.3 g along the row (above mu g, below the frame's uplift at about 0.24 g, which the sliding
    bases never let it reach) slides the row as one block. Every body's displacement at the end
    equals the independent Coulomb block's to 4 % of its 0.12-m slide. A compliant base under a
    slender column rocks a little as it slides (tilts of 2e-5 to 5e-5 rad), and that changes the
    slide at each of the six stick-slip reversals: measured on this bed, the paper's column alone
    (with its capital) slides 2.9 % more, a frame of 2 monoliths 1.1 % more, this row of 3 columns of
    2 drums 2.5 % less. The bound still tells the friction: the block's slide moves 15 % when mu moves
    5 % (0.139 m at mu = 0.095, 0.104 m at 0.105)."""
    colonnade = frame(3, drums=2)
    dt, duration = 0.005, 3.0
    t = np.arange(0.0, duration + 0.5 * dt, dt)
    acc = 0.3 * G * np.sin(2.0 * math.pi * t)
    run = simulate(colonnade, record(acc, dt), Excitation(), compliant(
        friction=0.1, joint_friction=10.0, normal_stiffness=1e11, joint_stiffness=1e11, tail=0.0, settle_limit=0.0))
    block_t, block_u = coulomb_block(acc, dt, 0.1, duration)
    expected = np.interp(duration, block_t, block_u)
    assert abs(expected) > 0.1  # it really slides, decimetres
    dx = run.histories.drum_dx.isel(time=-1).values
    np.testing.assert_allclose(dx, expected, rtol=0.04)
    assert np.ptp(dx) < 5e-4  # one block: the bodies together to the sway of 5e-5 rad at 4.6 m, 0.23 mm
    assert not run.summary["overturned"] and run.summary["peak_theta"] < 1e-3  # it slides, it does not rock


def two_blocks(gap=0.0):
    """Two stone blocks (1 x 0.6 x 0.5 m) on the ground end to end along x, a head joint between them."""
    m = 2700.0 * 1.0 * 0.6 * 0.5
    inertia = (m * (0.36 + 0.25) / 12.0, m * (1.0 + 0.25) / 12.0, m * (1.0 + 0.36) / 12.0)
    settings = compliant(contact_sectors=8)
    parts = tuple(Part(f"block {k + 1}", KIND_BLOCK, m, inertia, (k * (1.0 + gap), 0.0, 0.25), 0.25, 0.5,
                       0.5 * math.pi, True, (0.5, 0.3, 0.5), -1) for k in range(2))
    contacts = []
    for k in range(2):
        grid = rectangle_points(0.5, 0.3, settings)
        pts = np.column_stack([grid[:, 0], grid[:, 1], np.full(len(grid), -0.25), grid[:, 0], grid[:, 1], grid[:, 2]])
        contacts.append(Contact("bearing", GROUND, k, (k * (1.0 + gap), 0.0, 0.0), IDENTITY, (0.0, 0.0, -0.25),
                                IDENTITY, SHAPE_DISC, (math.inf, 0.0), pts, m, -1, False))
    grid = rectangle_points(0.3, 0.25, settings)
    pts = np.column_stack([np.full(len(grid), -0.5), grid[:, 0], grid[:, 1], grid[:, 0], grid[:, 1], grid[:, 2]])
    contacts.append(Contact("head", 0, 1, (0.5, 0.0, 0.0), END_FACE, (-0.5, 0.0, 0.0), END_FACE, SHAPE_RECT,
                            (0.3, 0.25), pts, m, -1, False))
    return Layout(parts, tuple(contacts), (0, 1), (0, 1), 0.5), settings


@pytest.mark.parametrize("sense", [1.0, -1.0])
def test_two_blocks_transmit_a_push_and_separate_without_pulling(sense):
    """Block 1 sent at 0.2 m/s along the row on ground of friction 0.05, block 2 at rest end to end with
    it (touching, pressed by nothing). Towards block 2: the head joint pushes, block 2 takes off
    at most of block 1's speed (the joint's dashpots lose some of the impact) and travels a few
    centimetres before friction stops it; the two part, the joint ends open. Away from block 2:
    the head joint cannot pull, and block 2 does not move at all, bit for bit."""
    layout, _ = two_blocks()
    settings = ModelSettings(model="3d-compliant", contact_sectors=8, friction=0.05, joint_friction=0.05,
                             contact_damping=1e6)
    asm = assemble(layout, settings, settings.contact_damping)
    params = asm.params(np.zeros((101, 3)), 0.01 / asm.time)
    y0 = rest_state(asm, params, settings.integrator)
    y = y0.copy()
    speed = math.sqrt(G * asm.length)  # the kernel's unit of velocity [m/s]
    y[ly.VX] = sense * 0.2 / speed
    raw = integrate(asm, params, y, 1.0, 0.001, 1, settings, histories=True)
    moved = (raw.y_end[[ly.X, ly.NB + ly.X]] - y0[[ly.X, ly.NB + ly.X]]) * asm.length
    if sense > 0:
        v2 = raw.hist_y[:, ly.NB + ly.VX] * speed
        assert 0.1 < v2.max() <= 0.2  # the push went through, no faster than it came
        assert moved[1] > 0.01  # block 2 slid centimetres
        assert (raw.y_end[ly.NB + ly.X] - raw.y_end[ly.X]) * asm.length > 1.0  # apart: the joint opened
    else:
        assert np.array_equal(raw.y_end[ly.NB:2 * ly.NB], y0[ly.NB:2 * ly.NB])
        assert moved[0] < -0.01


def test_energy_budget_of_a_colonnade_is_bounded_as_for_stacks():
    """A 2-column row of 2 drums and a capital under a two-component pulse that rocks it: the fixed-step
    integrator's energy budget closes to 5 % of the ground's work (its first-order error, as for
    drum stacks: tests/test_structures_drums.py), and the adaptive reference's to 1e-6."""
    colonnade = frame(2, drums=2)
    pulse = one_sine_pulse(4.0, 0.5, dt=0.005, duration=1.5)
    pair = GroundMotion.from_arrays(pulse.acc_x, 0.5 * pulse.acc_x, pulse.dt, record_id="pulse")
    for integrator, tolerance in (("semi-implicit", 0.05), ("dopri5", 1e-6)):
        s = simulate(colonnade, pair, Excitation(angle=20.0), compliant(integrator=integrator, tail=1.0,
                                                                        settle_limit=0.0), histories=False).summary
        assert s["uplifted"] and s["work_ground"] > 0.0
        assert abs(s["energy_balance_error"]) < tolerance * s["work_ground"], integrator


def first_landing_after_peak(response):
    """The rigid run's peak comes before its first landing (no restitution enters the peak)."""
    return response.impacts.shape[0] == 0 or response.impacts[0, 0] > response.summary["peak_time"]


def test_glued_frame_converges_to_the_rigid_frame():
    """A 2-column row of monolithic shafts whose capitals are no wider than their tops (c = r: the epistyle's
    far edge over the shaft's rim, so the capital turns with its shaft as the rigid frame's glued
    one does), its joints rough (friction 10), under an in-plane half-sine push (2.5 g tan(alpha_e),
    0.5 s) that rocks it to a peak of half its critical tilt before its first landing: the
    compliant frame's peak tilt tends to the ideal rigid `2d-frame`'s (point contacts rolling
    without slip) as the joints stiffen, as a single column's does (tests/test_compliant.py: the
    compliant lead goes as k^-1/2, +4.2 % at 1e11 and +0.5 % at 1e13 Pa/m for the paper's column).
    No landing comes before the peak, so the restitutions (the frame's by angular momentum, the
    joints' dashpots calibrated to the monolith's) do not enter. Asserted: within 2 % at 1e13
    Pa/m, and the k^-1/2 rate from 1e11 (a factor of 10, accepted 6 to 16)."""
    colonnade = Colonnade(DrumColumn.equal(PAPER, 1, Capital(0.8, 0.3)), 2, 2.5, 0.8)
    dt, push = 0.002, 0.5
    t = np.arange(0.0, 3.0, dt)
    acc = np.where(t <= push, 2.5 * math.tan(colonnade.frame.alpha) * G * np.sin(math.pi * t / push), 0.0)
    motion = record(acc, dt)
    rigid = simulate(colonnade, motion, Excitation(), ModelSettings(
        model="2d-frame", normal_stiffness=math.inf, friction=math.inf, tail=0.0, settle_limit=0.0))
    peak = rigid.summary["peak_theta"]
    assert 0.3 * colonnade.frame.alpha < peak < colonnade.frame.alpha  # a real rocking excursion
    assert first_landing_after_peak(rigid)
    errors = []
    for kn in (1e11, 1e13):
        soft = simulate(colonnade, motion, Excitation(), compliant(normal_stiffness=kn, joint_stiffness=kn,
                                                                   friction=10.0, joint_friction=10.0, tail=0.0,
                                                                   settle_limit=0.0), histories=False).summary
        errors.append(soft["peak_theta"] / peak - 1.0)
    assert abs(errors[1]) < 0.02, errors
    assert 6 < errors[0] / errors[1] < 16, errors


def _turned(y, asm, b, angle, pivot):
    """State y with body b turned rigidly by angle [rad] about the y axis through pivot [L] (ground frame)."""
    o = ly.NB * b
    c, s = math.cos(angle), math.sin(angle)
    dx, dz = y[o + ly.X] - pivot[0], y[o + ly.Z] - pivot[2]
    y[o + ly.X], y[o + ly.Z] = pivot[0] + c * dx + s * dz, pivot[2] - s * dx + c * dz
    qw, qx, qy, qz = y[o + ly.QW:o + ly.QZ + 1]
    hw, hy = math.cos(0.5 * angle), math.sin(0.5 * angle)  # about y, composed on the left
    y[o + ly.QW:o + ly.QZ + 1] = (hw * qw - hy * qy, hw * qx - hy * qz, hw * qy + hy * qw, hw * qz + hy * qx)


def test_a_body_has_fallen_off_its_support_only_measured_on_that_support():
    """The fall event of a body resting on another is its centre's distance from the supporting face,
    measured on the supporting body: a capital carried down by its drum tilted 40 deg about the
    drum's rim has not fallen (measured on the ground it had: its centre 0.65 m lower than at rest,
    more than its 0.3-m height, and a run named the capital as the body that fell while the top drum
    was still falling, 0.41 s before the drum lay down); the same capital slid 1.2 m sideways off the
    drum's top and dropped 0.31 m has (0.01 m past its height)."""
    column = DrumColumn.equal(PAPER, 1, CAPITAL)
    settings = compliant(contact_sectors=16)
    asm = assemble(column, settings, 1e7)
    params = asm.params(np.zeros((11, 3)), 0.01 / asm.time)
    y0 = rest_state(asm, params, settings.integrator)
    n = asm.n_bodies
    g = np.empty(2 * n)
    from pipeline.dynamics.compliant.assembly import event_values

    event_values(y0, asm.bodies, asm.joints, g)
    assert np.all(g < 0.0)  # the premise: at rest nothing has fallen
    tilted = y0.copy()
    rim = (0.5 / asm.length, 0.0, 0.0)  # the drum's base rim, on the ground
    for b in range(n):  # drum and capital together, as one
        _turned(tilted, asm, b, math.radians(40.0), rim)
    event_values(tilted, asm.bodies, asm.joints, g)
    capital_z = tilted[ly.NB + ly.Z] * asm.length
    assert capital_z < y0[ly.NB + ly.Z] * asm.length - 0.3  # the premise: lower than at rest by its height
    assert g[n + 1] < 0.0 and g[1] < 0.0  # not fallen, not lying
    off = y0.copy()
    off[ly.NB + ly.X] += 1.2 / asm.length
    off[ly.NB + ly.Z] -= 0.31 / asm.length
    event_values(off, asm.bodies, asm.joints, g)
    # to the joint's static penetration at rest (the rest state sinks it by 2e-6 m)
    assert g[n + 1] == pytest.approx(0.01 / asm.length, abs=1e-5)


def test_the_file_of_a_row_that_fell_names_the_body_that_fell_first(tmp_path):
    """Issue 47, item 1: a compliant colonnade's file names the body that fell first (overturn_body, as
    body_label names overturn_drum) and every joint (joint_label); its title names the row and the model (before:
    "a free-standing column", no overturn_body, no joint_label in the file)."""
    import xarray as xr

    from pipeline.dataset import histories_file, write_netcdf

    row = Colonnade(DrumColumn(PAPER, capital=CAPITAL), 2, 2.5, 0.8)
    run = simulate(row, one_sine_pulse(6.0, 1.0, dt=0.01, record_id="pulse"), Excitation(),
                   compliant(contact_sectors=8, tail=3.0))
    assert run.summary["overturned"]  # the premise
    write_netcdf(histories_file([run.histories], column="row", record="pulse", summaries=[run.summary]),
                 tmp_path / "row.nc")
    with xr.open_dataset(tmp_path / "row.nc") as ds:
        cell = ds.sel(column="row", record="pulse", model="3d-compliant")
        fell = str(cell["overturn_body"].values)
        assert fell == run.summary["overturn_body"] == str(ds["body_label"].values[int(cell["overturn_drum"])])
        assert fell == "column 2 shaft"
        assert len(ds["joint_label"]) == row.n_joints and str(ds["joint_label"].values[-1]) == \
            "capital 2 / epistyle block 1"
        assert ds.attrs["title"] == ("Response to ground motion of a colonnade of 2 monolithic columns with capitals "
                                     "carrying 1 epistyle block run by the 3D compliant drums on joints (3d-compliant)")
