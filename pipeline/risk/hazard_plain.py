"""A plain two-column hazard curve (``PGA [g],annual_rate [1/yr]``), read into a
:class:`pipeline.risk.hazard.HazardCurve` (the layout: :mod:`pipeline.risk.hazard_csv`)."""

import csv
import os
import re

import numpy as np

from pipeline.errors import InputError
from pipeline.risk.hazard import _VELOCITY_UNITS, LEVEL_UNITS, HazardCurve, annual_rate, check_reachable, parse_imt
from pipeline.risk.hazard_csv import _check_names, _check_separator, _check_trailing, _is_number, _lines


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
    check_reachable(levels * LEVEL_UNITS[key], im, [f"line {n}" for n, _ in rows[1:]], where, unit, LEVEL_UNITS[key],
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
