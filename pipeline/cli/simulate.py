"""``frustum simulate``: one column, one motion, one netCDF file of histories."""

import argparse
import math

import numpy as np

from pipeline.errors import InputError
from pipeline.simulate import MODELS
from pipeline.units import MARBLE_DENSITY, deg_to_rad

_EXAMPLES = """\
examples:
  the paper's column under FEMA P695 far-field record 1, at 30 deg, twice its amplitude:
    frustum simulate --column 0.5,0.4,4 --record FEMA-FF-01 --angle 30 --scale 2 \\
        --out response.nc --plot response.png
  a record file (MiniSEED here) whose header does not carry units:
    frustum simulate --column 0.5,0.4,4 --record quake.mseed --units m/s2 --out r.nc
  the compliant-contact model: the same column as 6 drums on joints of contact points:
    frustum simulate --column 0.5,0.4,4 --model 3d-compliant --drums 6 --joint-friction 0.6 \\
        --record FEMA-FF-01 --out drums.nc
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
    quake = p.add_argument_group("ground motion (earthquake response, from rest)")
    quake.add_argument("--record", metavar="ID_OR_FILE",
                       help="catalog id (frustum records list) or a record file; without it, free motion")
    quake.add_argument("--units", default=None, metavar="UNITS",
                       help="units of a record file that does not state them: m/s2, cm/s2, g")
    quake.add_argument("--angle", type=float, default=0.0, metavar="DEG",
                       help="incidence angle: the horizontal pair is turned counter-clockwise [deg] (default 0)")
    quake.add_argument("--scale", type=float, default=1.0, help="factor on the record [1] (default 1)")
    quake.add_argument("--no-vertical", action="store_true", help="ignore the record's vertical component")
    quake.add_argument("--model", choices=MODELS, default="3d",
                       help="3d: rolling frustum (the paper); 2d: planar rocking in the X plane; 3d-compliant: "
                       "rigid drums on joints of contact points (default 3d)")
    quake.add_argument("--tail", type=float, default=5.0, metavar="S",
                       help="free motion after the record ends [s] (default 5)")
    quake.add_argument("--contact-tilt", type=float, default=1e-5, metavar="RAD",
                       help="tilt below which the base is in full contact [rad] (default 1e-5)")
    quake.add_argument("--damping", type=float, default=0.0, metavar="NU",
                       help="viscous contact couple per m g R sqrt(R/g) [1] (default 0: none)")
    quake.add_argument("--friction", type=float, default=0.7, metavar="MU",
                       help="friction coefficient compared with the mobilized friction [1] (default 0.7)")
    quake.add_argument("--plot", metavar="FILE.png", help="also draw theta, contact path, mu_mob and excitation")
    joints = p.add_argument_group("compliant-contact model (--model 3d-compliant)")
    joints.add_argument("--drums", type=int, default=None, metavar="N",
                        help="cut the column into N drums of equal height (1: the monolith)")
    joints.add_argument("--drum-heights", default=None, metavar="H1,H2,...",
                        help="heights of the drums bottom first [m], adding up to h (instead of --drums)")
    joints.add_argument("--capital", default=None, metavar="SIDE,HEIGHT",
                        help="a square capital block on top, side and height [m]")
    joints.add_argument("--joint-friction", type=float, default=None, metavar="MU",
                        help="friction coefficient of the bed joints [1] (default: --friction, the base's)")
    joints.add_argument("--normal-stiffness", type=float, default=1.0e10, metavar="PA_M",
                        help="normal stiffness of the base per unit area [Pa/m] (default 1e10)")
    joints.add_argument("--joint-stiffness", type=float, default=None, metavar="PA_M",
                        help="normal stiffness of the bed joints per unit area [Pa/m] (default: the base's)")
    joints.add_argument("--anathyrosis", type=float, default=0.0, metavar="RATIO",
                        help="inner/outer radius of the bed joints' contact ring [1] (default 0: full)")
    free = p.add_argument_group("initial state (free motion)")
    for name, unit, default, text in [  # noqa: B007
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
    run.add_argument("--output-step", type=float, default=0.01, metavar="S",
                     help="sampling interval of the histories [s] (default 0.01)")
    run.add_argument("--duration", type=float, default=None, metavar="S",
                     help="simulated time of a free motion [s]")
    run.add_argument("--rtol", type=float, default=None,
                     help="relative tolerance (default 1e-9 with a record, 1e-12 free)")
    run.add_argument("--atol", type=float, default=None,
                     help="absolute tolerance (default 1e-12 with a record, 1e-14 free)")
    run.add_argument("--restitution", type=float, default=None, metavar="E",
                     help="theta' after / before a planar landing [1] (default: angular momentum "
                     "conservation, 1 - 2 m R^2 / I_P)")
    run.add_argument("--out", required=True, metavar="FILE.nc", help="netCDF file to write")
    p.set_defaults(handler=run_simulate)


def run_simulate(args):
    """Handler of ``frustum simulate``."""
    from pipeline.dataset import append_history, write_netcdf
    from pipeline.geometry import Column

    column = _drum_column(args, Column.parse(args.column, density=args.density))
    ds, summary = _earthquake(args, column) if args.record else _free(args, column)
    append_history(ds, "frustum simulate " + " ".join(_argv_echo(args)))
    write_netcdf(ds, args.out)
    print(column.describe())
    line = f"peak theta = {math.degrees(summary['peak_theta']):.3f} deg"
    if args.record:
        line += (f" ({summary['peak_theta_ratio']:.2f} theta_crit), "
                 f"{'overturned at %.2f s' % summary['overturn_time'] if summary['overturned'] else 'stands'}, "
                 f"{summary['n_impacts']} impacts, peak mu_mob = {summary['peak_mu_mob']:.2f}")
        if "n_drums" in summary:
            line += f", slip at the base {summary['slip']:.3g} m"
            if summary["n_drums"] > 1:
                line += "; drum peak tilts " + ", ".join(f"{math.degrees(t):.2f}" for t in summary["drum_peak_theta"])
                line += " deg; residual joint slips " + ", ".join(f"{x * 1e3:.1f}" for x in summary["joint_slip"])
                line += " mm"
    print(f"{line}; wrote {args.out}")
    if args.plot:
        from pipeline.plotting import plot_response

        plot_response(ds, summary, args.plot, friction=args.friction)
        print(f"wrote {args.plot}")
    return 0


def _drum_column(args, column):
    """The column as drums when any drum option is given (the compliant model then)."""
    from pipeline.drums import Capital, DrumColumn

    if args.drums is None and args.drum_heights is None and args.capital is None:
        return column
    if args.drums is not None and args.drum_heights is not None:
        raise InputError("give --drums N or --drum-heights H1,H2,..., not both")
    capital = None
    if args.capital is not None:
        parts = _floats(args.capital, "--capital", "SIDE,HEIGHT")
        if len(parts) != 2:
            raise InputError(f"--capital {args.capital!r}: give the side and the height of the block in metres, "
                             "e.g. 2.0,0.6")
        capital = Capital(*parts)
    if args.drum_heights is not None:
        return DrumColumn.from_heights(column, _floats(args.drum_heights, "--drum-heights", "H1,H2,..."), capital)
    return DrumColumn.equal(column, 1 if args.drums is None else args.drums, capital)


def _floats(text, option, form):
    try:
        return [float(x) for x in str(text).split(",")]
    except ValueError:
        raise InputError(f"{option} {text!r}: give numbers in metres as {form}") from None


def _earthquake(args, column):
    from pipeline.groundmotion import load
    from pipeline.simulate import Excitation, ModelSettings, simulate

    if args.theta0 is not None:
        raise InputError("--theta0 starts a free motion; an earthquake response starts at rest (drop --theta0)")
    settings = ModelSettings(
        model=args.model, restitution=args.restitution, contact_tilt=args.contact_tilt, damping=args.damping,
        friction=args.friction, tail=args.tail, rtol=args.rtol or 1e-9, atol=args.atol or 1e-12,
        output_step=args.output_step, normal_stiffness=args.normal_stiffness, joint_stiffness=args.joint_stiffness,
        joint_friction=args.joint_friction, anathyrosis=args.anathyrosis,
    )
    excitation = Excitation(angle=deg_to_rad(args.angle), scale=args.scale, vertical=not args.no_vertical)
    motion = load(args.record, units=args.units)
    response = simulate(column, motion, excitation, settings)
    return response.histories, response.summary


def _free(args, column):
    from pipeline.geometry import Column
    from pipeline.simulate import InitialState, ModelSettings, simulate_free

    if args.theta0 is None:
        raise InputError("give --record for an earthquake response, or --theta0 (degrees) for a free motion")
    if args.model != "3d" or not isinstance(column, Column):
        raise InputError("a free motion (--theta0) is the rigid 3d model's; the other models need a --record")
    if args.duration is None:
        raise InputError("a free motion needs --duration (seconds)")
    initial = InitialState(
        phi=deg_to_rad(args.phi0),
        theta=deg_to_rad(args.theta0),
        psi=deg_to_rad(args.psi0),
        phi_dot=args.phi_dot0,
        theta_dot=args.theta_dot0,
        psi_dot=args.psi_dot0,
    )
    settings = ModelSettings(rtol=args.rtol or 1e-12, atol=args.atol or 1e-14, output_step=args.output_step,
                             contact_tilt=0.0, damping=args.damping)
    ds = simulate_free(column, initial, args.duration, settings, restitution=args.restitution)
    return ds, {"peak_theta": float(np.nanmax(ds.theta.values))}


def _argv_echo(args):
    keys = ("column", "density", "record", "units", "angle", "scale", "model", "tail", "contact_tilt", "damping",
            "friction", "drums", "drum_heights", "capital", "joint_friction", "normal_stiffness", "joint_stiffness",
            "anathyrosis", "phi0", "theta0", "psi0", "phi_dot0", "theta_dot0", "psi_dot0",
            "duration", "output_step", "rtol", "atol", "restitution", "out")
    return [f"--{k.replace('_', '-')} {getattr(args, k)}" for k in keys if getattr(args, k, None) is not None]
