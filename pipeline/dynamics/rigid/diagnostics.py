"""Derived quantities of every output row of a rigid run: energy, contact force, friction, base position.

:func:`diagnostics_rows` (compiled) evaluates, for the rows of
:func:`pipeline.dynamics.rigid.run3d.run_frustum` or
:func:`pipeline.dynamics.rigid.run2d.run_rocking`, the columns ``D_*``: spin,
mechanical energy, normal and tangential force, mobilized friction, ground
acceleration, base centre, contact point and slip speed.
"""

import math

from numba import njit

from pipeline.dynamics.rigid import frustum as fk
from pipeline.dynamics.rigid import rocking as rk
from pipeline.dynamics.rigid.layout import (
    PHASE_FLIGHT, PHASE_OVERTURNED, PHASE_REST, PHASE_ROLLING, PHASE_SLIDING, PHASE_SLIPPING
)
from pipeline.dynamics.rigid.phases2d import energy2d, rocking_contact, rocking_slip
from pipeline.dynamics.rigid.phases3d import (
    consistent_direction, energy3d, horizontal_spin, layer_edge, rolling_contact, slip_with
)


(
    D_OMEGA,  # spin omega_zeta [1/tau]
    D_ENERGY,  # [m g R]
    D_NORMAL,  # normal force [m g]
    D_TANGENTIAL,  # |F_t| [m g]
    D_MU,  # |F_t| / N, nan in flight
    D_AX,  # ground acceleration [g]
    D_AY,
    D_AZ,
    D_BASE_X,  # base centre relative to the ground [R]
    D_BASE_Y,
    D_CONTACT_X,  # contact point on the rim, nan unless on the rim [R]
    D_CONTACT_Y,
    D_SLIP,  # speed of the sliding base or rim point [sqrt(g R)]
) = range(13)
N_DIAGNOSTICS = 13

# A rolling row asking more friction than mu N by more than this is a held rim (loop.holds_rim): the
# slip event keeps any other rolling row within mu N to its location's precision (1e-9, tests).
HELD_EXCESS = 1e-6


@njit(cache=True)
def _rolling_friction(f_t, f_z, opts):
    """|F_t| [m g] of a rolling row, a held rim's at its friction limit as the run's summary books it."""
    mu = opts[fk.OPT_MU]
    if mu < math.inf and opts[fk.OPT_UNILATERAL] != 0.0 and f_t > mu * max(f_z, 0.0) * (1.0 + HELD_EXCESS):
        return mu * max(f_z, 0.0)
    return f_t


@njit(cache=True, nogil=True)
def diagnostics_rows(tau, states, phase, params, model_3d, out):
    """Derived quantities of every output row (compiled loop), written to ``out`` (``D_*`` columns).

    Rows after the column lies down, or never reached, get NaN forces.
    """
    c, record, dt, opts = params
    zc = c[fk.C_ZC]
    mu = opts[fk.OPT_MU]
    for i in range(tau.shape[0]):
        t = tau[i]
        ax, ay, az = fk.ground_acceleration(t, record, dt)
        y = states[i]
        ph = phase[i]
        for k in range(N_DIAGNOSTICS):
            out[i, k] = math.nan
        out[i, D_AX], out[i, D_AY], out[i, D_AZ] = ax, ay, az
        out[i, D_SLIP] = 0.0
        if math.isnan(y[0]):
            continue
        if ph == PHASE_REST or ph == PHASE_SLIDING:
            normal = 1.0 + az
            out[i, D_OMEGA] = 0.0
            out[i, D_NORMAL] = normal
            out[i, D_BASE_X] = y[fk.XP] if model_3d else y[rk.X2]
            out[i, D_BASE_Y] = y[fk.YP] if model_3d else 0.0
            if ph == PHASE_REST:
                out[i, D_ENERGY] = zc
                out[i, D_TANGENTIAL] = math.sqrt(ax * ax + ay * ay)
            else:
                out[i, D_ENERGY] = energy3d(ph, y, c) if model_3d else energy2d(ph, y, c)
                out[i, D_TANGENTIAL] = mu * normal
                out[i, D_SLIP] = y[fk.SLIP_SPEED] if model_3d else abs(y[rk.V2])
            out[i, D_MU] = out[i, D_TANGENTIAL] / normal if normal > 0.0 else math.nan
            continue
        if ph == PHASE_OVERTURNED:
            continue
        if model_3d:
            _diagnose3d(t, y, ph, (c, record, dt, opts), out[i])
        else:
            _diagnose2d(t, y, ph, (c, record, dt, opts), out[i])


