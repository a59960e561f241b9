"""How far the issue-10 headlines move with the contact parameters that are not measured physics.

The studies ``model_2d_vs_3d``, ``fema_slenderness`` and ``real_column`` run every column at
friction 0.7, the rigid models' angular-momentum restitution and a bed of normal stiffness
1e10 Pa/m (the contact patch that gives the rolling resistance). None of these is measured for
a given column, so each headline column is rerun here, from its own study file (records,
angles, stripes, tail, vertical), with one setting moved at a time:

- friction 0.5 and 0.8 (stone on stone, dry; docs/model.md);
- restitution 5 % below and above the column's angular-momentum value 1 - 2/I_y (per column:
  ``restitution`` is then explicit in both models);
- rolling resistance: normal stiffness 1e9 and 1e11 Pa/m (a patch ten times wider or narrower,
  its dashpots critical as by default).

For each column and model the lognormal overturning fragility is fitted (maximum likelihood,
PGA) and the table gives the default median and the band over the variants, and the 2D / 3D
ratio of medians with its band (the ratio taken within each variant).

Run (about 5 minutes on two cores)::

    python studies/contact_bands/bands.py > studies/contact_bands/results.md

Results files go to ``out/contact_bands/`` (not in git).
"""

import argparse
import dataclasses
import math
import os
import sys
import time
import tomllib

import numpy as np
import xarray as xr

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, ROOT)

from pipeline.fragility import fragility  # noqa: E402
from pipeline.settings import housner_restitution  # noqa: E402
from pipeline.study import load_motions, parse_study, run_study  # noqa: E402
from pipeline.units import G  # noqa: E402

#: study file -> labels of the columns rerun (the paper's column and the extremes of slenderness)
STUDIES = {
    "model_2d_vs_3d": ["R0.5-s8-b0.8", "R0.5-s4-b1", "R0.5-s12-b1"],
    "real_column": ["pompeys-pillar", "corinth-apollo"],
}
#: incidence angles of the bands [degree]: two of the studies' eight (the 2D model is driven by the
#: component along the angle; the 3D results do not depend on it), to keep the 35 runs of a study short
ANGLES = (0.0, 90.0)
#: variant name -> (option changes, restitution factor or None)
VARIANTS = {
    "default": ({}, None),
    "friction 0.5": ({"friction": 0.5}, None),
    "friction 0.8": ({"friction": 0.8}, None),
    "restitution -5 %": ({}, 0.95),
    "restitution +5 %": ({}, 1.05),
    "k_n 1e9 Pa/m": ({"normal_stiffness": 1e9}, None),
    "k_n 1e11 Pa/m": ({"normal_stiffness": 1e11}, None),
}


def study_variant(name, label, changes, e_factor):
    """The study ``name`` restricted to one column, with its options changed."""
    path = os.path.join(ROOT, "studies", name, f"{name}.toml")
    with open(path, "rb") as fh:
        data = tomllib.load(fh)
    study = parse_study(data, path)
    info = next(c for c in study.columns if c.label == label)
    options = dict(study.options)
    options.update(changes)
    if e_factor is not None:
        options["restitution"] = min(1.0, e_factor * housner_restitution(info.column))
    return dataclasses.replace(study, columns=(info,), options=tuple(sorted(options.items())), block_columns=None,
                               angles=ANGLES)


