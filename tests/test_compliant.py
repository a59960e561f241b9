"""The compliant-contact model "3d-compliant": the acceptance points of issue 10.

Each test states where its tolerance comes from; docs/model.md ("The compliant-contact model")
has the numbers behind them.
"""

import math

import numpy as np
import pytest

from pipeline.compliant import calibrated_damping, critical_damping, planar_restitution
from pipeline.dataset import VARIABLES
from pipeline.structures.drums import DrumColumn
from pipeline.errors import InputError
from pipeline.structures.column import Column
from pipeline.groundmotion import GroundMotion, clough_penzien, load, one_sine_pulse, rectangular_pulse
from pipeline.settings import Excitation, ModelSettings, housner_restitution
from pipeline.simulate import simulate
from pipeline.units import G

PAPER = Column(0.5, 0.4, 4.0)
SHAPES = {"paper h/R 8": PAPER, "cylinder h/R 12": Column(0.4, 0.4, 4.8), "squat h/R 4": Column(0.6, 0.5, 2.4)}


def compliant(**options):
    return ModelSettings(model="3d-compliant", **options)


def first_peak(theta, window=50):
    """The first local maximum of a tilt history above 1e-3 rad, refined by a parabola."""
    for i in range(1, len(theta) - 1):
        if theta[i] > 1e-3 and theta[i] >= theta[max(0, i - window):i + window + 1].max():
            a, b, c = theta[i - 1:i + 2]
            curv = a - 2 * b + c
            return b - 0.125 * (c - a) ** 2 / curv if curv < 0 else b
    raise AssertionError("no rocking peak")


def _pulses(column):
    a_up, p = column.uplift_acceleration(), column.frequency_parameter()
    tp, td = round(math.pi / p, 2), round(1.0 / p, 2)
    return {"one-sine": one_sine_pulse(2.0 * a_up, tp, dt=0.001, duration=2 * tp),
            "rectangular": rectangular_pulse(1.5 * a_up, td, dt=0.001, duration=3 * td)}


def rigid_first_peak(column, motion):
    """First rocking peak of the rigid column, the paper's point contact rolling without slip.

    Planar rocking on a rim point, written out here independently of both kernels: at rest
    until |a| z_cm = g R (the root on the linearly interpolated record), then, leaning away
    from the acceleration of sign s at uplift,
    ``I_P theta'' = m l (s a(t) cos(alpha - theta) - g sin(alpha - theta))`` with
    l = sqrt(R^2 + z_cm^2), alpha = atan(R / z_cm), up to theta' = 0 (no landing before it).
    """
    from scipy.integrate import solve_ivp

    a = np.asarray(motion.acc_x, dtype=np.float64)
    t = np.arange(a.size) * motion.dt
    a_up = column.uplift_acceleration()
    k = int(np.argmax(np.abs(a) >= a_up))
    t_up = 0.0 if k == 0 else t[k - 1] + (a_up - abs(a[k - 1])) / (abs(a[k]) - abs(a[k - 1])) * motion.dt
    sign = math.copysign(1.0, a[k])
    length, alpha = column.contact_to_cm_distance, column.critical_tilt
    inertia = column.inertia_transverse_hat * column.R**2  # I_P / m

    def rhs(time, y):
        acc = sign * np.interp(time, t, a, right=0.0)
        return [y[1], length * (acc * math.cos(alpha - y[0]) - G * math.sin(alpha - y[0])) / inertia]

    def turning(time, y):
        return y[1] if y[0] > 1e-9 else 1.0  # not the start, where theta' = theta'' = 0

    turning.terminal, turning.direction = True, -1
    sol = solve_ivp(rhs, (t_up, t[-1] + 5.0), [0.0, 0.0], method="DOP853", rtol=1e-11, atol=1e-13,
                    events=turning, max_step=motion.dt)
    assert sol.status == 1 and sol.y[0, -1] > 0
    return sol.y[0, -1]


