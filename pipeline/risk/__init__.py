"""Site risk: how often a column reaches a damage state at its site, from a fragility and a hazard curve.

A fragility (:mod:`pipeline.fragility`) gives P(DS | IM = a), the probability of a damage state
given the shaking. A hazard curve gives H(a), the mean annual rate at which shaking at the site
exceeds a. The mean annual frequency of the damage state is the risk integral (Cornell 1968)::

    lambda_DS = integral P(DS | a) |dH/da| da                                       [1/yr]

Functions here are pure: arrays and Datasets in, arrays and Datasets out; reading a hazard curve
is the one thing that touches a file. One job a module:

* :mod:`~pipeline.risk.hazard`: the :class:`HazardCurve`, its intensity measure and units, the curve
  as integrated (:func:`usable_curve`, :func:`hazard_rate_at`);
* :mod:`~pipeline.risk.hazard_csv`: hazard curve files, told apart by their first line
  (:func:`read_hazard_curve`): :mod:`~pipeline.risk.hazard_openquake` (the OpenQuake engine's export,
  :func:`read_openquake_csv`) and :mod:`~pipeline.risk.hazard_plain` (a two-column CSV,
  :func:`read_plain_csv`);
* :mod:`~pipeline.risk.hazard_code`: a hazard curve from code values, PGAs at return periods joined and
  extended as power laws (:func:`code_hazard_curve`);
* :mod:`~pipeline.risk.integral`: the risk integral in closed form per power-law segment
  (:func:`segment_integral`, :func:`risk_integral`) with its bounds beyond the curve's ends, and
  :func:`probability_in`, :func:`return_period`;
* :mod:`~pipeline.risk.fragility_file`: fragility files as the risk reads them (:func:`open_fragility`,
  :func:`fragility_im`, :func:`check_im`);
* :mod:`~pipeline.risk.risk_dataset`: the risk dataset of every site, damage state, column and model
  (:func:`site_risk`, ``risk_flag``), at one period or several (:func:`periods`, :func:`in_period`);
* :mod:`~pipeline.risk.files`: its netCDF and CSV (:func:`write`, :func:`write_csv`, :func:`risk_rows`);
* :mod:`~pipeline.risk.words`: the risk in words (:func:`one_in`, :func:`percent`, :func:`years_words`,
  :func:`no_risk_reason`).

Every name is importable from ``pipeline.risk`` itself.
"""

from pipeline.risk.files import CSV_DIGITS, risk_rows, write, write_csv
from pipeline.risk.fragility_file import check_im, fragility_im, open_fragility
from pipeline.risk.hazard import (LEVEL_UNITS, MAX_LEVEL, OPENQUAKE_UNITS, SI_UNITS, HazardCurve, annual_rate,
                                  describe_im, hazard_rate_at, parse_imt, usable_curve)
from pipeline.risk.hazard_code import DEFAULT_SLOPE, SLOPE_RANGE, check_slope, code_hazard_curve, parse_code_values
from pipeline.risk.hazard_csv import read_hazard_curve
from pipeline.risk.hazard_openquake import read_openquake_csv
from pipeline.risk.hazard_plain import read_plain_csv
from pipeline.risk.integral import (RISK_SHARES, RiskParts, probability_in, return_period, risk_integral,
                                    segment_integral)
from pipeline.risk.risk_dataset import (DEFAULT_YEARS, LIMITS, RISK_ALL_EXCEED, RISK_FLAGS, RISK_MEDIAN_BEYOND,
                                        RISK_NO_EXCEEDANCE, RISK_NO_FIT, RISK_OK, RISK_OVERFLOW, check_years,
                                        in_period, periods, site_risk)
from pipeline.risk.words import no_risk_reason, one_in, percent, years_words

__all__ = [
    "DEFAULT_YEARS", "HazardCurve", "RiskParts", "RISK_FLAGS", "annual_rate", "probability_in", "parse_imt",
    "read_hazard_curve", "read_openquake_csv", "read_plain_csv", "usable_curve", "segment_integral",
    "risk_integral", "hazard_rate_at", "open_fragility", "fragility_im", "check_im", "site_risk", "risk_rows", "write",
    "write_csv", "one_in", "describe_im", "percent", "years_words", "no_risk_reason", "return_period", "MAX_LEVEL",
    "OPENQUAKE_UNITS", "LEVEL_UNITS", "SI_UNITS", "RISK_OK", "RISK_MEDIAN_BEYOND", "RISK_NO_EXCEEDANCE",
    "RISK_ALL_EXCEED", "RISK_NO_FIT", "RISK_OVERFLOW", "RISK_SHARES", "LIMITS", "CSV_DIGITS",
    "code_hazard_curve", "parse_code_values", "check_slope", "DEFAULT_SLOPE", "SLOPE_RANGE", "check_years", "periods", "in_period",
]
