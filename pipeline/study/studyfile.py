"""The study file: TOML in, a frozen, validated :class:`pipeline.study.spec.Study` out.

A study is the grid columns x records x incidence angles x scales x models
with the options of the model and where the results go. :func:`load_study`
reads and checks the whole file before anything is computed: an unknown
field, a wrong type, an empty grid or a record that cannot be loaded raises
:class:`pipeline.errors.InputError` naming the file, the field and the fix.

Format (every length in metres, angles in degrees, accelerations in m/s^2;
see docs/studies.md for the full reference)::

    title = "Quickstart"
    output = "out/quickstart.nc"     # relative to the study file's folder
    models = ["3d", "2d"]            # default ["3d"]; also "3d-compliant" (run at every angle)
    # or, instead of the list, the study's models under names of their own (variants):
    # [models.stack-wide]
    # model = "3d-compliant"         # the registry model (default: the table's name)
    # numerics = { edge_band = 1.0 } # its numerical choices; options = {...}; body = "outline"
    # [calibration]
    # bed = "stack-wide"             # its dashpots, calibrated on each column, for every model

    [[columns]]                      # explicit dimensions ...
    name = "paper"
    R = 0.5
    r = 0.4
    h = 4.0
    [[columns]]                      # ... or a named real column (pipeline/data/columns.toml)
    named = "pompeys-pillar"
    [[columns]]                      # drums (and a capital [side, height]) for "3d-compliant";
    name = "stack"                   # the rigid models run the shaft as a monolith
    R = 0.5
    r = 0.4
    h = 4.0
    drums = 4                        # or drum_heights = [1.0, 1.5, 1.5] (bottom first, sum h)
    capital = [1.2, 0.5]
    [[columns]]                      # a colonnade of the column for "2d-frame" (the others run the column)
    name = "row"
    R = 0.5
    r = 0.4
    h = 4.0
    capital = [1.0, 0.4]
    colonnade = {columns = 2, interaxial = 2.0, epistyle_height = 0.5}   # epistyle_width, course_height
    [[columns]]
    colonnade = "parthenon-east"     # a named colonnade (pipeline/data/colonnades.toml): its column too;
                                     # {named = "parthenon-east", course_height = 1.9} adds a course on it

    [column_grid]                    # ... and/or a grid: R x slenderness h/R x beta r/R
    R = 0.5
    slenderness = [6.0, 8.0]
    beta = [0.8, 1.0]
    drums = [1, 4]                   # optional: x equal drums (labels end -d1, -d4)

    [records]
    ids = ["FEMA-FF-01"]             # catalog ids (frustum records list)
    sets = ["SYN"]                   # whole catalog sets
    files = [{path = "quake.mseed", units = "g"},
             {path = ["RSN6_ELC180.AT2", "RSN6_ELC270.AT2"], id = "elcentro"},   # a pair: x, y
             {path = "gm.g3", units = "g", dt = 0.01, missing_y = "zero"}]     # OpenSees input
    synthetic = [{generator = "ricker_wavelet", id = "ricker", ap = 3.0, fp = 2.0}]

    [excitation]
    angles = [0.0, 45.0, 90.0]       # [deg]
    scales = [0.5, 1.0, 2.0]         # factors on the record, or instead:
    # intensity = {measure = "pga", units = "g", values = [0.1, 0.2, 0.4]}   # units required
    vertical = true
    sa_period = 1.0                  # optional: also report Sa(T) [s]

    [options]                        # pipeline.settings.ModelSettings
    friction = 0.7

    [imperfections]                  # imperfect drums (3d-compliant): the results' dimension seed
    tolerance = 0.002                # [m]: beds offset and out of level by up to it
    seeds = [1, 2, 3]                # one imperfect structure per seed
    friction_range = [0.5, 0.7]      # optional: each joint of a column draws its friction
    models = ["3d-compliant"]        # optional: which of the study's models draw them (default: all that can)

    [execution]
    block_columns = 4                # columns per Dask task (default: automatic)
"""

import hashlib
import math
import tomllib
from collections import Counter
from pathlib import Path

from pipeline.structures.named import named_columns
from pipeline.structures.colonnade import Colonnade, named_colonnades
from pipeline.structures.drums import Capital, DrumColumn
from pipeline.errors import InputError
from pipeline.structures.column import Column
from pipeline.models import DEFAULT, IMPERFECTIONS, REGISTRY, check_imperfect, unrun_part
from pipeline.models.options import OPTIONS
from pipeline.settings import check_column
from pipeline.study.spec import (BED_OPTIONS, BODIES, ColumnInfo, Intensity, ModelVariant, RecordSpec, Seeds, Study,
                                 variant_settings)
from pipeline.units import G

__all__ = ["load_study", "load_motions", "parse_study"]

_TOP = {"title", "summary", "output", "models", "calibration", "columns", "column_grid", "records", "excitation",
        "options", "imperfections", "execution"}
