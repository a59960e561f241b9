"""A study's results: the arrays every task fills, and the Dataset the whole grid becomes.

One value per cell of the grid (``DIMS``: column, record, angle, scale, model, and ``seed`` with
``[imperfections]``) for each of ``RESULT_VARIABLES``; a study that runs the compliant model also
holds ``COMPLIANT_VARIABLES`` and, per joint, ``JOINT_VARIABLES``; a study of imperfect drums the
imperfections drawn per column, seed and joint (``DRAWN_VARIABLES``). :func:`blank_arrays` makes them,
:func:`pipeline.study.run.run_task` fills a block of them, and :func:`assemble` turns the whole
grid into the CF Dataset that is written to netCDF (docs/studies.md has the schema).
"""

import json
import math
import os

import numpy as np
import xarray as xr

from pipeline import __version__
from pipeline import models as MD
from pipeline.dataset import STUDY_VARIABLES, annotate
from pipeline.models import REGISTRY
from pipeline.structures import description as D

FLOAT_VARIABLES = ("peak_theta", "peak_theta_ratio", "peak_time", "overturn_time", "uplift_time", "peak_mu_mob",
                   "residual_rotation", "residual_displacement", "work_ground", "energy_balance_error")
FLAG_VARIABLES = ("overturned", "undecided", "uplifted", "sliding_onset", "lift_off", "status")
INT_VARIABLES = ("n_impacts",)
RESULT_VARIABLES = FLOAT_VARIABLES + INT_VARIABLES + FLAG_VARIABLES
DTYPES = {**{n: np.float64 for n in FLOAT_VARIABLES}, **{n: np.int32 for n in INT_VARIABLES},
           **{n: np.int8 for n in FLAG_VARIABLES}}
DIMS = ("column", "record", "angle", "scale", "model")
# A study that runs the compliant model also holds (pipeline.compliant): the largest residual
# slip of a bed joint over its diameter, the body that fell first (-1: none), and per joint
# (dimension ``joint``; joint k is the base of body k) the residual dislocation. NaN for the
# rigid models and for the joints a column does not have.
# A colonnade's (NaN for a column): how far its epistyle slid on the capitals and opened between blocks.
COMPLIANT_VARIABLES = ("dislocation_ratio", "overturn_drum", "epistyle_slip", "epistyle_opening")
JOINT_VARIABLES = ("joint_slip", "joint_twist", "joint_tilt", "joint_opening")
DTYPES.update({"dislocation_ratio": np.float64, "overturn_drum": np.int32, "epistyle_slip": np.float64,
               "epistyle_opening": np.float64,
                **{n: np.float64 for n in JOINT_VARIABLES}})


#: What a study of imperfect drums records of each draw, per (column, seed, joint) (pipeline.structures.imperfections).
DRAWN_VARIABLES = ("bed_offset_x", "bed_offset_y", "bed_tilt", "bed_tilt_azimuth", "bed_friction")


def result_variables(n_joints=0):
    """Names of a study's result arrays: the common ones, and the compliant model's if ``n_joints`` > 0."""
    return RESULT_VARIABLES + (COMPLIANT_VARIABLES + JOINT_VARIABLES if n_joints else ())


def result_shape(name, shape, n_joints):
    """Shape of one result array: ``shape``, with the ``joint`` dimension last for a joint variable."""
    return tuple(shape) + ((n_joints,) if name in JOINT_VARIABLES else ())


def blank_arrays(shape, status, n_joints=0):
    """Result arrays of ``shape`` before any simulation: floats NaN, counts and flags 0 (``overturn_drum``
    -1), ``status`` as given; with ``n_joints`` > 0 also the compliant model's."""
    arrays = {name: np.zeros(result_shape(name, shape, n_joints), dtype=DTYPES[name])
              for name in result_variables(n_joints)}
    for name, values in arrays.items():
        if values.dtype.kind == "f":
            values[...] = np.nan
    arrays["status"][...] = status
    if n_joints:
        arrays["overturn_drum"][...] = -1
    return arrays


