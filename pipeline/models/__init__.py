"""The model registry: every model the pipeline runs, declared once.

Each entry (:class:`pipeline.models.spec.Model`) says what its model is (title and words for
help, plots and reports), the structures it runs (monoliths, drums, colonnades), whether the incidence
angle matters, the options it reads (declared once in :mod:`pipeline.models.options`) and its
numerical choices with their defaults, units and ranges, its state layout and histories, its
compiled kernels and where its simulation is. Everything above the kernels asks the registry and compares no model's name:
a new model is a kernel, one entry here (a module of this package) and catalog entries for
its new variables (docs/architecture.md).
"""

from pipeline.errors import InputError
from pipeline.models.compliant import COMPLIANT_DRUMS
from pipeline.models.frame import RIGID_FRAME
from pipeline.models.rigid import PLANAR_ROCKING, ROLLING_FRUSTUM
from pipeline.models.options import OPTIONS, Option
from pipeline.models.spec import Model, ModelDescription, StateLayout

__all__ = ["Model", "ModelDescription", "StateLayout", "Option", "OPTIONS", "REGISTRY", "DEFAULT", "names", "get", "describe", "title", "markdown",
           "style", "planar_pair", "base_of", "of_results", "flag", "results_title", "variant_text", "unrun_part",
           "IMPERFECTIONS", "imperfect_models", "check_imperfect"]

#: The models by name, in the order help and reports list them.
REGISTRY = {m.name: m for m in (ROLLING_FRUSTUM, PLANAR_ROCKING, COMPLIANT_DRUMS, RIGID_FRAME)}
#: The model run when none is named: the paper's.
DEFAULT = ROLLING_FRUSTUM.name


#: What a model that does not run a kind of structure runs of it instead, and the kind's name in the plural.
_INSTEAD = {"drums": ("each column as one rigid body", "drums"), "colonnade": ("the column alone", "colonnades")}


def unrun_part(kind, names_, key, run, fix):
    """The refusal of a part of a structure that only models of ``kind`` read (drums, a capital: ``"drums"``;
    a colonnade: ``"colonnade"``), given as ``key`` where none of the models ``names_`` runs that kind.

    One message for ``frustum simulate`` and a study file, each with its own words for the run and the fix;
    the caller knows that none of its models runs the kind (a study's variant may run a model of drums on
    the outline).

    Parameters
    ----------
    kind : str
        ``"drums"`` or ``"colonnade"``.
    names_ : sequence of str
        The models as the run names them (a study's variants by their own names).
    key : str
        How the part was given: ``"--drums"``, ``"drums"``.
    run : str
        ``"the run"``, ``"the study"``.
    fix : str
        The verb of the fix: ``"drop"``, ``"remove"``.
    """
    instead, plural = _INSTEAD[kind]
    runners = ", ".join(m.name for m in REGISTRY.values() if m.runs(kind))
    verb = "runs" if len(names_) == 1 else "run"
    return (f"no model of {run} runs {plural} ({', '.join(names_)} {verb} {instead}), so {key} would be ignored; "
            f"{plural} are run by {runners}: {fix} {key}, or run a model of {plural}")


#: The options that make a structure imperfect (:mod:`pipeline.structures.imperfections`).
IMPERFECTIONS = ("imperfections", "seed", "friction_range")


def imperfect_models():
    """The names of the models that draw imperfections (that read the option ``imperfections``)."""
    return tuple(m.name for m in REGISTRY.values() if "imperfections" in m.options)


def check_imperfect(models, given):
    """Refuse imperfections given where none of ``models`` draws them: they would be ignored.

    The one check behind ``frustum simulate --imperfections`` (and ``--seed``, ``--friction-range``)
    and a study's ``[imperfections]`` and ``[options]``, so that both say it in the same words.

    Parameters
    ----------
    models : sequence of str
        Registry names of the models that would run.
    given : str
        How the imperfections were given (``"--imperfections"``, ``"[imperfections]"``,
        ``"options.seed"``).
    """
    readers = imperfect_models()
    models = list(dict.fromkeys(models))
    if any(m in readers for m in models):
        return
    runs = f"model {models[0]} runs" if len(models) == 1 else f"models {', '.join(models)} run"
    raise InputError(f"{given} draws imperfect drums (beds offset and tilted within a tolerance, joint friction from a "
                     f"range), which only {' and '.join(readers)} {'runs' if len(readers) == 1 else 'run'}; {runs} "
                     f"perfect structures, so it would be ignored: drop {given}, or run {' or '.join(readers)}")


