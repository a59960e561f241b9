"""The compliant-contact family: rigid bodies on joints of contact points.

Kernel layer (dimensionless arrays in, arrays out), compiled with numba. One module a job:

* ``joint``: the joint law, written once (a spring-dashpot in compression, an elastic shear
  spring capped by Coulomb friction, per contact point), and the contact points of a face;
* ``stack``: N stacked rigid bodies (a monolith or drums, and a capital) on joints: state
  layout, tables, right-hand side, monitor and statistics, and the adaptive run (DOPRI5 or
  DOP853 of :mod:`pipeline.dynamics.integrators.dopri5` and
  :mod:`pipeline.dynamics.integrators.dop853`, the reference);
* ``semi_implicit``: the fixed-step semi-implicit integrator of DEM codes (the default),
  sharing the stack's layout, tables, monitor and statistics;
* ``linear_system``: its joints' linear algebra: a joint's dashpot (or spring) matrix from its
  points' moments, the block-tridiagonal ``M + h C`` of a stack and its block Cholesky solve,
  and the stiffest mode that bounds the step.

The ground motion is read as every family reads it (:mod:`pipeline.dynamics.excitation`).
"""
