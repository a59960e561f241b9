"""``frustum simulate``: one column, one motion, one netCDF file of histories."""

import argparse
import math

import numpy as np

from pipeline.errors import InputError
from pipeline.units import MARBLE_DENSITY, deg_to_rad

_EXAMPLES = """\
examples:
  free motion released on the rim (the paper's Section 4 case, rates in rad/s):
    frustum simulate --column 0.5,0.4,4 --theta0 10 --phi-dot0 0.44 --psi-dot0 -0.89 \\
        --duration 20 --out free.nc
"""


def register(subparsers):
    """Add the ``simulate`` sub-command."""
    p = subparsers.add_parser(
        "simulate",
        help="simulate one column and write its time histories to netCDF",
        description="Simulate one column (a rigid conical frustum rolling on the rim of its base) "
        "and write its time histories as a CF netCDF file.",
        epilog=_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    geo = p.add_argument_group("column")
    geo.add_argument("--column", required=True, metavar="R,r,h",
                     help="bottom radius R, top radius r and height h of the column [m], e.g. 0.5,0.4,4")
    geo.add_argument("--density", type=float, default=MARBLE_DENSITY, metavar="KG_M3",
                     help="mass density [kg/m^3] for forces in newtons and energy in joules "
                     f"(default {MARBLE_DENSITY:g}, marble)")
    free = p.add_argument_group("initial state (free motion)")
    for name, unit, default, text in [
        ("phi0", "deg", 0.0, "precession angle"),
        ("theta0", "deg", None, "inclination of the axis from the vertical (0 < theta0 < 90)"),
        ("psi0", "deg", 0.0, "spin angle"),
        ("phi-dot0", "rad/s", 0.0, "precession rate"),
        ("theta-dot0", "rad/s", 0.0, "inclination rate"),
        ("psi-dot0", "rad/s", 0.0, "spin angle rate"),
    ]:
        free.add_argument(f"--{name}", type=float, default=default, metavar=unit.upper().replace("/", "_"),
                          help=f"{text} [{unit}] (default {default if default is not None else 'required'})")
    run = p.add_argument_group("run")
    run.add_argument("--duration", type=float, required=True, metavar="S", help="simulated time [s]")
    run.add_argument("--output-step", type=float, default=0.01, metavar="S",
                     help="sampling interval of the histories [s] (default 0.01)")
    run.add_argument("--rtol", type=float, default=1e-10, help="relative tolerance (default 1e-10)")
    run.add_argument("--atol", type=float, default=1e-12, help="absolute tolerance (default 1e-12)")
    run.add_argument("--restitution", type=float, default=None, metavar="E",
                     help="theta' after / before a planar landing [1] (default: angular momentum "
                     "conservation, 1 - 2 m R^2 / I_P)")
    run.add_argument("--out", required=True, metavar="FILE.nc", help="netCDF file to write")
    p.set_defaults(handler=run_simulate)


def run_simulate(args):
    """Handler of ``frustum simulate``."""
    from pipeline.dataset import append_history, write_netcdf
    from pipeline.geometry import Column
    from pipeline.simulate import InitialState, ModelSettings, simulate_free

    column = Column.parse(args.column, density=args.density)
    if args.theta0 is None:
        raise InputError("free motion needs --theta0 (the initial inclination in degrees, 0 < theta0 < 90)")
    initial = InitialState(
        phi=deg_to_rad(args.phi0),
        theta=deg_to_rad(args.theta0),
        psi=deg_to_rad(args.psi0),
        phi_dot=args.phi_dot0,
        theta_dot=args.theta_dot0,
        psi_dot=args.psi_dot0,
    )
    settings = ModelSettings(rtol=args.rtol, atol=args.atol, output_step=args.output_step, contact_tilt=0.0)
    ds = simulate_free(column, initial, args.duration, settings, restitution=args.restitution)
    append_history(ds, "frustum simulate " + " ".join(_argv_echo(args)))
    write_netcdf(ds, args.out)
    theta = ds.theta.values
    print(f"{column.describe()}")
    print(f"peak theta = {math.degrees(float(np.nanmax(theta))):.3f} deg; wrote {args.out}")
    return 0


def _argv_echo(args):
    keys = ("column", "density", "phi0", "theta0", "psi0", "phi_dot0", "theta_dot0", "psi_dot0",
            "duration", "output_step", "rtol", "atol", "restitution", "out")
    return [f"--{k.replace('_', '-')} {getattr(args, k)}" for k in keys if getattr(args, k, None) is not None]
