"""What a study is, once its file is checked: the frozen :class:`Study` and its parts.

:class:`Study` holds the grid (columns x records x incidence angles x scales x models), the
models' options and where the results go; :class:`ColumnInfo`, :class:`RecordSpec` and
:class:`Intensity` are its columns, records and intensity targets. They are made by
:func:`pipeline.study.studyfile.parse_study`, never by hand-checked dicts.
"""

import math
from dataclasses import dataclass

from pipeline.structures.column import Column
from pipeline.models import REGISTRY
from pipeline.settings import ModelSettings

__all__ = ["Study", "ModelVariant", "ColumnInfo", "RecordSpec", "Intensity", "Seeds", "variant_settings", "BODIES",
           "BED_OPTIONS"]

#: What a variant may run instead of its model's own body: the column's outline as one body.
BODIES = ("outline",)
#: The options a calibrated bed (``[calibration] bed``) gives every model: its dashpots and the
#: restitution they reach.
BED_OPTIONS = ("contact_damping", "restitution")


@dataclass(frozen=True)
class ModelVariant:
    """A model of a study: a registry model under a name of its own (``[models.NAME]``).

    Attributes
    ----------
    name : str
        Its name in the study and the results (``model`` coordinate).
    model : str
        The registry model it runs.
    options : tuple of (str, object)
        Keyword arguments of :class:`pipeline.settings.ModelSettings` over the study's ``[options]``.
    numerics : tuple of (str, float)
        Overrides of the model's numerical choices (``ModelSettings.numerics``).
    body : str
        ``""``: what the model runs (the drums for a model of drums); ``"outline"``: the
        column's outline as one body.
    """

    name: str
    model: str
    options: tuple = ()
    numerics: tuple = ()
    body: str = ""

    @property
    def drums(self):
        """Whether it runs a column's drums (a model of drums, not told to run the outline)."""
        return REGISTRY[self.model].drums and self.body != "outline"

    @property
    def colonnade(self):
        """Whether it runs a column's colonnade (a model of colonnades)."""
        return REGISTRY[self.model].runs("colonnade")

    def describe(self):
        """What makes it a variant, in words (``"body = outline; numerics edge_band = 1"``), or ""."""
        parts = [f"body = {self.body}"] if self.body else []
        parts += [f"numerics {k} = {v:g}" if isinstance(v, float) else f"numerics {k} = {v}" for k, v in self.numerics]
        parts += [f"options {k} = {v:g}" if isinstance(v, (int, float)) else f"options {k} = {v}"
                  for k, v in self.options]
        return "; ".join(parts)


@dataclass(frozen=True)
class Seeds:
    """A study's imperfect drums (``[imperfections]``): the results' dimension ``seed``.

    Attributes
    ----------
    tolerance : float
        [m] (:mod:`pipeline.structures.imperfections`).
    seeds : tuple of int
        One imperfect structure per seed, the values of the dimension ``seed``.
    friction_range : tuple of float or None
        ``(lo, hi)`` [1] each joint of a column draws its friction from; None: the options'.
    models : tuple of str
        The study's models that draw them (the others run perfect drums once, repeated along ``seed``).
    """

    tolerance: float
    seeds: tuple
    friction_range: tuple | None
    models: tuple

    def options(self, seed):
        """The model options of the imperfect structure of ``seed``."""
        return (("imperfections", self.tolerance), ("seed", seed), ("friction_range", self.friction_range))


def variant_settings(variant, options, bed=None):
    """:class:`pipeline.settings.ModelSettings` of a :class:`ModelVariant` over a study's ``[options]``.

    Parameters
    ----------
    variant : ModelVariant
    options : tuple of (str, object)
        The study's options; the variant's own override them.
    bed : tuple of float, optional
        ``(c_n [Pa s/m], restitution [1])`` of a calibrated bed, given as ``contact_damping``
        and ``restitution``.
    """
    merged = {**dict(options), **dict(variant.options)}
    if bed is not None:
        merged.update(zip(BED_OPTIONS, bed))
    if variant.numerics:
        merged["numerics"] = variant.numerics
    return ModelSettings(model=variant.model, **merged)


