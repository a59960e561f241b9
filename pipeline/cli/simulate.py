"""``frustum simulate``: one column, one motion, one netCDF file of histories."""

import argparse
import math
import os

import numpy as np

from pipeline.cli.records import add_record_options, load_record, record_inputs
from pipeline.errors import InputError
from pipeline.models import DEFAULT, IMPERFECTIONS, REGISTRY, check_imperfect, unrun_part
from pipeline.models.rigid import ROLLING_FRUSTUM
from pipeline.models.options import OPTIONS
from pipeline.limits import check_tolerance
from pipeline.paths import check_output_file, check_plot_file
from pipeline.cli.summary_lines import run_lines
from pipeline.settings import FREE_MOTION, ModelSettings
from pipeline.structures import colonnade as row_limits
from pipeline.structures.colonnade import named_colonnades
from pipeline.units import MARBLE_DENSITY

DEFAULTS = ModelSettings()  # the options' defaults, written once (pipeline.settings)

_EXAMPLES = """\
examples:
  the paper's column under FEMA P695 far-field record 1, at 30 deg, twice its amplitude:
    frustum simulate --column 0.5,0.4,4 --record FEMA-FF-01 --angle 30 --scale 2 \\
        --out response.nc --plot response.png
  a PEER pair, and a single component (y = 0), from the repository's synthetic examples:
    frustum simulate --column 0.5,0.4,4 \\
        --record examples/synthetic-pair_X.AT2,examples/synthetic-pair_Y.AT2 --out r.nc
    frustum simulate --column 0.5,0.4,4 --record examples/synthetic-pair_X.AT2 --missing-y zero --out r.nc
  a bare column of numbers (OpenSees-style) in g, 0.01 s apart:
    frustum simulate --column 0.5,0.4,4 --record examples/synthetic-record-g.txt --units g --dt 0.01 \\
        --missing-y zero --out r.nc
  a recording of your own whose header does not carry units (MiniSEED, SAC, ... as ObsPy reads them):
    frustum simulate --column 0.5,0.4,4 --record YOUR_STATION.mseed --units m/s2 --out r.nc
  the compliant-contact model: the same column as 6 drums on joints of contact points:
    frustum simulate --column 0.5,0.4,4 --model 3d-compliant --drums 6 --joint-friction 0.6 \\
        --record FEMA-FF-01 --out drums.nc
  the same drums imperfect: beds offset and out of level by up to 2 mm, joint friction from 0.5 to 0.7,
  drawn from seed 7 (the same seed draws the same drums):
    frustum simulate --column 0.5,0.4,4 --model 3d-compliant --drums 6 --imperfections 0.002 --seed 7 \\
        --friction-range 0.5,0.7 --record FEMA-FF-01 --out imperfect.nc
  the rigid frame of two such columns with capitals carrying an epistyle 0.5 m high, axes 2 m apart:
    frustum simulate --column 0.5,0.4,4 --capital 1.0,0.4 --model 2d-frame --colonnade 2 --interaxial 2 \\
        --epistyle 0.5 --record FEMA-FF-01 --out frame.nc
  the Parthenon's east front (a named colonnade) as that frame:
    frustum simulate --model 2d-frame --colonnade parthenon-east --record FEMA-FF-01 --out parthenon.nc
  free motion released on the rim (the paper's Section 4 case, rates in rad/s):
    frustum simulate --column 0.5,0.4,4 --theta0 10 --phi-dot0 0.44 --psi-dot0 -0.89 \\
        --duration 20 --out free.nc
"""


