"""Records as users have them (issue 11): single AT2 components, pairs named on the command line
and in study files, OpenSees plain files, ObsPy streams in memory, and records that need a
baseline correction."""

import json
import re
import warnings

import numpy as np
import obspy
import pytest
import xarray as xr

from pipeline.cli import main
from pipeline.errors import InputError, RecordWarning
from pipeline.groundmotion import intensity as im
from pipeline.groundmotion import kanai_tajimi, load, ricker_wavelet
from pipeline.groundmotion.catalog import records_dir
from pipeline.units import G

AT2_PAIR = [records_dir() / "at2" / "AT2-KT-03_X.AT2", records_dir() / "at2" / "AT2-KT-03_Y.AT2"]


def _at2(path, component, acc_g, dt=0.01):
    """A PEER NGA-West2 file of one component named ``component`` (samples in g)."""
    body = "\n".join("".join(f"{v:15.7E}" for v in acc_g[i:i + 5]) for i in range(0, len(acc_g), 5))
    path.write_text("PEER NGA STRONG MOTION DATABASE RECORD\n"
                    f"Imperial Valley-06, 10/15/1979, El Centro Array #6, {component}\n"
                    "ACCELERATION TIME SERIES IN UNITS OF G\n"
                    f"NPTS={len(acc_g):7d}, DT=   {dt:.4f} SEC\n" + body + "\n")
    return path


@pytest.fixture(scope="module")
def quake():
    """A short two-component motion whose components differ (x: Ricker 3 m/s^2, y: Ricker 1 m/s^2)."""
    x = ricker_wavelet(3.0, 2.0, dt=0.01, duration=3.0)
    y = ricker_wavelet(1.0, 3.0, dt=0.01, duration=3.0)
    return x.acc_x / G, y.acc_x / G


def test_single_at2_090_is_shown_and_simulated_with_missing_y_zero(tmp_path, quake, capsys):
    at2 = _at2(tmp_path / "RSN6_ELC090.AT2", "090", quake[0])
    # without the choice: the message recommends an option the command has
    assert main(["records", "show", str(at2)]) == 2
    err = capsys.readouterr().err
    assert "only one horizontal component" in err and "--missing-y zero" in err
    assert main(["records", "show", str(at2), "--missing-y", "zero", "--json"]) == 0
    rows = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert [r["component"] for r in rows] == ["x", "y"]
    assert rows[0]["pga"] == pytest.approx(3.0 * np.max(np.abs(quake[0])) / 3.0 * G, rel=1e-6) and rows[1]["pga"] == 0.0
    out = tmp_path / "r.nc"
    assert main(["simulate", "--column", "0.5,0.4,4", "--record", str(at2), "--missing-y", "zero",
                 "--out", str(out)]) == 0
    with xr.open_dataset(out) as f:
        ds = f.isel(column=0, record=0, model=0)  # one run: labels on length-1 dimensions (docs/studies.md)
        np.testing.assert_allclose(ds.ground_acc_x.values[:300], quake[0][:300] * G, atol=1e-7 * G)
        assert np.all(ds.ground_acc_y.values == 0.0)
        assert "--missing-y zero" in ds.attrs["history"]


@pytest.mark.parametrize("channel", ["000", "UP", "FN", "HNN"])
def test_one_trace_with_missing_y_zero_is_x_whatever_its_channel(tmp_path, quake, channel):
    gm = load(_at2(tmp_path / f"c{channel}.AT2", channel, quake[0]), missing_y="zero")
    np.testing.assert_allclose(gm.acc_x, quake[0] * G, rtol=1e-6, atol=1e-12)
    assert np.all(gm.acc_y == 0.0) and gm.acc_z is None
    assert any("the only trace" in line and "is x" in line for line in gm.processing)


