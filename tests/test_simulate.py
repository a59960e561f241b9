"""Earthquake response: the acceptance points of the earthquake-response issue."""

import math

import numpy as np
import pytest

from pipeline.errors import InputError
from pipeline.structures.column import Column
from pipeline.groundmotion import GroundMotion, harmonic, load, rectangular_pulse
from pipeline.settings import Excitation, InitialState, ModelSettings, housner_restitution
from pipeline.simulate import simulate, simulate_free
from pipeline.units import G

PAPER = Column(0.5, 0.4, 4.0)


@pytest.fixture(scope="module")
def fema1():
    return load("FEMA-FF-01")


def _x_only(motion, factor=1.0):
    """The record's x component alone (y = 0): a one-directional excitation."""
    return GroundMotion.from_arrays(motion.acc_x * factor, np.zeros(motion.npts), motion.dt,
                                    record_id=motion.record_id + "-x")


def test_below_uplift_nothing_moves():
    a_up = PAPER.uplift_acceleration()
    motion = harmonic(0.98 * a_up, 1.5, duration=6.0, dt=0.005)
    r = simulate(PAPER, motion, Excitation(angle=23.0))
    assert not r.summary["uplifted"] and r.summary["n_impacts"] == 0
    assert np.all(r.histories.theta.values == 0.0)  # exactly, not approximately
    assert np.all(r.histories.phase.values == 0)
    assert r.summary["peak_theta"] == 0.0 and r.summary["residual_displacement"] == 0.0


def test_just_above_uplift_it_moves():
    a_up = PAPER.uplift_acceleration()
    motion = harmonic(1.05 * a_up, 1.5, duration=6.0, dt=0.005)
    r = simulate(PAPER, motion)
    assert r.summary["uplifted"] and r.summary["peak_theta"] > 0


@pytest.mark.parametrize("scale", [1.0, 2.5])
def test_cylinder_in_one_direction_reproduces_planar_rocking(fema1, scale):
    cylinder = Column(0.4, 0.4, 4.0)
    motion = _x_only(fema1)
    r3 = simulate(cylinder, motion, Excitation(scale=scale), ModelSettings(model="3d"))
    r2 = simulate(cylinder, motion, Excitation(scale=scale), ModelSettings(model="2d"))
    h3, h2 = r3.histories, r2.histories
    # planar by construction: no precession, no spin, the pivot stays on the x axis
    moving = h3.phase.values != 2  # rows after it lies down carry no forces or rates
    # (exactly 0 while it rolls; a slip along x carries cos(pi/2) = 6e-17 of round-off into the
    # out-of-plane force, which the held pivot keeps at that level: measured 6e-18 rad/s, 6e-19 m)
    assert np.all(np.abs(h3.phi_dot.values[moving]) < 1e-15)
    assert np.all(np.abs(h3.omega_zeta.values[moving]) < 1e-15)
    assert np.all(np.abs(np.nan_to_num(h3.y_p.values)) < 1e-15)
    first = r3.impacts[0, 0] if len(r3.impacts) else np.inf
    before = h3.time.values < first
    assert before.sum() > 50
    # same ODE by two code paths at rtol 1e-9: agreement far inside 1e-6 rad
    np.testing.assert_allclose(h3.theta.values[before], h2.theta.values[before], rtol=0, atol=1e-6)
    assert r3.summary["n_impacts"] == r2.summary["n_impacts"]
    assert r3.summary["overturned"] == r2.summary["overturned"]
    assert r3.summary["peak_theta"] == pytest.approx(r2.summary["peak_theta"], rel=1e-4)


@pytest.mark.parametrize("slenderness", [4.0, 8.0])
def test_free_planar_rocking_restitution_at_every_landing(slenderness):
    col = Column(0.5, 0.45, 0.5 * slenderness)
    e = housner_restitution(col)
    init = InitialState(theta=math.degrees(0.5 * col.critical_tilt))
    # a rigid base: the impact map alone, no patch damping on the way down
    settings = ModelSettings(contact_tilt=math.degrees(1e-5), rtol=1e-11, atol=1e-13, normal_stiffness=math.inf)
    from pipeline.simulate import _run  # the landing log of the kernel
    import pipeline.dynamics.rigid.frustum as fk
    y0 = np.zeros(fk.N_STATE)
    y0[fk.THETA] = math.radians(init.theta)
    raw = _run(col, settings, np.zeros((0, 3)), 1.0, y0, 8.0)
    log = raw.impacts
    assert len(log) >= 5
    ratios = -log[:-1, 2] / log[:-1, 1]  # the last one may settle
    np.testing.assert_allclose(ratios, e, rtol=1e-9)