def assemble(study, motions, measures, factors, arrays):
    """The results Dataset of a study (see docs/studies.md for the schema)."""
    n_joints = study.n_joints
    dims = DIMS + (("seed",) if study.seeds else ())
    ds = xr.Dataset({name: (dims + (("joint",) if name in JOINT_VARIABLES else ()), arrays[name])
                     for name in result_variables(n_joints)})
    cols = [c.column for c in study.columns]
    coords = {
        "column": ("column", [c.label for c in study.columns]),
        "record": ("record", [s.id for s in study.records]),
        "angle": ("angle", np.asarray(study.angles, dtype=np.float64)),
        "scale": ("scale", np.asarray(study.levels, dtype=np.float64)),
        "model": ("model", list(study.models)),
        "column_R": ("column", [c.R for c in cols]),
        "column_r": ("column", [c.r for c in cols]),
        "column_h": ("column", [c.h for c in cols]),
        "slenderness": ("column", [c.slenderness for c in cols]),
        "beta": ("column", [c.beta for c in cols]),
        "theta_crit": ("column", [c.critical_tilt for c in cols]),
        "earthquake": ("record", [str(m.metadata.get("event") or m.metadata.get("generator") or "unknown")
                                  for m in motions]),
        "station": ("record", [str(m.metadata.get("station") or "unknown") for m in motions]),
        "year": ("record", np.array([int(m.metadata.get("year") or -1) for m in motions], dtype=np.int32)),
        "magnitude": ("record", np.array([float(m.metadata.get("magnitude") or math.nan) for m in motions])),
        "record_sha256": ("record", [m.sha256() for m in motions]),
        "scale_factor": (("record", "scale"), factors),
        "pga": (("record", "scale"), factors * np.array([[m["pga"]] for m in measures])),
        "pgv": (("record", "scale"), factors * np.array([[m["pgv"]] for m in measures])),
    }
    if any(c.stack is not None or c.colonnade is not None for c in study.columns):
        coords["structure"] = ("column", [c.describe() for c in study.columns])
    if any(c.colonnade is not None for c in study.columns):  # the rows' numbers (a column alone: 1, NaN, 0)
        numbers = [D.dimensions(_stands(c)) for c in study.columns]
        for name, _unit, _value in D.DIMENSIONS:
            coords[name] = ("column", np.array([n[name] for n in numbers]))
    if any(c.source for c in study.columns):
        coords["structure_source"] = ("column", [c.source for c in study.columns])
    if any(math.isfinite(c.latitude) for c in study.columns):
        coords["latitude"] = ("column", [c.latitude for c in study.columns])
        coords["longitude"] = ("column", [c.longitude for c in study.columns])
    if study.sa_period is not None:
        coords["sa"] = (("record", "scale"), factors * np.array([[m["sa"]] for m in measures]))
    if n_joints:
        diameters = np.full((len(cols), n_joints), np.nan)
        for ci, info in enumerate(study.columns):
            faces = info.stack.joint_diameters() if info.stack is not None else (2.0 * info.column.R,)
            diameters[ci, :len(faces)] = faces
        coords["joint"] = ("joint", np.arange(n_joints, dtype=np.int32))
        coords["joint_diameter"] = (("column", "joint"), diameters)
        coords["n_drums"] = ("column", np.array([1 if c.stack is None else c.stack.n_drums for c in study.columns],
                                                dtype=np.int32))
    if study.variants:  # the study's own names: which registry model each is, and how it differs
        coords["base_model"] = ("model", [study.variant(m).model for m in study.models],
                                {"long_name": "registry model of each of the study's models"})
        coords["model_variant"] = ("model", [study.variant(m).describe() for m in study.models],
                                   {"long_name": "what the study changes of the registry model"})
    bed = study.beds()
    if bed:
        coords["bed_damping"] = ("column", [b[0] for b in bed], {
            "units": "Pa s m-1", "long_name": "normal contact dashpots per unit area given to every model",
            "comment": f"calibrated on the column's outline by the model '{study.calibration}'"})
        coords["bed_restitution"] = ("column", [b[1] for b in bed], {
            "units": "1", "long_name": "planar restitution the calibrated dashpots reach, given to every model"})
    if study.seeds:
        coords.update(_drawn(study, n_joints))
    ds = ds.assign_coords(coords)
    if n_joints:
        _labels(ds, study)
    annotate(ds, STUDY_VARIABLES)
    if study.intensity is not None:
        units = {"pga": "m s-2", "pgv": "m s-1"}[study.intensity.measure]
        ds["scale"].attrs.update(units=units, long_name=f"target {study.intensity.measure} of the scaled record "
                                 "(peak of the horizontal vector); the factor is scale_factor",
                                 comment=f"the study file states the targets in {study.intensity.units}: "
                                 + ", ".join(f"{v:g}" for v in study.intensity.stated))
    if study.sa_period is not None:
        ds["sa"].attrs["period"] = study.sa_period
        ds["sa"].attrs["long_name"] += f" (period {study.sa_period:g} s)"
    ds["angle"].attrs["comment"] = "degrees counter-clockwise; 3D results do not depend on it (axisymmetry)"
    ds["model"].attrs["comment"] = "; ".join(
        [f"{m.name}: {m.in_short}" for m in REGISTRY.values()]
        + [f"{m}: the model {study.variant(m).model}" + (f" with {study.variant(m).describe()}"
                                                        if study.variant(m).describe() else "")
           for m in study.models if m not in REGISTRY]
        + ["the rigid models run a column of drums as a monolith of its shaft"])
    ds.attrs.update({
        "title": study.title,
        # the opening line of its report: what stood and which models ran it, then the study's own words
        "summary": (f"Earthquake response of {what_ran(study)}, to {len(motions)} record(s), {len(study.angles)} "
                    f"incidence angle(s), {len(study.levels)} scale level(s).") + (f" {study.summary}" if study.summary
                                                                                   else ""),
        "structures": "; ".join(f"{c.label}: {D.title(_stands(c))}" for c in study.columns),
        "source": f"frustum-pipeline {__version__} (pipeline.study)",
        "study_file": os.path.basename(study.path),
        "study_path": study.path,
        "study_sha256": study.digest,
        "model_options": json.dumps(dict(study.options), sort_keys=True),
        "vertical_component": "used" if study.vertical else "ignored",
        "horizontal_components": "the records' horizontal pair" if study.components == "pair" else
        "the x component of each record alone (y set to zero before scaling), turned by the incidence angle",
        "energy_units": "energies and work per unit weight, E/(m g) [m]",
    })
    if study.seeds:
        spec = study.imperfections
        ds.attrs.update(imperfection_tolerance_m=spec.tolerance, imperfection_models=", ".join(spec.models),
                        imperfection_friction_range=("the options' friction" if spec.friction_range is None else
                                                     f"{spec.friction_range[0]:g} {spec.friction_range[1]:g}"))
    return ds


