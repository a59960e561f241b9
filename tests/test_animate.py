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

from pipeline.animate import STONE, Motion, drum_bodies, euler_rotation, frame_times, frustum_faces, render_frame
from pipeline.cli import main
from pipeline.dataset import histories_file, one_run, open_results, write_netcdf
from pipeline.structures.column import Column
from pipeline.groundmotion.synthesis import one_sine_pulse
from pipeline.settings import Excitation, ModelSettings
from pipeline.simulate import simulate

COLUMN = Column(0.5, 0.4, 4.0)
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


def _drum_run(rows):
    """Histories of a column of two drums and a capital in the layout of pipeline.compliant, at rest
    on a still ground, with the drums' states of ``rows`` (dict name -> (time, drum) values) put in."""
    import xarray as xr

    n_t = 2
    shapes = [(0.5, 0.45, 2.0, 0), (0.45, 0.4, 2.0, 0), (0.6, 0.6, 0.4, 1)]
    zeros = np.zeros(n_t)
    data = {name: ("time", zeros.copy()) for name in ("theta", "phi", "psi", "x_p", "y_p", "x_b", "y_b",
                                                       "ground_acc_x", "ground_acc_y", "ground_acc_z")}
    for name in ("drum_dx", "drum_dy", "drum_dz", "drum_theta", "drum_phi", "drum_rotation"):
        data[name] = (("time", "drum"), np.asarray(rows.get(name, np.zeros((n_t, 3))), dtype=float))
    coords = {"time": [0.0, 0.5], "drum": [0, 1, 2], "drum_z": ("drum", [0.0, 2.0, 4.0]),
              "drum_R": ("drum", [s[0] for s in shapes]), "drum_r": ("drum", [s[1] for s in shapes]),
              "drum_h": ("drum", [s[2] for s in shapes]), "drum_kind": ("drum", [s[3] for s in shapes]),
              "column_R": 0.5, "column_r": 0.4, "column_h": 4.0, "theta_crit": 0.12}
    return xr.Dataset(data, coords=coords, attrs={"model": "3d-compliant"})


def test_every_drum_is_drawn_at_its_own_displacement_tilt_and_rotation():
    """A known state: drum 0 slid and turned, drum 1 tilted towards phi and turned, the capital
    lifted and turned. The drawn faces are where the paper's Euler convention puts them (axis
    (sin phi sin theta, -cos phi sin theta, cos theta), centre of mass z_cm up the axis), to round-off."""
    rows = {"drum_dx": [[0, 0, 0], [0.1, 0.2, 0.3]], "drum_dy": [[0, 0, 0], [-0.05, 0.0, 0.1]],
            "drum_dz": [[0, 0, 0], [0.0, 0.01, 0.02]], "drum_theta": [[0, 0, 0], [0.0, 0.2, 0.0]],
            "drum_phi": [[np.nan] * 3, [np.nan, 0.7, np.nan]], "drum_rotation": [[0, 0, 0], [0.3, 0.9, 0.25]]}
    motion = Motion(_drum_run(rows))
    assert motion.height == pytest.approx(4.4)  # the capital's top sets the view
    bodies = drum_bodies(motion, 1)
    assert [shape.sides for shape, _ in bodies] == [0, 0, 4]
    faces = [frustum_faces(shape, pose)[0] for shape, pose in bodies]
    bottom, top = [f[-2] for f in faces], [f[-1] for f in faces]
    # drum 0 upright: its base slid by (0.1, -0.05) and turned by 0.3 rad (the first vertex at angle 0)
    np.testing.assert_allclose(bottom[0][0], [0.1 + 0.5 * math.cos(0.3), -0.05 + 0.5 * math.sin(0.3), 0.0], atol=1e-14)
    np.testing.assert_allclose(top[0].mean(axis=0), [0.1, -0.05, 2.0], atol=1e-14)
    # drum 1 tilted: the centre of mass at rest (z_cm of a frustum 0.45 -> 0.4, 2 m) moved by (0.2, 0, 0.01)
    R, r, h, theta, phi = 0.45, 0.4, 2.0, 0.2, 0.7
    zc = h * (R**2 + 2 * R * r + 3 * r**2) / (4 * (R**2 + R * r + r**2))
    axis = np.array([math.sin(phi) * math.sin(theta), -math.cos(phi) * math.sin(theta), math.cos(theta)])
    base = np.array([0.2, 0.0, 2.0 + zc + 0.01]) - zc * axis
    np.testing.assert_allclose(bottom[1].mean(axis=0), base, atol=1e-14)
    np.testing.assert_allclose(top[1].mean(axis=0), base + h * axis, atol=1e-14)
    np.testing.assert_allclose(np.linalg.norm(top[1] - (base + h * axis), axis=1), r, rtol=1e-14)
    np.testing.assert_allclose((top[1] - base - h * axis) @ axis, 0.0, atol=1e-14)  # the top face is square to the axis
    # the capital: a square of side 1.2 turned by 0.25 rad, lifted by 0.02 m
    edges = np.roll(bottom[2], -1, axis=0) - bottom[2]
    np.testing.assert_allclose(np.linalg.norm(edges, axis=1), 1.2, rtol=1e-14)
    np.testing.assert_allclose(edges[0] / 1.2, [-math.cos(0.25), -math.sin(0.25), 0.0], atol=1e-14)  # sides along x, y
    np.testing.assert_allclose(bottom[2].mean(axis=0), [0.3, 0.1, 4.02], atol=1e-14)


