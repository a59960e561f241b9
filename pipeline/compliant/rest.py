"""The rest state of a structure on its compliant joints: static equilibrium, held exactly.

Every body is laid on the face below it (the joints touching, pressed by nothing), then the
joints' springs are pressed in until they carry the weights: a few Newton steps of the linear
static problem ``K_n dx = W - F(x)`` (K_n the normal springs of every point, the bodies'
weights W, the joints' forces F), solved in the least-squares sense because the normal springs
alone hold no horizontal motion and no twist (at rest the shear springs carry nothing). A
column's joints are then pressed uniformly by the weight above them; an epistyle block that
bears on a whole abacus at one end and half of one at the other tilts a little, as it must.
Head joints (block against block) carry nothing at rest: each is laid touching after the
solve, its most pressed point exactly on its face. The loads that hold each body there are
then set to the joints' net force and torque in that state, as the integrator sums them
(:func:`pipeline.dynamics.compliant.assembly.set_static_loads`), so that a structure left
alone stays exactly still. They are its weight to the solve's round-off (1e-10), except for
the horizontal part of the normal forces of faces that rest tilted: an end block of a
colonnade, bearing on a whole abacus and half of the next, tilts its capitals and itself by
a few 1e-6 rad, and its normal forces lean by as much; the shear springs, unloaded at rest,
do not hold that lean, and the holding load does (a few 1e-6 of the weight).

Imperfect drums (:mod:`pipeline.structures.imperfections`) rest on leaning beds: there the weight
has a part along the bed that only the shear springs can carry, sticking, as they would have
taken it up while the structure settled from the laid state. Their static solve
(:func:`_settle_sticking`) is the same Newton iteration with every point's shear spring too (the
stiffness of :func:`pipeline.dynamics.compliant.linear_system.spring_matrices`), each pressed
point's shear state the point's slide along the face since it was laid (what ``u' = v_t`` sums
while the point sticks), run until the joints carry the weights to round-off: the holding loads
are then the weight, their horizontal parts below 1e-12 of it, and a point inside its friction
cone keeps its shear state (``u' = v_t = 0``): still, exactly. A point pushed onto its cone is
refused (the body would slide at rest). The perfect structures keep the solve above, to the bit.
"""

import math

import numpy as np

from pipeline.dynamics.compliant import assembly as sk
from pipeline.dynamics.compliant import linear_system as ls
from pipeline.dynamics.compliant import semi_implicit as si
from pipeline.dynamics.compliant.layout import (
    B_HOLD, B_MASS, J_F, J_KN, J_KS, J_MU, J_OX, NB, P_AREA, QW, QZ, X, Z, state_size,
)
from pipeline.errors import InputError

__all__ = ["rest_state", "laid_state", "released_state"]

NEWTON_STEPS = 4
# the sticking solve of imperfect drums: at most this many Newton steps (it converges in 4 or 5: the
# joints' springs are linear, the turns of the bodies by microradians the only nonlinearity) ...
STICKING_STEPS = 20
# ... until the largest residual force or torque is below this fraction of the largest weight and a step
# no longer halves it: its round-off, about 1e-12 (a point's penetration, microns, is the difference of
# positions of metres)
STICKING_RESIDUAL = 1e-10


def laid_state(asm):
    """Every body at its place at rest, upright and still, the joints touching and pressed by nothing."""
    n_b, n_p, n_j = asm.n_bodies, asm.points.shape[0], asm.n_joints
    y = np.zeros(state_size(n_b, n_p, n_j))
    for b, part in enumerate(asm.layout.parts):
        y[NB * b + X:NB * b + Z + 1] = np.asarray(part.centre) / asm.length
        y[NB * b + QW] = 1.0
    return y


def _turn(q, v):
    """The quaternion q turned by the rotation vector v (ground frame) [rad]."""
    angle = float(np.linalg.norm(v))
    if angle == 0.0:
        return q
    axis = v / angle
    c, s = math.cos(0.5 * angle), math.sin(0.5 * angle)
    p = np.array([c, *(s * axis)])
    w1, x1, y1, z1 = p
    w2, x2, y2, z2 = q
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def _heads(asm):
    return [j for j, c in enumerate(asm.layout.contacts) if c.kind == "head"]


