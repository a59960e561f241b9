"""Hazard curve files: :func:`read_hazard_curve` tells the two CSV formats apart by their first line, and
the checks of the text both share (separators, empty column names, trailing commas, unreachable levels).

* the OpenQuake engine's CSV export, exactly as ``oq export hcurves`` writes it
  (``hazard_curve-mean-PGA_<calc_id>.csv``; :func:`pipeline.risk.hazard_openquake.read_openquake_csv`): a
  first row holding the metadata as a comment (``#,,,,,"generated_by='OpenQuake engine 3.18.0', ...,
  kind='mean', investigation_time=50.0, imt='PGA'"``; older engines wrote ``# ..., investigation_time=1.0,
  imt="PGA"``), then the header ``lon,lat,depth,poe-0.1000000,...`` (a ``custom_site_id`` column first
  when the job named its sites), then one row per site. The intensity measure levels (IMLs) are in the
  column names, in g for PGA and SA(T) (cm/s for PGV), as the engine writes them; the values are
  probabilities of exceedance (PoE) in the investigation time T [yr], converted to annual rates by
  ``-ln(1 - PoE) / T`` (Poisson occurrence, the engine's own assumption).
* a plain two-column CSV (:func:`pipeline.risk.hazard_plain.read_plain_csv`): a header naming the
  intensity measure with its unit and the rate, e.g. ``PGA [g],annual_rate [1/yr]`` (or ``SA(1.0)
  [m/s2]``, ``PGV [cm/s]``; the second column may instead be ``poe in 50 years``), then one row per
  level; lines starting with ``#`` are comments.

Several sites in one file give a ``site`` dimension. Every level is converted to SI on reading (m/s^2
for PGA and Sa, m/s for PGV). Refused by name: fields separated by ``;`` or tabs, an engine export
without its ``#`` metadata row, an empty column name (a trailing comma), and a level no ground motion
reaches (beyond :data:`pipeline.risk.hazard.MAX_LEVEL`, 30 g; :func:`pipeline.risk.hazard.check_reachable`).
"""

import os
import re

from pipeline.errors import InputError


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
    from pipeline.risk.hazard_openquake import read_openquake_csv  # the readers build on this module's checks
    from pipeline.risk.hazard_plain import read_plain_csv

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


def _is_number(text):
    try:
        float(text)
        return True
    except ValueError:
        return False
