"""The compiled rigid 3D run agrees with the same model integrated by scipy."""

import math

import numpy as np
import pytest

from pipeline.dynamics.rigid import frustum as fk
from pipeline.dynamics.rigid import layout as lay
from pipeline.dynamics.rigid.run3d import run_frustum
from pipeline.dynamics.reference import run_frustum_scipy
from pipeline.structures.column import Column
from pipeline.groundmotion import GroundMotion, ricker_wavelet
from pipeline.settings import ModelSettings
from pipeline.simulate import _options
from pipeline.units import G


def _problem(rtol):
    column = Column(0.5, 0.4, 4.0)
    # a bidirectional motion: two Ricker wavelets, x and y, offset in time
    wx = ricker_wavelet(0.45 * G, 1.2, dt=0.005, t0=1.5, duration=6.0)
    wy = ricker_wavelet(0.35 * G, 0.9, dt=0.005, t0=2.2, duration=6.0)
    motion = GroundMotion.from_arrays(wx.acc_x, wy.acc_x, 0.005, record_id="two-rickers")
    ts = math.sqrt(column.R / G)
    record = np.ascontiguousarray(np.stack([motion.acc_x, motion.acc_y, np.zeros(motion.npts)], 1) / G)
    dt = motion.dt / ts
    params = (column.kernel_constants(), record, dt, _options(column, ModelSettings()))
    t_end = 8.0 / ts
    t_out = np.linspace(0, t_end, 801)
    return [params, -1.0, np.zeros(fk.N_STATE), t_end, t_end, t_out, np.zeros((801, fk.N_STATE)),
            np.zeros(801, np.int8), np.arange(len(record)) * dt, rtol, rtol * 1e-3,
            np.zeros(lay.N_SUMMARY), np.zeros((100, 4))]


def test_compiled_hybrid_matches_scipy_reference():
    compiled = _problem(1e-10)
    run_frustum(*compiled)
    reference = _problem(1e-12)
    run_frustum_scipy(*reference)
    s_c, s_r = compiled[11], reference[11]
    assert s_c[lay.S_PEAK_THETA] > 0.05  # it really rocks and wobbles
    assert s_c[lay.S_N_IMPACTS] == s_r[lay.S_N_IMPACTS]
    assert math.isnan(s_c[lay.S_OVERTURN_TIME]) == math.isnan(s_r[lay.S_OVERTURN_TIME])
    # two integrators of the same model, both converged to ~1e-7 or better
    assert s_c[lay.S_PEAK_THETA] == pytest.approx(s_r[lay.S_PEAK_THETA], rel=1e-6)
    rows = compiled[7] == lay.PHASE_ROLLING
    np.testing.assert_allclose(compiled[6][rows, fk.THETA], reference[6][rows, fk.THETA], atol=1e-6)
