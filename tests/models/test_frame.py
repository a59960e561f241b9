"""The rigid planar frame of a colonnade, ``2d-frame`` (issue 37, item 2).

* The derivation of docs/model.md ("The rigid planar frame"), by sympy: the frame's energy is one
  rocking block's (alpha_e, I_e, the ground's forcing), with a moving pivot too (slip) and about
  its equivalent centre (flight); the landing's restitution from the impulse-momentum balance of
  every body; Makris & Vassiliou's closed forms for prismatic columns.
* The kernel runs that block: a massless epistyle gives the ``2d`` model's run; a scipy
  integration of the one-degree-of-freedom equation with impacts matches a pulse's peak; a slow
  ramp uplifts the frame at g tan(alpha_e); the landings apply the frame's restitution.
"""

import math

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

from pipeline.dynamics.rigid import frustum as fk
from pipeline.dynamics.rigid import rocking as rk
from pipeline.dynamics.rigid.run2d import run_rocking
from pipeline.errors import InputError
from pipeline.frame import frame_constants, frame_lying_tilt, frame_options
from pipeline.groundmotion.record import GroundMotion
from pipeline.groundmotion.synthesis import one_sine_pulse
from pipeline.settings import Excitation, ModelSettings
from pipeline.simulate import RIGID_CONTACT_TILT, kernel_options, kernel_record, run_kernel, simulate
from pipeline.structures.colonnade import Colonnade, frame_block, rigid_column
from pipeline.structures.column import Column
from pipeline.structures.drums import Capital, DrumColumn
from pipeline.units import G, time_scale

PAPER = Column(0.5, 0.4, 4.0)
WITH_CAPITAL = DrumColumn(PAPER, capital=Capital(1.0, 0.4))
IDEAL = dict(normal_stiffness=math.inf, friction=math.inf)  # the ideal frame: a rigid point contact, no slip


def frame_settings(**options):
    return ModelSettings(model="2d-frame", **options)


# --- the derivation (docs/model.md), by sympy ---------------------------------------------------------

th, dth, ddth, t = sp.symbols("theta theta_dot theta_ddot t", real=True)
N, m, M, R, c, zc, Ht, Ic, g = sp.symbols("N m M R c z_c H_t I_c g", positive=True)
au, az, vp = sp.symbols("a_u a_z v_p", real=True)


def vanishes(expr):
    """Whether ``expr``, rational in the symbols and polynomial in sin(theta), cos(theta), is identically 0:
    its numerator's remainder by sin^2 + cos^2 - 1 (faster than sympy's simplify, and as exact)."""
    s_, c_ = sp.symbols("s_ c_")
    numerator = sp.expand(sp.together(expr).as_numer_denom()[0].subs({sp.sin(th): s_, sp.cos(th): c_}))
    return sp.expand(sp.rem(numerator, s_**2 + c_**2 - 1, s_)) == 0


def rotated(u, z):
    """A point at (u, z) from the pivot at rest, after the frame tilts by theta towards +u."""
    return sp.Matrix([u * sp.cos(th) + z * sp.sin(th), -u * sp.sin(th) + z * sp.cos(th)])


def velocity(r):
    return r.diff(th) * dth


COLUMN = rotated(-R, zc)  # a column's centre of mass: pivot at +R of its axis
EDGE = rotated(-(R + c), Ht)  # the bearing edge opposite the pivot, at the abacus top
M_TOT = N * m + M
B_E = (N * m * R + M * (R + c)) / M_TOT
Z_E = (N * m * zc + M * Ht) / M_TOT
I_P = Ic + m * (R**2 + zc**2)
L_T2 = (R + c) ** 2 + Ht**2
I_E = N * I_P + M * L_T2


