"""The GroundMotion type: immutability, rotation convention, digest, processing log."""

import math

import numpy as np
import pytest

from pipeline.groundmotion import GroundMotion, one_sine_pulse, processing as proc


@pytest.fixture()
def pulse():
    return one_sine_pulse(2.0, 0.5, dt=0.005, duration=2.0)


def test_arrays_are_read_only_and_stream_is_a_copy(pulse):
    with pytest.raises(ValueError):
        pulse.acc_x[0] = 1.0
    st = pulse.stream
    st[0].data[:] = 0.0
    assert pulse.acc_x.max() == pytest.approx(2.0)
    assert pulse.time[-1] == pytest.approx(pulse.duration) and pulse.npts == 401


def test_rotation_convention(pulse):
    r = pulse.rotated(90.0)  # degrees: motion on x turned to +y
    np.testing.assert_allclose(r.acc_y, pulse.acc_x, atol=1e-15)
    np.testing.assert_allclose(r.acc_x, 0.0, atol=1e-15)
    back = r.rotated(-90.0)
    np.testing.assert_allclose(back.acc_x, pulse.acc_x, atol=1e-15)
    assert "rotated(angle=90.0 deg)" in r.processing[-1]
    assert pulse.processing == [pulse.processing[0]]  # original untouched


def test_scaled_and_digest(pulse):
    s = pulse.scaled(2.0)
    np.testing.assert_array_equal(s.acc_x, 2.0 * pulse.acc_x)
    assert s.sha256() != pulse.sha256() and pulse.scaled(1.0).sha256() == pulse.sha256()
    assert len(pulse.sha256()) == 64


def test_processing_steps_use_obspy_and_are_logged(fema_ff01):
    gm = fema_ff01.with_processing(
        {"step": "baseline", "type": "linear"},
        {"step": "taper", "max_percentage": 0.05},
        {"step": "bandpass", "freqmin": 0.1, "freqmax": 20.0},
        ("resample", {"dt": 0.005}),
        {"step": "trim_arias"},
        {"step": "scale_to", "measure": "pga", "target": 3.0},
    )
    log = "\n".join(gm.processing)
    for text in ("ObsPy", "detrend(", "taper(", "filter(", "interpolate(", "trim(", "trim_arias(", "scale_to("):
        assert text in log
    assert gm.dt == 0.005
    assert max(np.abs(gm.acc_x).max(), np.abs(gm.acc_y).max()) == pytest.approx(3.0, rel=1e-12)
    # 5-95 % trim: the kept window carries 90 % of the Arias intensity.
    from pipeline.groundmotion import intensity as im
    total = im.arias_intensity(fema_ff01.acc_x, fema_ff01.dt) + im.arias_intensity(fema_ff01.acc_y, fema_ff01.dt)
    trimmed = proc.trim_arias(fema_ff01)
    kept = im.arias_intensity(trimmed.acc_x, trimmed.dt) + im.arias_intensity(trimmed.acc_y, trimmed.dt)
    assert kept / total == pytest.approx(0.90, abs=0.01)  # nearest-sample cut: within one dt of the crossings


def test_scale_to_arias_and_sa(fema_ff01):
    from pipeline.groundmotion import intensity as im

    a = proc.scale_to(fema_ff01, "arias", 1.0, combine="x")
    assert im.arias_intensity(a.acc_x, a.dt) == pytest.approx(1.0, rel=1e-12)
    s = proc.scale_to(fema_ff01, "sa", 4.0, combine="geomean", period=1.0)
    assert math.sqrt(im.spectral_acceleration(s.acc_x, s.dt, 1.0) * im.spectral_acceleration(s.acc_y, s.dt, 1.0)) == pytest.approx(4.0)
    r = proc.scale_to(fema_ff01, "pga", 5.0, combine="rotd50")
    assert im.rotd50(r.acc_x, r.acc_y, r.dt) == pytest.approx(5.0)


def test_processing_bad_arguments(pulse):
    from pipeline.errors import InputError

    with pytest.raises(InputError, match="freqmax=150.0 Hz is at or above the Nyquist frequency 100.0 Hz"):
        proc.bandpass(pulse, 0.1, 150.0)
    with pytest.raises(InputError, match="processing step 1 is 'smooth'"):
        proc.apply(pulse, [{"step": "smooth"}])


def test_explicit_construction_checks():
    from pipeline.errors import InputError

    with pytest.raises(InputError, match="r: a ground motion needs 2 horizontal components"):
        GroundMotion([], record_id="r")
    gm = GroundMotion.from_arrays([0.0, 1.0, 0.0], [0.0, 0.0, 0.0], 0.01, acc_z=[0.0, 0.5, 0.0], record_id="tiny")
    assert gm.components == ("x", "y", "z") and gm.acc_z[1] == 0.5