def test_restitution_tends_to_housner_block_value_for_slender_columns():
    """1 - e against Housner (1963) 1.5 sin^2(alpha) for the block of the same outline.

    Housner's rectangular block of width 2b and height 2H (here 2b = 2R,
    2H = h) rocking about a corner has e = 1 - 1.5 sin^2(alpha), alpha =
    atan(b / H), from the same angular-momentum argument with I_O = 4/3 m (b^2 + H^2).
    """
    ratios = []
    for slenderness in (5.0, 20.0, 100.0, 400.0):
        col = Column(1.0, 1.0, slenderness)
        alpha = math.atan(1.0 / (0.5 * slenderness))
        ratios.append((1 - housner_restitution(col)) / (1.5 * math.sin(alpha) ** 2))
    deviations = [abs(r - 1) for r in ratios]
    assert deviations == sorted(deviations, reverse=True)  # approaches 1 monotonically
    assert deviations[-1] < 1e-4  # cylinder vs block inertia differ by O(1/slenderness^2)


def _housner_rectangular_pulse_minimum(column, duration):
    """Minimum amplitude of a rectangular pulse that overturns, linearised Housner model.

    Linearised rocking (Housner 1963): theta'' = p^2 (theta - alpha + a/g)
    during the pulse, theta'' = p^2 (theta - alpha) after it. From rest,
    theta = (a/g - alpha)(cosh(p t) - 1); after the pulse the column passes
    theta = alpha iff theta'/p >= alpha - theta at its end, i.e.
    (a/g - alpha)(exp(p t_d) - 1) >= alpha:  a_min = g alpha / (1 - exp(-p t_d)).
    """
    p = column.frequency_parameter()
    return G * column.critical_tilt / (1 - math.exp(-p * duration))


def _minimum_overturning_amplitude(column, duration, model):
    lo, hi = column.uplift_acceleration(), 10 * G
    for _ in range(30):  # bisection to 1e-9 relative
        mid = math.sqrt(lo * hi)
        pulse = rectangular_pulse(mid, duration, dt=0.0005, duration=duration + 1.0)
        if simulate(column, pulse, settings=ModelSettings(model=model, tail=3.0), histories=False).summary["overturned"]:
            hi = mid
        else:
            lo = mid
    return hi


@pytest.mark.parametrize("duration", [0.3, 0.5, 1.0])
@pytest.mark.parametrize("model", ["3d", "2d"])
def test_rectangular_pulse_overturning_matches_linearised_housner(duration, model):
    slender = Column(0.2, 0.2, 4.0)  # h/R = 20, alpha = 0.0997 rad
    found = _minimum_overturning_amplitude(slender, duration, model)
    # the linearisation (sin(alpha - theta) ~ alpha - theta, cos ~ 1) errs by
    # O(alpha^2) ~ 1 %, within the 3 % the issue allows
    assert found == pytest.approx(_housner_rectangular_pulse_minimum(slender, duration), rel=0.03)


def test_incidence_angle_only_turns_the_3d_response(fema1):
    base = simulate(PAPER, fema1, Excitation(angle=0.0))
    turned = simulate(PAPER, fema1, Excitation(angle=40.0))
    for key in ("peak_theta", "n_impacts", "overturned", "peak_mu_mob", "residual_displacement", "work_ground"):
        assert turned.summary[key] == base.summary[key], key
    # contact point path turned by the angle
    c, s = math.cos(math.radians(40.0)), math.sin(math.radians(40.0))
    x0, y0 = base.histories.x_p.values, base.histories.y_p.values
    np.testing.assert_allclose(turned.histories.x_p.values, c * x0 - s * y0, atol=1e-12, equal_nan=True)


