"""``frustum fragility``: lognormal fragility curves from a study results file."""

import argparse

from pipeline.errors import InputError
from pipeline.undecided import DEFAULT_UNDECIDED, UNDECIDED_CHOICES

_EXAMPLES = """\
examples:
  overturning and damage-state curves against PGA, 200 bootstrap replicates:
    frustum fragility out/quickstart.nc --out out/quickstart_fragility.nc --bootstrap 200 --seed 1
  against PGV, damage states at 0.3 and 0.6 theta_crit:
    frustum fragility out/quickstart.nc --out frag-pgv.nc --im pgv --states 0.3,0.6
  a study of drums (model 3d-compliant): residual joint slip of 2 % and 20 % of the joint's diameter:
    frustum fragility out/drums.nc --out frag-drums.nc --dislocations 0.02,0.2
"""


def register(subparsers):
    """Add the ``fragility`` sub-command."""
    p = subparsers.add_parser(
        "fragility",
        help="fit lognormal fragility curves to study results (netCDF out)",
        description="Fit lognormal fragility curves (maximum likelihood, Baker 2015) for overturning and for "
        "damage states on peak theta/theta_crit, per column and model, to the results of 'frustum study run'; "
        "write median [IM units], dispersion beta and bootstrap bounds to netCDF.",
        epilog=_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("results", metavar="FILE.nc", help="study results written by 'frustum study run'")
    p.add_argument("--out", required=True, metavar="FRAGILITY.nc", help="netCDF file to write")
    p.add_argument("--im", default="pga", metavar="NAME",
                   help="intensity measure in the results: pga [m/s^2], pgv [m/s], sa [m/s^2] (default pga)")
    p.add_argument("--states", default="0.25,0.5,1", metavar="S1,S2,...",
                   help="damage states as thresholds on peak theta/theta_crit (default 0.25,0.5,1); "
                   "overturning is always fitted")
    p.add_argument("--dislocations", default=None, metavar="S1,S2,...",
                   help="dislocation damage states as thresholds on the largest residual slip of a bed joint over "
                   "its diameter (default 0.01,0.05,0.1 for results of the model 3d-compliant; 'none': skip)")
    p.add_argument("--bootstrap", type=int, default=0, metavar="N",
                   help="bootstrap replicates over records for confidence bounds (default 0: none)")
    p.add_argument("--seed", type=int, default=0, help="seed of the bootstrap (default 0)")
    p.add_argument("--confidence", type=float, default=0.9,
                   help="confidence level of the bounds, between 0 and 1 (default 0.9)")
    add_undecided_option(p)
    p.set_defaults(handler=run)


def add_undecided_option(p):
    """``--undecided``: how runs still able to fall at their settle limit count (fragility and report)."""
    p.add_argument("--undecided", choices=UNDECIDED_CHOICES, default=DEFAULT_UNDECIDED,
                   help="runs still able to fall when they reached their settle limit (the cap of simulated time "
                   "after the record) count as runs that stood (standing, the default), as runs that overturned, "
                   "or are left out (excluded); the report states what the other way moves")


def parse_states(text):
    """``"0.25,0.5,1"`` -> (0.25, 0.5, 1.0); empty -> () (overturning only)."""
    if text is None or not str(text).strip():
        return ()
    try:
        return tuple(float(part) for part in str(text).split(",") if part.strip())
    except ValueError:
        raise InputError(f"--states {text!r}: give numbers separated by commas, e.g. 0.25,0.5,1") from None


def parse_dislocations(text):
    """``"0.01,0.05"`` -> (0.01, 0.05); ``"none"`` or empty -> (); None -> None (the default)."""
    if text is None:
        return None
    if not str(text).strip() or str(text).strip().lower() == "none":
        return ()
    try:
        return tuple(float(part) for part in str(text).split(",") if part.strip())
    except ValueError:
        raise InputError(f"--dislocations {text!r}: give numbers separated by commas, e.g. 0.01,0.05,0.1, "
                         "or none") from None


def check_fit_options(args):
    """Refuse ``--bootstrap`` and ``--confidence`` (where the command has it) by name, before anything is read."""
    if args.bootstrap < 0:
        raise InputError(f"--bootstrap {args.bootstrap}: give 0 (no bounds) or a positive number of replicates, "
                         "e.g. 200")
    confidence = getattr(args, "confidence", 0.9)
    if not 0 < confidence < 1:  # NaN too
        raise InputError(f"--confidence {confidence:g}: give a level between 0 and 1, e.g. 0.9")


def run(args):
    from pipeline import fragility as F
    from pipeline.paths import check_output_file

    check_fit_options(args)
    check_output_file(args.out, "--out", kind="fragility", inputs=[("results file", args.results)])
    results = F.open_results(args.results)
    frag = F.fragility(results, im=args.im, states=parse_states(args.states), bootstrap=args.bootstrap,
                       seed=args.seed, confidence=args.confidence,
                       dislocations=parse_dislocations(args.dislocations), undecided=args.undecided)
    F.write(frag, args.out)
    units = frag["median"].attrs["units"]
    for c in frag["column"].values:
        for m in frag["model"].values:
            cell = frag.sel(state="overturning", column=c, model=m)
            status = F.FIT_STATUS[int(cell["fit_status"])]
            undecided = int(frag["n_undecided"].sel(column=c, model=m))
            print(f"{c} {m}: overturning median {args.im} = {float(cell['median']):.4g} {units}, "
                  f"beta = {float(cell['beta']):.3g} ({status}; {int(cell['n_exceed'])}/{int(cell['n_runs'])} runs"
                  + (f", {undecided} undecided counted as {args.undecided}" if undecided else "") + ")")
    print(f"wrote {args.out}")
    return 0
