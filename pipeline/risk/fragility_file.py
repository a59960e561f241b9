"""Fragility files as the risk reads them: :func:`open_fragility`, its intensity measure
(:func:`fragility_im`) and the check that a hazard curve is for the same one (:func:`check_im`)."""

import math
import os
import re

from pipeline.errors import InputError
from pipeline.risk.hazard import SI_UNITS, describe_im


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
