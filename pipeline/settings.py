"""Typed inputs of a simulation: the model and its options, the excitation, the initial state.

Every model reads its inputs from here, and every input is checked here, once, when it is
made (a bad value raises :class:`pipeline.errors.InputError` naming the field and the range):

* :class:`ModelSettings`: the model (a name of the registry, :mod:`pipeline.models`) and its
  options, each default written once (friction [1], stiffnesses [Pa/m], damping, tolerances,
  tail [s], ...); the numerical choices each model declares in its registry entry, and the
  compliant integrators (:data:`INTEGRATORS`). It imports no kernel: the command's help
  reads its defaults without loading numba.
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
from pipeline.models.compliant import COMPLIANT_DRUMS
from pipeline.errors import InputError
from pipeline.units import G, deg_to_rad

# Geometry the model is meant for: free-standing columns and drums, from
# squat drums to slender monoliths, from pebbles to the largest monoliths.
RADIUS_RANGE = (1e-3, 50.0)  # [m]
SLENDERNESS_RANGE = (0.05, 200.0)  # h/R [1]
BETA_RANGE = (0.05, 20.0)  # r/R [1]

# the range of the compliant model's numerical choices (pipeline.models.compliant), and what each is
_NUMERICS_RANGES = {
    "edge_band": (0.05, 5.0, "width of the band past a face's edge, in spacings of the outer rings of contact points"),
    "step_safety": (0.01, 0.9, "fixed step as a fraction of the stability limit of the stiffest joint"),
}
# Integrators of the compliant model: the fixed-step semi-implicit one (default) and the
# adaptive ones it is checked against (its registry entry).
INTEGRATORS = COMPLIANT_DRUMS.integrators


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
        ``slave_time``, ``look_ahead``, ``slaved_turn``; the compliant model's ``edge_band``
        and ``step_safety``), for studies that show what they move; e.g.
        ``(("slave_time", 1e-5),)``.
    tail : float
        Free motion after the record ends [s].
    rtol, atol : float
        Integration tolerances (dimensionless state).
    output_step : float
        Sampling interval of the time histories [s].
    integrator : {"semi-implicit", "dopri5", "dop853"}
        Integrator of the compliant-contact model: fixed steps of the
        semi-implicit scheme of DEM codes (default; springs explicit,
        dashpots implicit, friction by return to the Coulomb cone:
        :mod:`pipeline.dynamics.compliant.semi_implicit`), or the adaptive DOPRI5 it
        is checked against (``rtol``, ``atol``), or DOP853 before it
        (:mod:`pipeline.dynamics.integrators.dopri5`). The rigid models always use DOP853.
    step : float or None
        Fixed step of the semi-implicit integrator [s]; None: ``step_safety``
        (``numerics``, default 0.5) times the stability limit ``2 / omega_max``
        of the stiffest joint mode (its statistics are taken at every step,
        its history rows interpolated between steps; ``monitor_step`` is the
        adaptive integrators' sampling).
        A step above the stability limit is refused before computing.
    joint_stiffness, stiffness_ratio, contact_rings, contact_sectors, joint_friction, \
anathyrosis, base_anathyrosis, monitor_step
        Options of the compliant-contact model ``"3d-compliant"`` (there
        ``normal_stiffness`` and ``friction`` are the base's and
        ``restitution`` the target of the damping calibration); see
        :mod:`pipeline.compliant`.
    """

    model: str = models.DEFAULT
    restitution: float | None = None
    contact_tilt: float | None = None
    damping: float = 0.0
    friction: float = 0.7
    lift_off: bool = True
    normal_stiffness: float = 1.0e10
    contact_damping: float | None = None
    numerics: tuple = ()
    tail: float = 5.0
    rtol: float = 1e-9
    atol: float = 1e-12
    output_step: float = 0.01
    joint_stiffness: float | None = None
    stiffness_ratio: float = 0.5
    contact_rings: int = 3
    contact_sectors: int = 24
    joint_friction: float | tuple | None = None
    anathyrosis: float | tuple = 0.0
    base_anathyrosis: float = 0.0
    monitor_step: float = 0.001
    integrator: str = "semi-implicit"
    step: float | None = None

    def __post_init__(self):
        model = models.get(self.model)  # an unknown name is refused with the choices
        checks = {
            "damping": (0.0, 100.0, "(per m g R sqrt(R/g))"),
            "tail": (0.0, 3600.0, "s"),
        }
        for name, (lo, hi, unit) in checks.items():
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and lo <= value <= hi):
                raise InputError(f"{name} = {value!r} {unit} must be a number in [{lo:g}, {hi:g}]")
        if self.contact_tilt is not None and not (
                isinstance(self.contact_tilt, (int, float)) and 0.0 <= self.contact_tilt <= 0.5):
            raise InputError(f"contact_tilt = {self.contact_tilt!r} deg must be a number in [0, 0.5] "
                             "(or omitted: the compliance of the bed sets it)")
        if not (isinstance(self.friction, (int, float)) and (self.friction == math.inf or
                                                              0.0 < self.friction <= 10.0)):
            raise InputError(f"friction = {self.friction!r} must be a number in (0, 10], or inf for rolling "
                             "without slip")
        if not (isinstance(self.normal_stiffness, (int, float)) and 1e6 <= self.normal_stiffness <= math.inf):
            raise InputError(f"normal_stiffness = {self.normal_stiffness!r} Pa/m must be a number in [1e6, inf]")
        if self.contact_damping is not None and not (
                isinstance(self.contact_damping, (int, float)) and 0.0 <= self.contact_damping < math.inf):
            raise InputError(f"contact_damping = {self.contact_damping!r} Pa s/m must be a number >= 0 "
                             "(or omitted for critical damping)")
        for name, value in dict(self.numerics).items():  # the numerical choices the model declares
            if name not in model.numerics:
                raise InputError(f"numerics: {name!r} is not a numerical choice of the {model.name} model; "
                                 f"choose from {', '.join(model.numerics)}")
            if name in _NUMERICS_RANGES:
                _number(value, f"numerics: {name}", *_NUMERICS_RANGES[name][:2], "", _NUMERICS_RANGES[name][2])
            elif not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise InputError(f"numerics: {name} = {value!r} must be a positive number")
        for name in ("rtol", "atol", "output_step"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise InputError(f"{name} = {value!r} must be a positive number")
        if self.restitution is not None and not (0.0 <= self.restitution <= 1.0):
            raise InputError(f"restitution = {self.restitution!r} must be between 0 and 1 (or omitted)")
        _check_compliant(self, model)


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


# -- the compliant model's fields ------------------------------------------------------------

_STIFFNESS = (1e6, 1e14, "Pa/m", "normal stiffness of the joints per unit area")
_RANGES = {  # name: (low, high, unit, what)
    "stiffness_ratio": (1e-3, 10.0, "", "shear/normal stiffness ratio of the joints"),
    "base_anathyrosis": (0.0, 0.95, "", "inner/outer radius of the base's contact ring (0: full disc)"),
    "monitor_step": (1e-5, 1.0, "s", "sampling interval of the peak and contact statistics of the adaptive integrators"),
}


def _number(value, name, lo, hi, unit, what):
    ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
    if not (ok and lo <= value <= hi):
        raise InputError(f"{name} = {value!r} {unit}: the {what} must be a number in [{lo:g}, {hi:g}]".replace("  ", " "))
    return float(value)


def _whole(settings, name, lo, hi, even=False):
    value = getattr(settings, name)
    ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value) and value == int(value)
    if not (ok and lo <= value <= hi and (not even or int(value) % 2 == 0)):
        kind = "an even whole number" if even else "a whole number"
        raise InputError(f"{name} = {value!r} must be {kind} from {lo} to {hi}")
    object.__setattr__(settings, name, int(value))