@pytest.mark.parametrize("shape", list(SHAPES))
def test_converges_to_the_rigid_model_as_the_joint_stiffens(shape):
    """Planar pulses along a row of contact points: the first rocking peak tends to the rigid one.

    The compliant column starts to rock through an elastic phase whose duration goes as
    k_n^-1/2, and so does its lead over the rigid column (measured sequence, paper column,
    one-sine: +13.9, +4.2, +1.5, +0.5, +0.16 % at 1e10 ... 1e14 Pa/m). Asserted: within 1 % at
    1e14 Pa/m (measured <= 0.4 %), and the k^-1/2 rate between 1e12 and 1e14 (a factor of 10,
    accepted 6 to 16) so that the agreement is convergence, not coincidence. Friction 2: the
    rigid column does not slide. The first peak comes before any landing, so no restitution
    enters; the rigid reference (:func:`rigid_first_peak`, the paper's point contact rolling
    without slip) agrees with the rigid 2d model where that runs with a point contact.
    """
    column = SHAPES[shape]
    for name, pulse in _pulses(column).items():
        ref = rigid_first_peak(column, pulse)
        assert 0.3 < ref / column.critical_tilt < 1.0  # a real rocking excursion
        errors = []
        for kn in (1e12, 1e14):
            r = simulate(column, pulse, Excitation(), compliant(normal_stiffness=kn, friction=2.0, tail=1.0,
                                                                  output_step=0.001))
            errors.append(first_peak(r.histories.theta.values) / ref - 1)
        assert abs(errors[1]) < 0.01, (name, errors)
        assert 6 < errors[0] / errors[1] < 16, (name, errors)


@pytest.mark.parametrize("shape", list(SHAPES))
def test_the_rigid_reference_is_the_rigid_model(shape):
    """The independent first peak equals the rigid 2d and 3d models' with a point contact.

    Tolerance 1e-4: two integrations of one ODE at rtol <= 1e-9, the kernels starting at their
    contact tilt (1e-7 rad) and the peak read from a 1 ms grid by a parabola (measured <= 5e-6).
    The whole run must succeed: the cylinder and the squat column overturn afterwards, where
    infinite friction and lift-off contradict each other (tests/dynamics/test_contact_physics.py).
    """
    column = SHAPES[shape]
    for name, pulse in _pulses(column).items():
        ref = rigid_first_peak(column, pulse)
        for model in ("2d", "3d"):
            rigid = simulate(column, pulse, Excitation(), ModelSettings(
                model=model, normal_stiffness=math.inf, friction=math.inf, tail=1.0, output_step=0.001))
            assert first_peak(rigid.histories.theta.values) == pytest.approx(ref, rel=1e-4), (name, model)


def test_restitution_calibrated_to_a_reachable_target_holds_within_two_percent():
    """The damping found for e = 0.96 (released at 0.3 theta_crit) gives it at other amplitudes.

    Reachable at the default step: undamped the monolith lands with 0.967, critically damped with
    0.950 (measured). The compliant restitution varies with the release tilt by ~0.4 % from 0.15
    to 0.6 theta_crit (measured 0.964 and 0.960), well inside the 2 % asked.
    """
    settings = compliant()
    damping, reached = calibrated_damping(PAPER, settings, 0.96)
    assert reached == pytest.approx(0.96, abs=1e-4)  # Brent's tolerance on the damping ratio
    assert 0 < damping < critical_damping(PAPER, settings)
    for amplitude in (0.15, 0.6):
        assert planar_restitution(PAPER, settings, damping, amplitude) == pytest.approx(0.96, rel=0.02)


def test_a_flat_base_cannot_lose_what_the_rigid_point_impulse_loses():
    """The rigid model's default restitution 1 - 2/I_y (0.901 for the paper column) is out of reach.

    A column landing flat on a disc of contact points is caught by the whole landing side,
    not by the opposite rim point alone as the rigid impact law assumes: even at critical
    damping it keeps e = 0.96 (the impulse acts about half-way out, not at the rim; 0.934
    with contact on the rim alone): measured 0.960 at fine steps, 0.950 at the default step
    (the springs at the step's end damp the landing a little themselves). The default
    calibration then takes the most dissipative damping it considers and reports the
    restitution it reached.
    """
    settings = compliant()
    damping, reached = calibrated_damping(PAPER, settings)  # target: housner_restitution
    assert damping == pytest.approx(critical_damping(PAPER, settings))
    assert 0.94 < reached < 0.97 and reached > housner_restitution(PAPER) + 0.04
    # damping does lower it, monotonically, from nearly elastic (undamped 0.967 and at 0.3 of
    # critical 0.958 at the default step; 0.994 undamped with the springs at the step's start)
    e = [planar_restitution(PAPER, settings, z * critical_damping(PAPER, settings)) for z in (0.0, 0.3)]
    assert e[0] > 0.96 and e[0] > e[1] > reached


