"""Hazard curves: the :class:`HazardCurve` every source gives, its intensity measure and units, and the
curve as integrated (:func:`usable_curve`, :func:`hazard_rate_at`).

A hazard curve gives H(a), the mean annual rate at which shaking at a site exceeds a. Its sources are
files (:mod:`pipeline.risk.hazard_csv`: the OpenQuake engine's CSV and a plain CSV) and code values
(:mod:`pipeline.risk.hazard_code`); each gives a :class:`HazardCurve` with its levels in SI (m/s^2 for
PGA and Sa, m/s for PGV), the units of the fragility's medians.
"""

import re
from dataclasses import dataclass, field

import numpy as np

from pipeline.errors import InputError
from pipeline.risk.integral import _pieces, ln_rate
from pipeline.units import G


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
        The file read, or the code values given (``"code values 475:0.16"``).
    format : str
        ``"openquake"``, ``"plain"`` or ``"code"`` (:mod:`pipeline.risk.hazard_code`).
    imt : str
        The intensity measure as the file names it (``"PGA"``, ``"SA(1.0)"``).
    file_units : str
        Unit of the levels in the file (``"g"``).
    kind : str
        OpenQuake's ``kind`` (``"mean"``, ``"quantile-0.5"``, ``"rlz-000"``) or ``""``.
    slope_below, slope_beyond : float or None
        Slopes k = -d ln H / d ln a [1] of the power laws that extend the curve below its first
        and beyond its last level; None: the end segments' own (a file's curve).
    description : str
        The source in words, for provenance (code values: the points and the slopes); ``""`` for a file.
    extrapolated : str
        Where the curve is extrapolated, in words (code values); ``""`` for a file, whose ends say it.
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
    slope_below: float | None = None
    slope_beyond: float | None = None
    description: str = ""
    extrapolated: str = ""

    def describe(self):
        """The intensity measure in words: ``"PGA"``, ``"Sa(T = 1 s)"``."""
        return describe_im(self.im, self.period)

    @property
    def tails(self):
        """(slope below the first level, slope beyond the last) [1]; None where the end segment's own."""
        return self.slope_below, self.slope_beyond


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


def check_reachable(levels, im, names, where, unit, factor, fix):
    """Refuse levels [SI] beyond :data:`MAX_LEVEL`, naming the first (``names``: its column, line or value).

    ``unit`` and ``factor`` (to SI) are those the levels were given in; ``fix`` ends the message.
    """
    beyond = np.nonzero(levels > MAX_LEVEL[im])[0]
    if not beyond.size:
        return
    i = int(beyond[0])
    bound = MAX_LEVEL[im] / factor
    raise InputError(f"{where}{names[i]}: a level of {levels[i] / factor:g} {unit} is beyond any ground motion (the "
                     f"strongest recorded: {_STRONGEST[im]}; levels up to {bound:g} {unit} are accepted); {fix}")


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
    if keep.sum() < (1 if None not in hazard.tails else 2):  # one level and its slopes: a power law
        raise InputError(f"{hazard.source}: site {site}: fewer than two levels with a probability of exceedance "
                         "between 0 and 1; no curve to integrate")
    return levels[keep], rate[keep]


def hazard_rate_at(hazard, site_index, intensity):
    """Annual rate of exceedance [1/yr] of a site's curve at ``intensity`` [SI], log-log interpolated.

    Beyond the curve's ends its end segments' power laws are extended, or those of the curve's own
    ``tails`` (as in :func:`pipeline.risk.integral.risk_integral`).
    """
    levels, rates = usable_curve(hazard, site_index)
    return np.exp(ln_rate(*_pieces(levels, rates, hazard.tails), np.log(np.asarray(intensity, float)))[0])
