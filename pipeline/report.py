"""A short report of a study for people who do not program: Markdown, CSV, GeoJSON, figures.

:func:`write_report` turns a study results Dataset into a folder::

    DIR/report.md            what was simulated, the models' assumptions, the probability of
                             overturning at stated PGA levels, 2D against 3D, the figures
    DIR/report.html          the same, one self-contained file (figures embedded)
    DIR/summary.csv          one row per column and model (opens in a spreadsheet)
    DIR/columns.geojson      the columns that carry latitude/longitude (opens in a GIS)
    DIR/fragility.nc         the fitted curves (pipeline.fragility)
    DIR/figures/*.png|pdf

Each file says it was written by this project, so that a rerun may replace it
and nothing else (:func:`pipeline.paths.check_output_folder`): the figures in
their metadata, ``report.md`` in a closing HTML comment, ``report.html`` in a
``generator`` meta tag, ``columns.geojson`` in a ``generator`` member, the
netCDF files in their attributes; ``summary.csv`` by its header row.

Every number in the report and the CSV is read from the results Dataset or
from the fragility Dataset fitted to it here; nothing is typed in. The report
says what the data support: a median beyond the strongest (or below the
weakest) shaking simulated is marked *extrapolated*, a fit on fewer than
:data:`MIN_RECORDS` records is flagged as too few for a fragility, and
probabilities carry their bootstrap bounds.
"""

import csv
import json
import math
import os

import numpy as np

from pipeline import comparison as C
from pipeline import fragility as F
from pipeline.report_undecided import undecided_lines
from pipeline import models as MD
from pipeline.models import planar_pair
from pipeline import plotting_fragility as P
from pipeline import report_angles as A
from pipeline import report_colonnade as RC
from pipeline import report_seeds as RS
from pipeline.report_risk import risk_section
from pipeline.atomic import atomic_folder, atomic_open
from pipeline.dataset import write_netcdf
from pipeline.errors import InputError
from pipeline.paths import mark_text
from pipeline.units import G

#: PGA levels [g] at which the report states the probability of overturning.
DEFAULT_PGA_LEVELS_G = (0.1, 0.2, 0.3, 0.5, 0.8)

#: Fewest records for which the report treats a fitted curve as a fragility: the smallest record
#: set whose mean response ASCE/SEI 7-10 (16.1.3.2) accepts for response-history analysis.
MIN_RECORDS = 7

#: Significant digits of the numbers in summary.csv (records, bootstrap and fit carry no more).
CSV_DIGITS = 4

def assumptions(models, vertical=True, options=None, one_component=False):
    """The report's assumptions as Markdown bullets: what every model shares, then each model run.

    Each model is described by its entry of the registry (:mod:`pipeline.models`) and only the
    models given are described, so a report says nothing about a model it did not run.

    Parameters
    ----------
    models : sequence of str
        Models of the study, e.g. ``["3d", "2d"]``.
    vertical : bool
        Whether the records' vertical components were used.
    options : dict, optional
        The study's model options (``model_options``), listed as given.
    one_component : bool
        Whether each record's x component drove alone (``components = "x"``: y set to zero before scaling).

    Returns
    -------
    str
    """
    compliant = any(MD.REGISTRY[m].drums for m in models if m in MD.REGISTRY)
    shape = ("Each column is a conical frustum (a cone with its tip cut off): bottom radius R, top radius r, "
             "height h" + ("; the compliant model may cut it into drums and put a capital on top" if compliant
                           else "") + ". Its bodies are rigid and homogeneous: they do not bend, crack or break; "
             "flutes are ignored.")
    lines = [
        f"- {shape}",
        "- It stands free on a horizontal ground that moves with the recorded earthquake ("
        + ("the x component of each record alone, turned by the incidence angle, the y component set to zero "
           "before scaling" if one_component else "both horizontal components")
        + f"{' and the vertical one where recorded' if vertical else '; the vertical one is ignored'}); "
        "the ground itself is rigid: what gives is the contact of the base on it, as each model says below.",
    ]
    lines += [MD.markdown(m) for m in models]  # registry names (a study's variants: their models)
    if options:
        lines.append("- Model options of the study (the others at their defaults, docs/studies.md): "
                     + ", ".join(f"`{k}` = {v:g}" if isinstance(v, (int, float)) else f"`{k}` = {v}"
                                 for k, v in sorted(options.items())) + ".")
    lines.append("- The column *overturns* when it reaches the inclination at which its side touches the ground"
                 + (" (the compliant model: when any of its bodies lies down or falls)" if compliant else "")
                 + "; the *critical inclination* theta_crit is the static tipping angle (centre of mass above "
                 "the rim).")
    states = "- Damage states other than overturning are the peak inclination reaching a fraction of theta_crit"
    if compliant:
        states += (" and, for the compliant model, the largest residual slip of a bed joint reaching a fraction of "
                   "its diameter (`dislocation_s`; a column without bed joints reaches these only by overturning)")
    lines.append(states + ".")
    return "\n".join(lines) + "\n"


def _has_epistyle(results):
    """Whether any run of the results carried an epistyle (a colonnade run by a model of colonnades)."""
    return "epistyle_slip" in results and bool(np.isfinite(results["epistyle_slip"]).any())


