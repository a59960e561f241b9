"""The compliant model (``"3d-compliant"``): rigid bodies, a monolith, a column of drums and its
capital, or a colonnade of such columns carrying epistyle blocks, on joints of contact points
(:mod:`pipeline.compliant`, kernels in :mod:`pipeline.dynamics.compliant`)."""

from types import MappingProxyType

from pipeline.models.options import INTEGRATORS, Option, declared
from pipeline.models.rigid import RESULTS
from pipeline.models.spec import Model, ModelDescription, StateLayout, read

__all__ = ["COMPLIANT_DRUMS"]

# edge_band: width of the band past a face's edge over which a point's support runs off
# (pipeline.dynamics.compliant.joint.overlap), in spacings of the two outer rings of contact points;
# step_safety: the fixed step as a fraction of the stability limit 2 / omega_max of the
# stiffest joint mode with its springs explicit (pipeline.dynamics.compliant.semi_implicit);
# springs: "implicit" takes the pressed points' springs at the step's end (backward Euler, stable
# at any step: the step is then chosen for accuracy, step_safety 1 by default, docs/model.md "The
# springs at the step's end"), "explicit" at its start (symplectic Euler, stable below the limit
# only: step_safety < 1, 0.5 before issue 37's speed work, about 4 % frequency error on the
# stiffest mode)
NUMERICS = declared(
    Option("edge_band", 0.5, "1", "number",
           "width of the band past a face's edge, in spacings of the outer rings of contact points", 0.05, 5.0),
    Option("step_safety", 1.0, "1", "number",
           "fixed step as a fraction of the stability limit of the stiffest joint with explicit springs", 0.01, 2.0,
           note="below 1 with springs = explicit",
           read_with=(("step", (None,)), ("integrator", INTEGRATORS[:1]))),  # a given step is used as it is
    Option("springs", "implicit", "1", "choice",
           "the fixed-step integrator's joint springs: at the step's end or at its start",
           choices=("implicit", "explicit"),
           note="implicit: backward Euler, stable at any step; explicit: symplectic Euler, step below the limit",
           read_with=(("integrator", INTEGRATORS[:1]),)),
)

# Each body's block of the assembly's state vector (pipeline.dynamics.compliant.layout): centre of mass,
# orientation quaternion (body to ground), velocity of the centre (ground frame), angular velocity
# (body axes); the vector goes on with the contact points' shear displacements, the energy
# accumulators and the joints' slip paths
STATE = StateLayout("pipeline.dynamics.compliant.layout", "NB", (
    ("x", "X"), ("y", "Y"), ("z", "Z"), ("q_w", "QW"), ("q_x", "QX"), ("q_y", "QY"), ("q_z", "QZ"),
    ("v_x", "VX"), ("v_y", "VY"), ("v_z", "VZ"), ("omega_x", "WX"), ("omega_y", "WY"), ("omega_z", "WZ")), per="body")

# the time histories it writes, by catalog name: the column's (its base joint's) and every drum's
HISTORIES = ("theta", "phi", "psi", "x_p", "y_p", "x_b", "y_b", "omega_zeta", "energy_hat", "work_ground_hat",
             "normal_force_hat", "tangential_force_hat", "mu_mob", "ground_acc_x", "ground_acc_y", "ground_acc_z",
             "slip", "contact_area_fraction", "normal_force", "tangential_force", "energy", "phase", "drum_dx",
             "drum_dy", "drum_theta", "drum_rotation", "drum_dz", "drum_phi")

COMPLIANT_DRUMS = Model(
    name="3d-compliant",
    description=ModelDescription(
        title="3D compliant drums on joints",
        body="rigid bodies with six degrees of freedom each: one monolith, or a stack of drums (conical "
        "frustums, bottom first) with an optional square capital on top; the base on the ground and every bed "
        "joint between two bodies are joints of contact points (rings times sectors over the face)",
        follows=("rocking and wobbling of every body", "sliding of the base on the ground and of each drum on the "
                 "one below", "uplift and flight of the whole column or of the bodies above a joint",
                 "drum dislocations: the residual slip, twist, tilt and opening of every joint",
                 "overturning of the column or of any body above a joint"),
        contact="Joint law, at every contact point: a normal spring-dashpot that acts in compression only (a joint "
        "never pulls), and a shear spring capped by Coulomb friction (the point sticks inside the friction cone "
        "and slips on it). There is no impact law: landings are taken by the springs and dashpots. Energy is lost "
        "in the normal dashpots (damping calibrated to a planar restitution unless `contact_damping` is given) and "
        "to friction where points slip.",
        sliding_onset="the mobilized friction |F_t|/N of the base reached mu (the base slid on the ground)",
        lift_off="every contact point of the base lost contact (the column flew)",
        cite="docs/model.md",
        reference="docs/model.md, 'The compliant-contact model' (joints of contact points in the manner of DEM "
        "codes; the 3D compliant drums on joints)",
    ),
    in_short="rigid bodies (the drums and capital of a column, or the monolith) on joints of contact points "
    "(spring-dashpots, elastic-Coulomb friction), run at every angle",
    bodies=("column", "drums", "colonnade"),  # a monolith, a stack of drums and a capital, a colonnade
    angle_invariant=False,  # its contact points are not axisymmetric: it feels the direction
    planar=False,
    numeric_options=NUMERICS,
    state=STATE,
    histories=HISTORIES,
    # and of a column of drums: the largest residual slip of a bed joint over its diameter, the body
    # that fell first, the residual dislocation of every joint
    results=RESULTS + ("dislocation_ratio", "overturn_drum", "epistyle_slip", "epistyle_opening", "joint_slip",
                       "joint_twist", "joint_tilt", "joint_opening"),
    entry_points=(("pipeline.dynamics.compliant.semi_implicit", "run"),),  # its default integrator's run
    runner="pipeline.compliant:simulate_compliant",
    # fixed steps of the semi-implicit scheme (the default), or the adaptive ones it is checked
    # against (pipeline.dynamics.compliant.stack.METHODS)
    integrators=INTEGRATORS,
    style=MappingProxyType(dict(ls="-.", marker="^", filled=False, band_alpha=0.07)),
    # the base's friction and stiffness, the dashpots (or the restitution they are calibrated to), the
    # joints' points and law, the integrator and its step (rtol, atol: the adaptive ones)
    options=read("restitution", "friction", "normal_stiffness", "contact_damping", "tail", "settle_limit",
                 "joint_stiffness", "stiffness_ratio", "contact_rings", "contact_sectors", "joint_friction",
                 "anathyrosis", "base_anathyrosis", "imperfections", "seed", "friction_range", "monitor_step",
                 "integrator", "step", "rtol", "atol"),
    calibration="pipeline.compliant:calibrated_damping",
    # what its run would refuse of a structure (a colonnade without capitals, a per-joint list that does not
    # fit, imperfections its beds cannot take, a given fixed step above the stability limit: the layout,
    # joints and pipeline.compliant.fixed_step its run calls too), refused before simulate or a study computes
    checker="pipeline.compliant.integrate:check_run",
)
