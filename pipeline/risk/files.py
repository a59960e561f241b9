"""The risk dataset's files: CF netCDF (:func:`write`) and the spreadsheet (:func:`risk_rows`,
:func:`write_csv`), both written atomically."""

import csv
import math
import os

from pipeline import fragility as F
from pipeline.dataset import write_netcdf
from pipeline.risk.integral import RISK_SHARES
from pipeline.risk.risk_dataset import RISK_FLAGS, in_period, periods
from pipeline.units import G


#: Significant digits of the CSV (a hazard curve and a fragility carry no more).
CSV_DIGITS = 4


def risk_rows(risk):
    """One dict per site, column, model and damage state: the spreadsheet's rows (units in the keys).

    A probability per period (``probability_in_50_yr``, ``probability_in_2100_yr``, ...); a hazard curve
    from code values adds the share of the risk below its smallest PGA, the values and where the
    curve is extrapolated.
    """
    im = risk.attrs.get("intensity_measure", "pga")
    acc = im in ("pga", "sa")
    code = risk.attrs.get("hazard_format") == "code"
    rows = []
    for site in risk["site"].values:
        for c in risk["column"].values:
            for m in risk["model"].values:
                for state in risk["state"].values:
                    cell = risk.sel(site=site, column=c, model=m, state=state)

                    def v(name, cell=cell):
                        return float(cell[name])

                    row = {"site": str(site), "site_longitude": float(cell["site_longitude"]),
                           "site_latitude": float(cell["site_latitude"]), "column": str(c), "model": str(m),
                           "state": str(state)}
                    if acc:
                        row["fragility_median_g"] = v("fragility_median") / G
                    row[f"fragility_median_{'m_s2' if acc else 'm_s'}"] = v("fragility_median")
                    row["fragility_beta"] = v("fragility_beta")
                    row["fit_status"] = F.FIT_STATUS.get(int(cell["fit_status"]), "?")
                    row["annual_frequency_per_yr"] = v("annual_frequency")
                    row["annual_frequency_lower_per_yr"] = v("annual_frequency_lower")
                    row["annual_frequency_upper_per_yr"] = v("annual_frequency_upper")
                    row["annual_frequency_band_lower_per_yr"] = v("annual_frequency_band_lower")
                    row["annual_frequency_band_upper_per_yr"] = v("annual_frequency_band_upper")
                    row["return_period_yr"] = v("return_period")
                    for years in periods(risk):
                        for name in ("", "_lower", "_upper", "_band_lower", "_band_upper"):
                            row[f"probability_in_{years:g}_yr{name}"] = in_period(cell, f"probability_in_period{name}",
                                                                                  years)
                    if code:
                        row["share_below_first_level"] = v("share_below_first_level")
                    row["share_beyond_last_level"] = v("share_beyond_last_level")
                    for share in RISK_SHARES:
                        key = f"intensity_risk_{round(100 * share):02d}"
                        row[f"{key}_{'g' if acc else 'm_s'}"] = v(key) / (G if acc else 1.0)
                    row["risk_flag"] = RISK_FLAGS[int(cell["risk_flag"])]
                    if code:
                        row["hazard_code_values"] = risk.attrs["hazard_code_values"]
                        row["hazard_extrapolated"] = risk.attrs["hazard_extrapolated"]
                    rows.append(row)
    return rows


def _csv_value(value):
    if isinstance(value, float):
        if math.isnan(value):
            return ""
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return f"{value:.{CSV_DIGITS}g}"
    return value


def write_csv(risk, path):
    """Write :func:`risk_rows` as CSV, atomically (temporary name, then rename); returns ``path``."""
    from pipeline.atomic import atomic_open

    rows = risk_rows(risk)
    path = os.fspath(path)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with atomic_open(path, "w", encoding="utf-8", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        for row in rows:
            writer.writerow({k: _csv_value(v) for k, v in row.items()})
    return path


def write(risk, path):
    """Write a risk Dataset as CF netCDF, atomically (:func:`pipeline.dataset.write_netcdf`)."""
    return write_netcdf(risk, path)