def test_at2_pair_orientation_from_the_headers(tmp_path, quake):
    east = _at2(tmp_path / "ELC090.AT2", "090", quake[0])
    north = _at2(tmp_path / "ELC000.AT2", "000", quake[1])
    for files in ([east, north], [north, east]):  # list order does not matter: the headers say
        gm = load(files)
        np.testing.assert_allclose(gm.acc_x, quake[0] * G, rtol=1e-6, atol=1e-12)
        np.testing.assert_allclose(gm.acc_y, quake[1] * G, rtol=1e-6, atol=1e-12)
    assert any("x = '090' (azimuth 90 deg), y = '000'" in line for line in gm.processing)
    # 180/270: x is 270 (90 deg clockwise from 180), a frame turned by 180 deg
    gm = load([_at2(tmp_path / "a270.AT2", "270", quake[0]), _at2(tmp_path / "a180.AT2", "180", quake[1])][::-1])
    np.testing.assert_allclose(gm.acc_x, quake[0] * G, rtol=1e-6, atol=1e-12)
    with pytest.raises(InputError, match=r"'000' and '045' .* are not perpendicular; give components=.*--components"):
        load([north, _at2(tmp_path / "a045.AT2", "045", quake[0])])


def test_at2_without_direction_is_taken_in_list_order(tmp_path, quake):
    fn = _at2(tmp_path / "FN.AT2", "FN", quake[0])
    fp = _at2(tmp_path / "FP.AT2", "FP", quake[1])
    gm = load([fp, fn])
    np.testing.assert_allclose(gm.acc_x, quake[1] * G, rtol=1e-6, atol=1e-12)


def test_a_pair_of_at2_files_equals_the_catalogued_pair(tmp_path, capsys):
    pair = ",".join(str(p) for p in AT2_PAIR)
    assert main(["records", "show", pair, "--json"]) == 0
    files = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert main(["records", "show", "AT2-KT-03", "--json"]) == 0
    catalogued = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    for a, b in zip(files, catalogued):
        assert {k: v for k, v in a.items() if k != "record_id"} == {k: v for k, v in b.items() if k != "record_id"}
    outs = []
    for record in (pair, "AT2-KT-03"):
        outs.append(tmp_path / f"{len(outs)}.nc")
        assert main(["simulate", "--column", "0.5,0.4,4", "--record", record, "--tail", "1",
                     "--out", str(outs[-1])]) == 0
    with xr.open_dataset(outs[0]) as a, xr.open_dataset(outs[1]) as b:
        assert a.attrs["record_sha256"] == b.attrs["record_sha256"]
        for name in ("theta", "phi", "ground_acc_x", "ground_acc_y", "mu_mob"):
            np.testing.assert_array_equal(a[name].values, b[name].values)


def test_study_files_take_a_list_of_paths(tmp_path):
    from pipeline.study import load_motions, parse_study

    data = {"columns": [{"named": "paper"}], "excitation": {"scales": [1.0]},
            "records": {"ids": ["AT2-KT-03"], "files": [{"path": [str(p) for p in AT2_PAIR], "id": "pair"}]}}
    study = parse_study(data, tmp_path / "s.toml")
    assert study.records[1].path == tuple(str(p) for p in AT2_PAIR)
    catalogued, pair = load_motions(study)
    assert pair.sha256() == catalogued.sha256()
    data["records"]["files"][0]["path"] = [str(AT2_PAIR[0])] * 4
    with pytest.raises(InputError, match=r"field records\.files\[0\]\.path: a list names the 2 or 3 files"):
        parse_study(data, tmp_path / "s.toml")


