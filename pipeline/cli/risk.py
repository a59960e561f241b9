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
  from code values, PGA 0.16 g at a 475-year return period, Eurocode 8's slope k = 3 at every other PGA; the
  chance in 50 years and in 2,100 years:
    frustum risk out/quickstart_fragility.nc --hazard-pga 475:0.16 --years 50,2100 --out risk.nc
  two return periods: the power law through both, extended beyond them by its own slope (or by --hazard-slope):
    frustum risk out/quickstart_fragility.nc --hazard-pga 475:0.16,2475:0.30 --hazard-slope 3 --out risk.nc
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
        "two-column CSV (level with its unit, annual rate); its intensity measure must be the fragility's. Without a "
        "hazard curve, --hazard-pga gives one from code values: PGAs at return periods T, H(a_T) = 1/T, a power law "
        "H = H0 (a/a0)^-k in log-log between them and extrapolated beyond them (the files and the figure say where).",
        epilog=_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("fragility", metavar="FRAGILITY.nc", help="fragility written by 'frustum fragility' (medians in m/s^2)")
    p.add_argument("--hazard", metavar="CURVE.csv",
                   help="hazard curve: OpenQuake engine CSV (IMLs in g) or 'PGA [g],annual_rate [1/yr]' CSV "
                        "(or --hazard-pga)")
    p.add_argument("--hazard-pga", metavar="T:PGA[,T:PGA...]",
                   help="hazard from code values instead of --hazard: the PGA [g] at a return period T [yr], e.g. "
                        "475:0.16 (one value: slope --hazard-slope, default 3) or 475:0.16,2475:0.30 (the power law "
                        "between them, extended beyond them by the end segments' slopes)")
    p.add_argument("--hazard-slope", type=float, metavar="K",
                   help="slope k of H = H0 (a/a0)^-k beyond the --hazard-pga values, 0.5 to 10 (default 3 for one "
                        "value, the end segments' for two or more)")
    p.add_argument("--years", default="50", metavar="T[,T...]",
                   help="period(s) of the stated probability [yr], e.g. 50 or 50,2100 (default 50)")
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

    years = _years(args.years)
    _check_hazard_options(args)
    inputs = [("fragility file", args.fragility)] + ([("hazard curve", args.hazard)] if args.hazard else [])
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
    if args.hazard:
        hazard = R.read_hazard_curve(args.hazard)
    else:
        hazard = R.code_hazard_curve(args.hazard_pga, args.hazard_slope, where="--hazard-pga: ")
    risk = R.site_risk(frag, hazard, years=years)
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


def _years(text):
    """``--years``: one period [yr] (a float, the old form) or several (a list), each positive and given once."""
    values = []
    for part in str(text).split(","):
        try:
            value = float(part)
        except ValueError:
            raise InputError(f"--years {text}: {part.strip()!r} is not a number of years; give one or more, e.g. 50 "
                             "or 50,2100") from None
        if not (math.isfinite(value) and value > 0):
            raise InputError(f"--years {value:g}: give a positive number of years, e.g. 50")
        values.append(value)
    if len(set(values)) != len(values):
        raise InputError(f"--years {text}: a period is given twice; give each once, e.g. 50,2100")
    return values[0] if len(values) == 1 else values


def _check_hazard_options(args):
    """One source of the hazard: --hazard (a file) or --hazard-pga (code values); --hazard-slope only with the latter."""
    if args.hazard and args.hazard_pga:
        raise InputError(f"--hazard {args.hazard} and --hazard-pga {args.hazard_pga} both give the site's hazard; "
                         "give one of them")
    if not (args.hazard or args.hazard_pga):
        raise InputError("give the site's hazard: --hazard CURVE.csv (the OpenQuake engine's CSV or a two-column "
                         "CSV) or --hazard-pga T:PGA (code values, e.g. 475:0.16)")
    if args.hazard_slope is not None and not args.hazard_pga:
        raise InputError(f"--hazard-slope {args.hazard_slope:g} shapes a hazard curve from code values "
                         "(--hazard-pga); a hazard curve file has its own slopes: drop --hazard-slope")
    if args.hazard_slope is not None:
        from pipeline.risk import check_slope

        check_slope(args.hazard_slope, "--hazard-slope")


def _print_summary(risk, state):
    from pipeline import risk as R

    years = R.periods(risk)
    sites = [str(s) for s in risk["site"].values]
    if risk.attrs.get("hazard_format") == "code":
        print(f"hazard: {risk.attrs['hazard_source']}; extrapolated {risk.attrs['hazard_extrapolated']}")
    several = risk["hazard_level"].size > 1  # one code value: the whole curve is extrapolated, said above
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
                clauses = []
                for i, period in enumerate(years):
                    p, lo, hi, blo, bhi = (R.in_period(cell, f"probability_in_period{name}", period) for name in
                                           ("", "_lower", "_upper", "_band_lower", "_band_upper"))
                    band = f"; bootstrap band {R.percent(blo)} to {R.percent(bhi)}" if math.isfinite(blo) else ""
                    clauses.append(f"in {period:g} yr {R.percent(p)} ({R.one_in(p)}{band}; curve-end bounds "
                                   f"{R.percent(lo)} to {R.percent(hi)}{note if i == 0 else ''})")
                extrapolated = ""
                if risk.attrs.get("hazard_format") == "code" and several:
                    share = float(cell["share_below_first_level"]) + float(cell["share_beyond_last_level"])
                    extrapolated = f"; {R.percent(share)} of it from the extrapolated curve"
                print(f"{head} {lam:.3g} /yr, once in {R.years_words(float(cell['return_period']))} on average; "
                      f"{'; '.join(clauses)}{extrapolated}")
    if len(sites) > 10:
        print(f"... and {len(sites) - 10} more site(s): see the netCDF or --csv")
