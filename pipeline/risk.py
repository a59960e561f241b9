"""Site risk: how often a column reaches a damage state at its site, from a fragility and a hazard curve.

A fragility (:mod:`pipeline.fragility`) gives P(DS | IM = a), the probability of a damage state
given the shaking. A hazard curve gives H(a), the mean annual rate at which shaking at the site
exceeds a. The mean annual frequency of the damage state is the risk integral (Cornell 1968)::

    lambda_DS = integral P(DS | a) |dH/da| da                                       [1/yr]

Functions here are pure: arrays and Datasets in, arrays and Datasets out; reading a hazard curve
is the one thing that touches a file.

Hazard curves
-------------
:func:`read_hazard_curve` reads two formats, told apart by their first line:

* the OpenQuake engine's CSV export, exactly as ``oq export hcurves`` writes it
  (``hazard_curve-mean-PGA_<calc_id>.csv``; :func:`read_openquake_csv`): a first row holding
  the metadata as a comment (``#,,,,,"generated_by='OpenQuake engine 3.18.0', ..., kind='mean',
  investigation_time=50.0, imt='PGA'"``; older engines wrote ``# ..., investigation_time=1.0,
  imt="PGA"``), then the header ``lon,lat,depth,poe-0.1000000,...`` (a ``custom_site_id`` column
  first when the job named its sites), then one row per site. The intensity measure levels
  (IMLs) are in the column names, in g for PGA and SA(T) (cm/s for PGV), as the engine
  writes them; the values are probabilities of exceedance (PoE) in the investigation time T
  [yr], converted to annual rates by ``-ln(1 - PoE) / T`` (Poisson occurrence, the engine's
  own assumption).
* a plain two-column CSV (:func:`read_plain_csv`): a header naming the intensity measure with
  its unit and the rate, e.g. ``PGA [g],annual_rate [1/yr]`` (or ``SA(1.0) [m/s2]``, ``PGV
  [cm/s]``; the second column may instead be ``poe in 50 years``), then one row per level;
  lines starting with ``#`` are comments.

Several sites in one file give a ``site`` dimension. Every level is converted to SI on reading
(m/s^2 for PGA and Sa, m/s for PGV), the units of the fragility's medians. Refused by name: fields
separated by ``;`` or tabs, an engine export without its ``#`` metadata row, an empty column name (a
trailing comma), and a level no ground motion reaches (beyond :data:`MAX_LEVEL`, 30 g).

The integral
------------
Between its levels the hazard curve is interpolated log-log (a power law H = H_i (a/a_i)^-k_i on
each segment), and with a lognormal fragility each segment's integral has a closed form
(:func:`segment_integral`; integration by parts, then the Gaussian integral), so no quadrature
error enters. Over one segment extended from 0 to infinity it is Kennedy's closed form
``lambda = H(median) exp(k^2 beta^2 / 2)`` (Kennedy & Short 1994, Cornell et al. 2002).

Beyond the curve's last level a_L the hazard is unknown. :func:`risk_integral` returns three
numbers, so the part beyond is bounded and stated rather than silently dropped:

* ``lower``: shaking beyond a_L (rate H(a_L)) counted at P(a_L), the least probability it can
  have (P grows with a), and nothing below the first level a_0;
* ``upper``: shaking beyond a_L counted with P = 1, plus the part below a_0 as ``central``;
* ``central``: the last segment's power law extended beyond a_L, the first one's below a_0.

``central`` lies between the bounds. Where the fragility's median lies beyond a_L, most of the
risk comes from the extrapolation and the result is flagged (``risk_flag``) and warned about. Where
the first segment falls so steeply that, extended below a_0, the integral passes the largest float,
``central`` is NaN with ``risk_flag`` ``integral_overflows`` (:func:`no_risk_reason` says which
segment); ``lower`` remains.

Public functions: :func:`read_hazard_curve`, :func:`read_openquake_csv`, :func:`read_plain_csv`,
:func:`annual_rate`, :func:`segment_integral`, :func:`risk_integral`, :func:`probability_in`,
:func:`fragility_im`, :func:`check_im`, :func:`site_risk`, :func:`open_fragility`,
:func:`risk_rows`, :func:`write`, :func:`write_csv`; in words: :func:`one_in`, :func:`percent`,
:func:`years_words`, :func:`no_risk_reason`.
"""

import csv
import math
import os
import re
import warnings
from dataclasses import dataclass, field

import numpy as np
import xarray as xr
from scipy.special import log_ndtr

from pipeline import fragility as F
from pipeline.dataset import annotate, append_history, write_netcdf
from pipeline.errors import HazardWarning, InputError
from pipeline.units import G

#: Default period of the probability stated [yr].
DEFAULT_YEARS = 50.0

#: Units of the OpenQuake engine's intensity measure levels, and the factor to SI.
OPENQUAKE_UNITS = {"pga": ("g", G), "sa": ("g", G), "pgv": ("cm/s", 0.01)}

#: Units a plain CSV may give its levels in: name -> factor to SI (m/s^2 or m/s).
LEVEL_UNITS = {
    "g": G, "m/s2": 1.0, "m/s^2": 1.0, "m s-2": 1.0, "m/s²": 1.0, "cm/s2": 0.01, "cm/s^2": 0.01, "cm/s²": 0.01,
    "gal": 0.01, "m/s": 1.0, "m s-1": 1.0, "cm/s": 0.01, "cm s-1": 0.01,
}
_VELOCITY_UNITS = {"m/s", "m s-1", "cm/s", "cm s-1"}
SI_UNITS = {"pga": "m s-2", "sa": "m s-2", "pgv": "m s-1"}

#: The highest intensity level a hazard curve may hold, in SI: 30 g for PGA and Sa, 30 m/s for PGV. No
#: ground motion comes near it: the strongest PGA recorded is 4.36 g (vector sum of three components,
#: KiK-net IWTH25, 2008 Iwate-Miyagi Nairiku earthquake), the strongest PGV 3.18 m/s (1999 Chi-Chi;
#: Anderson 2010, BSSA 100(1)), and response spectra stay within some 3 times the PGA (Sa < 15 g). Hazard
#: calculations for the rarest shaking (1e-8 /yr) list levels of up to about 10 g. A level beyond the
#: bound is a slip (a level in cm/s^2 written as g, a missing decimal point), and it would make the curve
#: seem to cover shaking that never happens, narrowing the curve-end bounds to a false certainty.
MAX_LEVEL = {"pga": 30.0 * G, "sa": 30.0 * G, "pgv": 30.0}
_STRONGEST = {"pga": "PGA 4.36 g", "sa": "PGA 4.36 g", "pgv": "PGV 3.18 m/s"}

#: risk_flag values: how far a number rests on the data (CF flag_values / flag_meanings).
RISK_OK, RISK_MEDIAN_BEYOND, RISK_NO_EXCEEDANCE, RISK_ALL_EXCEED, RISK_NO_FIT, RISK_OVERFLOW = range(6)
RISK_FLAGS = {
    RISK_OK: "ok",
    RISK_MEDIAN_BEYOND: "median_beyond_hazard_curve",
    RISK_NO_EXCEEDANCE: "no_median_no_exceedance_observed",
    RISK_ALL_EXCEED: "no_median_every_run_exceeds",
    RISK_NO_FIT: "no_fit",
    RISK_OVERFLOW: "integral_overflows",
}

#: Shares of the risk at which the intensity is stated (``intensity_risk_05`` ...): 5, 50, 95 %.
RISK_SHARES = (0.05, 0.5, 0.95)

LIMITS = ("The fragility's PGA is the peak of the horizontal acceleration vector and its Sa the RotD50 of the "
          "record pair (pipeline.study.grid); a hazard curve is for the component its ground-motion models predict "
          "(often RotD50 or the geometric mean), which for PGA is lower than the vector peak by some 10-20 %: "
          "no conversion is applied, so with such a curve the risk is underestimated. Shaking beyond the "
          "curve's last level is bounded (annual_frequency_lower, annual_frequency_upper), the central value "
          "extends the curve's last segment. Occurrences are Poisson (probability in T years = "
          "1 - exp(-lambda T)); the column is assumed undamaged before each earthquake (no accumulation).")


