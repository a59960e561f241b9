"""Study files run the compliant model: options, one run per angle, the same numbers as simulate()."""

import math

import numpy as np
import pytest

from pipeline.errors import InputError
from pipeline.settings import Excitation
from pipeline.simulate import simulate
from pipeline.study import load_motions, load_study
from pipeline.study import run_study
from pipeline.study.grid import plan, record_intensity, scale_factors

STUDY = """\
title = "compliant"
output = "compliant.nc"
models = ["3d", "3d-compliant"]

[[columns]]
named = "paper"

[records]
synthetic = [{generator = "ricker_wavelet", id = "ricker", ap = 4.0, fp = 2.0, dt = 0.01, duration = 3.0}]

[excitation]
angles = [0.0, 7.5, 90.0]
scales = [1.0]

[options]
tail = 1.0
contact_sectors = 16
contact_rings = 3
normal_stiffness = 2e10
joint_friction = 0.5
"""


def test_a_study_runs_the_compliant_model_at_every_angle(write_study):
    study = load_study(write_study(STUDY))
    settings = study.settings("3d-compliant")
    assert settings.contact_sectors == 16 and isinstance(settings.contact_rings, int)
    assert settings.normal_stiffness == 2e10
    motions = load_motions(study)
    tasks = plan(study, scale_factors(study, [record_intensity(m, None) for m in motions]))
    assert sum(t.n_simulations for t in tasks) == 1 + 3  # 3d once (axisymmetric), compliant per angle
    ds = run_study(study, serial=True, progress=False).dataset
    comp = ds.sel(model="3d-compliant")
    peaks = comp.peak_theta.values[0, 0, :, 0]
    # the Ricker wavelet is along x: 90 deg maps the 16 sectors onto themselves, 7.5 deg does not
    # (the same response turned: the points summed in another order, round-off grown through landings)
    assert peaks[2] == pytest.approx(peaks[0], rel=1e-6) and abs(peaks[1] / peaks[0] - 1) > 1e-4
    direct = simulate(study.columns[0].column, motions[0], Excitation(angle=7.5), settings,
                      histories=False).summary
    for name in ("peak_theta", "residual_displacement", "work_ground", "energy_balance_error"):
        assert comp[name].values[0, 0, 1, 0] == direct[name], name
    assert np.all(comp.status.values == 0)


def test_a_bad_compliant_option_names_the_field(write_study):
    with pytest.raises(InputError, match="contact_sectors"):
        load_study(write_study(STUDY.replace("contact_sectors = 16", "contact_sectors = 15")))


DRUM_STUDY = """\
title = "drums"
output = "drums.nc"
models = ["3d", "3d-compliant"]

[[columns]]
named = "paper"

[[columns]]
name = "two"
R = 0.5
r = 0.4
h = 4.0
drums = 2

[records]
synthetic = [{generator = "ricker_wavelet", id = "ricker", ap = 4.0, fp = 2.0, dt = 0.01, duration = 1.5}]

[excitation]
angles = [0.0, 30.0]
scales = [2.0]

[options]
tail = 0.5
contact_sectors = 16
joint_friction = 0.5
"""


def test_a_drum_column_study_has_the_joints_of_simulate(write_study):
    """A monolith and two drums of the same outline: the compliant model's joints along `joint`
    (the monolith's joint 1 and the rigid model's joints NaN), equal to simulate() to the bit;
    the rigid model runs the drums' shaft as a monolith, the same numbers as the monolith's."""
    from pipeline.dataset import open_results
    from pipeline.structures.drums import DrumColumn

    study = load_study(write_study(DRUM_STUDY))
    assert [c.n_bodies for c in study.columns] == [1, 2] and study.n_joints == 2
    report = run_study(study, serial=True, progress=False)
    ds = open_results(report.path)  # through the file: the joint dimension and its attributes survive
    assert ds.joint_slip.dims == ("column", "record", "angle", "scale", "model", "joint")
    assert ds.joint_slip.attrs["units"] == "m" and ds.joint_twist_deg.attrs["units"] == "degree"
    np.testing.assert_array_equal(ds.joint_diameter.values, [[1.0, np.nan], [1.0, 0.9]])
    assert ds.n_drums.values.tolist() == [1, 2]
    rigid = ds.sel(model="3d")
    assert np.isnan(rigid.joint_slip.values).all() and np.isnan(rigid.dislocation_ratio.values).all()
    for name in ("peak_theta", "residual_displacement", "overturned"):
        np.testing.assert_array_equal(rigid[name].sel(column="two").values, rigid[name].sel(column="paper").values)
    comp = ds.sel(model="3d-compliant")
    assert np.isnan(comp.joint_slip.sel(column="paper", joint=1).values).all()
    assert (comp.dislocation_ratio.sel(column="paper").values == 0.0).all()
    settings = study.settings("3d-compliant")
    motion = load_motions(study)[0]
    direct = simulate(DrumColumn.equal(study.columns[1].column, 2), motion, Excitation(angle=30.0, scale=2.0),
                      settings, histories=False).summary
    cell = comp.sel(column="two", angle=30.0, scale=2.0).isel(record=0)
    for name in ("joint_slip", "joint_twist", "joint_tilt", "joint_opening"):
        np.testing.assert_array_equal(cell[name].values, direct[name], err_msg=name)
    assert float(cell.dislocation_ratio) == direct["dislocation_ratio"] == direct["joint_slip"][1] / 0.9
    assert float(cell.peak_theta) == direct["peak_theta"] and int(cell.overturn_drum) == direct["overturn_drum"] == -1
    assert np.all(ds.status.values == 0)


