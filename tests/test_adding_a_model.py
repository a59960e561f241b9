"""Adding a model takes a kernel, one registry entry and catalog entries, and nothing else (issue 28).

A model the pipeline has never seen is registered here, in this file alone, and run through
everything a user reaches: :func:`pipeline.simulate.simulate`, ``frustum simulate --model``, a
study file (``frustum study run``, in this process so that it sees the entry) and ``frustum
report``. No module of the pipeline is edited for it: docs/architecture.md says that this is
all a new model needs, and this test fails if one of those places still names the models it
knows.

The model is the quasi-static overturning check of a rigid block, the oldest and most
conservative of the classical ones: the column is taken to overturn as soon as the horizontal
ground acceleration exceeds ``g tan(alpha)``, ``tan(alpha) = R / z_cm`` (the acceleration at
which a rigid block on a rigid ground starts to uplift, Housner 1963). It follows no motion;
its "kernel" is one comparison, written with numpy.
"""

import math

import numpy as np
import pytest
import xarray as xr

from pipeline import models
from pipeline.cli import main
from pipeline.dataset import annotate
from pipeline.structures.column import Column
from pipeline.groundmotion import load
from pipeline.models.spec import Model, ModelDescription, StateLayout, read
from pipeline.response import Response
from pipeline.settings import Excitation, ModelSettings
from pipeline.simulate import simulate
from pipeline.units import G

NAME = "quasi-static"

# The state of its "kernel": none that evolves; one slot, so that the layout can be declared
# and checked as every model's is.
N_STATE = 1
THETA = 0


def capacity(column):
    """Ground acceleration at which the block uplifts, ``g R / z_cm`` [m/s^2]."""
    return G * column.R / column.z_cm


def quasi_static(column, motion, excitation, settings, histories=True, progress=None):
    """The run of the model: overturned when the horizontal ground acceleration first exceeds
    :func:`capacity`; a :class:`pipeline.response.Response` with every declared result."""
    ax = np.asarray(motion.acc_x, dtype=float) * excitation.scale
    ay = np.asarray(motion.acc_y, dtype=float) * excitation.scale
    horizontal = np.hypot(ax, ay)
    time = np.arange(horizontal.size) * motion.dt
    over = np.flatnonzero(horizontal > capacity(column))
    overturned = over.size > 0
    t_over = float(time[over[0]]) if overturned else math.nan
    peak_theta = 0.5 * math.pi if overturned else 0.0  # lying down, or never tilted
    summary = {
        "peak_theta": peak_theta,
        "peak_theta_ratio": peak_theta / column.critical_tilt,
        "peak_time": t_over if overturned else 0.0,
        "overturn_time": t_over,
        "uplift_time": t_over,
        "peak_mu_mob": float(horizontal.max() / G),  # the friction a base held still needs
        "residual_rotation": 0.0,
        "residual_displacement": 0.0,
        "work_ground": 0.0,
        "energy_balance_error": 0.0,
        "n_impacts": 0,
        "overturned": bool(overturned),
        "undecided": False,  # the check decides at once
        "uplifted": bool(overturned),
        "sliding_onset": bool(horizontal.max() / G > settings.friction),
        "lift_off": False,
    }
    ds = None
    if histories:
        theta = np.where(time >= t_over, 0.5 * math.pi, 0.0) if overturned else np.zeros_like(time)
        ds = xr.Dataset({"theta": ("time", theta), "ground_acc_x": ("time", ax), "ground_acc_y": ("time", ay),
                         "ground_acc_z": ("time", np.zeros_like(ax))}, coords={"time": time})
        # what every model's histories say of the run (pipeline.dataset.histories_file reads it)
        ds.attrs.update(model=settings.model, record_id=motion.record_id, column_R_m=column.R, column_r_m=column.r,
                        column_h_m=column.h, theta_crit_rad=column.critical_tilt,
                        incidence_angle_rad=excitation.angle_rad, scale=excitation.scale)
        annotate(ds)
    return Response(summary, ds)


