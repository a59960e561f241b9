"""Free motion: invariants, the planar limit (Eq. 14), the thin-disc limit."""

import math

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

from pipeline.dynamics.rigid import frustum as fk
from pipeline.structures.column import Column
from pipeline.settings import InitialState, ModelSettings
from pipeline.simulate import simulate_free
from pipeline.units import G

PAPER_COLUMN = Column(R=0.5, r=0.4, h=4.0)  # Figure 4
TAU_100 = 100 * math.sqrt(PAPER_COLUMN.R / G)  # tau = 100 in seconds

# (theta0, phi'0, psi'0) in the paper's dimensionless rates: IC1-IC3 (Eqs. 19-21)
# and the two Section 4 cases (Figures 6-8 and 10).
PAPER_CASES = {
    "IC1": (math.radians(1), 0.0, 0.0),
    "IC2": (math.radians(1), 0.01, 0.0),
    "IC3": (math.radians(1), 0.1, 0.0),
    "fig6-8": (math.pi / 18, 0.1, -0.2),
    "fig10": (math.pi / 18, 0.1, 0.5),
}


def _run(case, column=PAPER_COLUMN, duration=TAU_100, restitution=1.0, samples=4000):
    theta0, dphi0, dpsi0 = PAPER_CASES[case]
    init = InitialState.from_dimensionless(column.R, 0.0, theta0, 0.0, dphi0, 0.0, dpsi0)
    settings = ModelSettings(rtol=1e-12, atol=1e-14, output_step=duration / samples, contact_tilt=0.0)
    return simulate_free(column, init, duration, settings, restitution=restitution)


@pytest.fixture(scope="module")
def paper_runs():
    return {case: _run(case) for case in PAPER_CASES}


@pytest.mark.parametrize("case", list(PAPER_CASES))
def test_energy_is_conserved_over_tau_100(paper_runs, case):
    ds = paper_runs[case]
    assert not np.isnan(ds.theta.values).any()  # ran to the end, never lay down
    assert float(ds.tau[-1]) == pytest.approx(100.0)
    energy = ds.energy_hat.values
    # acceptance: 1e-9 relative; DOP853 at rtol 1e-12 gives ~1e-11 (IC1 includes
    # 58 elastic pivot switches, which conserve energy exactly).
    assert np.max(np.abs(energy - energy[0])) / energy[0] < 1e-9


def test_ic1_stays_planar_and_follows_eq14(paper_runs):
    ds = paper_runs["IC1"]
    # planar by construction: not approximately but exactly
    assert np.all(ds.x_p.values == 0.0)
    assert np.all(ds.phi_dot.values == 0.0) and np.all(ds.omega_zeta.values == 0.0)
    assert set(np.unique(ds.phi.values)) <= {0.0, math.pi}
    # Eq. 14, integrated on its own up to the first landing
    c = PAPER_COLUMN
    hk1, Iy = c.slenderness * c.k1, c.inertia_transverse_hat
    eq14 = lambda t, y: [y[1], (hk1 * math.sin(y[0]) - 2 * math.cos(y[0])) / (2 * Iy)]  # noqa: E731
    land = lambda t, y: y[0]  # noqa: E731
    land.terminal, land.direction = True, -1
    tau = ds.tau.values
    sol = solve_ivp(eq14, (0, 100), [math.radians(1), 0.0], method="DOP853", rtol=1e-12, atol=1e-14,
                    events=land, dense_output=True)
    before = tau < sol.t[-1]
    assert before.sum() > 10
    # two DOP853 solutions at rtol 1e-12 of the same ODE: agreement ~1e-12 of theta0
    np.testing.assert_allclose(ds.theta.values[before], sol.sol(tau[before])[0], rtol=0, atol=1e-12)
    # With elastic landings (restitution 1) the rocking is the periodic
    # extension of Eq. 14's quarter cycle: fall for tau_L, rise for tau_L.
    tau_land = sol.t[-1]
    phase = np.mod(tau, 2 * tau_land)
    mirrored = np.where(phase <= tau_land, phase, 2 * tau_land - phase)
    # 58 landings, each located to ~1e-12 relative in tau (<= 1e-10 by tau = 100),
    # drift the phase by <= 6e-9; theta then differs by <= |theta'|max (0.03)
    # times that, 2e-10: 5e-10 bounds it.
    np.testing.assert_allclose(ds.theta.values, sol.sol(mirrored)[0], rtol=0, atol=5e-10)


@pytest.mark.parametrize("case", ["IC2", "IC3"])
def test_ic2_ic3_leave_the_plane_of_rocking(paper_runs, case):
    """Figure 5: a small initial precession rate moves X_P out of the plane X = 0."""
    x_hat = paper_runs[case].x_p.values / PAPER_COLUMN.R
    assert np.max(np.abs(x_hat)) > 0.5  # Figure 5 shows |X_hat| of order 1 by tau = 100
    assert np.all(paper_runs[case].theta.values > 0)  # wobbling: no landing (Section 4.2)


# --- thin-disc limit ---------------------------------------------------------

