"""Which trace of a record is x, y or z.

In order of precedence:

1. ``components=(x, y[, z])`` naming channel codes or trace ids (y may be
   None: y = 0).
2. A single trace with ``missing_y="zero"`` is x, whatever its channel code.
3. Channel codes: the orientation letter (the last of a SEED channel)
   ``E``/``X``/``1`` -> x, ``N``/``Y``/``2`` -> y, ``Z``/``U``/``3`` -> z
   (east-north-up is right-handed); K-NET's ``EW``, ``NS``, ``UD`` likewise.
4. PEER AT2 headers that name a direction (azimuths ``000``/``090``,
   ``CHY101-N``, ``UP``; :func:`pipeline.groundmotion.at2.component_orientation`):
   of two perpendicular horizontals, x is the one 90 degrees clockwise from
   the other, as east is from north, so (x, y, up) stays right-handed; the
   pair 180/270 gives x = 270, y = 180, a frame turned by 180 degrees.
5. Files given as a list, in list order (x, y[, z]).
"""

import numpy as np
from obspy import Stream

from pipeline.errors import InputError
from pipeline.groundmotion.options import how_to_give
from pipeline.groundmotion.provenance import log_step

__all__ = ["select_components"]

_ORIENTATION = {"E": "x", "X": "x", "1": "x", "N": "y", "Y": "y", "2": "y", "Z": "z", "U": "z", "3": "z"}
_KNET_CHANNELS = {"EW": "x", "NS": "y", "UD": "z", "EW1": "x", "NS1": "y", "UD1": "z", "EW2": "x", "NS2": "y", "UD2": "z"}


def _code_role(trace):
    channel = (trace.stats.channel or "").upper()
    if channel in _KNET_CHANNELS:
        return _KNET_CHANNELS[channel]
    if len(channel) in (1, 3) and channel[-1:] in _ORIENTATION:
        return _ORIENTATION[channel[-1]]
    return None


def _match(stream, selector, where):
    hits = [tr for tr in stream if selector in (tr.id, tr.stats.channel)]
    if len(hits) != 1:
        available = ", ".join(f"{tr.id!r}" for tr in stream)
        raise InputError(f"{where}: component selector {selector!r} matches {len(hits)} traces; choose one of {available}")
    return hits[0]


def _zero_like(trace, where):
    zero = trace.copy()
    zero.data = np.zeros(trace.stats.npts)
    zero.stats.channel = (trace.stats.channel[:-1] + "0") if trace.stats.channel else "y0"
    log_step(zero, f"missing_y='zero': {where} has one horizontal component; y set to 0")
    return zero


def _by_codes(stream, where):
    roles = {}
    for tr in stream:
        role = _code_role(tr)
        if role is None:
            return None
        if role in roles:
            raise InputError(f"{where}: two traces ({roles[role].id}, {tr.id}) look like component {role}; "
                             f"give {how_to_give('components')}")
        roles[role] = tr
    return roles


def _by_azimuths(stream, where):
    """Roles from AT2 headers that name directions, or None if one of them names none."""
    horizontal, vertical = [], []
    for tr in stream:
        at2 = tr.stats.get("at2") or {}
        kind = at2.get("orientation")
        if kind is None:
            return None
        (vertical if kind == "vertical" else horizontal).append(tr)
    if len(vertical) > 1 or len(horizontal) > 2:
        return None
    roles = {"z": vertical[0]} if vertical else {}
    if len(horizontal) == 1:
        roles["x"] = horizontal[0]
    elif len(horizontal) == 2:
        a, b = horizontal
        turn = (b.stats.at2.azimuth - a.stats.at2.azimuth) % 360.0
        if turn not in (90.0, 270.0):
            raise InputError(
                f"{where}: the AT2 components {a.stats.at2.component!r} and {b.stats.at2.component!r} "
                f"(azimuths {a.stats.at2.azimuth:g} and {b.stats.at2.azimuth:g} deg) are not perpendicular; "
                f"give {how_to_give('components')}")
        x, y = (b, a) if turn == 90.0 else (a, b)
        roles.update(x=x, y=y)
        for tr in (x, y):
            log_step(tr, f"components from the AT2 headers: x = {x.stats.at2.component!r} (azimuth "
                         f"{x.stats.at2.azimuth:g} deg), y = {y.stats.at2.component!r} (azimuth "
                         f"{y.stats.at2.azimuth:g} deg): x is 90 deg clockwise from y, as east from north")
    return roles


def select_components(stream, where, components=None, missing_y="error", ordered=False):
    """Order the traces of ``stream`` as x, y[, z] (see the module notes).

    Parameters
    ----------
    stream : obspy.Stream
    where : str
        The record's name for messages (file names, id).
    components : sequence, optional
        Channel codes or trace ids of x, y[, z]; y may be None (y = 0).
    missing_y : {"error", "zero"}
        A single horizontal component: an error, or y = 0.
    ordered : bool
        The traces come from a list of files, in x, y[, z] order.

    Returns
    -------
    obspy.Stream
        The traces x, y[, z] (not copies: the caller owns ``stream``).
    """
    if missing_y not in ("error", "zero"):
        raise InputError(f"{where}: missing_y must be 'error' or 'zero', got {missing_y!r}")
    ids = [tr.id for tr in stream]
    if len(set(ids)) != len(ids):
        dup = sorted({i for i in ids if ids.count(i) > 1})
        raise InputError(f"{where}: trace {dup[0]} comes in several pieces (gaps or overlaps: non-uniform sampling); merge or trim it first")
    if components is not None:
        comps = list(components)
        if len(comps) not in (2, 3) or comps[0] is None:
            raise InputError(f"{where}: components must name x, y[, z] (y may be None for 'y = 0'), got {components!r}")
        x = _match(stream, comps[0], where)
        y = _zero_like(x, where) if comps[1] is None else _match(stream, comps[1], where)
        picked = [x, y] + ([_match(stream, comps[2], where)] if len(comps) == 3 and comps[2] is not None else [])
        return Stream(picked)
    if len(stream) == 1 and missing_y == "zero":  # the user said: this one trace, and y = 0
        x = stream[0]
        log_step(x, f"missing_y='zero': the only trace ({x.id}) is x")
        return Stream([x, _zero_like(x, where)])
    roles = _by_codes(stream, where) or _by_azimuths(stream, where)
    if roles is None:
        if ordered and len(stream) in (2, 3):
            roles = dict(zip(("x", "y", "z"), stream))
        else:
            raise InputError(f"{where}: cannot tell which trace is x, y or z ({', '.join(ids)}); "
                             f"give {how_to_give('components')} with channel codes or trace ids")
    if "x" not in roles and "y" in roles:
        raise InputError(f"{where}: only a y-like horizontal trace ({roles['y'].id}); use it as x with "
                         f"{how_to_give('missing_y', 'zero')}, or give {how_to_give('components')}")
    if "x" not in roles:
        raise InputError(f"{where}: no horizontal component among {', '.join(ids)}")
    if "y" not in roles:
        if missing_y != "zero":
            raise InputError(
                f"{where}: only one horizontal component ({roles['x'].id}); load its pair too "
                f"(a list of files: X,Y[,Z]) or set y = 0 with {how_to_give('missing_y', 'zero')}"
            )
        roles["y"] = _zero_like(roles["x"], where)
    return Stream([roles[k] for k in ("x", "y", "z") if k in roles])
