"""What a model declares: :class:`Model` (the registry's entries), :class:`ModelDescription` and
:class:`StateLayout`.

Plain data, below everything that reads it: a consumer asks an entry what it needs
(the body it runs, whether the incidence angle matters, its options and numerical choices,
its compiled kernels, its words for people) instead of comparing the model's name.
"""

from dataclasses import dataclass, field
from importlib import import_module
from types import MappingProxyType
from typing import NamedTuple

from pipeline.models.options import OPTIONS, declared, defaults
from pipeline.structures.kinds import KINDS

__all__ = ["Model", "ModelDescription", "StateLayout", "read"]


def read(*names):
    """The declarations (:data:`pipeline.models.options.OPTIONS`) of the options ``names``, in that order."""
    return declared(*(OPTIONS[name] for name in names))


class StateLayout(NamedTuple):
    """The state vector of a model's kernel, by name.

    Attributes
    ----------
    kernel : str
        The kernel module that lays the state out (``"pipeline.dynamics.rigid.frustum"``).
    size : str
        Its constant of the vector's (or, ``per`` a body, the block's) length (``"N_STATE"``).
    slots : tuple of (str, str)
        The components in order: (name, the kernel's index constant of it).
    per : str
        ``""``: the whole vector; ``"body"``: the block of each body, bottom first (a stack's
        vector goes on after the blocks with its contact points' and joints' states).
    """

    kernel: str
    size: str
    slots: tuple
    per: str = ""

    @property
    def names(self):
        """The components' names, in order."""
        return tuple(name for name, _ in self.slots)


class ModelDescription(NamedTuple):
    """What one model is, in words for people who do not program.

    Attributes
    ----------
    title : str
        Display name, e.g. in figure titles and the report's list of models.
    body : str
        What the column is in this model.
    follows : tuple of str
        The motions the model follows (computes), not merely flags.
    contact : str
        The contact law and where energy is lost.
    sliding_onset : str
        What a run counted by the ``sliding_onset`` flag did ("in N of M runs ...").
    lift_off : str
        What a run counted by the ``lift_off`` flag did.
    cite : str
        Where the model comes from, in running text.
    reference : str
        Where the model comes from, in full (the report's references).
    """

    title: str
    body: str
    follows: tuple
    contact: str
    sliding_onset: str
    lift_off: str
    cite: str
    reference: str


