"""The rigid models: the three-dimensional frustum and planar rocking, run event by event.

Kernel layer (dimensionless arrays in, arrays out), compiled with numba. One
call runs one column under one ground-acceleration record, for the
three-dimensional frustum (:func:`pipeline.dynamics.rigid.run3d.run_frustum`)
or for planar rocking (:func:`pipeline.dynamics.rigid.run2d.run_rocking`).
The base is a flat face of stone on stone; the phases (docs/model.md):

* **rest** (full base contact): the column moves with the ground. It leaves
  rest when the ground's push beats what the base can hold: it *uplifts* at
  ``|a_h| z_cm = (g + a_Z) R``, it *slides* at ``|a_h| = mu (g + a_Z)``,
  whichever threshold is lower (a column with ``mu < R / z_cm`` slides first),
  or it *flies* when ``g + a_Z`` reaches 0. The record is linear between
  samples, so the time is found exactly
  (:func:`pipeline.dynamics.rigid.contact.first_uplift`).
* **sliding** flat on the base (Coulomb friction, ``mu N`` against the
  sliding velocity), until the velocity vanishes (then rest, or sliding the
  other way).
* **rolling** on the rim (the paper's equations, :mod:`pipeline.dynamics.rigid.frustum`),
  while the normal force stays positive and the friction it needs stays
  below ``mu N``.
* **slipping** on the rim (:mod:`pipeline.dynamics.rigid.rim`): the rim point
  slides with Coulomb friction; back to rolling when the slip velocity
  vanishes and sticking holds.
* **flight**: the normal force would turn negative; the column flies until
  its lowest rim point (or its flat base) comes down, with a plastic impact
  that sticks or slides as Coulomb allows.
* **landing** near full contact (``theta`` down to ``theta_c``): the
  angular-momentum impact about the opposite rim point, or settling to rest.
* **overturned**: the side of the frustum touches the ground,
  ``theta_lie = pi/2 + atan((R - r)/h)``; the run ends.

Every phase is integrated by the compiled DOP853 (one wrapper per model; the
phase is read from the options array) with the terminal events
``EV_*`` of :mod:`pipeline.dynamics.rigid.layout`; the record's samples are break points. A step monitor updates the
peak mobilized friction and the lowest normal force at every accepted step,
so those peaks, like the sliding and lift-off flags (phases entered), do not
depend on the output grid. Every jump of mechanical energy at a transition is
added to ``summary[S_TRANSITION]``, so that
``E_end - E_0 = work + transitions - dissipated - friction`` holds to the
integration error.

The entry points release the GIL (``nogil=True``).

The family's modules, each with one job:

* ``layout``: phases, summary indices, events, numerical thresholds (no code);
* ``rim``, ``patch``, ``contact``, ``rocking``: the frustum slipping on its rim
  and in flight, the contact patch's couples, uplift and landing impacts, the
  planar rocking equations (the rolling equations are
  :mod:`pipeline.dynamics.rigid.frustum`'s);
* ``phases3d``, ``phases2d``: each model's phases as the integrator sees them
  (right-hand sides, events, step monitor, energy);
* ``loop``: the steps both runs take (rest until departure, booking a phase,
  lying down, the landing log, the summary);
* ``run3d``, ``run2d``: each model's transitions and its event loop;
* ``diagnostics``: derived quantities of every output row.
"""