def _without(asm, params, drop, y):
    """Kernel parameters and a state of the structure without the joints ``drop`` (their points gone):
    ``(params, state, length of the bodies' part of the state, the kept points' indices)``."""
    from pipeline.dynamics.compliant.assembly import make_params

    bodies, points, starts, joints = params[:4]
    keep = [j for j in range(joints.shape[0]) if j not in set(drop)]
    rows = np.concatenate([np.arange(starts[j], starts[j + 1]) for j in keep]) if keep else np.zeros(0, int)
    counts = [starts[j + 1] - starts[j] for j in keep]
    new_starts = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    sub = make_params(bodies, points[rows], new_starts, joints[keep], params[4], params[5], params[9])
    n_body = NB * asm.n_bodies
    y_sub = np.zeros(state_size(asm.n_bodies, len(rows), len(keep)))
    y_sub[:n_body] = y[:n_body]
    return sub, y_sub, n_body, rows


def _turn_bodies(y, step, n_bodies):
    """Move and turn every body by its row of ``step`` (n_bodies x 6: translation, rotation vector)."""
    for b in range(n_bodies):
        o = NB * b
        y[o + X:o + Z + 1] += step[b, :3]
        y[o + QW:o + QZ + 1] = _turn(y[o + QW:o + QZ + 1], step[b, 3:])


def _face_places(params, y):
    """Every point's place on its joint's face (xi_x, xi_y), its penetration d and its overlap s: (n, 4)."""
    joint_start = params[2]
    sk._kinematics(y, params)
    out = np.empty((params[1].shape[0], 4))
    for j in range(params[3].shape[0]):
        for p in range(joint_start[j], joint_start[j + 1]):
            g = sk._point_geometry(y, p, j, params)
            out[p] = g[6], g[7], g[8], g[12]
    return out


def _settle_sticking(params, y, weights, n_bodies, labels):
    """The static solve of a structure on leaning beds: normal and shear springs, the points sticking.

    Newton steps ``K dx = W + F(x)`` with ``K`` every point's normal and shear springs, each pressed
    point's shear state its slide along the face since the laid state ``y`` (0 for a point out of
    contact, whose spring would relax), until the residual is round-off (``STICKING_RESIDUAL`` of the
    weight). ``y`` (bodies and shear states) is set in place.

    Raises
    ------
    InputError
        A point whose shear spring at rest is on its friction cone (``labels[j]``, its joint).
    """
    joints, points = params[3], params[1]
    shear = NB * n_bodies
    laid = _face_places(params, y)[:, :2]
    loads = np.empty((n_bodies, 6))
    scale, before = float(np.max(np.abs(weights))), np.inf

    def stick():
        """Each pressed point's shear state its slide since it was laid, the others' 0."""
        places = _face_places(params, y)
        pressed = (places[:, 2] > 0.0) & (places[:, 3] > 0.0)
        slide = np.where(pressed[:, None], places[:, :2] - laid, 0.0)
        y[shear:shear + 2 * len(points)] = slide.ravel()
        return places, pressed, slide

    for _ in range(STICKING_STEPS):
        places, pressed, slide = stick()
        sk.joint_loads(y, params, loads)
        residual = loads + weights
        now = float(np.max(np.abs(residual)))
        if now <= STICKING_RESIDUAL * scale and now > 0.5 * before:
            break  # round-off
        before = now
        K = ls.spring_matrices(params, y)[0]
        _turn_bodies(y, np.linalg.solve(K, residual.ravel()).reshape(-1, 6), n_bodies)
    else:  # the last step's state, its shear states set (its residual is what the holding loads take)
        places, pressed, slide = stick()
    joint_start = params[2]
    for j in range(joints.shape[0]):
        p = np.arange(joint_start[j], joint_start[j + 1])
        spring = joints[j, J_KS] * points[p, P_AREA] * np.hypot(slide[p, 0], slide[p, 1])
        cap = joints[j, J_MU] * joints[j, J_KN] * points[p, P_AREA] * places[p, 3] * places[p, 2]
        if np.any(pressed[p] & (spring >= cap)):
            raise InputError(f"the {labels[j]} would slip at rest: the load along its leaning bed reaches its "
                             "friction at a contact point; give a smaller imperfections tolerance or a higher "
                             "friction")


