"""Planar rocking's phases: on a sticking or slipping pivot, sliding flat, in flight (compiled).

Right-hand sides, event functions (``EV_*`` of
:mod:`pipeline.dynamics.rigid.layout`) and step monitor of the phase that
``OPT_PHASE`` names, as the compiled DOP853 integrates it
(:func:`integrate2d`), in the state layout of
:mod:`pipeline.dynamics.rigid.rocking` (``N_STATE2``), with the viscous couple
and the contact patch's rolling damping; the mechanical energy of a state in
each phase (:func:`energy2d`).
"""

import math

import numpy as np
from numba import njit

from pipeline.dynamics.rigid import frustum as fk
from pipeline.dynamics.integrators.dop853 import dop853_monitored
from pipeline.dynamics.rigid import patch
from pipeline.dynamics.rigid import rocking as rk
from pipeline.dynamics.rigid.layout import (
    EVENT_DIRECTIONS, EV_LAND, EV_LIE, EV_LIFT, EV_SLIP, EV_STICK, EV_TURN, MAX_STEPS, PHASE_FLIGHT, PHASE_REST,
    PHASE_ROLLING, PHASE_SLIDING, PHASE_SLIPPING
)
from pipeline.dynamics.rigid.loop import watch_contact


@njit(cache=True)
def _rocking_couple(theta, dtheta, load, opts):
    """Rolling-damping couple of the contact patch on planar rocking [m g R], and its power."""
    theta_k = opts[fk.OPT_THETA_K]
    if theta_k <= 0.0:
        return 0.0, 0.0
    m = patch.couples(load, abs(theta), theta_k, opts[fk.OPT_PATCH_DAMPING], opts[fk.OPT_MU], dtheta, 0.0)[0]
    return m, -m * dtheta


@njit(cache=True)
def rocking_contact(theta, dtheta, a_u, a_z, c, opts):
    """Planar rocking on a pivot that sticks: ``(F_u, N, theta'', damped)``.

    Forces per m g; the centre of mass relative to the pivot is ``(C_u, C_z)``
    (:func:`pipeline.dynamics.rigid.rocking.cm_offset`) and the contact force is
    ``F = m (C'' + a_g + g e_z)``. theta'' includes the viscous couple nu and
    the contact patch's rolling damping, whose power (with nu's) is ``damped``.
    """
    cu, cz = rk.cm_offset(theta, c[fk.C_ZC])
    nu = opts[fk.OPT_NU]
    ddtheta = rk.angular_acceleration(theta, a_u, a_z, c) - nu * dtheta / c[fk.C_IY]
    damped = nu * dtheta * dtheta
    w2 = dtheta * dtheta
    if opts[fk.OPT_THETA_K] > 0.0:
        m, power = _rocking_couple(theta, dtheta, -cu * ddtheta - cz * w2 + 1.0 + a_z, opts)
        ddtheta += m / c[fk.C_IY]
        damped += power
    f_u = cz * ddtheta - cu * w2 + a_u
    f_z = -cu * ddtheta - cz * w2 + 1.0 + a_z
    return f_u, f_z, ddtheta, damped


@njit(cache=True)
def rocking_slip(theta, dtheta, sigma, a_u, a_z, c, opts):
    """Planar rocking on a slipping pivot with the patch's couple: ``(theta'', x'', N, damped)``."""
    mu = opts[fk.OPT_MU]
    nu = opts[fk.OPT_NU]  # the viscous couple, as rolling has it
    viscous = -nu * dtheta
    ddtheta, ddx, normal, _den = rk.slip_accelerations(theta, dtheta, sigma, mu, a_u, a_z, c, viscous)
    if opts[fk.OPT_THETA_K] <= 0.0:
        return ddtheta, ddx, normal, nu * dtheta * dtheta
    m, power = _rocking_couple(theta, dtheta, normal, opts)
    ddtheta, ddx, normal, _den = rk.slip_accelerations(theta, dtheta, sigma, mu, a_u, a_z, c, m + viscous)
    return ddtheta, ddx, normal, power + nu * dtheta * dtheta


@njit(cache=True)
def _rhs2d_slipping(t, y, params, dydt):
    c, record, dt, opts = params[0], params[1], params[2], params[3]
    a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
    mu = opts[fk.OPT_MU]
    theta, dtheta = y[rk.THETA2], y[rk.DTHETA2]
    ddtheta, ddx, normal, damped = rocking_slip(theta, dtheta, opts[fk.OPT_SIGN], a_u, a_z, c, opts)
    v_u, v_z = rk.cm_velocity(theta, dtheta, y[rk.V2], c[fk.C_ZC])
    for i in range(dydt.shape[0]):
        dydt[i] = 0.0
    dydt[rk.THETA2] = dtheta
    dydt[rk.DTHETA2] = ddtheta
    dydt[rk.X2] = y[rk.V2]
    dydt[rk.V2] = ddx
    dydt[rk.WORK2] = -a_u * v_u - a_z * v_z
    dydt[rk.DISSIPATED2] = damped
    # sigma v, not |v|: the same while slipping, and smooth through the stick, which
    # the last step crosses before the event is located on its interpolant (|v| put a
    # kink there: up to 1.5e-5 of the work lost in 34 of 38720 2D runs)
    dydt[rk.FRICTION2] = mu * normal * opts[fk.OPT_SIGN] * y[rk.V2]