_COLUMN = {"name", "R", "r", "h", "named"}
_DRUMS = {"drums", "drum_heights", "capital"}  # a column of drums (the compliant model)
# a row of the column carrying an epistyle (pipeline.structures.colonnade), for the models that run colonnades:
# a table of these, or the name of a colonnade of pipeline/data/colonnades.toml
_COLONNADE = {"columns", "interaxial", "epistyle_height", "epistyle_width", "course_height"}
# a named colonnade (pipeline/data/colonnades.toml) as a table, with a course added on its epistyle
_NAMED_COLONNADE = {"named", "course_height"}
_GRID = {"R", "slenderness", "beta"}
_GRID_OPTIONAL = {"drums"}  # a grid axis of drum counts (equal drums, no capital)
_RECORDS = {"ids", "sets", "files", "synthetic"}
_FILE = {"path", "units", "id", "components", "missing_y", "dt", "processing"}
_EXCITATION = {"angles", "scales", "intensity", "vertical", "sa_period", "components"}
#: ``[excitation] components``: the records' horizontal pair as recorded, or its x component alone (a drive in
#: one direction, turned by the angle: 0 along x, 90 across), the y set to zero before the record is scaled.
HORIZONTAL_COMPONENTS = ("pair", "x")
_INTENSITY = {"measure", "values", "units"}
# [options] may set what any model reads (each reads its own: Model.options); a variant only its model's
_OPTIONS = set().union(*(m.options for m in REGISTRY.values()))
_VARIANT = {"model", "options", "numerics", "body"}
_CALIBRATION = {"bed"}
_IMPERFECTIONS = {"tolerance", "seeds", "friction_range", "models"}
_EXECUTION = {"block_columns"}
_GENERATORS = ("one_sine_pulse", "cycloidal_pulse", "rectangular_pulse", "ricker_wavelet",
               "mavroeidis_papageorgiou", "harmonic", "kanai_tajimi", "clough_penzien")
INTENSITY_MEASURES = ("pga", "pgv")
#: Units a study may state its intensity targets in (factor to SI), per measure; no default.
INTENSITY_UNITS = {"pga": {"g": G, "m/s2": 1.0}, "pgv": {"m/s": 1.0, "cm/s": 0.01}}