def test_the_frames_energy_is_one_rocking_blocks():
    """V = m_tot g (b_e sin theta + z_e cos theta), T = I_e theta'^2 / 2: the columns turn about their pivots,
    the epistyle translates with the bearing edges (no rotation of its own)."""
    T = N * (m * velocity(COLUMN).dot(velocity(COLUMN)) / 2 + Ic * dth**2 / 2) + M * velocity(EDGE).dot(velocity(EDGE)) / 2
    V = g * (N * m * COLUMN[1] + M * EDGE[1])
    assert vanishes(T - I_E * dth**2 / 2)
    assert vanishes(V - M_TOT * g * (B_E * sp.sin(th) + Z_E * sp.cos(th)))
    assert not vanishes(V - M_TOT * g * (R * sp.sin(th) + Z_E * sp.cos(th)))  # the check can fail


def _frame_acceleration():
    """theta'' of the frame from Lagrange's equation, the ground's acceleration a field on every mass."""
    T = N * (m * velocity(COLUMN).dot(velocity(COLUMN)) / 2 + Ic * dth**2 / 2) + M * velocity(EDGE).dot(velocity(EDGE)) / 2
    field = sp.Matrix([au, g + az])  # -a_g - g e_z on every mass: potential (a_u x + (g + a_z) z) per kg
    V = N * m * field.dot(COLUMN) + M * field.dot(EDGE)
    # d/dt dT/dtheta' with theta(t): dT/dtheta' is linear in theta', so d/dt = (d/dtheta) theta' + (d/dtheta') theta''
    p = sp.diff(T, dth)
    lagrange = sp.diff(p, th) * dth + sp.diff(p, dth) * ddth - sp.diff(T, th) + sp.diff(V, th)
    return -lagrange.subs(ddth, 0) / sp.diff(lagrange, ddth)  # it is linear in theta''


def test_the_frames_equation_of_motion_is_the_blocks_and_the_kernels():
    """I_e theta'' = m_tot [(g + a_z)(z_e sin theta - b_e cos theta) - a_u (z_e cos theta + b_e sin theta)] (theta > 0),
    and at random numbers the planar kernel with the frame's constants computes it (per g / b_e, time
    sqrt(b_e / g)) to round-off."""
    ddtheta = _frame_acceleration()
    block = M_TOT * ((g + az) * (Z_E * sp.sin(th) - B_E * sp.cos(th)) - au * (Z_E * sp.cos(th) + B_E * sp.sin(th))) / I_E
    assert vanishes(ddtheta - block)
    rng = np.random.default_rng(37)
    f = sp.lambdify((th, au, az, N, m, M, R, c, zc, Ht, Ic, g), ddtheta)
    for _ in range(20):
        n = int(rng.integers(2, 9))
        body = (rng.uniform(1e3, 1e5), rng.uniform(0.2, 1.0))  # m [kg], R [m]
        values = dict(n=n, m=body[0], M=rng.uniform(0.0, 3.0) * n * body[0], R=body[1],
                      c=rng.uniform(0.6, 1.4) * body[1], zc=rng.uniform(3.0, 8.0) * body[1])
        values.update(Ht=values["zc"] * rng.uniform(1.8, 2.2), Ic=values["m"] * values["zc"] ** 2 / 3.0)
        frame = frame_block(values["n"], rigid_column_of(values), values["M"], values["R"], values["c"], values["Ht"])
        constants = frame_constants(frame)
        theta, a_u, a_z = rng.uniform(0.01, 0.3), rng.uniform(-1.0, 1.0) * G, rng.uniform(-0.3, 0.3) * G
        expected = f(theta, a_u, a_z, values["n"], values["m"], values["M"], values["R"], values["c"], values["zc"],
                     values["Ht"], values["Ic"], G)
        kernel = rk.angular_acceleration(theta, a_u / G, a_z / G, constants) * G / frame.b_e
        assert kernel == pytest.approx(expected, rel=1e-12)


def rigid_column_of(values):
    """A RigidColumn of the test's numbers (mass, centre, I_P = I_c + m (R^2 + z_c^2))."""
    from pipeline.structures.colonnade import RigidColumn

    i_p = values["Ic"] + values["m"] * (values["R"] ** 2 + values["zc"] ** 2)
    return RigidColumn(values["m"], values["zc"], i_p, values["Ic"])