# --------------------------------------------------------------------------- hazard curves


@dataclass(frozen=True)
class HazardCurve:
    """Hazard curves of one or more sites for one intensity measure.

    Attributes
    ----------
    im : str
        ``"pga"``, ``"sa"`` or ``"pgv"`` (the names of :mod:`pipeline.fragility`).
    period : float or None
        Period of Sa [s]; None for PGA and PGV.
    levels : numpy.ndarray
        Intensity levels, increasing, in SI: [m/s^2] for PGA and Sa, [m/s] for PGV. Shape (L,).
    rate : numpy.ndarray
        Annual rate of exceedance of each level [1/yr], shape (S, L); ``inf`` where the file
        gives a probability of exceedance of 1 (saturated), 0 where it gives 0.
    sites : tuple of str
        Site labels: the file's ``custom_site_id`` or ``site-<i>`` in row order.
    lon, lat, depth : numpy.ndarray
        Site coordinates as the file gives them ([degree_east], [degree_north], [km]); NaN in a
        plain CSV.
    investigation_time : float or None
        Investigation time of the probabilities in the file [yr]; None when it gave rates.
    poe : numpy.ndarray or None
        The file's probabilities of exceedance in ``investigation_time`` [1], shape (S, L).
    source : str
        The file read.
    format : str
        ``"openquake"`` or ``"plain"``.
    imt : str
        The intensity measure as the file names it (``"PGA"``, ``"SA(1.0)"``).
    file_units : str
        Unit of the levels in the file (``"g"``).
    kind : str
        OpenQuake's ``kind`` (``"mean"``, ``"quantile-0.5"``, ``"rlz-000"``) or ``""``.
    """

    im: str
    period: float | None
    levels: np.ndarray
    rate: np.ndarray
    sites: tuple
    lon: np.ndarray
    lat: np.ndarray
    depth: np.ndarray
    investigation_time: float | None
    poe: np.ndarray | None
    source: str
    format: str
    imt: str
    file_units: str
    kind: str = ""
    notes: tuple = field(default=())

    def describe(self):
        """The intensity measure in words: ``"PGA"``, ``"Sa(T = 1 s)"``."""
        return describe_im(self.im, self.period)


def describe_im(im, period=None):
    """``"PGA"``, ``"PGV"``, ``"Sa(T = 1 s)"`` (``"Sa (period not recorded)"`` without one)."""
    if im == "sa":
        return f"Sa(T = {period:g} s)" if period is not None else "Sa (period not recorded)"
    return im.upper()


def annual_rate(poe, investigation_time):
    """Annual rate of exceedance from a probability of exceedance in a time, ``-ln(1 - PoE) / T`` [1/yr].

    Parameters
    ----------
    poe : array_like
        Probability of exceedance in ``investigation_time`` [1], in [0, 1] (1 gives ``inf``).
    investigation_time : float
        [yr], > 0.
    """
    poe = np.asarray(poe, float)
    with np.errstate(divide="ignore"):
        return -np.log1p(-poe) / float(investigation_time)


def probability_in(rate, years):
    """Probability of at least one occurrence in ``years`` of a Poisson process of ``rate`` [1/yr]: 1 - exp(-rate T)."""
    with np.errstate(over="ignore"):  # rate T beyond the largest float is inf, and the probability 1
        return -np.expm1(-np.asarray(rate, float) * float(years))


_IMT = re.compile(r"^\s*(PGA|PGV|SA\s*\(\s*([0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*(?:s)?\s*\))\s*$", re.IGNORECASE)


def parse_imt(text, where=""):
    """``"PGA"`` -> ("pga", None); ``"SA(0.2)"`` -> ("sa", 0.2); ``"PGV"`` -> ("pgv", None)."""
    m = _IMT.match(str(text))
    if not m:
        raise InputError(f"{where}intensity measure {text!r} is not one this project fits fragilities against; "
                         "give PGA, SA(T) with T in seconds (e.g. SA(1.0)) or PGV")
    name = m.group(1).upper()
    if name.startswith("SA"):
        period = float(m.group(2))
        if not period > 0:
            raise InputError(f"{where}intensity measure {text!r}: the period of SA must be positive (e.g. SA(1.0))")
        return "sa", period
    return name.lower(), None


def read_hazard_curve(path):
    """Read a hazard curve file: the OpenQuake engine's CSV or a plain two-column CSV (module docstring).

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    HazardCurve
        Levels in SI ([m/s^2] for PGA and Sa, [m/s] for PGV), rates [1/yr].
    """
    path = os.fspath(path)
    rows = [line for line in _lines(path) if line.strip()]
    at = _header_index(rows)
    if at is not None:
        _check_separator(rows[at], f"{path}: ")
        if _is_openquake_header(rows[at]):
            return read_openquake_csv(path)
    return read_plain_csv(path)


def _lines(path):
    if not os.path.exists(path):
        raise InputError(f"{path}: no such file; give a hazard curve (the OpenQuake engine's CSV, e.g. "
                         "hazard_curve-mean-PGA_12.csv, or a two-column CSV 'PGA [g],annual_rate [1/yr]')")
    if os.path.isdir(path):
        raise InputError(f"{path} is a folder; give the hazard curve file (CSV)")
    try:
        with open(path, encoding="utf-8-sig", newline="") as fh:
            return fh.read().splitlines()
    except UnicodeDecodeError:
        raise InputError(f"{path}: not a text file; give a hazard curve as CSV") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot be read ({exc.strerror or exc})") from None


def _header_index(rows):
    """Index of the first row that is not a ``#`` comment (the header), or None."""
    return next((i for i, row in enumerate(rows) if not row.lstrip().startswith("#")), None)


def _is_openquake_header(row):
    """Whether a row is the engine's header (lon, lat, poe-...), whatever separates its fields."""
    names = [c.strip() for c in re.split(r"[,;\t]", row)]
    return "lon" in names and "lat" in names and any(c.startswith("poe-") for c in names)


def _check_separator(row, where):
    """Refuse a header whose fields are separated by ';' or tabs (a spreadsheet's "CSV" in some locales)."""
    if "," in row:
        return
    sep = next((s for s in (";", "\t") if s in row), None)
    if sep is None:
        return
    shown = row if len(row) <= 40 else row[:37] + "..."
    raise InputError(f"{where}the fields are separated by {'tabs' if sep == chr(9) else repr(sep)} ({shown!r}); "
                     "a hazard curve CSV separates them by commas, with decimal points, as the OpenQuake engine "
                     "writes it: export the curves again ('oq export hcurves') or save the file as comma-separated")


def _check_names(names, where):
    """Refuse empty column names in the header: a trailing comma, or two commas in a row."""
    empty = [i for i, name in enumerate(names) if not name]
    if not empty:
        return
    if empty == [len(names) - 1]:
        raise InputError(f"{where}the header ends in an empty column (a trailing comma after {names[-2]!r}); remove "
                         "the trailing comma (and any at the end of the rows)")
    raise InputError(f"{where}column {empty[0] + 1} of the header has no name (two commas in a row?); name every "
                     "column or remove the empty ones")


def _check_trailing(row, width, line_no, where):
    """A row longer than the header only by empty fields: say it is a trailing comma."""
    if len(row) > width and not any(c.strip() for c in row[width:]):
        raise InputError(f"{where}line {line_no} ends in {len(row) - width} empty field(s) beyond the {width} of "
                         "the header (a trailing comma?); remove the trailing comma")