def _stands(info):
    """What stands in a column entry of a study: its colonnade, its drums, or the column alone."""
    return info.colonnade or info.stack or info.column


def what_ran(study):
    """Each structure of a study with the models that ran it, as each ran it: ``"a colonnade of 6 columns ...
    (row) run by the 3D compliant drums on joints (3d-compliant); a monolithic column (the column of row
    alone) run by the 3D rolling frustum (3d)"``; columns alike, run by the same models, said once with
    their labels (:func:`pipeline.structures.description.what_ran`)."""
    runs = {}  # (the structure in words, how it was run, the models that ran it) -> the columns' labels
    for info in study.columns:
        bodies = {}
        for m in study.models:
            variant = study.variant(m)
            body = info.body(variant)
            # what stands, or a part of it: a colonnade's column alone, a column of drums as one body
            part = "" if body is _stands(info) else ("column" if info.colonnade is not None else "shaft")
            words = D.title(body, named=not part)
            bodies.setdefault((words, part), []).append((MD.title(variant.model), m))
        for (words, part), models in sorted(bodies.items(), key=lambda item: bool(item[0][1])):  # what stands first
            runs.setdefault((words, part, tuple(models)), []).append(info.label)
    said = []
    for (words, part, models), labels in runs.items():
        names = ", ".join(labels[:-1]) + " and " + labels[-1] if len(labels) > 1 else labels[0]
        many = len(labels) > 1
        if part == "column":
            said.append((f"{words} (the {'columns' if many else 'column'} of {names}{', each' if many else ''} alone)",
                         models))
        elif part == "shaft":
            said.append((f"{words} (the {'shafts' if many else 'shaft'} of {names}{', each' if many else ''} as one "
                         "body)", models))
        else:
            labels = [label for label in labels if f"({label}: " not in words]  # a named one says its id
            said.append((f"{words} ({', '.join(labels)})" if labels else words, models))
    return D.what_ran(said)


