"""The adaptive integrators: explicit Runge-Kutta with dense output and terminal events.

Kernel layer, compiled with numba; one job a module, one calling convention for both methods:

* ``driver``: the step loop both methods share (the explicit Runge-Kutta step on a tableau,
  step size control, the initial step, break points, the restart window, the output grid,
  terminal events and the step monitor), the ``STATUS_*`` codes and the returned tuple
  ``Dop853Result``; its docstring gives the calling convention and how to cache a caller;
* ``events``: the interpolant's evaluation, the output rows, the event signs and their
  roots (Brent's method), ``no_events`` and ``no_monitor``;
* ``dop853``: Dormand-Prince 8(5,3), the method (tableau, error estimate, 7th-order
  extension) and its integrators ``dop853``, ``dop853_monitored`` (the rigid models, and
  the compliant stack's reference);
* ``dopri5``: Dormand-Prince 5(4), the same for ``dopri5``, ``dopri5_monitored`` (the
  compliant stack's adaptive run).
"""