def _check_reachable(levels, im, names, where, unit, factor, fix):
    """Refuse levels [SI] beyond :data:`MAX_LEVEL`, naming the first (``names``: its column or line)."""
    beyond = np.nonzero(levels > MAX_LEVEL[im])[0]
    if not beyond.size:
        return
    i = int(beyond[0])
    bound = MAX_LEVEL[im] / factor
    raise InputError(f"{where}{names[i]}: a level of {levels[i] / factor:g} {unit} is beyond any ground motion (the "
                     f"strongest recorded: {_STRONGEST[im]}; levels up to {bound:g} {unit} are accepted); {fix}")


def _meta(comment, key):
    m = re.search(rf"\b{key}\s*=\s*(?:'([^']*)'|\"([^\"]*)\"|([^,\s\"']+))", comment)
    if not m:
        return None
    return next(g for g in m.groups() if g is not None)


def read_openquake_csv(path):
    """Read hazard curves exported by the OpenQuake engine (``hazard_curve-<kind>-<IMT>_<calc_id>.csv``).

    The engine writes (``openquake.commonlib`` export of ``hcurves``, ``writers.write_csv``): a
    first row ``#,,,,,"generated_by='OpenQuake engine 3.x', start_date=..., checksum=...,
    kind='mean', investigation_time=50.0, imt='PGA'"`` (one field per column, the comment in the
    last), then ``[custom_site_id,]lon,lat,depth,poe-<IML>,...`` with each IML as ``%.7f`` in
    g (PGA, SA) or cm/s (PGV), then one row per site: coordinates as ``%.5f`` and probabilities
    of exceedance in the investigation time as ``%.6E``; lines end in CRLF.

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    HazardCurve
        Levels in SI, annual rates ``-ln(1 - PoE) / investigation_time`` [1/yr].
    """
    path = os.fspath(path)
    lines = [line for line in _lines(path) if line.strip()]
    where = f"{path}: "
    at = _header_index(lines)
    if at == 0 and _is_openquake_header(lines[0]):
        raise InputError(f"{where}the first line is the header (lon,lat,...,poe-<IML>); the OpenQuake engine's "
                         "export starts with a '#' row of metadata before it (kind='mean', investigation_time=50.0, "
                         "imt='PGA'), without which the probabilities of exceedance cannot be turned into annual "
                         "rates: restore that row from the engine's export ('oq export hcurves')")
    if at is None or at == 0 or len(lines) < at + 2:
        raise InputError(f"{where}an OpenQuake hazard curve file has a '#' comment line of metadata, a header and a "
                         f"row per site; this one has {len(lines)} line(s)")
    _check_separator(lines[at], where)
    comment = " ".join(lines[:at])
    time_text = _meta(comment, "investigation_time")
    imt_text = _meta(comment, "imt")
    if imt_text is None:  # the file name says it too: hazard_curve-mean-PGA_12.csv
        m = re.search(r"-(PGA|PGV|SA\([0-9.]+\))(?:_\d+)?\.csv$", os.path.basename(path), re.IGNORECASE)
        imt_text = m.group(1) if m else None
    if time_text is None:
        raise InputError(f"{where}the first line has no investigation_time=...; without it the probabilities "
                         "of exceedance cannot be turned into annual rates (export the curves with the "
                         "OpenQuake engine, or give a two-column CSV of annual rates)")
    if imt_text is None:
        raise InputError(f"{where}the first line has no imt='...'; cannot tell which intensity measure the curve "
                         "is for (export the curves with the OpenQuake engine, one file per IMT)")
    try:
        T = float(time_text)
    except ValueError:
        raise InputError(f"{where}investigation_time={time_text!r} is not a number") from None
    if not (math.isfinite(T) and T > 0):
        raise InputError(f"{where}investigation_time={time_text!r} must be a positive number of years")
    im, period = parse_imt(imt_text, where)
    kind = _meta(comment, "kind") or ""

    header = [c.strip() for c in next(csv.reader([lines[at]]))]
    _check_names(header, where)
    poe_cols = [i for i, c in enumerate(header) if c.startswith("poe-")]
    other = [c for i, c in enumerate(header) if i not in poe_cols]
    unknown = [c for c in other if c not in ("custom_site_id", "lon", "lat", "depth")]
    if unknown or "lon" not in other or "lat" not in other:
        raise InputError(f"{where}header {','.join(header)!r}: expected [custom_site_id,]lon,lat,depth and then "
                         f"poe-<IML> columns{'; unknown: ' + ', '.join(unknown) if unknown else ''}")
    if len(poe_cols) < 2:
        raise InputError(f"{where}only {len(poe_cols)} intensity level (poe-<IML> column); a hazard curve needs "
                         "at least two")
    try:
        iml = np.array([float(header[i][4:]) for i in poe_cols])
    except ValueError:
        bad = next(header[i] for i in poe_cols if not _is_number(header[i][4:]))
        raise InputError(f"{where}column {bad!r}: the level after 'poe-' is not a number") from None
    if not (np.all(np.isfinite(iml)) and np.all(iml > 0) and np.all(np.diff(iml) > 0)):
        raise InputError(f"{where}the levels poe-<IML> must be positive and increasing; found "
                         f"{', '.join(f'{v:g}' for v in iml)}")
    unit, factor = OPENQUAKE_UNITS[im]
    _check_reachable(iml * factor, im, [f"column {header[i]!r}" for i in poe_cols], where, unit, factor,
                     f"give each level in {unit}, as the OpenQuake engine writes it (poe-0.5000000 for 0.5 {unit})")
    rows = list(csv.reader(lines[at + 1:]))
    sites, lon, lat, depth, poe = [], [], [], [], []
    for n, row in enumerate(rows):
        line_no = n + at + 2
        _check_trailing(row, len(header), line_no, where)
        if len(row) != len(header):
            raise InputError(f"{where}line {line_no} has {len(row)} fields, the header {len(header)}")
        try:
            values = [float(row[i]) for i in poe_cols]
            coords = {c: float(row[header.index(c)]) for c in ("lon", "lat", "depth") if c in header}
        except ValueError:
            raise InputError(f"{where}line {line_no}: a coordinate or a probability is not a number") from None
        values = np.array(values)
        if np.any(~np.isfinite(values) | (values < 0) | (values > 1)):
            raise InputError(f"{where}line {line_no}: probabilities of exceedance must lie in [0, 1]")
        label = row[header.index("custom_site_id")].strip() if "custom_site_id" in header else f"site-{n}"
        sites.append(label)
        lon.append(coords["lon"])
        lat.append(coords["lat"])
        depth.append(coords.get("depth", math.nan))
        poe.append(values)
    if len(set(sites)) != len(sites):
        raise InputError(f"{where}site labels repeat ({', '.join(sorted({s for s in sites if sites.count(s) > 1}))})")
    poe = np.array(poe)
    return HazardCurve(im=im, period=period, levels=iml * factor, rate=annual_rate(poe, T), sites=tuple(sites),
                       lon=np.array(lon), lat=np.array(lat), depth=np.array(depth), investigation_time=T, poe=poe,
                       source=path, format="openquake", imt=imt_text, file_units=unit, kind=kind)


def _is_number(text):
    try:
        float(text)
        return True
    except ValueError:
        return False


_LEVEL_HEADER = re.compile(r"^\s*(?P<imt>PGA|PGV|S[Aa]\s*\([^)]*\))\s*(?:\[(?P<u1>[^\]]+)\]|\((?P<u2>[^)]+)\)|"
                           r"[_ ]\s*(?P<u3>\S+))\s*$", re.IGNORECASE)
_YEARS = re.compile(r"([0-9]*\.?[0-9]+)\s*-?\s*(?:y|yr|yrs|year|years)\b", re.IGNORECASE)