def test_with_moving_pivots_and_in_flight_the_energy_is_the_blocks_too():
    """Slip: the pivots move together at v_p; the kinetic energy is the block's,
    m_tot v_p^2 / 2 + m_tot v_p (d rbar/dtheta)_u theta' + I_e theta'^2 / 2 (rbar the mass-weighted mean of the
    column centres and the bearing edges). Flight: about the moving rbar it is m_tot |v|^2 / 2 + A theta'^2 / 2
    with A = I_e - m_tot |rbar|^2, the block's central inertia (the axes' offsets along the row do not turn)."""
    shift = sp.Matrix([vp, 0])
    T = (N * (m * (shift + velocity(COLUMN)).dot(shift + velocity(COLUMN)) / 2 + Ic * dth**2 / 2)
         + M * (shift + velocity(EDGE)).dot(shift + velocity(EDGE)) / 2)
    rbar = (N * m * COLUMN + M * EDGE) / M_TOT
    block = M_TOT * vp**2 / 2 + M_TOT * vp * velocity(rbar)[0] + I_E * dth**2 / 2
    assert vanishes(T - block)
    v = shift + velocity(rbar)  # the equivalent centre's velocity
    central = I_E - M_TOT * rbar.dot(rbar)
    assert vanishes(T - (M_TOT * v.dot(v) / 2 + central * dth**2 / 2))
    assert vanishes(rbar.dot(rbar) - (B_E**2 + Z_E**2))  # rbar is (b_e, z_e) turned: the block's


def _landing_restitution():
    """theta'+ / theta'- of a landing at theta = 0, by Newton-Euler in impulses for every body.

    Before: pivots at +R, the epistyle on the edges at -c; after: pivots at -R, the epistyle on the
    edges at +c. Unknowns: the rate after, the capitals' impulse J on the epistyle (each column gets
    -J/N at its new top edge) and the ground's impulse G on each column at its new pivot."""
    w_before, w_after, ju, jz, gu, gz = sp.symbols("w_before w_after J_u J_z G_u G_z", real=True)
    # velocities from the rotation about the old and the new pivot, at theta = 0: v = w (z, -u)
    v_col_before = w_before * sp.Matrix([zc, R])  # centre at (-R, z_c) from the old pivot
    v_col_after = w_after * sp.Matrix([zc, -R])  # at (+R, z_c) from the new one
    v_epi_before = w_before * sp.Matrix([Ht, R + c])
    v_epi_after = w_after * sp.Matrix([Ht, -(R + c)])
    J = sp.Matrix([ju, jz])
    Gi = sp.Matrix([gu, gz])

    def moment(r, f):  # about the centre of mass; positive tilts towards +u
        return r[1] * f[0] - r[0] * f[1]

    new_pivot_from_centre = sp.Matrix([-R, -zc])
    new_edge_from_centre = sp.Matrix([c, Ht - zc])
    equations = list(M * (v_epi_after - v_epi_before) - J)
    equations += list(m * (v_col_after - v_col_before) - (Gi - J / N))
    equations.append(Ic * (w_after - w_before) - (moment(new_pivot_from_centre, Gi)
                                                  + moment(new_edge_from_centre, -J / N)))
    solution = sp.solve(equations, (w_after, ju, jz, gu, gz), dict=True)[0]
    return sp.simplify(solution[w_after] / w_before)


def test_the_landings_restitution_from_angular_momentum_about_the_new_pivots():
    """e = 1 - 2 (N m R^2 + M (R + c)^2) / I_e: the columns' angular momentum about their new pivots is kept but
    for the epistyle's impulse at the new top edges; the 2d model's 1 - 2 m R^2 / I_P without an epistyle."""
    e = _landing_restitution()
    assert sp.simplify(e - (1 - 2 * (N * m * R**2 + M * (R + c) ** 2) / I_E)) == 0
    assert sp.simplify(e.subs(M, 0) - (1 - 2 * m * R**2 / I_P)) == 0


