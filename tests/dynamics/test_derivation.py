"""The compiled kernel evaluates exactly what the sympy derivation gives."""

import numpy as np
import pytest
import sympy as sp

from pipeline.dynamics import derivation as d
from pipeline.dynamics.rigid import frustum as fk
from pipeline.structures.column import Column


@pytest.fixture(scope="module")
def symbolic():
    acc = d.accelerations()
    T, V, P = d.energy()
    _, _, F = d.equations_of_motion()
    args = (d.theta, d.phi, d.dphi, d.dtheta, d.dpsi, d.ax, d.ay, d.az, d.Iy, d.Iz, d.zc)
    F_args = args + (d.ddphi, d.ddtheta, d.ddpsi)
    return {
        "acc": sp.lambdify(args, acc, "math"),
        "E": sp.lambdify(args, T + V, "math"),
        "P": sp.lambdify(args, P, "math"),
        "F": sp.lambdify(F_args, list(F), "math"),
    }


def _random_states(n, seed=0):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        col = Column(R=rng.uniform(0.2, 2.0), r=rng.uniform(0.1, 2.0), h=rng.uniform(0.05, 12.0))
        c = col.kernel_constants()
        state = dict(
            theta=rng.uniform(1e-3, 1.5), phi=rng.uniform(-np.pi, np.pi),
            dphi=rng.normal(0, 2), dtheta=rng.normal(0, 1), dpsi=rng.normal(0, 2),
            ax=rng.normal(0, 0.5), ay=rng.normal(0, 0.5), az=rng.normal(0, 0.3),
        )
        yield c, state


def _rotate(phi, ax, ay):
    return ax * np.cos(phi) + ay * np.sin(phi), -ax * np.sin(phi) + ay * np.cos(phi)


def test_kernel_matches_symbolic_accelerations_forces_energy_power(symbolic):
    # Both sides are double-precision evaluations of the same closed forms in
    # different algebraic arrangements: agreement to ~1e-12 relative (a few
    # hundred ulps, the terms reach ~1/theta^2 ~ 1e6 at theta = 1e-3).
    for c, s in _random_states(200):
        args = (s["theta"], s["phi"], s["dphi"], s["dtheta"], s["dpsi"], s["ax"], s["ay"], s["az"],
                c[fk.C_IY], c[fk.C_IZ], c[fk.C_ZC])
        a_xi, a_eta = _rotate(s["phi"], s["ax"], s["ay"])
        # the kernel's speeds are (phi', theta', omega_zeta), omega_zeta = phi' cos + psi'
        omega = s["dphi"] * np.cos(s["theta"]) + s["dpsi"]
        got = fk.accelerations(s["theta"], s["dphi"], s["dtheta"], omega, a_xi, a_eta, s["az"], c)
        ddphi, ddtheta, ddpsi = symbolic["acc"](*args)
        domega = ddphi * np.cos(s["theta"]) - s["dphi"] * np.sin(s["theta"]) * s["dtheta"] + ddpsi
        want = (ddphi, ddtheta, domega)
        # phi'' is a difference of terms of size |rates|/sin(theta) (up to 1e4
        # here): both sides agree to ~1e-13 of that size, not of the result.
        terms = (abs(s["dphi"] * s["dtheta"]) + abs(omega * s["dtheta"]) + abs(a_xi)) / np.sin(s["theta"])
        scale = max(1.0, terms, *map(abs, want))
        np.testing.assert_allclose(got, want, rtol=1e-10, atol=1e-13 * scale)
        e_got = fk.energy(s["theta"], s["dphi"], s["dtheta"], omega, c)
        assert e_got == pytest.approx(symbolic["E"](*args), rel=1e-12, abs=1e-12)
        p_got = fk.ground_power(s["theta"], s["dphi"], s["dtheta"], omega, a_xi, a_eta, s["az"], c[fk.C_ZC])
        assert p_got == pytest.approx(symbolic["P"](*args), rel=1e-11, abs=1e-12)
        F_want = symbolic["F"](*args, ddphi, ddtheta, ddpsi)  # plane frame (X, Y, Z)
        f_xi, f_n, f_z = fk.contact_force(s["theta"], s["dphi"], s["dtheta"], omega, *got,
                                          a_xi, a_eta, s["az"], c[fk.C_ZC])
        fx_w, fn_w = _rotate(s["phi"], F_want[0], F_want[1])
        # the symbolic force uses psi'' (size ~ terms), the kernel omega_zeta'
        f_scale = max(1.0, terms, *map(abs, F_want))
        np.testing.assert_allclose([f_xi, f_n, f_z], [fx_w, fn_w, F_want[2]], rtol=1e-10, atol=1e-13 * f_scale)


def test_energy_rate_equals_ground_power_symbolically():
    """d(T+V)/dtau - P_ground vanishes identically on the derived equations."""
    T, V, P = d.energy()
    E = T + V
    acc = d.accelerations()
    dE = (sp.diff(E, d.theta) * d.dtheta + sp.diff(E, d.phi) * d.dphi + sp.diff(E, d.dphi) * acc[0]
          + sp.diff(E, d.dtheta) * acc[1] + sp.diff(E, d.dpsi) * acc[2])
    residual = sp.lambdify((d.theta, d.phi, d.dphi, d.dtheta, d.dpsi, d.ax, d.ay, d.az, d.Iy, d.Iz, d.zc),
                           dE - P, "mpmath")
    import mpmath
    mpmath.mp.dps = 40
    rng = np.random.default_rng(3)
    for _ in range(5):
        vals = [mpmath.mpf(float(v)) for v in rng.uniform(0.1, 1.2, 8)] + [mpmath.mpf(20.2), mpmath.mpf(1.41), mpmath.mpf(3.7)]
        assert abs(residual(*vals)) < mpmath.mpf(10) ** -30