def test_opensees_plain_files_one_column_in_g_with_dt(tmp_path, quake, capsys):
    acc_g = quake[0]
    one = tmp_path / "elcentro.g3"  # an extension ObsPy does not know: bare numbers are read as text
    one.write_text("\n".join(f"{v:.8e}" for v in acc_g) + "\n")
    wrapped = tmp_path / "elcentro.th"  # 5 to a line, the last line shorter (301 samples)
    wrapped.write_text("\n".join(" ".join(f"{v:.8e}" for v in acc_g[i:i + 5]) for i in range(0, len(acc_g), 5)))
    a = load(one, units="g", dt=0.01, missing_y="zero")
    b = load(wrapped, units="g", dt=0.01, missing_y="zero")
    np.testing.assert_allclose(a.acc_x, acc_g * G, rtol=1e-8, atol=0)
    assert a.sha256() == b.sha256() and a.npts == 301 and a.dt == 0.01
    assert any("wrapped over rows" in line for line in b.processing)
    with pytest.raises(InputError, match=r"only one horizontal component .*--missing-y zero"):
        load(one, units="g", dt=0.01)
    with pytest.raises(InputError, match=r"1 columns; expected \[time,\] x.*\(with dt=DT \[s\] \(command line: --dt DT"):
        load(one, units="g", missing_y="zero")
    out = tmp_path / "r.nc"
    assert main(["simulate", "--column", "0.5,0.4,4", "--record", str(one), "--units", "g", "--dt", "0.01",
                 "--missing-y", "zero", "--tail", "1", "--out", str(out)]) == 0
    assert "wrote" in capsys.readouterr().out


def test_multi_column_plain_file(tmp_path, quake):
    cols = tmp_path / "xy.acc"
    cols.write_text("\n".join(f"{x:.8e} {y:.8e}" for x, y in zip(*quake)))
    gm = load(cols, units="g", dt=0.01)
    np.testing.assert_allclose(gm.acc_y, quake[1] * G, rtol=1e-8, atol=0)
    timed = tmp_path / "t.txt"
    timed.write_text("\n".join(f"{0.01 * k:.2f} {x:.8e} {y:.8e} 0.0" for k, (x, y) in enumerate(zip(*quake))))
    with pytest.raises(InputError, match=r"first column is a time axis .*give no dt"):
        load(timed, units="g", dt=0.01)


def test_load_takes_an_obspy_stream_or_trace(tmp_path):
    kt = kanai_tajimi(2, duration=4.0, dt=0.01)
    path = tmp_path / "kt.mseed"
    kt.write(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RecordWarning)  # synthetic noise drifts
        from_file = load(path, units="m/s2")
        st = obspy.read(str(path))
        from_stream = load(st, units="m/s2")
        from_trace = load(st[0], units="m/s2", missing_y="zero", record_id="one")
    assert from_stream.sha256() == from_file.sha256()
    np.testing.assert_array_equal(from_trace.acc_x, from_file.acc_x)
    assert from_trace.record_id == "one" and from_stream.record_id == st[0].id
    assert st[0].stats.calib == 1.0 and "processing" not in st[0].stats  # the caller's stream is untouched
    with pytest.raises(InputError, match=r"does not state its units; give units=U \(command line: --units U"):
        load(st)


def test_a_record_with_an_offset_warns_and_names_the_fix(tmp_path, capsys):
    pulse = ricker_wavelet(2.0, 2.0, dt=0.01, duration=4.0)
    shifted = tmp_path / "offset.mseed"
    pulse.scaled(1.0).write(shifted)
    st = obspy.read(str(shifted))
    for tr in st:
        tr.data = tr.data + 5.0 * G  # a 5 g offset, as the record
    st.write(str(shifted), format="MSEED", encoding="FLOAT64")
    with pytest.warns(RecordWarning, match=r"offset\.mseed: component x has an offset: mean 49\.\d+ m/s\^2 .*"
                                            r"baseline_correct.*--baseline linear"):
        load(shifted, units="m/s2")
    with warnings.catch_warnings():
        warnings.simplefilter("error", RecordWarning)  # corrected: no warning
        corrected = load(shifted, units="m/s2", processing=[{"step": "baseline", "type": "demean"}])
    assert im.pga(corrected.acc_x) == pytest.approx(2.0, rel=1e-6)
    assert main(["records", "show", str(shifted), "--units", "m/s2"]) == 0
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith("frustum: warning: ") and "baseline_correct" in err[0]
    assert main(["records", "show", str(shifted), "--units", "m/s2", "--baseline", "demean"]) == 0
    assert capsys.readouterr().err == ""