def _fmt(value, digits=3):
    """Numbers as they appear in the report (and are compared in tests)."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "n/a"
    return f"{value:.{digits}g}"


def _pct(p):
    """A probability as the report prints it: one decimal, never rounded to a certainty it is not."""
    if not np.isfinite(p):
        return "n/a"
    if 0.0 < p < 0.0005:
        return "< 0.1 %"
    if 0.9995 <= p < 1.0:
        return "> 99.9 %"
    return f"{100 * p:.1f} %"


def _pct_bounds(p, lower=math.nan, upper=math.nan):
    """``12.2 % (9.1 to 15.0)``: the probability and its bootstrap bounds [%] when they are known."""
    if not (np.isfinite(lower) and np.isfinite(upper)):
        return _pct(p)
    return f"{_pct(p)} ({_pct(lower).replace(' %', '')} to {_pct(upper)})"


def _g_and_ms2(x):
    return f"{_fmt(x / G)} g ({_fmt(x)} m/s²)"


def overturning_probabilities(frag, pga_levels_g=DEFAULT_PGA_LEVELS_G):
    """Probability of overturning at the stated PGA levels, per column and model.

    Parameters
    ----------
    frag : xarray.Dataset
        Fragility against PGA.
    pga_levels_g : sequence of float
        PGA levels [g].

    Returns
    -------
    dict
        ``{(column, model): numpy.ndarray of probabilities [1]}``, from the
        fitted lognormal curve (degenerate fits as documented in
        :func:`pipeline.fragility.fitted_probability`).
    """
    out = {}
    levels = np.asarray(pga_levels_g, float) * G
    for c in frag["column"].values:
        for m in frag["model"].values:
            cell = frag.sel(state="overturning", column=c, model=m)
            out[(str(c), str(m))] = F.fitted_probability(levels, float(cell["median"]), float(cell["beta"]),
                                                         int(cell["fit_status"]))
    return out


def probability_bounds(frag, column, model, pga_levels_g=DEFAULT_PGA_LEVELS_G, state="overturning"):
    """Pointwise bootstrap bounds of the probability at the stated PGA levels (NaN without a bootstrap).

    Read from the bands ``probability_lower``/``probability_upper`` of the
    fragility Dataset, interpolated in log PGA on its ``im_level`` grid (NaN
    outside the grid).

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        Lower and upper bounds [1], one per level.
    """
    levels = np.asarray(pga_levels_g, float) * G
    if "probability_lower" not in frag:
        return np.full(levels.shape, np.nan), np.full(levels.shape, np.nan)
    grid = np.log(frag["im_level"].values)
    cell = frag.sel(state=state, column=column, model=model)
    return tuple(np.interp(np.log(levels), grid, cell[name].values, left=np.nan, right=np.nan)
                 for name in ("probability_lower", "probability_upper"))


def simulated_pga_range(results, column, model):
    """Weakest and strongest PGA [m/s^2] of the valid runs of a column and model."""
    one = results.sel(column=column, model=model)
    pga = F.intensity(one, "pga").where(F._valid(one))
    return float(pga.min()), float(pga.max())


def extrapolation(median, pga_range):
    """``"above"`` or ``"below"`` when a median [m/s^2] lies outside the PGA range simulated, else ``""``."""
    lo, hi = pga_range
    if not np.isfinite(median):
        return ""
    return "above" if median > hi else "below" if median < lo else ""


def model_comparison(results, frag, pga_levels_g=DEFAULT_PGA_LEVELS_G):
    """Where and by how much the 2D analysis is unconservative, per column.

    Returns
    -------
    list of dict
        Per column: medians [m/s^2] of both models and their ratio 2D/3D,
        probabilities of overturning at ``pga_levels_g`` for both, and from the
        runs themselves (no fit) the fraction that overturned per scale stripe
        for both models and the largest shortfall of 2D (3D fraction minus 2D
        fraction) with its stripe.
    """
    pair = planar_pair([str(m) for m in frag["model"].values])
    if pair is None:  # the 3D model and its planar counterpart are compared, or nothing
        return []
    spatial, planar = pair
    probs = overturning_probabilities(frag, pga_levels_g)
    rows = []
    for c in frag["column"].values:
        c = str(c)
        cell = frag.sel(state="overturning", column=c)
        m3, m2 = float(cell["median"].sel(model=spatial)), float(cell["median"].sel(model=planar))
        f3 = cell["stripe_fraction"].sel(model=spatial).values
        f2 = cell["stripe_fraction"].sel(model=planar).values
        gap = f3 - f2
        worst = int(np.nanargmax(gap)) if np.any(np.isfinite(gap)) else 0
        rows.append({
            "column": c,
            "median_3d": m3,
            "median_2d": m2,
            "extrapolated_3d": extrapolation(m3, simulated_pga_range(results, c, spatial)),
            "extrapolated_2d": extrapolation(m2, simulated_pga_range(results, c, planar)),
            "ratio": m2 / m3 if (np.isfinite(m2) and np.isfinite(m3) and m3 > 0) else math.nan,
            "p3d": probs[(c, spatial)],
            "p2d": probs[(c, planar)],
            "stripe_scale": frag["scale"].values,
            "stripe_im": frag["stripe_im"].values,
            "fraction_3d": f3,
            "fraction_2d": f2,
            "worst_stripe": worst,
            "worst_gap": float(gap[worst]) if np.isfinite(gap[worst]) else math.nan,
            "stripes_2d_lower": int(np.sum(gap > 0)),
            "stripes_2d_higher": int(np.sum(gap < 0)),
        })
    return rows


def summary_rows(results, frag, pga_levels_g=DEFAULT_PGA_LEVELS_G):
    """Rows of ``summary.csv``: one per column and model, SI units and g, with fitted values.

    Besides the fit: diameters beside radii, the number of records and whether
    they are too few (< :data:`MIN_RECORDS`), the PGA range simulated and
    whether the median lies outside it (``median_extrapolated``: ``above``,
    ``below`` or empty), and bootstrap bounds of every stated probability.
    """
    probs = overturning_probabilities(frag, pga_levels_g)
    rows = []
    failed = ~F._valid(results) & (F.counted(results) > 0)  # a repeated run (angles, perfect drums' seeds) once
    seeds = RS.seed_spread(results) if RS.seeded_models(results) else None
    colonnades = bool(RC.colonnade_cells(results))

    def coord(name, c, factor=1.0):
        return float(frag[name].sel(column=c)) * factor if name in frag.coords else ""

    for c in frag["column"].values:
        for m in frag["model"].values:
            c, m = str(c), str(m)
            over = frag.sel(state="overturning", column=c, model=m)
            lo_pga, hi_pga = simulated_pga_range(results, c, m)
            n_records = int(frag["n_records"].sel(column=c, model=m))
            row = {
                "column": c,
                "model": m,
                "R_m": coord("column_R", c),
                "r_m": coord("column_r", c),
                "D_base_m": coord("column_R", c, 2.0),
                "D_top_m": coord("column_r", c, 2.0),
                "h_m": coord("column_h", c),
                "slenderness_h_over_R": coord("slenderness", c),
                "conicity_r_over_R": coord("column_beta", c),
                "theta_crit_deg": coord("theta_crit", c, 180.0 / math.pi),
                "latitude": coord("latitude", c),
                "longitude": coord("longitude", c),
                "records": n_records,
                "too_few_records": n_records < MIN_RECORDS,
                "runs": int(over["n_runs"]),
                "runs_overturned": int(over["n_exceed"]),
                "fraction_overturned": int(over["n_exceed"]) / int(over["n_runs"]) if int(over["n_runs"]) else "",
                "failed_runs_excluded": int(failed.sel(column=c, model=m).sum()),
                "pga_simulated_min_g": lo_pga / G,
                "pga_simulated_max_g": hi_pga / G,
                "fit_status": F.FIT_STATUS[int(over["fit_status"])],
                "median_pga_overturning_m_s2": float(over["median"]),
                "median_pga_overturning_g": float(over["median"]) / G,
                "median_extrapolated": extrapolation(float(over["median"]), (lo_pga, hi_pga)),
                "beta_overturning": float(over["beta"]),
            }
            if "median_lower" in frag:
                row.update({
                    "median_pga_overturning_lower_m_s2": float(over["median_lower"]),
                    "median_pga_overturning_upper_m_s2": float(over["median_upper"]),
                    "beta_overturning_lower": float(over["beta_lower"]),
                    "beta_overturning_upper": float(over["beta_upper"]),
                })
            lower, upper = probability_bounds(frag, c, m, pga_levels_g)
            for level, p, a, b in zip(pga_levels_g, probs[(c, m)], lower, upper):
                row[f"p_overturning_at_{level:g}g"] = float(p)
                if "probability_lower" in frag:
                    row[f"p_overturning_at_{level:g}g_lower"] = float(a)
                    row[f"p_overturning_at_{level:g}g_upper"] = float(b)
            for state in frag["state"].values[1:]:
                cell = frag.sel(state=state, column=c, model=m)
                row[f"median_pga_{state}_m_s2"] = float(cell["median"])
                row[f"beta_{state}"] = float(cell["beta"])
            if colonnades:  # what fell first, what the standing ones kept (report_colonnade)
                row.update(RC.colonnade_columns(results, c, m))
            if seeds is not None:  # do the seeds of imperfect drums agree (report_seeds)
                row.update(RS.seed_columns(seeds, c, m))
            rows.append(row)
    return rows


def _atomic_text(path, **open_kwargs):
    """Open ``path`` for writing text under a temporary name; renamed on success, removed on failure."""
    return atomic_open(path, "w", encoding="utf-8", **open_kwargs)


def _write_csv(rows, path):
    with _atomic_text(path, newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        for row in rows:
            writer.writerow({k: _csv_value(v) for k, v in row.items()})


def _csv_value(value):
    """A CSV cell: floats to :data:`CSV_DIGITS` significant digits, NaN empty, flags as true/false."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return f"{value:.{CSV_DIGITS}g}" if math.isfinite(value) else ""
    return value