def test_frustum_animate_draws_a_compliant_run_of_two_drums(tmp_path, capsys):
    """A simulated stack of two drums (3d-compliant) in a file with the rigid 3d run: frustum animate
    writes every frame, and drum 0's drawn base sits where the simulation put the base centre
    (x_b, y_b, from its quaternion directly) plus the ground's displacement, to round-off."""
    from pipeline.animate import ground_displacement
    from pipeline.structures.drums import DrumColumn

    motion = one_sine_pulse(6.0, 0.4, dt=0.01, record_id="pulse")
    runs = [simulate(DrumColumn.equal(Column(0.5, 0.4, 4.0), 2), motion, Excitation(angle=30.0),
                     ModelSettings(model="3d-compliant", tail=0.6, contact_sectors=16, joint_friction=0.5)).histories,
            simulate(Column(0.5, 0.4, 4.0), motion, Excitation(angle=30.0), ModelSettings(model="3d", tail=0.6)).histories]
    path = tmp_path / "drums.nc"
    write_netcdf(histories_file(runs, column="two", record="pulse"), path)
    out = tmp_path / "drums.gif"
    assert main(["animate", str(path), "--out", str(out)]) == 0
    assert "11 frames" in capsys.readouterr().out  # 0, 0.1, ..., 1.0 s
    with Image.open(out) as gif:
        assert gif.n_frames == 11 and gif.size == (768, 416)
    run = one_run(open_results(path), model="3d-compliant")
    drawn = Motion(run)
    assert len(drawn.drums) == 2 and drawn.height == pytest.approx(4.0, abs=1e-4)
    i = int(np.argmax(run["theta"].values))  # the largest tilt: drum 0 rocks on its rim
    assert run["drum_theta"].values[i, 0] > 0.01
    ground = np.stack([ground_displacement(run[f"ground_acc_{c}"].values, run["time"].values) for c in "xy"], axis=1)
    base0 = drum_bodies(drawn, i)[0][1].centre
    np.testing.assert_allclose(base0[:2], [run["x_b"].values[i] + ground[i, 0], run["y_b"].values[i] + ground[i, 1]],
                               rtol=0, atol=1e-9)


def _supported(frame_):
    """Whether every body a frame draws rests on the ground or on the drawn body below it (to 1 cm)."""
    from pipeline.animate import frustum_faces, lowest_point

    tops = {}
    for b, shape, pose in frame_.bodies:
        tops[b] = float(max(face[:, 2].max() for face in frustum_faces(shape, pose)[0]))
    for b, shape, pose in frame_.bodies:
        low = lowest_point(shape, pose)
        if not (abs(low) <= 0.01 or (b - 1 in tops and low <= tops[b - 1] + 0.01)):
            return False
    return True


@pytest.fixture(scope="module")
def fallen_stack(tmp_path_factory):
    """Two drums and a capital (the paper's column) that a 0.51 g one-sine pulse of 1 s overturns: the top
    drum reaches its lying tilt at 2.21 s on the rim of the bottom one, 2 m up (the compliant run ends
    there), written as 'frustum simulate' writes it, with its summary."""
    from pipeline.structures.drums import Capital, DrumColumn

    column = DrumColumn.equal(Column(0.5, 0.4, 4.0), 2, capital=Capital(1.1, 0.3))
    response = simulate(column, one_sine_pulse(5.0, 1.0, dt=0.01, record_id="pulse"), Excitation(angle=30.0),
                        ModelSettings(model="3d-compliant", tail=4.0, contact_sectors=16))
    path = tmp_path_factory.mktemp("fallen") / "fallen.nc"
    write_netcdf(histories_file([response.histories], column="two", record="pulse",
                                summaries=[response.summary]), path)
    return one_run(open_results(path)), response.summary