@pytest.mark.parametrize("damping", [0.0, 0.05])
@pytest.mark.parametrize("scale", [1.0, 2.0])
@pytest.mark.parametrize("stiffness", [math.inf, 1e10])
def test_energy_budget_balances(fema1, damping, scale, stiffness):
    r = simulate(PAPER, fema1, Excitation(scale=scale), ModelSettings(damping=damping, normal_stiffness=stiffness),
                 histories=False)
    s = r.summary
    # E_final - E_initial = work + transitions - dissipated - friction, to 1e-6 of the work
    assert abs(s["energy_balance_error"]) < 1e-6 * abs(s["work_ground"])
    # impacts, slaps and settling never add energy; only each uplift's lift to theta_c
    # does, by the potential energy of that tilt (theta_c R per unit weight, 1e-5 m at most)
    assert s["energy_transitions"] <= 1e-4 * abs(s["work_ground"])
    if damping or stiffness < math.inf:  # the viscous couple, or the contact patch's dashpots
        assert s["energy_dissipated"] > 0
    else:
        assert s["energy_dissipated"] == 0.0


def test_damping_reduces_the_response(fema1):
    plain = simulate(PAPER, fema1, histories=False).summary
    damped = simulate(PAPER, fema1, settings=ModelSettings(damping=0.2), histories=False).summary
    assert damped["energy_final"] < plain["energy_final"]


@pytest.mark.parametrize("record", ["FEMA-FF-01", "FEMA-FF-02"])
def test_tolerance_convergence_of_peak_theta(record):
    """Tightening the tolerances tenfold changes peak theta by less than 1e-3 relative."""
    motion = load(record)
    loose = simulate(PAPER, motion, settings=ModelSettings(rtol=1e-9, atol=1e-12), histories=False).summary
    tight = simulate(PAPER, motion, settings=ModelSettings(rtol=1e-10, atol=1e-13), histories=False).summary
    assert not loose["overturned"] and not tight["overturned"]
    assert tight["peak_theta"] == pytest.approx(loose["peak_theta"], rel=1e-3)


def test_bad_input_is_rejected_with_a_message(fema1):
    with pytest.raises(InputError, match="scale = 0"):
        Excitation(scale=0)
    with pytest.raises(InputError, match="scale = -2"):
        Excitation(scale=-2)
    with pytest.raises(InputError, match="model = '4d' is unknown"):
        ModelSettings(model="4d")
    with pytest.raises(InputError, match="slenderness h/R = 1000"):
        simulate(Column(0.01, 0.01, 10.0), fema1)
    with pytest.raises(InputError, match="column R = 200 m"):
        simulate(Column(200, 200, 400), fema1)
    with pytest.raises(InputError, match="NaN or infinite"):
        bad = fema1.acc_x.copy()
        bad[100] = np.nan
        simulate(PAPER, GroundMotion.from_arrays(bad, fema1.acc_y, fema1.dt, record_id="bad"))


def test_regression_turning_point_just_before_a_record_sample_does_not_hang():
    """A turning point 3e-9 s before a sample once made the run loop for ever (r/R = 1)."""
    r = simulate(Column(0.5, 0.5, 4.0), load("FEMA-FF-12"), Excitation(0.0, 3.5309436681931916),
                 ModelSettings(model="3d"), histories=False)
    assert r.summary["rhs_evaluations"] < 1_000_000


def test_regression_uplift_on_the_verge_does_not_cycle_without_time_advancing():
    """2D: an excitation hovering just above the uplift threshold once cycled a million times."""
    r = simulate(Column(0.5, 0.4, 6.0), load("FEMA-FF-03"), Excitation(90.0, 1.0964),
                 ModelSettings(model="2d"), histories=False)
    assert 0 < r.summary["n_impacts"] < 10_000
    assert abs(r.summary["energy_balance_error"]) < 1e-6 * abs(r.summary["work_ground"])


def test_flags_and_peaks_agree_with_the_history_through_overturning(fema1):
    """FEMA-FF-01 x3 overturns the paper's column after slipping on its rim.

    With slip and flight modelled the history never holds a normal force
    below zero or a mobilized friction above mu; the summary's flags are the
    phases the history shows, and its peak friction bounds the history's.
    """
    settings = ModelSettings()
    r = simulate(PAPER, fema1, Excitation(scale=3.0), settings)
    h = r.histories
    phase = h.phase.values
    assert r.summary["overturned"] and (phase == 2).any()
    assert r.summary["sliding_onset"] == bool(np.isin(phase, (3, 4)).any())
    assert r.summary["lift_off"] == bool((phase == 5).any())
    assert np.nanmin(h.normal_force_hat.values) >= 0.0
    assert np.nanmax(h.mu_mob.values) <= settings.friction * (1 + 1e-9)
    assert r.summary["peak_mu_mob"] >= np.nanmax(h.mu_mob.values) * (1 - 1e-9)
    assert r.summary["peak_mu_mob"] <= settings.friction * (1 + 1e-9)


