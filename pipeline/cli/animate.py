"""``frustum animate``: the motion of a simulated column or colonnade as a GIF or MP4."""

import argparse

_EXAMPLES = """\
examples:
  both models side by side, in real time (10 frames per second of motion):
    frustum simulate --column 0.5,0.4,4 --record FEMA-FF-01 --scale 2 --model 3d,2d --out r.nc
    frustum animate r.nc --out motion.gif
  the 3D model only, at half speed, as MP4 (pip install -e '.[video]'):
    frustum animate r.nc --out motion.mp4 --model 3d --speed 0.5
  a colonnade: the Parthenon's east front as the rigid frame (every column, capital and the epistyle):
    frustum simulate --model 2d-frame --colonnade parthenon-east --record FEMA-FF-01 --out front.nc
    frustum animate front.nc --out front.gif
  a compliant row of 3 columns of 3 drums under 2 epistyle blocks, every body at its own displacement and tilt:
    frustum simulate --column 0.5,0.4,4 --drums 3 --capital 1.1,0.3 --model 3d-compliant --colonnade 3 \
        --interaxial 2.3 --epistyle 0.7 --record SYN-RICKER --scale 2 --out row.nc
    frustum animate row.nc --out row.gif
"""


def register(subparsers):
    """Add the ``animate`` sub-command."""
    from pipeline.animate import HOLD

    p = subparsers.add_parser(
        "animate", help="animate a simulated column or colonnade (GIF or MP4)",
        description="Draw the structure of a 'frustum simulate' file in 3D moving with the ground: a column as a "
        "solid frustum, its drums and capital, or a colonnade: a 3d-compliant row body by body (every drum, "
        "capital and epistyle block at its own displacement, tilt and twist), a 2d-frame result as the frame "
        "(every column with its capital rocking in unison under the epistyle); its contact path on the ground, an "
        "arrow for the ground acceleration, time and tilt against the model's own theta_crit; one view per model, side "
        "by side. A structure that overturned is shown from then on as the run left it, still and "
        f"greyed, with when it fell and which bodies fell; the animation ends {HOLD:g} s after that.",
        epilog=_EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("result", metavar="RESULT.nc", help="histories written by 'frustum simulate'")
    p.add_argument("--out", required=True, metavar="FILE.gif|FILE.mp4", help="animation to write")
    p.add_argument("--fps", type=float, default=10.0, help="frames per second of the animation (default 10)")
    p.add_argument("--speed", type=float, default=1.0,
                   help="seconds of motion per second of animation (default 1: real time)")
    p.add_argument("--model", default=None, metavar="MODEL[,MODEL]",
                   help="models to draw, e.g. 3d,2d or 3d-compliant,2d-frame (default: all in the file)")
    p.add_argument("--dpi", type=float, default=80.0, help="resolution [dots per inch] (default 80)")
    p.set_defaults(handler=run)


def run(args):
    """Handler of ``frustum animate``."""
    from pipeline.animate import animate_file, check_animation_options, check_animation_path

    # every option and the output are refused before the file is read
    check_animation_options(args.fps, args.speed, args.dpi)
    check_animation_path(args.out, "--out", inputs=[("results file", args.result)])
    models = [m.strip() for m in args.model.split(",") if m.strip()] if args.model else None
    n = animate_file(args.result, args.out, fps=args.fps, speed=args.speed, models=models, dpi=args.dpi)
    print(f"wrote {args.out} ({n} frames, {args.fps:g} per second, speed {args.speed:g})")
    return 0