@dataclass(frozen=True)
class ColumnInfo:
    """A column of the study and what is known about it.

    Attributes
    ----------
    column : pipeline.structures.column.Column
    label : str
        Unique label in the results (``column`` coordinate).
    latitude, longitude : float
        Position [degree] of a named real column, NaN otherwise.
    source : str
        Where the dimensions come from.
    stack : pipeline.structures.drums.DrumColumn or None
        The column as drums (and capital) that the compliant model runs; None: the monolith
        ``column``. The rigid models always run ``column``, the shaft as one body.
    colonnade : pipeline.structures.colonnade.Colonnade or None
        A row of the column (``stack``, or the monolith) carrying an epistyle, which the models
        of colonnades run; None: the column stands alone.
    """

    column: Column
    label: str
    latitude: float = math.nan
    longitude: float = math.nan
    source: str = ""
    stack: object = None
    colonnade: object = None

    @property
    def n_bodies(self):
        """Rigid bodies of the compliant model: drums and capital (1 for a monolith)."""
        return 1 if self.stack is None else self.stack.n_bodies

    @property
    def n_joints(self):
        """Joints of the compliant model: one per body of a column; a colonnade's columns', its blocks'
        bearings on the capitals and the head joints between blocks."""
        if self.colonnade is not None:
            return self.colonnade.n_joints
        return self.n_bodies

    def describe(self):
        """What stands, in words: the colonnade it stands in, its drums and capital, or the column alone."""
        if self.colonnade is not None:  # without its name when that is the label the results show
            text = self.colonnade.describe()
            return text.removeprefix(f"{self.label}: ")
        return (self.stack or self.column).describe()

    def body(self, variant):
        """What a :class:`ModelVariant` runs: the colonnade for a model of colonnades, the drums for a model of
        drums, else the shaft as a monolith."""
        stack = None if variant.body == "outline" else self.stack
        return REGISTRY[variant.model].structure(self.column, stack, self.colonnade)


@dataclass(frozen=True)
class RecordSpec:
    """Where one record comes from: a catalog id, a file or a synthesis.

    Attributes
    ----------
    kind : {"catalog", "file", "synthetic"}
    id : str
        Record label in the results (the catalog id, the file's id, the
        synthetic record's id).
    path : str or tuple of str
        Absolute file path, or 2-3 paths forming one record (kind "file").
    units : str or None
        Units of a file that does not state them.
    components : tuple or None
        Channel codes or trace ids of x, y[, z] (y None: y = 0).
    missing_y : {"error", "zero"}
        A file with one horizontal component: an error, or y = 0.
    dt : float or None
        Time step [s] of a text file without a time column.
    processing : tuple of dict
        Steps run after loading (:func:`pipeline.groundmotion.processing.apply`).
    generator : str
        Synthesis function (kind "synthetic").
    params : tuple of (str, object)
        Its keyword arguments.
    field : str
        Where it was given in the study file, for messages.
    """

    kind: str
    id: str
    path: str | tuple = ""
    units: str | None = None
    components: tuple | None = None
    missing_y: str = "error"
    dt: float | None = None
    processing: tuple = ()
    generator: str = ""
    params: tuple = ()
    field: str = ""

    def load(self):
        """Load the record as a :class:`pipeline.groundmotion.GroundMotion` (SI)."""
        from pipeline.groundmotion import load, synthesis

        if self.kind == "catalog":
            return load(self.id)
        if self.kind == "file":
            return load(list(self.path) if isinstance(self.path, tuple) else self.path, units=self.units,
                        components=self.components, missing_y=self.missing_y, dt=self.dt,
                        processing=list(self.processing) or None)
        func = getattr(synthesis, self.generator)
        return func(**dict(self.params), record_id=self.id)


@dataclass(frozen=True)
class Intensity:
    """Scaling to target intensity levels instead of fixed factors.

    Attributes
    ----------
    measure : {"pga", "pgv"}
        Peak of the horizontal acceleration [m/s^2] or velocity [m/s] vector
        (independent of the incidence angle), as the ``pga``/``pgv`` results.
    values : tuple of float
        Target levels in SI units ([m/s^2] or [m/s]).
    units : str
        The unit the study file stated them in (``"g"``, ``"m/s2"``,
        ``"m/s"``, ``"cm/s"``).
    stated : tuple of float
        The levels as the study file gives them, in ``units``.
    """

    measure: str
    values: tuple
    units: str = "m/s2"
    stated: tuple = ()