def test_prismatic_columns_give_makris_and_vassilious_closed_forms():
    """Columns of width 2b and height 2h, no capital (c = b, H_t = 2h, I_P = 4 m (b^2 + h^2) / 3), gamma =
    M / (N m): alpha_e = alpha, p_e = p sqrt((1 + 2 gamma)/(1 + 3 gamma)), e = (1 - 1.5 sin^2 alpha + 3 gamma
    cos 2 alpha)/(1 + 3 gamma) (Makris & Vassiliou 2013); the uplift does not depend on gamma."""
    b, h, gamma = sp.symbols("b h gamma", positive=True)
    prismatic = {R: b, c: b, zc: h, Ht: 2 * h, Ic: m * (b**2 + h**2) / 3, M: gamma * N * m}
    alpha = sp.atan(b / h)
    L = sp.sqrt(b**2 + h**2)
    assert sp.simplify((B_E / Z_E).subs(prismatic) - b / h) == 0
    p2 = 3 * g / (4 * L)
    p_e2 = (M_TOT * g * sp.sqrt(B_E**2 + Z_E**2) / I_E).subs(prismatic)
    assert sp.simplify(p_e2 - p2 * (1 + 2 * gamma) / (1 + 3 * gamma)) == 0
    makris = (1 - sp.Rational(3, 2) * sp.sin(alpha) ** 2 + 3 * gamma * sp.cos(2 * alpha)) / (1 + 3 * gamma)
    e = (1 - 2 * (N * m * R**2 + M * (R + c) ** 2) / I_E).subs(prismatic)
    assert sp.simplify(sp.expand_trig(e - makris)) == 0


def test_the_frame_block_of_prismatic_columns_is_makris_and_vassilious_to_round_off():
    """The same closed forms from pipeline.structures.colonnade.frame_block, in numbers: prismatic columns
    (R = r = 0.4 m, h = 4 m, no capital) under epistyles of gamma 0.2 to 3: alpha_e = alpha for the cylinders
    of a Colonnade, and p_e, e for Makris's rectangular blocks."""
    column = Column(0.4, 0.4, 4.0, density=2500.0)
    body = rigid_column(column)
    b, hh = 0.4, 2.0
    L = math.hypot(b, hh)
    alpha = math.atan(b / hh)
    p = math.sqrt(3 * G / (4 * L))
    for n, gamma in [(2, 0.2), (4, 1.0), (6, 3.0)]:
        # the cylinder's own frame: its uplift does not depend on gamma either (R + c = 2 R, H_t = 2 z_c)
        row = Colonnade(column, n, 1.0, 1.0)
        assert row.frame.alpha == pytest.approx(alpha, rel=1e-14)
        # Makris's blocks are rectangular, I_P = 4 m L^2 / 3 (a cylinder's is not): their closed forms on their body
        box = body._replace(inertia_pivot=4 / 3 * body.mass * L**2)
        frame = frame_block(n, box, gamma * n * body.mass, b, b, 2 * hh)
        assert frame.alpha == pytest.approx(alpha, rel=1e-14)
        assert frame.uplift_acceleration == pytest.approx(G * math.tan(alpha), rel=1e-14)
        assert frame.frequency_parameter == pytest.approx(p * math.sqrt((1 + 2 * gamma) / (1 + 3 * gamma)), rel=1e-14)
        makris = (1 - 1.5 * math.sin(alpha) ** 2 + 3 * gamma * math.cos(2 * alpha)) / (1 + 3 * gamma)
        assert frame.restitution == pytest.approx(makris, rel=1e-14)


@pytest.mark.parametrize("column, c, H_t", [(WITH_CAPITAL, 0.5, 4.4),
                                             (DrumColumn(Column(0.9525, 0.74, 9.57), capital=Capital(2.0, 0.86)),
                                              1.0, 10.43)], ids=["paper-capital", "parthenon"])
def test_for_frustums_with_capitals_the_epistyle_moves_the_uplift_towards_its_bearing_edges(column, c, H_t):
    """tan alpha_e runs from the column's R / z_c (no epistyle) towards (R + c) / H_t (a heavy one),
    monotonically: down for the paper's column under a 1 x 0.4 m capital (0.2304 to 1.0 / 4.4), up for the
    Parthenon's (0.1847 to 1.9525 / 10.43)."""
    body = rigid_column(column)
    R = column.column.R
    tans = [frame_block(2, body, gamma * 2 * body.mass, R, c, H_t).uplift_acceleration / G
            for gamma in (0.0, 0.5, 2.0, 1e6)]
    assert tans[0] == pytest.approx(R / body.z_c, rel=1e-14)
    assert tans[3] == pytest.approx((R + c) / H_t, rel=1e-5)
    direction = np.sign(np.diff(tans))
    assert np.all(direction == np.sign((R + c) / H_t - R / body.z_c))