@njit(cache=True)
def _pivot_from_row(y, opts):
    """The drilling state of an output row, from its turning about the vertical through P."""
    om_z = horizontal_spin(y[fk.THETA], y[fk.DPHI], y[fk.DTHETA], y[fk.OMEGA])[2]
    scale = abs(y[fk.DPHI]) + abs(y[fk.OMEGA]) + abs(y[fk.DTHETA])
    held = opts[fk.OPT_THETA_K] > 0.0 and abs(om_z) <= 1e-9 * scale
    opts[fk.OPT_PIVOT_HELD] = 1.0 if held else 0.0
    opts[fk.OPT_DRILL_SIGN] = 0.0 if held or opts[fk.OPT_THETA_K] <= 0.0 else math.copysign(1.0, om_z)


@njit(cache=True)
def _row_direction(t, y, params):
    """Slip direction of an output row: stored, or slaved (consistent) inside the slow layer."""
    normal = slip_with(t, y, params, y[fk.SLIP_DIR])[0]
    if y[fk.SLIP_SPEED] >= layer_edge(y, params[3], normal):
        return y[fk.SLIP_DIR]
    return consistent_direction(t, y, params, y[fk.SLIP_DIR])


@njit(cache=True)
def _diagnose3d(t, y, ph, params, row):
    c = params[0]
    zc = c[fk.C_ZC]
    theta = y[fk.THETA]
    sp_, cp = fk.sincos(y[fk.PHI])
    row[D_OMEGA] = y[fk.OMEGA]
    if ph == PHASE_SLIPPING:
        synced = y.copy()
        synced[fk.SLIP_DIR] = _row_direction(t, y, params)
        row[D_ENERGY] = energy3d(ph, synced, c)
    else:
        row[D_ENERGY] = energy3d(ph, y, c)
    if ph == PHASE_FLIGHT:
        lean = zc * math.sin(theta)
        row[D_BASE_X] = y[fk.XP] - sp_ * lean
        row[D_BASE_Y] = y[fk.YP] + cp * lean
        row[D_NORMAL] = 0.0
        row[D_TANGENTIAL] = 0.0
        return
    row[D_BASE_X] = y[fk.XP] - sp_ * math.cos(theta)
    row[D_BASE_Y] = y[fk.YP] + cp * math.cos(theta)
    row[D_CONTACT_X] = y[fk.XP]
    row[D_CONTACT_Y] = y[fk.YP]
    if ph == PHASE_ROLLING:
        # the pivot was held where the column does not turn about the vertical through P
        _pivot_from_row(y, params[3])
        f_xi, f_n, f_z, _ax, _ay, _az = rolling_contact(t, y, params)
        f_t = _rolling_friction(math.sqrt(f_xi * f_xi + f_n * f_n), f_z, params[3])
    else:
        f_z = slip_with(t, y, params, synced[fk.SLIP_DIR])[0]
        f_t = params[3][fk.OPT_MU] * f_z
        row[D_SLIP] = y[fk.SLIP_SPEED]
    row[D_NORMAL] = f_z
    row[D_TANGENTIAL] = f_t
    row[D_MU] = f_t / f_z if f_z > 0.0 else math.nan


@njit(cache=True)
def _diagnose2d(t, y, ph, params, row):
    c, record, dt, opts = params
    zc = c[fk.C_ZC]
    theta = y[rk.THETA2]
    row[D_OMEGA] = 0.0
    row[D_ENERGY] = energy2d(ph, y, c)
    row[D_BASE_Y] = 0.0
    if ph == PHASE_FLIGHT:
        row[D_BASE_X] = y[rk.X2] - zc * math.sin(theta)
        row[D_NORMAL] = 0.0
        row[D_TANGENTIAL] = 0.0
        return
    side = math.copysign(1.0, theta)
    row[D_BASE_X] = y[rk.X2] - side * math.cos(theta)
    row[D_CONTACT_X] = y[rk.X2]
    row[D_CONTACT_Y] = 0.0
    a_u, _unused, a_z = fk.ground_acceleration(t, record, dt)
    if ph == PHASE_ROLLING:
        f_u, f_z, _dd, _p = rocking_contact(theta, y[rk.DTHETA2], a_u, a_z, c, opts)
        f_t = _rolling_friction(abs(f_u), f_z, opts)
    else:
        f_z = rocking_slip(theta, y[rk.DTHETA2], math.copysign(1.0, y[rk.V2]), a_u, a_z, c, opts)[2]
        f_t = opts[fk.OPT_MU] * f_z
        row[D_SLIP] = abs(y[rk.V2])
    row[D_NORMAL] = f_z
    row[D_TANGENTIAL] = f_t
    row[D_MU] = f_t / f_z if f_z > 0.0 else math.nan
