"""The rigid models of a monolith: the paper's 3D rolling frustum (``"3d"``) and classical
planar rocking (``"2d"``), both run by the event-driven kernels of :mod:`pipeline.dynamics.rigid`
through :func:`pipeline.simulate.simulate_rigid`."""

from types import MappingProxyType

from pipeline.citation import CITE, REFERENCE
from pipeline.models.options import Option, declared
from pipeline.models.spec import Model, ModelDescription, StateLayout, read

__all__ = ["ROLLING_FRUSTUM", "PLANAR_ROCKING"]

_RIGID_CONTACT = (  # {pivot}: what the tipped column turns on, {rim}: where it touches
    "The base is a flat face of stone on a bed: it stays at rest with the ground, slides flat on it or, once "
    "tipped, {pivot}, whose point of contact slips when the friction needed exceeds "
    "Coulomb's `friction` times the normal force; when the ground would have to pull, the column flies and lands "
    "again with a plastic impact that sticks or slides. The bed's compliance (`normal_stiffness`) gives the "
    "patch under the {rim} its rolling damping and drilling friction. Energy is lost at landings (angular momentum "
    "about the new pivot is kept, or the `restitution` given; passages close to a landing lose part of it), to "
    "friction while sliding or slipping, in the patch's dashpots and in the optional viscous contact couple "
    "(`damping`).")

# Numerical thresholds of the rigid kernels (defaults; carried in the options array,
# pipeline.dynamics.rigid.frustum.OPT_*, so that
# studies/thresholds can vary them). No physical result may depend on them:
# studies/thresholds/results.md shows that none does.
#
# slave_time [tau]: the direction of a two-dimensional Coulomb slip relaxes
# towards the consistent one (slip acceleration along the slip) at the rate
# k / s, k of order mu N: at slip onset and stop (s -> 0) that is infinitely
# fast, and no explicit step survives it. Below s = slave_time mu N the
# direction is therefore slaved: taken as the consistent direction, solved at
# every evaluation (an error of the order of the lag slave_time x the turning
# rate of that direction); above it the direction is a state. The layer is
# left at slave_time mu N and entered again below half of it.
#
# look_ahead [tau]: a phase that starts on a bound (stick after a slip stops,
# say) is checked a little ahead as well: the integrator reads the event signs
# only after a restart window of 1e-7 of its first step, and a bound left
# within it would not be seen (the phase would then violate it until the next
# crossing).
#
# landing_margin [1]: rolling starts at theta_c; the landing surface lies a
# hair below it, (1 - landing_margin) theta_c, so a column that uplifts on the
# verge of the threshold (theta'' ~ 0) does not start on the landing surface,
# where round-off would trip the event at once.
#
# min_rebound [rad]: a rebound that would rise less than this above theta_c is
# a settling: shorter excursions than an integration step could slip past the
# landing event (and with theta_c = 0 the column would never settle otherwise).
#
# slaved_turn [rad]: where the contact frame turns fast (phi' ~ 1e6 near the
# vertical) a lag of slave_time would let it turn far; the layer's edge shrinks
# so that the frame turns at most about slaved_turn within the lag (layer_edge).
NUMERICS = declared(
    Option("landing_margin", 1e-3, "1", "number", "landing surface's depth below theta_c, a fraction of it", 0.0,
           open_lo=True),
    Option("min_rebound", 1e-8, "rad", "number", "smallest rebound above theta_c that is not a settling", 0.0,
           open_lo=True),
    Option("slave_time", 1e-6, "1", "number", "lag of a slaved slip direction, in units of sqrt(R/g)", 0.0,
           open_lo=True),
    Option("look_ahead", 1e-7, "1", "number", "look-ahead of a phase started on a bound, in units of sqrt(R/g)",
           0.0, open_lo=True),
    Option("slaved_turn", 1e-3, "rad", "number", "largest turn of the contact frame within the slaving lag", 0.0,
           open_lo=True),
)

# The state vector of the 3D kernel (pipeline.dynamics.rigid.frustum): its slots by name, and the
# kernel's index constant of each (tests/test_models.py checks them against the kernel)
STATE_3D = StateLayout("pipeline.dynamics.rigid.frustum", "N_STATE", (
    ("phi", "PHI"), ("theta", "THETA"), ("psi", "PSI"), ("phi_dot", "DPHI"), ("theta_dot", "DTHETA"),
    ("omega_zeta", "OMEGA"), ("x_p", "XP"), ("y_p", "YP"), ("work", "WORK"), ("dissipated", "DISSIPATED"),
    ("friction", "FRICTION"), ("slip_speed", "SLIP_SPEED"), ("slip_direction", "SLIP_DIR"), ("z_c", "ZC"),
    ("v_x", "VX"), ("v_y", "VY"), ("v_z", "VZ")))