def _write_geojson(rows, path):
    features = []
    for row in rows:
        if row["latitude"] == "" or not np.isfinite(row["latitude"]):
            continue
        props = {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in row.items()
                 if k not in ("latitude", "longitude")}
        features.append({"type": "Feature",
                         "geometry": {"type": "Point", "coordinates": [row["longitude"], row["latitude"]]},
                         "properties": props})
    if not features:
        return None
    with _atomic_text(path) as fh:
        json.dump({"type": "FeatureCollection", "generator": mark_text(), "features": features}, fh, indent=1)
    return path


CAPTIONS = (
    ("median_model_vs_model", "Median PGA of overturning of every model with its bootstrap band over records; the "
     "reference model first, its band shaded across the panel."),
    ("fragility_overturning", "Probability of overturning against PGA. Lines: fitted curves; markers: the fraction "
     "of runs that overturned at each intensity; shading: the uncertainty that comes from the choice of records."),
    ("fragility_states", "Probability of reaching each damage state: the peak tilt reaching a quarter, half or all "
     "of the tipping angle theta_crit, and overturning."),
    ("fragility_all_columns", "The overturning curves of all columns side by side."),
    ("median_by_angle", "Median PGA of overturning of each column fitted at each incidence angle on its own, with "
     "its bootstrap band over the records: a colonnade weaker across its row than along it stands lower at 90 deg."),
    ("median_pga_grid", "Median PGA of overturning (50 % chance) for each column shape; higher means the column "
     "needs stronger shaking to fall."),
    ("probability_grid", "Probability of overturning at one stated PGA for each column shape."),
    ("median_ratio_2d_3d_grid", "How many times stronger the shaking must be in the 2D analysis than in the 3D one "
     "for the same 50 % chance of overturning; above 1 the 2D analysis is unconservative."),
    ("geometry_map", "Probability of overturning at one stated PGA, by slenderness and conicity of the columns."),
    ("ida", "Each line follows one record as it is scaled up: the peak tilt as a fraction of the tipping angle; "
     "crosses mark runs in which the column fell."),
    ("angle_polar", "2D analysis: the share of records that topple the column for each direction of shaking "
     "(solid)."),
    ("median_2d_vs_3d", "Each point is a column: above the dashed line the 2D analysis needs stronger shaking than "
     "the 3D one to topple it (unconservative)."),
    ("risk_", "Risk at the site. Top: how often shaking exceeds each PGA there (the hazard curve, dots as read, "
     "dotted where extended beyond them). Middle: the probability of overturning at each PGA. Bottom: their "
     "product, which shows the shaking levels that carry the risk; its area is the yearly rate of overturning."),
    ("trajectories", "Paths on the ground of chosen runs: the contact point on the rim (blue) and the centre of the "
     "base (orange). Planar rocking would draw a straight line; the rolling (wobbling) column circles."),
)


#: What a figure's caption adds when the study ran a model of a kind: (figure prefix, what the
#: model is, an attribute of its registry entry) -> words.
CAPTION_MODEL_NOTES = {
    ("fragility_states", "drums"): "; for columns of drums, also the residual slip of a joint reaching a "
    "fraction of its diameter.",
    ("angle_polar", "angle_invariant"): "; dotted rings: the 3D model, which does not depend on the direction.",
}


def _options(results):
    """The model options the study runner recorded (JSON), or none."""
    try:
        return json.loads(results.attrs.get("model_options", "{}"))
    except (TypeError, ValueError):
        return {}


def _values(results, name):
    return [str(v) for v in np.asarray(results[name].values).ravel()] if name in results.variables else []


