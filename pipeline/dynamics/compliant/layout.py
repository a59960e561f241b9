"""Layouts of the compliant-contact kernels: the tables of an assembly, its state, its statistics.

An assembly is a set of rigid bodies (drums, capitals, epistyle blocks) and a list of joints.
A joint is a face of its *lower* body (or of the ground) and a set of contact points of its
*upper* body pressing on that face; the face may have any orientation (a bed joint's is
horizontal, the head joint between two epistyle blocks vertical). Every point carries the
joint law of :mod:`pipeline.dynamics.compliant.joint`, in the frame of its face.

Everything is dimensionless: lengths per a reference length L, time per sqrt(L/g), masses per
the total mass M, forces per M g, energies per M g L, stiffnesses per unit area per M g / L^3,
damping per unit area per M g sqrt(L/g) / L^3. Plain constants: read by the kernels
(:mod:`pipeline.dynamics.compliant.assembly`, :mod:`pipeline.dynamics.compliant.semi_implicit`)
and the layer above (:mod:`pipeline.compliant`).

State vector (length :func:`state_size`), in this order:

* per body (13): centre of mass x, y, z; orientation quaternion w, x, y, z (body to ground;
  normalised where it is used); velocity of the centre of mass (ground frame); angular
  velocity in body axes;
* per contact point (2): elastic shear displacement in the frame of its face;
* work of the ground motion, friction dissipation, damping dissipation;
* per joint: the slip path, the area-weighted mean of the points' plastic slip [L].

Body axes are principal (inertia I_x, I_y, I_z); a drum's or a capital's axis is z.
"""

# Columns of the body table (one row per body).
# B_HOLD..B_HOLD + 5: the joints' net force and torque on the body in the rest state (ground
# frame): what holds it there. Its weight and any round-off of the rest state are taken to be
# these (B_HOLD + 2 is the weight, m g to round-off), so that at rest every derivative is exactly
# zero. B_SUPPORT: the joint on whose face the body rests (-1: a body on the ground). B_Z_FALL:
# the body has fallen off its support when its centre's distance from that face, along the
# face's normal and in the frame of the body below, is less than this: its rest distance less
# its own height (measured on the supporting body, so that a capital carried down by a tilting
# drum has not fallen off it); for a body on the ground, the height 0 (below the ground).
B_MASS, B_IX, B_IY, B_IZ, B_ZC, B_HEIGHT, B_COS_LIE, B_Z_FALL, B_SUPPORT, B_HOLD = range(10)
N_BODY_COLS = B_HOLD + 6

# Columns of the point table (one row per contact point, joint by joint): the point in the upper
# body's axes (from its centre of mass), its place on the upper body's own bearing face (u, v:
# the centre of pressure is taken in these) and its area.
P_X, P_Y, P_Z, P_U, P_V, P_AREA = range(6)
N_POINT_COLS = 6

# Columns of the joint table (one row per joint).
# J_LOWER, J_UPPER: the bodies (J_LOWER -1: the ground). J_OX..J_OZ: the face's centre in the
# lower body's axes (from its centre of mass; the ground's: absolute); J_F..J_F + 8: the face's
# axes in the lower body's axes, row-major 3 x 3 whose columns are the face's x, y and normal
# (pointing to the upper body). J_SHAPE: SHAPE_DISC (radius J_FA; inf for the ground) or
# SHAPE_RECT (half sides J_FA, J_FB along the face's x and y).
# J_UX..J_UZ, J_G..J_G + 8: the upper body's own bearing face (where it sits on the face below
# when the joint is closed and undisturbed), its centre and axes in the upper body's axes (the
# joint's dislocation is measured between the two).
# J_RIM: the centre of pressure's distance (u, v) beyond which the joint rocks on its rim, and
# J_LAND back inside which it has landed; J_RIM < 0: no rim statistics (a rectangle, a head joint).
# J_IMPLICIT: 1 if the fixed-step integrator takes the joint's springs at the step's end (backward
# Euler, numerics ``springs = "implicit"``), 0 if at its start (symplectic Euler); the adaptive
# integrators do not read it.
(J_LOWER, J_UPPER, J_OX, J_OY, J_OZ) = range(5)
J_F = 5
J_UX, J_UY, J_UZ = range(J_F + 9, J_F + 12)
J_G = J_F + 12
(J_SHAPE, J_FA, J_FB, J_KN, J_KS, J_MU, J_CN, J_TAU, J_BAND, J_AREA, J_RIM, J_DELTA, J_UFLOOR,
 J_LAND, J_IMPLICIT) = range(J_G + 9, J_G + 24)