def test_flat_sliding_of_a_squat_cylinder():
    """R = r = h = 1 m, mu = 0.3, rectangular pulse 0.6 g for 0.5 s: slides A (A - mu g) t_d^2 / (2 mu g).

    Closed form 0.7355 m; the record's linear edges lengthen the pulse by half a sample
    (+0.2 %, measured 0.7371 m); asserted within 1 %. It does not rock: uplift needs 2 g.
    """
    column = Column(1.0, 1.0, 1.0)
    A, mu, td = 0.6 * G, 0.3, 0.5
    pulse = rectangular_pulse(A, td, dt=0.001, duration=1.5)
    s = simulate(column, pulse, Excitation(), compliant(friction=mu, tail=0.5), histories=False).summary
    expected = A * (A - mu * G) * td**2 / (2 * mu * G)
    assert expected == pytest.approx(0.7355, abs=1e-4)
    assert s["residual_displacement"] == pytest.approx(expected, rel=0.01)
    assert s["slip"] == pytest.approx(s["residual_displacement"], rel=1e-3)  # all of it by sliding
    assert s["sliding_onset"] and not s["uplifted"] and s["peak_theta"] < 1e-5
    assert s["peak_mu_mob"] == pytest.approx(mu, rel=1e-3)


def coulomb_block(acc_x, acc_y, dt_record, mu, duration, h=1e-5):
    """Independent Coulomb sliding block on the ground, relative to it (Moreau's implicit step).

    v' = -a_g + friction; each step the friction impulse up to mu g h either stops the
    relative velocity (stick) or takes mu g h off its magnitude (slip). First order in h.
    """
    n = int(round(duration / h))
    mid = (np.arange(n) + 0.5) * h
    t_rec = np.arange(len(acc_x)) * dt_record
    gx = np.interp(mid, t_rec, acc_x, right=0.0)
    gy = np.interp(mid, t_rec, acc_y, right=0.0)
    v, x = np.zeros(2), np.zeros(2)
    path = np.zeros((n + 1, 2))
    impulse = mu * G * h
    for i in range(n):
        trial = v - h * np.array([gx[i], gy[i]])
        speed = math.hypot(trial[0], trial[1])
        new = np.zeros(2) if speed <= impulse else trial * (1.0 - impulse / speed)
        x = x + 0.5 * h * (v + new)
        v = new
        path[i + 1] = x
    return np.arange(n + 1) * h, path


def test_bidirectional_sliding_follows_an_independent_coulomb_block():
    """The base's path under a two-component record equals a Coulomb block's to 1 %.

    The joint is elastic: its friction turns towards a new slip direction only as fast as its
    elastic displacement (microns) allows, so on curved paths the compliant friction lags
    the Coulomb one; the lag goes as 1/k_s (max deviation 1.4 % of the largest displacement
    at the default 1e10 Pa/m, 0.2 % at 1e11, measured). Asserted at 1e11 Pa/m within 1 %;
    the Coulomb block at h = 1e-5 s is converged to 0.02 % (h = 2e-5 and 5e-6 agree).
    """
    column, mu = Column(1.0, 1.0, 1.0), 0.3
    motion = clough_penzien(7, duration=6.0, dt=0.01, pga=0.6 * G, omega_f=3.0)
    tc, xc = coulomb_block(motion.acc_x, motion.acc_y, motion.dt, mu, motion.duration + 2.0)
    r = simulate(column, motion, Excitation(), compliant(friction=mu, normal_stiffness=1e11, tail=2.0))
    h = r.histories
    cx, cy = np.interp(h.time.values, tc, xc[:, 0]), np.interp(h.time.values, tc, xc[:, 1])
    largest = np.hypot(cx, cy).max()
    assert largest > 0.02  # it slides about in both directions
    assert np.hypot(h.x_b.values - cx, h.y_b.values - cy).max() < 0.01 * largest
    assert r.summary["slip"] == pytest.approx(np.sum(np.hypot(*np.diff(xc, axis=0).T)), rel=0.01)
    assert r.summary["peak_theta"] < 1e-5


def ramp(rate, duration, dt=0.001):
    """Ground acceleration rising linearly at ``rate`` [m/s^3] along x."""
    t = np.arange(int(round(duration / dt)) + 1) * dt
    return GroundMotion.from_arrays(rate * t, np.zeros_like(t), dt, record_id="ramp")


