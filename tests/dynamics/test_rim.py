"""The rim-slip and flight equations of :mod:`pipeline.dynamics.rigid.rim` against invariants.

Each test checks a property the equations must have whatever their form, computed here from
first principles and not from the module: the power balance of the contact force, the
angular momentum of torque-free flight, the kinematics of the material point at P by finite
differences of a prescribed motion, and the symmetry of the impulse response. Random states
are drawn away from theta = 0 (where the Euler angles are singular) on a solid cylinder of
radius 1 and height 8 (units of R), whose inertia is known in closed form.
"""

import math

import numpy as np
import pytest

from pipeline.dynamics.rigid import frustum as fk
from pipeline.dynamics.rigid import rim

# Solid cylinder, radius 1, height 8 [R], unit mass: central axial 1/2, transverse 1/4 + H^2/12.
HEIGHT = 8.0
ZC = HEIGHT / 2.0
CENTRAL_TRANSVERSE = 0.25 + HEIGHT ** 2 / 12.0
CENTRAL_AXIAL = 0.5
CONSTANTS = fk.column_constants(CENTRAL_TRANSVERSE + 1.0 + ZC ** 2, CENTRAL_AXIAL + 1.0, ZC)

# Every quantity below is a sum of O(1-10) terms of double precision: 1e-11 of the largest
# term leaves three orders of magnitude above rounding and none for a wrong coefficient.
TOL = 1e-11


def _states(n, seed):
    """n random states (theta, phi', theta', omega_zeta, v_xi, v_n) away from theta = 0."""
    rng = np.random.default_rng(seed)
    theta = rng.uniform(0.05, 1.4, n)
    rates = rng.normal(0.0, 1.0, (n, 3))
    vel = rng.normal(0.0, 1.0, (n, 2))
    return [(theta[i], *rates[i], *vel[i]) for i in range(n)]


def _slip_velocity(theta, dphi, dtheta, omega, v_xi, v_n, v_z):
    """Velocity of the body's material point at P in (xi, n, Z), from first principles.

    Body frame (xi, eta, zeta): zeta the axis, eta the tilted transverse axis towards the
    centre of the base from P; omega = (theta', phi' sin theta, omega_zeta); r_CP = (0, -1, -zc).
    """
    s, co = math.sin(theta), math.cos(theta)
    w = np.array([dtheta, dphi * s, omega])
    r = np.array([0.0, -1.0, -ZC])
    u = np.cross(w, r)
    # eta = n cos + Z sin, zeta = -n sin + Z cos
    return np.array([v_xi + u[0], v_n + u[1] * co - u[2] * s, v_z + u[1] * s + u[2] * co])


def _energy_rate(theta, dphi, dtheta, omega, v, a, rates):
    """d/dt of :func:`rim.energy` written out: v . a + A (theta' theta'' + w_eta w_eta') + C w w' + v_z."""
    ddphi, ddtheta, domega, dw_eta = rates
    A, C = CENTRAL_TRANSVERSE, CENTRAL_AXIAL
    w_eta = dphi * math.sin(theta)
    return float(np.dot(v, a)) + A * (dtheta * ddtheta + w_eta * dw_eta) + C * omega * domega + v[2]


