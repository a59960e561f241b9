"""The OpenQuake engine's hazard curve export (``hazard_curve-<kind>-<IMT>_<calc_id>.csv``), read into a
:class:`pipeline.risk.hazard.HazardCurve` (the layout: :mod:`pipeline.risk.hazard_csv`)."""

import csv
import math
import os
import re

import numpy as np

from pipeline.errors import InputError
from pipeline.risk.hazard import OPENQUAKE_UNITS, HazardCurve, annual_rate, check_reachable, parse_imt
from pipeline.risk.hazard_csv import (_check_names, _check_separator, _check_trailing, _header_index, _is_number,
                                      _is_openquake_header, _lines)


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
    check_reachable(iml * factor, im, [f"column {header[i]!r}" for i in poe_cols], where, unit, factor,
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