def write_report(results, out_dir, pga_levels_g=DEFAULT_PGA_LEVELS_G, states=F.DEFAULT_STATES, bootstrap=200,
                 seed=0, confidence=F.DEFAULT_CONFIDENCE, title=None, trajectories=None, notes=None, focus=None,
                 stripe_tables_max=4, hazard=None, years=50.0, reference=None, undecided=F.DEFAULT_UNDECIDED):
    """Write the report folder of a study.

    Parameters
    ----------
    results : xarray.Dataset
        Study results (see :func:`pipeline.fragility.open_results`); must
        carry ``pga``.
    out_dir : str or os.PathLike
        Folder to write (created). Written atomically: every file is made in
        a temporary folder beside it and moved in only when all are written
        (:func:`pipeline.atomic.atomic_folder`), so a failure leaves nothing
        half-written; other files already in the folder are kept.
    pga_levels_g : sequence of float
        PGA levels [g] at which the probability of overturning is stated.
    states, bootstrap, seed, confidence
        Passed to :func:`pipeline.fragility.fragility`.
    title : str, optional
        Report title (default: the study's title).
    trajectories : list of (label, xarray.Dataset), optional
        Histories of chosen runs to draw as contact-point paths.
    notes : str, optional
        Extra Markdown inserted after the summary (e.g. what the study asks).
    focus : str, optional
        Column drawn in the single-column figures (default: the first).
    stripe_tables_max : int
        Per-stripe 2D/3D tables are written for at most this many columns
        (the bullet list covers every column).
    hazard : pipeline.risk.HazardCurve, optional
        A PGA hazard curve of the site(s): the report adds "Risk at the site" (the chance of
        overturning in ``years``, :func:`pipeline.risk.site_risk`), ``risk.nc``, ``risk.csv`` and
        a figure of the risk integrand.
    years : float
        Period of the probability stated with ``hazard`` [yr].
    reference : str, optional
        With several models, the one every other is compared with ("Model against model",
        ``comparison.csv``, ``comparison.nc``; :func:`pipeline.comparison.compare_models`);
        default the study's first model.
    undecided : str
        How runs still able to fall at their settle limit count in every fit, count and comparison
        (:func:`pipeline.fragility.resolve_undecided`); the report also states what the other way moves.

    Returns
    -------
    dict
        Paths written (``report``, ``csv``, ``geojson`` or None,
        ``fragility``, ``figures``) and the fragility Dataset (``frag``).
    """
    dest = os.fspath(out_dir)
    with atomic_folder(dest) as tmp:
        out = _write_report_into(F.resolve_undecided(results, undecided), tmp, pga_levels_g, states, bootstrap, seed,
                                 confidence, title, trajectories, notes, focus, stripe_tables_max, hazard, years,
                                 reference)

    def moved(path):
        return None if path is None else os.path.join(dest, os.path.relpath(path, tmp))

    return {k: ([moved(p) for p in v] if k == "figures" else v if k in ("frag", "risk", "comparison") else moved(v))
            for k, v in out.items()}


