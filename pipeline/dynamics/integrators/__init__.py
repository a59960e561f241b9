"""The adaptive integrators: explicit Runge-Kutta with dense output and terminal events.

Kernel layer, compiled with numba; one module an integrator, with one calling convention:

* ``dop853``: Dormand-Prince 8(5,3) (the rigid models, and the compliant stack's reference),
  and the event and output driver both integrators share, which ``dopri5`` imports from it:
  the event signs and the earliest event (``_read_event_signs``, ``_earliest_event``), the
  output grid and the interpolant (``_outputs_until``, ``_dense_eval``), the initial step
  (``_select_initial_step``), the restart window (``_START_WINDOW``), the ``STATUS_*`` codes,
  the returned tuple ``Dop853Result`` and ``no_monitor``;
* ``dopri5``: Dormand-Prince 5(4) (the compliant stack's adaptive run).
"""