def test_peak_friction_never_exceeds_mu(fema1):
    """The acceptance bound of issue 10: peak_mu_mob <= mu (1 + 1e-9).

    Measured 0.70021 for mu 0.7 while the slip equations lacked the patch's drilling
    couple (a slip could not start where rolling asked more than mu N); 0.7 now.
    """
    r = simulate(PAPER, fema1, Excitation(scale=3.0), ModelSettings(), histories=False)
    assert r.summary["peak_mu_mob"] <= 0.7 * (1 + 1e-9)


def test_simulations_in_threads_equal_serial_ones():
    """The entry kernels release the GIL: simulations run side by side in threads give the serial numbers exactly."""
    from concurrent.futures import ThreadPoolExecutor

    from pipeline.groundmotion.synthesis import kanai_tajimi

    motion = kanai_tajimi(duration=6.0, dt=0.01, pga=3.0, seed=3, record_id="kt-threads")
    cases = [(Column(0.4, 0.36, h), ModelSettings(model=model, tail=1.0), angle)
             for h in (2.8, 3.6) for model in ("3d", "2d") for angle in (0.0, 40.0)]

    def run(case):
        column, settings, angle = case
        return simulate(column, motion, Excitation(angle=angle), settings, histories=True)

    serial = [run(case) for case in cases]
    with ThreadPoolExecutor(max_workers=4) as pool:
        threaded = list(pool.map(run, cases * 2))
    assert any(r.summary["uplifted"] for r in serial)  # the runs do rock
    for ref, got in zip(serial * 2, threaded):
        assert got.summary["peak_theta"] == ref.summary["peak_theta"]
        np.testing.assert_array_equal(got.histories.theta.values, ref.histories.theta.values)


def test_excitation_angle_is_in_degrees():
    """``Excitation(angle=90)`` turns an x-only record onto y: the 2D model (X plane) then sees nothing.

    In radians, 90 would leave cos(90 rad) = -0.45 of the record on X and the column would rock.
    """
    a_up = PAPER.uplift_acceleration()
    motion = harmonic(3.0 * a_up, 1.0, duration=3.0, dt=0.005)
    assert Excitation(angle=30).angle_rad == pytest.approx(math.pi / 6, rel=1e-15)
    at_0 = simulate(PAPER, motion, Excitation(angle=0), ModelSettings(model="2d", tail=1.0), histories=False)
    at_90 = simulate(PAPER, motion, Excitation(angle=90), ModelSettings(model="2d", tail=1.0), histories=False)
    assert at_0.summary["uplifted"] and at_0.summary["peak_theta"] > 1e-3
    assert not at_90.summary["uplifted"] and at_90.summary["peak_theta"] == 0.0


def test_the_file_says_which_contact_the_run_had():
    """A rigid run's file names its ground (lift_off), its bed's stiffness and the patch's dashpots it ran with:
    critical damping 2 sqrt(k_n m / A) by default (m of marble, 2700 kg/m^3, when the column has no density),
    the given value otherwise, none for the paper's point contact."""
    motion = harmonic(0.5 * PAPER.uplift_acceleration(), 1.5, duration=1.0, dt=0.01)
    ds = simulate(PAPER, motion, settings=ModelSettings(lift_off=False, normal_stiffness=1e9)).histories
    mass = 2700.0 * math.pi * 4.0 / 3.0 * (0.5**2 + 0.5 * 0.4 + 0.4**2)
    assert ds.attrs["lift_off"] == "false" and ds.attrs["normal_stiffness_Pa_m"] == 1e9
    assert ds.attrs["contact_damping_Pa_s_m"] == pytest.approx(2.0 * math.sqrt(1e9 * mass / (math.pi * 0.25)), rel=1e-12)
    given = simulate(PAPER, motion, settings=ModelSettings(contact_damping=3e5)).histories
    assert given.attrs["lift_off"] == "true" and given.attrs["contact_damping_Pa_s_m"] == 3e5
    point = simulate(PAPER, motion, settings=ModelSettings(normal_stiffness=math.inf)).histories
    assert point.attrs["normal_stiffness_Pa_m"] == math.inf and point.attrs["contact_damping_Pa_s_m"] == 0.0
