"""A hazard curve from code values: PGAs at return periods, joined and extended as power laws.

Users in Greece and Europe often have no hazard curve, only a code's values: the PGA of a zone at
a 475-year return period (the Greek code's zones: 0.16 g and 0.24 g), perhaps also at 2,475 years.
A code's return period is T = -t / ln(1 - p) (475 years: 10 % in 50 years), so the annual rate of
exceeding the PGA a_T is exactly H(a_T) = 1/T. Eurocode 8 writes the hazard as a power law,
H(a) = k0 a^-k, "with k generally of the order of 3" (EN 1998-1:2004, 2.1(4) note; 2 to 4 across
Europe). :func:`code_hazard_curve` makes of the values a :class:`~pipeline.risk.hazard.HazardCurve`
whose levels are the PGAs and whose rates are 1/T:

* one value (T0, a0): H(a) = (1/T0) (a / a0)^-k at every level, k the slope given (default 3);
* two or more: between neighbours (T_i, a_i), (T_j, a_j) the power law through both, of slope
  k_ij = ln(T_j / T_i) / ln(a_j / a_i) (from ln H = -ln T); below the smallest PGA and beyond the
  largest the end segments' power laws extended, or the slope given to both ends.

The curve is extrapolated everywhere but between the given PGAs. The risk integral treats a
code curve as it treats a file's (:mod:`pipeline.risk.integral`): the central value extends the
power laws, the bounds say what shaking beyond the largest given PGA can add at least and at most.
With one value and a lognormal fragility (median m, dispersion beta) the central value is Kennedy's
closed form H(m) exp(k^2 beta^2 / 2).
"""

import math

import numpy as np

from pipeline.errors import InputError
from pipeline.risk.hazard import HazardCurve, check_reachable, parse_imt
from pipeline.units import G

#: Default slope k of the hazard's power law: Eurocode 8's "of the order of 3" (EN 1998-1:2004, 2.1(4)).
DEFAULT_SLOPE = 3.0

#: Slopes accepted [1], given or between two values. A 5 times rarer shaking (475 to 2,475 years) is
#: 5.2^(1/k) times stronger: 27 times at k = 0.5 (0.16 g becomes 4.3 g, near the strongest PGA ever
#: recorded, 4.36 g), 18 % at k = 10. Code values and Eurocode 8's k (about 3; 2 to 4 across Europe)
#: lie well inside; a slope outside is a slip (a PGA in the wrong unit, a return period mistyped).
SLOPE_RANGE = (0.5, 10.0)

_EXAMPLE = "e.g. 475:0.16 or 475:0.16,2475:0.30 (the return period in years, then the PGA in g)"


def parse_code_values(text, where=""):
    """``"475:0.16,2475:0.30"`` -> ((475.0, 0.16), (2475.0, 0.3)): return periods [yr] and PGAs [g].

    Raises
    ------
    InputError
        A pair that is not two numbers ``T:a``, naming it and the form.
    """
    parts = [part.strip() for part in str(text).split(",")]
    if not any(parts):
        raise InputError(f"{where}no return period and PGA given; give T:a pairs, {_EXAMPLE}")
    pairs = []
    for part in parts:
        bits = part.split(":")
        try:
            if len(bits) != 2:
                raise ValueError
            pairs.append((float(bits[0]), float(bits[1])))
        except ValueError:
            raise InputError(f"{where}{part!r} is not a return period and a PGA; give T:a pairs, {_EXAMPLE}") from None
    return tuple(pairs)


def _slope_words(k):
    return f"{float(f'{k:.3g}'):g}"


def check_slope(k, what, where="", fix="give one inside, e.g. 3"):
    """Refuse a slope k [1] outside :data:`SLOPE_RANGE`, naming it (``what``) and saying why."""
    lo, hi = SLOPE_RANGE
    if not (math.isfinite(k) and lo <= k <= hi):
        raise InputError(f"{where}{what} is {_slope_words(k)}; slopes of a hazard curve's power law lie between {lo:g} and "
                         f"{hi:g} (Eurocode 8's k is about 3, 2 to 4 across Europe; at {lo:g} a 2,475-year PGA "
                         f"would be 27 times the 475-year one, at {hi:g} only 18 % above it): {fix}")


