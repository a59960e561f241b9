"""Typed inputs of a simulation: the model and its options, the excitation, the initial state.

Every model reads its inputs from here, and every input is checked here, once, when it is
made (a bad value raises :class:`pipeline.errors.InputError` naming the field and the range):

* :class:`ModelSettings`: the model (a name of the registry, :mod:`pipeline.models`) and its
  options, each declared once with its default, unit and range in
  :data:`pipeline.models.options.OPTIONS` (friction [1], stiffnesses [Pa/m], damping,
  tolerances, tail [s], ...) and checked by its one validator; the numerical choices each
  model declares in its registry entry, and the compliant integrators (:data:`INTEGRATORS`).
  It imports no kernel: the command's help reads its defaults without loading numba.
* :class:`Excitation`: how a record drives the column (incidence angle [deg], scale [1],
  vertical component).
* :class:`InitialState`: Euler angles [deg] and rates [rad/s] of a free motion.
* :func:`check_column`: the geometry the models are meant for (R [m], h/R, r/R).
* :func:`housner_restitution`: the restitution [1] a ``restitution`` left unset stands for.

It sits below the models (:mod:`pipeline.simulate`, :mod:`pipeline.compliant`) and the
studies, and imports only kernels' constants.
"""

import math
from dataclasses import dataclass

from pipeline import models
from pipeline.errors import InputError
from pipeline.models.options import INTEGRATORS, OPTIONS
from pipeline.structures.imperfections import Imperfections
from pipeline.units import G, deg_to_rad

# Geometry the model is meant for: free-standing columns and drums, from
# squat drums to slender monoliths, from pebbles to the largest monoliths.
RADIUS_RANGE = (1e-3, 50.0)  # [m]
SLENDERNESS_RANGE = (0.05, 200.0)  # h/R [1]
BETA_RANGE = (0.05, 20.0)  # r/R [1]

# the options' defaults, written once (pipeline.models.options)
_DEFAULT = {name: option.default for name, option in OPTIONS.items()}


@dataclass(frozen=True)
class InitialState:
    """Euler angles [deg] and their rates [rad/s] at t = 0 (the paper's Figure 2).

    Angles in degrees, as on the command line; :meth:`from_dimensionless`
    takes the paper's own radians and rates per tau.
    """

    phi: float = 0.0
    theta: float = 0.0
    psi: float = 0.0
    phi_dot: float = 0.0
    theta_dot: float = 0.0
    psi_dot: float = 0.0

    def __post_init__(self):
        for name in ("phi", "theta", "psi", "phi_dot", "theta_dot", "psi_dot"):
            value = getattr(self, name)
            if not math.isfinite(value):
                raise InputError(f"initial {name} = {value!r} must be a finite number")
        if not 0.0 < self.theta < 90.0:
            raise InputError(
                f"initial theta = {self.theta:g} deg: a free motion starts tilted on its rim, 0 < theta < 90 deg"
            )

    @property
    def angles_rad(self):
        """(phi, theta, psi) [rad]."""
        return deg_to_rad(self.phi), deg_to_rad(self.theta), deg_to_rad(self.psi)

    @classmethod
    def from_dimensionless(cls, radius, phi, theta, psi, dphi, dtheta, dpsi):
        """Build from the paper's dimensionless values: angles [rad], rates per tau, for a base radius [m]."""
        rate = math.sqrt(G / radius)
        return cls(math.degrees(phi), math.degrees(theta), math.degrees(psi), dphi * rate, dtheta * rate,
                   dpsi * rate)