def test_paper_energy_eq13_is_the_derived_energy():
    T, V, _ = d.energy()
    th, hk1 = d.theta, 2 * d.zc
    e13 = (sp.Rational(1, 2) * d.Iy * d.dtheta**2
           + sp.Rational(1, 2) * (d.Iz * sp.cos(th) ** 2 + sp.sin(th) * ((d.Iy - 1) * sp.sin(th) - hk1 * sp.cos(th))) * d.dphi**2
           + sp.Rational(1, 2) * d.Iz * d.dpsi**2 + (d.Iz * sp.cos(th) - hk1 / 2 * sp.sin(th)) * d.dphi * d.dpsi
           + sp.Rational(1, 2) * (2 * sp.sin(th) + hk1 * sp.cos(th)))
    assert sp.simplify(sp.expand_trig(e13 - T - V)) == 0


def test_printed_g_coefficients_misprints_are_exactly_g23_and_g34():
    """docs/misprints.md: every printed g_ij of Eq. 12 but g23 and g34 equals the derived one."""
    der = d.derived_coefficients()
    pap = d.paper_coefficients(2 * d.zc)
    vals = {d.Iy: 20.2, d.Iz: 1.413, d.zc: 3.705, d.theta: 0.37, d.phi: 0.81, d.ax: 0.3, d.ay: -0.7}
    wrong = {k for k in der if abs(float((der[k] - pap[k]).subs(vals))) > 1e-12}
    assert wrong == {"g23", "g34"}
    # the corrections of docs/misprints.md restore them
    th, hk1 = d.theta, 2 * d.zc
    D = 4 * (d.Iy - 1) * d.Iz - hk1**2
    a_xi = d.ax * sp.cos(d.phi) + d.ay * sp.sin(d.phi)
    g23 = -(2 * d.Iz * sp.sin(th) + hk1 * sp.cos(th)) / (2 * d.Iy)
    g34 = (4 * (d.Iy - 1) + 2 * hk1 * (d.Iz - 1) * sp.cot(th) - hk1**2) / D * a_xi
    assert abs(float((der["g23"] - g23).subs(vals))) < 1e-12
    assert abs(float((der["g34"] - g34).subs(vals))) < 1e-12


def test_damping_couple_accelerations_match_symbolic():
    (dp, dt_, ds), nu = d.couple_accelerations()
    f = sp.lambdify((d.theta, d.dphi, d.dtheta, d.dpsi, nu, d.Iy, d.Iz, d.zc), (dp, dt_, ds), "math")
    rng = np.random.default_rng(11)
    for c, s in _random_states(50, seed=4):
        nu_val = rng.uniform(0.01, 0.5)
        omega = s["dphi"] * np.cos(s["theta"]) + s["dpsi"]
        got = fk.damping_accelerations(s["theta"], s["dphi"], s["dtheta"], omega, nu_val, c)
        ddphi, ddtheta, ddpsi = f(s["theta"], s["dphi"], s["dtheta"], s["dpsi"], nu_val, c[fk.C_IY], c[fk.C_IZ], c[fk.C_ZC])
        domega = ddphi * np.cos(s["theta"]) + ddpsi  # the rates themselves are unchanged by M
        terms = nu_val * (abs(s["dphi"]) + abs(omega) / np.sin(s["theta"]) + abs(s["dtheta"]))
        np.testing.assert_allclose(got[:3], (ddphi, ddtheta, domega), rtol=1e-10, atol=1e-13 * max(1.0, terms))
        # dissipated power = -M . omega = nu |omega|^2
        w2 = s["dtheta"] ** 2 + (s["dphi"] * np.sin(s["theta"])) ** 2 + omega**2
        assert got[3] == pytest.approx(nu_val * w2, rel=1e-13)


def test_any_couple_accelerations_match_symbolic():
    """fk.couple_accelerations (the patch's couples) against the symbolic inverse mass matrix."""
    (dp, dt_, ds), (mx, me, mz) = d.general_couple_accelerations()
    f = sp.lambdify((d.theta, mx, me, mz, d.Iy, d.Iz, d.zc), (dp, dt_, ds), "math")
    rng = np.random.default_rng(12)
    for c, s in _random_states(50, seed=5):
        m = rng.normal(size=3)
        got = fk.couple_accelerations(s["theta"], *m, c)
        ddphi, ddtheta, ddpsi = f(s["theta"], *m, c[fk.C_IY], c[fk.C_IZ], c[fk.C_ZC])
        domega = ddphi * np.cos(s["theta"]) + ddpsi  # the rates are unchanged by a couple
        np.testing.assert_allclose(got, (ddphi, ddtheta, domega), rtol=1e-10,
                                   atol=1e-12 * (1 + abs(ddphi)))
