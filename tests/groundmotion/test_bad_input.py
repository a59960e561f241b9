"""Every bad input gets an InputError naming the file or id and the problem."""

import numpy as np
import obspy
import pytest

from pipeline.errors import InputError
from pipeline.groundmotion import GroundMotion, load, one_sine_pulse


@pytest.fixture()
def mseed(tmp_path):
    gm = one_sine_pulse(2.0, 1.0, dt=0.001, duration=6.0)
    path = tmp_path / "pulse.mseed"
    gm.write(path, format="MSEED", reclen=512)
    return path


def test_truncated_mseed(mseed, tmp_path):
    data = mseed.read_bytes()
    cut = tmp_path / "cut.mseed"
    cut.write_bytes(data[: len(data) // 2 + 100])
    with pytest.raises(InputError, match=r"cut\.mseed: damaged file.*truncated or corrupt"):
        load(cut, units="m/s^2")


def test_truncated_sac(tmp_path):
    tr = obspy.Trace(np.zeros(1000))
    tr.write(str(tmp_path / "a.sac"), format="SAC")
    cut = tmp_path / "cut.sac"
    cut.write_bytes((tmp_path / "a.sac").read_bytes()[:2000])
    with pytest.raises(InputError, match=r"cut\.sac: could not be read.*truncated or corrupt"):
        load(cut, units="g")


def test_corrupt_file(tmp_path):
    junk = tmp_path / "junk.bin"
    junk.write_bytes(b"\x01\x02 not a waveform \xff" * 50)
    with pytest.raises(InputError, match=r"junk\.bin: not a waveform format ObsPy knows"):
        load(junk, units="g")


def test_truncated_at2(tmp_path):
    p = tmp_path / "t.AT2"
    p.write_text("PEER NGA STRONG MOTION DATABASE RECORD\nEv, 1/1/2000, St, 000\n"
                 "ACCELERATION TIME SERIES IN UNITS OF G\nNPTS=     10, DT=   .0100 SEC\n"
                 "  .1000000E-01  .1000000E-01\n")
    with pytest.raises(InputError, match=r"t\.AT2: header says NPTS=10 but the file holds 2 samples"):
        load(p, missing_y="zero")


def test_corrupt_at2_body(tmp_path):
    p = tmp_path / "c.AT2"
    p.write_text("PEER NGA STRONG MOTION DATABASE RECORD\nEv, 1/1/2000, St, 000\n"
                 "ACCELERATION TIME SERIES IN UNITS OF G\nNPTS=      2, DT=   .0100 SEC\n"
                 "  .1000000E-01  ##garbage\n")
    with pytest.raises(InputError, match=r"c\.AT2: unreadable sample text '##garbage'"):
        load(p, missing_y="zero")


def test_at2_missing_sampling(tmp_path):
    p = tmp_path / "m.AT2"
    p.write_text("PEER NGA STRONG MOTION DATABASE RECORD\nEv, 1/1/2000, St, 000\n"
                 "ACCELERATION TIME SERIES IN UNITS OF G\nno sampling here\n  .1E-01\n")
    with pytest.raises(InputError, match=r"m\.AT2: line 4 of the AT2 header gives no sampling"):
        load(p, missing_y="zero")


def test_velocity_file_refused(tmp_path):
    p = tmp_path / "v.AT2"
    p.write_text("PEER NGA STRONG MOTION DATABASE RECORD\nEv, 1/1/2000, St, 000\n"
                 "VELOCITY TIME SERIES IN UNITS OF CM/S\nNPTS=      1, DT=   .0100 SEC\n  .1E-01\n")
    with pytest.raises(InputError, match=r"only acceleration files"):
        load(p, format="AT2", missing_y="zero")


def test_text_missing_sampling(tmp_path):
    from pipeline.groundmotion.files import read_text

    p = tmp_path / "one.txt"
    np.savetxt(p, np.zeros(10))
    # one unnamed column without dt: it would have to be time and nothing else
    with pytest.raises(InputError, match=r"one\.txt: 1 columns; expected \[time,\] x"):
        load(p, units="g")
    named = tmp_path / "named.txt"
    named.write_text("x\n" + "\n".join("0.0" for _ in range(10)))
    with pytest.raises(InputError, match=r"named\.txt: no sampling: give dt=DT \[s\] \(command line: --dt DT; .*or a time column"):
        read_text(named, units="g", missing_y="zero")


def test_text_non_uniform_sampling(tmp_path):
    p = tmp_path / "nu.csv"
    t = np.array([0.0, 0.01, 0.02, 0.035, 0.04, 0.05])
    np.savetxt(p, np.column_stack([t, t, t]), delimiter=",")
    with pytest.raises(InputError, match=r"nu\.csv: non-uniform sampling: time column steps from 0\.02 to 0\.035"):
        load(p, units="g")


def test_stream_with_gap_is_non_uniform(tmp_path):
    tr = obspy.Trace(np.ones(100), header={"channel": "HNE", "sampling_rate": 100.0})
    tr2 = tr.copy()
    tr2.stats.starttime += 2.0
    north = tr.copy()
    north.stats.channel = "HNN"
    p = tmp_path / "gap.mseed"
    obspy.Stream([tr, tr2, north]).write(str(p), format="MSEED")
    with pytest.raises(InputError, match=r"gap\.mseed: trace \.\.\.HNE comes in several pieces \(gaps or overlaps: non-uniform"):
        load(p, units="g")


def test_missing_sampling_rate_on_stream():
    tr = obspy.Trace(np.ones(10))
    tr.stats.sampling_rate = 1.0
    tr2 = tr.copy()
    tr.stats.__dict__["sampling_rate"] = 0.0  # a header without sampling
    with pytest.raises(InputError, match=r"rec: component x .* has no sampling rate .*set the trace.s stats.delta"):
        GroundMotion(obspy.Stream([tr, tr2]), record_id="rec")


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_nan_and_inf_samples(tmp_path, bad):
    p = tmp_path / "bad.csv"
    rows = np.column_stack([np.arange(5) * 0.01, np.ones(5), np.ones(5)])
    rows[3, 1] = bad
    np.savetxt(p, rows, delimiter=",")
    with pytest.raises(InputError, match=r"bad\.csv: component x .* 1 NaN or infinite samples \(first at index 3"):
        load(p, units="g")


def test_components_of_different_lengths(tmp_path):
    x = obspy.Trace(np.ones(100), header={"channel": "HNE", "sampling_rate": 100.0})
    y = obspy.Trace(np.ones(90), header={"channel": "HNN", "sampling_rate": 100.0})
    p = tmp_path / "len.mseed"
    obspy.Stream([x, y]).write(str(p), format="MSEED")
    with pytest.raises(InputError, match=r"len\.mseed: components have different lengths \(x=100, y=90\)"):
        load(p, units="g")
    csv = tmp_path / "len.csv"
    csv.write_text("time,x,y\n0,1,1\n0.01,1,1\n0.02,1\n")
    with pytest.raises(InputError, match=r"len\.csv, line 4: 2 columns where earlier rows have 3"):
        load(csv, units="g")


def test_components_of_different_steps():
    x = obspy.Trace(np.ones(100), header={"sampling_rate": 100.0})
    y = obspy.Trace(np.ones(100), header={"sampling_rate": 50.0})
    with pytest.raises(InputError, match=r"r: components have different time steps \(x=0\.01, y=0\.02 s\)"):
        GroundMotion(obspy.Stream([x, y]), record_id="r")


def test_units_missing_and_unknown(mseed):
    with pytest.raises(InputError, match=r"pulse\.mseed: the file does not state its units; give units="):
        load(mseed)
    with pytest.raises(InputError, match=r"pulse\.mseed: unknown acceleration units 'furlongs'; use one of"):
        load(mseed, units="furlongs")


def test_unknown_record_id():
    with pytest.raises(InputError, match=r"unknown record id or missing file 'FEMA-FF-23'.*frustum records list"):
        load("FEMA-FF-23")
    with pytest.raises(InputError, match=r"unknown record id or missing file 'FEMA-F-01' \(did you mean FEMA-FF-01"):
        load("FEMA-F-01")
    with pytest.raises(InputError, match=r"'FEMA-FF' is a record set, not a record; use load_set"):
        load("FEMA-FF")


def test_changed_bundled_file_is_refused(tmp_path, monkeypatch):
    import shutil

    from pipeline.groundmotion import catalog

    root = catalog.records_dir()
    copy = tmp_path / "records"
    shutil.copytree(root, copy, ignore=shutil.ignore_patterns("*.py"))
    data = bytearray((copy / "synthetic" / "SYN-KT-01.mseed").read_bytes())
    data[-100] ^= 0xFF  # flip bits in the last samples
    (copy / "synthetic" / "SYN-KT-01.mseed").write_bytes(bytes(data))
    monkeypatch.setenv("FRUSTUM_RECORDS", str(copy))
    with pytest.raises(InputError, match=r"SYN-KT-01\.mseed: file digest differs from records/catalog\.toml for SYN-KT-01"):
        load("SYN-KT-01")


def test_polynomial_baseline_without_order_names_the_parameter():
    from pipeline.groundmotion.processing import baseline_correct

    with pytest.raises(InputError, match="needs order="):
        baseline_correct(one_sine_pulse(1.0, 0.5, dt=0.01), "polynomial")
