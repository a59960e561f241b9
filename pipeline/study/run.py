"""One task on a worker: a record on a block of columns, for every angle, scale and model.

Physics used to save work: the 3D column is axisymmetric, so its response to the record turned
by the incidence angle is the response to the record as recorded, turned by that angle
(:mod:`pipeline.simulate` already runs 3D in the record's frame). Every 3D summary value is
therefore exactly independent of the angle: a task runs 3D once per (column, record, scale) and
broadcasts the values over the angles. The 2D model (rocking in the plane of the X component of
the turned pair) is run at every angle, as is the compliant-contact model (``3d-compliant``),
whose discrete contact points are not axisymmetric. The registry says which model is which
(``Model.angle_invariant``). With ``[imperfections]`` a model that draws imperfect drums runs once
per seed (its settings' ``seed``), the others once, repeated along the seeds.

A simulation that fails is flagged in its cells (status 1), never raised: one failure must not
end a study.
"""

import math
import time
from dataclasses import replace

from pipeline.models import REGISTRY
from pipeline.settings import Excitation
from pipeline.simulate import simulate
from pipeline.study.results import FLAG_VARIABLES, FLOAT_VARIABLES, JOINT_VARIABLES, blank_arrays


def run_task(task, motion):
    """Run one task; a failing simulation is flagged (status 1), not raised.

    Parameters
    ----------
    task : Task
    motion : pipeline.groundmotion.GroundMotion

    Returns
    -------
    dict
        ``index``, ``record``, ``start``, ``stop``, ``runs`` (simulations run),
        ``seconds`` (wall time [s]), ``cpu_seconds`` (CPU time of the
        process [s]), ``errors`` (first messages) and
        ``arrays``: name -> array (n_block_columns, n_angles, n_scales, n_models).
    """
    t0, c0 = time.perf_counter(), time.process_time()
    arrays = blank_arrays(task.shape, status=0, n_joints=task.n_joints)
    runs, errors = 0, []
    for ci, shaft in enumerate(task.columns):
        stack = task.stacks[ci] if task.stacks else None
        for mi, settings in enumerate(task.settings):
            model = REGISTRY[settings.model]
            # a model of drums runs the drums (unless its variant runs the outline); a model of
            # monoliths the shaft as a monolith
            drums = task.drums[mi] if task.drums else model.drums
            column = stack if (stack is not None and drums) else shaft
            if task.colonnades and task.colonnades[ci] is not None and model.runs("colonnade"):
                column = task.colonnades[ci]  # a model of colonnades runs the column's row
            if task.beds:  # the study's calibrated bed, the same for every model
                settings = replace(settings, contact_damping=task.beds[ci][0], restitution=task.beds[ci][1])
            # imperfect drums: one run per seed; perfect ones once, broadcast along the seeds (if any)
            seed_runs = [(settings, ())] if not task.seeds else \
                [(replace(settings, seed=seed), (k,)) for k, seed in enumerate(task.seeds)] if task.seeded[mi] else \
                [(settings, (slice(None),))]
            for si, factor in enumerate(task.factors):
                # angle-invariant: one run at the first angle, broadcast (axisymmetry, module docstring)
                angle_runs = [(task.angles[0], slice(None))] if model.angle_invariant else \
                    [(a, ai) for ai, a in enumerate(task.angles)]
                for (angle, where), (drawn, at) in ((a, d) for a in angle_runs for d in seed_runs):
                    runs += 1
                    index = (ci, where, si, mi) + at
                    try:
                        summary = simulate(column, motion, Excitation(angle=angle, scale=factor,
                                                                      vertical=task.vertical),
                                           drawn, histories=False).summary
                    except Exception as exc:  # noqa: BLE001 - one failure must not kill the study
                        arrays["status"][index] = 1
                        if len(errors) < 5:
                            seed = f" seed {drawn.seed}" if at and drawn.seed is not None else ""
                            errors.append(f"{column.name} {settings.model} angle {angle:g} deg "
                                          f"factor {factor:g}{seed}: {type(exc).__name__}: {exc}")
                        continue
                    for name in FLOAT_VARIABLES:
                        arrays[name][index] = summary[name]
                    arrays["n_impacts"][index] = summary["n_impacts"]
                    for name in FLAG_VARIABLES[:-1]:
                        arrays[name][index] = 1 if summary[name] else 0
                    if task.n_joints:
                        # a rigid column is one body: if anything fell, it did
                        arrays["overturn_drum"][index] = summary.get("overturn_drum", 0 if summary["overturned"] else -1)
                        if "joint_slip" in summary:
                            for name in ("dislocation_ratio", "epistyle_slip", "epistyle_opening"):
                                arrays[name][index] = summary.get(name, math.nan)
                            joints = index + (slice(0, len(summary["joint_slip"])),)
                            for name in JOINT_VARIABLES:
                                arrays[name][joints] = summary[name]
    return {"index": task.index, "record": task.record, "start": task.start, "stop": task.stop, "runs": runs,
            "seconds": time.perf_counter() - t0, "cpu_seconds": time.process_time() - c0, "errors": errors,
            "arrays": arrays}


def failed_result(task, message):
    """What a task that could not run yields: every cell status 1 (NaN, flags 0)."""
    arrays = blank_arrays(task.shape, status=1, n_joints=task.n_joints)
    return {"index": task.index, "record": task.record, "start": task.start, "stop": task.stop, "runs": 0,
            "seconds": 0.0, "cpu_seconds": 0.0, "errors": [f"columns {task.start}-{task.stop - 1}: {message}"],
            "arrays": arrays}