@njit(cache=True)
def _rhs2d_rolling(t, y, params, dydt):
    c, record, dt, opts = params[0], params[1], params[2], params[3]
    a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
    theta, dtheta = y[rk.THETA2], y[rk.DTHETA2]
    _f_u, _f_z, ddtheta, damped = rocking_contact(theta, dtheta, a_u, a_z, c, opts)
    v_u, v_z = rk.cm_velocity(theta, dtheta, 0.0, c[fk.C_ZC])
    for i in range(dydt.shape[0]):
        dydt[i] = 0.0
    dydt[rk.THETA2] = dtheta
    dydt[rk.DTHETA2] = ddtheta
    dydt[rk.WORK2] = -a_u * v_u - a_z * v_z
    dydt[rk.DISSIPATED2] = damped


@njit(cache=True)
def rhs2d(t, y, params, dydt):
    """Right-hand side of the phase ``params[3][OPT_PHASE]`` (planar rocking)."""
    record, dt, opts = params[1], params[2], params[3]
    phase = opts[fk.OPT_PHASE]
    if phase == PHASE_ROLLING:
        _rhs2d_rolling(t, y, params, dydt)
        return
    if phase == PHASE_SLIPPING:
        _rhs2d_slipping(t, y, params, dydt)
        return
    a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
    for i in range(dydt.shape[0]):
        dydt[i] = 0.0
    dydt[rk.X2] = y[rk.V2]
    if phase == PHASE_FLIGHT:
        dydt[rk.THETA2] = y[rk.DTHETA2]
        dydt[rk.V2] = -a_u
        dydt[rk.Z2] = y[rk.VZ2]
        dydt[rk.VZ2] = -1.0 - a_z
        dydt[rk.WORK2] = -a_u * y[rk.V2] - a_z * y[rk.VZ2]
    else:  # sliding flat
        mu = opts[fk.OPT_MU]
        dydt[rk.V2] = -a_u - mu * (1.0 + a_z) * opts[fk.OPT_SIGN]
        dydt[rk.WORK2] = -a_u * y[rk.V2]
        dydt[rk.FRICTION2] = mu * (1.0 + a_z) * opts[fk.OPT_SIGN] * y[rk.V2]  # smooth at the stop


@njit(cache=True)
def events2d(t, y, params, g):
    """Event functions of the current phase, planar rocking (``EV_*``)."""
    c, record, dt, opts = params[0], params[1], params[2], params[3]
    phase = opts[fk.OPT_PHASE]
    for i in range(g.shape[0]):
        g[i] = 1.0
    a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
    if phase == PHASE_SLIDING:
        g[EV_LIFT] = 1.0 + a_z
        g[EV_STICK] = opts[fk.OPT_SIGN] * y[rk.V2]
        return
    theta = y[rk.THETA2]
    g[EV_LIE] = abs(theta) - opts[fk.OPT_THETA_LIE]
    g[EV_TURN] = y[rk.DTHETA2]
    if phase == PHASE_FLIGHT:
        g[EV_LAND] = y[rk.Z2] - rk.cm_offset(theta, c[fk.C_ZC])[1]
        return
    # signed with the pivot side, so that theta_c = 0 is a crossing too
    g[EV_LAND] = opts[fk.OPT_PIVOT] * theta - (1.0 - opts[fk.OPT_LANDING_MARGIN]) * opts[fk.OPT_THETA_C]
    unilateral = opts[fk.OPT_UNILATERAL] != 0.0
    held = opts[fk.OPT_RIM_HELD] != 0.0  # (loop.holds_rim)
    if phase == PHASE_ROLLING:
        f_u, f_z, _dd, _p = rocking_contact(theta, y[rk.DTHETA2], a_u, a_z, c, opts)
        if held:
            # falls through 0 when a contact the model allows exists again (N pushes, for
            # mu = inf) or the flight would rise; no slip event while held
            contact = f_z
            if opts[fk.OPT_MU] < math.inf:
                stick, slip = _contact_margins2d(theta, y[rk.DTHETA2], f_u, f_z, a_u, a_z, c, opts)
                contact = max(stick, slip)
            g[EV_LIFT] = min(-contact, -flight_gap_acceleration2d(theta, y[rk.DTHETA2], a_z, c))
        elif unilateral:
            g[EV_LIFT] = f_z
        if opts[fk.OPT_MU] < math.inf and not held:
            g[EV_SLIP] = opts[fk.OPT_MU] * f_z - abs(f_u)
    else:
        if unilateral:
            normal = rocking_slip(theta, y[rk.DTHETA2], opts[fk.OPT_SIGN], a_u, a_z, c, opts)[2]
            # held: falls through 0 when N pushes again or the flight would rise
            g[EV_LIFT] = min(-normal, -flight_gap_acceleration2d(theta, y[rk.DTHETA2], a_z, c)) if held else normal
        g[EV_STICK] = opts[fk.OPT_SIGN] * y[rk.V2]


