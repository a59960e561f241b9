"""``frustum animate``: the expected frames, and a frame that shows the frustum as the reference does.

The reference frame (tests/data/animate/frame_3d_2d.png) was rendered by
:func:`pipeline.animate.render_frame` for the run below at t = 1.0 s; regenerate
it with ``python tests/test_animate.py`` after a deliberate change of the
drawing, and look at it before committing.
"""

import math
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from pipeline.animate import STONE, euler_rotation, frame_times, render_frame
from pipeline.cli import main
from pipeline.dataset import histories_file, one_run, open_results, write_netcdf
from pipeline.geometry import Column
from pipeline.groundmotion.synthesis import one_sine_pulse
from pipeline.simulate import Excitation, ModelSettings, simulate

REFERENCE = Path(__file__).parent / "data" / "animate" / "frame_3d_2d.png"
T_REFERENCE = 1.0  # [s]: both columns tilted


def _write_run(path):
    motion = one_sine_pulse(6.0, 0.6, dt=0.01, record_id="pulse")
    runs = [simulate(Column(0.5, 0.4, 4.0), motion, Excitation(angle=30.0),
                     ModelSettings(model=m, tail=0.9)).histories for m in ("3d", "2d")]
    write_netcdf(histories_file(runs, column="paper", record="pulse"), path)
    return path


@pytest.fixture(scope="module")
def result(tmp_path_factory):
    return _write_run(tmp_path_factory.mktemp("animate") / "run.nc")


def test_gif_has_the_real_time_frames(result, tmp_path, capsys):
    ds = open_results(result)
    duration = float(ds.time[-1] - ds.time[0])
    assert duration == pytest.approx(1.5)  # 0.6 s pulse + 0.9 s tail
    out = tmp_path / "motion.gif"
    assert main(["animate", str(result), "--out", str(out)]) == 0
    with Image.open(out) as gif:
        assert gif.n_frames == 16  # 0, 0.1, ..., 1.5 s: real time at 10 frames per second
        assert gif.info["duration"] == 100  # [ms] per frame
        assert gif.size == (768, 416)  # 3D and 2D side by side
    assert "16 frames" in capsys.readouterr().out
    assert [p.name for p in tmp_path.iterdir()] == ["motion.gif"]  # no temporary file left


def test_frame_times_follow_fps_and_speed():
    time = np.arange(0.0, 30.0 + 1e-9, 0.01)
    assert len(frame_times(time, 10.0)) == 301
    assert len(frame_times(time, 10.0, speed=0.5)) == 601  # slow motion: twice the frames
    assert len(frame_times(time, 25.0)) == 751


def test_a_frame_shows_the_frustum_as_the_reference_does(result):
    ds = open_results(result)
    frame = render_frame([one_run(ds, model="3d"), one_run(ds, model="2d")], T_REFERENCE)
    reference = np.asarray(Image.open(REFERENCE).convert("RGB"))
    assert frame.shape == reference.shape
    diff = np.abs(frame.astype(int) - reference.astype(int)).max(axis=2)
    # tight enough that the same run 0.1 s earlier or later fails (0.1 % to 0.2 % of the pixels differ then)
    assert diff.mean() < 0.1 and np.mean(diff > 60) < 0.0005, (diff.mean(), np.mean(diff > 60))
    # independent of the reference: each view holds a tall shaded body of stone colour
    half = frame.shape[1] // 2
    for view in (frame[:, :half], frame[:, half:]):
        rgb = view.astype(float) / 255.0
        hue = rgb / np.maximum(rgb.sum(axis=2, keepdims=True), 1e-9)
        stone = (np.abs(hue - STONE / STONE.sum()).max(axis=2) < 0.02) & (rgb.sum(axis=2) > 0.6)
        rows, cols = np.nonzero(stone)
        assert stone.sum() > 2000
        assert (rows.max() - rows.min()) > 3 * (np.percentile(cols, 95) - np.percentile(cols, 5))


def test_euler_rotation_puts_the_axis_and_the_contact_point_where_simulate_does():
    phi, theta = 0.7, 0.3
    rot = euler_rotation(phi, theta, 1.1)
    np.testing.assert_allclose(rot[:, 2], [math.sin(phi) * math.sin(theta), -math.cos(phi) * math.sin(theta),
                                           math.cos(theta)], atol=1e-15)
    # base centre minus contact point, as pipeline.simulate computes x_b - x_p (its y is the same formula)
    centre_to_contact = euler_rotation(phi, theta, 0.0) @ [0.0, -1.0, 0.0]
    np.testing.assert_allclose(-centre_to_contact[:2], [-math.sin(phi) * math.cos(theta),
                                                        math.cos(phi) * math.cos(theta)], atol=1e-15)
    assert centre_to_contact[2] == pytest.approx(-math.sin(theta))  # the base centre is above the pivot


def test_bad_output_names_the_fix(result, tmp_path, capsys):
    assert main(["animate", str(result), "--out", str(tmp_path / "m.avi")]) == 2
    assert ".gif or .mp4" in capsys.readouterr().err
    assert main(["animate", str(result), "--out", str(tmp_path / "m.gif"), "--model", "4d"]) == 2
    assert "4d not in the file" in capsys.readouterr().err


if __name__ == "__main__":  # regenerate the reference frame
    import tempfile

    with tempfile.TemporaryDirectory() as folder:
        ds = open_results(_write_run(Path(folder) / "run.nc"))
        image = render_frame([one_run(ds, model="3d"), one_run(ds, model="2d")], T_REFERENCE)
    REFERENCE.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray(image).save(REFERENCE, optimize=True)
    print(f"wrote {REFERENCE}")
