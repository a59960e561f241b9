"""The compliant model's run: a structure at rest, a ground motion, a response.

:func:`simulate_compliant` is the registry's runner of ``3d-compliant``
(:mod:`pipeline.models.compliant`): it checks the fixed step against the structure's stability
limit before computing, calibrates (or takes) the joints' damping, builds the kernel's tables
and rest state, runs an integrator and returns the summary and histories.
"""

import math

import numpy as np

from pipeline.compliant.calibration import calibrated_damping
from pipeline.compliant.histories import histories as run_histories
from pipeline.compliant.integrate import fixed_step, integrate
from pipeline.compliant.layouts import outline_of
from pipeline.compliant.rest import laid_state, rest_state
from pipeline.compliant.summary import summary as run_summary
from pipeline.compliant.tables import assemble
from pipeline.errors import InputError
from pipeline.response import Response
from pipeline.settings import Excitation, check_column
from pipeline.units import G

__all__ = ["simulate_compliant", "turned_record"]


def turned_record(motion, excitation):
    """The record turned by the incidence angle and scaled: (n, 3) [g].

    The compliant column is not axisymmetric (its contact points are not), so it really
    feels the direction of the motion: the pair is turned counter-clockwise as
    :meth:`pipeline.groundmotion.GroundMotion.rotated` does.
    """
    gamma = excitation.angle_rad
    ax = np.asarray(motion.acc_x, dtype=np.float64) * excitation.scale
    ay = np.asarray(motion.acc_y, dtype=np.float64) * excitation.scale
    az = motion.acc_z
    az = np.zeros_like(ax) if (az is None or not excitation.vertical) else np.asarray(az) * excitation.scale
    c, s = math.cos(gamma), math.sin(gamma)
    return np.ascontiguousarray(np.stack([c * ax - s * ay, s * ax + c * ay, az], axis=1) / G)


def simulate_compliant(column, motion, excitation, settings, histories=True, progress=None):
    """Response of a structure at rest (a monolith, drums, a colonnade) to a ground motion, compliant contact.

    The run of the registry's compliant model (:mod:`pipeline.models.compliant`);
    same arguments and the same :class:`pipeline.response.Response`. ``progress(done, total)``
    [s of motion], if given, is called about every simulated second (fixed-step integrator).
    """
    stack = outline_of(column, whole=True)
    check_column(stack.column)
    if not isinstance(excitation, Excitation):
        raise InputError(f"excitation must be an Excitation, got {type(excitation).__name__}")
    step, limit = None, math.nan
    if settings.integrator == "semi-implicit":  # an unstable step is refused before any computing
        probe = assemble(column, settings, 0.0)
        step, limit = fixed_step(probe, probe.params(), laid_state(probe), settings)
    if settings.contact_damping is None:
        damping, restitution = calibrated_damping(column, settings)
    else:
        damping, restitution = settings.contact_damping, math.nan
    asm = assemble(column, settings, damping)
    params = asm.params(turned_record(motion, excitation), motion.dt / asm.time)
    y0 = rest_state(asm, params, settings.integrator)
    if settings.integrator == "semi-implicit":  # its statistics come from every step: samples for histories only
        stride = 1
    else:
        stride = max(1, int(math.ceil(settings.output_step / settings.monitor_step - 1e-9)))
    raw = integrate(asm, params, y0, motion.duration + settings.tail, settings.output_step / stride, stride,
                     settings, histories, stack.column.critical_tilt,
                     step=step, progress=progress, settle_limit=settings.settle_limit)
    summary = run_summary(stack, asm, params, settings, raw, damping, restitution)
    summary.update(record_id=motion.record_id, angle=float(excitation.angle), scale=float(excitation.scale),
                   step=float(raw.step), step_limit=float(limit))
    ds = run_histories(column, asm, settings, raw, motion, excitation, damping) if histories else None
    return Response(summary, ds, np.empty((0, 4)))
