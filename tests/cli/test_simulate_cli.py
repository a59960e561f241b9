"""``frustum simulate`` writes the histories the issue names, with units."""

import math

import netCDF4
import numpy as np
import pytest
import xarray as xr

from pipeline.cli import main

REQUIRED = ["time", "tau", "phi", "theta", "psi", "x_p", "y_p", "phi_dot", "theta_dot", "psi_dot",
            "omega_zeta", "energy_hat", "normal_force", "mu_mob"]


def test_free_simulation_writes_annotated_netcdf(tmp_path):
    out = tmp_path / "free.nc"
    status = main(["simulate", "--column", "0.5,0.4,4", "--theta0", "10", "--phi-dot0", "0.44",
                   "--psi-dot0", "-0.89", "--duration", "2", "--out", str(out)])
    assert status == 0
    with netCDF4.Dataset(out) as nc:
        for name in REQUIRED:
            assert name in nc.variables, name
            assert nc.variables[name].units and nc.variables[name].long_name, name
    ds = xr.open_dataset(out).sel(column="R0.5-r0.4-h4", record="free-motion", model="3d")
    assert ds.theta.values[0] == pytest.approx(math.radians(10))
    assert ds.theta_deg.values[0] == pytest.approx(10)
    assert ds.phi_dot.values[0] == pytest.approx(0.44)
    assert ds.time.values[-1] == pytest.approx(2.0)
    # normal force in newtons: about the weight of the column at rest on its rim
    weight = 2700 * math.pi * 4 * (0.25 + 0.2 + 0.16) / 3 * 9.80665
    assert 0.5 * weight < float(ds.normal_force[0]) < 1.5 * weight
    assert not list(tmp_path.glob(".partial-*"))  # written atomically


@pytest.mark.parametrize("argv,message", [
    (["--column", "0.5,0,4"], "column r = 0.0"),
    (["--column", "0.5,0.4"], "R,r,h"),
    (["--column", "0.5,0.4,4", "--theta0", "95"], "theta = 95 deg"),
    (["--column", "0.5,0.4,4", "--theta0", "5", "--duration", "-1"], "duration = -1"),
])
def test_bad_input_is_named(argv, message, tmp_path, capsys):
    argv = ["simulate", *argv, "--out", str(tmp_path / "x.nc")]
    if "--duration" not in argv:
        argv += ["--duration", "1"]
    assert main(argv) == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "x.nc").exists()


def test_earthquake_simulation_writes_netcdf_and_plot(tmp_path, capsys):
    out, png = tmp_path / "r.nc", tmp_path / "r.png"
    status = main(["simulate", "--column", "0.5,0.4,4", "--record", "FEMA-FF-01", "--angle", "30",
                   "--scale", "1", "--model", "3d", "--out", str(out), "--plot", str(png)])
    assert status == 0
    text = capsys.readouterr().out
    assert "stands" in text and "impacts" in text
    ds = xr.open_dataset(out).sel(column="R0.5-r0.4-h4", record="FEMA-FF-01", model="3d")
    for name in REQUIRED + ["ground_acc_x", "ground_acc_y", "phase", "x_b"]:
        assert name in ds and ds[name].attrs.get("long_name"), name
    assert float(ds.angle) == pytest.approx(30) and ds.angle.attrs["units"] == "degree"
    assert np.all(ds.theta.values[ds.time.values < 3.0] == 0.0)  # at rest before the strong motion
    assert png.stat().st_size > 20_000


@pytest.mark.parametrize("argv,message", [
    (["--record", "FEMA-FF-99"], "FEMA-FF-99"),
    (["--record", "FEMA-FF-01", "--scale", "0"], "scale = 0"),
    (["--record", "FEMA-FF-01", "--theta0", "3"], "drop --theta0"),
    (["--theta0", "3"], "--duration"),
])
def test_earthquake_bad_input(argv, message, tmp_path, capsys):
    assert main(["simulate", "--column", "0.5,0.4,4", *argv, "--out", str(tmp_path / "x.nc")]) == 2
    assert message in capsys.readouterr().err
