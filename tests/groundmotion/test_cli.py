"""``frustum records list|show|plot``."""

import json

import pytest

from pipeline.cli import main
from pipeline.groundmotion import intensity as im, load
from pipeline.groundmotion.catalog import records_dir


def test_list(capsys):
    assert main(["records", "list"]) == 0
    out = capsys.readouterr().out
    for set_id in ("FEMA-FF", "FEMA-NFP", "FEMA-NFNP", "SYN", "AT2-EXAMPLES"):
        assert set_id in out
    assert main(["records", "list", "--set", "FEMA-NFNP"]) == 0
    assert "FEMA-NFNP-14" in capsys.readouterr().out


def test_show_json_catalog_id(capsys):
    assert main(["records", "show", "SYN-KT-01", "--json"]) == 0
    rows = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert [r["component"] for r in rows] == ["x", "y"]
    gm = load("SYN-KT-01")
    assert rows[0]["npts"] == gm.npts and rows[0]["dt"] == gm.dt
    assert rows[0]["pga"] == im.pga(gm.acc_x) and rows[1]["pgv"] == im.pgv(gm.acc_y, gm.dt)
    assert rows[1]["arias"] == im.arias_intensity(gm.acc_y, gm.dt)


def test_show_file_and_errors(capsys, knet_file):
    at2 = records_dir() / "at2" / "AT2-KT-03_X.AT2"
    assert main(["records", "show", str(at2), "--missing-y", "zero", "--json"]) == 0
    assert len(capsys.readouterr().out.splitlines()) == 2
    assert main(["records", "show", str(knet_file), "--missing-y", "zero"]) == 0
    assert "header calibration" in capsys.readouterr().out
    assert main(["records", "show", "NOPE-01"]) == 2
    assert "unknown record id or missing file 'NOPE-01'" in capsys.readouterr().err


def test_plot(tmp_path, capsys):
    out = tmp_path / "syn.png"
    assert main(["records", "plot", "SYN-MP", "--out", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and out.stat().st_size > 20_000
    assert main(["records", "plot", "SYN-MP", "--out", str(tmp_path / "x.pdf")]) == 0  # any matplotlib format
    assert (tmp_path / "x.pdf").read_bytes()[:4] == b"%PDF"
    assert main(["records", "plot", "SYN-MP", "--out", str(tmp_path / "x.docx")]) == 2