def _write_report_into(results, out_dir, pga_levels_g, states, bootstrap, seed, confidence, title, trajectories, notes,
                       focus, stripe_tables_max, hazard=None, years=50.0, reference=None):
    """:func:`write_report` into ``out_dir`` (a temporary folder); returns what it wrote there."""
    out_dir = os.fspath(out_dir)
    results = F._normalise(results, F._where(results))
    if "pga" not in results.variables:
        raise InputError(f"{F._where(results)}: the report states probabilities at PGA levels but the dataset "
                         "has no 'pga'; re-run the study with a runner that writes it")
    valid = F._valid(results)
    if not bool(valid.any()):  # nothing to fit or draw: say so, not a plotting library's error
        raise InputError(f"{F._where(results)}: every one of its {int(valid.size)} simulations failed (status 1), "
                         "so there is nothing to report; see why in the messages of 'frustum study run', fix the "
                         "study and run it again")
    RC.check_labels(results)  # the bodies that fell first, read before anything is fitted
    os.makedirs(os.path.join(out_dir, "figures"), exist_ok=True)
    frag = F.fragility(results, im="pga", states=states, bootstrap=bootstrap, seed=seed, confidence=confidence)
    frag_path = F.write(frag, os.path.join(out_dir, "fragility.nc"))
    figs = []
    fig_dir = os.path.join(out_dir, "figures")
    columns = [str(c) for c in frag["column"].values]
    models = [str(m) for m in frag["model"].values]
    if focus is not None:
        if focus not in columns:
            raise InputError(f"focus column {focus!r} is not in the results; columns: {', '.join(columns)}")
        columns = [focus] + [c for c in columns if c != focus]
    grid_like = "slenderness" in frag.coords and "column_beta" in frag.coords and len(columns) >= 4

    # figures
    figs += P.plot_fragility(frag, os.path.join(fig_dir, "fragility_overturning"), column=columns[0],
                             states=["overturning"],
                             title=f"Probability of overturning, column '{columns[0]}'")[:1]
    for c in columns[:1] if grid_like else columns:
        figs += P.plot_fragility(frag, os.path.join(fig_dir, f"fragility_states_{c}"), column=c,
                                 models=[models[0]],
                                 title=f"Damage states of column '{c}', {models[0].upper()} model")[:1]
    if len(columns) > 1 and not grid_like:
        figs += _overturning_all_columns(frag, os.path.join(fig_dir, "fragility_all_columns"))[:1]
    if grid_like:
        for m in models:
            med = frag["median"].sel(state="overturning", model=m).values / G
            figs += P.plot_column_grid(
                frag, med, os.path.join(fig_dir, f"median_pga_grid_{m}"), "median PGA of overturning [g]",
                f"{MD.results_title(results, m)}: median PGA of overturning [g] (n/a: none overturned up to "
                f"{_fmt(float(results['pga'].max()) / G)} g)", cmap="viridis_r")[:1]
            level = _informative_level(frag, pga_levels_g)
            p = overturning_probabilities(frag, (level,))
            figs += P.plot_column_grid(
                frag, [p[(c, m)][0] for c in frag["column"].values],
                os.path.join(fig_dir, f"probability_grid_{m}"), "probability of overturning [1]",
                f"{MD.results_title(results, m)}: probability of overturning at PGA = {level:g} g "
                f"({_fmt(level * G)} m/s²)", vmin=0, vmax=1)[:1]
        pair = planar_pair(models)
        if pair is not None:
            ratio = (frag["median"].sel(state="overturning", model=pair[1])
                     / frag["median"].sel(state="overturning", model=pair[0])).values
            figs += P.plot_column_grid(
                frag, ratio, os.path.join(fig_dir, "median_ratio_2d_3d_grid"), "median PGA 2D / median PGA 3D [1]",
                "Median PGA of overturning, 2D over 3D (> 1: 2D unconservative)", cmap="magma_r", fmt="{:.2f}")[:1]
    elif len(columns) > 2 and "slenderness" in frag.coords and len(np.unique(frag["slenderness"].values)) > 2:
        level = _informative_level(frag, pga_levels_g) * G
        for m in models:
            figs += P.plot_geometry_map(frag, os.path.join(fig_dir, f"geometry_map_{m}"), level, model=m)[:1]
    for m in models:
        view = F.ida(results, im="pga", model=m, column=columns[0])
        figs += P.plot_ida(view, os.path.join(fig_dir, f"ida_{columns[0]}_{m}"),
                           title=f"IDA, column '{columns[0]}', {m.upper()} model"
                           + ("" if MD.flag(results, m, "angle_invariant") else " (largest over incidence angles)"))[:1]
    planar = [m for m in models if MD.flag(results, m, "planar")]
    if planar and results.sizes["angle"] > 1:
        figs += P.plot_angle_polar(results, os.path.join(fig_dir, f"angle_polar_{columns[0]}"), columns[0],
                                   model=planar[0])[:1]
    by_angle = A.fragility_by_angle(results, bootstrap=bootstrap, seed=seed, confidence=confidence)
    if by_angle is not None:
        figs += A.plot_angle_medians(by_angle, os.path.join(fig_dir, "median_by_angle"))[:1]
    comparison = model_comparison(results, frag, pga_levels_g)
    if comparison:
        figs += P.plot_model_comparison(frag, os.path.join(fig_dir, "median_2d_vs_3d"))[:1]
    versus = versus_path = versus_csv = None
    if len(models) > 1:
        versus = C.compare_models(results, frag, reference=reference)
        versus_path = write_netcdf(versus, os.path.join(out_dir, "comparison.nc"))
        versus_csv = os.path.join(out_dir, "comparison.csv")
        _write_csv(C.comparison_rows(versus), versus_csv)
        figs += P.plot_model_medians(versus, os.path.join(fig_dir, "median_model_vs_model"))[:1]
    if trajectories:
        figs += P.plot_trajectories(trajectories, os.path.join(fig_dir, "trajectories"),
                                    title="Paths on the ground of chosen runs")[:1]

    risk = risk_path = risk_csv = None
    if hazard is not None:
        from pipeline import risk as R
        from pipeline.plotting_risk import plot_risk_stem

        risk = R.site_risk(frag, hazard, years=years)
        risk_path = R.write(risk, os.path.join(out_dir, "risk.nc"))
        risk_csv = R.write_csv(risk, os.path.join(out_dir, "risk.csv"))
        site = str(risk["site"].values[0])
        figs += plot_risk_stem(risk, os.path.join(fig_dir, f"risk_{columns[0]}"), site=site, column=columns[0],
                               title=f"Risk of overturning of column '{columns[0]}' at site {site}: hazard curve, "
                               "fragility and risk integrand")[:1]

    rows = summary_rows(results, frag, pga_levels_g)
    csv_path = os.path.join(out_dir, "summary.csv")
    _write_csv(rows, csv_path)
    geo_path = _write_geojson(rows, os.path.join(out_dir, "columns.geojson"))
    args = (results, frag, rows, comparison, pga_levels_g, figs, out_dir, title, notes, geo_path, stripe_tables_max,
            by_angle)
    md_path = os.path.join(out_dir, "report.md")
    with _atomic_text(md_path) as fh:
        fh.write(_markdown(*args, risk=(risk, hazard), versus=versus) + f"\n<!-- {mark_text()} -->\n")
    html_path = os.path.join(out_dir, "report.html")
    with _atomic_text(html_path) as fh:
        fh.write(_html(_markdown(*args, image=_data_uri, risk=(risk, hazard), versus=versus),
                       title or results.attrs.get("title", "Study report")))
    out = {"report": md_path, "html": html_path, "csv": csv_path, "geojson": geo_path, "fragility": frag_path,
           "figures": figs, "frag": frag}
    if risk is not None:
        out.update(risk_nc=risk_path, risk_csv=risk_csv, risk=risk)
    if versus is not None:
        out.update(comparison_nc=versus_path, comparison_csv=versus_csv, comparison=versus)
    return out


def _data_uri(path):
    """A figure file as a ``data:`` URI (base64), so that the HTML report needs no other file."""
    import base64
    import mimetypes

    kind = mimetypes.guess_type(path)[0] or "application/octet-stream"
    with open(path, "rb") as fh:
        return f"data:{kind};base64,{base64.b64encode(fh.read()).decode('ascii')}"


_HTML_STYLE = """body{font-family:sans-serif;max-width:75em;margin:2em auto;padding:0 1em;line-height:1.4}
table{border-collapse:collapse;margin:1em 0;font-size:90%}th,td{border:1px solid #bbb;padding:.25em .5em}
th{background:#eee}img{max-width:100%}code{background:#f4f4f4}"""


def _html(markdown_text, title):
    """One self-contained HTML page from the report's Markdown (markdown-it-py, tables enabled)."""
    import html

    from markdown_it import MarkdownIt

    body = MarkdownIt("commonmark").enable("table").render(markdown_text)
    return (f"<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<meta name=\"generator\" content=\"{html.escape(mark_text())}\">\n"
            f"<title>{html.escape(title)}</title>\n<style>{_HTML_STYLE}</style>\n</head>\n<body>\n{body}</body>\n"
            "</html>\n")


