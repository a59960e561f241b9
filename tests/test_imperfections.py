"""Imperfect drums (issue 48, item 2): beds offset and tilted within a tolerance, friction drawn from a range.

What the draw is (within the tolerance, in the documented order, reproducible), what it does (a column
driven in one direction leaves the plane only when imperfect, Mouzakis et al. 2002), that an imperfect
structure rests exactly still, that a run is reproducible from its seed and records its draw, and what is
refused. Each tolerance says where it comes from.
"""

import math

import numpy as np
import pytest
import xarray as xr

from pipeline.cli import main
from pipeline.compliant import assemble, integrate, rest_state
from pipeline.dynamics.compliant.layout import B_HOLD, B_MASS, NB
from pipeline.errors import InputError
from pipeline.groundmotion import GroundMotion, one_sine_pulse
from pipeline.settings import Excitation, ModelSettings
from pipeline.simulate import simulate
from pipeline.structures.colonnade import Colonnade
from pipeline.structures.column import Column
from pipeline.structures.drums import Capital, DrumColumn
from pipeline.structures.imperfections import MAX_TOLERANCE_RATIO, Imperfections, bed_diameters, draw

PAPER = Column(0.5, 0.4, 4.0)
FOUR = DrumColumn.equal(PAPER, 4)  # the paper's column in 4 drums, as the issue asks
CAPPED = DrumColumn.equal(PAPER, 4, Capital(1.1, 0.3))


def imperfect(tolerance=0.002, seed=1, **kw):
    return ModelSettings(model="3d-compliant", imperfections=tolerance, seed=seed, **kw)


# ----------------------------------------------------------------------------------------------- the draw


def test_the_draw_stays_within_the_tolerance():
    """Every offset inside the disc of radius tolerance (0 at the base on the ground), every bed out of
    level by at most the tolerance across its diameter, every friction inside its range: exactly, these
    are bounds of the construction, not statistics."""
    spec = Imperfections(0.005, 11, (0.5, 0.7))
    d = draw(spec, CAPPED)
    assert d.n_joints == CAPPED.n_bodies == 5
    assert d.offset_x[0] == d.offset_y[0] == 0.0  # the ground has no axis to be off
    assert np.all(np.hypot(d.offset_x, d.offset_y) <= 0.005)
    assert np.all(np.tan(d.tilt) * bed_diameters(CAPPED) <= 0.005 * (1 + 1e-15))
    assert np.all((d.friction >= 0.5) & (d.friction <= 0.7))
    assert np.all(np.abs(d.azimuth) <= math.pi)
    np.testing.assert_allclose(np.hypot(d.slope_x, d.slope_y), np.tan(d.tilt), rtol=1e-15)
    assert np.all(np.isnan(draw(Imperfections(0.005, 11), CAPPED).friction))  # no range: the settings' friction


def test_the_draw_is_reproducible_and_in_the_documented_order():
    """Same seed, same draw to the bit; another seed, another draw. The order of the module docstring,
    re-drawn here from the generator by hand: per joint an offset pair (rejection in the square), a
    direction pair, the rise, the friction; so the geometry does not depend on a friction range, and a
    column alone draws what column 1 of a row of it draws."""
    spec = Imperfections(0.003, 4, (0.4, 0.8))
    first, again, other = draw(spec, CAPPED), draw(Imperfections(0.003, 4, (0.4, 0.8)), CAPPED), \
        draw(Imperfections(0.003, 5, (0.4, 0.8)), CAPPED)
    for name in ("offset_x", "offset_y", "slope_x", "slope_y", "tilt", "azimuth", "friction"):
        assert np.array_equal(getattr(first, name), getattr(again, name)), name
    assert not np.array_equal(first.slope_x, other.slope_x) and not np.array_equal(first.friction, other.friction)

    rng = np.random.Generator(np.random.PCG64(4))
    diameters = bed_diameters(CAPPED)

    def disc(positive):
        while True:
            u, v = 2.0 * rng.random() - 1.0, 2.0 * rng.random() - 1.0
            if u * u + v * v <= 1.0 and (u * u + v * v > 0.0 or not positive):
                return u, v

    for j in range(CAPPED.n_bodies):
        u, v = disc(False)
        dx, dy = disc(True)
        slope = 0.003 * rng.random() / diameters[j]
        mu = 0.4 + 0.4 * rng.random()
        expected = (0.0, 0.0) if j == 0 else (0.003 * u, 0.003 * v)
        assert (first.offset_x[j], first.offset_y[j]) == expected
        norm = math.sqrt(dx * dx + dy * dy)
        assert (first.slope_x[j], first.slope_y[j]) == (slope * (dx / norm), slope * (dy / norm))
        assert first.friction[j] == mu
    plain = draw(Imperfections(0.003, 4), CAPPED)
    assert np.array_equal(plain.slope_x, first.slope_x) and np.array_equal(plain.offset_y, first.offset_y)
    row = draw(spec, Colonnade(CAPPED, 3, 2.5, 0.8))
    assert row.n_joints == 15 and np.array_equal(row.slope_y[:5], first.slope_y)
    assert list(row.column) == [0] * 5 + [1] * 5 + [2] * 5


