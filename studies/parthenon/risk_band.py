"""The Parthenon's east front at the Acropolis under a band of code hazards (issue 48, item 3).

No hazard curve of the Acropolis is readable here; the Greek code's zones give a 475-year PGA of
0.16 g or 0.24 g (Athens has been quoted in both) and Eurocode 8 writes the hazard as a power law
H(a) = k0 a^-k with k about 3 (2 to 4 across Europe). For each corner of that band this runs
``frustum risk --hazard-pga 475:PGA --hazard-slope K --years 50,2100`` on the front report's
fragility and prints one Markdown table per damage state: the annual frequency with its bootstrap
band over records, the chance in 50 years and the chance of standing 2,100 years (exp(-2100 lambda),
the centuries from 438 BC to the explosion of 1687), each with its band::

    python studies/parthenon/risk_band.py studies/parthenon/front-report/fragility.nc \
        --csv studies/parthenon/risk_band.csv

The power law is extrapolated above 0.16 or 0.24 g, where the fragility's medians lie: the tables
are the code's hazard taken at its word far beyond the return periods it was written for.
"""

import argparse
import contextlib
import csv
import math
import os
import sys
import tempfile

from pipeline.cli import main as frustum

PGAS_475 = (0.16, 0.24)  # [g], the Greek code's zones quoted for Athens
SLOPES = (2.0, 3.0, 4.0)  # [1], Eurocode 8's k across Europe
YEARS = 2100  # [yr], about 438 BC to AD 1687
STATES = {  # damage state of the fragility file: words of the table
    "overturning": "overturning (any body of the front lies down or falls)",
    "dislocation_0.01": "DS1, a drum dislocated by 1 % of its diameter (19 mm)",
    "dislocation_0.05": "DS2, 5 % (the drums need re-setting)",
    "dislocation_0.1": "DS3, 10 % (a column markedly weakened)",
}


def corner(fragility, pga, slope, folder):
    """Rows of ``frustum risk``'s CSV for one corner of the band (hazard PGA [g] at 475 years, slope)."""
    out = os.path.join(folder, f"risk_{pga:g}_k{slope:g}")
    with contextlib.redirect_stdout(sys.stderr):  # its lines to stderr: stdout is the tables
        status = frustum(["risk", fragility, "--hazard-pga", f"475:{pga:g}", "--hazard-slope", f"{slope:g}",
                          "--years", f"50,{YEARS}", "--out", out + ".nc", "--csv", out + ".csv"])
    if status:
        sys.exit(status)
    with open(out + ".csv", newline="") as fh:
        return list(csv.DictReader(fh))


def standing(rate):
    """Chance of standing YEARS years at an annual frequency ``rate`` [1/yr] (Poisson) [%]."""
    return 100.0 * math.exp(-YEARS * rate)


def _same_fit(row, other):
    """Whether two rows of the risk CSV carry the same fragility (median and dispersion)."""
    return other is not None and all(row[f] == other[f] for f in ("fragility_median_g", "fragility_beta"))


def table_rows(rows, state, model):
    """Markdown rows of one damage state and model over every corner of the band."""
    lines = []
    for (pga, slope), got in rows.items():
        row = next((r for r in got if r["state"] == state and r["model"] == model), None)
        falls = next((r for r in got if r["state"] == "overturning" and r["model"] == model), None)
        if row is None or (state != "overturning" and _same_fit(row, falls)):
            continue  # a model without bed joints (the rigid frame) reaches a dislocation only by falling
        rate, lo, hi = (float(row[f"annual_frequency{s}_per_yr"]) for s in ("", "_band_lower", "_band_upper"))
        p50, p50_lo, p50_hi = (100 * float(row[f"probability_in_50_yr{s}"]) for s in ("", "_band_lower",
                                                                                    "_band_upper"))
        lines.append(f"| {pga:g} g | {slope:g} | {rate:.2g} ({lo:.2g}-{hi:.2g}) | {1 / rate:,.0f} | "
                     f"{p50:.2g} ({p50_lo:.2g}-{p50_hi:.2g}) | {standing(rate):.0f} "
                     f"({standing(hi):.2g}-{standing(lo):.0f}) | {row['risk_flag']} |")
    return lines


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("fragility", help="fragility.nc of `frustum report` or `frustum fragility`")
    parser.add_argument("--models", default="front,frame", help="models to tabulate (default front,frame)")
    parser.add_argument("--csv", help="also write every corner's rows to this CSV")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as folder:
        rows = {(pga, slope): corner(args.fragility, pga, slope, folder) for pga in PGAS_475 for slope in SLOPES}
    for model in args.models.split(","):
        for state, words in STATES.items():
            lines = table_rows(rows, state, model)
            if not lines:
                continue
            print(f"\n**{model}: {words}**\n")
            print("| 475-yr PGA | slope k | annual frequency [1/yr] (band) | return period [yr] | "
                  f"in 50 yr [%] (band) | standing {YEARS:,} yr [%] (band) | flag |")
            print("|---|---|---|---|---|---|---|")
            print("\n".join(lines))
    if args.csv:
        fields = list(next(iter(rows.values()))[0])
        with open(args.csv, "w", newline="") as fh:
            writer = csv.DictWriter(fh, fieldnames=["hazard_pga_475_g", "hazard_slope"] + fields)
            writer.writeheader()
            for (pga, slope), got in rows.items():
                for row in got:
                    writer.writerow({"hazard_pga_475_g": pga, "hazard_slope": slope, **row})


if __name__ == "__main__":
    main()
