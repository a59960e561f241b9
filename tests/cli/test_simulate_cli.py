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
    (["--column", "0.5,0.4,4", "--theta0", "5", "--duration", "-1"], "--duration -1.0: give a positive number"),
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


@pytest.fixture
def no_computing(monkeypatch):
    """Make any simulation fail the test: what is refused must be refused before computing."""
    import pipeline.simulate

    def forbidden(*args, **kwargs):
        raise AssertionError("computed before refusing")

    monkeypatch.setattr(pipeline.simulate, "simulate", forbidden)
    monkeypatch.setattr(pipeline.simulate, "simulate_free", forbidden)


FREE = ["--column", "0.5,0.4,4", "--theta0", "5", "--duration", "2"]
QUAKE = ["--column", "0.5,0.4,4", "--record", "FEMA-FF-01"]


@pytest.mark.parametrize("argv, message", [
    # 1e9 s every 0.01 s: 1e11 rows of 1 KiB; it once tried to allocate 745 GiB and died
    (FREE[:-1] + ["1e9"], "1e+09 s of histories every 0.01 s (100,000,000,001 rows) needs about 93.1 TiB of memory"),
    (QUAKE + ["--output-step", "1e-9"], "rows) needs about"),
    (QUAKE + ["--rtol", "0"], "--rtol 0.0: give a number in [1e-14, 0.1]"),
    (QUAKE + ["--rtol", "1e-20"], "--rtol 1e-20: give a number in [1e-14, 0.1]"),
    (FREE + ["--atol", "0"], "--atol 0.0: give a number in [1e-300, 0.01]"),
    (QUAKE + ["--plot", "x.txt"], "--plot 'x.txt': not a figure format matplotlib writes"),
    (QUAKE + ["--dt", "0"], "--dt 0.0: give the time step as a positive number of seconds"),
    # a flag no model of the run reads would be ignored, and the file would look as if it had taken it
    (QUAKE + ["--model", "3d,2d", "--joint-friction", "0.6"],
     "--joint-friction is an option of --model 3d-compliant; --model 3d,2d does not read it"),
    (FREE + ["--friction", "0.5"], "--friction is an option of --model 3d,2d,3d-compliant,2d-frame; a free motion"),
])
def test_impossible_requests_are_refused_before_computing(argv, message, tmp_path, capsys, no_computing,
                                                          monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["simulate", *argv, "--out", str(tmp_path / "x.nc")]) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.splitlines()) == 1
    assert list(tmp_path.iterdir()) == []


def test_bad_outputs_are_refused_before_computing(tmp_path, capsys, no_computing):
    a_file = tmp_path / "a_file"
    a_file.write_text("")
    for out, message in [("/", "--out '/' is a folder; give the path of a file"),
                         (str(tmp_path), "is a folder; give the path of a file"),
                         (str(tmp_path / "new") + "/", "is a folder"),
                         (str(a_file / "x.nc"), f"{a_file} is not a folder"),
                         ("/proc/x.nc", "/proc cannot be written (read-only or no permission)")]:
        assert main(["simulate", *QUAKE, "--out", out]) == 2, out
        err = capsys.readouterr().err
        assert message in err and len(err.splitlines()) == 1, (out, err)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a_file"]