def _settle(params, y, weights, n_bodies):
    """The static solve of a structure on level beds: the normal springs alone (module docstring)."""
    K = ls.spring_matrices(params, y)[2]
    # the normal springs hold no horizontal motion and no twist of a horizontal face: those rows are
    # exactly zero, and a direct solve of the rest keeps a symmetric column's zeros exact
    held = np.nonzero(np.diag(K) != 0.0)[0]
    loads = np.empty((n_bodies, 6))
    for _ in range(NEWTON_STEPS):
        sk.joint_loads(y, params, loads)
        residual = (loads + weights).ravel()
        if np.max(np.abs(residual)) == 0.0:
            break
        step = np.zeros(6 * n_bodies)
        step[held] = np.linalg.solve(K[np.ix_(held, held)], residual[held])
        _turn_bodies(y, step.reshape(-1, 6), n_bodies)


def rest_state(asm, params, integrator):
    """The rest state of the structure, its holding loads set for the integrator (in ``params``).

    Parameters
    ----------
    asm : pipeline.compliant.tables.Assembly
    params : tuple
        Its kernel parameters (:meth:`Assembly.params`): the head joints' faces are laid
        touching and the bodies' holding loads set in them.
    integrator : str
        ``"semi-implicit"`` or an adaptive one: the loads as that integrator sums the joints.

    Raises
    ------
    InputError
        A joint that does not press over its whole face at rest (a load outside its face).
    """
    y = laid_state(asm)
    heads = _heads(asm)
    bodies, joints = params[0], params[3]
    solve, y_solve, bodies_part, rows = _without(asm, params, heads, y)  # the heads carry nothing at rest
    weights = np.zeros((asm.n_bodies, 6))
    weights[:, 2] = -bodies[:, B_MASS]
    if asm.layout.imperfections is not None:  # leaning beds: the shear springs carry their share, sticking
        from pipeline.compliant.summary import joint_labels

        labels = [label for j, label in enumerate(joint_labels(asm.layout)) if j not in set(heads)]
        _settle_sticking(solve, y_solve, weights, asm.n_bodies, labels)
        shear, n_rows = NB * asm.n_bodies, len(rows)
        for k in (0, 1):  # the shear states back to the whole structure's points
            y[shear + 2 * rows + k] = y_solve[bodies_part + 2 * np.arange(n_rows) + k]
    else:
        _settle(solve, y_solve, weights, asm.n_bodies)
    y[:bodies_part] = y_solve[:bodies_part]
    solve = params
    _check_pressed(asm, solve, y)
    for j in heads:  # laid touching: the most pressed point on the face (the face moved along its normal)
        sk._kinematics(y, params)
        d = max(sk._penetration(y, p, j, params)[0] for p in range(asm.joint_start[j], asm.joint_start[j + 1]))
        normal = joints[j, J_F:J_F + 9].reshape(3, 3)[:, 2]
        joints[j, J_OX:J_OX + 3] -= d * normal
    if integrator == "semi-implicit":
        si.set_static_loads(y, 1.0, params, si.make_scratch(params, asm.pattern))
    else:
        sk.set_static_loads(y, params)
    return y


def _check_pressed(asm, params, y):
    """Every point of a joint that carries a load presses in at rest."""
    sk._kinematics(y, params)
    for j, c in enumerate(asm.layout.contacts):
        if c.kind == "head":
            continue
        d = [sk._penetration(y, p, j, params)[0] for p in range(asm.joint_start[j], asm.joint_start[j + 1])]
        if min(d) <= 0.0:
            raise InputError(f"the {c.kind} joint under {asm.layout.parts[c.upper].label} does not press over its "
                             "whole face at rest: the load on it falls outside its face; check the structure's "
                             "dimensions")


def released_state(asm, params, theta, integrator):
    """A monolith tilted by theta [rad] towards +x, still, on its rim point at (R, 0).

    The pivot point is pressed in by the whole weight (its static penetration); the rest of
    the base is in the air.
    """
    y = rest_state(asm, params, integrator)
    bodies = params[0]
    q = (math.cos(0.5 * theta), 0.0, math.sin(0.5 * theta), 0.0)
    rot = np.empty(9)
    sk.rotation_matrix(*q, rot)
    rot = rot.reshape(3, 3)
    points = asm.points
    radius = float(np.max(np.hypot(points[:, 3], points[:, 4])))
    pivot = rot @ np.array([radius, 0.0, -bodies[0, 4]])  # B_ZC
    rim = int(np.argmax(points[:, 0]))  # the rim point on the +x axis
    sink = bodies[0, B_HOLD + 2] / (asm.joints[0, J_KN] * points[rim, 5])
    y[QW:QZ + 1] = q
    y[X] = -pivot[0]
    y[Z] = -pivot[2] - sink
    return y
