"""The grid -> tasks -> results path, run serially: every cell is the simulation it names."""

import math

import numpy as np
import pytest

from pipeline.settings import Excitation
from pipeline.simulate import simulate
from pipeline.study import load_motions, load_study, run_study
from pipeline.study import run as task_run
from pipeline.study.grid import block_size, longest_first, plan, record_intensity, scale_factors

from study_files import SMALL_STUDY


def _direct(study, motions, ci, ri, ai, si, mi):
    column = study.columns[ci].column
    return simulate(column, motions[ri], Excitation(angle=study.angles[ai], scale=study.scales[si]),
                    study.settings(study.models[mi]), histories=False).summary


def test_cells_equal_direct_simulations(small_reference):
    """Spot checks: the value in the file is the direct simulate() result for that cell, exactly."""
    path, ds = small_reference
    study = load_study(path)
    motions = load_motions(study)
    rng = np.random.default_rng(5)
    cells = [tuple(int(rng.integers(n)) for n in study.shape) for _ in range(8)] + [(3, 1, 2, 2, 1), (0, 0, 0, 0, 0)]
    for cell in cells:
        summary = _direct(study, motions, *cell)
        for name in ("peak_theta", "peak_theta_ratio", "overturn_time", "peak_mu_mob", "residual_rotation",
                     "residual_displacement", "work_ground", "energy_balance_error"):
            value = ds[name].values[cell]
            assert value == summary[name] or (math.isnan(value) and math.isnan(summary[name])), (cell, name)
        for name in ("overturned", "uplifted", "sliding_onset", "lift_off"):
            assert ds[name].values[cell] == int(summary[name]), (cell, name)
        assert ds.n_impacts.values[cell] == summary["n_impacts"]
        assert ds.status.values[cell] == 0


def test_3d_broadcast_over_angles_equals_a_direct_run_at_another_angle(small_reference):
    """3D is run once per (column, record, scale) at the first angle; a direct run at 90 deg gives the same numbers."""
    path, ds = small_reference
    study = load_study(path)
    motions = load_motions(study)
    mi = study.models.index("3d")
    ai = study.angles.index(90.0)
    for ci, ri, si in [(0, 1, 2), (2, 1, 1), (1, 0, 2)]:
        summary = _direct(study, motions, ci, ri, ai, si, mi)
        for name in ("peak_theta", "n_impacts", "peak_mu_mob", "work_ground", "residual_displacement"):
            np.testing.assert_array_equal(ds[name].values[ci, ri, :, si, mi], summary[name])
    three = ds.sel(model="3d")
    assert (three.peak_theta == three.peak_theta.isel(angle=0)).all()


def test_2d_depends_on_the_angle(small_reference):
    """The planar model rocks in the X plane of the turned pair: a two-component record gives different results."""
    _, ds = small_reference
    two = ds.sel(model="2d", record="kt-1", scale=2.0)
    assert not np.allclose(two.peak_theta.isel(angle=0), two.peak_theta.isel(angle=2))
    # the Ricker wavelet is on x only: at 90 deg its X component vanishes
    assert (ds.sel(model="2d", record="ricker", angle=90.0).peak_theta == 0).all()


def test_task_layout_and_count(write_study):
    study = load_study(write_study())
    motions = load_motions(study)
    factors = scale_factors(study, [record_intensity(m) for m in motions])
    tasks = plan(study, factors)
    assert len(tasks) == 2 * 2  # two records x two blocks of two columns
    assert sum(t.n_simulations for t in tasks) == 4 * 2 * 3 * (1 + 3)  # 3d once, 2d per angle
    assert [(t.record, t.start, t.stop) for t in tasks] == [(0, 0, 2), (0, 2, 4), (1, 0, 2), (1, 2, 4)]