def test_offsets_are_uniform_in_the_disc_and_rises_uniform_across_the_bed():
    """Over 4000 bed joints: a uniform disc of radius t has E[r^2] = t^2 / 2 and a uniform azimuth; the rise
    across the bed, D tan(tilt), is uniform in [0, t]: mean t / 2. Each mean has a standard error of
    1/sqrt(12 n) = 0.0046 of its range (0.011 for the azimuth's cosine, whose variance is 1/2): the bounds are
    4 standard errors."""
    t, n_drums = 0.004, 40
    stack = DrumColumn.equal(Column(0.5, 0.5, 40.0), n_drums)
    r2, rise, cos = [], [], []
    for seed in range(100):
        d = draw(Imperfections(t, seed), stack)
        r2 += list((d.offset_x[1:] ** 2 + d.offset_y[1:] ** 2) / t ** 2)
        rise += list(np.tan(d.tilt) * 1.0 / t)
        cos += list(np.cos(np.arctan2(d.offset_y[1:], d.offset_x[1:])))
    assert np.mean(r2) == pytest.approx(0.5, abs=4 * 0.0046)
    assert np.mean(rise) == pytest.approx(0.5, abs=4 * 0.0046)
    assert np.mean(cos) == pytest.approx(0.0, abs=4 * 0.011)


# ----------------------------------------------------------------------------------------- what it does


def _tilt_components(histories):
    """Peak |x| and |y| components of the top drum's axis (in and out of the plane of an x drive)."""
    theta = histories.drum_theta.values[:, -1]
    phi = np.nan_to_num(histories.drum_phi.values[:, -1])  # NaN while upright: no tilt to split
    # Z-X-Z Euler angles: the axis is (sin phi sin theta, -cos phi sin theta, cos theta)
    return np.max(np.abs(np.sin(theta) * np.sin(phi))), np.max(np.abs(np.sin(theta) * np.cos(phi)))


@pytest.fixture(scope="module")
def x_pulse():
    """A one-sine pulse along x alone, twice the paper column's uplift acceleration over 0.6 s: the 4 drums
    rock to 0.33 theta_crit (4.9 deg at the top) and stand."""
    return one_sine_pulse(2.0 * PAPER.uplift_acceleration(), 0.6, dt=0.002, duration=3.6)


def test_a_drive_in_one_direction_stays_in_its_plane_unless_the_drums_are_imperfect(x_pulse):
    """Mouzakis et al. (2002): a column driven in one direction moved out of that plane, triggered by
    imperfections. The perfect drums are mirror-symmetric about the plane of the drive: their peak
    out-of-plane tilt is round-off grown through the rocking (measured 2e-12 of the in-plane one; 9e-9 at
    1.5 times this pulse, where it rocks to 0.56 theta_crit, whence this pulse). Imperfect within 2 mm,
    20 seeds gave out-of-plane peaks of 1.9 % to 28 % of the in-plane ones (median 14 %); these three
    13-15 %: 5 % is a plain departure from the plane with a margin of 2.5 on them."""
    perfect = simulate(FOUR, x_pulse, Excitation(vertical=False), ModelSettings(model="3d-compliant", tail=2.0))
    inside, outside = _tilt_components(perfect.histories)
    assert inside > 0.05 and not perfect.summary["overturned"]
    assert outside < 1e-9 * inside
    for seed in (1, 2, 3):
        run = simulate(FOUR, x_pulse, Excitation(vertical=False), imperfect(0.002, seed, tail=2.0))
        inside, outside = _tilt_components(run.histories)
        assert outside > 0.05 * inside, seed
        assert not run.summary["overturned"]


def test_an_imperfect_run_is_reproducible_from_its_seed(x_pulse):
    """Two runs with the same seed: the same summary and histories, to the bit; another seed draws other
    drums, and they move otherwise."""
    runs = [simulate(FOUR, x_pulse, Excitation(vertical=False), imperfect(0.002, seed, tail=0.5,
                                                                          friction_range=(0.5, 0.7)))
            for seed in (7, 7, 8)]
    first, again, other = runs
    assert first.histories.identical(again.histories)
    for key, value in first.summary.items():
        np.testing.assert_array_equal(value, again.summary[key], err_msg=key)
    assert not np.array_equal(first.summary["bed_tilt"], other.summary["bed_tilt"])
    assert not np.array_equal(first.histories.drum_theta.values, other.histories.drum_theta.values)