def read_plain_csv(path):
    """Read a plain two-column hazard curve: intensity with its unit, then annual rate (or PoE in T years).

    Header examples: ``PGA [g],annual_rate [1/yr]``; ``SA(1.0) [m/s2],rate``; ``pga_g,poe in 50
    years``; ``PGV [cm/s],annual rate of exceedance``. Units of the levels: g, m/s2, cm/s2 (gal)
    for PGA and Sa; m/s, cm/s for PGV. Lines starting with ``#`` are comments.

    Returns
    -------
    HazardCurve
        One site, ``site-0``; levels in SI, rates [1/yr].
    """
    path = os.fspath(path)
    where = f"{path}: "
    lines = _lines(path)
    first = next((line for line in lines if line.strip() and not line.lstrip().startswith("#")), None)
    if first is not None:
        _check_separator(first, where)
    rows = [(n + 1, row) for n, row in enumerate(csv.reader(lines))
            if row and any(c.strip() for c in row) and not row[0].lstrip().startswith("#")]
    example = "e.g. 'PGA [g],annual_rate [1/yr]' or 'SA(1.0) [g],poe in 50 years'"
    if rows:
        _check_names([c.strip() for c in rows[0][1]], where)
    if len(rows) < 3:
        raise InputError(f"{where}a hazard curve needs a header ({example}) and at least two levels")
    _, header = rows[0]
    if len(header) != 2 or _is_number(header[0]):
        raise InputError(f"{where}the first line must name two columns, the intensity with its unit and the annual "
                         f"rate of exceedance ({example}); found {','.join(header)!r}")
    m = _LEVEL_HEADER.match(header[0])
    if not m:
        raise InputError(f"{where}first column {header[0]!r}: name the intensity measure and its unit, e.g. "
                         "'PGA [g]', 'SA(1.0) [g]', 'PGV [cm/s]'")
    im, period = parse_imt(m.group("imt"), where)
    unit = (m.group("u1") or m.group("u2") or m.group("u3")).strip()
    key = unit.lower().replace(" ", "") if unit.lower().replace(" ", "") in LEVEL_UNITS else unit.lower()
    if key not in LEVEL_UNITS or (im == "pgv") != (key in _VELOCITY_UNITS):
        allowed = "m/s, cm/s" if im == "pgv" else "g, m/s2, cm/s2 (gal)"
        raise InputError(f"{where}first column {header[0]!r}: unit {unit!r} unknown for {im.upper()}; use {allowed}")
    second = header[1].strip().lower()
    T = None
    if "poe" in second or "probab" in second:
        y = _YEARS.search(second)
        if not y:
            raise InputError(f"{where}second column {header[1]!r}: a probability of exceedance needs its time, "
                             "e.g. 'poe in 50 years'")
        T = float(y.group(1))
        if not T > 0:
            raise InputError(f"{where}second column {header[1]!r}: the time must be positive")
    elif not any(w in second for w in ("rate", "afe", "frequency", "lambda", "1/yr", "per year")):
        raise InputError(f"{where}second column {header[1]!r}: give the annual rate of exceedance "
                         "('annual_rate [1/yr]') or a probability of exceedance with its time ('poe in 50 years')")
    levels, values = [], []
    for line_no, row in rows[1:]:
        _check_trailing(row, 2, line_no, where)
        if len(row) != 2:
            raise InputError(f"{where}line {line_no} has {len(row)} fields; give two: level, rate")
        try:
            levels.append(float(row[0]))
            values.append(float(row[1]))
        except ValueError:
            raise InputError(f"{where}line {line_no}: {','.join(row)!r} is not two numbers") from None
    levels, values = np.array(levels), np.array(values)
    if not (np.all(np.isfinite(levels)) and np.all(levels > 0) and np.all(np.diff(levels) > 0)):
        raise InputError(f"{where}the levels must be positive and increasing, one per line")
    _check_reachable(levels * LEVEL_UNITS[key], im, [f"line {n}" for n, _ in rows[1:]], where, unit, LEVEL_UNITS[key],
                     f"give the levels in the unit the header names ({unit})")
    if T is None:
        if np.any(~np.isfinite(values) | (values < 0)):
            raise InputError(f"{where}annual rates must be non-negative numbers")
        rate, poe = values, None
    else:
        if np.any(~np.isfinite(values) | (values < 0) | (values > 1)):
            raise InputError(f"{where}probabilities of exceedance must lie in [0, 1]")
        rate, poe = annual_rate(values, T), values[None, :]
    return HazardCurve(im=im, period=period, levels=levels * LEVEL_UNITS[key], rate=rate[None, :], sites=("site-0",),
                       lon=np.array([np.nan]), lat=np.array([np.nan]), depth=np.array([np.nan]),
                       investigation_time=T, poe=poe, source=path, format="plain", imt=m.group("imt").strip(),
                       file_units=unit)


def usable_curve(hazard, site_index):
    """(levels [SI], rates [1/yr]) of one site: the levels with a finite positive rate.

    A probability of exceedance of 1 (infinite rate) at the lowest levels and of 0 at the highest
    are left out: the curve runs from its first finite to its last positive rate. A rate that
    grows with the level is refused (a hazard curve never rises).
    """
    rate = np.asarray(hazard.rate[site_index], float)
    levels = np.asarray(hazard.levels, float)
    site = hazard.sites[site_index]
    # compared, not subtracted: saturated levels (PoE = 1) have an infinite rate, and inf - inf is NaN
    rising = np.nonzero(rate[1:] > rate[:-1] + 1e-9 * np.maximum(rate[:-1], 1e-300))[0]
    if rising.size:
        i = int(rising[0])
        raise InputError(f"{hazard.source}: site {site}: the rate of exceedance rises from {rate[i]:.4g} to "
                         f"{rate[i + 1]:.4g} /yr between levels {i + 1} and {i + 2}; a hazard curve never rises "
                         "with the level (is the file sorted?)")
    keep = np.isfinite(rate) & (rate > 0)
    if keep.sum() < 2:
        raise InputError(f"{hazard.source}: site {site}: fewer than two levels with a probability of exceedance "
                         "between 0 and 1; no curve to integrate")
    return levels[keep], rate[keep]


def hazard_rate_at(hazard, site_index, intensity):
    """Annual rate of exceedance [1/yr] of a site's curve at ``intensity`` [SI], log-log interpolated.

    Beyond the curve's ends its end segments' power laws are extended (as in :func:`risk_integral`).
    """
    levels, rates = usable_curve(hazard, site_index)
    x, ln_h, k = _pieces(levels, rates)
    g = np.log(np.asarray(intensity, float))
    seg = np.clip(np.searchsorted(x, g, side="right") - 1, 0, len(k) - 1)
    return np.exp(ln_h[seg] - k[seg] * (g - x[seg]))


# --------------------------------------------------------------------------- the integral


def _log_ndtr_diff(a, b):
    """log(Phi(b) - Phi(a)) for a <= b, stable in both tails (-inf where b <= a)."""
    a, b = np.broadcast_arrays(np.asarray(a, float), np.asarray(b, float))
    upper = a > 0  # both in the upper tail: Phi(b) - Phi(a) = Phi(-a) - Phi(-b)
    big = np.where(upper, log_ndtr(-a), log_ndtr(b))
    small = np.where(upper, log_ndtr(-b), log_ndtr(a))
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.asarray(big + np.log1p(-np.exp(small - big)), float)
    return np.where(~(b > a) | np.isneginf(big), -np.inf, out)