@pytest.mark.parametrize("column, mu", [(Column(1.0, 1.0, 1.0), 0.3), (Column(1.0, 1.0, 1.0), 1.2),
                                        (PAPER, 0.2), (PAPER, 0.7)])
def test_slides_or_uplifts_first(column, mu):
    """mu < R/z_cm: it slides at |a| = mu g; otherwise it uplifts at g R/z_cm (a slow ramp).

    Sliding: the base's mobilised friction reaches 0.999 mu (the definition of the onset);
    measured -0.1 to -0.25 %. Uplift: the base's centre of pressure passes the chord between
    a rim point's neighbours, R cos(2 pi/S), the start of rocking on the rim of a compliant
    base; quasi-statically 3.4 % early (S = 24) at most, but near the moment capacity the
    rotation runs ahead of the centre of pressure: measured -0.4 %. Asserted within 1 %.
    """
    slide, uplift = mu * G, column.uplift_acceleration()
    rate = 0.05 * G  # slow: the columns' rocking and sliding time scales are 0.1-1 s
    duration = 1.2 * min(slide, uplift) / rate
    s = simulate(column, ramp(rate, duration), Excitation(), compliant(friction=mu, tail=0.0),
                 histories=False).summary
    if mu < column.R / column.z_cm:
        assert s["sliding_onset"] and not s["uplifted"]
        assert rate * s["sliding_time"] == pytest.approx(slide, rel=0.005)
    else:
        assert s["uplifted"] and not s["sliding_onset"]
        assert rate * s["uplift_time"] == pytest.approx(uplift, rel=0.01)


@pytest.fixture(scope="module")
def fema1():
    return load("FEMA-FF-01")


@pytest.mark.parametrize("scale", [1.0, 2.0])
def test_energy_budget_balances_under_a_far_field_record(fema1, scale):
    """Adaptive reference (DOPRI5): kinetic + potential + elastic energy changes by the ground's
    work less what friction and the dashpots take, to 1e-6 of the work (measured -7.8e-9 and
    -1.7e-9 at the default tolerances), in a run that stands (scale 1) and one that overturns
    (scale 2)."""
    s = simulate(PAPER, fema1, Excitation(angle=17.0, scale=scale), compliant(integrator="dopri5"),
                 histories=False).summary
    assert s["overturned"] == (scale == 2.0)
    assert s["energy_friction"] > 0 and s["energy_damping"] > 0
    assert abs(s["energy_balance_error"]) < 1e-6 * s["work_ground"]
    assert s["energy_final"] - s["energy_initial"] == pytest.approx(
        s["work_ground"] - s["energy_dissipated"], abs=1e-6 * s["work_ground"])


EXPLICIT = (("springs", "explicit"), ("step_safety", 0.5))  # the fixed-step scheme before issue 37's speed work


@pytest.mark.parametrize("scale", [1.0, 2.0])
def test_fixed_step_energy_budget_is_first_order_in_the_step(fema1, scale):
    """The semi-implicit integrator with the springs at the step's start books its energy with the
    discrete scheme; what is left is the scheme's first-order error: measured -2.14e-2 and -2.44e-2 of the work at the default step
    (0.701 ms here: 0.5 of the 1.40 ms limit), -1.06e-2 and -1.36e-2 at half of it, -5.6e-3 and
    -7.9e-3 at a quarter. Asserted: within 3 % of the work at the default step (a guard on the
    measured values, not a physical bound), and halving the step multiplies it by 0.35 to 0.7
    (first order: 0.5; measured 0.50 and 0.56, then 0.53 and 0.58 from half to a quarter).
    Booking friction as the spring energy the return to the cone drops (instead of Coulomb's
    mu f_el times the plastic slip) fails the ratio, as does the dashpot's power without
    backward Euler's own share."""
    errors = []
    step = None
    for _ in range(2):
        s = simulate(PAPER, fema1, Excitation(angle=17.0, scale=scale), compliant(step=step, numerics=EXPLICIT),
                     histories=False).summary
        assert s["overturned"] == (scale == 2.0)
        assert s["rejected_steps"] == 0 and s["steps"] > 0
        errors.append(s["energy_balance_error"] / s["work_ground"])
        step = 0.5 * s["step"]
    assert abs(errors[0]) < 0.03
    assert 0.35 < errors[1] / errors[0] < 0.7


