"""Reports of the issue-6 studies from the results of ``frustum study run``.

Run the studies first (each from its study file alone), then this script::

    frustum study run studies/fema_slenderness/fema_slenderness.toml
    frustum study run studies/model_2d_vs_3d/model_2d_vs_3d.toml
    frustum study run studies/damping/damping_nu0.toml      # and damping_nu002, damping_nu01
    frustum study run studies/real_column/real_column.toml
    python studies/fragility_reports.py                     # all four, or: --only model_2d_vs_3d

Each study folder receives ``report.md``, ``summary.csv`` (``columns.geojson`` where
columns carry coordinates) and ``figures/`` (PNG and PDF). The fragility netCDF files,
the one-file HTML reports (``out/NAME_report.html``) and the study results stay in
``out/`` (not in git). ``frustum report FILE.nc --out DIR``
writes the same report for any one study; this script adds what spans studies (the
damping comparison) and the contact-point paths of chosen runs, which need new
simulations with time histories.
"""

import argparse
import math
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, ROOT)

from pipeline import fragility as F  # noqa: E402
from pipeline import plotting_fragility as P  # noqa: E402
from pipeline.report import _fmt, _pct, write_report  # noqa: E402
from pipeline.units import G  # noqa: E402

OUT = os.path.join(ROOT, "out")
BOOTSTRAP = 200
SEED = 2015
PAPER = "R0.5-s8-b0.8"  # the paper's column (R = 0.5 m, r = 0.4 m, h = 4 m) in the study grids


def _column(results, label):
    from pipeline.structures.column import Column

    c = results.sel(column=label)
    return Column(float(c["column_R"]), float(c["column_r"]), float(c["column_h"]), name=label)


def chosen_runs(results, label, model="3d"):
    """Three runs of a column worth looking at: the largest rocking that stands, a moderate one, an overturning."""
    one = results.sel(column=label, model=model).isel(angle=0)
    ratio = one["peak_theta_ratio"].where(one["status"] == 0)
    over = one["overturned"] == 1
    picks = []
    standing = ratio.where(~over & (ratio < 0.9))
    if np.isfinite(standing.max()):
        idx = np.unravel_index(int(np.nanargmax(standing.values)), standing.shape)
        picks.append(("largest rocking that stands", idx))
    moderate = np.abs(ratio.where(~over) - 0.3)
    if np.isfinite(moderate.min()):
        picks.append(("moderate", np.unravel_index(int(np.nanargmin(moderate.values)), moderate.shape)))
    if bool(over.any()):
        pga = one["pga"].where(over)
        picks.append(("overturns", np.unravel_index(int(np.nanargmin(pga.values)), pga.shape)))
    out = []
    for why, (r, k) in picks:
        rec = str(one["record"].values[r])
        out.append((why, rec, float(one["scale_factor"].values[r, k]), float(one["pga"].values[r, k])))
    return out


def trajectories(results, label, model="3d"):
    """Simulate the chosen runs again with time histories (same record, factor, settings)."""
    import json

    from pipeline.groundmotion import load
    from pipeline.settings import Excitation, ModelSettings
    from pipeline.simulate import simulate

    options = json.loads(results.attrs.get("model_options", "{}"))
    settings = ModelSettings(model=model, **{k: v for k, v in options.items()
                                             if k in ("friction", "tail", "damping", "restitution", "contact_tilt")})
    column = _column(results, label)
    runs = []
    for why, rec, factor, pga in chosen_runs(results, label, model):
        resp = simulate(column, load(rec), Excitation(angle=0.0, scale=factor), settings, histories=True)
        s = resp.summary
        state = "overturned" if s["overturned"] else f"peak θ/θ_crit = {s['peak_theta_ratio']:.2f}"
        runs.append((f"{why}: {rec} × {factor:.2f}\nPGA {pga / G:.2f} g ({pga:.2f} m/s²), {state}", resp.histories))
    return runs


CONTACT = (
    " **Contact** (issue 10): the rigid models with the physical contact of docs/model.md: Coulomb friction 0.7 "
    "(sliding on the base, slip on the rim), lift-off and touch-down, the contact patch of a bed of normal "
    "stiffness 1e10 Pa/m (rolling damping, drilling friction) and the continuous passage law near full contact; "
    "landings by the angular-momentum restitution. How far the medians move with friction 0.5-0.8, restitution "
    "+-5 % and the patch (1e9-1e11 Pa/m): `studies/contact_bands/results.md`.")