@dataclass(frozen=True)
class ModelSettings:
    """The model and its options.

    Every option's default, unit and range is declared once in
    :data:`pipeline.models.options.OPTIONS` and checked here by its one validator
    (:meth:`pipeline.models.options.Option.check`); the rules that tie options together (a step
    only for the semi-implicit integrator, the drums' finite friction and stiffness, the
    numerics of the model) follow.

    Parameters
    ----------
    model : str
        A model of the registry (:func:`pipeline.models.names`): the rolling frustum of
        the paper, planar rocking (Housner), or rigid drums on joints of contact points.
    restitution : float, optional
        theta' after / before a landing [1]. Default (None): the impact
        conserves angular momentum about the new pivot (for planar rocking
        ``1 - 2 m R^2 / I_P``).
    contact_tilt : float or None
        theta_c [deg]: below this inclination the base is in full contact;
        rolling starts there after uplift and a landing happens there, and a
        passage through a minimum of theta near it slaps in part
        (docs/model.md). None (default): theta_k of the compliant bed
        (:func:`contact_tilt`). 0 is allowed for planar motion only.
    damping : float
        Viscous contact couple nu, per m g R sqrt(R/g) [1]; 0 is the paper's
        model without dissipation other than impacts.
    friction : float
        Coulomb friction coefficient of the base on the ground [1]: the base
        slides flat, or the rim slips, when the friction needed exceeds
        ``friction`` times the normal force. ``math.inf`` is the paper's
        rolling without slip.
    lift_off : bool
        The ground can only push: the column flies when the normal force
        would pull, and lands with an impact. False holds the rim on the
        ground whatever the force, as the paper's model does.
    normal_stiffness : float
        Normal stiffness of the bed joint per unit area, k_n [Pa/m]. The
        rigid models take from it the contact patch under the rim
        (:mod:`pipeline.dynamics.rigid.patch`: rolling damping and drilling
        friction); ``math.inf`` is the paper's point contact.
    contact_damping : float or None
        Normal dashpots of the joint per unit area, c_n [Pa s/m]; None: the
        critical damping of the column bouncing on its base,
        ``2 sqrt(k_n m / A)``. The compliant model calibrates it to
        ``restitution`` instead (:func:`pipeline.compliant.calibrated_damping`);
        its default target, the rigid value, is out of its reach and gives
        that critical damping too.
    numerics : tuple of (str, float)
        Overrides of the numerical choices the model declares (``Model.numerics`` of its
        registry entry: the rigid kernels' thresholds ``landing_margin``, ``min_rebound``,
        ``slave_time``, ``look_ahead``, ``slaved_turn``; the compliant model's ``edge_band``,
        ``step_safety`` and ``springs``), for studies that show what they move; e.g.
        ``(("slave_time", 1e-5),)``.
    tail : float
        Free motion after the record ends [s].
    settle_limit : float
        Longest free motion after the tail [s] to decide the outcome: a column that could still
        overturn when the tail ends runs on with the ground still until it cannot (its energy
        below the lowest overturning barrier, its swing past its peak), rests or falls; one not
        decided within it is reported ``undecided`` (docs/model.md, "The end of a run").
    rtol, atol : float
        Integration tolerances (dimensionless state).
    output_step : float
        Sampling interval of the time histories [s].
    integrator : {"semi-implicit", "dopri5", "dop853"}
        Integrator of the compliant-contact model: fixed steps of the
        semi-implicit scheme of DEM codes (default; springs and dashpots at
        the step's end, friction by return to the Coulomb cone:
        :mod:`pipeline.dynamics.compliant.semi_implicit`), or the adaptive DOPRI5 it
        is checked against (``rtol``, ``atol``), or DOP853 before it
        (:mod:`pipeline.dynamics.integrators.dopri5`). The rigid models always use DOP853.
    step : float or None
        Fixed step of the semi-implicit integrator [s]; None: ``step_safety``
        (``numerics``, default 1) times the stability limit ``2 / omega_max``
        of the stiffest joint mode with explicit springs (its statistics are
        taken at every step, its history rows interpolated between steps;
        ``monitor_step`` is the adaptive integrators' sampling). With
        ``numerics`` ``springs = "explicit"`` a step at or above that limit is
        refused before computing.
    imperfections, seed, friction_range
        Imperfect drums (the compliant model): the tolerance of their beds [m], the seed of the
        draw and the range of the joints' friction [1] (:attr:`imperfect`,
        :mod:`pipeline.structures.imperfections`).
    joint_stiffness, stiffness_ratio, contact_rings, contact_sectors, joint_friction, \
anathyrosis, base_anathyrosis, monitor_step
        Options of the compliant-contact model ``"3d-compliant"`` (there
        ``normal_stiffness`` and ``friction`` are the base's and
        ``restitution`` the target of the damping calibration); see
        :mod:`pipeline.compliant`.
    """

    model: str = models.DEFAULT
    restitution: float | None = _DEFAULT["restitution"]
    contact_tilt: float | None = _DEFAULT["contact_tilt"]
    damping: float = _DEFAULT["damping"]
    friction: float = _DEFAULT["friction"]
    lift_off: bool = _DEFAULT["lift_off"]
    normal_stiffness: float = _DEFAULT["normal_stiffness"]
    contact_damping: float | None = _DEFAULT["contact_damping"]
    numerics: tuple = ()
    tail: float = _DEFAULT["tail"]
    settle_limit: float = _DEFAULT["settle_limit"]
    rtol: float = _DEFAULT["rtol"]
    atol: float = _DEFAULT["atol"]
    output_step: float = _DEFAULT["output_step"]
    joint_stiffness: float | None = _DEFAULT["joint_stiffness"]
    stiffness_ratio: float = _DEFAULT["stiffness_ratio"]
    contact_rings: int = _DEFAULT["contact_rings"]
    contact_sectors: int = _DEFAULT["contact_sectors"]
    joint_friction: float | tuple | None = _DEFAULT["joint_friction"]
    anathyrosis: float | tuple = _DEFAULT["anathyrosis"]
    base_anathyrosis: float = _DEFAULT["base_anathyrosis"]
    imperfections: float | None = _DEFAULT["imperfections"]
    seed: int | None = _DEFAULT["seed"]
    friction_range: tuple | None = _DEFAULT["friction_range"]
    monitor_step: float = _DEFAULT["monitor_step"]
    integrator: str = _DEFAULT["integrator"]
    step: float | None = _DEFAULT["step"]

    def __post_init__(self):
        model = models.get(self.model)  # an unknown name is refused with the choices
        # every option against its declaration, normalised (whole numbers given as floats by study
        # files become ints, lists become tuples)
        for name, option in OPTIONS.items():
            object.__setattr__(self, name, option.check(getattr(self, name)))
        _check_numerics(self.numerics, model)
        _check_across(self, model)
        _check_imperfections(self)

    @property
    def imperfect(self):
        """The structure's imperfections (:class:`pipeline.structures.imperfections.Imperfections`) these
        settings draw, or None (perfect drums)."""
        if self.imperfections is None:
            return None
        return Imperfections(self.imperfections, self.seed, self.friction_range)