def code_hazard_curve(points, slope=None, im="PGA", site="site-0", where=""):
    """A hazard curve through code values: PGAs at return periods, power laws between and beyond them.

    Parameters
    ----------
    points : str or sequence of (float, float)
        Return periods [yr] and PGAs [g]: ``"475:0.16,2475:0.30"`` or ``[(475, 0.16), (2475, 0.30)]``,
        in any order.
    slope : float, optional
        Slope k [1] of the power law H = H0 (a / a0)^-k beyond the given values, in
        :data:`SLOPE_RANGE`. One value: default :data:`DEFAULT_SLOPE` (Eurocode 8's k); two or more:
        default the end segments' own slopes.
    im : str
        The intensity measure the values are of: ``"PGA"`` (or ``"SA(T)"``, both in g).
    site : str
        Label of the site.
    where : str
        Prefix of the refusals (``"--hazard-pga: "``).

    Returns
    -------
    HazardCurve
        ``format`` ``"code"``; levels [m/s^2] the PGAs, rates [1/yr] 1/T; ``slope_below``,
        ``slope_beyond`` [1]; ``description`` (the points and slopes) and ``extrapolated`` (where) in words.

    Raises
    ------
    InputError
        A return period or PGA not positive and finite, a PGA beyond any ground motion, a return
        period given twice, a PGA that does not grow with the return period, a slope (given, or between
        two values) outside :data:`SLOPE_RANGE`, an intensity measure other than an acceleration.
    """
    pairs = parse_code_values(points, where) if isinstance(points, str) else tuple(
        (float(t), float(a)) for t, a in points)
    if not pairs:
        raise InputError(f"{where}no return period and PGA given; give T:a pairs, {_EXAMPLE}")
    name, period = parse_imt(im, where)
    if name == "pgv":
        raise InputError(f"{where}code values are accelerations in g; give im='PGA' (or 'SA(T)')")
    for t, a in pairs:
        if not (math.isfinite(t) and t > 0):
            raise InputError(f"{where}{t:g}:{a:g}: the return period {t:g} is not a positive number of years; give "
                             f"T:a pairs, {_EXAMPLE}")
        if not (math.isfinite(a) and a > 0):
            raise InputError(f"{where}{t:g}:{a:g}: the PGA {a:g} is not a positive number of g; give T:a pairs, "
                             f"{_EXAMPLE}")
    check_reachable(np.array([a for _, a in pairs]) * G, name, [f"{t:g}:{a:g}" for t, a in pairs], where, "g", G,
                    "give the PGA in g (0.16 for 0.16 g), after the return period in years")
    periods = [t for t, _ in pairs]
    twice = sorted({t for t in periods if periods.count(t) > 1})
    if twice:
        given = ", ".join(f"{t:g}:{a:g}" for t, a in pairs if t == twice[0])
        raise InputError(f"{where}the return period {twice[0]:g} years is given twice ({given}); give each once")
    pairs = sorted(pairs)
    for (t1, a1), (t2, a2) in zip(pairs, pairs[1:]):
        if not a2 > a1:
            raise InputError(f"{where}the PGA at {t2:g} years ({a2:g} g) is not above that at {t1:g} years ({a1:g} g); "
                             "shaking exceeded less often is stronger: check the values (the return period in years "
                             "first, then the PGA in g)")
        check_slope(math.log(t2 / t1) / math.log(a2 / a1), f"the slope between {t1:g}:{a1:g} and {t2:g}:{a2:g}",
                    where, "check the values")
    given = slope is not None
    if given:
        check_slope(float(slope), "the slope given", where)
    if len(pairs) == 1 and not given:
        slope = DEFAULT_SLOPE
    levels = np.array([a for _, a in pairs]) * G
    rates = np.array([1.0 / t for t, _ in pairs])
    ks = -np.diff(np.log(rates)) / np.diff(np.log(levels))
    below = float(slope) if slope is not None else float(ks[0])
    beyond = float(slope) if slope is not None else float(ks[-1])
    values = ",".join(f"{t:g}:{a:g}" for t, a in pairs)
    description, extrapolated = _words(pairs, ks, below, beyond, given, name.upper() if name == "pga" else im)
    return HazardCurve(im=name, period=period, levels=levels, rate=rates[None, :], sites=(str(site),),
                       lon=np.array([np.nan]), lat=np.array([np.nan]), depth=np.array([np.nan]),
                       investigation_time=None, poe=None, source=f"code values {values}", format="code",
                       imt=str(im).strip(), file_units="g", slope_below=below, slope_beyond=beyond,
                       description=description, extrapolated=extrapolated)


def _words(pairs, ks, below, beyond, given, imt):
    """(description, extrapolated): the code values and their power laws, and where the curve is extrapolated."""
    at = ", ".join(f"{a:g} g at {t:g} years" for t, a in pairs)
    (t0, a0), (t1, a1) = pairs[0], pairs[-1]
    if len(pairs) == 1:
        whose = "given" if given else "the default: Eurocode 8's k is about 3"
        return (f"code values: {imt} {at}; H(a) = (1/{t0:g}) (a / {a0:g} g)^-{_slope_words(below)}, slope "
                f"{_slope_words(below)} ({whose})",
                f"at every {imt} but {a0:g} g (return period {t0:g} years): the power law of slope {_slope_words(below)}")
    if given:
        ends = f"the slope given, {_slope_words(below)}"
    elif ks.size == 1:
        ends = f"its own slope, {_slope_words(below)}"
    else:
        ends = f"the end segments' slopes, {_slope_words(below)} below and {_slope_words(beyond)} beyond"
    between = (f"the power law through them (slope {_slope_words(ks[0])})" if ks.size == 1 else
               f"power laws between them (slopes {', '.join(_slope_words(k) for k in ks)})")
    return (f"code values: {imt} {at}; {between}, extended with {ends}",
            f"below {a0:g} g and beyond {a1:g} g (return periods under {t0:g} or over {t1:g} years): "
            f"{'the power law' if ks.size == 1 and not given else 'power laws'} of {ends}")


__all__ = ["DEFAULT_SLOPE", "SLOPE_RANGE", "check_slope", "code_hazard_curve", "parse_code_values"]