def segment_integral(x1, x2, x_ref, ln_h_ref, k, median, beta):
    """Integral of P(DS | a) |dH/da| da over one power-law segment of a hazard curve [1/yr].

    On the segment ``x1 <= ln a <= x2`` the hazard is ``ln H = ln_h_ref - k (ln a - x_ref)`` and the
    fragility is lognormal, ``P = Phi((ln a - ln median) / beta)``. Integrating by parts and then the
    Gaussian integral gives, with ``z = (x - ln median) / beta``::

        H(x1) Phi(z1) - H(x2) Phi(z2) + H(median) exp(k^2 beta^2 / 2) [Phi(z2 + k beta) - Phi(z1 + k beta)]

    (the last term evaluated in logs, so steep segments do not overflow). From 0 to infinity it is
    Kennedy's ``H(median) exp(k^2 beta^2 / 2)``.

    Parameters
    ----------
    x1, x2 : array_like
        Ends of the segment, ln of the intensity in the fragility's units (``x1`` may be -inf,
        ``x2`` +inf).
    x_ref, ln_h_ref : array_like
        A point of the segment's power law: ln intensity and ln H [ln(1/yr)].
    k : array_like
        Slope -d ln H / d ln a [1], >= 0.
    median : array_like
        Fragility median, units of the intensity; ``inf`` gives P = 0, ``0`` gives P = 1.
    beta : array_like
        Dispersion [1]; 0 is a step at the median.

    Returns
    -------
    numpy.ndarray
        [1/yr], broadcast over the arguments; NaN where ``median`` is NaN or ``beta`` is NaN for a
        finite positive median.
    """
    x1, x2, x_ref, ln_h_ref, k, median, beta = np.broadcast_arrays(
        *(np.asarray(v, float) for v in (x1, x2, x_ref, ln_h_ref, k, median, beta)))
    out = np.full(x1.shape, np.nan)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        mu = np.log(median)

        def ln_h(x):
            return ln_h_ref - k * (x - x_ref)

        def h(x):  # H at a segment's end (0 at +inf, inf at -inf for k > 0)
            return np.where(np.isposinf(x), 0.0, np.where(np.isneginf(x), np.inf, np.exp(ln_h(x))))

        flat = k == 0
        never = np.isposinf(mu)  # P = 0
        always = np.isneginf(mu)  # P = 1
        step = np.isfinite(mu) & (beta == 0)
        smooth = np.isfinite(mu) & (beta > 0)

        # P = 1: every exceedance counts
        out = np.where(always, h(x1) - h(x2), out)
        out = np.where(never, 0.0, out)
        # a step at the median: H(max(x1, mu)) - H(x2) where the median lies below x2
        lo = np.maximum(x1, mu)
        out = np.where(step, np.where(mu < x2, h(lo) - h(x2), 0.0), out)
        # lognormal: the closed form
        z1 = (x1 - mu) / beta
        z2 = (x2 - mu) / beta
        t1 = np.where(np.isneginf(x1), 0.0, np.exp(ln_h(x1) + log_ndtr(z1)))
        t2 = np.where(np.isposinf(x2), 0.0, np.exp(ln_h(x2) + log_ndtr(z2)))
        kb = k * beta
        t3 = np.exp(ln_h(mu) + 0.5 * kb**2 + _log_ndtr_diff(z1 + kb, z2 + kb))
        out = np.where(smooth, np.maximum(t1 - t2 + t3, 0.0), out)
        out = np.where(flat & (smooth | step | never | always), 0.0, out)
    return out


@dataclass(frozen=True)
class RiskParts:
    """The risk integral of one hazard curve against fragilities, with the parts outside the curve.

    Attributes (arrays broadcast over the fragilities given), all [1/yr] except the shares:
    ``central``, ``lower``, ``upper`` (module docstring), ``inside`` (between the first and last
    level), ``below`` (below the first level, first segment extended), ``beyond`` (beyond the last
    level, last segment extended), ``h_last`` (H at the last level), ``p_last`` (P at the last
    level [1]).
    """

    central: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    inside: np.ndarray
    below: np.ndarray
    beyond: np.ndarray
    h_last: float
    p_last: np.ndarray


def _pieces(levels, rates):
    x = np.log(np.asarray(levels, float))
    ln_h = np.log(np.asarray(rates, float))
    k = np.maximum(-np.diff(ln_h) / np.diff(x), 0.0)
    return x, ln_h, k


def risk_integral(levels, rates, median, beta):
    """Mean annual frequency of a damage state: the risk integral over a tabulated hazard curve.

    Parameters
    ----------
    levels : array_like
        Intensity levels of the hazard curve, increasing, in the units of ``median`` (SI:
        [m/s^2] for PGA and Sa).
    rates : array_like
        Annual rate of exceedance at each level [1/yr], positive, non-increasing.
    median, beta : array_like
        Lognormal fragility: median [units of ``levels``] (``inf``: never reached, ``0``:
        always) and dispersion [1] (0: a step). Broadcast together.

    Returns
    -------
    RiskParts
        ``central`` = below + inside + beyond; ``lower`` = inside + P(a_L) H(a_L); ``upper`` =
        below + inside + H(a_L).
    """
    x, ln_h, k = _pieces(levels, rates)
    median, beta = np.broadcast_arrays(np.asarray(median, float), np.asarray(beta, float))
    shape = median.shape
    m = median[..., None]
    b = beta[..., None]
    inside = segment_integral(x[:-1], x[1:], x[:-1], ln_h[:-1], k, m, b).sum(axis=-1)
    below = segment_integral(-np.inf, x[0], x[0], ln_h[0], k[0], median, beta)
    beyond = segment_integral(x[-1], np.inf, x[-1], ln_h[-1], k[-1], median, beta)
    h_last = float(np.exp(ln_h[-1]))
    p_last = F.probability(np.exp(x[-1]), np.where(np.isnan(median), np.nan, median),
                           np.where(np.isfinite(median) & (median > 0), beta, 1.0)).reshape(shape)
    lower = inside + p_last * h_last
    upper = below + inside + h_last
    # a flat last segment never releases H(a_L): count it at P(a_L) at least
    central = below + inside + np.maximum(beyond, p_last * h_last)
    return RiskParts(central=central, lower=lower, upper=upper, inside=inside, below=below, beyond=beyond,
                     h_last=h_last, p_last=p_last)


def _log_probability(im, median, beta):
    """ln P(DS | im) of a lognormal fragility (:func:`pipeline.fragility.probability`), from ``log_ndtr``
    where it is smooth, so that the far lower tail stays a number where P itself underflows to 0."""
    im, median, beta = np.broadcast_arrays(*(np.asarray(v, float) for v in (im, median, beta)))
    with np.errstate(divide="ignore"):  # P = 0 (a step not reached, a median never reached): ln P = -inf
        out = np.log(F.probability(im, median, beta))
    smooth = np.isfinite(median) & (median > 0) & (beta > 0)
    out[smooth] = log_ndtr(np.log(im[smooth] / median[smooth]) / beta[smooth])
    return out


def _integrand(grid, levels, rates, median, beta):
    """P(DS | a) |dH/d ln a| on ``grid`` [1/yr per unit ln a], and H(a) on it (curve extended by its end segments).

    The product is taken in logs: where the first segment, extended below the curve, gives a rate
    beyond the largest float, P there is far below the smallest, and their product may be either.
    """
    x, ln_h, k = _pieces(levels, rates)
    g = np.log(grid)
    seg = np.clip(np.searchsorted(x, g, side="right") - 1, 0, len(k) - 1)
    ln_hg = ln_h[seg] - k[seg] * (g - x[seg])
    b = np.where(np.isfinite(median) & (median > 0), beta, 1.0)[..., None]
    p = F.probability(grid, median[..., None], b)
    with np.errstate(divide="ignore"):  # a flat segment (k = 0) adds nothing: ln k = -inf
        ln_k = np.log(k[seg])
    with np.errstate(over="ignore"):  # beyond the largest float the value is inf (risk_flag integral_overflows)
        return np.exp(_log_probability(grid, median[..., None], b) + ln_k + ln_hg), np.exp(ln_hg), p


def _shares(grid, density, below, total, shares=RISK_SHARES):
    """Intensities below which the given shares of ``total`` accrue (NaN where the grid does not reach them)."""
    g = np.log(grid)
    with np.errstate(over="ignore", invalid="ignore"):  # sums beyond the largest float: inf, skipped below
        steps = (0.5 * density[..., 1:] + 0.5 * density[..., :-1]) * np.diff(g)
        cum = np.concatenate([np.zeros(density.shape[:-1] + (1,)), np.cumsum(steps, axis=-1)], axis=-1)
        cum = cum + below[..., None]
    out = np.full(density.shape[:-1] + (len(shares),), np.nan)
    for index in np.ndindex(density.shape[:-1]):
        t = total[index]
        if not (np.isfinite(t) and t > 0 and np.all(np.isfinite(cum[index]))):
            continue
        frac = cum[index] / t
        for j, s in enumerate(shares):
            above = np.nonzero(frac >= s)[0]
            if above.size and above[0] > 0:
                i = above[0]
                w = (s - frac[i - 1]) / (frac[i] - frac[i - 1])
                out[index + (j,)] = math.exp(g[i - 1] + w * (g[i] - g[i - 1]))
    return out