QUASI_STATIC = Model(
    name=NAME,
    description=ModelDescription(
        title="Quasi-static overturning check",
        body="a rigid block on rigid ground",
        follows=("no motion: it compares the ground acceleration with the block's uplift acceleration",),
        contact="The column overturns when the horizontal ground acceleration first exceeds g R / z_cm.",
        sliding_onset="the ground acceleration exceeded mu g",
        lift_off="never",
        cite="Housner 1963",
        reference="Housner G.W. (1963), The behavior of inverted pendulum structures during earthquakes, "
        "Bulletin of the Seismological Society of America 53(2), 403-417",
    ),
    in_short="quasi-static uplift check of a rigid block (a test model)",
    bodies=("column",),
    angle_invariant=True,  # it reads the magnitude of the horizontal acceleration only
    planar=False,
    numeric_options=read(),
    state=StateLayout(__name__, "N_STATE", (("theta", "THETA"),)),
    histories=("theta", "ground_acc_x", "ground_acc_y", "ground_acc_z"),
    results=models.REGISTRY[models.DEFAULT].results,
    entry_points=(),
    runner=f"{__name__}:quasi_static",
    options=read("friction", "tail"),
)


@pytest.fixture
def registered(monkeypatch):
    """The registry with the new model's one entry added, as a module of pipeline/models would add it."""
    monkeypatch.setitem(models.REGISTRY, NAME, QUASI_STATIC)
    return QUASI_STATIC


def test_simulate_runs_the_new_model_from_its_entry(registered):
    column, motion = Column(0.5, 0.4, 4.0), load("SYN-ONESINE")  # a_p = 0.3 g
    limit = capacity(column) / G  # 0.26 g for this column
    assert 0.2 < limit < 0.3
    stands = simulate(column, motion, Excitation(scale=0.8 * limit / 0.3), ModelSettings(model=NAME))
    falls = simulate(column, motion, Excitation(scale=1.2 * limit / 0.3), ModelSettings(model=NAME))
    assert not stands.summary["overturned"] and falls.summary["overturned"]
    assert set(registered.results) <= set(falls.summary)
    assert set(falls.histories.data_vars) >= set(registered.histories)
    # its options are refused by name like any model's
    with pytest.raises(Exception, match="friction"):
        ModelSettings(model=NAME, friction=-1.0)


def test_the_command_line_lists_and_runs_it(registered, tmp_path, capsys):
    with pytest.raises(SystemExit):
        main(["simulate", "--help"])
    assert NAME in capsys.readouterr().out
    out = tmp_path / "r.nc"
    code = main(["simulate", "--column", "0.5,0.4,4", "--record", "SYN-ONESINE", "--scale", "2",
                 "--model", NAME, "--out", str(out)])
    assert code == 0
    assert f"{NAME}: peak theta" in capsys.readouterr().out
    with xr.open_dataset(out) as ds:
        assert str(ds["model"].values[0]) == NAME


def test_a_study_and_its_report_take_it(registered, tmp_path):
    study = tmp_path / "study.toml"
    study.write_text(f"""title = "A new model beside the paper's"
output = "results.nc"
models = ["{NAME}", "3d"]

[[columns]]
named = "paper"

[records]
ids = ["SYN-ONESINE", "SYN-RICKER"]

[excitation]
angles = [0.0, 45.0]
scales = [0.5, 1.0, 1.5, 2.0]

[options]
tail = 1.0
""")
    assert main(["study", "run", str(study), "--serial", "--quiet"]) == 0
    with xr.open_dataset(tmp_path / "results.nc") as ds:
        assert list(ds["model"].values) == [NAME, "3d"]
        over = ds["overturned"].sel(model=NAME).astype(bool)
        others = [d for d in over.dims if d != "scale"]
        # one comparison with the uplift acceleration: both records peak at 0.3 g, so the
        # outcome is the scale's alone, the same for every record and angle
        limit = capacity(Column(0.5, 0.4, 4.0)) / G
        assert (over.all(others) == over.any(others)).all()
        assert list(over.any(others).values) == list(0.3 * ds["scale"].values > limit)
    assert main(["report", str(tmp_path / "results.nc"), "--out", str(tmp_path / "report"), "--bootstrap", "50"]) == 0
    text = (tmp_path / "report" / "report.md").read_text()
    assert "Quasi-static overturning check" in text