def _number_or_list(settings, name, lo, hi, what):
    value = getattr(settings, name)
    if value is None:
        return
    if isinstance(value, (list, tuple)):
        checked = tuple(_number(v, f"{name}[{i}]", lo, hi, "", what) for i, v in enumerate(value))
        if not checked:
            raise InputError(f"{name} is an empty list: give one number, or one per bed joint (bottom first)")
        object.__setattr__(settings, name, checked)
    else:
        object.__setattr__(settings, name, _number(value, name, lo, hi, "", what))


def _check_compliant(settings, model):
    """Check (and normalise) the compliant-model fields of a ModelSettings, naming the field.

    Called by ``ModelSettings.__post_init__`` for every model: the fields exist for all.
    Whole-number fields given as floats (study files) become ints; lists become tuples.
    """
    for name, (lo, hi, unit, what) in _RANGES.items():
        object.__setattr__(settings, name, _number(getattr(settings, name), name, lo, hi, unit, what))
    if settings.integrator not in INTEGRATORS:
        raise InputError(f"integrator = {settings.integrator!r} is unknown; choose one of {', '.join(INTEGRATORS)} "
                         "(semi-implicit, the default, takes fixed steps; dopri5 is the adaptive reference, "
                         "dop853 the one before it)")
    if settings.step is not None:
        object.__setattr__(settings, "step", _number(settings.step, "step", 1e-7, 0.01, "s",
                                                     "fixed step of the semi-implicit integrator"))
        if settings.integrator != "semi-implicit":
            raise InputError(f"step = {settings.step:g} s is the fixed step of the semi-implicit integrator; "
                             f"integrator = {settings.integrator!r} chooses its own steps (set rtol/atol instead)")
    _whole(settings, "contact_rings", 2, 8)
    _whole(settings, "contact_sectors", 4, 256, even=True)
    if settings.joint_stiffness is not None:
        lo, hi, unit, _ = _STIFFNESS
        object.__setattr__(settings, "joint_stiffness", _number(
            settings.joint_stiffness, "joint_stiffness", lo, hi, unit, "normal stiffness of the bed joints per unit area"))
    if settings.contact_damping is not None:
        object.__setattr__(settings, "contact_damping", _number(
            settings.contact_damping, "contact_damping", 0.0, 1e12, "Pa s/m",
            "normal damping of the joints per unit area (omit it to calibrate it to the restitution)"))
    _number_or_list(settings, "joint_friction", 1e-3, 100.0, "friction coefficient of the bed joints")
    _number_or_list(settings, "anathyrosis", 0.0, 0.95, "inner/outer radius of the bed joints' contact ring")
    if model.drums:
        # the rigid models also take an infinite stiffness and friction (the paper's point contact
        # rolling without slip); the joints of contact points need finite ones
        _number(settings.normal_stiffness, "normal_stiffness", *_STIFFNESS)
        if not math.isfinite(settings.friction):
            raise InputError("friction = inf is the rigid models' rolling without slip; the compliant model "
                             "needs a finite friction coefficient at the base (e.g. 10 for no sliding)")


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