@pytest.mark.parametrize("error, message", [
    (OSError(28, "No space left on device"), "cannot write (No space left on device)"),
    (RuntimeError("NetCDF: HDF error"), "the netCDF library could not write (NetCDF: HDF error); "),
])
def test_a_full_disk_gives_one_line_and_no_partial_file(tmp_path, capsys, monkeypatch, error, message):
    def full(self, path, *args, **kwargs):
        with open(path, "wb") as fh:  # half a file, then the disk is full
            fh.write(b"CDF")
        raise error

    monkeypatch.setattr(xr.Dataset, "to_netcdf", full)
    out = tmp_path / "r.nc"
    assert main(["simulate", *FREE, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"frustum: error: {out}: {message}") and len(err.splitlines()) == 1
    assert list(tmp_path.iterdir()) == []


# the model-option flags that existed before they were generated from the registry (issue 28): users'
# scripts name them
_FLAGS_OF_OLD = ("--tail", "--contact-tilt", "--damping", "--friction", "--joint-friction", "--normal-stiffness",
                 "--joint-stiffness", "--anathyrosis", "--contact-damping", "--integrator", "--step", "--rtol",
                 "--atol", "--restitution")


def test_the_model_option_flags_are_the_registrys_options():
    """One flag per option some model reads, named after it, its help from the table (unit, default)."""
    from pipeline.cli import build_parser
    from pipeline.models import REGISTRY
    from pipeline.models.options import OPTIONS

    simulate = build_parser()._subparsers._group_actions[0].choices["simulate"]
    actions = {a.option_strings[0]: a for a in simulate._actions if a.option_strings}
    read = set().union(*(m.options for m in REGISTRY.values()))
    for name in read:
        action = actions["--" + name.replace("_", "-")]
        assert action.default is None and action.dest == name  # not given: each model's own default
        option = OPTIONS[name]
        assert option.words in action.help and (option.kind in ("choice", "bool") or f"[{option.unit}]" in action.help)
    assert set(_FLAGS_OF_OLD) <= set(actions)
    args = simulate.parse_args(["--column", "1,1,1", "--out", "x.nc", "--joint-friction", "0.6,0.5",
                                "--anathyrosis", "0.2", "--contact-rings", "4", "--integrator", "dopri5"])
    assert args.joint_friction == (0.6, 0.5) and args.anathyrosis == 0.2 and args.contact_rings == 4
    assert args.integrator == "dopri5"


def test_each_model_gets_the_options_it_reads(monkeypatch):
    """--contact-damping reaches the rigid models too (they read it: the patch's dashpots); an option a model
    does not read is not given to it."""
    from pipeline.cli import build_parser
    from pipeline.cli import simulate as cli

    simulate = build_parser()._subparsers._group_actions[0].choices["simulate"]
    args = simulate.parse_args(["--column", "1,1,1", "--out", "x.nc", "--contact-damping", "1e5", "--damping", "0.1",
                                "--joint-friction", "0.6"])
    rigid = cli._model_settings(args, "3d", output_step=0.02)
    assert rigid.contact_damping == 1e5 and rigid.damping == 0.1 and rigid.joint_friction is None
    assert rigid.lift_off  # not given: the rigid models' default, a ground that only pushes
    held = simulate.parse_args(["--column", "1,1,1", "--out", "x.nc", "--no-lift-off"])
    assert not cli._model_settings(held, "3d").lift_off and not cli._model_settings(held, "2d").lift_off
    assert cli._model_settings(simulate.parse_args(["--column", "1,1,1", "--out", "x.nc", "--lift-off"]), "2d").lift_off
    drums = cli._model_settings(args, "3d-compliant")
    assert drums.joint_friction == 0.6 and drums.damping == 0.0 and drums.contact_damping == 1e5


def test_the_history_echoes_a_command_that_runs_as_typed():
    """The command written into a file's history parses back to the same flags: a switch as --no-flag, a
    list comma-separated (a switch echoed as '--lift-off False' was refused by the parser)."""
    import shlex

    from pipeline.cli import build_parser
    from pipeline.cli import simulate as cli

    simulate = build_parser()._subparsers._group_actions[0].choices["simulate"]
    typed = ["--column", "0.5,0.4,4", "--record", "FEMA-FF-01", "--model", "3d", "--no-lift-off", "--friction", "0.5",
             "--out", "x.nc"]
    args = simulate.parse_args(typed)
    echoed = shlex.split(" ".join(cli._argv_echo(args)))
    assert "--no-lift-off" in echoed
    again = simulate.parse_args(echoed)
    assert vars(again) == vars(args)
    drums = simulate.parse_args(["--column", "0.5,0.4,4", "--model", "3d-compliant", "--drums", "2",
                                 "--joint-friction", "0.6,0.5", "--out", "x.nc"])
    assert vars(simulate.parse_args(shlex.split(" ".join(cli._argv_echo(drums))))) == vars(drums)