# --------------------------------------------------------------------------- fragility files


def open_fragility(path):
    """Open a fragility file written by ``frustum fragility`` (or a report's ``fragility.nc``).

    Returns
    -------
    xarray.Dataset
        Loaded; ``source_file`` attribute set to ``path``.
    """
    from pipeline import dataset

    path = os.fspath(path)
    frag = dataset.open_results_file(path, "frustum fragility")
    missing = [name for name in ("median", "beta", "fit_status") if name not in frag.variables]
    if missing or not {"state", "column", "model"} <= set(frag.dims):
        raise InputError(f"{path}: not a fragility file (no {', '.join(missing) or 'state/column/model dims'}); "
                         "give the netCDF written by 'frustum fragility'")
    frag.attrs["source_file"] = path
    return frag


def fragility_im(frag):
    """(im, period [s] or None, units) of a fragility Dataset.

    The period of Sa is the attribute ``intensity_measure_period`` (written since issue 27) or, in
    older files, read from the median's long name ``... (period 1 s)``.
    """
    im = str(frag.attrs.get("intensity_measure", "pga"))
    units = str(frag["median"].attrs.get("units", frag.attrs.get("intensity_measure_units", "")))
    period = frag.attrs.get("intensity_measure_period")
    if period is None and im == "sa":
        m = re.search(r"\(period ([0-9.eE+-]+) s\)", str(frag["median"].attrs.get("long_name", "")))
        period = float(m.group(1)) if m else None
    return im, (None if period is None else float(period)), units


def check_im(frag, hazard):
    """Refuse a hazard curve whose intensity measure is not the fragility's (PGA with PGA, Sa(T) with Sa(T))."""
    im, period, units = fragility_im(frag)
    where = frag.attrs.get("source_file", "the fragility")
    needs = describe_im(im, period)
    has = hazard.describe()
    fix = (f"give a hazard curve of {needs} (OpenQuake: imt='{'SA(%g)' % period if im == 'sa' and period else im.upper()}'"
           f") or fit the fragility against {hazard.im} ('frustum fragility --im {hazard.im}'"
           + (f" on a study with sa_period = {hazard.period:g}" if hazard.im == "sa" else "") + ")")
    if im not in SI_UNITS:
        raise InputError(f"{where}: its fragility is against {im!r}, for which no hazard curve is read; fit it against "
                         "pga or sa ('frustum fragility --im pga')")
    if im != hazard.im:
        raise InputError(f"{hazard.source}: the hazard curve is for {has} but the fragility {where} is against "
                         f"{needs}; {fix}")
    if im == "sa":
        if period is None:
            raise InputError(f"{where}: the fragility is against Sa but does not record its period; refit it with "
                             "'frustum fragility --im sa' (which records intensity_measure_period)")
        if not math.isclose(period, hazard.period, rel_tol=1e-6):
            raise InputError(f"{hazard.source}: the hazard curve is for {has} but the fragility {where} is against "
                             f"{needs}; {fix}")
    if units != SI_UNITS[im]:
        raise InputError(f"{where}: the fragility's median is in {units!r}, expected {SI_UNITS[im]!r} for {needs}")


# --------------------------------------------------------------------------- the risk dataset


def _flags(status, beyond_curve, overflow):
    flag = np.full(status.shape, RISK_NO_FIT, np.int8)
    flag[(status == F.FIT_OK) | (status == F.FIT_SEPARATED)] = RISK_OK
    flag[status == F.FIT_NO_EXCEEDANCE] = RISK_NO_EXCEEDANCE
    flag[status == F.FIT_ALL_EXCEED] = RISK_ALL_EXCEED
    out = np.broadcast_to(flag, beyond_curve.shape).copy()
    out[(out == RISK_OK) & beyond_curve] = RISK_MEDIAN_BEYOND
    out[overflow] = RISK_OVERFLOW  # no number at all says more than where the median lies
    return out


def return_period(annual_frequency):
    """Mean return period 1/lambda [yr]: ``inf`` where lambda is 0, NaN where it is NaN.

    Where 1/lambda is beyond the largest float (lambda subnormal) it is ``inf`` as well, without
    numpy's overflow warning.
    """
    lam = np.asarray(annual_frequency, float)
    out = np.where(np.isnan(lam), np.nan, np.inf)
    return np.divide(1.0, lam, out=out, where=lam > 1.0 / np.finfo(float).max)


def _grid(hazard, medians, betas, n):
    lo = min(usable_curve(hazard, s)[0][0] for s in range(len(hazard.sites))) / 2.0
    hi_curve = max(usable_curve(hazard, s)[0][-1] for s in range(len(hazard.sites)))
    ok = np.isfinite(medians) & (medians > 0)
    reach = np.where(ok, medians * np.exp(2.5 * np.nan_to_num(betas, nan=0.0)), 0.0)
    hi = min(max(hi_curve * 3.0, float(reach.max(initial=0.0))), hi_curve * 30.0)
    return np.geomspace(lo, hi, n)