def _disc_by_lagrange_multipliers():
    """Rolling thin disc (radius 1, unit mass, g = 1) by the Lagrange equations with multipliers.

    Independent of pipeline.dynamics.derivation: the centre's velocity comes
    from differentiating its position in all five coordinates
    (phi, theta, psi, X, Y), and rolling enters through the multipliers of the
    constraints X' + psi' cos(phi) = 0, Y' + psi' sin(phi) = 0 (the paper's
    Eqs. 2 and 8).
    """
    t = sp.Symbol("t")
    q = [sp.Function(n)(t) for n in ("phi", "theta", "psi", "X", "Y")]
    ph, th, ps, X, Y = q
    dq = [sp.diff(v, t) for v in q]
    centre = sp.Matrix([X - sp.sin(ph) * sp.cos(th), Y + sp.cos(ph) * sp.cos(th), sp.sin(th)])
    v = centre.diff(t)
    w = [dq[1], dq[0] * sp.sin(th), dq[0] * sp.cos(th) + dq[2]]  # body components (paper Eq. 3)
    T = (v.dot(v) + sp.Rational(1, 4) * (w[0] ** 2 + w[1] ** 2) + sp.Rational(1, 2) * w[2] ** 2) / 2
    L = T - centre[2]
    lam = sp.symbols("l1 l2")
    B = [[0, 0, sp.cos(ph), 1, 0], [0, 0, sp.sin(ph), 0, 1]]
    eqs = [sp.diff(sp.diff(L, dq[i]), t) - sp.diff(L, q[i]) - sum(lam[j] * B[j][i] for j in range(2))
           for i in range(5)]
    ddq = [sp.diff(v, t, 2) for v in q]
    # constraints differentiated once, to close the system for the accelerations
    eqs += [sp.diff(dq[3] + dq[2] * sp.cos(ph), t), sp.diff(dq[4] + dq[2] * sp.sin(ph), t)]
    syms = sp.symbols("p th s x y dp dth ds dx dy ap ath as ax ay")
    sub = {}
    for i in range(5):
        sub[ddq[i]] = syms[10 + i]
    for i in range(5):
        sub[dq[i]] = syms[5 + i]
    for i in range(5):
        sub[q[i]] = syms[i]
    eqs = [e.subs(sub) for e in eqs]
    unknowns = list(syms[10:]) + list(lam)
    Mat, rhs = sp.linear_eq_to_matrix(eqs, unknowns)
    f = sp.lambdify(syms[:10], (Mat, rhs), "numpy")

    def accel(theta, dphi, dtheta, dpsi):
        Mn, rn = f(0.3, theta, 0.0, 0.0, 0.0, dphi, dtheta, dpsi, -dpsi * math.cos(0.3), -dpsi * math.sin(0.3))
        sol = np.linalg.solve(np.array(Mn, dtype=float), np.array(rn, dtype=float).ravel())
        return sol[0], sol[1], sol[2]

    return accel


def test_thin_disc_limit_matches_independent_rolling_disc_model():
    disc = _disc_by_lagrange_multipliers()
    thin = Column(R=1.0, r=1.0, h=1e-9)
    c = thin.kernel_constants()
    # h -> 0, beta = 1: Iy -> 5/4 (1/4 + 1), Iz -> 3/2, zc -> 0, errors O(h)
    assert c[fk.C_IY] == pytest.approx(1.25, abs=1e-8)
    assert c[fk.C_IZ] == pytest.approx(1.5, abs=1e-12)
    assert c[fk.C_ZC] == pytest.approx(0.0, abs=1e-8)
    rng = np.random.default_rng(7)
    for _ in range(50):
        theta, dphi, dtheta, dpsi = rng.uniform(0.05, 1.4), *rng.normal(0, 1.5, 3)
        ddphi, ddtheta, domega = fk.accelerations(theta, dphi, dtheta, dphi * math.cos(theta) + dpsi, 0.0, 0.0, 0.0, c)
        ours = (ddphi, ddtheta, domega + dphi * math.sin(theta) * dtheta - ddphi * math.cos(theta))  # psi''
        theirs = disc(theta, dphi, dtheta, dpsi)
        # O(h) = 1e-9 differences in the constants, times accelerations of O(10)
        np.testing.assert_allclose(ours, theirs, rtol=1e-7, atol=1e-7)


def test_thin_disc_trajectory_matches_independent_model():
    disc = _disc_by_lagrange_multipliers()

    def fun(t, y):
        a = disc(y[1], y[3], y[4], y[5])
        return [y[3], y[4], y[5], *a]

    y0 = [0.0, 0.4, 0.0, 0.8, 0.0, 1.9]  # a rolling, wobbling coin
    ref = solve_ivp(fun, (0, 15), y0, method="DOP853", rtol=1e-11, atol=1e-13, dense_output=True)
    thin = Column(R=1.0, r=1.0, h=1e-9)
    init = InitialState.from_dimensionless(1.0, *y0)
    ds = simulate_free(thin, init, 15 * math.sqrt(1 / G),
                       ModelSettings(rtol=1e-11, atol=1e-13, output_step=0.05 * math.sqrt(1 / G), contact_tilt=0.0))
    tau = ds.tau.values
    want = ref.sol(tau)
    # independent integrations at rtol 1e-11 over a mildly chaotic 15 tau: 1e-6
    for i, name in enumerate(["phi", "theta", "psi"]):
        np.testing.assert_allclose(ds[name].values, want[i], atol=1e-6)


@pytest.mark.parametrize("contact_tilt", [0.0, math.degrees(1e-5)])
def test_decaying_planar_rocking_settles_and_never_crosses_zero(contact_tilt):
    """Regression: impacts piling up must end at rest, not slip through theta = 0."""
    theta0, _, _ = PAPER_CASES["IC1"]
    init = InitialState.from_dimensionless(PAPER_COLUMN.R, 0.0, theta0, 0.0, 0.0, 0.0, 0.0)
    duration = 60 * math.sqrt(PAPER_COLUMN.R / G)
    settings = ModelSettings(rtol=1e-12, atol=1e-14, output_step=duration / 3000, contact_tilt=contact_tilt)
    ds = simulate_free(PAPER_COLUMN, init, duration, settings)  # Housner restitution
    assert np.nanmin(ds.theta.values) >= 0.0
    assert ds.phase.values[-1] == 0 and ds.theta.values[-1] == 0.0
