"""The options a model may read, declared once: :class:`Option` and the table :data:`OPTIONS`.

One declaration per option (name, default, unit, kind, range, what None stands for, words for
help and errors) and one validator, :meth:`Option.check`. Everything else reads them:
:class:`pipeline.settings.ModelSettings` takes its fields' defaults from :data:`OPTIONS` and
checks every field with it; each registry entry names the options it reads
(``Model.options``), from which the study whitelist and the ``frustum simulate`` flags come.
The models' numerical choices (``Model.numerics``) are declared with the same class, in their
entries' modules.

Plain data, below the registry: it imports only the ground floor.
"""

import math
from dataclasses import dataclass
from types import MappingProxyType

from pipeline.errors import InputError
from pipeline.limits import ATOL_RANGE, RTOL_RANGE
from pipeline.structures.imperfections import FRICTION_RANGE, SEED_RANGE

__all__ = ["Option", "KINDS", "OPTIONS", "INTEGRATORS", "declared", "defaults"]

#: What an option's value may be: a number, a whole number, a number or a list of numbers (one per
#: bed joint), a range of two numbers (lo, hi), one of a few words, or true/false.
KINDS = ("number", "whole", "numbers", "range", "choice", "bool")


@dataclass(frozen=True)
class Option:
    """One option of a model: what it is, its default, its unit and the values it may take.

    Attributes
    ----------
    name : str
        The field of :class:`pipeline.settings.ModelSettings` (a study's option; its flag is the
        name with dashes for underscores, e.g. ``--joint-friction``).
    default : object
        Its default, written here once.
    unit : str
        Its unit (``"1"``: dimensionless).
    kind : str
        One of :data:`KINDS`.
    words : str
        What it is, a noun phrase for help and errors ("Coulomb friction coefficient of ...").
    lo, hi : float
        Its range of a number, closed (``open_lo``: the lower end is excluded).
    open_lo : bool
        The lower end of the range is excluded.
    none : str
        What None stands for; "" if None is refused.
    inf : str
        What ``inf`` stands for, if it is allowed; "" if refused.
    choices : tuple of str
        The values of a choice, the default first.
    even : bool
        A whole number must be even.
    note : str
        More words for the help (how the choices differ, ...).
    metavar : str
        The placeholder of its value in the help.
    read_with : tuple of (str, tuple)
        When it is read at all: pairs (another option, the values under which this one is read),
        every pair to hold; e.g. ``(("step", (None,)),)``: read only while ``step`` is not given.
        Empty: read whenever its model runs. A study refuses it given where it is not read
        (:meth:`unread_with`).
    """

    name: str
    default: object
    unit: str
    kind: str
    words: str
    lo: float = -math.inf
    hi: float = math.inf
    open_lo: bool = False
    none: str = ""
    inf: str = ""
    choices: tuple = ()
    even: bool = False
    note: str = ""
    metavar: str = ""
    read_with: tuple = ()

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"option {self.name}: kind {self.kind!r} is not one of {KINDS}")

    def range_text(self):
        """``"(0, 10], or inf for rolling without slip"``: the values a number may take, in words."""
        if self.kind == "choice":
            return "one of " + ", ".join(self.choices)
        if self.kind == "bool":
            return "true or false"
        lo, hi = (f"{int(v)}" if self.kind == "whole" and math.isfinite(v) else f"{v:g}" for v in (self.lo, self.hi))
        text = f"{'(' if self.open_lo else '['}{lo}, {hi}{')' if self.hi == math.inf else ']'}"
        return text + (f", or inf for {self.inf}" if self.inf else "")

    def unread_with(self, settings):
        """What in ``settings`` leaves this option unread (``"step = 0.005"``), or "" if it is read.

        Parameters
        ----------
        settings : pipeline.settings.ModelSettings
            The settings of a model that declares the option (:attr:`read_with` names their fields).
        """
        for name, values in self.read_with:
            value = getattr(settings, name)
            if value not in values:
                return f"{name} = {value:g}" if isinstance(value, float) else f"{name} = {value}"
        return ""

    def read_with_text(self):
        """``"only with step not given and integrator semi-implicit"``: :attr:`read_with` in words, or ""."""
        parts = [f"{name} not given" if values == (None,) else f"{name} {' or '.join(map(str, values))}"
                 for name, values in self.read_with]
        return "only with " + " and ".join(parts) if parts else ""

    def check(self, value, label=None):
        """``value`` if it is one this option takes, normalised (float, int, tuple); else InputError.

        Parameters
        ----------
        value : object
        label : str, optional
            How the value was given, for the message (default: the option's name).

        Raises
        ------
        pipeline.errors.InputError
            Naming the label, the value, what the option is, its range and what to give instead.
        """
        label = label or self.name
        if value is None and self.none:
            return None
        if self.kind == "choice":
            if value not in self.choices:
                note = f" ({self.note})" if self.note else ""
                raise InputError(f"{label} = {value!r} is unknown; choose one of {', '.join(self.choices)}{note}")
            return value
        if self.kind == "bool":
            if not isinstance(value, bool):
                raise InputError(f"{label} = {value!r}: the {self.words} must be true or false")
            return value
        if self.kind == "range":
            return self._range(value, label)
        if self.kind == "numbers" and isinstance(value, (list, tuple)):
            if not value:
                raise InputError(f"{label} is an empty list: give one number, or one per bed joint (bottom first)")
            return tuple(self._number(v, f"{label}[{i}]", omit=False) for i, v in enumerate(value))
        return self._number(value, label)

    def _range(self, value, label):
        """Two numbers ``lo <= hi``, each in the option's range, as a tuple of floats."""
        if isinstance(value, (list, tuple)) and len(value) == 2:
            lo, hi = (self._number(v, f"{label}[{i}]", omit=False) for i, v in enumerate(value))
            if lo <= hi:
                return lo, hi
        unit = "" if self.unit == "1" else f" {self.unit}"
        note = f" ({self.note})" if self.note else ""
        raise InputError(f"{label} = {value!r}{unit}: the {self.words} must be two numbers LO,HI with LO <= HI, "
                         f"each in {self.range_text()}{note}")

    def _number(self, value, label, omit=True):
        ok = isinstance(value, (int, float)) and not isinstance(value, bool)
        if ok and value == math.inf and self.inf:
            return float(value)
        ok = ok and math.isfinite(value) and (self.lo < value if self.open_lo else self.lo <= value) and value <= self.hi
        whole = self.kind == "whole"
        if ok and whole:
            ok = value == int(value) and (not self.even or int(value) % 2 == 0)
        if not ok:
            what = "an even whole number" if self.even else "a whole number" if whole else "a number"
            unit = "" if self.unit == "1" else f" {self.unit}"
            omit = f" (or omit it: {self.none})" if self.none and omit else ""
            raise InputError(f"{label} = {value!r}{unit}: the {self.words} must be {what} in {self.range_text()}{omit}")
        return int(value) if whole else float(value)

    def help(self, default=None):
        """Help of its flag: words, unit, default (``default`` in words, if given, instead) and range."""
        if default is None:
            default = (f"default: {self.none}" if self.default is None else
                       f"default {str(self.default).lower()}" if isinstance(self.default, (str, bool))
                       else f"default {self.default:g}")
        unit = "" if self.kind in ("choice", "bool") else f" [{self.unit}]"
        note = f"; {self.note}" if self.note else ""
        inf = f"; inf: {self.inf}" if self.inf else ""
        return f"{self.words}{unit} ({default}{inf}{note})"