NOTES = {
    "fema_slenderness": (
        "**Question.** How does the probability of overturning of a free-standing column under the FEMA P695 "
        "far-field records depend on its slenderness h/R and conicity r/R? The paper's column is "
        f"`{PAPER}` (R = 0.5 m, r = 0.4 m, h = 4 m). Every record is scaled to the same PGA at each stripe, "
        "so each stripe is one intensity level (multiple-stripe analysis)." + CONTACT),
    "model_2d_vs_3d": (
        "**Question.** The paper (Section 5) argues that a free-standing column wobbles rather than rocks, so "
        "two-dimensional rocking analyses should miss its response. Where, and by how much, does the 2D "
        "planar-rocking analysis give a lower probability of overturning than the 3D rolling frustum for the "
        "same columns, records and intensity? (2D is driven by the component of the record along the incidence "
        "angle; 3D by both horizontal components.)" + CONTACT),
    "real_column": (
        "**Question.** How likely are two real monolithic shafts to overturn under far-field earthquakes? "
        "Dimensions: Pompey's Pillar, Alexandria, monolithic shaft 20.46 m high, 2.71 m diameter at the base and "
        "2.30 m at the top (Wikipedia, 'Pompey's Pillar (column)'); a monolithic Doric column of the Temple of "
        "Apollo at Corinth, about 7.2 m high with a lower diameter of about 1.72 m (Wikipedia, 'Temple of Apollo "
        "(Corinth)'; the Edinburgh Encyclopaedia gives 23 ft 8.5 in = 7.23 m including the capital and 5 ft 7 in "
        "= 1.70 m), top radius 0.65 m assumed. Base mouldings, capitals and pedestals are not modelled." + CONTACT),
}

FOCUS = {"fema_slenderness": PAPER, "model_2d_vs_3d": PAPER, "real_column": "corinth-apollo"}


def component_share(results):
    """Peak of the record's component along each incidence angle over the peak of the horizontal vector [1].

    The 2D model is driven by that component; the dataset's PGA is the vector's. Returns the median and
    the range over records and angles (read from the records themselves, not from the dataset).
    """
    from pipeline.groundmotion import load

    shares = []
    for rec in results["record"].values:
        gm = load(str(rec))
        vector = np.max(np.hypot(gm.acc_x, gm.acc_y))
        for a in np.radians(results["angle"].values):
            shares.append(np.max(np.abs(gm.acc_x * math.cos(a) - gm.acc_y * math.sin(a))) / vector)
    shares = np.array(shares)
    return float(np.median(shares)), float(shares.min()), float(shares.max())


def report_study(name):
    path = os.path.join(OUT, f"{name}.nc")
    results = F.open_results(path)
    t0 = time.time()
    notes = NOTES[name] + (f"\n\n*Reproduce:* `frustum study run studies/{name}/{name}.toml` (results in `out/{name}.nc`), "
                           f"then `python studies/fragility_reports.py --only {name}`; or, for this report without "
                           f"the contact paths, `frustum report out/{name}.nc --out DIR --bootstrap {BOOTSTRAP} "
                           f"--seed {SEED}`.")
    if "2d" in [str(m) for m in results["model"].values]:
        med, lo, hi = component_share(results)
        notes += (f" The peak of the component that drives the 2D model is, over these records and angles, "
                  f"{100 * med:.0f} % of the vector PGA in the median ({100 * lo:.0f} % to {100 * hi:.0f} %): "
                  "a ratio of 2D to 3D median PGA well above "
                  f"{1 / med:.2f} points to the 3D motion itself rather than to the weaker driving component.")
    runs = trajectories(results, FOCUS[name]) if name != "model_2d_vs_3d" else None
    out = write_report(results, os.path.join(HERE, name), bootstrap=BOOTSTRAP, seed=SEED, notes=notes,
                       focus=FOCUS[name], trajectories=runs)
    os.replace(out["fragility"], os.path.join(OUT, f"{name}_fragility.nc"))  # netCDF stays out of git
    os.replace(out["html"], os.path.join(OUT, f"{name}_report.html"))  # the figures again, embedded: not in git
    print(f"{name}: {out['report']} ({len(out['figures'])} figures, {time.time() - t0:.0f} s)")
    return out