@pytest.mark.parametrize("mu", [0.0, 0.3, 0.8])
def test_rim_slip_loses_exactly_the_friction_power(mu):
    """While P slides, the energy changes at the power of Coulomb's force, -mu N |v_s| (0 frictionless).

    The normal force comes from the height constraint (:func:`rim.slip_normal_force`), so the
    vertical velocity of the centre follows the rim's lever and the material point at P does
    not leave the plane; its horizontal velocity is the slip.
    """
    for theta, dphi, dtheta, omega, v_xi, v_n in _states(40, seed=1):
        v_z = dtheta * rim.reach(theta, ZC)  # d lever / dt
        v_s = _slip_velocity(theta, dphi, dtheta, omega, v_xi, v_n, v_z)
        assert abs(v_s[2]) < TOL
        speed = math.hypot(v_s[0], v_s[1])
        f_xi, f_n = -mu * v_s[0] / speed, -mu * v_s[1] / speed
        normal, den = rim.slip_normal_force(theta, dphi, dtheta, omega, f_xi, f_n, 0.0, CONSTANTS)
        assert den > 0.0
        rates = rim.rotation_accelerations(theta, dphi, dtheta, omega, f_xi, f_n, normal, CONSTANTS)
        a = np.array([normal * f_xi, normal * f_n, normal - 1.0])  # per m g, ground at rest
        power = _energy_rate(theta, dphi, dtheta, omega, np.array([v_xi, v_n, v_z]), a, rates)
        assert power == pytest.approx(-mu * normal * speed, abs=TOL * (1.0 + abs(normal) * 10))
        # and the normal force holds the centre on the lever: Z_C'' = N - 1
        ddtheta = rates[1]
        lever_rate2 = ddtheta * rim.reach(theta, ZC) - dtheta ** 2 * rim.lever(theta, ZC)
        assert normal - 1.0 == pytest.approx(lever_rate2, abs=TOL * (1.0 + abs(normal) * 10))


def test_a_couple_does_its_own_work():
    """A couple m (body components) adds exactly m . omega to the energy rate, nothing else."""
    rng = np.random.default_rng(2)
    for theta, dphi, dtheta, omega, v_xi, v_n in _states(20, seed=3):
        m = rng.normal(0.0, 0.5, 3)
        base = rim.rotation_accelerations(theta, dphi, dtheta, omega, 0.0, 0.0, 0.0, CONSTANTS)
        with_couple = rim.rotation_accelerations(theta, dphi, dtheta, omega, 0.0, 0.0, 0.0, CONSTANTS, *m)
        v = np.array([v_xi, v_n, 0.0])
        a = np.array([0.0, 0.0, -1.0])
        gained = (_energy_rate(theta, dphi, dtheta, omega, v, a, with_couple)
                  - _energy_rate(theta, dphi, dtheta, omega, v, a, base))
        w = np.array([dtheta, dphi * math.sin(theta), omega])
        assert gained == pytest.approx(float(np.dot(m, w)), abs=TOL)


def test_flight_keeps_the_rotational_energy_and_the_angular_momentum():
    """No contact (N = 0): torque-free, so |L|^2 and the rotational energy do not change."""
    A, C = CENTRAL_TRANSVERSE, CENTRAL_AXIAL
    for theta, dphi, dtheta, omega, _, _ in _states(40, seed=4):
        ddphi, ddtheta, domega, dw_eta = rim.rotation_accelerations(theta, dphi, dtheta, omega, 0.3, -0.2, 0.0,
                                                                    CONSTANTS)
        w_eta = dphi * math.sin(theta)
        # components in the turning frame: the rate of |L|^2 is that of the components' squares
        d_l2 = 2.0 * (A * A * dtheta * ddtheta + A * A * w_eta * dw_eta + C * C * omega * domega)
        d_rot = A * (dtheta * ddtheta + w_eta * dw_eta) + C * omega * domega
        assert d_l2 == pytest.approx(0.0, abs=TOL * 100)
        assert d_rot == pytest.approx(0.0, abs=TOL * 10)
        # phi'' from the rate of the eta component: w_eta' = phi'' sin + phi' theta' cos
        assert dw_eta == pytest.approx(ddphi * math.sin(theta) + dphi * dtheta * math.cos(theta), abs=TOL * 10)


def _world_slip_velocity(t, motion):
    """The velocity of the material point at the current contact point P, world axes, at time t."""
    phi, theta, spin, vc = motion
    p, dp = phi(t)
    th, dth = theta(t)
    w3 = spin(t)[0]
    v = _slip_velocity(th, dp, dth, w3, 0.0, 0.0, 0.0)
    xi = np.array([math.cos(p), math.sin(p), 0.0])
    n = np.array([-math.sin(p), math.cos(p), 0.0])
    return v[0] * xi + v[1] * n + np.array([0.0, 0.0, v[2]]) + vc(t)[0]