def test_a_drifting_velocity_warns():
    from pipeline.groundmotion.checks import baseline_problems
    from pipeline.groundmotion.record import GroundMotion

    t = np.arange(1001) * 0.01
    a = np.sin(2 * np.pi * t) + 0.005  # mean 0.5 % of the peak (under 1 %), velocity ends at 0.05 m/s
    gm = GroundMotion.from_arrays(a, np.zeros_like(a), 0.01, record_id="drift")
    assert [p.split(",")[0] for p in baseline_problems(gm)] == ["component x: velocity drifts"]
    assert baseline_problems(load("FEMA-FF-15")) == []  # the worst FEMA record (2.6 %) stays quiet


def test_every_option_a_message_recommends_exists():
    """Every ``--option`` written in the package's source is an option of some frustum command."""
    from pathlib import Path

    from pipeline.cli import build_parser

    def options(parser):
        found = set()
        for action in parser._actions:
            found.update(o for o in action.option_strings if o.startswith("--"))
            for sub in (getattr(action, "choices", None) or {}).values() if hasattr(action, "_name_parser_map") \
                    else ():
                found |= options(sub)
        return found

    known = options(build_parser())
    root = Path(__file__).parents[2] / "pipeline"
    named = set()
    for path in root.rglob("*.py"):
        named |= set(re.findall(r"(?<![\w-])--[a-z][a-z0-9]*(?:-[a-z0-9]+)*", path.read_text(encoding="utf-8")))
    assert {"--missing-y", "--components", "--units", "--dt", "--baseline"} <= named
    other_commands = {"--user", "--now"}  # systemctl's, in what 'frustum workflow install-units' tells to run
    assert sorted(named - known - other_commands) == []


def test_knet_test_file_shows_the_headers_max_acc(knet_file, capsys):
    """`frustum records show test.knet`: PGA 0.04383 m/s^2 = the header's Max. Acc. 4.383 gal, within 1 %."""
    assert main(["records", "show", str(knet_file), "--missing-y", "zero", "--json"]) == 0
    x = json.loads(capsys.readouterr().out.splitlines()[0])
    assert x["pga"] == pytest.approx(0.04383, rel=0.01)
    assert x["pgv"] < 0.01 and x["pgd"] < 0.01  # 2.53 m/s and 74.7 m with the offset left in
    assert main(["records", "show", str(knet_file), "--missing-y", "zero"]) == 0
    assert "offset -0.0429339 m/s^2 removed (mean of the whole record, NIED's definition)" in capsys.readouterr().out


def test_study_file_entries_take_the_record_options(tmp_path, quake):
    from pipeline.study import load_motions, parse_study

    (tmp_path / "gm.g3").write_text("\n".join(f"{v:.8e}" for v in quake[0]))
    entry = {"path": "gm.g3", "units": "g", "dt": 0.01, "missing_y": "zero",
             "processing": [{"step": "baseline", "type": "demean"}]}
    data = {"columns": [{"named": "paper"}], "excitation": {"scales": [1.0]}, "records": {"files": [entry]}}
    study = parse_study(data, tmp_path / "s.toml")
    (motion,) = load_motions(study)
    direct = load(tmp_path / "gm.g3", units="g", dt=0.01, missing_y="zero",
                  processing=[{"step": "baseline", "type": "demean"}])
    assert motion.sha256() == direct.sha256() and study.records[0].id == "gm"
    for key, value, message in [("missing_y", "yes", 'give "zero"'), ("dt", -1, "must be positive"),
                                ("components", ["HNE"], "name x, y[, z]"),
                                ("processing", [{"step": "smooth"}], "with NAME one of baseline")]:
        bad = dict(data, records={"files": [dict(entry, **{key: value})]})
        with pytest.raises(InputError, match=rf"field records\.files\[0\]\.{key}.*{re.escape(message)}"):
            parse_study(bad, tmp_path / "s.toml")
