"""The compliant-contact model ``3d-compliant``: rigid bodies on joints of contact points.

The friendly layer over the kernels of :mod:`pipeline.dynamics.compliant`, one job a module:

* :mod:`~pipeline.compliant.parts`: a structure (a monolith, a column of drums and its capital,
  :mod:`~pipeline.compliant.colonnade` a colonnade) as bodies and joints in SI units;
* :mod:`~pipeline.compliant.tables`: those as the kernel's dimensionless tables, with the joint law's
  parameters from the settings; :mod:`~pipeline.compliant.barriers`: the energy it takes to fall;
* :mod:`~pipeline.compliant.rest`: the rest state (static equilibrium, held exactly);
* :mod:`~pipeline.compliant.calibration`: the joints' damping from a coefficient of restitution;
* :mod:`~pipeline.compliant.integrate`: the fixed step and its limit, the integrators, the end of a run;
* :mod:`~pipeline.compliant.run`: :func:`simulate_compliant`, the registry's runner;
* :mod:`~pipeline.compliant.summary`, :mod:`~pipeline.compliant.histories`: what a run reports.

docs/model.md, "The compliant-contact model", says what it models and how it is checked.
"""

from pipeline.compliant.barriers import overturning_barriers
from pipeline.compliant.calibration import calibrated_damping, critical_damping, planar_restitution
from pipeline.compliant.integrate import fixed_step, integrate
from pipeline.compliant.layouts import layout_of, outline_of
from pipeline.compliant.parts import as_stack, lying_tilt
from pipeline.compliant.rest import released_state, rest_state
from pipeline.compliant.run import simulate_compliant, turned_record
from pipeline.compliant.summary import dislocation_ratio, joint_dislocations
from pipeline.compliant.tables import Assembly, assemble, numerics

__all__ = ["simulate_compliant", "calibrated_damping", "critical_damping", "planar_restitution", "assemble",
           "Assembly", "numerics", "as_stack", "outline_of", "layout_of", "lying_tilt", "rest_state",
           "released_state", "fixed_step", "integrate", "turned_record", "joint_dislocations", "dislocation_ratio",
           "overturning_barriers"]