def test_a_drum_column_that_overturned_is_shown_as_the_run_left_it_and_says_so(fallen_stack):
    """From the overturn on: the caption says when and which bodies fell, the view stays at the last
    computed row, and no body is drawn in the air (before: the top drum and the capital hung there for the
    rest of the record while the ground moved on, and nothing said the run had ended)."""
    from pipeline.animate import frame, lowest_point

    run, summary = fallen_stack
    motion = Motion(run)
    assert summary["overturned"] and summary["overturn_drum"] == 1  # the premise: the top drum lay down first
    over = summary["overturn_time"]
    times = frame_times(motion.time, 10.0)
    before = [frame(motion, t) for t in times if t < over]
    after = [frame(motion, t) for t in times if t >= over]
    assert len(before) > 10 and len(after) > 10
    assert all(not f.ended and f.caption == "" and len(f.bodies) == 3 for f in before)
    assert all(_supported(f) for f in before)  # the check below holds the standing column too
    row = motion.overturn_row
    in_the_air = [b for b, (shape, pose) in enumerate(drum_bodies(motion, row)) if lowest_point(shape, pose) > 1.0]
    assert in_the_air == [1, 2]  # the premise: the last computed state has the top drum and capital up high
    for f in after:
        assert f.ended and f.row == row  # still: the last computed state, not the held rows moving on
        assert f.caption.startswith(f"Overturned at {over:.2f} s: the run ends here")
        assert "Drum 2 and the capital fell: not drawn" in f.caption
        assert [b for b, _, _ in f.bodies] == [0]  # the bottom drum stands; nothing hangs in the air
        assert _supported(f)


def test_the_view_of_a_fallen_column_is_drawn_greyed_and_the_animation_ends_soon_after(fallen_stack):
    from pipeline.animate import HOLD, _end_time

    run, summary = fallen_stack
    over = summary["overturn_time"]
    motion = Motion(run)
    assert motion.time[-1] == pytest.approx(5.0)  # the premise: 1 s pulse and 4 s of tail
    times = frame_times(motion.time, 10.0, end=_end_time([motion], speed=1.0))
    assert times[-1] == pytest.approx(math.floor((over + HOLD) * 10) / 10)  # not the 2.8 s of still frames after
    for t, stone in ((over - 0.3, True), (over + 0.1, False)):
        rgb = render_frame([run], t).astype(float) / 255.0
        hue = rgb / np.maximum(rgb.sum(axis=2, keepdims=True), 1e-9)
        coloured = (np.abs(hue - STONE / STONE.sum()).max(axis=2) < 0.02) & (rgb.sum(axis=2) > 0.6)
        grey = (np.ptp(rgb, axis=2) < 0.01) & (rgb.sum(axis=2) > 0.6) & (rgb.sum(axis=2) < 2.7)
        # before: marble-coloured drums; after: the standing drum in grey, no marble (a few edge pixels
        # of the anti-aliased plate fall within the hue's 2 %: 8 of them here)
        if stone:
            assert coloured.sum() > 1000
        else:
            assert coloured.sum() < 50 and grey.sum() > 1000, (coloured.sum(), grey.sum())


def test_a_rigid_column_that_overturned_lies_greyed_and_the_caption_says_when():
    """The rigid models follow the final fall until the column lies on its side: drawn there, on the ground."""
    from pipeline.animate import frame, lowest_point

    motion_ = one_sine_pulse(8.0, 0.8, dt=0.01, record_id="pulse")
    response = simulate(COLUMN, motion_, Excitation(angle=30.0, scale=2.0), ModelSettings(tail=2.0))
    assert response.summary["overturned"]  # the premise
    motion = Motion(one_run(histories_file([response.histories], column="paper", record="pulse",
                                           summaries=[response.summary])))
    after = [frame(motion, t) for t in frame_times(motion.time, 10.0) if t >= motion.overturn_time]
    assert after
    for f in after:
        assert f.ended and f.row == motion.overturn_row
        assert f.caption.startswith(f"Overturned at {motion.overturn_time:.2f} s: the run ends here")
        assert "The column fell and lies on the ground as computed" in f.caption
        ((b, shape, pose),) = f.bodies
        assert abs(lowest_point(shape, pose)) < 0.01 and _supported(f)