def names():
    """The models' names, in the registry's order."""
    return tuple(REGISTRY)


def get(name):
    """The registry's entry of the model ``name``; an unknown name is refused with the choices."""
    try:
        return REGISTRY[name]
    except (KeyError, TypeError):
        raise InputError(f"model = {name!r} is unknown; choose one of {', '.join(REGISTRY)}") from None


def base_of(results, name):
    """The registry name of the model a results file calls ``name``.

    A study may run variants of a registry model under names of their own (``[models.NAME]``
    in the study file); its results say which model each one is in the variable
    ``base_model`` (dim ``model``). Without it, or for a name it does not hold, the name is the
    registry's own.
    """
    if "base_model" in getattr(results, "variables", ()) and name in results["model"].values:
        return str(results["base_model"].sel(model=name).values)
    return name


def of_results(results, name):
    """The registry entry of a results file's model ``name`` (:func:`base_of`), or None if unknown."""
    return REGISTRY.get(base_of(results, name))


def flag(results, name, attribute):
    """A registry attribute (``drums``, ``planar``, ``angle_invariant``) of a results file's model;
    False for a model the registry does not know (e.g. a peer engine's cells)."""
    return bool(getattr(of_results(results, name), attribute, False))


def variant_text(results, name):
    """What makes a results file's model a variant of its registry model (``model_variant``), or ""."""
    if "model_variant" in getattr(results, "variables", ()) and name in results["model"].values:
        return str(results["model_variant"].sel(model=name).values)
    return ""


def results_title(results, name):
    """Display name of a results file's model: the registry's title, and for a variant its own
    name, model and what it changes (``"stack-wide: 3D compliant drums on joints, numerics edge_band = 1"``)."""
    base = base_of(results, name)
    if base == name:
        return title(name)
    variant = variant_text(results, name)
    return f"{name}: {title(base)}" + (f", {variant}" if variant else "")


def describe(name):
    """The description of a model; an unknown name (e.g. in an old results file) gets a
    placeholder that says so, not an error."""
    model = REGISTRY.get(name)
    if model is not None:
        return model.description
    return ModelDescription(title=str(name), body=f"model {name!r} (no description)", follows=(), contact="",
                            sliding_onset="the flag was set", lift_off="the flag was set", cite="", reference="")


def title(name):
    """Display name of a model (``"3D rolling frustum"``), or the name itself if unknown."""
    return describe(name).title


def markdown(name):
    """The model's description as one Markdown bullet (the report's assumptions)."""
    model = REGISTRY.get(name)
    if model is not None:
        return model.markdown()
    return f"- **{name}** (`{name}`): model {name!r} (no description)."


#: How plots draw a model the registry does not know (e.g. from an old results file).
_UNKNOWN_STYLE = {"ls": ":", "marker": "D", "filled": False, "band_alpha": 0.07}


def style(name):
    """How plots draw a model: line style ``ls``, ``marker``, ``filled`` marker, ``band_alpha``.

    An entry that says nothing of some of them (a new model need not) is drawn as an unknown
    model is, in those."""
    model = REGISTRY.get(name)
    return {**_UNKNOWN_STYLE, **(model.style if model is not None else {})}


def planar_pair(names_):
    """(3D model, its planar counterpart) among the names given, the first such pair, or None:
    the pair reports compare (is planar rocking conservative for this column?)."""
    for name in names_:
        model = REGISTRY.get(name)
        if model is not None and model.planar_of in names_:
            return model.planar_of, name
    return None