def test_drum_columns_in_a_study_file(write_study):
    """Named columns bring their drums and capital; drums, drum_heights and capital replace them."""
    text = DRUM_STUDY.replace('[[columns]]\nnamed = "paper"\n', (
        '[[columns]]\nnamed = "parthenon-peristyle"\n\n'
        '[[columns]]\nnamed = "parthenon-peristyle"\nname = "shaft"\ndrums = 1\ncapital = false\n\n'
        '[[columns]]\nname = "cut"\nR = 0.5\nr = 0.4\nh = 4.0\ndrum_heights = [1.0, 3.0]\ncapital = [1.2, 0.5]\n'))
    study = load_study(write_study(text), load_records=False)
    parthenon, shaft, cut, two = study.columns
    assert parthenon.stack.n_drums == 11 and parthenon.stack.capital.side == 2.0 and parthenon.n_bodies == 12
    assert shaft.stack is None and shaft.body(study.variant("3d-compliant")) is shaft.column
    assert cut.stack.cuts == (1.0,) and cut.n_bodies == 3 and cut.body(study.variant("3d")) is cut.column
    assert cut.body(study.variant("3d-compliant")) is cut.stack
    assert study.n_joints == 12
    from pipeline.cli.study import describe

    first = describe(study).splitlines()[0]  # what stood, and which models ran it as what
    assert first.startswith("drums: a column of 11 drums and a capital (parthenon-peristyle: Parthenon, Athens "
                            "(Greece): Doric column of the peristyle, marble drums and capital) run by the 3D "
                            "compliant drums on joints (3d-compliant); a monolithic column (the shafts of "
                            "parthenon-peristyle, cut and two, each as one body) run by the 3D rolling frustum (3d); a "
                            "monolithic column (shaft) run by the 3D rolling frustum (3d) and the 3D compliant drums "
                            "on joints")
    said = describe(study).splitlines()[2]  # frustum study check says which columns are drums
    assert said.startswith("columns of drums") and "shaft (" not in said and "cut (2 drum(s)" in said
    for bad, field in [("drums = 2\ndrum_heights = [2.0, 2.0]", "drum_heights"), ("drums = 2.5", "drums"),
                       ("drum_heights = [1.0, 2.0]", "add up to 3 m"), ("capital = [1.0]", "capital")]:
        with pytest.raises(InputError, match=field):
            load_study(write_study(DRUM_STUDY.replace("drums = 2", bad)), load_records=False)


def test_a_column_grid_with_drum_counts(write_study):
    """``drums`` in ``[column_grid]`` is one more grid axis: equal drums, labels ending -dN."""
    grid = "[column_grid]\nR = 0.5\nslenderness = [6.0, 8.0]\nbeta = 0.8\ndrums = [1, 4]\n\n"
    text = DRUM_STUDY.replace('[[columns]]\nnamed = "paper"\n', grid)
    study = load_study(write_study(text), load_records=False)
    labels = [c.label for c in study.columns]
    assert labels == ["two", "R0.5-s6-b0.8-d1", "R0.5-s6-b0.8-d4", "R0.5-s8-b0.8-d1", "R0.5-s8-b0.8-d4"]
    one, four = study.columns[3], study.columns[4]
    assert one.stack is None and one.n_bodies == 1  # one drum is the monolith
    assert four.stack.n_drums == 4 and four.n_bodies == 4 and four.column.h == pytest.approx(4.0)
    assert four.stack.cuts == pytest.approx((1.0, 2.0, 3.0))
    for bad, field in [("drums = [1, 4]", "drums = 0"), ("drums = [1, 4]", "drums = [2, 2.5]"),
                       ("drums = [1, 4]", "drums = [3, 3]")]:
        with pytest.raises(InputError, match="column_grid.drums"):
            load_study(write_study(text.replace(bad, field)), load_records=False)


def test_memory_estimate_counts_the_joint_arrays(write_study):
    """A study of drums holds per cell 4 joint variables x n_joints float64 and 4 scalars (dislocation_ratio,
    epistyle_slip, epistyle_opening float64; overturn_drum int32), copied once."""
    from pipeline.limits import results_bytes
    from pipeline.study.grid import memory_estimate, n_tasks

    study = load_study(write_study(DRUM_STUDY), load_records=False)
    plain = results_bytes(study.n_simulations, n_tasks(study))
    assert study.n_joints == 2
    assert memory_estimate(study) - plain == study.n_simulations * 2 * (3 * 8 + 4 + 4 * 8 * 2)
