"""Hazard curve files for the risk tests, written the way the OpenQuake engine writes them.

The engine (``openquake.baselib.writers.write_csv`` called by the hcurves CSV export,
``export_hcurves_by_imt_csv``) opens the file with ``newline=''`` and writes with
``csv.writer`` (CRLF line ends): first a row of as many fields as the header, ``#``, empty
fields and the metadata ``'%s=%r'`` joined by ``', '`` in the last field (quoted, it holds
commas); then the header ``lon,lat,depth,poe-<IML as %.7f>``; then one row per site, the
coordinates as ``%.5f`` and the probabilities of exceedance as ``%.6E``.
"""

import csv
import io

import numpy as np

from pipeline.units import G


def openquake_text(levels_g, poe, lonlat, investigation_time=50.0, imt="PGA", kind="mean", depth=-0.1):
    """The text of ``hazard_curve-<kind>-<imt>_<id>.csv`` for sites ``lonlat`` [(lon, lat)] and PoE (site, level)."""
    header = ["lon", "lat", "depth"] + ["poe-%.7f" % iml for iml in levels_g]
    meta = {"generated_by": "OpenQuake engine 3.18.0", "start_date": "2024-06-03T09:36:04",
            "checksum": 2107362341, "kind": kind, "investigation_time": float(investigation_time), "imt": imt}
    out = io.StringIO(newline="")
    w = csv.writer(out)
    w.writerow(["#"] + [""] * (len(header) - 2) + [", ".join("%s=%r" % item for item in meta.items())])
    w.writerow(header)
    for (lon, lat), row in zip(lonlat, np.atleast_2d(poe)):
        w.writerow(["%.5f" % lon, "%.5f" % lat, "%.5f" % depth] + ["%.6E" % p for p in row])
    return out.getvalue()


#: Intensity levels of the example curves [g] (a typical OpenQuake job's PGA levels).
EXAMPLE_LEVELS_G = np.array([0.005, 0.01, 0.02, 0.04, 0.07, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.7, 1.0, 1.3, 1.6, 2.0])


def quadratic_curve(levels_g, anchors):
    """Annual rates [1/yr] of a curve with ln H quadratic in ln a through three (a [g], H [1/yr]) anchors."""
    u = np.log([a for a, _ in anchors])
    c = np.polyfit(u, np.log([h for _, h in anchors]), 2)
    return np.exp(np.polyval(c, np.log(levels_g)))


#: Two made-up sites: a high-hazard one (475-yr PGA 0.25 g, 2475-yr 0.5 g) and a lower one (0.12 g, 0.25 g).
EXAMPLE_SITES = {
    "high": ((23.72700, 37.97200), [(0.01, 0.2), (0.25, 1 / 475), (0.5, 1 / 2475)]),
    "low": ((22.88000, 37.90500), [(0.01, 0.1), (0.12, 1 / 475), (0.25, 1 / 2475)]),
}


def example_openquake_text(investigation_time=50.0):
    """The two example sites as an engine export (PoE in ``investigation_time`` years)."""
    rates = np.array([quadratic_curve(EXAMPLE_LEVELS_G, anchors) for _, anchors in EXAMPLE_SITES.values()])
    poe = -np.expm1(-rates * investigation_time)
    return openquake_text(EXAMPLE_LEVELS_G, poe, [ll for ll, _ in EXAMPLE_SITES.values()], investigation_time)


def plain_text(levels_g, rates, header="PGA [g],annual_rate [1/yr]"):
    """A plain two-column curve."""
    return header + "\n" + "".join(f"{float(a)!r},{float(h)!r}\n" for a, h in zip(levels_g, rates))


def power_law_text(k0, k, median_ms2, levels=40, header="PGA [g],annual_rate [1/yr]"):
    """A plain curve H = k0 a^-k (a in m/s^2) from 1e-3 times the median to 1e3 times it or 20 g, whichever
    is lower (the reader refuses levels beyond 30 g, pipeline.risk.MAX_LEVEL), levels written in g."""
    a = np.geomspace(median_ms2 * 1e-3, min(median_ms2 * 1e3, 20.0 * G), levels)
    return plain_text(a / G, k0 * a ** -k, header)


def fixed_fragility(frag, median_g, beta, state="overturning"):
    """A copy of a fragility Dataset whose ``state`` has the given lognormal fit in every column and model
    (median [g], beta [1], fit_status ok) and no bootstrap replicates: a risk whose numbers follow from the
    hazard curve and these two alone."""
    from pipeline import fragility as F

    out = frag.drop_vars([n for n in frag.variables if "bootstrap" in frag[n].dims], errors="ignore")
    out = out.drop_dims("bootstrap", errors="ignore").copy(deep=True)
    out["median"].loc[{"state": state}] = median_g * G
    out["beta"].loc[{"state": state}] = beta
    out["fit_status"].loc[{"state": state}] = F.FIT_OK
    return out


if __name__ == "__main__":  # regenerate tests/data/hazard/hazard_curve-mean-PGA_1.csv
    import sys
    from pathlib import Path

    target = Path(__file__).parents[1] / "data" / "hazard" / "hazard_curve-mean-PGA_1.csv"
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_bytes(example_openquake_text().encode("utf-8"))
    sys.stdout.write(f"wrote {target}\n")