def report_damping():
    """Study (c): the same 3D study with nu = 0, 0.02, 0.1; one page comparing the fits."""
    labels = {"0": "damping_nu0", "0.02": "damping_nu002", "0.1": "damping_nu01"}
    frags, results = {}, {}
    for nu, stem in labels.items():
        results[nu] = F.open_results(os.path.join(OUT, f"{stem}.nc"))
        frags[nu] = F.fragility(results[nu], bootstrap=BOOTSTRAP, seed=SEED)
        F.write(frags[nu], os.path.join(OUT, f"{stem}_fragility.nc"))
    here = os.path.join(HERE, "damping")
    figs = []
    columns = [str(c) for c in frags["0"]["column"].values]
    for c in columns:
        figs += P.plot_curve_comparison({f"ν = {nu}": f for nu, f in frags.items()},
                                        os.path.join(here, "figures", f"overturning_{c}"), c,
                                        title=f"Column '{c}' (h/R = {float(frags['0']['slenderness'].sel(column=c)):g}), "
                                        "3D: probability of overturning for three contact dampings ν")[:1]
    lines = ["# Sensitivity of the 3D fragility to the contact damping ν", "",
             "Besides the landings, friction (sliding and slip) and the contact patch's dashpots, the 3D model "
             "dissipates through an optional viscous contact couple "
             "(`ModelSettings.damping` = ν, per m g R sqrt(R/g)). Three runs of one study differ only in ν "
             "(`damping_nu0.toml`, `damping_nu002.toml`, `damping_nu01.toml`): four columns (R = 0.5 m, r/R = 0.8, "
             f"h/R = 6, 8, 10, 12; `{PAPER}` is the paper's column) under the 22 FEMA P695 far-field pairs at "
             "11 PGA stripes (0.1 g to 3 g). All numbers below are read from the three results files.", "",
             "*Reproduce:* `frustum study run studies/damping/damping_nu0.toml` (and `damping_nu002.toml`, "
             "`damping_nu01.toml`), then `python studies/fragility_reports.py --only damping`. The bootstrap uses "
             f"the same seed ({SEED}) for the three, so the intervals come from the same record resamples.", "",
             f"Median PGA of overturning [g] with the {100 * frags['0'].attrs['confidence_level']:g} % bootstrap "
             f"interval over records ({BOOTSTRAP} replicates), dispersion β, and the overturned runs:", "",
             "| column | " + " | ".join(f"ν = {nu}: median [g] | β | overturned" for nu in labels) + " | median ν=0.1 / ν=0 |",
             "|---|" + "---|---|---|" * len(labels) + "---|"]
    for c in columns:
        cells = []
        meds = {}
        for nu, f in frags.items():
            cell = f.sel(state="overturning", column=c, model="3d")
            med = float(cell["median"])
            meds[nu] = med
            cells.append(f"{_fmt(med / G)} ({_fmt(float(cell['median_lower']) / G)} to "
                         f"{_fmt(float(cell['median_upper']) / G)}) | {_fmt(float(cell['beta']))} | "
                         f"{int(cell['n_exceed'])} / {int(cell['n_runs'])}")
        ratio = meds["0.1"] / meds["0"] if meds["0"] > 0 else math.nan
        lines.append(f"| {c} | " + " | ".join(cells) + f" | {_fmt(ratio)} |")
    lines += [""]
    for nu in ("0.02", "0.1"):
        changes, overlaps = [], 0
        for c in columns:
            a = frags["0"].sel(state="overturning", column=c, model="3d")
            b = frags[nu].sel(state="overturning", column=c, model="3d")
            changes.append(float(b["median"]) / float(a["median"]) - 1)
            overlaps += float(b["median_lower"]) <= float(a["median_upper"]) and \
                float(a["median_lower"]) <= float(b["median_upper"])
        k = int(np.argmax(np.abs(changes)))
        lines.append(f"- ν = {nu} against ν = 0: the median PGA of overturning changes by "
                     f"{100 * min(changes):+.0f} % to {100 * max(changes):+.0f} % over the four columns (largest "
                     f"for `{columns[k]}`); the bootstrap intervals overlap for {overlaps} of {len(columns)} columns.")
    lines += ["", "Probability of overturning at stated PGA levels (fitted curves):", "",
              "| column | PGA | " + " | ".join(f"ν = {nu}" for nu in labels) + " |", "|---|---|" + "---|" * len(labels)]
    for c in columns:
        for level in (0.3, 0.5, 0.8):
            ps = [F.probability(level * G, float(f["median"].sel(state="overturning", column=c, model="3d")),
                                float(f["beta"].sel(state="overturning", column=c, model="3d"))) for f in frags.values()]
            lines.append(f"| {c} | {level:g} g ({_fmt(level * G)} m/s²) | " + " | ".join(_pct(float(p)) for p in ps) + " |")
    lines += ["", "Fraction of runs that overturned at each stripe (from the runs, no fit):", "",
              "| column | PGA [g] | " + " | ".join(f"ν = {nu}" for nu in labels) + " |", "|---|---|" + "---|" * len(labels)]
    for c in columns:
        for k, s in enumerate(frags["0"]["scale"].values):
            fr = [float(f["stripe_fraction"].sel(state="overturning", column=c, model="3d").values[k])
                  for f in frags.values()]
            if any(v > 0 for v in fr):
                lines.append(f"| {c} | {_fmt(float(frags['0']['stripe_im'].values[k]) / G)} | "
                             + " | ".join(_pct(v) for v in fr) + " |")
    lines += ["", "## Figures", ""] + [f"![{os.path.basename(p)}]({os.path.relpath(p, here)})\n" for p in figs]
    with open(os.path.join(here, "report.md"), "w", encoding="utf-8") as fh:
        fh.write("\n".join(lines) + "\n")
    print(f"damping: {os.path.join(here, 'report.md')}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--only", choices=("fema_slenderness", "model_2d_vs_3d", "damping", "real_column"))
    args = parser.parse_args(argv)
    for name in ("fema_slenderness", "model_2d_vs_3d", "real_column", "damping"):
        if args.only and args.only != name:
            continue
        if not all(os.path.exists(os.path.join(OUT, f)) for f in (
                [f"{name}.nc"] if name != "damping" else ["damping_nu0.nc", "damping_nu002.nc", "damping_nu01.nc"])):
            print(f"{name}: results missing in {OUT}; run its study file(s) first (see the docstring)")
            continue
        report_damping() if name == "damping" else report_study(name)


if __name__ == "__main__":
    main()
