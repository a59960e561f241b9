"""The compliant model's given fixed step against a column's stability limit, before anything is computed.

:func:`check_fixed_step` is the registry's check of the compliant model
(``Model.checker`` of :data:`pipeline.models.compliant.COMPLIANT_DRUMS`): a study calls it for
every column (monolith or drums) a model runs, so that a step its runs would refuse is refused
by ``frustum study check`` and before ``frustum study run`` computes, with the words of
``frustum simulate``. It calls what the run calls (:func:`pipeline.compliant.fixed_step` on the
column's joints at rest, as :func:`pipeline.compliant.simulate_compliant` does before its run);
it lives here, not beside that function, while ``pipeline/compliant.py`` is being rewritten.
"""

from pipeline.compliant import as_stack, assemble, fixed_step
from pipeline.dynamics.compliant import stack as sk
from pipeline.models.options import INTEGRATORS

__all__ = ["check_fixed_step"]


def check_fixed_step(column, settings):
    """Refuse a given fixed step above the stability limit of ``column``, as its run would.

    Nothing is checked (nor assembled) without a given step, or with an adaptive integrator:
    the default step is a fraction ``step_safety`` < 1 of the limit.

    Parameters
    ----------
    column : pipeline.structures.column.Column or pipeline.structures.drums.DrumColumn
        What the model runs: the monolith, or the drums and capital.
    settings : pipeline.settings.ModelSettings
        The compliant model's settings; the joints' dashpots do not enter the limit (they are
        implicit in the fixed-step scheme), so a calibrated bed changes nothing here.

    Raises
    ------
    pipeline.errors.InputError
        ``step = ... s is above the stability limit ... s ...`` (:func:`pipeline.compliant.fixed_step`).
    """
    if settings.step is None or settings.integrator != INTEGRATORS[0]:
        return
    probe = assemble(as_stack(column), settings, 0.0)
    params = probe.params()
    fixed_step(probe, params, sk.rest_state(params), settings)