# --- the runs ------------------------------------------------------------------------------------------


def pulse(amplitude, period, dt=0.002):
    return one_sine_pulse(amplitude, period, dt=dt, duration=period, direction=0.0, record_id="frame-pulse")


@pytest.fixture
def massless_epistyle(monkeypatch):
    """The epistyle's mass set to 0 exactly: the frame is then N columns rocking apart, each as one body."""
    monkeypatch.setattr(Colonnade, "epistyle_mass", property(lambda self: 0.0))


@pytest.mark.parametrize("options", [{}, IDEAL, dict(damping=0.05, friction=0.3, normal_stiffness=1e9)],
                         ids=["defaults", "ideal", "damped-slipping-soft"])
def test_a_massless_epistyle_gives_the_2d_models_run_of_the_column(massless_epistyle, options):
    """Without a capital the column is the 2d model's frustum: its peak tilt, uplift time and impacts are the
    2d model's to round-off (the constants agree to a few ulps: I_e / (m_tot b_e^2) against I_y_hat). The
    same options mean the same physics on both: friction, the bed's patch, the viscous couple."""
    record = pulse(0.35 * G, 0.6)
    row = Colonnade(PAPER, 3, 1.5, 0.3)
    frame = simulate(row, record, Excitation(angle=10.0), frame_settings(tail=1.0, **options)).summary
    column = simulate(PAPER, record, Excitation(angle=10.0), ModelSettings(model="2d", tail=1.0, **options)).summary
    assert column["uplifted"] and column["n_impacts"] > 0
    for name in ("peak_theta", "peak_time", "uplift_time", "peak_mu_mob", "residual_displacement", "work_ground"):
        # the base's residual displacement is a sum over landings of +-2 R cos(theta_c): exact to round-off of R
        # at each, 6e-13 m apart measured; the rest to the integrator's tolerance at most
        assert frame[name] == pytest.approx(column[name], rel=1e-9, abs=1e-10), name
    for name in ("n_impacts", "overturned", "sliding_onset", "lift_off"):
        assert frame[name] == column[name], name


def test_a_massless_epistyle_gives_the_planar_run_of_a_column_with_its_capital(massless_epistyle):
    """With a capital, the 2d kernel run on the column and capital as one rigid body (its own constants,
    I_P / (m R^2) and z_c / R, and the kernel's own restitution 1 - 2 / I_y): the frame's peak tilt and uplift
    time to round-off."""
    record = pulse(0.4 * G, 0.6)
    row = Colonnade(WITH_CAPITAL, 2, 2.0, 0.5)
    settings = frame_settings(tail=1.0, **IDEAL)
    frame = simulate(row, record, Excitation(), settings).summary
    body = rigid_column(WITH_CAPITAL)
    R = PAPER.R
    iy, z = body.inertia_pivot / (body.mass * R**2), body.z_c / R
    constants = fk.column_constants(iy, 1.0 + 1.1 * z * z / (iy - 1.0), z)  # I_z does not enter planar rocking
    t_scale = time_scale(R)
    options = kernel_options(settings, frame_lying_tilt(row), 0.0, 0.0, 0.0, RIGID_CONTACT_TILT)
    params = (constants, kernel_record(record, Excitation(), True), record.dt / t_scale, options)
    raw = run_kernel(run_rocking, params, t_scale, -1.0, settings, np.zeros(rk.N_STATE2), record.duration + 1.0)
    assert raw.summary[5] > 0  # it landed (S_N_IMPACTS)
    assert frame["peak_theta"] == pytest.approx(raw.summary[1], rel=1e-9)
    assert frame["uplift_time"] == pytest.approx(raw.summary[4] * t_scale, rel=1e-12)
    assert frame["n_impacts"] == int(raw.summary[5])