if __name__ == "__main__":  # regenerate the reference frame
    import tempfile

    with tempfile.TemporaryDirectory() as folder:
        ds = open_results(_write_run(Path(folder) / "run.nc"))
        image = render_frame([one_run(ds, model="3d"), one_run(ds, model="2d")], T_REFERENCE)
    REFERENCE.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray(image).save(REFERENCE, optimize=True)
    print(f"wrote {REFERENCE}")


def test_frustum_animate_draws_a_colonnade_body_by_body(tmp_path, capsys):
    """A compliant colonnade (two columns of a drum and a capital, one epistyle block) under a pulse: the
    simulate command animates it, every body drawn where it stands along the row; the block is
    drawn as its box (half length and half width from the file), resting on both capitals' tops
    (its underside within 1 mm of the abacus top, at its rest penetration of microns), and the
    view's ground plate spans the row."""
    from pipeline.animate import frame, lowest_point
    from pipeline.structures.colonnade import Colonnade
    from pipeline.structures.drums import Capital, DrumColumn

    row = Colonnade(DrumColumn.equal(Column(0.5, 0.4, 4.0), 1, Capital(1.1, 0.3)), 2, 2.5, 0.8)
    motion = one_sine_pulse(3.0, 0.4, dt=0.01, record_id="pulse")
    run = simulate(row, motion, Excitation(), ModelSettings(model="3d-compliant", tail=0.3, contact_sectors=8))
    path = tmp_path / "row.nc"
    write_netcdf(histories_file([run.histories], column="row", record="pulse", summaries=[run.summary]), path)
    out = tmp_path / "row.gif"
    assert main(["animate", str(path), "--out", str(out)]) == 0
    assert "8 frames" in capsys.readouterr().out  # 0, 0.1, ..., 0.7 s
    drawn = Motion(one_run(open_results(path)))
    assert [s.sides for s in drawn.drums] == [0, 4, 0, 4, 4] and drawn.drums[-1].half_y == pytest.approx(0.55)
    assert drawn.labels[-1] == "epistyle block 1" and drawn.span == pytest.approx((-1.25 - 0.55, 1.25 + 0.55))
    shown = frame(drawn, 0.0)
    assert len(shown.bodies) == 5 and not shown.ended
    block = shown.bodies[-1]
    assert lowest_point(block[1], block[2]) == pytest.approx(4.3, abs=1e-3)  # on the abacus tops
    np.testing.assert_allclose(block[2].centre[:2], [0.0, 0.0], atol=1e-6)  # between the two columns


def _drawn_bodies(view):
    """The bodies a drawn view shows: its solids that are visible and hold a body's faces (more than the one
    placeholder triangle every solid starts with)."""
    return [solid for solid in view.solids if solid.get_visible() and len(solid.get_paths()) > 1]


@pytest.fixture(scope="module")
def frame_row(tmp_path_factory):
    """A rigid frame (2d-frame) of three of the paper's columns with capitals under two epistyle blocks, rocking
    under a one-sine pulse, and the same row as the compliant model, in one file as frustum simulate writes it."""
    from pipeline.structures.colonnade import Colonnade
    from pipeline.structures.drums import Capital, DrumColumn

    row = Colonnade(DrumColumn(Column(0.5, 0.4, 4.0), capital=Capital(1.1, 0.3)), 3, 2.5, 0.8)
    pulse = one_sine_pulse(4.0, 0.5, dt=0.01, record_id="pulse")
    runs = [simulate(row, pulse, Excitation(), ModelSettings(model=m, tail=0.5, **extra))
            for m, extra in (("3d-compliant", {"contact_sectors": 8}), ("2d-frame", {}))]
    path = tmp_path_factory.mktemp("frame") / "row.nc"
    write_netcdf(histories_file([r.histories for r in runs], column="row", record="pulse",
                                summaries=[r.summary for r in runs]), path)
    return row, path


