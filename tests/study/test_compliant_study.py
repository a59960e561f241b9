"""Study files run the compliant model: options, one run per angle, the same numbers as simulate()."""

import math

import numpy as np
import pytest

from pipeline.errors import InputError
from pipeline.simulate import Excitation, simulate
from pipeline.study import load_motions, load_study
from pipeline.sweep import plan, run_study, scale_factors, record_intensity

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