@pytest.mark.parametrize("scale", [1.0, 2.0])
def test_energy_budget_with_the_springs_at_the_step_end_is_first_order(fema1, scale):
    """The default scheme books the springs' share of the solve with the dashpots (backward Euler's
    average dissipation); the budget's error is again the scheme's, first order in the step, about
    the explicit scheme's at the same step: measured -1.90e-2 and -3.27e-2 of the work at the
    default step (0.70 ms), -6.4e-3 and -8.3e-3 at a quarter of it (ratios 0.34 and 0.26; first
    order 0.25, none 1). Asserted: within 5 % of the work at the default step (a guard on the
    measured values), and the quarter step's error 0.1-0.6 of it."""
    errors = []
    step = None
    for _ in range(2):
        s = simulate(PAPER, fema1, Excitation(angle=17.0, scale=scale), compliant(step=step), histories=False).summary
        assert s["overturned"] == (scale == 2.0)
        errors.append(s["energy_balance_error"] / s["work_ground"])
        step = 0.25 * s["step"]
    assert abs(errors[0]) < 0.05
    assert 0.1 < errors[1] / errors[0] < 0.6


def test_a_column_left_alone_stays_exactly_still():
    quiet = GroundMotion.from_arrays(np.zeros(500), np.zeros(500), 0.01, record_id="quiet")
    r = simulate(DrumColumn.equal(PAPER, 3), quiet, Excitation(), compliant(tail=1.0))
    h, s = r.histories, r.summary
    for name in ("theta", "drum_theta", "drum_dx", "drum_dy", "drum_rotation", "x_b", "y_b", "slip", "omega_zeta"):
        assert np.all(h[name].values == 0.0), name
    assert np.all(h.contact_area_fraction.values == 1.0) and np.all(h.phase.values == 0)
    assert s["peak_theta"] == 0.0 and s["energy_final"] == s["energy_initial"] and s["work_ground"] == 0.0


def test_the_record_is_really_turned_by_the_incidence_angle():
    """The points are not axisymmetric: a planar pulse between two rim points meets a flat.

    90 deg maps the 24 sectors onto themselves: the response is the same, turned (the points
    are summed in another order, and once that round-off flips a step-size decision the two
    runs differ by the integration error: 1.2e-9 of the peak with DOPRI5 at rtol 1e-9, hence
    1e-8). 7.5 deg (half a sector) pivots on a chord of the rim polygon: another response
    (more than 1e-3).
    """
    pulse = _pulses(PAPER)["rectangular"]
    runs = {a: simulate(PAPER, pulse, Excitation(angle=a), compliant(tail=0.5)) for a in (0, 7.5, 90)}
    p0, p90, p7 = (runs[a].summary["peak_theta"] for a in (0, 90, 7.5))
    assert p90 == pytest.approx(p0, rel=1e-8)
    h0, h90 = runs[0].histories, runs[90].histories
    np.testing.assert_allclose(h90.y_b.values, h0.x_b.values, atol=1e-9)
    np.testing.assert_allclose(h90.x_b.values, -h0.y_b.values, atol=1e-9)
    assert abs(p7 / p0 - 1) > 1e-3
    assert np.abs(runs[7.5].histories.ground_acc_y.values).max() > 0.1  # the y component it turned into


def test_histories_and_summary_use_the_shared_names():
    pulse = _pulses(PAPER)["rectangular"]
    r = simulate(DrumColumn.equal(PAPER, 2), pulse, Excitation(), compliant(tail=0.2))
    ds = r.histories
    for name in ("theta", "phi", "psi", "x_p", "y_p", "normal_force_hat", "tangential_force_hat", "mu_mob",
                 "ground_acc_x", "ground_acc_y", "ground_acc_z", "energy", "slip", "contact_area_fraction",
                 "drum_dx", "drum_dy", "drum_theta", "drum_rotation"):
        assert name in ds and name in VARIABLES, name
        assert ds[name].attrs["units"] == VARIABLES[name].units
    assert ds.drum_theta.dims == ("time", "drum") and list(ds.drum.values) == [0, 1]
    for key in ("peak_theta", "peak_theta_ratio", "overturned", "overturn_time", "uplifted", "n_impacts",
                "peak_mu_mob", "sliding_onset", "lift_off", "residual_rotation", "residual_displacement",
                "energy_balance_error", "slip", "contact_area_fraction"):
        assert key in r.summary, key