N_JOINT_COLS = J_G + 24
SHAPE_DISC, SHAPE_RECT = 0, 1
GROUND = -1

# Per-body state.
X, Y, Z, QW, QX, QY, QZ, VX, VY, VZ, WX, WY, WZ = range(13)
NB = 13
# Accumulators after the shear states.
A_WORK, A_FRICTION, A_DAMPING = range(3)
N_ACC = 3

# Scratch columns per body (params[6]): rotation matrix (row-major), angular velocity in the
# ground frame, force and torque (ground frame, torque about the centre) from the joints.
W_R, W_OM, W_F, W_T = 0, 9, 12, 15
N_WORK = 18
# Scratch columns per joint (params[8]): the face's axes in the ground frame (row-major, columns
# the face's x, y, normal) and its centre (ground frame).
JW_R, JW_O = 0, 9
N_JWORK = 12

# Columns of the per-joint monitor (params[7]).
# M_NORMAL_EL: the elastic part of the normal force, which the friction cap uses. M_TX, M_TY:
# the resultant of the points' friction forces (face frame). M_COP_BX, M_COP_BY: the centre of
# pressure on the upper body's bearing face (u, v); M_COP_X, M_COP_Y: on the face below.
(M_NORMAL, M_TX, M_TY, M_COP_BX, M_COP_BY, M_COP_X, M_COP_Y, M_AREA, M_ELASTIC, M_NORMAL_EL) = range(10)
N_MON = 10

# Summary of a run. S_UNDECIDED: 1 if the run reached its settle limit after the tail with the
# structure still able to fall.
(S_STATUS, S_PEAK_THETA, S_PEAK_TIME, S_OVERTURN_TIME, S_OVERTURN_BODY, S_NFEV, S_STEPS,
 S_REJECTED, S_CALLS, S_END_TIME, S_ENERGY_START, S_ENERGY_END, S_UNDECIDED) = range(13)
N_SUMMARY = 13
# Per-body statistics: peak tilt and its time, unwrapped rotation about the vertical.
BS_PEAK, BS_PEAK_TIME, BS_ROTATION = range(3)
N_BODY_STATS = 3
# Per-joint statistics.
(JS_UPLIFT_TIME, JS_RETURNS, JS_MIN_NORMAL, JS_PEAK_MU, JS_MIN_AREA, JS_ON_RIM,
 JS_SLIDE_TIME, JS_FLIGHT_TIME) = range(8)  # JS_RETURNS: landings, from the rim back into the base
N_JOINT_STATS = 8
# History diagnostics of the first joint (a column's base) and the whole assembly.
(D_NORMAL, D_TANGENTIAL, D_MU, D_COP_X, D_COP_Y, D_AREA, D_ENERGY, D_AX, D_AY, D_AZ, D_ON_RIM) = range(11)
N_DIAG = 11
# Per-body history: centre displacement x, y, tilt, rotation about the vertical (unwrapped).
H_DX, H_DY, H_TILT, H_ROT = range(4)
N_HBODY = 4

# A joint mobilises its friction when |F_t| reaches this fraction of mu N (sliding onset).
SLIDE_FRACTION = 0.999
# A watched body's tilt counts as rising (its swing's peak still ahead) above this rate [rad per
# time unit sqrt(L/g)]. A structure at rest on its compliant joints keeps tilt rates of round-off
# and of micro-vibration, 1e-15 to 1e-8 rad/s of either sign (measured on a row of 6 columns after
# FEMA-FF-01 at 0.2 g), and all of its column tops had to be falling at one instant: a lottery that
# kept runs going for tens of seconds on still ground (that row: 54 s past its tail, twice the
# cost of its run). A real swing turns at mrad/s and more; a tilt rising at this floor for a whole
# 60-s settle limit (265 time units at L = 0.5 m) would gain 3e-5 rad, 0.0015 deg, below the
# 0.01 deg summaries show. The floor changes when a run is decided, never its outcome or peak
# (that row: peak and outcome alike at floors 1e-9 and 1e-7, decided 21 s and 3 s past its tail).
RISE_FLOOR = 1e-7
STATUS_COLLAPSED = 2  # summary status: a body fell off its support (or below the ground)


def state_size(n_bodies, n_points, n_joints):
    """Length of the state vector."""
    return NB * n_bodies + 2 * n_points + N_ACC + n_joints


def kept_size(n_bodies, n_joints):
    """Length of a history row of states: bodies, accumulators, slip paths (no shear states)."""
    return NB * n_bodies + N_ACC + n_joints
