"""The energy a structure must gain to fall, and the tilts past which it falls: the end of a run.

A run that ends (record and tail) with the structure still able to fall goes on with the ground
still until it cannot (docs/model.md, "The end of a run"): its energy above the rest state
below the lowest barrier of any way it can fall, and every body on the near side of the tilt
past which its part falls. The ways counted here, each as one rigid block:

* **tipping**: the part of a column above a joint (that joint's body and everything on it in the
  column) tips about the joint's rim when its centre of mass passes over it: at the tilt
  ``atan(a / z)``, its weight risen by ``M (sqrt(a^2 + z^2) - z)`` (a the face's radius, z the
  part's centre above the joint);
* **sliding off**: the part above a joint of finite extent slides off it only if friction lets it
  travel the face's half extent: ``mu M g a`` is the least energy friction takes on the way;
* **the frame** (a colonnade): the columns rocking in unison about their base rims with the
  epistyle on their capitals' far edges, in the row's plane and across it: one rigid block of
  the combined weights (Makris & Vassiliou 2013, with frustum columns and capitals).

The lowest of these is the barrier; a mechanism with several joints open at once is taken to
need no less. The bound is conservative in the sense that matters: a lower barrier only makes a
run go on longer (up to its settle limit) before it is decided.
"""

import math

import numpy as np

from pipeline.compliant.parts import KIND_BLOCK
from pipeline.dynamics.compliant.layout import GROUND
from pipeline.units import G

__all__ = ["overturning_barriers", "frame_barrier"]


def frame_barrier(terms):
    """The rise over which a rigid frame tips, and the tilt at which it does.

    Parameters
    ----------
    terms : sequence of (weight [N], lever [m], angle [rad])
        Each mass of the frame rocking about the pivot: its weight, its distance from the pivot
        and the angle of that line from the vertical, at rest.

    Returns
    -------
    tuple of float
        ``(rise [J], critical tilt [rad])``: the potential ``sum W l cos(a - theta)`` is one
        cosine of amplitude ``|sum W l e^{i a}|`` peaking at the tilt ``arg sum W l e^{i a}``.
    """
    total = sum(w * l * complex(math.cos(a), math.sin(a)) for w, l, a in terms)
    rest = sum(w * l * math.cos(a) for w, l, a in terms)
    return abs(total) - rest, math.atan2(total.imag, total.real)


def _column_parts(layout):
    """The bodies of each column, bottom first: {column: [body, ...]}."""
    columns = {}
    for b, part in enumerate(layout.parts):
        if part.kind != KIND_BLOCK:
            columns.setdefault(part.column, []).append(b)
    return columns


def overturning_barriers(layout, contacts, law, total_mass, length):
    """The lowest barrier of a structure [M g L] and the critical tilt of each body [rad].

    Parameters
    ----------
    layout : pipeline.compliant.parts.Layout
    contacts : sequence of pipeline.compliant.parts.Contact
    law : sequence of (stiffness, friction)
        Each joint's (:func:`pipeline.compliant.tables._joint_law`).
    total_mass, length : float
        The units M [kg] and L [m].
    """
    parts = layout.parts
    rises = []
    critical = np.full(len(parts), 0.5 * math.pi)
    contact_of = {c.upper: (c, law[j]) for j, c in enumerate(contacts) if c.kind in ("base", "bed", "capital")}
    columns = _column_parts(layout)
    for bodies in columns.values():
        for k, b in enumerate(bodies):
            contact, (_stiffness, mu) = contact_of[b]
            above = bodies[k:]
            mass = sum(parts[i].mass for i in above)
            base = parts[b].centre[2] - parts[b].zc
            z = sum(parts[i].mass * parts[i].centre[2] for i in above) / mass - base
            a = _radius(contact)
            critical[b] = math.atan2(a, z)
            rises.append(mass * G * (math.hypot(a, z) - z))
            if contact.kind != "base":
                rises.append(mu * mass * G * a)
    for j, c in enumerate(contacts):
        if c.kind == "bearing" and c.lower != GROUND:  # a block sliding off a capital: its share of the block
            rises.append(law[j][1] * c.load * G * min(c.half))
    if not rises:  # no column, no support to slide off: only rest decides (nothing bounds a fall)
        return 0.0, critical
    blocks = [b for b, p in enumerate(parts) if p.kind == KIND_BLOCK]
    if blocks and columns:
        for rise, tilt in _frame_barriers(layout, contacts, columns, blocks):
            rises.append(rise)
            for bodies in columns.values():
                for b in bodies:
                    critical[b] = min(critical[b], tilt)
    return min(rises) / (total_mass * G * length), critical


def _radius(contact):
    """The radius of a column joint's face (the ground's: the upper body's base)."""
    if math.isfinite(contact.half[0]):
        return contact.half[0]
    return float(np.max(np.hypot(contact.points[:, 3], contact.points[:, 4])))


def _frame_barriers(layout, contacts, columns, blocks):
    """The frame's barrier and critical tilt in the row's plane and across it."""
    parts = layout.parts
    bearing = [c for c in contacts if c.kind == "bearing"]
    epistyle = sum(parts[b].mass for b in blocks)
    top = max(parts[b].centre[2] - parts[b].zc for b in blocks)  # the blocks' underside
    out = []
    for axis in (0, 1):  # the row (x), across it (y)
        terms = []
        for bodies in columns.values():
            base = contacts[[c.upper for c in contacts].index(bodies[0])]
            a = _radius(base)
            mass = sum(parts[b].mass for b in bodies)
            z = sum(parts[b].mass * parts[b].centre[2] for b in bodies) / mass
            terms.append((mass * G, math.hypot(a, z), math.atan2(a, z)))
            # the epistyle rests on the far edge of the capital's bearings, across from the pivot
            c = max(abs(bc.origin[axis]) + bc.half[axis] for bc in bearing if bc.lower == bodies[-1])
            far = a + c
            share = epistyle / len(columns)
            terms.append((share * G, math.hypot(far, top), math.atan2(far, top)))
        out.append(frame_barrier(terms))
    return out