@dataclass(frozen=True)
class Model:
    """One entry of the registry (:mod:`pipeline.models`).

    Attributes
    ----------
    name : str
        The name users give (``ModelSettings.model``, study files, ``--model``) and the
        value of the CF ``model`` coordinate of results.
    description : ModelDescription
        Title and words for help, plots and reports.
    in_short : str
        What the model is in one line, for the comment of the CF ``model`` coordinate.
    bodies : tuple of str
        The kinds of structure it runs (:data:`pipeline.structures.kinds.KINDS`): ``"column"``, a
        monolithic :class:`pipeline.structures.column.Column`; ``"drums"``, a column built of drums
        (:class:`pipeline.structures.drums.DrumColumn`, and a capital); ``"colonnade"``, a row of
        columns carrying an epistyle (:class:`pipeline.structures.colonnade.Colonnade`). The first is
        what it runs when nothing else is said (a study's kernel warm-up, the contract test).
        :attr:`drums` is ``"drums" in bodies``.
    angle_invariant : bool
        Its results do not depend on the incidence angle (an axisymmetric column whose
        response turns with the record): a study runs it at one angle and repeats it.
    planar : bool
        Moves in the vertical plane of the incidence angle only (driven by the record's
        component along it).
    planar_of : str or None
        For a planar model, the name of the 3D model it is the planar counterpart of (reports
        compare the two).
    numeric_options : mapping of str to Option
        Its numerical choices that are not measured physics, declared with their defaults,
        units and ranges (:class:`pipeline.models.options.Option`; ``ModelSettings.numerics``
        overrides them; studies show what they move). :attr:`numerics` are their defaults.
    state : StateLayout
        Its kernel's state vector by name (or a stack's per body).
    histories : tuple of str
        The time histories a run writes, by catalog name (:data:`pipeline.dataset.VARIABLES` or
        ``FLAGS``; the catalog adds a ``NAME_deg`` twin of an angle people read).
    results : tuple of str
        The scalar results of one run that a study keeps, by catalog name
        (:data:`pipeline.dataset.STUDY_VARIABLES`): every run's summary holds them.
    entry_points : tuple of (str, str)
        Its compiled kernels as (module, function): compiled before a study's workers start and
        looked up in numba's cache.
    integrators : tuple of str
        The integrators ``ModelSettings.integrator`` may name for it, the default first (empty:
        the model has one, chosen by its kernels).
    runner : str
        ``"module:function"`` of its simulation, called as
        ``function(column, motion, excitation, settings, histories, progress)`` and returning a
        :class:`pipeline.response.Response` (imported when first run, so that the registry
        stays below the code it names).
    style : mapping
        How plots draw it: line style ``ls``, ``marker``, ``filled`` marker, ``band_alpha``
        (opacity of its bootstrap band).
    options : mapping of str to Option
        The options it reads (fields of :class:`pipeline.settings.ModelSettings`), declared in
        :data:`pipeline.models.options.OPTIONS` with defaults, units and ranges (:func:`read`): a
        study may set them (its ``[options]`` take any model's; a variant ``[models.NAME]`` only
        its model's) and ``frustum simulate`` has a flag for each.
    calibration : str
        ``"module:function"`` that calibrates its contact dashpots on a column's outline,
        called as ``function(column, settings)`` and returning ``(c_n [Pa s/m], restitution
        reached [1])`` (``[calibration] bed`` of a study); "" for a model that cannot.
    checker : str
        ``"module:function"`` that refuses, before anything is computed, what its run would refuse
        of a column with given settings (e.g. a fixed step above the column's stability limit):
        called as ``function(column, settings)``, raising :class:`pipeline.errors.InputError` whose
        message begins ``option = value`` when an option is at fault; "" for a model whose settings
        are checked in full by :class:`pipeline.settings.ModelSettings`.
    """

    name: str
    description: ModelDescription
    in_short: str
    bodies: tuple
    angle_invariant: bool
    planar: bool
    numeric_options: MappingProxyType
    state: StateLayout
    histories: tuple
    results: tuple
    entry_points: tuple
    runner: str
    integrators: tuple = ()
    style: MappingProxyType = field(default_factory=lambda: MappingProxyType({}))
    planar_of: str | None = None
    options: MappingProxyType = field(default_factory=lambda: MappingProxyType({}))
    calibration: str = ""
    checker: str = ""

    def __post_init__(self):
        unknown = [b for b in self.bodies if b not in KINDS]
        if not self.bodies or unknown or isinstance(self.bodies, str):
            raise ValueError(f"model {self.name}: bodies {self.bodies!r} must be a tuple of {', '.join(KINDS)}")

    @property
    def drums(self):
        """Whether it runs columns built of drums (``"drums"`` in :attr:`bodies`)."""
        return "drums" in self.bodies

    def runs(self, kind):
        """Whether it runs structures of ``kind`` (one of :data:`pipeline.structures.kinds.KINDS`)."""
        return kind in self.bodies

    def structure(self, column, stack=None, colonnade=None):
        """What it runs of a column given as its shaft, its drums and the colonnade it stands in: the colonnade
        if it runs colonnades, the drums if it runs drums, else the shaft as a monolith (``frustum simulate``
        and a study alike).

        Parameters
        ----------
        column : pipeline.structures.column.Column
            The shaft's outline.
        stack : pipeline.structures.drums.DrumColumn, optional
            The column as drums and a capital (None: the monolith).
        colonnade : pipeline.structures.colonnade.Colonnade, optional
            The row it stands in (None: it stands alone).
        """
        if colonnade is not None and self.runs("colonnade"):
            return colonnade
        if stack is not None and self.drums:
            return stack
        return column

    @property
    def numerics(self):
        """Its numerical choices' defaults, ``{name: value}``."""
        return defaults(self.numeric_options)

    @property
    def title(self):
        """Display name (``"3D rolling frustum"``)."""
        return self.description.title

    def run(self, column, motion, excitation, settings, histories=True, progress=None):
        """The response of ``column`` (a structure of one of :attr:`bodies`) to ``motion`` in this model (see
        :func:`pipeline.simulate.simulate`)."""
        module, function = self.runner.split(":")
        return getattr(import_module(module), function)(column, motion, excitation, settings, histories, progress)

    def calibrate(self, column, settings):
        """``(c_n [Pa s/m], restitution reached [1])`` of its dashpots on ``column``'s outline (:attr:`calibration`)."""
        module, function = self.calibration.split(":")
        damping, reached = getattr(import_module(module), function)(column, settings)
        return float(damping), float(reached)

    def check(self, column, settings):
        """Refuse, before computing, what a run of ``column`` with ``settings`` would refuse (:attr:`checker`)."""
        if self.checker:
            module, function = self.checker.split(":")
            getattr(import_module(module), function)(column, settings)

    def markdown(self):
        """The model's description as one Markdown bullet (the report's assumptions)."""
        d = self.description
        source = f", {d.cite}" if d.cite else ""
        return (f"- **{d.title}** (`{self.name}`{source}): {d.body}. It follows {'; '.join(d.follows)}. "
                f"{d.contact}").rstrip()