def _check_numerics(numerics, model):
    """Overrides of the numerical choices ``model`` declares, each against its declaration."""
    for name, value in dict(numerics).items():
        if name not in model.numeric_options:
            raise InputError(f"numerics: {name!r} is not a numerical choice of the {model.name} model; "
                             f"choose from {', '.join(model.numeric_options)}")
        model.numeric_options[name].check(value, f"numerics: {name}")


def _check_across(settings, model):
    """The rules that tie options together or to the model."""
    if settings.step is not None and settings.integrator != "semi-implicit":
        raise InputError(f"step = {settings.step:g} s is the fixed step of the semi-implicit integrator; "
                         f"integrator = {settings.integrator!r} chooses its own steps (set rtol/atol instead)")
    if model.drums:
        # the rigid models also take an infinite stiffness and friction (the paper's point contact
        # rolling without slip); the joints of contact points need finite ones
        joints = OPTIONS["joint_stiffness"]
        if not settings.normal_stiffness <= joints.hi:
            raise InputError(f"normal_stiffness = {settings.normal_stiffness!r} Pa/m: the {model.name} model's "
                             f"joints of contact points need a finite stiffness in [{joints.lo:g}, {joints.hi:g}] "
                             "(inf is the rigid models' point contact)")
        if not math.isfinite(settings.friction):
            raise InputError("friction = inf is the rigid models' rolling without slip; the compliant model "
                             "needs a finite friction coefficient at the base (e.g. 10 for no sliding)")