def load_study(path, load_records=True):
    """Read and validate a study file.

    Parameters
    ----------
    path : str or os.PathLike
    load_records : bool
        Also load every record once, so that a record that cannot be loaded
        fails here, before any computation.

    Returns
    -------
    Study

    Raises
    ------
    InputError
        Naming the file and the field.
    """
    path = Path(path).resolve()
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise InputError(f"{path}: cannot read the study file ({exc.strerror}); check the path") from None
    try:
        data = tomllib.loads(raw.decode("utf-8"))
    except (UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise InputError(f"{path}: not a valid TOML file: {exc}") from None
    study = parse_study(data, path, hashlib.sha256(raw).hexdigest())
    if load_records:
        load_motions(study)
    return study


def load_motions(study):
    """Load every record of a study, in order (with ``components = "x"``, its x component alone).

    Returns
    -------
    list of pipeline.groundmotion.GroundMotion

    Raises
    ------
    InputError
        Naming the study file, the field and the record that cannot be loaded.
    """
    motions = []
    for spec in study.records:
        try:
            motion = spec.load()
            motions.append(motion.one_component("x") if study.components == "x" else motion)
        except Exception as exc:  # noqa: BLE001 - any loader failure is a bad field
            text = str(exc) if isinstance(exc, InputError) else f"{type(exc).__name__}: {exc}"
            raise InputError(f"{study.path}: field {spec.field}: record {spec.id!r} cannot be loaded: {text}") from None
    return motions


class _Checker:
    """Type checks that name the file and the field."""

    def __init__(self, path):
        self.path = path

    def fail(self, field, message):
        raise InputError(f"{self.path}: field {field}: {message}")

    def table(self, value, field, allowed):
        if not isinstance(value, dict):
            self.fail(field, f"must be a table, got {type(value).__name__}")
        unknown = sorted(set(value) - allowed)
        if unknown:
            self.fail(f"{field}.{unknown[0]}" if field else unknown[0],
                      f"unknown field; allowed here: {', '.join(sorted(allowed))}")
        return value

    def number(self, value, field, positive=False, lo=None, hi=None):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            self.fail(field, f"must be a number, got {value!r}")
        value = float(value)
        if positive and value <= 0:
            self.fail(field, f"must be positive, got {value!r}")
        if (lo is not None and value < lo) or (hi is not None and value > hi):
            self.fail(field, f"{value!r} is out of range [{lo}, {hi}]")
        return value

    def numbers(self, value, field, positive=False, scalar_ok=False):
        if scalar_ok and not isinstance(value, list):
            value = [value]
        if not isinstance(value, list):
            self.fail(field, f"must be a list of numbers, got {type(value).__name__}")
        if not value:
            self.fail(field, "is empty: give at least one value (an empty grid computes nothing)")
        out = tuple(self.number(v, f"{field}[{i}]", positive) for i, v in enumerate(value))
        if len(set(out)) != len(out):
            self.fail(field, f"has repeated values {list(out)}; give each value once")
        return out

    def unique(self, values, field, message):
        """Fail on the first value (in sorted order) given more than once; ``message`` formats it as {!r}."""
        counts = Counter(values)
        dup = sorted(v for v, n in counts.items() if n > 1)
        if dup:
            self.fail(field, message.format(dup[0]))

    def string(self, value, field):
        if not isinstance(value, str) or not value.strip():
            self.fail(field, f"must be a non-empty string, got {value!r}")
        return value

    def strings(self, value, field):
        if not isinstance(value, list):
            self.fail(field, f"must be a list of strings, got {type(value).__name__}")
        return [self.string(v, f"{field}[{i}]") for i, v in enumerate(value)]


def parse_study(data, path="<study>", digest=""):
    """Validate a study given as a dict (parsed TOML); see :func:`load_study`."""
    path = Path(path)
    ck = _Checker(path)
    ck.table(data, "", _TOP)
    title = ck.string(data.get("title", path.stem), "title")
    summary = data.get("summary", "")
    if not isinstance(summary, str):
        ck.fail("summary", "must be a string")
    given = ck.string(data.get("output", f"{path.stem}.nc"), "output")
    output = (path.parent / given).resolve()
    if given.endswith(("/", "\\")) or not output.name or output.is_dir():
        ck.fail("output", f"{given!r} is a folder; give the path of a file, e.g. out/{path.stem}.nc "
                "(its checkpoint folder, FILE.checkpoint, goes beside it)")
    output = str(output)
    models, variants = _models(data.get("models", [DEFAULT]), ck)
    columns = _columns(data, ck)
    records = _records(data.get("records"), ck, path)
    angles, scales, intensity, vertical, sa_period, components = _excitation(data.get("excitation"), ck)
    options = _options(ck, data.get("options", {}), "options", _OPTIONS)
    named = {v.name: v for v in variants}  # empty for a list of registry names
    imperfections = _imperfections(data.get("imperfections"), ck, models, named, options)
    for m in models:
        try:
            variant_settings(named.get(m, ModelVariant(m, m)), options)
        except InputError as exc:
            ck.fail(f"models.{m}" if m in named else "options", str(exc))
    _check_bodies(ck, models, named, columns)
    calibration = _calibration(data.get("calibration"), ck, models, named)
    execution = ck.table(data.get("execution", {}), "execution", _EXECUTION)
    block = execution.get("block_columns")
    if block is not None and (isinstance(block, bool) or not isinstance(block, int) or block < 1):
        ck.fail("execution.block_columns", f"must be a positive integer, got {block!r}")
    study = Study(
        path=str(path), digest=digest, title=title, summary=summary, output=output, columns=columns,
        records=records, angles=angles, scales=scales, intensity=intensity, models=models, vertical=vertical,
        components=components,
        sa_period=sa_period, options=options, block_columns=block, variants=variants, calibration=calibration,
        imperfections=imperfections,
    )
    _refuse_unread(ck, data, study)
    _check_runs(ck, study, len(data.get("columns", [])))
    return study


def _refuse_unread(ck, data, study):
    """Refuse what no model of the study would read: it would be ignored, and the results would
    look as if it had been taken (the registry says what each model reads: ``Model.options``,
    ``Model.numerics``, ``Model.drums``; an option's ``read_with`` when it is read at all).

    * an ``[options]`` key that no model of the study reads, naming the models that do;
    * a variant's option or numerical choice that its own settings leave unread (``step_safety``
      beside a given ``step``);
    * with ``[calibration] bed``: ``contact_damping`` (every model gets the bed's dashpots) and a
      variant's ``restitution`` (every model but the bed gets the restitution the bed reaches);
    * a colonnade in a study none of whose models runs colonnades, and drums (``drums``,
      ``drum_heights``, ``capital``, ``[column_grid] drums``) in a study none of whose models runs drums
      (a colonnade's capital is read by a model of colonnades), in the words of ``frustum simulate``
      (:func:`pipeline.models.unrun_part`).
    """
    variants = [study.variant(m) for m in study.models]
    bed = study.calibration

    def unread(variant, key, own):
        """Why ``variant`` does not read option ``key`` (of its own table or of ``[options]``), or ""."""
        model = REGISTRY[variant.model]
        if key not in model.options:
            return f"{variant.name} does not read it"
        if not own and key in dict(variant.options):
            return f"{variant.name} sets its own, models.{variant.name}.options.{key}"
        if bed is not None and key in BED_OPTIONS and (key != "restitution" or variant.name != bed):
            # the bed model reads a restitution as its calibration's target
            return f"{variant.name} gets the calibrated bed's, [calibration] bed = {bed!r}"
        why = model.options[key].unread_with(study.settings(variant.name))
        return f"{variant.name} does not read it with {why}" if why else ""

    for key, _ in study.options:
        if key in IMPERFECTIONS:  # in the words of frustum simulate --imperfections
            try:
                check_imperfect([v.model for v in variants], f"options.{key}")
            except InputError as exc:
                ck.fail(f"options.{key}", str(exc))
        reasons = [unread(v, key, own=False) for v in variants]
        if all(reasons):
            readers = [m.name for m in REGISTRY.values() if key in m.options]
            fix = "remove it" if any(key in REGISTRY[v.model].options for v in variants) else \
                f"it is an option of {', '.join(readers)}: remove it, or run a model that reads it"
            ck.fail(f"options.{key}",
                    f"no model of the study reads {key} ({'; '.join(reasons)}){_when(OPTIONS[key])}; {fix}")
    for v in study.variants:
        for key, _ in v.options:
            why = unread(v, key, own=True)
            if why:
                ck.fail(f"models.{v.name}.options.{key}", f"{why}{_when(OPTIONS[key])}: remove it")
        numerics = REGISTRY[v.model].numeric_options
        for key, _ in v.numerics:
            why = numerics[key].unread_with(study.settings(v.name))
            if why:
                ck.fail(f"models.{v.name}.numerics.{key}", f"{v.name} does not read {key} with {why}"
                        f"{_when(numerics[key])}: give one of them")
    rows = any(v.colonnade for v in variants)
    if not rows:
        fields = [f"columns[{i}].colonnade" for i, entry in enumerate(data.get("columns", [])) if "colonnade" in entry]
        if fields:
            ck.fail(fields[0], unrun_part("colonnade", study.models, "colonnade", "the study", "remove"))
    if not any(v.drums for v in variants):
        # a colonnade's capital is read by a model of colonnades (the rigid frame's column carries it)
        fields = [(f"columns[{i}].{k}", k) for i, entry in enumerate(data.get("columns", []))
                  for k in sorted(_DRUMS) if k in entry and not (k == "capital" and rows and "colonnade" in entry)]
        if "drums" in data.get("column_grid", {}):
            fields.append(("column_grid.drums", "drums"))
        if fields:
            field, key = fields[0]
            ck.fail(field, unrun_part("drums", study.models, key, "the study", "remove"))


def _when(option):
    """`` (read only with ...)`` of an option with conditions, or ""."""
    text = option.read_with_text()
    return f" (read {text})" if text else ""


def _check_runs(ck, study, n_entries):
    """Refuse, before any record is loaded or anything computed, what a model's runs would refuse of
    a column (``Model.check``: a colonnade the model cannot run, a fixed step above the stability
    limit), for every column as each model runs it (its colonnade, its drums, or the monolith), naming
    the field of the option at fault, or the column's (``n_entries`` of them are ``[[columns]]``
    entries, the rest ``[column_grid]``'s) when the column is."""
    for name in study.models:
        variant = study.variant(name)
        model = REGISTRY[variant.model]
        if not model.checker:
            continue
        for seed in study.seeds if study.seeded(name) else (None,):  # each imperfect structure
            settings = study.settings(name, seed=seed)
            for k, info in enumerate(study.columns):
                try:
                    model.check(info.body(variant), settings)
                except InputError as exc:
                    column = f"columns[{k}]" if k < n_entries else "column_grid"
                    ck.fail(_field_at_fault(study, variant, str(exc), column),
                            f"column {info.label!r}, model {name}: {exc}")


def _field_at_fault(study, variant, message, column):
    """The field of the option a message begins with (``step = ...``): the variant's own options, else
    ``[options]``; the variant's table, or ``options``, if it names a numerical choice of the model; else
    the ``column``'s own field, whose structure the model refuses."""
    for prefix, given in ((f"models.{variant.name}.options", variant.options), ("options", study.options)):
        for key, _ in given:
            if message.startswith(f"{key} = "):
                return f"{prefix}.{key}"
    if study.seeded(variant.name) and message.startswith("imperfections = "):
        return "imperfections.tolerance"
    numerics = REGISTRY[variant.model].numeric_options
    if any(message.startswith(f"{key} = ") for key in numerics) or message.startswith("step = "):
        return f"models.{variant.name}" if study.variants else "options"
    return column


def _imperfections(section, ck, models, named, options):
    """``[imperfections]``: the study's imperfect drums, one structure per seed (:class:`Seeds`), or None.

    Its models (``models``, default every model of the study that draws imperfections) run once per
    seed; the others once, repeated along the results' dimension ``seed``.
    """
    if section is None:
        return None
    ck.table(section, "imperfections", _IMPERFECTIONS)
    base = {m: named[m].model if m in named else m for m in models}
    given = [f"options.{k}" for k, _ in options if k in IMPERFECTIONS] + [
        f"models.{m}.options.{k}" for m in named for k, _ in named[m].options if k in IMPERFECTIONS]
    if given:
        ck.fail(given[0], "the study's [imperfections] draws the imperfect drums, one structure per seed: give the "
                f"tolerance, seeds and friction range there, not {given[0].rsplit('.', 1)[1]} in the options")
    drawing = section.get("models")
    if drawing is None:
        drawing = [m for m in models if "imperfections" in REGISTRY[base[m]].options]
        try:
            check_imperfect([base[m] for m in models], "[imperfections]")
        except InputError as exc:
            ck.fail("imperfections", str(exc))
    else:
        drawing = ck.strings(drawing, "imperfections.models")
        ck.unique(drawing, "imperfections.models", "model {!r} is named twice")
        for i, m in enumerate(drawing):
            if m not in models:
                ck.fail(f"imperfections.models[{i}]", f"{m!r} is not a model of the study; give some of "
                        f"{', '.join(models)}")
            try:
                check_imperfect([base[m]], f"imperfections.models[{i}] = {m!r}")
            except InputError as exc:
                ck.fail(f"imperfections.models[{i}]", str(exc))
    for key in ("tolerance", "seeds"):
        if key not in section:
            ck.fail(f"imperfections.{key}", "missing: [imperfections] needs a tolerance [m] and seeds (a list of "
                    "whole numbers, one imperfect structure each)")
    tolerance = _checked(ck, "imperfections", ck.number(section["tolerance"], "imperfections.tolerance"),
                         "imperfections.tolerance")
    seeds = section["seeds"]
    if not isinstance(seeds, list) or not seeds:
        ck.fail("imperfections.seeds", f"must be a non-empty list of whole numbers, one imperfect structure each; "
                f"got {seeds!r}")
    seeds = tuple(_checked(ck, "seed", v, f"imperfections.seeds[{i}]") for i, v in enumerate(seeds))
    ck.unique([str(v) for v in seeds], "imperfections.seeds", "seed {} is given twice: each seed draws one structure")
    friction = section.get("friction_range")
    if friction is not None:
        friction = _checked(ck, "friction_range", friction, "imperfections.friction_range")
    return Seeds(tolerance, seeds, friction, tuple(drawing))


def _checked(ck, name, value, field):
    """``value`` checked by the declaration of the option ``name``, failing at ``field``."""
    try:
        return OPTIONS[name].check(value, field)
    except InputError as exc:
        ck.fail(field, str(exc))


def _options(ck, table, field, allowed):
    """Checked model options of a table (``[options]`` or a variant's ``options``), sorted by name.

    Each is checked against its declaration (:data:`pipeline.models.options.OPTIONS`); a study's
    numbers are finite (no lists, no inf) and kept as floats.
    """
    options = ck.table(table, field, allowed)
    checked = {}
    for key, value in options.items():
        option = OPTIONS[key]
        if option.kind in ("number", "whole", "numbers"):
            value = ck.number(value, f"{field}.{key}")
        try:
            normal = option.check(value)
        except InputError as exc:
            ck.fail(f"{field}.{key}", str(exc))
        checked[key] = normal if option.kind == "range" else value  # a range as a tuple, hashable
    return tuple(sorted(checked.items()))


def _models(value, ck):
    """``models``: a list of registry names, or ``[models.NAME]`` tables of variants.

    Returns
    -------
    tuple
        ``(names, variants)``: the model axis, and its :class:`ModelVariant` per name (empty
        for a list).
    """
    if isinstance(value, dict):  # [models.NAME] tables: variants under names of their own
        if not value:
            ck.fail("models", f"is empty: give one or more [models.NAME] tables with model = one of {', '.join(REGISTRY)}")
        variants = tuple(_variant(name, entry, ck) for name, entry in value.items())
        return tuple(v.name for v in variants), variants
    models = tuple(ck.strings(value, "models"))
    if not models:
        ck.fail("models", f"is empty: give one or more of {', '.join(REGISTRY)}")
    for i, m in enumerate(models):
        if m not in REGISTRY:
            ck.fail(f"models[{i}]", f"{m!r} is unknown; choose from {', '.join(REGISTRY)}")
    if len(set(models)) != len(models):
        ck.fail("models", "has repeated models")
    return models, ()


def _numeric(ck, option, value, field):
    """One numerical choice of a variant: a number, or one of its words (``springs = "explicit"``)."""
    if option.kind != "choice":
        return ck.number(value, field)
    if value not in option.choices:
        ck.fail(field, f"{value!r} is unknown; choose one of {', '.join(map(repr, option.choices))} ({option.note})")
    return value


def _variant(name, entry, ck):
    """One ``[models.NAME]`` table: a registry model with its own options, numerics and body."""
    field = f"models.{name}"
    if not isinstance(entry, dict):
        ck.fail(field, f"must be a table ([models.{name}] with model = one of {', '.join(REGISTRY)})")
    ck.table(entry, field, _VARIANT)
    base = entry.get("model", name)
    if base not in REGISTRY:
        ck.fail(f"{field}.model", f"{base!r} is not a model; choose one of {', '.join(REGISTRY)}")
    if name != base and name in REGISTRY:  # its results would be labelled as the other model's
        ck.fail(field, f"a variant of {base} may not be named {name!r}, the name of the registry model {name} "
                f"({REGISTRY[name].title}): give it a name of its own, one no registry model has "
                f"({', '.join(REGISTRY)})")
    model = REGISTRY[base]
    given = entry.get("options", {})
    for key in given if isinstance(given, dict) else ():
        if key in OPTIONS and key not in model.options:
            readers = ", ".join(m.name for m in REGISTRY.values() if key in m.options) or "no model"
            ck.fail(f"{field}.options.{key}", f"{base} does not read {key}, an option of {readers}: remove it, "
                    "or give it to a variant of a model that reads it")
    options = _options(ck, given, f"{field}.options", set(model.options))
    numerics = ck.table(entry.get("numerics", {}), f"{field}.numerics", set(model.numerics))
    numerics = tuple(sorted((k, _numeric(ck, model.numeric_options[k], v, f"{field}.numerics.{k}"))
                            for k, v in numerics.items()))
    body = entry.get("body", "")
    if body != "" and body not in BODIES:
        ck.fail(f"{field}.body", f"{body!r} is not a body; give body = {' or '.join(map(repr, BODIES))} (the "
                "column's outline as one body), or leave it out for what the model runs")
    if "body" in entry and not model.drums:
        runners = ", ".join(m.name for m in REGISTRY.values() if m.drums)
        ck.fail(f"{field}.body", f"{base} runs the column's outline as one body already, so body would be "
                f"ignored; body is read by models of drums ({runners}): remove it")
    return ModelVariant(name, base, options, numerics, body)


def _calibration(section, ck, models, named):
    """``[calibration] bed = NAME``: the model whose dashpots every model gets, or None."""
    if section is None:
        return None
    ck.table(section, "calibration", _CALIBRATION)
    bed = ck.string(section.get("bed", ""), "calibration.bed")
    able = [m for m in models if REGISTRY[named[m].model if m in named else m].calibration]
    if bed not in models or bed not in able:
        what = "is not a model of the study" if bed not in models else "cannot calibrate its contact dashpots"
        ck.fail("calibration.bed", f"{bed!r} {what}; give one of {', '.join(able) or '(none: add a compliant model)'}")
    return bed


def _columns(data, ck):
    out = []
    entries = data.get("columns", [])
    if not isinstance(entries, list):
        ck.fail("columns", "must be an array of tables ([[columns]])")
    presets = None
    for i, entry in enumerate(entries):
        field = f"columns[{i}]"
        ck.table(entry, field, _COLUMN | _DRUMS | {"colonnade"})
        entry = _named_colonnade_column(ck, entry, field)
        if "named" in entry:
            if set(entry) - {"named", "name", "colonnade"} - _DRUMS:
                ck.fail(field, "a named column takes no dimensions (give either named = ID or R, r, h)")
            presets = presets or named_columns()
            key = ck.string(entry["named"], f"{field}.named")
            if key not in presets:
                ck.fail(f"{field}.named", f"{key!r} is not a named column; known: {', '.join(sorted(presets))}")
            p = presets[key]
            label = ck.string(entry.get("name", key), f"{field}.name")
            info = ColumnInfo(Column(p["R"], p["r"], p["h"], name=label), label,
                              float(p.get("latitude", math.nan)), float(p.get("longitude", math.nan)),
                              p.get("source", ""))
        else:
            missing = [k for k in ("R", "r", "h") if k not in entry]
            if missing:
                ck.fail(f"{field}.{missing[0]}", "missing: give R, r and h in metres, or named = ID")
            dims = [ck.number(entry[k], f"{field}.{k}", positive=True) for k in ("R", "r", "h")]
            label = ck.string(entry.get("name", f"R{dims[0]:g}-r{dims[1]:g}-h{dims[2]:g}"), f"{field}.name")
            info = ColumnInfo(Column(*dims, name=label), label, source="study file")
        info = _drum_column(ck, entry, info, p if "named" in entry else {}, field)
        _check(ck, info.column, field)
        out.append(_colonnade(ck, entry, info, field))
    grid = data.get("column_grid")
    if grid is not None:
        ck.table(grid, "column_grid", _GRID | _GRID_OPTIONAL)
        for k in sorted(_GRID):
            if k not in grid:
                ck.fail(f"column_grid.{k}", "missing: a grid needs R, slenderness and beta")
        radii = ck.numbers(grid["R"], "column_grid.R", positive=True, scalar_ok=True)
        slender = ck.numbers(grid["slenderness"], "column_grid.slenderness", positive=True, scalar_ok=True)
        betas = ck.numbers(grid["beta"], "column_grid.beta", positive=True, scalar_ok=True)
        counts = _grid_drums(ck, grid)
        for R in radii:
            for s in slender:
                for b in betas:
                    for n in counts:
                        label = f"R{R:g}-s{s:g}-b{b:g}" + ("" if n is None else f"-d{n}")
                        col = Column(R, b * R, s * R, name=label)
                        _check(ck, col, "column_grid")
                        info = ColumnInfo(col, label, source="study grid")
                        if n is not None:
                            info = _drum_column(ck, {"drums": n}, info, {}, "column_grid.drums")
                        out.append(info)
    if not out:
        ck.fail("columns", "no columns: give [[columns]] entries or a [column_grid]")
    ck.unique([c.label for c in out], "columns", "column label {!r} is used twice; give each column a distinct name")
    return tuple(out)


def _grid_drums(ck, grid):
    """Drum counts of ``[column_grid]`` (``drums = N`` or a list), or ``[None]`` without drums."""
    if "drums" not in grid:
        return [None]
    value = grid["drums"]
    counts = value if isinstance(value, list) else [value]
    if not counts:
        ck.fail("column_grid.drums", "give a whole number of drums or a list of them, e.g. drums = [1, 4]")
    for k, n in enumerate(counts):
        if isinstance(n, bool) or not isinstance(n, int) or n < 1:
            ck.fail(f"column_grid.drums[{k}]" if isinstance(value, list) else "column_grid.drums",
                    f"must be a whole number of drums (1 or more), got {n!r}")
    ck.unique([str(n) for n in counts], "column_grid.drums", "drum count {} is given twice")
    return counts


def _drum_column(ck, entry, info, preset, field):
    """``info`` with the drums of the entry (or of the named preset), if it has any.

    A named column keeps its preset's drums and capital unless the entry gives its own:
    ``drums = N`` or ``drum_heights = [...]`` cut it again, ``capital = [side, height]``
    replaces the capital and ``capital = false`` removes it.
    """
    from dataclasses import replace

    given = {k: entry[k] for k in _DRUMS if k in entry}
    if "drums" in given and "drum_heights" in given:
        ck.fail(f"{field}.drum_heights", "give drums = N or drum_heights = [...], not both")
    merged = {k: preset[k] for k in ("drums", "drum_heights") if k in preset and not
              ({"drums", "drum_heights"} & set(given))}
    merged.update({k: given[k] for k in ("drums", "drum_heights") if k in given})
    capital = None
    if "capital_side" in preset:
        capital = Capital(preset["capital_side"], preset["capital_height"])
    if "capital" in given:
        value = given["capital"]
        if value is False:
            capital = None
        elif (isinstance(value, list) and len(value) == 2):
            side, height = (ck.number(v, f"{field}.capital[{k}]", positive=True) for k, v in enumerate(value))
            capital = Capital(side, height)
        else:
            ck.fail(f"{field}.capital", f"give [side, height] of the square block in metres, or false; got {value!r}")
    if not merged and capital is None:
        return info
    column = Column(info.column.R, info.column.r, info.column.h)
    try:
        if "drum_heights" in merged:
            heights = merged["drum_heights"]
            if not isinstance(heights, list) or not heights:
                ck.fail(f"{field}.drum_heights", "must be a list of heights [m], bottom first, adding up to h")
            heights = [ck.number(v, f"{field}.drum_heights[{k}]", positive=True) for k, v in enumerate(heights)]
            stack = DrumColumn.from_heights(column, heights, capital, info.label)
        else:
            n = merged.get("drums", 1)
            if isinstance(n, bool) or not isinstance(n, int):
                ck.fail(f"{field}.drums", f"must be a whole number of drums, got {n!r}")
            stack = DrumColumn.equal(column, n, capital, info.label)
    except InputError as exc:
        ck.fail(field, str(exc))
    if stack.n_bodies == 1:
        return info  # one drum, no capital: the monolith
    return replace(info, stack=stack)


def _named_colonnade(ck, value, where):
    """The id of a named colonnade given as ``colonnade = "ID"`` or ``colonnade = {named = "ID", course_height
    = H}`` (a course, frieze and cornice, added on its epistyle), or None for a table of dimensions."""
    if isinstance(value, dict) and "named" in value:
        added = sorted(set(value) - _NAMED_COLONNADE)
        if added:
            ck.fail(f"{where}.{added[0]}", "a named colonnade brings its columns, interaxial and epistyle: only "
                    "course_height may be added to it (or describe the row with colonnade = {columns = N, "
                    "interaxial = S, epistyle_height = H})")
        if "course_height" in value:
            ck.number(value["course_height"], f"{where}.course_height")
        value = ck.string(value["named"], f"{where}.named")
    if not isinstance(value, str):
        return None
    presets = named_colonnades()
    if value not in presets:
        ck.fail(where, f"{value!r} is not a named colonnade; known: {', '.join(sorted(presets))} (or "
                "give a table {columns = N, interaxial = S, epistyle_height = H})")
    return value


def _named_colonnade_column(ck, entry, field):
    """``entry``, and for a named colonnade (which brings its column, :func:`_named_colonnade`) with its column
    named (``named = `` the colonnade's column, ``name = `` the colonnade's id unless given)."""
    value = _named_colonnade(ck, entry.get("colonnade"), f"{field}.colonnade")
    if value is None:
        return entry
    presets = named_colonnades()
    mine = sorted(set(entry) & ({"named", "R", "r", "h"} | _DRUMS))
    if mine:
        ck.fail(f"{field}.{mine[0]}", f"colonnade = {value!r} is a named colonnade, which brings its column: drop "
                f"{mine[0]}, or describe the row with colonnade = {{columns = N, interaxial = S, epistyle_height = H}}")
    return {**entry, "named": presets[value]["column"], "name": entry.get("name", value)}


def _colonnade(ck, entry, info, field):
    """``info`` with the colonnade of the entry (``colonnade = {...}`` or a named one), if it has one.

    The row is of the column as given (its drums and capital, its density); the models that run
    colonnades run it, the others the column (:meth:`pipeline.study.spec.ColumnInfo.body`).
    """
    from dataclasses import replace

    value = entry.get("colonnade")
    if value is None:
        return info
    where = f"{field}.colonnade"
    named = _named_colonnade(ck, value, where)
    if named is not None:
        preset = named_colonnades()[named]
        table = {k: preset[k] for k in _COLONNADE if k in preset}
        if isinstance(value, dict) and "course_height" in value:
            table["course_height"] = value["course_height"]
        source = preset.get("source", "")
    else:
        table = ck.table(value, where, _COLONNADE)
        missing = [k for k in ("columns", "interaxial", "epistyle_height") if k not in table]
        if missing:
            ck.fail(f"{where}.{missing[0]}", "missing: a colonnade needs columns (their number), interaxial (the "
                    "spacing of the axes [m]) and epistyle_height [m]")
        for key in ("interaxial", "epistyle_height", "epistyle_width", "course_height"):
            if key in table:
                ck.number(table[key], f"{where}.{key}")
        n = table["columns"]
        if isinstance(n, bool) or not isinstance(n, int):
            ck.fail(f"{where}.columns", f"must be a whole number of columns (at least 2), got {n!r}")
        source = info.source
    body = info.stack if info.stack is not None else DrumColumn(info.column)
    try:
        row = Colonnade(body, table["columns"], table["interaxial"], table["epistyle_height"],
                        table.get("epistyle_width"), table.get("course_height", 0.0), info.label)
    except InputError as exc:
        ck.fail(where, str(exc))
    return replace(info, colonnade=row, source=source)


def _check_bodies(ck, models, named, columns):
    """Every model of the study runs every column: one that runs colonnades only needs each column to carry one."""
    for m in models:
        model = REGISTRY[named[m].model if m in named else m]
        if model.runs("column") or model.runs("drums"):
            continue
        bare = [c.label for c in columns if c.colonnade is None]
        if bare:
            ck.fail("columns", f"model {m!r} runs colonnades, and column {bare[0]!r} carries none: give it colonnade "
                    "= {columns = N, interaxial = S, epistyle_height = H} (or a named colonnade, e.g. colonnade = "
                    f"{sorted(named_colonnades())[0]!r}), or run {m!r} in a study of its own")


def _check(ck, column, field):
    try:
        check_column(column)
    except InputError as exc:
        ck.fail(field, str(exc))


def _records(section, ck, path):
    if section is None:
        ck.fail("records", "missing: give [records] with ids, sets, files or synthetic")
    ck.table(section, "records", _RECORDS)
    from pipeline.groundmotion import list_records, list_sets

    out = []
    known_sets = [s["id"] for s in list_sets()]
    for i, set_id in enumerate(ck.strings(section.get("sets", []), "records.sets")):
        if set_id not in known_sets:
            ck.fail(f"records.sets[{i}]", f"{set_id!r} is not a record set; known: {', '.join(known_sets)}")
        for rid in list_records(set_id):
            out.append(RecordSpec("catalog", rid, field=f"records.sets[{i}]"))
    for i, rid in enumerate(ck.strings(section.get("ids", []), "records.ids")):
        out.append(RecordSpec("catalog", rid, field=f"records.ids[{i}]"))
    files = section.get("files", [])
    if not isinstance(files, list):
        ck.fail("records.files", "must be a list of tables {path = ..., units = ...}")
    for i, entry in enumerate(files):
        out.append(_file_record(entry, f"records.files[{i}]", ck, path))
    synth = section.get("synthetic", [])
    if not isinstance(synth, list):
        ck.fail("records.synthetic", "must be a list of tables {generator = ..., id = ..., ...}")
    for i, entry in enumerate(synth):
        field = f"records.synthetic[{i}]"
        if not isinstance(entry, dict):
            ck.fail(field, "must be a table {generator = ..., id = ..., parameters}")
        gen = ck.string(entry.get("generator"), f"{field}.generator")
        if gen not in _GENERATORS:
            ck.fail(f"{field}.generator", f"{gen!r} is unknown; choose from {', '.join(_GENERATORS)}")
        rid = ck.string(entry.get("id"), f"{field}.id")
        params = tuple(sorted((k, v) for k, v in entry.items() if k not in ("generator", "id")))
        _check_signature(ck, gen, params, field)
        out.append(RecordSpec("synthetic", rid, generator=gen, params=params, field=field))
    if not out:
        ck.fail("records", "no records: give ids, sets, files or synthetic (an empty grid computes nothing)")
    ck.unique([r.id for r in out], "records", "record {!r} is given twice; give each record once (files/synthetic: set id)")
    return tuple(out)


def _file_record(entry, field, ck, study_path):
    """A ``[records] files`` entry: one path, or 2-3 paths (x, y[, z]), and how to read them."""
    ck.table(entry, field, _FILE)
    given = entry.get("path")
    if isinstance(given, list):
        if not 2 <= len(given) <= 3:
            ck.fail(f"{field}.path", f"a list names the 2 or 3 files of one record (x, y[, z]), got {len(given)}")
        names = ck.strings(given, f"{field}.path")
    else:
        names = [ck.string(given, f"{field}.path")]
    full = tuple(str((study_path.parent / n).resolve()) for n in names)
    units = entry.get("units")
    if units is not None:
        ck.string(units, f"{field}.units")
    components = entry.get("components")
    if components is not None:
        components = ck.strings(components, f"{field}.components")
        if len(components) not in (2, 3):
            ck.fail(f"{field}.components", 'name x, y[, z], e.g. ["HNE", "HNN"] ("none" for y = 0)')
        components = tuple(None if c.lower() == "none" else c for c in components)
    missing_y = entry.get("missing_y", "error")
    if missing_y not in ("error", "zero"):
        ck.fail(f"{field}.missing_y", f'{missing_y!r}: give "zero" (y = 0) or "error"')
    dt = entry.get("dt")
    if dt is not None:
        dt = ck.number(dt, f"{field}.dt", positive=True)
    processing = entry.get("processing", [])
    from pipeline.groundmotion.processing import STEPS

    if not isinstance(processing, list):
        ck.fail(f"{field}.processing", 'must be a list of steps, e.g. [{step = "baseline", type = "linear"}]')
    for k, step in enumerate(processing):
        if not isinstance(step, dict) or step.get("step") not in STEPS:
            ck.fail(f"{field}.processing[{k}]", f"give {{step = NAME, ...}} with NAME one of {', '.join(STEPS)}")
    rid = ck.string(entry.get("id", Path(names[0]).stem), f"{field}.id")
    return RecordSpec("file", rid, path=full if len(full) > 1 else full[0], units=units, components=components,
                      missing_y=missing_y, dt=dt, processing=tuple(processing), field=field)


def _check_signature(ck, generator, params, field):
    import inspect

    from pipeline.groundmotion import synthesis

    sig = inspect.signature(getattr(synthesis, generator))
    for key, _ in params:
        if key not in sig.parameters or key == "record_id":
            allowed = [p for p in sig.parameters if p != "record_id"]
            ck.fail(f"{field}.{key}", f"unknown parameter of {generator}; allowed: {', '.join(allowed)}")
    given = {k for k, _ in params}
    for name, p in sig.parameters.items():
        if p.default is inspect.Parameter.empty and name not in given:
            ck.fail(f"{field}.{name}", f"missing: {generator} needs it")


def _excitation(section, ck):
    if section is None:
        ck.fail("excitation", "missing: give [excitation] with angles and scales (or intensity)")
    ck.table(section, "excitation", _EXCITATION)
    angles = ck.numbers(section.get("angles", [0.0]), "excitation.angles")
    scales = intensity = None
    if "scales" in section and "intensity" in section:
        ck.fail("excitation.intensity", "give either scales or intensity, not both")
    if "intensity" in section:
        table = ck.table(section["intensity"], "excitation.intensity", _INTENSITY)
        measure = ck.string(table.get("measure"), "excitation.intensity.measure")
        if measure not in INTENSITY_MEASURES:
            ck.fail("excitation.intensity.measure", f"{measure!r}: choose {' or '.join(INTENSITY_MEASURES)}")
        if "values" not in table:
            ck.fail("excitation.intensity.values", "missing: give the target levels")
        choices = INTENSITY_UNITS[measure]
        hint = " or ".join(f'units = "{u}"' for u in choices)
        if "units" not in table:
            ck.fail("excitation.intensity.units", f"missing: state the unit of the {measure} targets, {hint}")
        units = table["units"]
        if units not in choices:
            ck.fail("excitation.intensity.units", f"{units!r} is not a unit of {measure}; give {hint}")
        stated = ck.numbers(table["values"], "excitation.intensity.values", positive=True)
        intensity = Intensity(measure, tuple(v * choices[units] for v in stated), units, stated)
    else:
        if "scales" not in section:
            ck.fail("excitation.scales", "missing: give the factors on the records (or intensity)")
        scales = ck.numbers(section["scales"], "excitation.scales", positive=True)
    vertical = section.get("vertical", True)
    if not isinstance(vertical, bool):
        ck.fail("excitation.vertical", f"must be true or false, got {vertical!r}")
    sa_period = section.get("sa_period")
    if sa_period is not None:
        sa_period = ck.number(sa_period, "excitation.sa_period", positive=True)
    components = section.get("components", "pair")
    if components not in HORIZONTAL_COMPONENTS:
        ck.fail("excitation.components", f"{components!r}: give \"pair\" (both horizontal components, as recorded) "
                "or \"x\" (the x component alone, turned by the angles: a drive in one direction)")
    return angles, scales, intensity, vertical, sa_period, components