def declared(*options):
    """A read-only mapping name -> :class:`Option` of ``options``, in the order given."""
    return MappingProxyType({o.name: o for o in options})


def defaults(options):
    """``{name: default}`` of a mapping of declarations."""
    return MappingProxyType({name: o.default for name, o in options.items()})


_BED = "the bed joints (between drums)"
#: The compliant model's integrators, the default first: the fixed-step one, then the adaptive ones.
_INTEGRATORS = ("semi-implicit", "dopri5", "dop853")
#: Every option of a model (:class:`pipeline.settings.ModelSettings`), in the order help lists them.
OPTIONS = declared(
    Option("restitution", None, "1", "number", "theta' after / before a planar landing", 0.0, 1.0,
           none="angular momentum conservation about the new pivot, 1 - 2 m R^2 / I_P", metavar="E"),
    Option("contact_tilt", None, "deg", "number", "tilt below which the base is in full contact", 0.0, 0.5,
           none="the compliance of the bed sets it: the tilt theta_k where it loses full contact under the weight",
           note="0 for planar motion only", metavar="DEG"),
    Option("damping", 0.0, "1", "number", "viscous contact couple per m g R sqrt(R/g)", 0.0, 100.0, metavar="NU"),
    Option("friction", 0.7, "1", "number", "Coulomb friction coefficient of the base on the ground", 0.0, 10.0,
           open_lo=True, inf="rolling without slip (the rigid models)",
           note="beyond it the base slides, or its rim slips", metavar="MU"),
    Option("lift_off", True, "1", "bool", "ground that can only push (the column flies when it would pull)",
           note="false holds the rim on the ground whatever the force, as the paper's model does"),
    Option("normal_stiffness", 1.0e10, "Pa/m", "number", "normal stiffness of the base's bed per unit area",
           1e6, math.inf, inf="the paper's point contact (the rigid models)", metavar="PA_M"),
    Option("contact_damping", None, "Pa s/m", "number", "normal dashpots of the joints per unit area", 0.0, 1e12,
           none="critical damping of the column bouncing on its base; the compliant model calibrates it to the "
           "restitution, which needs a bed stiff enough to rock on", metavar="PA_S_M"),
    Option("tail", 5.0, "s", "number", "free motion after the record ends", 0.0, 3600.0, metavar="S"),
    Option("settle_limit", 60.0, "s", "number", "longest free motion after the tail to decide the outcome", 0.0,
           3600.0, note="a column that could still overturn when the tail ends runs on with the ground still until "
           "its energy is below the lowest overturning barrier with its swing past its peak, it rests or it falls; "
           "one still undecided then is reported undecided (fragility and reports count it as standing by "
           "default: --undecided)", metavar="S"),
    Option("rtol", 1e-9, "1", "number", "relative tolerance of the adaptive integrators", *RTOL_RANGE,
           note="below 1e-14 the integrator's steps shrink to nothing"),
    Option("atol", 1e-12, "1", "number", "absolute tolerance of the adaptive integrators (dimensionless state)",
           *ATOL_RANGE, note="0 is no tolerance"),
    Option("output_step", 0.01, "s", "number", "sampling interval of the histories", 0.0, open_lo=True,
           metavar="S"),
    Option("joint_stiffness", None, "Pa/m", "number", f"normal stiffness of {_BED} per unit area", 1e6, 1e14,
           none="the base's, normal_stiffness", metavar="PA_M"),
    Option("stiffness_ratio", 0.5, "1", "number", "shear/normal stiffness ratio of the joints", 1e-3, 10.0,
           metavar="RATIO"),
    Option("contact_rings", 3, "1", "whole", "number of rings of contact points over a joint's face", 2, 8,
           metavar="N"),
    Option("contact_sectors", 24, "1", "whole", "number of sectors of contact points around a joint's face", 4,
           256, even=True, metavar="N"),
    Option("joint_friction", None, "1", "numbers", f"friction coefficient of {_BED}", 1e-3, 100.0,
           none="the base's, friction", note="one value, or one per bed joint of a single column bottom first",
           metavar="MU[,MU...]"),
    Option("anathyrosis", 0.0, "1", "numbers", f"inner/outer radius of the contact ring of {_BED}", 0.0, 0.95,
           none="full faces, as 0",
           note="0: the full face; one value, or one per bed joint of a single column bottom first",
           metavar="RATIO[,...]"),
    Option("base_anathyrosis", 0.0, "1", "number", "inner/outer radius of the base's contact ring", 0.0, 0.95,
           note="0: the full disc", metavar="RATIO"),
    # imperfect drums (pipeline.structures.imperfections): a tolerance, a seed, a friction range
    Option("imperfections", None, "m", "number", "tolerance of the drums' beds (each bed offset and out of level by "
           "up to it, drawn from the seed)", 0.0, 0.5, none="perfect drums",
           note="at most 5 % of the smallest bed diameter; with seed", metavar="TOL_M"),
    Option("seed", None, "1", "whole", "seed of the imperfections' draw", *SEED_RANGE,
           none="no imperfections", note="the same seed draws the same imperfections", metavar="N"),
    Option("friction_range", None, "1", "range", "range of friction coefficients each joint of a column draws from",
           *FRICTION_RANGE, none="the friction and joint_friction given",
           note="with imperfections; replaces friction and joint_friction at the columns' joints", metavar="LO,HI"),
    Option("monitor_step", 0.001, "s", "number",
           "sampling interval of the peak and contact statistics of the adaptive integrators", 1e-5, 1.0, metavar="S",
           read_with=(("integrator", _INTEGRATORS[1:]),)),  # the fixed-step one takes them at every step
    Option("integrator", "semi-implicit", "1", "choice", "integrator of the compliant model",
           choices=_INTEGRATORS,
           note="semi-implicit takes fixed steps, springs and dashpots at the step's end (fast); dopri5 is the "
           "adaptive reference (rtol, atol; drum stacks take minutes), dop853 the one before it"),
    Option("step", None, "s", "number", "fixed step of the semi-implicit integrator", 1e-7, 0.01,
           none="step_safety (numerics) times the stability limit of the stiffest joint with explicit springs; "
           "with numerics springs = explicit a step at or above the limit is refused", metavar="S"),
)

#: The compliant model's integrators, the default first (its registry entry's).
INTEGRATORS = OPTIONS["integrator"].choices
