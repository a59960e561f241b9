"""What a study is, once its file is checked: the frozen :class:`Study` and its parts.

:class:`Study` holds the grid (columns x records x incidence angles x scales x models), the
models' options and where the results go; :class:`ColumnInfo`, :class:`RecordSpec` and
:class:`Intensity` are its columns, records and intensity targets. They are made by
:func:`pipeline.study.studyfile.parse_study`, never by hand-checked dicts.
"""

import math
from dataclasses import dataclass

from pipeline.geometry import Column
from pipeline.models import REGISTRY
from pipeline.settings import ModelSettings

__all__ = ["Study", "ColumnInfo", "RecordSpec", "Intensity"]


@dataclass(frozen=True)
class ColumnInfo:
    """A column of the study and what is known about it.

    Attributes
    ----------
    column : pipeline.geometry.Column
    label : str
        Unique label in the results (``column`` coordinate).
    latitude, longitude : float
        Position [degree] of a named real column, NaN otherwise.
    source : str
        Where the dimensions come from.
    stack : pipeline.drums.DrumColumn or None
        The column as drums (and capital) that the compliant model runs; None: the monolith
        ``column``. The rigid models always run ``column``, the shaft as one body.
    """

    column: Column
    label: str
    latitude: float = math.nan
    longitude: float = math.nan
    source: str = ""
    stack: object = None

    @property
    def n_bodies(self):
        """Rigid bodies of the compliant model: drums and capital (1 for a monolith)."""
        return 1 if self.stack is None else self.stack.n_bodies

    def body(self, model):
        """What ``model`` (a name) runs: the drums for a model of drums, else the shaft as a monolith."""
        return self.stack if (self.stack is not None and REGISTRY[model].drums) else self.column


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
    vertical : bool
        Use the records' vertical components.
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
        """Size of the grid (3D runs are shared over angles, see pipeline.study.run)."""
        return math.prod(self.shape)

    @property
    def n_joints(self):
        """Length of the results' ``joint`` dimension: the most bodies of a column when the
        compliant model is run (joint k is the base of body k), else 0 (no such dimension)."""
        if not any(REGISTRY[m].drums for m in self.models):
            return 0
        return max(c.n_bodies for c in self.columns)

    def settings(self, model):
        """:class:`pipeline.settings.ModelSettings` of one model."""
        return ModelSettings(model=model, **dict(self.options))
