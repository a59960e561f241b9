"""What ``frustum simulate`` prints of one run: its outcome in a line, and a structure's bodies and joints by name.

A column of drums or a colonnade gets a few more lines: the peak tilt of each body (of a
colonnade, each column's largest body and each epistyle block), how far the epistyle moved on
its capitals and opened between its blocks, and the largest residual slip of each kind of joint.
Every name is the summary's own (``body_label``, ``joint_label`` of
:mod:`pipeline.compliant.summary`, and which column a body belongs to, ``body_column``, and what
kind each joint is, ``joint_kind``): nothing here builds a label.
"""

import math

import numpy as np

from pipeline.response import outcome

__all__ = ["run_lines", "JOINT_KINDS"]

#: The kinds of joint (``joint_kind``) in the order and the words of the slips line.
JOINT_KINDS = {"base": "bases", "bed": "bed joints", "capital": "capitals on shafts", "bearing": "block bearings",
               "head": "head joints"}


def run_lines(model, summary, record=True):
    """The lines that tell one run: the first names the model, the others (indented) a structure's parts.

    Parameters
    ----------
    model : str
        The model's name, as the run was asked for.
    summary : dict
        :attr:`pipeline.response.Response.summary` of the run (SI: rad, m).
    record : bool
        A run under a record (False: a free motion, which reports its peak alone).

    Returns
    -------
    list of str
    """
    line = f"{model}: peak theta = {math.degrees(summary['peak_theta']):.3f} deg"
    if not record:
        return [line]
    line += (f" ({summary['peak_theta_ratio']:.2f} theta_crit), {outcome(summary)}, {summary['n_impacts']} impacts, "
             f"peak mu_mob = {summary['peak_mu_mob']:.2f}")
    if "joint_slip" not in summary:  # a rigid body: the line says it all
        return [line]
    columns = np.asarray(summary["body_column"])
    several = np.max(columns) > 0
    line += f", mean plastic slip of {'a' if several else 'the'} base's points {_mm(summary['slip'])}"
    if summary["n_bodies"] == 1:
        return [line]
    return [line, *(_tilts(summary, columns) if several else [_body_tilts(summary)]), *_epistyle(summary),
            _slips(summary)]


def _deg(angle):
    return f"{math.degrees(angle):.2f}"


def _mm(length):
    return f"{length * 1e3:.1f} mm"


def _body_tilts(summary):
    """A column of drums: every body's peak tilt, named."""
    tilts = summary["drum_peak_theta"]
    return "  peak tilt [deg] of each body: " + ", ".join(
        f"{label} {_deg(t)}" for label, t in zip(summary["body_label"], tilts))


def _tilts(summary, columns):
    """A colonnade: each column's largest peak tilt, naming the body that reached it, and each block's."""
    labels, tilts = summary["body_label"], np.asarray(summary["drum_peak_theta"])
    largest = []
    for k in range(int(np.max(columns)) + 1):
        bodies = np.flatnonzero(columns == k)
        b = bodies[int(np.argmax(tilts[bodies]))]
        largest.append(f"{labels[b]} {_deg(tilts[b])}")
    lines = ["  peak tilt [deg] of each column (its largest body): " + ", ".join(largest)]
    blocks = np.flatnonzero(columns < 0)
    if blocks.size:
        lines.append("  peak tilt [deg] of each epistyle block: "
                     + ", ".join(f"{str(labels[b]).removeprefix('epistyle ')} {_deg(tilts[b])}" for b in blocks))
    return lines


def _epistyle(summary):
    """How far the epistyle's blocks ended from their places on their capitals and its head joints open (residual:
    ``epistyle_slip``, ``epistyle_opening``); nothing for a structure without an epistyle."""
    if not math.isfinite(summary.get("epistyle_slip", math.nan)):
        return []
    heads = "head" in summary["joint_kind"]
    opening = (f", its head joints open up to {_mm(summary['epistyle_opening'])}" if heads else
               " (one block: no head joint)")
    return [f"  epistyle at the end: its blocks moved up to {_mm(summary['epistyle_slip'])} on their capitals"
            f"{opening}"]


def _slips(summary):
    """The largest residual slip of each kind of joint, named by its joint, and the dislocation ratio, which
    counts the bed joints and the capitals on their shafts only."""
    kinds = np.asarray(summary["joint_kind"])
    slips = np.asarray(summary["joint_slip"])
    parts = []
    for kind, words in JOINT_KINDS.items():
        joints = np.flatnonzero(kinds == kind)
        if joints.size:
            j = joints[int(np.argmax(slips[joints]))]
            parts.append(f"{words} {_mm(slips[j])} ({summary['joint_label'][j]})")
    ratio = summary["dislocation_ratio"]
    return ("  residual slips, the largest of each kind of joint: " + "; ".join(parts)
            + f"; the largest of a bed joint or capital on its shaft over the joint's diameter {100 * ratio:.2f} %")
