"""The bodies and joints of a colonnade for the compliant model: columns of drums carrying epistyle blocks.

Each column (:func:`pipeline.compliant.parts.column_layout`) stands on the ground at its axis;
each epistyle block bears on two capitals over the rectangles :meth:`Colonnade.bearings` gives
(a rectangular face of the abacus top, the block's underside pressing on it), and neighbouring
blocks meet end to end over the inner columns (a vertical face, its normal along the row: the
head joint, which pushes and never pulls). The course above the epistyle rides on its block as
mass. The fixed-step solve eliminates each column's drums into its capital, then the capitals
and blocks along the row (cap 1, block 1, cap 2, block 2, ...), which fills in nothing.
"""

import numpy as np

from pipeline.compliant.parts import (
    END_FACE, IDENTITY, KIND_BLOCK, KIND_CAPITAL, Contact, Layout, Part, column_layout, drawn, rectangle_nodes,
)
from pipeline.dynamics.compliant import joint as jl
from pipeline.dynamics.compliant.layout import SHAPE_RECT
from pipeline.errors import InputError
from pipeline.structures.description import bearing_label, block_label, head_label

__all__ = ["colonnade_layout", "is_colonnade"]


def is_colonnade(structure):
    """Whether a structure is a colonnade (:class:`pipeline.structures.colonnade.Colonnade`)."""
    from pipeline.structures.colonnade import Colonnade

    return isinstance(structure, Colonnade)


def rectangle_points(half_a, half_b, settings):
    """Contact points of a rectangle (half sides a, b) about its centre: (n, 3) rows of (a, b, area).

    Gauss-Lobatto nodes along each side (:func:`pipeline.compliant.parts.rectangle_nodes`), their
    tensor product: the area and second moments are exact, and the points come in mirror pairs
    (p, -p) next to each other, as a disc's do.
    """
    n = rectangle_nodes(settings)
    x, w = jl.lobatto_nodes(n)
    rows = []
    for i in range(n):
        for k in range(n):
            a, b = x[i] * half_a, x[k] * half_b
            if (a, b) > (0.0, 0.0) or (a == 0.0 and b == 0.0):
                area = w[i] * w[k] * half_a * half_b
                rows.append((a, b, area))
                if a != 0.0 or b != 0.0:
                    rows.append((-a, -b, area))
    return np.array(rows)


def colonnade_layout(colonnade, settings):
    """The :class:`pipeline.compliant.parts.Layout` of a colonnade."""
    if colonnade.capital is None:
        raise InputError("the compliant model runs a colonnade whose columns have capitals (its blocks bear on the "
                         "abacus); give the column a capital, or run the rigid frame (2d-frame)")
    stack = colonnade.column
    carried = np.zeros(colonnade.n_columns)  # each capital's share of the epistyle, by bearing area
    for k in range(colonnade.n_blocks):
        bearings = colonnade.bearings(k)
        for b in bearings:
            carried[b.column] += colonnade.block_mass(k) * b.area / sum(c.area for c in bearings)
    parts, contacts, tops = [], [], []
    beds = drawn(colonnade, settings)  # imperfect drums, or None
    for i, x in enumerate(colonnade.axes()):
        p, c = column_layout(stack, x, len(parts), i, settings, row=True, carried=carried[i],
                             columns=colonnade.n_columns, beds=beds)
        parts += p
        contacts += c
        tops.append(len(parts) - 1)
    first_block = len(parts)
    cap = parts[tops[0]]
    cap_top = cap.height - cap.zc  # the abacus top above the capital's centre
    height = colonnade.block_height
    for k in range(colonnade.n_blocks):
        x0, x1 = colonnade.block_extent(k)
        half = (0.5 * (x1 - x0), 0.5 * colonnade.epistyle_width, height)
        centre = colonnade.block_centre(k)
        if beds is not None:  # laid level between its capitals' tops, off their perfect height by microns
            rise = [parts[tops[i]].centre[2] + cap_top - colonnade.abacus_top for i in (k, k + 1)]
            centre = (centre[0], centre[1], centre[2] + 0.5 * (rise[0] + rise[1]))
        parts.append(Part(block_label(k), KIND_BLOCK, colonnade.block_mass(k), colonnade.block_inertia(k),
                          centre, 0.5 * height, height, 0.5 * np.pi, False, half, -1))
    axes = colonnade.axes()
    for k in range(colonnade.n_blocks):
        block = first_block + k
        centre = parts[block].centre
        bearings = colonnade.bearings(k)
        total = sum(b.area for b in bearings)
        for b in bearings:
            cx, cy = 0.5 * (b.x0 + b.x1), 0.5 * (b.y0 + b.y1)
            ha, hb = 0.5 * (b.x1 - b.x0), 0.5 * (b.y1 - b.y0)
            # the rectangle's centre on the block's underside, in the block's axes
            ux, uy, uz = axes[b.column] + cx - centre[0], cy, -0.5 * height
            grid = rectangle_points(ha, hb, settings)
            points = np.column_stack([ux + grid[:, 0], uy + grid[:, 1], np.full(len(grid), uz), grid[:, 0], grid[:, 1],
                                      grid[:, 2]])
            contacts.append(Contact("bearing", tops[b.column], block, (cx, cy, cap_top), IDENTITY, (ux, uy, uz),
                                    IDENTITY, SHAPE_RECT, (ha, hb), points,
                                    parts[block].mass * b.area / total, -1, False, bearing_label(k, b.column)))
    for head in colonnade.head_joints():
        left, right = first_block + head.left, first_block + head.right
        lc, rc = parts[left].centre, parts[right].centre
        zc = 0.5 * (head.z0 + head.z1)
        hy, hz = 0.5 * (head.y1 - head.y0), 0.5 * (head.z1 - head.z0)
        grid = rectangle_points(hy, hz, settings)
        ux, uy, uz = head.x - rc[0], 0.5 * (head.y0 + head.y1), zc - rc[2]
        points = np.column_stack([np.full(len(grid), ux), uy + grid[:, 0], uz + grid[:, 1], grid[:, 0], grid[:, 1],
                                  grid[:, 2]])
        contacts.append(Contact("head", left, right, (head.x - lc[0], uy, zc - lc[2]), END_FACE, (ux, uy, uz),
                                END_FACE, SHAPE_RECT, (hy, hz), points, parts[right].mass, -1, False,
                                head_label(head.left, head.right)))
    drums = [b for b, p in enumerate(parts) if p.kind != KIND_BLOCK and p.kind != KIND_CAPITAL]
    row = []
    for i, top in enumerate(tops):
        row.append(top)
        if i < colonnade.n_blocks:
            row.append(first_block + i)
    return Layout(tuple(parts), tuple(contacts), tuple(tops), tuple(drums + row), stack.column.R, beds)