def medians(results):
    """Overturning median PGA [g] per model from a one-column results dataset."""
    fit = fragility(results, states=())
    med = fit["median"].sel(state="overturning").isel(column=0)
    return {str(m): float(med.sel(model=m)) / G for m in fit["model"].values}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--serial", action="store_true", help="run in this process (no Dask cluster)")
    parser.add_argument("--only", choices=sorted(STUDIES), help="compute one study's bands (no table)")
    parser.add_argument("--table-only", action="store_true",
                        help="compute nothing: tabulate the columns whose seven results are in out/contact_bands/")
    args = parser.parse_args()
    out_dir = os.path.join(ROOT, "out", "contact_bands")
    os.makedirs(out_dir, exist_ok=True)
    start = time.perf_counter()
    table = {}
    missing = set()
    n_runs = 0
    for name, labels in STUDIES.items():
        if args.only and name != args.only:
            continue
        motions = None
        for label in labels:
            for variant, (changes, e_factor) in VARIANTS.items():
                study = study_variant(name, label, changes, e_factor)
                motions = motions or load_motions(study)
                out = os.path.join(out_dir, f"{name}-{label}-{variant.replace(' ', '_').replace('%', 'pc')}.nc")
                if not os.path.exists(out):
                    if args.table_only:
                        missing.add((name, label))
                        continue
                    run_study(study, out=out, motions=motions, workers=args.workers, serial=args.serial,
                              progress=False)
                with xr.open_dataset(out) as results:
                    results.load()
                n_runs += int(results["status"].size)
                table[(name, label, variant)] = medians(results)
                print(f"{name} {label} {variant}: {table[(name, label, variant)]}", file=sys.stderr)
    if args.only:
        return 0
    minutes = (time.perf_counter() - start) / 60
    print("# Contact-parameter bands of the issue-10 headlines\n")
    made = (f"tabulated by `python studies/contact_bands/bands.py --table-only` from out/contact_bands/ "
            f"({n_runs} result cells, computed earlier)" if args.table_only else
            f"Made by `python studies/contact_bands/bands.py` ({n_runs} result cells, {minutes:.0f} min on "
            f"{args.workers} workers for the runs not already in out/contact_bands/)")
    # a table-only pass has no computing time to report: saying "0 min" would read as a measurement
    print(f"{made[0].upper()}{made[1:]}. Each column from its study file "
          f"(22 FEMA P695 far-field pairs, 11 PGA stripes, vertical on) at incidence angles "
          f"{', '.join(f'{a:g}' for a in ANGLES)} deg (the studies have 8; the 3D model does not depend on it),"
          " one setting moved at a time: friction 0.5 and 0.8 (default 0.7), "
          "restitution 0.95 and 1.05 times 1 - 2/I_y (default the angular-momentum law), normal stiffness "
          "1e9 and 1e11 Pa/m (default 1e10: the contact patch and its rolling resistance). Median PGA [g] of "
          "the lognormal overturning fragility; band = lowest - highest over the seven settings.\n")
    print("| study | column | 3D median [g] | 3D band [g] | 2D median [g] | 2D band [g] | 2D / 3D | 2D / 3D band |")
    print("|---|---|---|---|---|---|---|---|")
    for name, labels in STUDIES.items():
        for label in labels:
            if (name, label) in missing:
                print(f"| {name} | {label} | not computed | | | | | |")
                continue
            rows = [table[(name, label, v)] for v in VARIANTS]
            d3 = np.array([r.get("3d", math.nan) for r in rows])
            d2 = np.array([r.get("2d", math.nan) for r in rows])
            ratio = d2 / d3
            print(f"| {name} | {label} | {d3[0]:.3f} | {np.nanmin(d3):.3f} - {np.nanmax(d3):.3f} | {d2[0]:.3f} | "
                  f"{np.nanmin(d2):.3f} - {np.nanmax(d2):.3f} | {ratio[0]:.2f} | "
                  f"{np.nanmin(ratio):.2f} - {np.nanmax(ratio):.2f} |")
    print("\n## Every setting\n")
    print("| study | column | setting | 3D median [g] | 2D median [g] | 2D / 3D |")
    print("|---|---|---|---|---|---|")
    for (name, label, variant), r in table.items():
        d3, d2 = r.get("3d", math.nan), r.get("2d", math.nan)
        print(f"| {name} | {label} | {variant} | {d3:.3f} | {d2:.3f} | {d2 / d3:.2f} |")


if __name__ == "__main__":
    sys.exit(main())