def test_a_rigid_frame_is_drawn_as_the_frame_its_file_describes(frame_row):
    """Issue 47, item 2: a 2d-frame run is drawn as its frame, read back from the file's attributes: every column
    with its capital and the epistyle, 3 + 3 + 1 bodies drawn (before: one bare column). The columns turn in
    unison by the frame's tilt about their pivots and the epistyle, translated as the model says
    (epistyle_dx, epistyle_dz), rests on the capitals' top edges opposite the pivots, to round-off: the drawing
    and the model's own histories agree."""
    from pipeline.animate import _figure, frustum_faces

    row, path = frame_row
    run = one_run(open_results(path), model="2d-frame")
    i = int(np.nanargmax(run["theta"].values))
    t = float(run["time"].values[i])
    assert math.degrees(float(run["theta"].values[i])) > 0.5  # the premise: the frame rocks
    fig, views = _figure([run], dpi=40)
    try:
        views[0].draw(t)
        fig.canvas.draw()
        assert len(_drawn_bodies(views[0])) == 7
        assert "2D rigid frame of a colonnade: 7 bodies" in views[0].title.get_text()
    finally:
        import matplotlib.pyplot as plt

        plt.close(fig)
    motion = views[0].motion
    bodies = motion.bodies(motion, i)
    assert [shape.sides for shape, _ in bodies] == [0, 4, 0, 4, 0, 4, 4]
    epistyle = frustum_faces(*bodies[-1])[0][-2]  # its underside
    lean = math.copysign(1.0, float(run["phi"].values[i]))  # +1: towards +x, on the pivots at +R
    for k in range(3):
        top = frustum_faces(*bodies[2 * k + 1])[0][-1]  # the capital's top face
        edge = top[np.argmax(top[:, 2])]  # its highest corner: on the edge opposite the pivot
        assert math.copysign(1.0, edge[0] - row.axes()[k] - float(run["x_b"].values[i])) == -lean
        np.testing.assert_allclose(edge[2], epistyle[:, 2].max(), rtol=0, atol=1e-9)
        # and it moved along the row by the epistyle's translation, the model's epistyle_dx
        np.testing.assert_allclose(edge[0], row.axes()[k] - lean * 0.55 + float(run["epistyle_dx"].values[i])
                                   + motion.ground[i, 0], rtol=0, atol=1e-9)
    # the epistyle's underside lies level on those edges, its x the row's blocks' span moved by epistyle_dx
    np.testing.assert_allclose(np.ptp(epistyle[:, 2]), 0.0, atol=1e-12)
    np.testing.assert_allclose([epistyle[:, 0].min(), epistyle[:, 0].max()],
                               np.array([-2.5 - 0.55, 2.5 + 0.55]) + float(run["epistyle_dx"].values[i])
                               + motion.ground[i, 0], atol=1e-9)


def test_side_by_side_each_panel_has_its_own_theta_crit(frame_row):
    """A file with 3d-compliant and 2d-frame of one row: the compliant panel's theta_crit is its column's (15.1 deg),
    the frame's panel the frame's (before: both the frame's)."""
    from pipeline.animate import _figure

    row, path = frame_row
    ds = open_results(path)
    fig, views = _figure([one_run(ds, model="3d-compliant"), one_run(ds, model="2d-frame")], dpi=40)
    try:
        for view in views:
            view.draw(0.5)
        compliant, frame_ = (view.title.get_text() for view in views)
    finally:
        import matplotlib.pyplot as plt

        plt.close(fig)
    assert "(θ_crit 15.1°)" in compliant and "3D compliant drums on joints: 8 bodies" in compliant
    assert f"(θ_crit {math.degrees(row.frame.alpha):.1f}°)" in frame_ and math.degrees(row.frame.alpha) < 14.0


def test_simulate_animates_a_rigid_frame(tmp_path, capsys):
    """`frustum simulate --model 2d-frame --animate` draws the frame, as `frustum animate` does (before: refused)."""
    out, gif = tmp_path / "frame.nc", tmp_path / "frame.gif"
    assert main(["simulate", "--column", "0.5,0.4,4", "--capital", "1.1,0.3", "--model", "2d-frame", "--colonnade", "3",
                 "--interaxial", "2.5", "--epistyle", "0.8", "--record", "SYN-RICKER", "--tail", "0.5", "--out",
                 str(out), "--animate", str(gif)]) == 0
    assert f"wrote {gif}" in capsys.readouterr().out
    with Image.open(gif) as image:
        assert image.n_frames > 10
    assert len(Motion(one_run(open_results(out))).frame) == 7