def _check_imperfections(settings):
    """Imperfections need a tolerance and a seed together, and no other per-joint friction beside a
    friction range (:mod:`pipeline.structures.imperfections`). A model that does not draw them does
    not read them (a study's ``[options]`` are every model's); ``frustum simulate`` and a study refuse
    them where no model draws them (:func:`pipeline.models.check_imperfect`)."""
    given = [name for name in models.IMPERFECTIONS if getattr(settings, name) is not None]
    if not given:
        return
    first = f"{given[0]} = {getattr(settings, given[0])!r}"
    if settings.imperfections is None:
        raise InputError(f"{first} draws imperfect drums: give imperfections too, the tolerance of their beds [m] "
                         "(0: the geometry perfect, only the friction drawn), or drop it")
    if settings.seed is None:
        raise InputError(f"imperfections = {settings.imperfections:g} m are drawn from a seed: give seed too, a whole "
                         "number (the same seed draws the same imperfections; several seeds: a study's "
                         "[imperfections] seeds)")
    if settings.friction_range is not None and isinstance(settings.joint_friction, tuple):
        raise InputError(f"friction_range = {settings.friction_range[0]:g},{settings.friction_range[1]:g} draws the "
                         "friction of every joint of a column, and joint_friction gives a list of its own: give one "
                         "of them")


@dataclass(frozen=True)
class Excitation:
    """How a record drives the column.

    Parameters
    ----------
    angle : float
        Incidence angle [degree]: the horizontal pair is turned
        counter-clockwise by it (:meth:`pipeline.groundmotion.GroundMotion.rotated`).
        Degrees as on the command line and in study files; :attr:`angle_rad`
        is what the kernels use.
    scale : float
        Factor on every component [1], > 0.
    vertical : bool
        Use the record's vertical component if it has one.
    """

    angle: float = 0.0
    scale: float = 1.0
    vertical: bool = True

    def __post_init__(self):
        if not (isinstance(self.scale, (int, float)) and math.isfinite(self.scale) and self.scale > 0):
            raise InputError(f"scale = {self.scale!r} must be a positive number")
        if not math.isfinite(self.angle):
            raise InputError(f"angle = {self.angle!r} must be a finite number of degrees")

    @property
    def angle_rad(self):
        """Incidence angle [rad]."""
        return deg_to_rad(self.angle)


def check_column(column):
    """Reject geometry outside the range the model is meant for, naming the value."""
    lo, hi = RADIUS_RANGE
    if not lo <= column.R <= hi:
        raise InputError(f"column R = {column.R:g} m is out of range [{lo:g}, {hi:g}] m")
    lo, hi = SLENDERNESS_RANGE
    if not lo <= column.slenderness <= hi:
        raise InputError(f"column slenderness h/R = {column.slenderness:g} is out of range [{lo:g}, {hi:g}]")
    lo, hi = BETA_RANGE
    if not lo <= column.beta <= hi:
        raise InputError(f"column conicity r/R = {column.beta:g} is out of range [{lo:g}, {hi:g}]")


# the restitution ModelSettings.restitution = None stands for, and the compliant model's
# default target of its damping calibration (pipeline.compliant.calibrated_damping)
def housner_restitution(column):
    """Coefficient of restitution of planar rocking from angular momentum conservation.

    Conserving the angular momentum about the new contact point, opposite
    the old one across the base, gives ``theta'_after / theta'_before =
    1 - 2 m R^2 / I_P = 1 - 2 / I_y_hat`` (docs/model.md). For a slender
    column this tends to Housner's ``1 - 1.5 sin^2(alpha)`` of the block with
    the same outline. Clipped at 0 for squat columns (I_y_hat < 2).
    """
    return max(0.0, 1.0 - 2.0 / column.inertia_transverse_hat)


#: The settings of a free motion (:func:`pipeline.simulate.simulate_free`): tight tolerances,
#: landing at theta = 0.
FREE_MOTION = ModelSettings(rtol=1e-12, atol=1e-14, contact_tilt=0.0)


__all__ = [
    "INTEGRATORS",
    "FREE_MOTION",
    "InitialState",
    "ModelSettings",
    "Excitation",
    "check_column",
    "housner_restitution",
]