def test_the_draw_is_recorded_in_the_file(tmp_path):
    """frustum simulate writes the tolerance, seed and range and the drawn values per joint, with units,
    equal to the draw (the file's joints are the structure's: a column's base, bed joints, capital)."""
    out = tmp_path / "imperfect.nc"
    assert main(["simulate", "--column", "0.5,0.4,4", "--drums", "4", "--capital", "1.1,0.3", "--model",
                 "3d-compliant", "--imperfections", "0.004", "--seed", "12", "--friction-range", "0.55,0.65",
                 "--record", "SYN-ONESINE", "--tail", "0.2", "--out", str(out)]) == 0
    expected = draw(Imperfections(0.004, 12, (0.55, 0.65)), CAPPED)
    with xr.open_dataset(out) as ds:
        run = ds.isel(column=0, record=0).sel(model="3d-compliant")
        assert float(run.imperfection_tolerance) == 0.004 and int(run.imperfection_seed) == 12
        assert float(run.imperfection_friction_min) == 0.55 and float(run.imperfection_friction_max) == 0.65
        for name, values in (("bed_offset_x", expected.offset_x), ("bed_offset_y", expected.offset_y),
                             ("bed_tilt", expected.tilt), ("bed_tilt_azimuth", expected.azimuth),
                             ("bed_friction", expected.friction)):
            np.testing.assert_array_equal(run[name].values, values, err_msg=name)
        assert run.bed_offset_x.attrs["units"] == "m" and run.bed_tilt.attrs["units"] == "rad"
        assert run.bed_tilt_deg.attrs["units"] == "degree" and run.bed_friction.attrs["units"] == "1"
        assert np.all(np.hypot(run.bed_offset_x, run.bed_offset_y) <= 0.004)


# --------------------------------------------------------------------------------------------- the rest


def _rest(structure, settings):
    asm = assemble(structure, settings, 1e7)
    params = asm.params(np.zeros((2001, 3)), 0.01 / asm.time)
    return asm, params, rest_state(asm, params, settings.integrator)


@pytest.mark.parametrize("structure", [CAPPED, Colonnade(DrumColumn.equal(PAPER, 2, Capital(1.1, 0.3)), 3, 2.5,
                                                         0.8)], ids=["column", "colonnade"])
def test_an_imperfect_structure_rests_exactly_still(structure):
    """On leaning beds the weight has a part along each bed: the sticking shear springs carry it, so the
    holding loads are the weights, their horizontal parts round-off (below 1e-9 of the weight; the static
    solve's floor is about 1e-12, a penetration of microns from positions of metres), and 20 s without
    ground motion leave every body's place and turn bit for bit (the existing standard of rest: the tilt
    unchanged below 1e-12 rad)."""
    settings = imperfect(0.005, 3, friction_range=(0.5, 0.7), contact_damping=1e7)
    asm, params, y0 = _rest(structure, settings)
    hold, weight = params[0][:, B_HOLD:B_HOLD + 6], params[0][:, B_MASS]
    assert np.max(np.abs(hold[:, :2])) < 1e-9 * weight.sum()
    np.testing.assert_allclose(hold[:, 2], weight, rtol=1e-9)
    assert np.max(np.abs(asm.layout.imperfections.tilt)) > 1e-3  # the beds do lean
    raw = integrate(asm, params, y0, 20.0, 0.01, 1, settings, histories=True)
    assert raw.t_mon[-1] * asm.time == pytest.approx(20.0)
    n = NB * asm.n_bodies
    assert np.array_equal(raw.y_end[:n], y0[:n])  # every body's place, turn and velocity
    tilt = raw.hist_body[:, :, 2]  # H_TILT
    assert np.max(np.abs(tilt - tilt[0])) < 1e-12


def test_a_quiet_record_leaves_an_imperfect_column_where_it_stood():
    """Through simulate(): the histories of 20 s without ground motion are their first row (body places and
    turns), and the dislocations, measured from the rest state, are zero."""
    quiet = GroundMotion.from_arrays(np.zeros(2001), np.zeros(2001), 0.01, record_id="quiet")
    run = simulate(CAPPED, quiet, Excitation(), imperfect(0.005, 3, friction_range=(0.5, 0.7), tail=0.0))
    for name in ("drum_dx", "drum_dy", "drum_dz", "drum_theta", "drum_rotation"):
        values = run.histories[name].values
        assert np.max(np.abs(values - values[0])) < 1e-12, name
    assert np.all(run.summary["joint_slip"] == 0.0) and np.all(run.summary["joint_twist"] == 0.0)