def test_failed_simulation_is_flagged_not_fatal(write_study, monkeypatch):
    real = task_run.simulate

    def flaky(column, motion, excitation, settings, histories=False):
        if column.name == "squat" and settings.model == "2d" and excitation.scale == 2.0:
            raise FloatingPointError("injected failure")
        return real(column, motion, excitation, settings, histories=histories)

    monkeypatch.setattr(task_run, "simulate", flaky)
    report = run_study(load_study(write_study()), serial=True, progress=False)
    ds = report.dataset
    bad = ds.sel(column="squat", model="2d", scale=2.0)
    assert (bad.status == 1).all() and bad.peak_theta.isnull().all()
    assert report.failed == bad.status.size == 2 * 3
    assert int((ds.status == 0).sum()) == ds.status.size - report.failed
    assert ds.peak_theta.where(ds.status == 0).notnull().sum() == ds.status.size - report.failed


def test_same_study_same_numbers(write_study, small_reference, same_results):
    report = run_study(load_study(write_study()), serial=True, progress=False)
    same_results(report.dataset, small_reference[1])


def test_intensity_levels_scale_each_record_to_the_target(write_study):
    text = SMALL_STUDY.replace("scales = [0.5, 1.0, 2.0]", 'intensity = {measure = "pgv", units = "m/s", values = [0.2, 0.4]}')
    ds = run_study(load_study(write_study(text)), serial=True, progress=False).dataset
    np.testing.assert_allclose(ds.pgv.values, [[0.2, 0.4], [0.2, 0.4]], rtol=1e-12)
    assert ds.scale.attrs["units"] == "m s-1"
    assert not np.allclose(ds.scale_factor.sel(record="ricker"), ds.scale_factor.sel(record="kt-1"))


def test_pga_is_the_peak_of_the_horizontal_vector_and_angle_independent(small_reference):
    from pipeline.groundmotion.synthesis import kanai_tajimi

    _, ds = small_reference
    kt = kanai_tajimi(1, duration=6.0, dt=0.01, pga=3.0)
    expected = np.max(np.hypot(kt.acc_x, kt.acc_y))
    np.testing.assert_allclose(ds.pga.sel(record="kt-1").values, expected * np.array([0.5, 1.0, 2.0]), rtol=1e-12)
    turned = kt.rotated(30.0)
    assert record_intensity(turned)["pga"] == pytest.approx(expected, rel=1e-12)
    assert record_intensity(turned)["pgv"] == pytest.approx(record_intensity(kt)["pgv"], rel=1e-12)


def test_automatic_blocks_are_even(write_study):
    """Without block_columns, ~64 simulations per task, spread evenly: 10 columns at 10 per column -> 5 + 5."""
    grid = ('[column_grid]\nR = 0.4\nslenderness = [6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 12.0, 13.0, 14.0, 15.0]\n'
            'beta = 0.9\n')
    text = SMALL_STUDY.replace("[execution]\nblock_columns = 2\n", "")
    text = text[:text.index("[[columns]]")] + grid + text[text.index("[records]"):]
    text = text.replace("angles = [0.0, 30.0, 90.0]", "angles = [0.0]").replace(
        "scales = [0.5, 1.0, 2.0]", "scales = [0.5, 1.0, 1.5, 2.0, 2.5]")
    study = load_study(write_study(text))
    assert len(study.columns) == 10 and study.block_columns is None
    # per column: 5 scales x (3d once + 2d at 1 angle) = 10 simulations; ceil(64 / 10) = 7 would leave 7 + 3
    assert block_size(study) == 5
    motions = load_motions(study)
    tasks = plan(study, scale_factors(study, [record_intensity(m) for m in motions]))
    assert [t.n_simulations for t in tasks] == [50] * 4


def test_longest_tasks_go_first(write_study):
    """The submission order is a permutation of the tasks, longest record first, then the more slender block."""
    study = load_study(write_study())
    motions = load_motions(study)
    tasks = plan(study, scale_factors(study, [record_intensity(m) for m in motions]))
    order = longest_first(tasks, motions)
    assert sorted(t.index for t in order) == [t.index for t in tasks]
    durations = [motions[t.record].duration for t in order]
    assert durations == sorted(durations, reverse=True) and durations[0] > durations[-1]
    # same record: the block holding the most slender column first
    same = [t for t in order if t.record == order[0].record]
    assert max(c.slenderness for c in same[0].columns) >= max(c.slenderness for c in same[1].columns)