@pytest.mark.parametrize("options, field", [
    ({"normal_stiffness": -1.0}, "normal_stiffness"),
    ({"contact_sectors": 25}, "contact_sectors"),
    ({"contact_rings": 2.5}, "contact_rings"),
    ({"anathyrosis": 0.99}, "anathyrosis"),
    ({"joint_friction": [0.5, "x"]}, "joint_friction"),
    ({"friction": 0.0}, "friction"),
    ({"contact_damping": -3.0}, "contact_damping"),
])
def test_bad_settings_name_the_field(options, field):
    with pytest.raises(InputError, match=field):
        compliant(**options)


def test_a_drum_column_needs_the_compliant_model():
    pulse = _pulses(PAPER)["rectangular"]
    with pytest.raises(InputError, match="3d-compliant"):
        simulate(DrumColumn.equal(PAPER, 2), pulse, Excitation(), ModelSettings(model="3d"))
    with pytest.raises(InputError, match="joint_friction has 3 values for 1 bed joint"):
        simulate(DrumColumn.equal(PAPER, 2), pulse, Excitation(), compliant(joint_friction=(0.5, 0.6, 0.7)))


def test_the_band_past_a_face_edge_is_a_numerical_choice_set_in_numerics():
    """edge_band sets the bed joints' run-off band and nothing else; the default is 0.5 ring spacings."""
    from pipeline.compliant import assemble
    from pipeline.dynamics.compliant import layout as sk
    from pipeline.models.compliant import COMPLIANT_DRUMS

    NUMERICS = COMPLIANT_DRUMS.numerics

    column = DrumColumn.equal(PAPER, 3)
    default = assemble(column, compliant(), damping=1e7)
    assert NUMERICS["edge_band"] == 0.5
    same = assemble(column, compliant(numerics=(("edge_band", 0.5),)), damping=1e7)
    assert np.array_equal(same.joints, default.joints)  # bit for bit: the cached stack rows stay valid
    narrow = assemble(column, compliant(numerics=(("edge_band", 0.25),)), damping=1e7)
    # 3 Gauss-Lobatto rings (centre dropped): at half and all of a drum's base radius, so the
    # spacing is half that radius (in units of the column's base radius); assemble rounds the
    # ring radii to 1e-9 to tell the rings apart, hence the tolerance
    spacing = [0.5 * d.R / PAPER.R for d in column.drums()]
    assert narrow.joints[:, sk.J_BAND] == pytest.approx([0.25 * x for x in spacing], abs=2e-9)
    assert np.array_equal(2.0 * narrow.joints[:, sk.J_BAND], default.joints[:, sk.J_BAND])
    others = [c for c in range(sk.N_JOINT_COLS) if c != sk.J_BAND]
    assert np.array_equal(narrow.joints[:, others], default.joints[:, others])
    with pytest.raises(InputError, match="numerics: edge_band"):
        compliant(numerics=(("edge_band", 0.0),))
    with pytest.raises(InputError, match="'slave_time' is not a numerical choice of the 3d-compliant model"):
        compliant(numerics=(("slave_time", 1e-5),))
    # the rigid models have their own numerical choices
    with pytest.raises(InputError, match="'edge_band' is not a numerical choice of the 3d model"):
        ModelSettings(model="3d", numerics=(("edge_band", 0.5),))


@pytest.mark.parametrize("stiffness", [1e6, 1e8])
def test_a_bed_too_soft_to_calibrate_on_is_refused_by_name(stiffness):
    """The damping calibration measures a planar rocking restitution; on a soft bed there is none
    to measure. At 1e6 Pa/m (the documented minimum; the paper's column sinks 86 mm) the released
    column never rocks back up; at 1e8 undamped it measured 0.13 against 0.90 critically damped
    (DOPRI5 the same: 0.128 and 0.895), a bounce read as a rebound, so the old calibration
    returned no damping and e = 0.13 as if that were the restitution. Both are refused with the
    fix (give contact_damping), and with contact_damping given the same bed runs."""
    pulse = one_sine_pulse(3.0, 0.5, dt=0.01, duration=1.0)
    with pytest.raises(InputError, match=r"normal_stiffness = .* could not measure a rocking restitution.*"
                                         r"contact_damping"):
        simulate(PAPER, pulse, Excitation(), compliant(normal_stiffness=stiffness), histories=False)
    s = simulate(PAPER, pulse, Excitation(), compliant(normal_stiffness=stiffness, contact_damping=1e5, tail=0.5),
                 histories=False).summary
    assert s["contact_damping"] == 1e5 and math.isnan(s["restitution"])