def _reference_peak(row, record, e, end):
    """The frame's one-degree-of-freedom equation with impacts, integrated by scipy (DOP853, rtol 1e-12).

    I_e theta'' = m_tot [g (z_e sin|theta| - b_e cos|theta|) sgn(theta) - a_u (z_e cos theta + b_e sin|theta|)],
    a_u the record linearly interpolated as the kernel reads it (0 after it); from rest until |a_u| =
    g b_e / z_e, then rocking, theta' scaled by e where theta crosses 0, until ``end`` [s]. Everything from
    the parts (masses and inertia of pipeline.structures.colonnade.rigid_column, tested on their own).
    Returns the largest |theta| at a turning point [rad] and its time [s]."""
    body = rigid_column(row.column)
    n, M = row.n_columns, row.epistyle_mass
    R, c, H_t = row.column.column.R, row.half_abacus, row.abacus_top
    m_tot = n * body.mass + M
    b = (n * body.mass * R + M * (R + c)) / m_tot
    z = (n * body.mass * body.z_c + M * H_t) / m_tot
    I_e = n * body.inertia_pivot + M * ((R + c) ** 2 + H_t**2)
    times = np.arange(len(record.acc_x)) * record.dt
    acc = np.asarray(record.acc_x, dtype=float)
    # rest until the ground tips it: the first sample interval where |a| reaches g b / z, solved linearly
    k = int(np.argmax(np.abs(acc) >= G * b / z))
    target = math.copysign(G * b / z, acc[k])
    t = times[k - 1] + (target - acc[k - 1]) / (acc[k] - acc[k - 1]) * record.dt
    side = -math.copysign(1.0, acc[k])  # the inertial force -a tips it away from the acceleration

    def rhs(s, y):
        th_ = abs(y[0])
        a = np.interp(s, times, acc, right=0.0)
        return [y[1], m_tot * (G * (z * math.sin(th_) - b * math.cos(th_)) * side
                               - a * (z * math.cos(th_) + b * math.sin(th_))) / I_e]

    def crossing(s, y):
        return y[0]

    def turning(s, y):
        return y[1]

    crossing.terminal = True
    peak = (0.0, math.nan)
    y = [side * 1e-300, 0.0]
    while t < end:
        crossing.direction = -side
        sol = solve_ivp(rhs, (t, end), y, method="DOP853", rtol=1e-12, atol=1e-15, events=(crossing, turning),
                        max_step=record.dt, dense_output=True)
        for s, state in zip(sol.t_events[1], sol.y_events[1]):
            if abs(state[0]) > peak[0]:
                peak = (abs(state[0]), s)
        if not sol.t_events[0].size or abs(sol.y_events[0][0][1]) < 1e-9:  # the end, or settled
            break
        t = sol.t_events[0][0]
        y = [0.0, e * sol.y_events[0][0][1]]
        side = -side
    return peak


def test_an_independent_integration_of_the_frames_equation_matches_the_run():
    """A one-sine pulse of 1.6 g tan(alpha_e) over 0.5 s rocks the paper's columns with capitals under a
    0.6 m epistyle; scipy's DOP853 (rtol 1e-12) on the frame's equation, with the record interpolated as the
    kernel reads it and theta' scaled by the frame's e at every crossing of 0, gives the largest peak. The
    run (the ideal frame, landing at theta = 0: contact_tilt 0; rtol 1e-11) agrees within 1e-7 in the peak
    and its time: the global errors of both integrators at these tolerances over a few landings are far
    below it, and the peak is a maximum, so an error in its time enters the tilt to second order only."""
    row = Colonnade(WITH_CAPITAL, 3, 2.0, 0.6)
    frame = row.frame
    record = pulse(1.6 * frame.uplift_acceleration, 0.5, dt=0.001)
    settings = frame_settings(tail=1.5, contact_tilt=0.0, rtol=1e-11, atol=1e-14, **IDEAL)
    summary = simulate(row, record, Excitation(), settings).summary
    expected, when = _reference_peak(row, record, frame.restitution, record.duration + 1.5)
    assert summary["n_impacts"] > 1 and not summary["lift_off"]
    assert summary["peak_theta"] == pytest.approx(expected, rel=1e-7)
    assert summary["peak_time"] == pytest.approx(when, rel=1e-7)