def _informative_level(frag, pga_levels_g):
    """The stated PGA level [g] nearest (in log) the geometric mean of the fitted medians of overturning."""
    med = frag["median"].sel(state="overturning").values.ravel() / G
    med = med[np.isfinite(med) & (med > 0)]
    if med.size == 0:
        return pga_levels_g[len(pga_levels_g) // 2]
    target = math.exp(np.mean(np.log(med)))
    return min(pga_levels_g, key=lambda lv: abs(math.log(lv / target)))


def _overturning_all_columns(frag, stem):
    import matplotlib.pyplot as plt

    factor, xlabel, secondary = P.im_axis("pga", frag["median"].attrs.get("units", "m s-2"))
    grid = frag["im_level"].values * factor
    fig, ax = plt.subplots(figsize=(8.5, 5.5), constrained_layout=True)
    for i, c in enumerate(frag["column"].values):
        for m in frag["model"].values:
            cell = frag.sel(state="overturning", column=c, model=m)
            ax.plot(grid, cell["probability"].values, color=f"C{i}", ls=MD.style(MD.base_of(frag, str(m)))["ls"], lw=1.5,
                    label=f"{c}, {str(m).upper()} (h/R = {float(frag['slenderness'].sel(column=c)):.3g})"
                    if "slenderness" in frag.coords else f"{c}, {m}")
    ax.set_xscale("log")
    P._plain_log(ax.xaxis)
    ax.set_xlabel(xlabel)
    P._secondary(ax, secondary)
    ax.set_ylabel("probability of overturning [1]")
    ax.set_ylim(-0.02, 1.02)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small", loc="upper left")
    ax.set_title("Probability of overturning of every column (lognormal fits; solid 3D, dashed 2D)",
                 fontsize="medium")
    return P._save(fig, stem)


def _extrapolated_mark(where):
    """`` (extrapolated)`` after a median that lies outside the PGA range simulated."""
    return " (extrapolated)" if where else ""


def _caveats(rows):
    """Markdown lines that say where the data do not support a fitted number."""
    lines = []
    few = sorted({(r["column"], r["records"]) for r in rows if r["too_few_records"]})
    if few:
        lines.append(f"**Too few records for a fragility:** {', '.join(f'{c!r} ({n})' for c, n in few)} "
                     f"{'has' if len(few) == 1 else 'have'} fewer than {MIN_RECORDS} records with valid runs. A "
                     "lognormal curve fitted to so few records (and its bootstrap bounds, which resample them) "
                     f"describes these records, not earthquakes in general; use at least {MIN_RECORDS}.")
        lines.append("")
    for r in rows:
        if r["fit_status"] == "no_exceedance_observed":
            lines.append(f"- '{r['column']}' ({r['model'].upper()}): no run overturned, up to a PGA of "
                         f"{_fmt(r['pga_simulated_max_g'])} g: its median PGA of overturning lies above that, by an "
                         "amount these runs cannot tell.")
        if r["median_extrapolated"]:
            side = ("beyond the strongest shaking simulated" if r["median_extrapolated"] == "above"
                    else "below the weakest shaking simulated")
            edge = r["pga_simulated_max_g"] if r["median_extrapolated"] == "above" else r["pga_simulated_min_g"]
            lines.append(f"- **Extrapolated:** the median PGA of overturning of '{r['column']}' "
                         f"({r['model'].upper()}), {_fmt(r['median_pga_overturning_g'])} g, lies {side} "
                         f"({_fmt(edge)} g): there the curve is the lognormal assumption, not the runs.")
    if any(r["median_extrapolated"] or r["fit_status"] == "no_exceedance_observed" for r in rows):
        lines.append("")
    return lines


def _markdown(results, frag, rows, comparison, pga_levels_g, figs, out_dir, title, notes, geo_path,
              stripe_tables_max=4, by_angle=None, image=None, risk=(None, None), versus=None):
    """The report as Markdown; ``image(path)`` gives a figure's link (default: its path relative to the report)."""
    image = image or (lambda path: os.path.relpath(path, out_dir))
    n = results.sizes
    models = [str(m) for m in frag["model"].values]
    records = _values(results, "record")
    quakes = sorted(set(_values(results, "earthquake"))) if "earthquake" in results.variables else []
    once = F.counted(results) > 0  # runs as the fits count them: a repeat (angle-invariant, perfect seeds) once
    n_total = int(once.sum())
    n_failed = int((~F._ok(results) & once).sum())
    lines = [f"# {title or results.attrs.get('title', 'Study report')}", ""]
    if results.attrs.get("summary"):
        lines += [str(results.attrs["summary"]), ""]
    if notes:
        lines += [notes, ""]
    lines += ["## What was simulated", ""]
    lines += [f"- **{n['column']} column(s)**:", "",
              "| column | base diameter [m] | top diameter [m] | R [m] | r [m] | h [m] | h/R | r/R | theta_crit [deg] |",
              "|---|---|---|---|---|---|---|---|---|"]
    for c in frag["column"].values:
        get = lambda name: float(frag[name].sel(column=c)) if name in frag.coords else math.nan  # noqa: E731
        lines.append(f"| {c} | {_fmt(2 * get('column_R'), 4)} | {_fmt(2 * get('column_r'), 4)} | "
                     f"{_fmt(get('column_R'), 4)} | {_fmt(get('column_r'), 4)} | {_fmt(get('column_h'), 4)} | "
                     f"{_fmt(get('slenderness'))} | {_fmt(get('column_beta'))} | "
                     f"{_fmt(math.degrees(get('theta_crit')))} |")
    lines.append("")
    if "structure" in results.coords:  # drums, capitals, colonnades: what the dimensions above do not say
        lines += [f"- **{c}**: {results['structure'].sel(column=c).item()}." for c in frag["column"].values] + [""]
        if _has_epistyle(results):
            lines += ["A colonnade's columns stand in a straight row; their capitals carry an epistyle of blocks "
                      "laid from axis to axis, each resting on its capitals through rectangular joints and "
                      "pressing on its neighbours through vertical head joints. The incidence angle is measured "
                      "from the row (0: along it, in the frame's plane; 90: across it). A run overturns when any "
                      "body (drum, capital or epistyle block) lies down or falls off the body it rests on; "
                      "`epistyle_slip` is the largest slip of an epistyle block on its capitals at the end, "
                      "`epistyle_opening` the widest opening between blocks.", ""]
    lines.append(f"- **{n['record']} earthquake record(s)**" +
                 (f" from {len(quakes)} earthquake(s): {', '.join(quakes)}" if quakes else "") +
                 (f" (ids {records[0]} ... {records[-1]})" if len(records) > 1 else f" ({records[0]})") + ".")
    angles = results["angle"].values
    invariant = [m.upper() for m in models if MD.flag(results, m, "angle_invariant")]
    lines.append(f"- **{n['angle']} incidence angle(s)**: {', '.join(_fmt(a) for a in angles)} deg "
                 "(the direction in which the record hits the column" +
                 (f"; the {' and '.join(invariant)} results do not depend on it" if invariant else "") + ").")
    scale_units = results["scale"].attrs.get("units", "1")
    scale_text = ", ".join(_fmt(s) for s in results["scale"].values)
    if scale_units in ("1", ""):
        stripes = f"records scaled by {scale_text}"
    elif scale_units == "m s-2":
        stripes = ("every record scaled to the same PGA, " +
                   ", ".join(_fmt(v / G) for v in results["scale"].values) + " g (" + scale_text + " m/s²)")
    else:
        stripes = f"records scaled to {scale_text} {scale_units}"
    lines.append(f"- **{n['scale']} intensity stripe(s)**: {stripes}.")
    pga = results["pga"]
    lines.append(f"- PGA (peak ground acceleration of the scaled record) ranges from {_g_and_ms2(float(pga.min()))} "
                 f"to {_g_and_ms2(float(pga.max()))}.")
    lines.append(f"- **Model(s)**: {', '.join(f'{MD.results_title(results, m)} (`{m}`)' for m in models)}.")
    if "bed_damping" in results.variables:  # [calibration] bed: one bed for every model
        lines.append("- **One bed for every model**: " + "; ".join(
            f"'{c}': dashpots {_fmt(float(results['bed_damping'].sel(column=c)), 4)} Pa s/m, restitution "
            f"{_fmt(float(results['bed_restitution'].sel(column=c)), 4)}" for c in results["column"].values)
            + f" ({results['bed_damping'].attrs.get('comment', 'calibrated')}; the restitution they reach is "
            "given to every model).")
    lines.append(f"- {n_total} simulations in the dataset, {n_failed} failed and left out.")
    lines += undecided_lines(results, _options(results).get("settle_limit"))
    lines += RS.imperfection_lines(results, _fmt)
    for flag in ("sliding_onset", "lift_off"):  # each model says what its flag counts (its registry entry)
        if flag in results.variables:
            for m in models:
                ok = (F._valid(results) & once).sel(model=m)  # a repeated run once
                count = int(((results[flag].sel(model=m) > 0) & ok).sum())
                lines.append(f"- {m.upper()}: in {count} of {int(ok.sum())} runs {getattr(MD.describe(MD.base_of(results, m)), flag)}.")
    lines += ["", "## Assumptions of the models" if len(models) > 1 else "## Assumptions of the model", ""]
    options = _options(results)
    bases = list(dict.fromkeys(MD.base_of(results, m) for m in models))
    lines.append(assumptions([m for m in bases if m in MD.REGISTRY],
                             vertical=results.attrs.get("vertical_component", "used") != "ignored", options=options,
                             one_component="x component" in str(results.attrs.get("horizontal_components", ""))))
    for m in (m for m in bases if m not in MD.REGISTRY):  # e.g. a peer engine's cells, merged in
        said = str(results["model_description"].sel(model=m).values) if "model_description" in results.coords else ""
        lines.append(f"- **{m}** (`{m}`): {said or 'a model this pipeline does not know (no description)'}.")
    variants = [m for m in models if MD.base_of(results, m) != m]
    if variants:
        lines += ["- Variants of these models run by the study, under names of their own: "
                  + "; ".join(f"`{m}`: `{MD.base_of(results, m)}`"
                              + (f" with {MD.variant_text(results, m)}" if MD.variant_text(results, m) else "")
                              for m in variants) + ".", ""]

    lines += ["## Probability of overturning", ""]
    lines.append("Fitted lognormal fragility curves (maximum likelihood, Baker 2015) give the probability that "
                 "the column overturns when the ground shakes with a given PGA. "
                 f"Bounds are {100 * frag.attrs['confidence_level']:g} % bootstrap intervals over the records "
                 f"({frag.attrs['bootstrap_replicates']} replicates).")
    lines.append("")
    head = "| column | model | " + " | ".join(f"P at {lv:g} g ({_fmt(lv * G)} m/s²)" for lv in pga_levels_g) + \
        " | median PGA [g] | median PGA [m/s²] | dispersion beta | overturned / runs | records |"
    lines += [head, "|" + "---|" * (head.count("|") - 1)]
    for row in rows:
        probs = [_pct_bounds(row[f"p_overturning_at_{lv:g}g"], row.get(f"p_overturning_at_{lv:g}g_lower", math.nan),
                             row.get(f"p_overturning_at_{lv:g}g_upper", math.nan)) for lv in pga_levels_g]
        bounds = ""
        if "median_pga_overturning_lower_m_s2" in row:
            bounds = f" ({_fmt(row['median_pga_overturning_lower_m_s2'] / G)} to " \
                     f"{_fmt(row['median_pga_overturning_upper_m_s2'] / G)})"
        status = row["fit_status"]
        med_g = _fmt(row["median_pga_overturning_g"]) + bounds if status in ("ok", "perfectly_separated") \
            else status.replace("_", " ")
        med_g += _extrapolated_mark(row["median_extrapolated"])
        records = f"{row['records']}" + (" (too few)" if row["too_few_records"] else "")
        lines.append(f"| {row['column']} | {row['model'].upper()} | " + " | ".join(probs) +
                     f" | {med_g} | {_fmt(row['median_pga_overturning_m_s2'])} | {_fmt(row['beta_overturning'])} | "
                     f"{row['runs_overturned']} / {row['runs']} | {records} |")
    lines.append("")
    lines.append("Probabilities are followed by their bootstrap bounds where a bootstrap was run. "
                 "*n/a*: no fit (see `fit_status` in `summary.csv`: e.g. no run overturned, so the median PGA lies "
                 "above the strongest shaking simulated). A dispersion of 0 means the runs were perfectly separated "
                 "by PGA (all stood below, all overturned above): the step is placed between the two.")
    lines.append("")
    lines += _caveats(rows)
    lines += A.angle_section(results, by_angle, _fmt)
    lines += RC.dislocation_section(results, frag, _fmt)
    lines += RC.colonnade_section(results, _fmt)
    lines += RS.seeds_section(results, _fmt)
    if risk[0] is not None:
        lines += risk_section(risk[0], risk[1], frag, _fmt)

    targets = F.in_stripes(results)  # every record scaled to the stripe's PGA
    if comparison:
        lines += ["## 2D against 3D", ""]
        lines.append("A 2D (planar rocking) analysis is *unconservative* where it predicts a lower probability of "
                     "overturning than the 3D model, i.e. a higher median PGA. The numbers below are read from the "
                     "dataset: first from the fitted curves, then directly as fractions of runs that overturned.")
        lines.append("")
        ratios = np.array([r["ratio"] for r in comparison])
        finite = np.isfinite(ratios)
        if finite.any():
            lo, hi = int(np.nanargmin(ratios)), int(np.nanargmax(ratios))
            extrapolated = [r["column"] for r in comparison if r["extrapolated_3d"] or r["extrapolated_2d"]]
            lines.append(f"**In short:** 2D is unconservative for {int(np.sum(ratios[finite] > 1))} of "
                         f"{len(comparison)} column(s): its median PGA of overturning is {_fmt(ratios[lo])} "
                         f"('{comparison[lo]['column']}') to {_fmt(ratios[hi])} ('{comparison[hi]['column']}') times "
                         "the 3D one." + (
                             f" For {', '.join(repr(c) for c in extrapolated)} a median is *extrapolated* beyond the "
                             "shaking simulated, so that ratio rests on the lognormal assumption, not on runs."
                             if extrapolated else ""))
            lines.append("")
        lines.append("Note: PGA here is the peak of the horizontal acceleration vector of the record. The 2D model "
                     "feels only the component along the incidence angle, whose peak is at most that PGA, as in "
                     "the usual 2D analysis of one component; part of the difference comes from that, the rest "
                     "from the 3D rolling (wobbling) motion.")
        lines.append("")
        lines.append("| column | median PGA 3D [g] | median PGA 2D [g] | 2D / 3D | " +
                     " | ".join(f"P 3D / 2D at {lv:g} g" for lv in pga_levels_g) + " |")
        lines.append("|" + "---|" * (4 + len(pga_levels_g)))
        for r in comparison:
            lines.append(f"| {r['column']} | {_fmt(r['median_3d'] / G)}{_extrapolated_mark(r['extrapolated_3d'])} | "
                         f"{_fmt(r['median_2d'] / G)}{_extrapolated_mark(r['extrapolated_2d'])} | "
                         f"{_fmt(r['ratio'])} | " +
                         " | ".join(f"{_pct(a)} / {_pct(b)}" for a, b in zip(r["p3d"], r["p2d"])) + " |")
        lines.append("")
        for r in comparison:
            if np.isfinite(r["ratio"]):
                verdict = ("2D is **unconservative**: it needs a {:.0f} % stronger PGA to overturn the column half "
                           "of the time".format(100 * (r["ratio"] - 1)) if r["ratio"] > 1 else
                           "2D is conservative here: its median PGA is {:.0f} % lower".format(100 * (1 - r["ratio"])))
                marked = [label for label, key in (("3D", "extrapolated_3d"), ("2D", "extrapolated_2d")) if r[key]]
                if marked:
                    verdict += f" (the {' and '.join(marked)} median extrapolated beyond the shaking simulated)"
            else:
                verdict = "no median for one of the models (see the table above)"
            k = r["worst_stripe"]
            where = (f"at PGA {_g_and_ms2(r['stripe_im'][k])}" if targets else
                     f"at scale factor {_fmt(r['stripe_scale'][k])} (geometric-mean PGA {_g_and_ms2(r['stripe_im'][k])})")
            lines.append(f"- Column '{r['column']}': {verdict}. In {r['stripes_2d_lower']} of "
                         f"{len(r['fraction_3d'])} intensity stripes fewer runs overturn in 2D than in 3D"
                         f" (more in {r['stripes_2d_higher']}); the "
                         f"largest shortfall is {_pct(r['worst_gap'])} of the runs (3D {_pct(r['fraction_3d'][k])}, "
                         f"2D {_pct(r['fraction_2d'][k])}) {where}.")
        lines.append("")
        if len(comparison) <= stripe_tables_max:
            lines.append("Fraction of runs that overturned per stripe (records and, for 2D, angles pooled):")
            lines.append("")
        for r in comparison[:stripe_tables_max] if len(comparison) <= stripe_tables_max else []:
            if targets:
                lines.append(f"| '{r['column']}': PGA [g] | PGA [m/s²] | 3D | 2D |")
            else:
                lines.append(f"| '{r['column']}': scale factor | geometric-mean PGA [g] | 3D | 2D |")
            lines.append("|---|---|---|---|")
            for k in range(len(r["fraction_3d"])):
                first = _fmt(r['stripe_im'][k] / G) if targets else _fmt(r['stripe_scale'][k])
                second = _fmt(r['stripe_im'][k]) if targets else _fmt(r['stripe_im'][k] / G)
                lines.append(f"| {first} | {second} | {_pct(r['fraction_3d'][k])} | {_pct(r['fraction_2d'][k])} |")
            lines.append("")

    if versus is not None:
        lines += C.markdown_section(versus)
    lines += ["## Figures", ""]
    for path in figs:
        stem = os.path.splitext(os.path.basename(path))[0]
        name = stem.replace("_", " ")
        lines += [f"![{name}]({image(path)})", ""]
        caption = next((text for prefix, text in CAPTIONS if stem.startswith(prefix)), None)
        for (prefix, kind), more in CAPTION_MODEL_NOTES.items():  # only what the models run draw
            if caption and stem.startswith(prefix) and any(MD.flag(results, m, kind) for m in models):
                caption = caption[:-1] + more
        if caption:
            lines += [f"*{caption}*", ""]
    bases = list(dict.fromkeys(MD.base_of(results, m) for m in models))  # each model described once
    lines += ["## References", ""] + [f"- {MD.describe(m).reference}." for m in bases if MD.describe(m).reference]
    lines += ["- Baker J.W. (2015), Efficient analytical fragility function fitting using dynamic structural "
              "analysis data, Earthquake Spectra 31(1), 579-599 (the fit).", ""]
    lines += ["## Files", "",
              "- `report.html`: this report in one file, figures included (opens in any browser, can be mailed).",
              "- `summary.csv`: one row per column and model (dimensions, runs, medians and dispersions of every "
              "damage state, probabilities at the PGA levels above); opens in a spreadsheet.",
              "- `fragility.nc`: the fitted curves (netCDF, CF-1.10).",
              "- `figures/`: every figure as PNG and PDF."]
    if geo_path:
        lines.append("- `columns.geojson`: the columns with their coordinates and results; opens in a GIS.")
    if versus is not None:
        lines.append("- `comparison.csv`, `comparison.nc`: every model against the reference, per column (medians "
                     "and bands, cell-by-cell outcomes, peak-tilt ratios; spreadsheet and netCDF).")
    if risk[0] is not None:
        lines.append("- `risk.nc`, `risk.csv`: the risk at the site(s) of every column, model and damage state "
                     "(mean annual frequency, probability in the period, bounds; netCDF and spreadsheet).")
    lines.append("")
    source = results.attrs.get("source_file") or results.attrs.get("study_file")
    if source:
        lines.append(f"Results file: `{os.path.basename(str(source))}`"
                     + (f", study digest `{results.attrs['study_digest']}`" if "study_digest" in results.attrs else "")
                     + ".")
    lines.append("")
    return "\n".join(lines)


__all__ = ["write_report", "overturning_probabilities", "model_comparison", "summary_rows", "DEFAULT_PGA_LEVELS_G"]
