"""Contact transitions: exact uplift time, the landing impact map."""

import math

import numpy as np
import pytest

from pipeline.dynamics.rigid import frustum as fk
from pipeline.dynamics.rigid import contact
from pipeline.structures.column import Column

PAPER = Column(0.5, 0.4, 4.0)


def _demand_at(record, dt, zc, t):
    ax, ay, az = fk.ground_acceleration(t, record, dt)
    return contact.uplift_demand(ax, ay, az, zc)


def test_first_uplift_is_the_exact_crossing_of_the_threshold():
    c = PAPER.kernel_constants()
    zc = c[fk.C_ZC]
    rng = np.random.default_rng(1)
    dt = 0.05
    record = rng.normal(0, 0.12, size=(400, 3))
    record[:, 2] *= 0.5
    t_up = contact.first_uplift(record, dt, zc, 0.0)
    assert math.isfinite(t_up)
    # the demand reaches 1 at t_up (linear interpolation is exact there) ...
    assert _demand_at(record, dt, zc, t_up) == pytest.approx(1.0, abs=1e-12)
    # ... and is below 1 at every earlier sample and on a fine grid before it
    fine = np.linspace(0, t_up, 5000, endpoint=False)
    assert max(_demand_at(record, dt, zc, t) for t in fine) < 1.0
    # searching again from later finds a later uplift, never an earlier one
    assert contact.first_uplift(record, dt, zc, t_up + 1.0) >= t_up + 1.0


def test_no_uplift_below_threshold():
    zc = PAPER.kernel_constants()[fk.C_ZC]
    record = np.zeros((100, 3))
    record[:, 0] = 0.999 / zc  # just below the uplift acceleration
    assert contact.first_uplift(record, 0.1, zc, 0.0) == math.inf


def test_uplift_azimuth_leans_against_the_acceleration():
    for ax, ay in [(1.0, 0.0), (0.0, 1.0), (-0.3, 0.4)]:
        phi = contact.uplift_azimuth(ax, ay)
        s, co = math.sin(phi), math.cos(phi)
        a_xi = ax * co + ay * s
        a_eta = -ax * s + ay * co
        assert a_xi == pytest.approx(0.0, abs=1e-15)
        assert a_eta == pytest.approx(math.hypot(ax, ay))  # drives theta'' > 0


@pytest.mark.parametrize("slenderness", [3.0, 8.0, 20.0])
def test_planar_impact_restitution_is_one_minus_two_over_iy(slenderness):
    col = Column(1.0, 0.8, slenderness)
    c = col.kernel_constants()
    theta_c = 1e-6
    y = np.zeros(fk.N_STATE)
    y[fk.THETA], y[fk.DTHETA] = theta_c, -0.3
    out = np.empty_like(y)
    dke = contact.landing_impact(y, theta_c, c, out)
    e = 1 - 2 / c[fk.C_IY]
    assert out[fk.DTHETA] == pytest.approx(-e * y[fk.DTHETA], rel=1e-13)
    assert out[fk.DPHI] == 0.0 and out[fk.OMEGA] == 0.0  # planar stays planar
    assert out[fk.PHI] == pytest.approx(math.pi) and out[fk.YP] == 2.0 and out[fk.XP] == 0.0
    assert dke == pytest.approx(0.5 * c[fk.C_IY] * 0.09 * (e**2 - 1), rel=1e-12)


def _skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def test_general_impact_conserves_angular_momentum_about_the_new_pivot():
    """Independent check with vectors in the body frame (xi, eta, zeta)."""
    col = Column(0.5, 0.4, 4.0)
    c = col.kernel_constants()
    A, C, zc = c[fk.C_A], c[fk.C_IZ] - 1, c[fk.C_ZC]
    I_C = np.diag([A, A, C])
    r_PC, r_QC = np.array([0, 1.0, zc]), np.array([0, -1.0, zc])  # Q: the new pivot
    theta_c = 1e-5
    rng = np.random.default_rng(5)
    for _ in range(20):
        y = np.zeros(fk.N_STATE)
        y[fk.PHI] = rng.uniform(-3, 3)
        y[fk.THETA] = theta_c
        y[fk.DTHETA] = -abs(rng.normal(0, 0.3))
        y[fk.DPHI] = rng.normal(0, 0.3) / theta_c  # precession ~ 1/theta near landing
        y[fk.OMEGA] = rng.normal(0, 0.3)
        w = np.array([y[fk.DTHETA], y[fk.DPHI] * math.sin(theta_c), y[fk.OMEGA]])
        H_before = I_C @ w + np.cross(r_QC, np.cross(w, r_PC))
        out = np.empty_like(y)
        dke = contact.landing_impact(y, theta_c, c, out)
        # back to the old body axes: xi' = -xi, eta' = -eta
        w_new = np.array([-out[fk.DTHETA], -out[fk.DPHI] * math.sin(theta_c), out[fk.OMEGA]])
        I_Q = I_C + (r_QC @ r_QC) * np.eye(3) - np.outer(r_QC, r_QC)
        np.testing.assert_allclose(I_Q @ w_new, H_before, rtol=1e-11, atol=1e-12)
        # the energy change it reports is what the energy function sees
        e_before = fk.energy(y[fk.THETA], y[fk.DPHI], y[fk.DTHETA], y[fk.OMEGA], c)
        e_after = fk.energy(out[fk.THETA], out[fk.DPHI], out[fk.DTHETA], out[fk.OMEGA], c)
        assert dke == pytest.approx(e_after - e_before, rel=1e-11, abs=1e-13)
        assert dke <= 1e-15  # an impact never creates energy