def _labels(ds, study):
    """Each column's joints by name (``joint_label``, a string variable on (column, joint): CF takes a label
    coordinate of one dimension only) and, per run, the body that fell first (``overturn_body``: the label
    of ``overturn_drum`` in what the model ran, the whole structure for a model that runs it as one body)."""
    n_joints = ds.sizes["joint"]
    joints = np.full((len(study.columns), n_joints), "", dtype=object)
    for ci, info in enumerate(study.columns):
        labels = D.joint_labels(_stands(info))
        joints[ci, :len(labels)] = labels
    ds["joint_label"] = (("column", "joint"), joints)
    drum = ds["overturn_drum"]
    axis = drum.dims.index("model")  # a study of imperfect drums has the dimension seed after it
    fell = np.full(drum.shape, "", dtype=object)
    for mi, m in enumerate(study.models):
        variant = study.variant(m)
        per_body = "overturn_drum" in REGISTRY[variant.model].results
        for ci, info in enumerate(study.columns):
            body = info.body(variant)
            names = D.body_labels(body) if per_body else (D.whole_label(body),)
            where = (ci,) + (slice(None),) * (axis - 1) + (mi,)
            cell = drum.values[where]
            index = np.where(cell >= 0, cell if per_body else 0, -1)
            fell[where] = np.where(index >= 0, np.asarray(names, dtype=object)[np.clip(index, 0, None)], "")
    ds["overturn_body"] = (drum.dims, fell)


def _drawn(study, n_joints):
    """The coordinates of a study of imperfect drums: ``seed``, which models draw from it (``seeded``) and
    the imperfections drawn per column, seed and joint (:data:`DRAWN_VARIABLES`; NaN past a column's
    joints).

    Each column's draw is its largest structure's (its colonnade, if a model that draws imperfections
    runs it): a model that runs fewer joints of it (the column alone, its outline) draws their first
    ones alike (:mod:`pipeline.structures.imperfections`, the draw order).
    """
    from pipeline.structures.imperfections import Imperfections, bed_diameters, draw

    spec = study.imperfections
    values = {name: np.full((len(study.columns), len(spec.seeds), n_joints), np.nan) for name in DRAWN_VARIABLES}
    for ci, info in enumerate(study.columns):
        bodies = [info.body(study.variant(m)) for m in spec.models]
        body = max(bodies, key=lambda b: bed_diameters(b).size)  # the one with the most joints
        for k, seed in enumerate(spec.seeds):
            recorded = draw(Imperfections(spec.tolerance, seed, spec.friction_range), body).recorded()
            for name in DRAWN_VARIABLES:
                drawn = recorded[name][:n_joints]
                values[name][ci, k, :drawn.size] = drawn
    coords = {"seed": ("seed", np.asarray(spec.seeds, dtype=np.int64)),
              # a flag as a coordinate: cfchecks wants its units (CF 3.1)
              "seeded": ("model", np.array([study.seeded(m) for m in study.models], dtype=np.int8), {"units": "1"})}
    coords.update({name: (("column", "seed", "joint"), values[name]) for name in DRAWN_VARIABLES})
    return coords
