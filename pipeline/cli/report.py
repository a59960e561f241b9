"""``frustum report``: a Markdown report, CSV, GeoJSON and figures of a study."""

import argparse
import math

from pipeline.cli.fragility import add_undecided_option
from pipeline.errors import InputError

#: The files a report writes in its folder, checked against the inputs and the user's files before computing
#: (the figures' names depend on the data: every existing figure there must be one a report wrote).
REPORT_FILES = ("report.md", "report.html", "summary.csv", "columns.geojson", "fragility.nc", "comparison.nc",
                "comparison.csv", "figures/*.png", "figures/*.pdf")
#: The files ``--hazard`` adds.
RISK_FILES = ("risk.nc", "risk.csv")
#: How an existing file of each name is recognised as one a report wrote (others: the project's mark).
REPORT_KINDS = {"fragility.nc": "fragility", "risk.nc": "risk", "summary.csv": "summary-csv", "risk.csv": "risk-csv",
                "comparison.nc": "comparison", "comparison.csv": "comparison-csv"}

_EXAMPLES = """\
examples:
  frustum report out/quickstart.nc --out out/quickstart-report
  probabilities stated at 0.15, 0.3 and 0.45 g, 500 bootstrap replicates:
    frustum report out/quickstart.nc --out report --pga-levels 0.15,0.3,0.45 --bootstrap 500
  several models (or variants) compared with the one named, not the study's first:
    frustum report out/drums.nc --out report --reference stack
  a peer engine's cells (written in the layout of a study's results) beside a study's models:
    frustum report out/drums.nc out/pybullet.nc --out report --reference stack
  with the chance of overturning in 50 years at the sites of an OpenQuake PGA hazard curve:
    frustum report out/quickstart.nc --out report --hazard examples/synthetic-hazard_curve-mean-PGA.csv
"""


def register(subparsers):
    """Add the ``report`` sub-command."""
    p = subparsers.add_parser(
        "report",
        help="write a short Markdown report with figures, CSV and GeoJSON of study results",
        description="Write DIR/report.md and DIR/report.html (one self-contained file; what was simulated, the model's assumptions, the probability of "
        "overturning at stated PGA levels, 2D against 3D when both were run, figures), DIR/summary.csv "
        "(one row per column and model), DIR/columns.geojson (columns with coordinates), DIR/fragility.nc "
        "and DIR/figures/ (PNG and PDF).",
        epilog=_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("results", metavar="FILE.nc", nargs="+",
                   help="study results written by 'frustum study run'; several files of the same columns, records, "
                   "angles and scales are reported as one, their models compared side by side")
    p.add_argument("--out", required=True, metavar="DIR", help="folder to write (created)")
    p.add_argument("--pga-levels", default="0.1,0.2,0.3,0.5,0.8", metavar="G1,G2,...",
                   help="PGA levels [g] at which to state the probability of overturning (default 0.1,0.2,0.3,0.5,0.8)")
    p.add_argument("--states", default="0.25,0.5,1", metavar="S1,S2,...",
                   help="damage states as thresholds on peak theta/theta_crit (default 0.25,0.5,1)")
    p.add_argument("--bootstrap", type=int, default=200, metavar="N",
                   help="bootstrap replicates over records (default 200)")
    p.add_argument("--seed", type=int, default=0, help="seed of the bootstrap (default 0)")
    p.add_argument("--title", default=None, help="report title (default: the study's title)")
    p.add_argument("--hazard", default=None, metavar="CURVE.csv",
                   help="PGA hazard curve of the site(s): OpenQuake engine CSV (IMLs in g) or 'PGA [g],annual_rate "
                   "[1/yr]'; adds 'Risk at the site' (chance of overturning in --years), risk.nc and risk.csv")
    p.add_argument("--years", type=float, default=50.0, metavar="T",
                   help="period of the chance stated with --hazard [yr] (default 50)")
    p.add_argument("--reference", default=None, metavar="MODEL",
                   help="with several models: the one every other is compared with in 'Model against model', "
                   "comparison.csv and comparison.nc (default: the study's first model)")
    add_undecided_option(p)
    p.set_defaults(handler=run)


def run(args):
    from pipeline import fragility as F
    from pipeline.cli.fragility import check_fit_options, parse_states
    from pipeline.paths import check_output_folder
    from pipeline.report import write_report

    try:
        levels = tuple(float(v) for v in args.pga_levels.split(",") if v.strip())
    except ValueError:
        raise InputError(f"--pga-levels {args.pga_levels!r}: give PGA values in g separated by commas") from None
    if not levels or any(not (v > 0) for v in levels):
        raise InputError(f"--pga-levels {args.pga_levels!r}: give positive PGA values in g, e.g. 0.1,0.2,0.3")
    check_fit_options(args)
    hazard = None
    inputs = [("results file", path) for path in args.results]
    if args.hazard is not None:
        from pipeline import risk as R

        if not (math.isfinite(args.years) and args.years > 0):
            raise InputError(f"--years {args.years:g}: give a positive number of years, e.g. 50")
        inputs.append(("hazard curve", args.hazard))
        hazard = R.read_hazard_curve(args.hazard)  # read and checked before any fitting
        if hazard.im != "pga":
            raise InputError(f"{args.hazard}: the hazard curve is for {hazard.describe()} but the report's fragility "
                             "is against PGA; give a PGA hazard curve (OpenQuake: imt='PGA'), or use 'frustum "
                             "fragility --im sa' and 'frustum risk' for Sa")
        for i in range(len(hazard.sites)):
            R.usable_curve(hazard, i)
    elif args.years != 50.0:
        raise InputError("--years is the period of the chance stated with --hazard; give --hazard CURVE.csv too")
    writes = REPORT_FILES + (RISK_FILES if hazard is not None else ())
    check_output_folder(args.out, "--out", writes=writes, kinds=REPORT_KINDS, inputs=inputs)
    from pipeline.comparison import merge_results, reference_model

    results = merge_results([F.open_results(path) for path in args.results])
    reference_model(results, args.reference, "--reference")  # before the fitting, which takes long
    out = write_report(results, args.out, pga_levels_g=levels, states=parse_states(args.states),
                       bootstrap=args.bootstrap, seed=args.seed, title=args.title, hazard=hazard, years=args.years,
                       reference=args.reference, undecided=args.undecided)
    print(f"wrote {out['report']}, {out['html']}, {out['csv']}" + (f", {out['geojson']}" if out["geojson"] else "")
          + (f", {out['risk_nc']}, {out['risk_csv']}" if out.get("risk_nc") else "")
          + (f", {out['comparison_nc']}, {out['comparison_csv']}" if out.get("comparison_nc") else "")
          + f" and {len(out['figures'])} figure(s)")
    return 0