def register(subparsers):
    """Add the ``simulate`` sub-command."""
    p = subparsers.add_parser(
        "simulate",
        help="simulate one column, column of drums or colonnade and write its time histories to netCDF",
        description="Simulate one column (a rigid conical frustum rolling on the rim of its base), a column of "
        "drums with its capital, or a colonnade (a row of such columns carrying an epistyle), under one record or "
        "released free, and write its time histories as a CF netCDF file.",
        epilog=_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    geo = p.add_argument_group("column")
    geo.add_argument("--column", metavar="R,r,h",
                     help="bottom radius R, top radius r and height h of the column [m], e.g. 0.5,0.4,4 (required, "
                     "but with a named --colonnade, which brings its own)")
    geo.add_argument("--density", type=float, default=MARBLE_DENSITY, metavar="KG_M3",
                     help="mass density [kg/m^3] for forces in newtons and energy in joules "
                     f"(default {MARBLE_DENSITY:g}, marble)")
    quake = p.add_argument_group("ground motion (earthquake response, from rest)")
    quake.add_argument("--record", metavar="ID_OR_FILE",
                       help="catalog id (frustum records list), a record file, or 2-3 files X,Y[,Z] "
                       "(e.g. an AT2 pair); without it, free motion")
    add_record_options(quake)
    quake.add_argument("--angle", type=float, default=0.0, metavar="DEG",
                       help="incidence angle: the horizontal pair is turned counter-clockwise [deg] (default 0)")
    quake.add_argument("--scale", type=float, default=1.0, help="factor on the record [1] (default 1)")
    quake.add_argument("--no-vertical", action="store_true", help="ignore the record's vertical component")
    quake.add_argument("--model", default=DEFAULT, metavar="|".join(REGISTRY) + "|" + ",".join(list(REGISTRY)[:2]),
                       help="; ".join(f"{m.name}: {m.title}" for m in REGISTRY.values())
                       + f"; several, comma-separated: in one file along the model dimension (default {DEFAULT})")
    quake.add_argument("--plot", metavar="FILE.png",
                       help="also draw theta, contact path, mu_mob and excitation (any format matplotlib writes: "
                       ".png, .pdf, .svg, ...; with two models, one file per model: FILE_3d.png, FILE_2d.png)")
    joints = p.add_argument_group(f"column of drums (--model {', '.join(m.name for m in REGISTRY.values() if m.drums)})")
    joints.add_argument("--drums", type=int, default=None, metavar="N",
                        help="cut the column into N drums of equal height (1: the monolith)")
    joints.add_argument("--drum-heights", default=None, metavar="H1,H2,...",
                        help="heights of the drums bottom first [m], adding up to h (instead of --drums)")
    joints.add_argument("--capital", default=None, metavar="SIDE,HEIGHT",
                        help="a square capital block on top, side and height [m]")
    rows = ", ".join(m.name for m in REGISTRY.values() if m.runs("colonnade"))
    row = p.add_argument_group(f"colonnade (--model {rows})")
    row.add_argument("--colonnade", default=None, metavar="N|NAME",
                     help=f"a row of N (2 to {row_limits.MAX_COLUMNS}) of the column (with its --capital; for "
                     "3d-compliant also its drums, which --model 2d-frame alone refuses) carrying an epistyle of "
                     "N - 1 blocks laid from axis to axis; or a named colonnade of pipeline/data/colonnades.toml "
                     f"({', '.join(sorted(named_colonnades()))}), which brings its column, spacing and epistyle")
    row.add_argument("--interaxial", type=float, default=None, metavar="S",
                     help="spacing of the column axes [m], at least the abacus side and the base diameter, at most "
                     f"{row_limits.MAX_INTERAXIAL:g} m and {row_limits.MAX_INTERAXIAL_DIAMETERS:g} base diameters")
    row.add_argument("--epistyle", default=None, metavar="HEIGHT[,WIDTH]",
                     help="height of the epistyle blocks and their width across the row [m]: a height from "
                     f"1/{row_limits.MAX_SPAN_DEPTH:g} of the interaxial to {row_limits.MAX_EPISTYLE_FRACTION:g} of "
                     f"the columns' height, a width {row_limits.EPISTYLE_WIDTH_RANGE[0]:g} to "
                     f"{row_limits.EPISTYLE_WIDTH_RANGE[1]:g} times the abacus side (width default: the abacus side, "
                     "2 r without --capital)")
    row.add_argument("--course", type=float, default=None, metavar="HEIGHT",
                     help="a course on the epistyle (frieze and cornice) as a height [m] of its width and density, "
                     "carried as mass (default 0: none; a named colonnade takes one too)")
    add_model_options(p)
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
    run.add_argument("--output-step", type=float, default=DEFAULTS.output_step, metavar="S",
                     help=f"sampling interval of the histories [s] (default {DEFAULTS.output_step:g})")
    run.add_argument("--duration", type=float, default=None, metavar="S",
                     help="simulated time of a free motion [s]")
    run.add_argument("--out", required=True, metavar="FILE.nc", help="netCDF file to write")
    run.add_argument("--animate", metavar="FILE.gif",
                     help="also animate the motion, every model side by side in real time (.gif, or .mp4 with "
                     "pip install -e '.[video]'); as 'frustum animate OUT --out FILE'")
    p.set_defaults(handler=run_simulate)


def _readers():
    """``{option name: names of the models that read it}``, in the table's order (the options some model reads)."""
    readers = {name: tuple(m.name for m in REGISTRY.values() if name in m.options) for name in OPTIONS}
    return {name: models for name, models in readers.items() if models}


# defaults that depend on the run: a free motion integrates tighter
_DEFAULT_TEXT = {name: f"default {getattr(DEFAULTS, name):g} with a record, {getattr(FREE_MOTION, name):g} free"
                 for name in ("rtol", "atol")}


def add_model_options(parser):
    """One flag per option some model reads (its name, dashes for underscores: ``--joint-friction``), grouped
    by the models that read it.

    Help, unit, default, type and choices come from the option's declaration
    (:data:`pipeline.models.options.OPTIONS`); every flag's default is None, "not given", so
    that each model gets the options it reads that were given and its own defaults for the rest.
    """
    groups = {}
    for name, models in _readers().items():
        groups.setdefault(models, []).append(OPTIONS[name])
    for models, options in sorted(groups.items(), key=lambda item: -len(item[0])):
        title = ("model options (every model)" if len(models) == len(REGISTRY) else
                 "options of --model " + ", ".join(f"{m} ({REGISTRY[m].title})" for m in models))
        group = parser.add_argument_group(title)
        for option in options:
            flag = "--" + option.name.replace("_", "-")
            help_ = option.help(_DEFAULT_TEXT.get(option.name)).replace("%", "%%")
            if option.kind == "bool":
                group.add_argument(flag, action=argparse.BooleanOptionalAction, default=None, help=help_)
            elif option.kind == "choice":
                group.add_argument(flag, choices=option.choices, default=None, help=help_)
            else:
                kind = {"number": float, "whole": int, "numbers": _numbers, "range": _numbers}[option.kind]
                group.add_argument(flag, type=kind, default=None, metavar=option.metavar or None, help=help_)


def _numbers(text):
    """A number, or numbers separated by commas (one per bed joint, bottom first) as a tuple."""
    try:
        values = tuple(float(x) for x in str(text).split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: give a number, or numbers separated by commas "
                                         "(e.g. 0.6 or 0.6,0.5)") from None
    return values[0] if len(values) == 1 else values


def _refuse_unread(args, read, runs):
    """Refuse a model-option flag that was given but that no model of the run reads: it would be
    ignored, and the run would look as if it had taken it."""
    for name, readers in _readers().items():
        if name not in read and getattr(args, name, None) is not None:
            flag = "--" + name.replace("_", "-")
            raise InputError(f"{flag} is an option of --model {','.join(readers)}; {runs} does not read it "
                             f"(drop {flag}, or run a model that reads it)")


def _model_settings(args, model, **fixed):
    """:class:`ModelSettings` of ``model``: the options it reads whose flags were given, its defaults for the rest."""
    given = {name: getattr(args, name) for name in REGISTRY[model].options if getattr(args, name) is not None}
    return ModelSettings(model=model, **{**given, **fixed})


def run_simulate(args):
    """Handler of ``frustum simulate``."""
    from pipeline.dataset import append_history, histories_file, write_netcdf
    from pipeline.structures.column import Column

    # everything that can be refused is refused before computing
    inputs = record_inputs(args.record)
    check_output_file(args.out, "--out", kind="histories", inputs=inputs)
    models = _models(args.model)
    if args.plot:  # every file it will write: one per model when there are several
        for path in [args.plot] if len(models) == 1 else [_suffixed(args.plot, m) for m in models]:
            check_plot_file(path, "--plot", inputs=inputs)
    _check_sampling(args)
    for name in ("rtol", "atol"):
        if getattr(args, name) is not None:
            check_tolerance(name, getattr(args, name), f"--{name}")
    colonnade = _named_row(args, models)
    if colonnade is not None:  # it brings its column
        stack = colonnade.column
    else:
        if args.column is None:
            raise InputError("give the column as --column R,r,h in metres (e.g. 0.5,0.4,4), or a named --colonnade")
        stack = _drum_column(args, Column.parse(args.column, density=args.density))
        colonnade = _row(args, stack)
    _refuse_unrun_drums(args, models, colonnade)
    column = getattr(stack, "column", stack)  # the shaft's outline, a monolith
    # what each model runs: the colonnade, the drums or the shaft alone, as a study gives it (Model.structure)
    bodies = {m: REGISTRY[m].structure(column, stack if stack is not column else None, colonnade) for m in models}
    if args.animate:
        from pipeline.animate import check_animation_path

        check_animation_path(args.animate, "--animate", inputs=inputs + [("results file", args.out)])
    if args.record:
        runs = _earthquake(args, bodies, models)
    else:
        if models != [ROLLING_FRUSTUM.name] or stack is not column or colonnade is not None:
            raise InputError(f"--model {args.model}: a free motion is the {ROLLING_FRUSTUM.title} only (drop --model, "
                             "the drum options and --colonnade)")
        runs = [_free(args, column)]
    label = f"R{column.R:g}-r{column.r:g}-h{column.h:g}"
    if colonnade is not None:
        label = colonnade.name or f"{label}-x{colonnade.n_columns}"
    # the summary goes into the file too: what the console prints must not be all there is of it
    ds = histories_file([h for h, _ in runs], column=label, record=runs[0][0].attrs.get("record_id", "free-motion"),
                        summaries=[s for _, s in runs])
    append_history(ds, "frustum simulate " + " ".join(_argv_echo(args)))
    write_netcdf(ds, args.out)
    for body in dict.fromkeys(bodies.values()):
        print(body.describe())
    for (histories, summary), model in zip(runs, models):
        print("\n".join(run_lines(model, summary, record=bool(args.record))))
    print(f"wrote {args.out}")
    if args.plot:
        from pipeline.plotting import plot_response

        for (histories, summary), model in zip(runs, models):
            path = args.plot if len(runs) == 1 else _suffixed(args.plot, model)
            plot_response(histories, summary, path, friction=_given(args.friction, DEFAULTS.friction))
            print(f"wrote {path}")
    if args.animate:
        from pipeline.animate import animate_file

        n = animate_file(args.out, args.animate)
        print(f"wrote {args.animate} ({n} frames)")
    return 0


def _check_sampling(args):
    """The options the memory estimate divides by, refused by name before they are used."""
    if not (math.isfinite(args.output_step) and args.output_step > 0):
        raise InputError(f"--output-step {args.output_step!r}: give the sampling interval of the histories as a "
                         "positive number of seconds, e.g. 0.01")
    tail, option = _given(args.tail, DEFAULTS.tail), OPTIONS["tail"]
    if not (math.isfinite(tail) and option.lo <= tail <= option.hi):
        raise InputError(f"--tail {tail!r}: give the {option.words} as a number of seconds in "
                         f"{option.range_text()}, e.g. {option.default:g}")


def _models(text):
    models = [m.strip() for m in str(text).split(",") if m.strip()]
    if not models or any(m not in REGISTRY for m in models) or len(set(models)) != len(models):
        raise InputError(f"--model {text}: give one or more of {', '.join(REGISTRY)}, comma-separated (e.g. "
                         f"{','.join(list(REGISTRY)[:2])})")
    return models


def _drum_column(args, column):
    """The column as drums when any drum option is given (the compliant model then)."""
    from pipeline.structures.drums import Capital, DrumColumn

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


def _named_row(args, models):
    """The named colonnade of ``--colonnade NAME``, or None; the colonnade's options are refused where
    nothing reads them, or where they are missing."""
    from pipeline.structures.colonnade import named_colonnade

    runs_rows = [m for m in models if REGISTRY[m].runs("colonnade")]
    given = [f"--{name}" for name in ("interaxial", "epistyle", "course") if getattr(args, name) is not None]
    if args.colonnade is None:
        if given:
            raise InputError(f"{given[0]} describes a colonnade: give --colonnade N (the number of columns) too, or "
                             f"drop {given[0]}")
        needs = [m for m in runs_rows if not REGISTRY[m].runs("column")]
        if needs:
            raise InputError(f"--model {needs[0]} runs a colonnade: give --colonnade N --interaxial S --epistyle HEIGHT "
                             f"(or a named colonnade, e.g. --colonnade {sorted(named_colonnades())[0]})")
        return None
    if not runs_rows:
        raise InputError(unrun_part("colonnade", models, "--colonnade", "the run", "drop"))
    text = str(args.colonnade).strip()
    if _number(text) is not None:
        missing = [flag for flag, value in (("--interaxial", args.interaxial), ("--epistyle", args.epistyle))
                   if value is None]
        if missing:
            raise InputError(f"--colonnade {text}: give {' and '.join(missing)} too (the spacing of the axes and the "
                             "height of the epistyle in metres, e.g. --interaxial 2.0 --epistyle 0.5)")
        return None
    if text not in named_colonnades():
        raise InputError(f"--colonnade {text}: give a whole number of columns (at least 2), or the name of a named "
                         f"colonnade ({', '.join(sorted(named_colonnades()))})")
    # a course (frieze and cornice) may be added to a named colonnade, which has none of its own
    mine = [flag for flag in given if flag != "--course"] + [
        f"--{name.replace('_', '-')}" for name in ("column", "drums", "drum_heights", "capital")
        if getattr(args, name) is not None]
    if mine:
        raise InputError(f"--colonnade {text} is a named colonnade, which brings its column and epistyle (--course "
                         f"may be added): drop {mine[0]}, or describe the row yourself with --colonnade N --interaxial "
                         "S --epistyle HEIGHT")
    return named_colonnade(text, course_height=args.course)


def _refuse_unrun_drums(args, models, colonnade):
    """Refuse drums (``--drums``, ``--drum-heights``, ``--capital``) that no model of the run runs, as a
    study refuses them: a capital is read too by a model of colonnades that runs the row given."""
    if any(REGISTRY[m].drums for m in models):
        return
    rows = colonnade is not None and any(REGISTRY[m].runs("colonnade") for m in models)
    flags = [f"--{name.replace('_', '-')}" for name in ("drums", "drum_heights", "capital")
             if getattr(args, name) is not None and not (name == "capital" and rows)]
    if flags:
        raise InputError(unrun_part("drums", models, flags[0], "the run", "drop"))


def _number(text):
    try:
        return float(text)
    except ValueError:
        return None


def _row(args, column):
    """The colonnade of ``--colonnade N --interaxial S --epistyle HEIGHT[,WIDTH] [--course HEIGHT]`` of
    ``column``, or None without ``--colonnade``."""
    from pipeline.structures.colonnade import Colonnade

    if args.colonnade is None:
        return None
    n = _number(args.colonnade)
    if not (math.isfinite(n) and n == int(n)):
        raise InputError(f"--colonnade {args.colonnade}: give a whole number of columns (at least 2), or the name of "
                         f"a named colonnade ({', '.join(sorted(named_colonnades()))})")
    epistyle = _floats(args.epistyle, "--epistyle", "HEIGHT[,WIDTH]")
    if len(epistyle) not in (1, 2):
        raise InputError(f"--epistyle {args.epistyle!r}: give the height of the blocks, and optionally their width, in "
                         "metres (e.g. 0.5 or 0.5,1.0)")
    width = epistyle[1] if len(epistyle) == 2 else None
    return Colonnade(column, int(n), args.interaxial, epistyle[0], width,
                     0.0 if args.course is None else args.course)


def _floats(text, option, form):
    try:
        return [float(x) for x in str(text).split(",")]
    except ValueError:
        raise InputError(f"{option} {text!r}: give numbers in metres as {form}") from None


def _suffixed(path, model):
    stem, ext = os.path.splitext(path)
    return f"{stem}_{model}{ext}"


def _earthquake(args, bodies, models):
    """[(histories, summary)] of the record under each model, each on its structure (``bodies[model]``)."""
    from pipeline.settings import Excitation
    from pipeline.simulate import simulate

    if args.theta0 is not None:
        raise InputError("--theta0 starts a free motion; an earthquake response starts at rest (drop --theta0)")
    excitation = Excitation(angle=args.angle, scale=args.scale, vertical=not args.no_vertical)
    for name in IMPERFECTIONS:  # in the words a study's [imperfections] gets (pipeline.models.check_imperfect)
        if getattr(args, name) is not None:
            check_imperfect(models, "--" + name.replace("_", "-"))
    _refuse_unread(args, {name for model in models for name in REGISTRY[model].options}, f"--model {args.model}")
    settings = {model: _model_settings(args, model, output_step=args.output_step) for model in models}
    for model in models:  # what any run would refuse, before the first one computes (as a study checks)
        REGISTRY[model].check(bodies[model], settings[model])
    motion = load_record(args)
    tail = _given(args.tail, DEFAULTS.tail)
    _check_output_step(args.output_step, motion.duration + tail,
                       f"record {motion.duration:g} s + --tail {tail:g} s", "--tail")
    _check_history_memory(len(models) * (motion.duration + tail), args.output_step,
                          "the record and --tail" + (" for each model" if len(models) > 1 else ""))
    runs = []
    for model in models:
        response = simulate(bodies[model], motion, excitation, settings[model],
                            progress=_progress_line(model, settings[model]))
        runs.append((response.histories, response.summary))
    return runs


def _progress_line(model, settings):
    """A progress line (seconds of motion simulated, ETA) on stderr for the runs of a model of drums
    with the fixed-step integrator (the only long single runs)."""
    if not REGISTRY[model].drums or settings.integrator != "semi-implicit":
        return None
    from pipeline.study.progress import Progress

    bar = []

    def report(done, total):
        if not bar:
            bar.append(Progress(total, unit=f"s of motion ({model})"))
        bar[0].update(done)

    return report


def _free(args, column):
    from pipeline.settings import InitialState
    from pipeline.simulate import simulate_free

    if args.theta0 is None:
        raise InputError("give --record for an earthquake response, or --theta0 (degrees) for a free motion")
    if args.duration is None:
        raise InputError("a free motion needs --duration (seconds)")
    _refuse_unread(args, {"rtol", "atol", "damping", "restitution"}, "a free motion (without --record)")
    initial = InitialState(
        phi=args.phi0,
        theta=args.theta0,
        psi=args.psi0,
        phi_dot=args.phi_dot0,
        theta_dot=args.theta_dot0,
        psi_dot=args.psi_dot0,
    )
    settings = ModelSettings(rtol=_given(args.rtol, FREE_MOTION.rtol), atol=_given(args.atol, FREE_MOTION.atol),
                             output_step=args.output_step, contact_tilt=0.0,
                             damping=_given(args.damping, DEFAULTS.damping))
    if not (math.isfinite(args.duration) and args.duration > 0):
        raise InputError(f"--duration {args.duration!r}: give a positive number of seconds")
    _check_output_step(args.output_step, args.duration, "--duration", "--duration")
    _check_history_memory(args.duration, settings.output_step, "--duration")
    ds = simulate_free(column, initial, args.duration, settings, restitution=args.restitution)
    return ds, {"peak_theta": float(np.nanmax(ds.theta.values))}


def _given(value, default):
    """An option's value, or its default when not given (0 is a value: it is refused, not replaced)."""
    return default if value is None else value


def _check_output_step(output_step, length, what, longer):
    """Refuse a sampling interval longer than the run (``length`` [s]): the histories would be its first row alone."""
    if output_step > length:
        raise InputError(f"--output-step {output_step:g}: longer than the run ({what} = {length:g} s), whose "
                         f"histories would keep its first instant alone; give at most {length:g} s, e.g. 0.01, "
                         f"or a longer {longer}")


def _check_history_memory(duration, output_step, what):
    """Refuse histories that cannot fit in memory, before computing."""
    from pipeline.limits import check_fits, history_bytes

    if not math.isfinite(duration / output_step):  # a step so small the row count overflows
        raise InputError(f"--output-step {output_step:g}: {duration:g} s of histories at that step are more rows "
                         "than can be held; sample less often with a larger --output-step, e.g. 0.01")
    rows = math.floor(duration / output_step) + 1
    check_fits(history_bytes(duration, output_step),
               f"{duration:g} s of histories every {output_step:g} s ({rows:,} rows)",
               f"shorten {what} or sample less often with a larger --output-step")


def _argv_echo(args):
    keys = ("column", "density", "record", "units", "components", "missing_y", "dt", "baseline", "angle", "scale",
            "model", "drums", "drum_heights", "capital", "colonnade", "interaxial", "epistyle", "course", *_readers(), "phi0", "theta0", "psi0", "phi_dot0",
            "theta_dot0", "psi_dot0", "duration", "output_step", "out")
    return [_echo(k.replace("_", "-"), getattr(args, k)) for k in keys if getattr(args, k, None) is not None]


def _echo(flag, value):
    """A flag with its value as it is typed: a list comma-separated, a switch as the flag alone or its "no-" form."""
    if isinstance(value, bool):
        return f"--{'' if value else 'no-'}{flag}"
    return f"--{flag} " + (",".join(f"{v:g}" for v in value) if isinstance(value, tuple) else str(value))
