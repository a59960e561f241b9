"""The compliant-contact family: rigid bodies on a list of joints of contact points.

Kernel layer (dimensionless arrays in, arrays out), compiled with numba. One module a job:

* ``layout``: the tables of an assembly (bodies, contact points, joints), its state, its
  statistics (plain constants);
* ``joint``: the joint law, written once (a spring-dashpot in compression, an elastic shear
  spring capped by Coulomb friction, per contact point, in the frame of its face, whatever
  the face's orientation), and the contact points of a face;
* ``assembly``: rigid bodies on joints (a monolith, a column of drums and its capital, a
  colonnade of such columns carrying epistyle blocks): kinematics, the joints' forces,
  right-hand side, energy, events, monitor and statistics, and the adaptive run (DOPRI5 or
  DOP853 of :mod:`pipeline.dynamics.integrators.dopri5` and
  :mod:`pipeline.dynamics.integrators.dop853`, the reference);
* ``semi_implicit``: the fixed-step semi-implicit integrator of DEM codes (the default),
  sharing the assembly's layout, tables, monitor and statistics;
* ``linear_system``: its joints' linear algebra: a joint's dashpot (or spring) matrix from its
  points' moments, ``M + h C`` as 6 x 6 blocks on the joints' pattern and its block Cholesky
  solve in an order that fills in nothing, and the stiffest mode that bounds the step;
* ``unsigned`` and ``vector_lanes``: how the compiled loops are compiled (indices without a
  negative-index test; the fixed-step loop with LLVM's SLP vectoriser), the numbers unchanged.

The ground motion is read as every family reads it (:mod:`pipeline.dynamics.excitation`).
"""