def test_a_slow_ramp_uplifts_the_frame_at_g_tan_alpha_e():
    """A ramp of 0.05 g/s, sampled every 0.01 s: the piecewise-linear record is the ramp itself, and the run's
    uplift time is g tan(alpha_e) / rate within the ramp's resolution (one sample: 5e-4 g) and, as the kernel
    solves the crossing on it exactly, to round-off. tan(alpha_e) from the parts, here in the test."""
    row = Colonnade(WITH_CAPITAL, 4, 2.0, 0.8, course_height=0.4)
    body = rigid_column(WITH_CAPITAL)
    n, M = 4, row.epistyle_mass
    tan_alpha = (n * body.mass * 0.5 + M * (0.5 + 0.5)) / (n * body.mass * body.z_c + M * 4.4)
    rate = 0.05 * G  # [m/s^2 per s]
    t_up = G * tan_alpha / rate
    dt = 0.01
    times = np.arange(0.0, t_up + 1.0, dt)
    record = GroundMotion.from_arrays(rate * times, np.zeros_like(times), dt, record_id="ramp")
    summary = simulate(row, record, Excitation(), frame_settings(tail=0.0, **IDEAL)).summary
    assert abs(summary["uplift_time"] - t_up) < dt
    assert summary["uplift_time"] == pytest.approx(t_up, rel=1e-12)
    assert tan_alpha < 0.5 / body.z_c  # the epistyle lowered it below the column's own


def test_the_landings_apply_the_frames_restitution():
    """Every landing of the ideal frame scales theta' by the frame's e (the impact log, to round-off); a given
    restitution replaces it."""
    row = Colonnade(WITH_CAPITAL, 2, 2.0, 0.5)
    record = pulse(1.5 * row.frame.uplift_acceleration, 0.6)
    for given, e in [(None, row.frame.restitution), (0.8, 0.8)]:
        response = simulate(row, record, Excitation(), frame_settings(tail=2.0, restitution=given, **IDEAL))
        impacts = response.impacts
        assert len(impacts) > 1
        assert impacts[:, 2] / impacts[:, 1] == pytest.approx(np.full(len(impacts), e), rel=1e-13)
        assert response.histories.attrs["restitution"] == pytest.approx(e, rel=1e-15)


def test_the_options_are_the_frames(massless_epistyle):
    """The patch and the couple on the frame's terms: theta_k under a base's share, N couples of one column's."""
    row = Colonnade(WITH_CAPITAL, 3, 2.0, 0.5)
    settings = frame_settings(damping=0.2, normal_stiffness=1e9)
    opts = frame_options(row, settings)
    body = rigid_column(WITH_CAPITAL)
    assert opts[fk.OPT_THETA_K] == pytest.approx(body.mass * G / (1e9 * math.pi * 0.5**3), rel=1e-14)
    assert opts[fk.OPT_THETA_C] == opts[fk.OPT_THETA_K]
    assert opts[fk.OPT_NU] == pytest.approx(0.2, rel=1e-14)  # massless epistyle: b_e = R, m_tot = N m
    assert math.isnan(frame_constants(row.frame)[fk.C_IZ])  # the 3D constants are no frame's


def test_the_viscous_couple_is_the_2d_models_at_every_column_base():
    """damping nu puts nu m g R sqrt(R/g) theta' at each of the N bases (m the column's mass with its capital):
    the energy it removes, per the frame's weight, is N nu m g R sqrt(R/g) int theta'^2 dt / (m_tot g). The
    integral by the trapezoid rule on a 1 ms output grid of a smooth rocking history: within 1e-3."""
    row = Colonnade(WITH_CAPITAL, 3, 2.0, 0.6)
    frame = row.frame
    record = pulse(1.6 * frame.uplift_acceleration, 0.5)
    response = simulate(row, record, Excitation(), frame_settings(tail=1.0, damping=0.3, output_step=0.001, **IDEAL))
    rate = response.histories.theta_dot.values
    couple = 3 * 0.3 * frame.m * G * frame.R * math.sqrt(frame.R / G)  # [N m s]
    removed = couple * np.trapezoid(rate**2, dx=0.001) / (frame.m_tot * G)
    assert response.summary["energy_dissipated"] == pytest.approx(removed, rel=1e-3)
    assert response.summary["energy_dissipated"] > 1e-3 * response.summary["work_ground"]