def site_risk(frag, hazard, years=DEFAULT_YEARS, n_grid=301):
    """The risk of every site, damage state, column and model of a fragility.

    Parameters
    ----------
    frag : xarray.Dataset
        Fragility from :func:`pipeline.fragility.fragility` or :func:`open_fragility`: ``median``
        [m/s^2 for PGA and Sa], ``beta`` [1], ``fit_status``, and with a bootstrap
        ``median_bootstrap``/``beta_bootstrap`` (the replicates).
    hazard : HazardCurve
        Same intensity measure as the fragility (:func:`check_im`), levels in SI.
    years : float
        Period of the probability stated [yr] (``probability_in_period``).
    n_grid : int
        Points of the intensity grid of the integrand (for plots and the shares).

    Returns
    -------
    xarray.Dataset
        Dims ``site``, ``state``, ``column``, ``model`` (labels), ``intensity`` and ``hazard_level``.
        ``annual_frequency`` [1/yr] with ``_lower``/``_upper`` (bounds for the curve's end) and, with
        bootstrap replicates, ``_band_lower``/``_band_upper`` at the fragility's confidence level;
        the same for ``probability_in_period`` [1]; ``return_period`` [yr]; the shares below the
        first and beyond the last level [1]; ``intensity_risk_05/50/95`` [IM units];
        ``risk_flag``; ``risk_integrand`` [1/yr per unit ln IM], ``fragility_probability`` [1] and
        ``hazard_rate_interpolated`` [1/yr] on ``intensity``; the curve as read, ``hazard_rate``
        [1/yr] (and ``hazard_poe``) on ``hazard_level``.
    """
    years = float(years)
    if not (math.isfinite(years) and years > 0):
        raise InputError(f"years = {years!r}: give a positive number of years, e.g. 50")
    check_im(frag, hazard)
    im, period, units = fragility_im(frag)
    status = frag["fit_status"].transpose("state", "column", "model").values.astype(int)
    usable = (status == F.FIT_OK) | (status == F.FIT_SEPARATED)
    median = np.where(usable, frag["median"].transpose("state", "column", "model").values, np.nan)
    beta = np.where(usable, frag["beta"].transpose("state", "column", "model").values, np.nan)
    replicates = "median_bootstrap" in frag.variables and frag.sizes.get("bootstrap", 0) > 0
    if replicates:
        med_b = frag["median_bootstrap"].transpose("bootstrap", "state", "column", "model").values
        bet_b = frag["beta_bootstrap"].transpose("bootstrap", "state", "column", "model").values
    confidence = float(frag.attrs.get("confidence_level", F.DEFAULT_CONFIDENCE))
    grid = _grid(hazard, median, beta, n_grid)

    nS = len(hazard.sites)
    shape = (nS,) + median.shape
    out = {name: np.full(shape, np.nan) for name in (
        "annual_frequency", "annual_frequency_lower", "annual_frequency_upper", "annual_frequency_band_lower",
        "annual_frequency_band_upper", "share_below_first_level", "share_beyond_last_level")}
    shares = np.full(shape + (len(RISK_SHARES),), np.nan)
    integrand = np.full(shape + (grid.size,), np.nan)
    h_grid = np.full((nS, grid.size), np.nan)
    beyond_curve = np.zeros(shape, bool)
    overflow = np.zeros(shape, bool)
    curve_end = np.full(nS, np.nan)
    for s in range(nS):
        levels, rates = usable_curve(hazard, s)
        curve_end[s] = levels[-1]
        parts = risk_integral(levels, rates, median, beta)
        # a usable fit whose integral is no number: beyond the largest float (risk_flag integral_overflows)
        overflow[s] = usable & ~np.isfinite(parts.central)
        central = np.where(overflow[s], np.nan, parts.central)
        with np.errstate(invalid="ignore", divide="ignore"):
            out["annual_frequency"][s] = central
            out["annual_frequency_lower"][s] = parts.lower
            out["annual_frequency_upper"][s] = parts.upper
            out["share_below_first_level"][s] = parts.below / central
            out["share_beyond_last_level"][s] = (central - parts.below - parts.inside) / central
        beyond_curve[s] = np.isfinite(median) & (median > levels[-1])
        dens, hg, _ = _integrand(grid, levels, rates, median, beta)
        integrand[s] = dens
        h_grid[s] = hg
        shares[s] = _shares(grid, dens, parts.below, central)
        if replicates:
            lam = risk_integral(levels, rates, med_b, bet_b).central  # (bootstrap, state, column, model)
            lo, hi = _band(lam, confidence)
            out["annual_frequency_band_lower"][s] = np.where(usable, lo, np.nan)
            out["annual_frequency_band_upper"][s] = np.where(usable, hi, np.nan)
    flag = _flags(status, beyond_curve, overflow)
    _warn(hazard, frag, flag, median, curve_end, units)

    dims = ("site", "state", "column", "model")
    level = f"{100 * confidence:g} %"
    ds = xr.Dataset(coords=_coords(frag, hazard, grid, years, im, units))
    for name, values in out.items():
        ds[name] = (dims, values)
    for name in ("", "_lower", "_upper", "_band_lower", "_band_upper"):
        ds[f"probability_in_period{name}"] = (dims, probability_in(out[f"annual_frequency{name}"], years))
    ds["return_period"] = (dims, return_period(out["annual_frequency"]))
    for j, share in enumerate(RISK_SHARES):
        ds[f"intensity_risk_{round(100 * share):02d}"] = (dims, shares[..., j], {"units": units})
    ds["risk_flag"] = (dims, flag)
    ds["risk_integrand"] = (dims + ("intensity",), integrand)
    ds["fragility_probability"] = (("state", "column", "model", "intensity"),
                                   F.probability(grid, median[..., None],
                                                 np.where(np.isfinite(median) & (median > 0), beta, 1.0)[..., None]))
    ds["hazard_rate_interpolated"] = (("site", "intensity"), h_grid)
    ds["hazard_rate"] = (("site", "hazard_level"), np.asarray(hazard.rate, float))
    if hazard.poe is not None:
        ds["hazard_poe"] = (("site", "hazard_level"), np.asarray(hazard.poe, float),
                            {"comment": f"in the investigation time, {hazard.investigation_time:g} years"})
    ds["hazard_curve_end"] = (("site",), curve_end, {"units": units})
    fdims = ("state", "column", "model")
    ds["fragility_median"] = (fdims, frag["median"].transpose(*fdims).values, {"units": units})
    ds["fragility_beta"] = (fdims, frag["beta"].transpose(*fdims).values)
    ds["fit_status"] = (fdims, frag["fit_status"].transpose(*fdims).values, dict(frag["fit_status"].attrs))
    own = {name: dict(var.attrs) for name, var in ds.variables.items()}
    annotate(ds)
    for name, attrs in own.items():  # IM-dependent units stay the fragility's
        ds[name].attrs = {**ds[name].attrs, **attrs}
    for name in ("annual_frequency_band_lower", "annual_frequency_band_upper", "probability_in_period_band_lower",
                 "probability_in_period_band_upper"):
        ds[name].attrs["long_name"] += f" ({level})"
        if not replicates:
            ds[name].attrs["comment"] = ("NaN: the fragility file has no bootstrap replicates (median_bootstrap); "
                                         "rerun 'frustum fragility --bootstrap N'")
    ds.attrs.update(
        title=F.structures_title("Risk of damage states at sites", frag.attrs),
        summary="Mean annual frequency of each damage state, column and model of a fragility at each site of a "
                "hazard curve: lambda = integral P(DS | a) |dH/da| da, the hazard curve interpolated log-log, "
                "each segment integrated in closed form against the lognormal fragility; the part beyond the "
                "curve's last level bounded (annual_frequency_lower/upper).",
        intensity_measure=im,
        intensity_measure_units=units,
        **({"intensity_measure_period": period} if period is not None else {}),
        years=years,
        hazard_file=os.path.basename(hazard.source),
        hazard_format=hazard.format,
        hazard_imt=hazard.imt,
        hazard_level_units_in_file=hazard.file_units,
        hazard_kind=hazard.kind,
        **({"hazard_investigation_time": hazard.investigation_time} if hazard.investigation_time else {}),
        fragility_file=os.path.basename(str(frag.attrs.get("source_file", ""))),
        confidence_level=confidence,
        bootstrap_replicates=int(frag.sizes.get("bootstrap", 0)) if replicates else 0,
        method="Cornell C.A. (1968) Engineering seismic risk analysis, BSSA 58(5); closed form per power-law "
               "segment (Kennedy R.P., Short S.A. (1994) UCRL-15910; Cornell C.A. et al. (2002) J. Struct. Eng. "
               "128(4)); Poisson occurrence",
        limits=LIMITS,
    )
    for key in ("results_study", "results_study_digest", "results_title", "structures"):
        if key in frag.attrs:
            ds.attrs[key] = str(frag.attrs[key])
    append_history(ds, f"pipeline.risk hazard={os.path.basename(hazard.source)} years={years:g}")
    return ds


def _band(samples, confidence):
    """Percentile interval over the first axis (no interpolation; NaN replicates left out, inf kept)."""
    alpha = 0.5 * (1.0 - confidence)
    out = np.full((2,) + samples.shape[1:], np.nan)
    for index in np.ndindex(samples.shape[1:]):
        v = samples[(slice(None),) + index]
        v = v[~np.isnan(v)]
        if v.size:
            out[(slice(None),) + index] = np.quantile(v, [alpha, 1.0 - alpha], method="inverted_cdf")
    out[~np.isfinite(out)] = np.nan
    return out[0], out[1]


