"""Figures of one run: nothing after overturning, angle and scale in the title, no empty panel, any format."""

import math

import matplotlib.pyplot as plt
import numpy as np
import pytest

from pipeline.cli import main
from pipeline.structures.column import Column
from pipeline.groundmotion.synthesis import one_sine_pulse
from pipeline.plotting import plot_response, response_figure
from pipeline.settings import Excitation, InitialState, ModelSettings
from pipeline.simulate import simulate, simulate_free

COLUMN = Column(0.5, 0.4, 4.0)


@pytest.fixture(scope="module")
def overturning():
    motion = one_sine_pulse(8.0, 0.8, dt=0.01, record_id="pulse")
    response = simulate(COLUMN, motion, Excitation(angle=30.0, scale=2.0), ModelSettings(tail=2.0))
    assert response.summary["overturned"]  # the premise
    return response


def test_nothing_is_drawn_after_overturning(overturning):
    ds, summary = overturning.histories, overturning.summary
    fig = response_figure(ds, summary)
    theta_ax, path_ax, mu_ax, ground_ax = fig.axes
    t_over = summary["overturn_time"]
    (theta_line,) = [line for line in theta_ax.lines if line.get_label() == r"$\theta$"]
    assert theta_line.get_xdata().max() <= t_over + 1e-9
    (mu_line,) = [line for line in mu_ax.lines if line.get_label() == r"$\mu_{mob}$"]
    # friction and paths stop where the column passes theta_crit for the last time
    last_upright = mu_line.get_xdata().max()
    assert last_upright < t_over
    assert np.degrees(ds.theta.sel(time=last_upright).item()) <= math.degrees(COLUMN.critical_tilt)
    n_drawn = len(mu_line.get_xdata())
    for line in path_ax.lines[:2]:  # contact point and base centre
        assert len(line.get_xdata()) == n_drawn
    # and what is drawn stays within the run's peak while in contact: no blow-up in the final fall
    drawn = mu_line.get_ydata()
    assert np.all(np.isfinite(drawn)) and np.max(drawn) <= summary["peak_mu_mob"] * (1 + 1e-12)
    plt.close(fig)


def test_title_names_record_angle_and_scale(overturning):
    fig = response_figure(overturning.histories, overturning.summary)
    title = fig._suptitle.get_text()
    assert title.startswith("pulse at 30°, × 2, 3D rolling frustum, column R = 0.5 m")
    assert title.endswith(f"(overturned at {overturning.summary['overturn_time']:.2f} s)")  # the run's outcome
    plt.close(fig)


def test_free_motion_has_no_empty_excitation_panel():
    ds = simulate_free(COLUMN, InitialState(theta=10, phi_dot=0.44, psi_dot=-0.89), 2.0)
    fig = response_figure(ds, {"peak_theta": float(np.nanmax(ds.theta.values))})
    assert len(fig.axes) == 3
    assert all(ax.lines for ax in fig.axes)
    assert "Excitation" not in [ax.get_title() for ax in fig.axes]
    assert fig._suptitle.get_text().startswith("free motion, 3D rolling frustum")
    plt.close(fig)


@pytest.mark.parametrize("suffix, magic", [(".svg", b"<?xml"), (".pdf", b"%PDF"), (".png", b"\x89PNG")])
def test_any_format_matplotlib_writes(overturning, tmp_path, suffix, magic):
    path = plot_response(overturning.histories, overturning.summary, tmp_path / f"r{suffix}")
    assert open(path, "rb").read(8).startswith(magic)
    assert [p.name for p in tmp_path.iterdir()] == [f"r{suffix}"]  # no temporary file left


def test_records_plot_writes_svg_and_names_the_formats(tmp_path, capsys):
    assert main(["records", "plot", "FEMA-FF-01", "--out", str(tmp_path / "rec.svg")]) == 0
    assert b"<svg" in (tmp_path / "rec.svg").read_bytes()[:1000]
    assert main(["records", "plot", "FEMA-FF-01", "--out", str(tmp_path / "rec.xyz")]) == 2
    err = capsys.readouterr().err
    assert "--out" in err and "rec.xyz': not a figure format matplotlib writes" in err and ".svg" in err


def test_the_study_plot_draws_pga_in_g_on_every_panel(tmp_path):
    """Issue 47, item 2: a study scaled to target PGAs draws them in g on the right panel, as the left panel and the
    reports do (before: m s-2 there, g on the left)."""
    from pipeline.plotting import study_figure
    from pipeline.study import load_study, run_study

    (tmp_path / "targets.toml").write_text(
        'title = "targets"\noutput = "targets.nc"\nmodels = ["3d"]\noptions = {tail = 0.5}\n'
        'excitation = {angles = [0.0], intensity = {measure = "pga", units = "g", values = [0.2, 0.4]}}\n'
        'records = {synthetic = [{generator = "one_sine_pulse", id = "pulse", ap = 3.0, tp = 0.4, dt = 0.01}]}\n'
        'columns = [{name = "paper", R = 0.5, r = 0.4, h = 4.0}]\n', encoding="utf-8")
    report = run_study(load_study(tmp_path / "targets.toml"), serial=True, progress=False)
    fig = study_figure(report.dataset)
    try:
        left, right = fig.axes
        assert left.get_xlabel() == "PGA of the scaled record (horizontal vector) [g]"
        assert right.get_xlabel() == "target PGA of the scaled record [g]"
        np.testing.assert_allclose(right.lines[0].get_xdata(), [0.2, 0.4], rtol=1e-12)
        np.testing.assert_allclose(left.collections[0].get_offsets()[:, 0], [0.2, 0.4], rtol=1e-9)
    finally:
        plt.close(fig)


def test_a_colonnades_response_plot_draws_its_contact_at_its_base(tmp_path):
    """Issue 47, item 1: the compliant colonnade's base path (its first column's) is drawn from where that base
    stood, around the "base at start" circle at the origin, as its contact point is (before: x_b absolute, 1.25 m
    off along the row)."""
    from pipeline.structures.colonnade import Colonnade
    from pipeline.structures.drums import Capital, DrumColumn

    row = Colonnade(DrumColumn(COLUMN, capital=Capital(1.1, 0.3)), 2, 2.5, 0.8)
    run = simulate(row, one_sine_pulse(3.0, 0.4, dt=0.01, record_id="pulse"), Excitation(),
                   ModelSettings(model="3d-compliant", tail=0.5, contact_sectors=8))
    fig = response_figure(run.histories, run.summary)
    try:
        path = fig.axes[1]
        lines = {line.get_label(): np.asarray(line.get_xydata()) for line in path.lines}
        for name in ("contact point", "base centre"):
            drawn = lines[name][np.isfinite(lines[name]).all(axis=1)]
            assert drawn.size and np.all(np.hypot(*drawn.T) <= 50.0 + 1.0), name  # [cm]: within the base's rim
        assert np.all(np.abs(lines["base centre"]) < 1.0)  # [cm]: where the base stood, not 125 cm along the row
    finally:
        plt.close(fig)