@pytest.mark.parametrize("model, body", [("2d-frame", Colonnade(WITH_CAPITAL, 2, 2.0, 0.5)),
                                         ("2d", Column(0.3, 0.24, 2.4)),
                                         ("3d", Column(0.3, 0.24, 2.4))], ids=["frame", "2d", "3d"])
def test_the_last_row_of_the_histories_is_the_runs_end(model, body):
    """The output grid's last instant, 100 steps of 0.01 s, rounded past the run's end in the kernel's time
    (by 9e-16 for R = 0.3 m, the column's unit, and for this frame's b_e = 0.601 m): the integration stopped before it
    and the row stayed unfilled (at rest, positions NaN) while the column rocked on."""
    record = one_sine_pulse(4.0, 0.5, dt=0.005, duration=0.6, direction=0.0, record_id="frame-pulse")
    h = simulate(body, record, Excitation(), ModelSettings(model=model, tail=0.4)).histories
    assert h.time.values[-1] == pytest.approx(1.0, abs=1e-12)
    assert h.phase.values[-1] == h.phase.values[-2] != 0  # still rocking at the end
    assert not np.isnan(h.x_b.values[-1]) and h.theta.values[-1] > 0


def test_a_frame_model_refuses_a_column_and_the_others_refuse_a_colonnade():
    record = pulse(3.0, 0.5)
    with pytest.raises(InputError, match="model = '2d-frame' runs colonnades: a monolithic column needs one of "
                                         "3d, 2d, 3d-compliant"):
        simulate(PAPER, record, Excitation(), frame_settings())
    with pytest.raises(InputError, match="model = '2d' runs monolithic columns: a colonnade of 2 columns needs one "
                                         "of 3d-compliant, 2d-frame"):
        simulate(Colonnade(PAPER, 2, 1.5, 0.3), record, Excitation(), ModelSettings(model="2d"))


def test_the_frames_file_says_which_colonnade_ran_and_reads_back_to_it():
    """Issue 47, item 1: the frame's histories name the colonnade and the model in their title and hold the row in
    their attributes, which read back to the same frame (what frustum animate draws); an overturned frame fell as
    one body, the colonnade (before: the title explained the variables, the row was colonnade_columns,
    colonnade_interaxial_m, ..., and no run said which body fell)."""
    from pipeline.structures.description import colonnade_from_attributes

    row = Colonnade(WITH_CAPITAL, 3, 2.0, 0.5, 0.9, 0.2)
    pulse = one_sine_pulse(8.0, 1.0, dt=0.01, record_id="pulse")
    run = simulate(row, pulse, Excitation(), frame_settings(tail=2.0))
    attrs = run.histories.attrs
    assert attrs["title"] == ("Response to ground motion of a colonnade of 3 monolithic columns with capitals carrying "
                              "2 epistyle blocks run by the 2D rigid frame of a colonnade (2d-frame)")
    assert "colonnade_columns" not in attrs and attrs["comment"].startswith("2d-frame, the colonnade as a rigid planar")
    back = colonnade_from_attributes(attrs, PAPER)
    assert back.frame == row.frame and back.axes() == row.axes() and back.block_height == pytest.approx(0.7)
    assert attrs["theta_crit_rad"] == row.frame.alpha
    assert run.summary["overturned"] and run.summary["overturn_body"] == "the colonnade"  # the premise and the word
    still = simulate(row, one_sine_pulse(0.5, 1.0, dt=0.01, record_id="pulse"), Excitation(), frame_settings())
    assert not still.summary["overturned"] and still.summary["overturn_body"] == ""