def _coords(frag, hazard, grid, years, im, units):
    acc = im in ("pga", "sa")
    coords = {
        "site": ("site", np.array(hazard.sites, dtype=object)),
        "site_longitude": ("site", np.asarray(hazard.lon, float)),
        "site_latitude": ("site", np.asarray(hazard.lat, float)),
        "site_depth": ("site", np.asarray(hazard.depth, float)),
        "state": ("state", frag["state"].values.astype(str).astype(object), {"long_name": "damage state"}),
        "column": ("column", frag["column"].values.astype(str).astype(object)),
        "model": ("model", frag["model"].values.astype(str).astype(object)),
        "intensity": ("intensity", grid, {"units": units}),
        "hazard_level": ("hazard_level", np.asarray(hazard.levels, float), {"units": units}),
        "years": ((), years),
    }
    if acc:
        coords["intensity_g"] = ("intensity", grid / G)
        coords["hazard_level_g"] = ("hazard_level", np.asarray(hazard.levels, float) / G)
    for name in ("state_measure", "state_threshold"):
        if name in frag.coords:
            coords[name] = ("state", frag[name].values, dict(frag[name].attrs))
    for name in ("column_R", "column_r", "column_h", "slenderness", "theta_crit", "column_beta", "latitude",
                 "longitude", *F.STRUCTURE_COORDS):
        if name in frag.coords and frag[name].dims == ("column",):
            coords[name] = ("column", frag[name].values, dict(frag[name].attrs))
    return coords


def _warn(hazard, frag, flag, median, curve_end, units):
    """One warning per site where the hazard curve ends before a fragility's median."""
    factor, unit = (1.0 / G, "g") if units == "m s-2" else (1.0, units)
    states, columns, models = (frag[d].values for d in ("state", "column", "model"))
    for s, site in enumerate(hazard.sites):
        cells = np.argwhere(flag[s] == RISK_MEDIAN_BEYOND)
        if not cells.size:
            continue
        named = [f"{columns[c]} {models[m]} {states[i]} (median {median[i, c, m] * factor:.3g} {unit})"
                 for i, c, m in cells[:3]]
        more = f" and {len(cells) - 3} more" if len(cells) > 3 else ""
        warnings.warn(f"{os.path.basename(hazard.source)}: the hazard curve of site {site} ends at "
                      f"{curve_end[s] * factor:.3g} {unit}, below the fragility median of {', '.join(named)}{more}: "
                      "that risk rests partly on the curve extended beyond its last level; see "
                      "annual_frequency_lower/upper (risk_flag median_beyond_hazard_curve)", HazardWarning, stacklevel=2)


# --------------------------------------------------------------------------- files


#: Significant digits of the CSV (a hazard curve and a fragility carry no more).
CSV_DIGITS = 4


def risk_rows(risk):
    """One dict per site, column, model and damage state: the spreadsheet's rows (units in the keys)."""
    im = risk.attrs.get("intensity_measure", "pga")
    acc = im in ("pga", "sa")
    rows = []
    years = float(risk["years"])
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
                    for name in ("", "_lower", "_upper", "_band_lower", "_band_upper"):
                        row[f"probability_in_{years:g}_yr{name}"] = v(f"probability_in_period{name}")
                    row["share_beyond_last_level"] = v("share_beyond_last_level")
                    for share in RISK_SHARES:
                        key = f"intensity_risk_{round(100 * share):02d}"
                        row[f"{key}_{'g' if acc else 'm_s'}"] = v(key) / (G if acc else 1.0)
                    row["risk_flag"] = RISK_FLAGS[int(cell["risk_flag"])]
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


def one_in(p):
    """A probability in plain words: ``"about 1 in 250"``, ``"about 6 in 10"``, ``"less than 1 in a million"``."""
    if not np.isfinite(p):
        return "unknown"
    if p <= 0:
        return "practically no"
    if p < 1e-6:
        return "less than 1 in a million"
    if p >= 0.95:
        return "almost certain (more than 19 in 20)"
    if p >= 0.3:
        return f"about {round(10 * p)} in 10"
    n = 1.0 / p
    digits = 2 if n >= 10 else 1
    n = float(f"{n:.{digits}g}")
    return f"about 1 in {n:,.0f}"


def percent(p):
    """A probability in percent as the command, the figure and the report print it, never rounded to a
    certainty it is not.

    Two significant digits (``2.4 %``, ``0.059 %``, ``99 %``); from 99.5 % on, the decimals that keep it
    below 100 (``99.7 %``, ``99.97 %``), and ``> 99.99 %`` beyond; ``< 0.0001 %`` below 1e-6; ``0 %``
    for 0 and ``n/a`` for NaN.
    """
    if not np.isfinite(p):
        return "n/a"
    if p <= 0:
        return "0 %"
    if p < 1e-6:
        return "< 0.0001 %"
    if p < 0.995:
        return f"{float(f'{100 * p:.2g}'):g} %"
    for digits in (1, 2):
        text = f"{100 * p:.{digits}f}"
        if float(text) < 100:
            return f"{text} %"
    return "> 99.99 %"


def years_words(period):
    """A return period [yr] in words: ``2,100 years`` (two significant digits, as :func:`one_in`),
    ``more than a million years``, ``never`` (infinite), ``n/a`` (NaN)."""
    if np.isnan(period):
        return "n/a"
    if period == np.inf:
        return "never"
    if period > 1e6:
        return "more than a million years"
    if period < 1e-3:
        return "less than 0.001 years"
    r = float(f"{period:.2g}")
    text = f"{r:,.0f}" if r >= 10 else f"{r:g}"
    return f"{text} year{'' if r == 1 else 's'}"


def no_risk_reason(risk, site, column, model, state):
    """Why a cell of :func:`site_risk` has no annual frequency, in words; None when it has one.

    The reason follows ``risk_flag``: the fragility has no median (no run, or every run, reached the
    state), was not fitted (its ``fit_status``), or the integral is beyond the largest float (which
    part of the hazard curve makes it so, and the lower bound that remains).
    """
    cell = risk.sel(site=site, column=column, model=model, state=state)
    if np.isfinite(float(cell["annual_frequency"])):
        return None
    flag = RISK_FLAGS[int(cell["risk_flag"])]
    if flag == "no_median_no_exceedance_observed":
        return f"no run reached {state}, so the fragility has no median to integrate"
    if flag == "no_median_every_run_exceeds":
        return f"every run reached {state}, so the fragility has no median to integrate"
    if flag == "no_fit":
        return f"the fragility was not fitted ({F.FIT_STATUS.get(int(cell['fit_status']), '?').replace('_', ' ')})"
    if flag != "integral_overflows":
        return f"the risk integral is not a number (risk_flag {flag})"
    factor, unit = (1.0 / G, "g") if risk["intensity"].attrs.get("units") == "m s-2" else (1.0, "m/s")
    rate = risk["hazard_rate"].sel(site=site).values
    keep = np.isfinite(rate) & (rate > 0)
    levels, rates = risk["hazard_level"].values[keep], rate[keep]
    parts = risk_integral(levels, rates, float(cell["fragility_median"]), float(cell["fragility_beta"]))
    lower = f"{float(cell['annual_frequency_lower']):.3g} /yr"
    if np.isfinite(parts.below):  # the integral is at most about the largest rate: not met in practice
        return f"the risk integral is beyond the largest number a float holds (at least {lower})"
    k = (math.log(rates[0]) - math.log(rates[1])) / math.log(levels[1] / levels[0])  # a ratio may overflow
    a0, a1 = (f"{v * factor:.3g}" for v in levels[:2])
    return (f"the hazard curve's first segment ({a0} to {a1} {unit}) falls as a^-{float(f'{k:.3g}'):g}; extended "
            f"below {a0} {unit}, as the central value extends it, it carries the risk integral beyond the largest "
            "number a float holds (1.8e308 /yr); hazard curves flatten towards weak shaking (slopes of a few): check "
            f"the rates of the first levels, or give lower levels (shaking above {a0} {unit} alone gives at least "
            f"{lower})")


__all__ = [
    "DEFAULT_YEARS", "HazardCurve", "RiskParts", "RISK_FLAGS", "annual_rate", "probability_in", "parse_imt",
    "read_hazard_curve", "read_openquake_csv", "read_plain_csv", "usable_curve", "segment_integral",
    "risk_integral", "hazard_rate_at", "open_fragility", "fragility_im", "check_im", "site_risk", "risk_rows", "write", "write_csv",
    "one_in", "describe_im", "percent", "years_words", "no_risk_reason", "return_period", "MAX_LEVEL",
]