# planar rocking (pipeline.dynamics.rigid.rocking): x, v along the incidence direction mean the pivot or the
# base centre or the centre of mass, by phase
STATE_2D = StateLayout("pipeline.dynamics.rigid.rocking", "N_STATE2", (
    ("theta", "THETA2"), ("theta_dot", "DTHETA2"), ("work", "WORK2"), ("dissipated", "DISSIPATED2"),
    ("friction", "FRICTION2"), ("x", "X2"), ("v", "V2"), ("z", "Z2"), ("v_z", "VZ2")))

# the time histories each writes, by catalog name (pipeline.dataset.VARIABLES, FLAGS)
_HISTORIES = ("phi", "theta", "x_p", "y_p", "x_b", "y_b", "theta_dot", "omega_zeta", "energy_hat", "normal_force_hat",
              "tangential_force_hat", "mu_mob", "slip_velocity", "ground_acc_x", "ground_acc_y", "ground_acc_z",
              "phase")
HISTORIES_2D = _HISTORIES
HISTORIES_3D = _HISTORIES + ("psi", "phi_dot", "psi_dot")

# what a study keeps of a run, by catalog name (pipeline.dataset)
RESULTS = ("peak_theta", "peak_theta_ratio", "peak_time", "overturn_time", "uplift_time", "peak_mu_mob",
           "residual_rotation", "residual_displacement", "work_ground", "energy_balance_error", "n_impacts",
           "overturned", "undecided", "uplifted", "sliding_onset", "lift_off")
# what both rigid models share: a monolith, the same kernels' thresholds and results, one runner
_RIGID = dict(bodies=("column",), numeric_options=NUMERICS, results=RESULTS,
              runner="pipeline.simulate:simulate_rigid",
              # its impact law, contact tilt and couple, friction, ground that only pushes or holds the rim,
              # contact patch (k_n, c_n), tail and settle limit, tolerances
              options=read("restitution", "contact_tilt", "damping", "friction", "lift_off", "normal_stiffness",
                           "contact_damping", "tail", "settle_limit", "rtol", "atol"))

ROLLING_FRUSTUM = Model(
    name="3d",
    description=ModelDescription(
        title="3D rolling frustum",
        body="one rigid, homogeneous conical frustum (a cone with its tip cut off) standing free on its base",
        follows=("rocking and wobbling: rolling on the rim of the base, the contact point travelling around it",
                 "spin about its own axis", "sliding of the base and slip of the rim on the ground",
                 "uplift and flight", "overturning"),
        contact=_RIGID_CONTACT.format(pivot="rolls on the rim of the base", rim="rim")
        + " The column is axisymmetric, so its results do not depend on the incidence angle.",
        sliding_onset="the base slid or the rim slipped on the ground (friction reached mu N); the motion follows it",
        lift_off="the column lifted off into flight (the normal force reached zero); the motion follows it",
        cite=CITE,
        reference=f"{REFERENCE} (the 3D rolling frustum; its contact: docs/model.md)",
    ),
    in_short="rigid conical frustum rolling on the rim of its base (the paper)",
    angle_invariant=True,
    planar=False,
    state=STATE_3D,
    histories=HISTORIES_3D,
    entry_points=(("pipeline.dynamics.rigid.run3d", "run_frustum"),
                  ("pipeline.dynamics.rigid.diagnostics", "diagnostics_rows")),
    **_RIGID,
    style=MappingProxyType(dict(ls="-", marker="o", filled=True, band_alpha=0.12)),
)

PLANAR_ROCKING = Model(
    name="2d",
    description=ModelDescription(
        title="2D planar rocking",
        body="the same rigid frustum, held in the vertical plane of the incidence angle (classical planar "
        "rocking)",
        follows=("rocking on one edge of the base and the other, driven by the component of the record along the "
                 "incidence angle", "sliding of the base and slip of the edge on the ground", "uplift and flight",
                 "overturning"),
        contact=_RIGID_CONTACT.format(pivot="rocks on an edge of the base", rim="edge")
        + " It neither wobbles nor spins.",
        sliding_onset="the base slid or its edge slipped on the ground (friction reached mu N); the motion follows it",
        lift_off="the column lifted off into flight (the normal force reached zero); the motion follows it",
        cite="Housner 1963",
        reference="Housner G.W. (1963), The behavior of inverted pendulum structures during earthquakes, Bulletin "
        "of the Seismological Society of America 53(2), 403-417 (the 2D planar rocking; its contact: "
        "docs/model.md)",
    ),
    in_short="planar rocking in the vertical plane of the X component of the turned pair",
    angle_invariant=False,
    planar=True,
    planar_of=ROLLING_FRUSTUM.name,
    state=STATE_2D,
    histories=HISTORIES_2D,
    entry_points=(("pipeline.dynamics.rigid.run2d", "run_rocking"),
                  ("pipeline.dynamics.rigid.diagnostics", "diagnostics_rows")),
    **_RIGID,
    style=MappingProxyType(dict(ls="--", marker="s", filled=False, band_alpha=0.07)),
)
