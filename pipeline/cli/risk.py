"""``frustum risk``: how likely a column is to reach a damage state at its site, from a fragility and a hazard curve."""

import argparse
import math

from pipeline.errors import InputError

_EXAMPLES = """\
examples:
  the risk of every column, model and damage state at the sites of an OpenQuake hazard curve (PGA):
    frustum risk out/quickstart_fragility.nc --hazard examples/synthetic-hazard_curve-mean-PGA.csv \\
        --out risk.nc
  in 100 years, with a spreadsheet and a figure:
    frustum risk out/quickstart_fragility.nc --hazard YOUR_SITE.csv --years 100 --out risk.nc --csv risk.csv --plot risk.png
  a plain two-column curve: first line 'PGA [g],annual_rate [1/yr]' (or 'SA(1.0) [g],poe in 50 years')
"""


def register(subparsers):
    """Add the ``risk`` sub-command."""
    p = subparsers.add_parser(
        "risk",
        help="mean annual frequency and probability in N years of each damage state at a site (netCDF out)",
        description="Integrate the fragility of 'frustum fragility' against a site's hazard curve "
        "(lambda = integral P(DS | a) |dH/da| da, the curve interpolated log-log, the part beyond its last level "
        "bounded): mean annual frequency [1/yr], probability in --years, return period [yr] and the bootstrap band "
        "of every site, damage state, column and model. The hazard curve is the OpenQuake engine's CSV "
        "(hazard_curve-mean-PGA_<id>.csv: levels in g, probabilities of exceedance in its investigation time) or a "
        "two-column CSV (level with its unit, annual rate); its intensity measure must be the fragility's.",
        epilog=_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("fragility", metavar="FRAGILITY.nc", help="fragility written by 'frustum fragility' (medians in m/s^2)")
    p.add_argument("--hazard", required=True, metavar="CURVE.csv",
                   help="hazard curve: OpenQuake engine CSV (IMLs in g) or 'PGA [g],annual_rate [1/yr]' CSV")
    p.add_argument("--years", type=float, default=50.0, metavar="T",
                   help="period of the stated probability [yr] (default 50)")
    p.add_argument("--out", required=True, metavar="RISK.nc", help="netCDF file to write")
    p.add_argument("--csv", default=None, metavar="FILE.csv",
                   help="also write one row per site, column, model and damage state (units in the column names)")
    p.add_argument("--plot", default=None, metavar="FILE.png",
                   help="also draw the hazard curve, the fragility and the risk integrand (any matplotlib format)")
    p.add_argument("--state", default="overturning", metavar="STATE",
                   help="damage state drawn by --plot and printed (default overturning)")
    p.set_defaults(handler=run)


def run(args):
    from pipeline import risk as R
    from pipeline.paths import check_output_file, check_plot_file

    if not (math.isfinite(args.years) and args.years > 0):
        raise InputError(f"--years {args.years:g}: give a positive number of years, e.g. 50")
    inputs = [("fragility file", args.fragility), ("hazard curve", args.hazard)]
    outs = [("--out", args.out)] + [(o, p) for o, p in (("--csv", args.csv), ("--plot", args.plot)) if p]
    for i, (label, path) in enumerate(outs):  # two outputs on one path would leave only the last
        for other, path2 in outs[:i]:
            if check_output_file(path, label, kind=None) == check_output_file(path2, other, kind=None):
                raise InputError(f"{label} {path!r} is also given to {other}; give each output its own file name")
    check_output_file(args.out, "--out", kind="risk", inputs=inputs)
    if args.csv:
        check_output_file(args.csv, "--csv", kind="risk-csv", inputs=inputs)  # its header row tells ours
    if args.plot:
        check_plot_file(args.plot, "--plot", inputs=inputs)
    frag = R.open_fragility(args.fragility)
    states = [str(s) for s in frag["state"].values]
    if args.state not in states:
        raise InputError(f"--state {args.state!r} is not in {args.fragility}; its damage states: {', '.join(states)}")
    hazard = R.read_hazard_curve(args.hazard)
    risk = R.site_risk(frag, hazard, years=args.years)
    R.write(risk, args.out)
    written = [args.out]
    if args.csv:
        written.append(R.write_csv(risk, args.csv))
    if args.plot:
        from pipeline.plotting_risk import plot_risk

        written.append(plot_risk(risk, args.plot, state=args.state))
    _print_summary(risk, args.state)
    print(f"wrote {', '.join(written)}")
    return 0


def _print_summary(risk, state):
    from pipeline import risk as R

    years = float(risk["years"])
    sites = [str(s) for s in risk["site"].values]
    for site in sites[:10]:
        for c in risk["column"].values:
            for m in risk["model"].values:
                cell = risk.sel(site=site, column=c, model=m, state=state)
                head = f"{site} {c} {m} {state}:"
                reason = R.no_risk_reason(risk, site, c, m, state)
                if reason is not None:
                    print(f"{head} no risk computed: {reason}")
                    continue
                lam = float(cell["annual_frequency"])
                flag = R.RISK_FLAGS[int(cell["risk_flag"])]
                note = "" if flag == "ok" else f"; {flag.replace('_', ' ')}"
                if lam <= 0:
                    print(f"{head} 0 /yr{note}")
                    continue
                p = float(cell["probability_in_period"])
                lo, hi = float(cell["probability_in_period_lower"]), float(cell["probability_in_period_upper"])
                blo, bhi = (float(cell[f"probability_in_period_band_{b}"]) for b in ("lower", "upper"))
                band = f"; bootstrap band {R.percent(blo)} to {R.percent(bhi)}" if math.isfinite(blo) else ""
                print(f"{head} {lam:.3g} /yr, once in {R.years_words(float(cell['return_period']))} on average; in "
                      f"{years:g} yr {R.percent(p)} ({R.one_in(p)}{band}; curve-end bounds {R.percent(lo)} to "
                      f"{R.percent(hi)}{note})")
    if len(sites) > 10:
        print(f"... and {len(sites) - 10} more site(s): see the netCDF or --csv")