@dataclass(frozen=True)
class Study:
    """A validated study.

    Attributes
    ----------
    path : str
        The study file (absolute).
    digest : str
        SHA-256 of the study file's bytes.
    title, summary : str
    output : str
        Results file (absolute).
    columns : tuple of ColumnInfo
    records : tuple of RecordSpec
    angles : tuple of float
        Incidence angles [degree].
    scales : tuple of float or None
        Factors on the records, or None with ``intensity``.
    intensity : Intensity or None
    models : tuple of str
        Names of the study's models (the registry's, or the study's variants').
    variants : tuple of ModelVariant
        With ``[models.NAME]`` tables: one per model, in order; empty for a list of registry names.
    calibration : str or None
        The model whose contact dashpots are calibrated on each column's outline and given,
        with the restitution they reach, to every model (``[calibration] bed``).
    vertical : bool
        Use the records' vertical components.
    components : str
        ``"pair"``: the records' horizontal pair as recorded; ``"x"``: the x component alone (y set
        to zero before the records are scaled, so the stripes are its peaks), turned by the angles.
    sa_period : float or None
        Period [s] of the reported spectral acceleration.
    options : tuple of (str, object)
        Keyword arguments of :class:`pipeline.settings.ModelSettings` (no model).
    block_columns : int or None
        Columns per task (None: automatic).
    """

    path: str
    digest: str
    title: str
    summary: str
    output: str
    columns: tuple
    records: tuple
    angles: tuple
    scales: tuple | None
    intensity: Intensity | None
    models: tuple
    vertical: bool
    sa_period: float | None
    options: tuple
    block_columns: int | None
    variants: tuple = ()
    calibration: str | None = None
    components: str = "pair"
    imperfections: Seeds | None = None

    @property
    def seeds(self):
        """The values of the results' dimension ``seed`` (``[imperfections] seeds``); () without one."""
        return () if self.imperfections is None else self.imperfections.seeds

    def seeded(self, name):
        """Whether the study's model ``name`` draws imperfect drums from each seed."""
        return self.imperfections is not None and name in self.imperfections.models

    @property
    def grid_shape(self):
        """Shape of the results' arrays: :attr:`shape`, and the seeds with ``[imperfections]``."""
        return self.shape + ((len(self.seeds),) if self.seeds else ())

    @property
    def levels(self):
        """Values of the ``scale`` dimension: factors, or intensity targets."""
        return self.scales if self.scales is not None else self.intensity.values

    @property
    def shape(self):
        """(columns, records, angles, scales, models)."""
        return (len(self.columns), len(self.records), len(self.angles), len(self.levels), len(self.models))

    @property
    def n_simulations(self):
        """Size of the grid, seeds included (3D runs are shared over angles, see pipeline.study.run)."""
        return math.prod(self.grid_shape)

    @property
    def n_joints(self):
        """Length of the results' ``joint`` dimension: the most joints of a column (a colonnade's, where it
        carries one) when the compliant model is run, else 0 (no such dimension)."""
        if not any(self.variant(m).drums for m in self.models):
            return 0
        return max(c.n_joints if c.colonnade is not None and any(self.variant(m).colonnade and self.variant(m).drums
                                                                  for m in self.models) else c.n_bodies
                   for c in self.columns)

    @property
    def registry_models(self):
        """The registry models the study runs, each once (its variants' models)."""
        return tuple(dict.fromkeys(self.variant(m).model for m in self.models))

    def beds(self):
        """The calibrated bed of every column: ``(c_n [Pa s/m], restitution [1])`` each, or () without one.

        The dashpots of the :attr:`calibration` model calibrated on each column's outline (its
        registry entry's :meth:`pipeline.models.spec.Model.calibrate`, cached per process), and
        the restitution they reach: every model of the study gets both, so that a difference
        between the models is the models', not their beds'.
        """
        if self.calibration is None:
            return ()
        settings = self.settings(self.calibration)
        model = REGISTRY[settings.model]
        return tuple(model.calibrate(c.column, settings) for c in self.columns)

    def variant(self, name):
        """The :class:`ModelVariant` of a model of the study (a registry name: that model as it is)."""
        return next((v for v in self.variants if v.name == name), None) or ModelVariant(name, name)

    def settings(self, name, bed=None, seed=None):
        """:class:`pipeline.settings.ModelSettings` of one model of the study.

        Parameters
        ----------
        name : str
            A name of :attr:`models`.
        bed : tuple of float, optional
            ``(c_n [Pa s/m], restitution [1])`` of the calibrated bed (:attr:`calibration`),
            given to the model as ``contact_damping`` and ``restitution``.
        seed : int, optional
            A model that draws imperfect drums (:meth:`seeded`): the seed of its structure (default
            the first of :attr:`seeds`).
        """
        options = self.options
        if self.seeded(name):
            options = options + self.imperfections.options(self.seeds[0] if seed is None else seed)
        return variant_settings(self.variant(name), options, bed)