def test_material_point_acceleration_is_the_rate_of_the_slip_velocity():
    """Against a central difference of v_P along a prescribed (not dynamic) smooth motion.

    The function takes the rates of the motion as inputs, so any smooth phi(t), theta(t),
    omega_zeta(t) and centre velocity serve; the contact point moves along the rim with the
    turning frame, which the difference sees and the formula must too.
    """
    phi = lambda t: (0.3 + 0.7 * t + 0.4 * t * t, 0.7 + 0.8 * t)  # noqa: E731 (value, rate)
    theta = lambda t: (0.4 + 0.5 * t - 0.3 * t * t, 0.5 - 0.6 * t)  # noqa: E731
    spin = lambda t: (1.1 - 0.9 * t + 0.5 * t ** 3, -0.9 + 1.5 * t * t)  # noqa: E731
    vc = lambda t: (np.array([0.2 * t, -0.1 + 0.3 * t * t, 0.05 * t ** 3]),  # noqa: E731
                    np.array([0.2, 0.6 * t, 0.15 * t * t]))
    motion = (phi, theta, spin, vc)
    h = 1e-5
    for t in (0.0, 0.37, 0.81):
        fd = (_world_slip_velocity(t + h, motion) - _world_slip_velocity(t - h, motion)) / (2.0 * h)
        p, dp = phi(t)
        th, dth = theta(t)
        w3, dw3 = spin(t)
        ddphi, ddtheta = 0.8, -0.6
        dw_eta = ddphi * math.sin(th) + dp * dth * math.cos(th)
        acc = vc(t)[1]
        xi = np.array([math.cos(p), math.sin(p), 0.0])
        n = np.array([-math.sin(p), math.cos(p), 0.0])
        a_xi, a_n, a_z = float(acc @ xi), float(acc @ n), acc[2]
        r = rim.material_point_acceleration(th, dp, dth, w3, ddtheta, dw_eta, dw3, a_xi, a_n, a_z, ZC)
        formula = r[0] * xi + r[1] * n + np.array([0.0, 0.0, r[2]])
        # central difference: error h^2 |v'''| / 6 ~ 1e-10, rounding eps |v| / h ~ 1e-11
        np.testing.assert_allclose(formula, fd, atol=1e-8)


def test_an_impulse_changes_the_slip_velocity_as_the_response_says_and_the_response_is_symmetric():
    """apply_impulse and impulse_response agree, and the map J -> dv_P is symmetric positive definite.

    dv_P = (1/m + r x I^-1 x r) J is the inverse of the effective mass at P: symmetric and
    positive definite for any body (Kelvin's theorem on impulsive motion).
    """
    for theta, dphi, dtheta, omega, v_xi, v_n in _states(20, seed=5):
        K = np.empty((3, 3))
        for j in range(3):
            J = np.zeros(3)
            J[j] = 1.0
            K[:, j] = rim.impulse_response(theta, *J, CONSTANTS)
            new_dphi, new_dtheta, new_omega = rim.apply_impulse(theta, dphi, dtheta, omega, *J, CONSTANTS)
            before = _slip_velocity(theta, dphi, dtheta, omega, v_xi, v_n, 0.0)
            after = _slip_velocity(theta, new_dphi, new_dtheta, new_omega, v_xi + J[0], v_n + J[1], J[2])
            np.testing.assert_allclose(after - before, K[:, j], atol=TOL)
        np.testing.assert_allclose(K, K.T, atol=TOL)
        assert np.linalg.eigvalsh(0.5 * (K + K.T)).min() > 0.0


def test_rolling_velocity_leaves_the_material_point_at_rest():
    """cm_velocity_rolling is the velocity for which v_P = 0, and its vertical part is d lever / dt."""
    for theta, dphi, dtheta, omega, _, _ in _states(20, seed=6):
        v = rim.cm_velocity_rolling(theta, dphi, dtheta, omega, ZC)
        np.testing.assert_allclose(_slip_velocity(theta, dphi, dtheta, omega, *v), 0.0, atol=TOL)
        assert v[2] == pytest.approx(dtheta * rim.reach(theta, ZC), abs=TOL)