# ------------------------------------------------------------------------------------------- refusals


@pytest.mark.parametrize("options, message", [
    ({"imperfections": -0.001, "seed": 1}, "imperfections = -0.001 m: the tolerance of the drums' beds"),
    ({"imperfections": math.nan, "seed": 1}, "imperfections = nan m"),
    ({"imperfections": 0.002}, "imperfections = 0.002 m are drawn from a seed: give seed too"),
    ({"seed": 3}, "seed = 3 draws imperfect drums: give imperfections too"),
    ({"imperfections": 0.002, "seed": -1}, "seed = -1: the seed of the imperfections' draw must be a whole number "
                                           "in [0, 4294967295]"),
    ({"imperfections": 0.002, "seed": 1.5}, "seed = 1.5"),
    ({"imperfections": 0.002, "seed": 1, "friction_range": (0.7, 0.5)}, "friction_range = (0.7, 0.5): the range "
                                                                        "of friction coefficients"),
    ({"imperfections": 0.002, "seed": 1, "friction_range": 0.6}, "must be two numbers LO,HI with LO <= HI"),
    ({"imperfections": 0.002, "seed": 1, "friction_range": (0.5, 0.7), "joint_friction": (0.5, 0.6, 0.6)},
     "give one of them"),
])
def test_bad_imperfections_are_refused_naming_the_option(options, message):
    with pytest.raises(InputError, match=message.replace("(", r"\(").replace(")", r"\)").replace("[", r"\[")):
        ModelSettings(model="3d-compliant", **options)


def test_a_tolerance_beyond_five_percent_of_the_smallest_bed_is_refused():
    """5 % of the capital's bed (the shaft's top, 0.8 m): 40 mm is the most; the Imperfections of any
    structure are checked against its own beds."""
    limit = MAX_TOLERANCE_RATIO * 0.8
    draw(Imperfections(limit, 1), CAPPED)
    with pytest.raises(InputError, match=r"imperfections = 0\.041 m is more than 5 % of the smallest bed diameter "
                                         r"of the columns \(0\.8 m\).*give at most 0\.04 m"):
        simulate(CAPPED, one_sine_pulse(1.0, 0.5), Excitation(), imperfect(0.041, 1))


def test_a_bed_leaning_past_its_friction_angle_is_refused_naming_the_joint():
    """A friction range of 0.001-0.002 under beds out of level by up to 20 mm over 0.8-1 m (tan up to
    0.025): the body would slide at rest, not stand imperfect."""
    with pytest.raises(InputError, match=r"imperfections = 0\.02 m: the (base of the column|bed joint under drum \d|"
                                         r"bed joint under capital) leans .* deg \(seed 2\), at or past its friction "
                                         r"angle atan\(0\.00\d+\)"):
        simulate(CAPPED, one_sine_pulse(1.0, 0.5), Excitation(), imperfect(0.02, 2, friction_range=(0.001, 0.002)))


def test_imperfections_with_a_rigid_model_are_refused_in_the_words_of_a_study(tmp_path, capsys):
    """One check (pipeline.models.check_imperfect) for simulate and a study: the same words."""
    out = tmp_path / "r.nc"
    assert main(["simulate", "--column", "0.5,0.4,4", "--imperfections", "0.002", "--seed", "1", "--record",
                 "SYN-ONESINE", "--out", str(out)]) == 2
    cli = capsys.readouterr().err
    assert ("--imperfections draws imperfect drums (beds offset and tilted within a tolerance, joint friction "
            "from a range), which only 3d-compliant runs; model 3d runs perfect structures, so it would be "
            "ignored: drop --imperfections, or run 3d-compliant") in cli
    study = tmp_path / "s.toml"
    study.write_text('models = ["3d", "2d"]\n[[columns]]\nnamed = "paper"\n[records]\nids = ["SYN-ONESINE"]\n'
                     '[excitation]\nscales = [1.0]\n[imperfections]\ntolerance = 0.002\nseeds = [1, 2]\n')
    assert main(["study", "check", str(study)]) == 2
    words = capsys.readouterr().err
    assert ("field imperfections: [imperfections] draws imperfect drums (beds offset and tilted within a "
            "tolerance, joint friction from a range), which only 3d-compliant runs; models 3d, 2d run perfect "
            "structures, so it would be ignored: drop [imperfections], or run 3d-compliant") in words
    assert not out.exists()