@njit(cache=True)
def _contact_margins2d(theta, dtheta, f_u, f_z, a_u, a_z, c, opts):
    """How near the contacts the model allows the pivot is [m g]: ``(stick, slip)``, each >= 0 if it is allowed.

    Rolling (``F_u, N`` = ``f_u, f_z``) within friction on a pushing N: ``min(N, mu N - |F_u|)``;
    the slip against the friction rolling would need (the choice of ``run2d._enter_contact2d``):
    its N.
    """
    sigma = -1.0 if f_u > 0.0 else 1.0
    normal = rocking_slip(theta, dtheta, sigma, a_u, a_z, c, opts)[2]
    return min(f_z, opts[fk.OPT_MU] * f_z - abs(f_u)), normal


@njit(cache=True)
def contact_margins2d(theta, dtheta, a_u, a_z, c, opts):
    """:func:`_contact_margins2d` of a planar state on its pivot [m g]."""
    f_u, f_z, _dd, _p = rocking_contact(theta, dtheta, a_u, a_z, c, opts)
    return _contact_margins2d(theta, dtheta, f_u, f_z, a_u, a_z, c, opts)


@njit(cache=True)
def monitor2d(t, y, params, g):
    """Peak mobilized friction and lowest normal force at every accepted step (planar).

    The event functions there (``g``) already hold N and ``mu N - |F_u|``.
    """
    c, record, dt, opts, summary = params[0], params[1], params[2], params[3], params[4]
    phase = opts[fk.OPT_PHASE]
    mu = opts[fk.OPT_MU]
    # the event functions hold N unless the rim is held (then they hold the hold's end)
    fast = opts[fk.OPT_UNILATERAL] != 0.0 and mu < math.inf and opts[fk.OPT_RIM_HELD] == 0.0
    if phase == PHASE_ROLLING:
        if fast:
            normal = g[EV_LIFT]
            f_t = mu * normal - g[EV_SLIP]
        else:
            a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
            f_u, normal, _dd, _p = rocking_contact(y[rk.THETA2], y[rk.DTHETA2], a_u, a_z, c, opts)
            f_t = abs(f_u)
            if opts[fk.OPT_RIM_HELD] != 0.0 and mu < math.inf:
                # a held rim is at its friction limit: what it asks beyond is the patch
                # couple's overreach (loop.holds_rim), not friction the ground gives
                f_t = min(f_t, mu * max(normal, 0.0))
        watch_contact(summary, f_t / normal if normal > 0.0 else 0.0, normal)
    elif phase == PHASE_SLIPPING:
        if fast:
            normal = g[EV_LIFT]
        else:
            a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
            normal = rocking_slip(y[rk.THETA2], y[rk.DTHETA2], opts[fk.OPT_SIGN], a_u, a_z, c, opts)[2]
        watch_contact(summary, mu, normal)
    elif phase == PHASE_SLIDING:
        watch_contact(summary, mu, g[EV_LIFT])
    elif phase == PHASE_FLIGHT:
        watch_contact(summary, 0.0, 0.0)


@njit(cache=True)
def integrate2d(params, t0, y0, t_end, t_out, y_out, out_start, t_breaks, rtol, atol, h0):
    return dop853_monitored(rhs2d, events2d, monitor2d, params, t0, y0, t_end, t_out, y_out, out_start,
                            EVENT_DIRECTIONS, t_breaks, rtol, atol, np.inf, h0, MAX_STEPS)


@njit(cache=True)
def energy2d(phase, y, c):
    """Mechanical energy [m g R] of a planar state in a given phase."""
    zc = c[fk.C_ZC]
    if phase == PHASE_REST:
        return zc
    if phase == PHASE_SLIDING:
        return zc + 0.5 * y[rk.V2] * y[rk.V2]
    theta, dtheta = y[rk.THETA2], y[rk.DTHETA2]
    if phase == PHASE_FLIGHT:
        return rk.energy_moving(theta, dtheta, y[rk.V2], y[rk.VZ2], y[rk.Z2], c)
    if phase == PHASE_SLIPPING:
        v_u, v_z = rk.cm_velocity(theta, dtheta, y[rk.V2], zc)
        return rk.energy_moving(theta, dtheta, v_u, v_z, rk.cm_offset(theta, zc)[1], c)
    return rk.energy(theta, dtheta, c)


@njit(cache=True)
def flight_gap_acceleration2d(theta, dtheta, a_z, c):
    """Planar :func:`flight_gap_acceleration`: the free column does not turn (theta'' = 0)."""
    return -1.0 - a_z + rk.cm_offset(theta, c[fk.C_ZC])[1] * dtheta * dtheta
