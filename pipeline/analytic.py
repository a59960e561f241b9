"""The paper's closed-form results, derived again and corrected where misprinted.

Every function here is a pure function of the column's dimensionless constants
and of dimensionless states (the paper's Eq. 9: rates per tau = t sqrt(g/R),
lengths per R). The column may be given as a :class:`pipeline.structures.column.Column`
or as any sequence whose first three entries are ``(Iy, Iz, zc)``:

* ``Iy`` = I_y^P / (m R^2), the paper's transverse inertia "at P";
* ``Iz`` = I_z^P / (m R^2), the axial one;
* ``zc`` = z_cm / R = h_hat k1 / 2 (so the paper's ``h_hat k1`` is ``2 zc``);

which is also the layout of :meth:`Column.kernel_constants`.

Each formula was checked against our own derivation
(:mod:`pipeline.dynamics.derivation`) or against numerical integration of the
full equations (``tests/test_analytic.py``); the printed forms that fail those
checks are listed with their corrections in ``docs/misprints.md``. Names and
equation numbers follow the paper:

* Eq. 14: :func:`rocking_acceleration`;
* Eqs. 16-18: :func:`coupling_matrix`, :func:`eigenvalue_product`,
  :func:`perturbation_eigenvalues`;
* Section 4, Fig. 9: :func:`wobbling_p`, :func:`wobbling_s`, :func:`ps_product`;
* Eqs. 23-25: :func:`wobbling_constants`, :func:`wobbling_rates`,
  :func:`rate_sum`;
* Eqs. 26-27: :func:`wobbling_rates_approx`, :func:`spin_approx`;
* Eqs. 29-32: :func:`impact_residual`, :func:`impact_ratio`,
  :func:`impact_ratio_series`, :func:`impact_spin`, :func:`impact_velocity`;
* Section 4.2, theta_min from the energy with the exact rates:
  :func:`rates_along_theta`, :func:`turning_inclination`, :func:`total_energy` (Eq. 13);
* Appendix B: :func:`appell_solution` (Gauss hypergeometric functions through
  ``mpmath.hyp2f1``; ``scipy.special.hyp2f1`` takes real parameters only and
  here they are complex), :func:`impact_ratio_exact`,
  :func:`impact_velocity_exact`.
"""

import math
from dataclasses import dataclass

import mpmath
import numpy as np

from pipeline.structures.column import axial_inertia_hat, k1_coefficient, transverse_inertia_hat


def _constants(column):
    """(Iy, Iz, hk1) from a Column or a sequence starting with (Iy, Iz, zc)."""
    if hasattr(column, "kernel_constants"):
        c = column.kernel_constants()
    else:
        c = column
    Iy, Iz, zc = (float(c[i]) for i in range(3))
    return Iy, Iz, 2.0 * zc


def _denominator(Iy, Iz, hk1):
    """The paper's recurring ``4 (I_y - 1) I_z - h^2 k1^2`` (> 0 for every frustum) [1]."""
    return 4.0 * (Iy - 1.0) * Iz - hk1 * hk1


# Section 3: planar rocking and its stability ---------------------------------------------


def rocking_acceleration(theta, column):
    """Angular acceleration of planar rocking on a rim point, the paper's Eq. 14.

    Parameters
    ----------
    theta : float or array_like
        Inclination [rad], 0 < theta < pi/2, the column leaning towards its pivot.
    column : Column or sequence
        The column (see the module docstring).

    Returns
    -------
    float or numpy.ndarray
        theta'' [1/tau^2] = (h k1 sin(theta) - 2 cos(theta)) / (2 I_y): negative
        (back towards full contact) below the critical tilt.
    """
    Iy, _, hk1 = _constants(column)
    theta = np.asarray(theta, dtype=float)
    return (hk1 * np.sin(theta) - 2.0 * np.cos(theta)) / (2.0 * Iy)


def coupling_matrix(theta, column):
    """The matrix [[g11, g13], [g31, g33]] of the paper's Eqs. 12 and 17 [1].

    In free motion phi'' = (g11 phi' + g13 psi') theta' and psi'' = (g31 phi' +
    g33 psi') theta' exactly (Eq. 12): the out-of-plane rates obey a linear
    system in theta, ``d(phi', psi')/dtheta = G(theta) (phi', psi')``. The
    printed g11, g13, g31, g33 agree with our derivation.

    Parameters
    ----------
    theta : float
        Inclination [rad], 0 < theta < pi.
    column : Column or sequence

    Returns
    -------
    numpy.ndarray, shape (2, 2)
    """
    Iy, Iz, hk1 = _constants(column)
    D = _denominator(Iy, Iz, hk1)
    cot = np.cos(theta) / np.sin(theta)
    csc = 1.0 / np.sin(theta)
    g11 = 2.0 * (Iz - 1.0) * (2.0 * cot * Iz - hk1) / D - 2.0 * cot
    g13 = 4.0 * csc * (Iz - 1.0) * Iz / D
    g31 = (
        (4.0 * hk1 * np.cos(theta) - 4.0 * (Iy - Iz - 1.0) * np.sin(theta)) * (Iz - 1.0)
        + 2.0 * (4.0 * Iy * Iz - 2.0 * Iz**2 - 2.0 * Iz - hk1**2) * csc
    ) / D
    g33 = -2.0 * (Iz - 1.0) * (2.0 * Iz * cot - hk1) / D
    return np.array([[g11, g13], [g31, g33]])


def eigenvalue_product(theta, dtheta, column):
    """Product rho1 rho2 of the eigenvalues of the paper's Eq. 17, Eq. 18 (corrected).

    ``rho1 rho2 = -4 (I_z - 1)(h k1 cot(theta) + I_z + 1) theta'^2 /
    (4 (I_y - 1) I_z - h^2 k1^2)``, negative for every frustum with
    0 < theta < pi/2: the eigenvalues are real with opposite signs and rocking
    is unstable. The first printed form of Eq. 18 lacks the minus sign; the
    second printed form (in k1, k2, k3) is right.

    Parameters
    ----------
    theta : float or array_like
        Inclination of the planar rocking motion [rad].
    dtheta : float or array_like
        Its rate theta' [1/tau].
    column : Column or sequence

    Returns
    -------
    float or numpy.ndarray
        rho1 rho2 [1/tau^2].
    """
    Iy, Iz, hk1 = _constants(column)
    theta = np.asarray(theta, dtype=float)
    cot = np.cos(theta) / np.sin(theta)
    return -4.0 * (Iz - 1.0) * (hk1 * cot + Iz + 1.0) / _denominator(Iy, Iz, hk1) * np.asarray(dtheta) ** 2


def perturbation_eigenvalues(theta, dtheta, column):
    """Eigenvalues (rho_plus, rho_minus) of theta' [[g11, g13], [g31, g33]] (Eqs. 17-18).

    Their trace is ``-2 cot(theta) theta'`` (g11 + g33 = -2 cot(theta)) and
    their product is :func:`eigenvalue_product`. Small out-of-plane rates
    (phi', psi') of planar rocking grow locally like exp(int rho_plus dtau).

    Parameters
    ----------
    theta, dtheta : float or array_like
        Inclination [rad] and its rate [1/tau] along the planar motion.
    column : Column or sequence

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        rho_plus >= 0 >= rho_minus [1/tau].
    """
    theta = np.asarray(theta, dtype=float)
    dtheta = np.asarray(dtheta, dtype=float)
    trace = -2.0 * np.cos(theta) / np.sin(theta) * dtheta
    prod = eigenvalue_product(theta, dtheta, column)
    root = np.sqrt(trace**2 - 4.0 * prod)  # real: prod <= 0
    return 0.5 * (trace + root), 0.5 * (trace - root)


# Section 4: free wobbling --------------------------------------------------------------


def wobbling_p(column):
    """The paper's p = 2 h k1 / I_z (Section 4, Eq. 23) [1]."""
    Iy, Iz, hk1 = _constants(column)
    return 2.0 * hk1 / Iz


def wobbling_s(column):
    """The paper's s = (4 (I_y - 1) I_z - h^2 k1^2) / (2 h k1 (I_z - 1)) (Eq. 23) [1].

    1/s is the growth rate in theta of phi' + psi' (Eq. 25).
    """
    Iy, Iz, hk1 = _constants(column)
    return _denominator(Iy, Iz, hk1) / (2.0 * hk1 * (Iz - 1.0))


def ps_product(slenderness, beta):
    """p s as a function of slenderness h/R and conicity beta = r/R (Figure 9) [1].

    ``p s = (4 (I_y - 1) I_z - h^2 k1^2) / (I_z (I_z - 1))``; h k1 cancels.
    In the small-angle wobbling solution ``psi'/phi' -> p s / 2 - 1`` on the
    solution that reaches theta = 0 (Eq. 30).

    Parameters
    ----------
    slenderness : float or array_like
        h/R, the paper's h_hat [1].
    beta : float or array_like
        r/R [1].

    Returns
    -------
    float or numpy.ndarray
    """
    h = np.asarray(slenderness, dtype=float)
    beta = np.asarray(beta, dtype=float)
    Iy, Iz = transverse_inertia_hat(h, beta), axial_inertia_hat(beta)
    return _denominator(Iy, Iz, h * k1_coefficient(beta)) / (Iz * (Iz - 1.0))


def wobbling_constants(theta0, dphi0, dpsi0, column):
    """Integration constants c1, c2 of the wobbling velocities (Eq. 24) [1/tau].

    ``c1 = -exp(-theta0/s) (phi'0 + psi'0)`` and
    ``c2 = exp(theta0/s) [(2 theta0 - s)/p (phi'0 + psi'0) - phi'0 theta0^2]``,
    as printed: they return (phi'0, psi'0) at theta0 from the *corrected*
    Eq. 23 (:func:`wobbling_rates`).

    Parameters
    ----------
    theta0 : float
        Initial inclination [rad].
    dphi0, dpsi0 : float
        Initial rates phi'0, psi'0 [1/tau].
    column : Column or sequence

    Returns
    -------
    (float, float)
    """
    p, s = wobbling_p(column), wobbling_s(column)
    total = dphi0 + dpsi0
    c1 = -np.exp(-theta0 / s) * total
    c2 = np.exp(theta0 / s) * ((2.0 * theta0 - s) / p * total - dphi0 * theta0**2)
    return c1, c2


def wobbling_rates(theta, theta0, dphi0, dpsi0, column):
    """Free-wobbling velocities phi'(theta), psi'(theta), the paper's Eq. 23 (corrected).

    The exact solution of the small-angle equations (Eq. 22, no ground motion):

    ``phi' = -(c1/p) e^(theta/s) [2/theta - s/theta^2] - c2 e^(-theta/s) / theta^2``,
    ``psi' =  (c1/p) e^(theta/s) [-p + 2/theta - s/theta^2] + c2 e^(-theta/s) / theta^2``.

    The paper prints ``1/theta - s/(2 theta^2)`` in both brackets, which
    solves neither Eq. 22 nor, with Eq. 24, the initial conditions.

    Parameters
    ----------
    theta : float or array_like
        Inclination [rad] (the velocities depend on theta alone).
    theta0 : float
        Inclination where phi' = phi'0 and psi' = psi'0 [rad].
    dphi0, dpsi0 : float
        phi'0, psi'0 [1/tau].
    column : Column or sequence

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        phi', psi' [1/tau].
    """
    p, s = wobbling_p(column), wobbling_s(column)
    c1, c2 = wobbling_constants(theta0, dphi0, dpsi0, column)
    t = np.asarray(theta, dtype=float)
    bracket = 2.0 / t - s / t**2
    grow = c1 / p * np.exp(t / s)
    decay = c2 * np.exp(-t / s) / t**2
    return -grow * bracket - decay, grow * (bracket - p) + decay


def rate_sum(theta, theta0, dphi0, dpsi0, column):
    """phi' + psi' = (phi'0 + psi'0) exp((theta - theta0)/s), the paper's Eq. 25 [1/tau]."""
    s = wobbling_s(column)
    return (dphi0 + dpsi0) * np.exp((np.asarray(theta, dtype=float) - theta0) / s)


def wobbling_rates_approx(theta, theta0, dphi0, dpsi0, column):
    """Small-angle approximation of the wobbling velocities, the paper's Eq. 26 (corrected).

    Leading terms of :func:`wobbling_rates` for theta, theta0 -> 0:

    ``phi' ~  2 S/(p s) + B (theta0/theta)^2``,
    ``psi' ~ (p s - 2) S/(p s) - B (theta0/theta)^2``,

    with ``S = phi'0 + psi'0`` and ``B = ((p s - 2) phi'0 - 2 psi'0)/(p s)``.
    The paper prints them with ``p s`` replaced by ``-p s`` in the terms
    ``+-2`` (``-2 S/(p s)``, ``(p s + 2)``), which contradicts its own Eqs.
    23-25 and 30; for slender columns (p s >> 2) the difference is small.

    Parameters
    ----------
    theta : float or array_like
        Inclination [rad].
    theta0 : float
        Initial inclination [rad].
    dphi0, dpsi0 : float
        phi'0, psi'0 [1/tau].
    column : Column or sequence

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        Approximate phi', psi' [1/tau]; exact at theta = theta0.
    """
    ps = wobbling_p(column) * wobbling_s(column)
    total = dphi0 + dpsi0
    singular = ((ps - 2.0) * dphi0 - 2.0 * dpsi0) / ps * (theta0 / np.asarray(theta, dtype=float)) ** 2
    return 2.0 * total / ps + singular, (ps - 2.0) * total / ps - singular


def spin_approx(dphi0, dpsi0):
    """Spin omega_zeta ~ phi'0 + psi'0 for small inclinations, the paper's Eq. 27 [1/tau]."""
    return dphi0 + dpsi0


def impact_residual(theta0, dphi0, dpsi0, column):
    """s c1 - p c2, which vanishes when the column reaches theta = 0 (Eq. 29) [1/tau].

    The energy (Eq. 28) grows like ((s c1 - p c2)/theta)^2 as theta -> 0, so the
    column reaches full contact only where it is zero; with either sign it
    turns at some theta_min > 0.
    """
    p, s = wobbling_p(column), wobbling_s(column)
    c1, c2 = wobbling_constants(theta0, dphi0, dpsi0, column)
    return s * c1 - p * c2


def impact_ratio(theta0, column):
    """(psi'0/phi'0) for impact, the closed form of the paper's Eq. 30 (corrected) [1].

    ``p theta0^2 / ((exp(-2 theta0/s) - 1) s + 2 theta0) - 1``: Eq. 29 with
    Eq. 24 solved for the ratio. The paper prints ``exp(+2 theta0/s)``, which
    contradicts its own series (:func:`impact_ratio_series`).

    Parameters
    ----------
    theta0 : float or array_like
        Initial inclination [rad] (theta'0 does not matter).
    column : Column or sequence

    Returns
    -------
    float or numpy.ndarray
    """
    p, s = wobbling_p(column), wobbling_s(column)
    t0 = np.asarray(theta0, dtype=float)
    # expm1 keeps the difference accurate: the denominator is O(theta0^2)
    return p * t0**2 / (np.expm1(-2.0 * t0 / s) * s + 2.0 * t0) - 1.0


def impact_ratio_series(theta0, column):
    """Small-angle series of the impact ratio, the paper's Eq. 30 [1].

    ``p s / 2 - 1 + p theta0 / 3 + p theta0^2 / (18 s) + O(theta0^3)``.
    """
    p, s = wobbling_p(column), wobbling_s(column)
    t0 = np.asarray(theta0, dtype=float)
    return p * s / 2.0 - 1.0 + p * t0 / 3.0 + p * t0**2 / (18.0 * s)


def impact_spin(dphi0, column):
    """Spin for impact, omega_zeta ~ (p s / 2) phi'0, the paper's Eq. 31 [1/tau]."""
    return 0.5 * wobbling_p(column) * wobbling_s(column) * dphi0


def impact_velocity(theta0, dphi0, dpsi0, dtheta0, column):
    """Inclination rate at impact, the paper's Eq. 32 (corrected) [1/tau].

    When Eq. 29 holds, omega_eta -> 0 and omega_zeta -> -c1 as theta -> 0, so
    the energy (Eq. 13) gives
    ``theta'_imp = -sqrt((2 E0 - I_z c1^2 - h k1) / I_y)``: the potential
    energy at full contact is e/2 = h k1 / 2. The paper prints ``+ h k1``.

    Parameters
    ----------
    theta0 : float
        Initial inclination [rad].
    dphi0, dpsi0, dtheta0 : float
        Initial rates [1/tau]; (dphi0, dpsi0) should satisfy the impact condition.
    column : Column or sequence

    Returns
    -------
    float
        theta' at theta = 0 [1/tau] (negative), NaN if the energy does not reach.
    """
    Iy, Iz, hk1 = _constants(column)
    c1, _ = wobbling_constants(theta0, dphi0, dpsi0, column)
    E0 = total_energy(theta0, dphi0, dtheta0, dpsi0, column)
    arg = (2.0 * E0 - Iz * c1**2 - hk1) / Iy
    return -np.sqrt(arg) if arg >= 0 else np.nan


def rates_along_theta(theta0, dphi0, dpsi0, column, theta_end=1e-8, rtol=1e-11):
    """Exact free-motion rates (phi', psi') as functions of theta, by integrating in theta.

    Eq. 12 without ground motion gives ``d(phi', psi')/dtheta = G(theta) (phi', psi')``
    (:func:`coupling_matrix`), linear and independent of time: the rates are
    single-valued functions of theta whatever theta'. Integrated from theta0
    down to ``theta_end`` with scipy's DOP853.

    Returns
    -------
    scipy.integrate.OdeSolution
        Dense solution: ``sol(theta)`` -> (phi', psi') [1/tau].
    """
    from scipy.integrate import solve_ivp

    def f(t, x):
        return coupling_matrix(t, column) @ x

    sol = solve_ivp(f, (theta0, theta_end), [dphi0, dpsi0], method="DOP853", rtol=rtol, atol=1e-14,
                    dense_output=True)
    if sol.status != 0:
        raise RuntimeError(f"integration in theta failed: {sol.message}")
    return sol.sol


def turning_inclination(theta0, dphi0, dpsi0, column, dtheta0=0.0):
    """theta_min of free motion: the first theta below theta0 where theta' = 0 [rad].

    The paper's "introducing Eqs. 23 into the total energy" (Section 4.2), done
    with the exact rates (:func:`rates_along_theta`) instead of the small-angle
    ones: ``I_y theta'^2 / 2 = E0 - E(theta, phi'(theta), 0, psi'(theta))``.
    Returns 0.0 when theta' stays non-zero down to 1e-8 rad (impact).

    Parameters
    ----------
    theta0 : float
        Initial inclination [rad] (theta'0 <= 0: the column first descends).
    dphi0, dpsi0, dtheta0 : float
        Initial rates [1/tau].
    column : Column or sequence
    """
    from scipy.optimize import brentq

    E0 = total_energy(theta0, dphi0, dtheta0, dpsi0, column)
    sol = rates_along_theta(theta0, dphi0, dpsi0, column)

    def margin(t):  # I_y theta'^2 / 2 at inclination t
        dphi, dpsi = sol(t)
        return E0 - total_energy(t, dphi, 0.0, dpsi, column)

    grid = theta0 * np.logspace(0, math.log10(1e-8 / theta0), 400)[1:]
    for a, b in zip(grid[:-1], grid[1:]):
        if margin(b) < 0.0 <= margin(a):
            return brentq(margin, b, a, xtol=1e-15, rtol=1e-13)
    return 0.0


def total_energy(theta, dphi, dtheta, dpsi, column):
    """Total energy E / (m g R) of free motion, the paper's Eq. 13 [1]."""
    Iy, Iz, hk1 = _constants(column)
    s, c = np.sin(theta), np.cos(theta)
    return (
        0.5 * Iy * dtheta**2
        + 0.5 * (Iz * c**2 + s * ((Iy - 1.0) * s - hk1 * c)) * dphi**2
        + 0.5 * Iz * dpsi**2
        + (Iz * c - 0.5 * hk1 * s) * dphi * dpsi
        + 0.5 * (2.0 * s + hk1 * c)
    )


# Appendix B: the hypergeometric solution --------------------------------------------------


def appell_parameters(column):
    """b, c, Delta, Delta* of the paper's Appendix B [1] (complex).

    ``b = (I_z - 1) / (h^2 k1^2 - 4 (I_y - 1) I_z)``, ``c = h k1 b / 2``,
    ``Delta = sqrt(1/4 + 4 (b + i c))``, ``Delta* = sqrt(1/4 + 4 (b - i c))``.
    """
    Iy, Iz, hk1 = _constants(column)
    b = (Iz - 1.0) / (-_denominator(Iy, Iz, hk1))
    c = 0.5 * hk1 * b
    delta = mpmath.sqrt(mpmath.mpf(0.25) + 4 * (b + 1j * c))
    delta_star = mpmath.sqrt(mpmath.mpf(0.25) + 4 * (b - 1j * c))
    return b, c, delta, delta_star


def _eta_coefficients(column):
    """(a, b) of Eq. B.2: omega_eta = a d(omega_zeta)/dtheta + b omega_zeta."""
    Iy, Iz, hk1 = _constants(column)
    den = hk1**2 - 4.0 * Iy + 4.0
    return -_denominator(Iy, Iz, hk1) / den, 2.0 * hk1 * (Iz - 1.0) / den


@dataclass(frozen=True)
class AppellSolution:
    """Spin omega_zeta(theta) of free motion in Gauss hypergeometric functions (Appendix B).

    ``omega_zeta = A1 T_Delta + A2 T_-Delta`` (Eq. B.4) with
    ``T_D(theta) = z^(1/4 + D/2) F((1 + D + Delta*)/2, (1 + D - Delta*)/2; 1 + D; z)``,
    ``z = (q - i)/(q + i) = exp(-2 i theta)``, ``q = cot(theta)``; it solves
    Eq. B.3 (with d/dq) and hence B.1 (with its sign corrected, see
    ``docs/misprints.md``). ``omega_eta`` follows from Eq. B.2.

    Built by :func:`appell_solution`; evaluate with the methods, which take
    theta in radians and return rates per tau.
    """

    A1: complex
    A2: complex
    delta: complex
    delta_star: complex
    eta_a: float
    eta_b: float
    dps: int

    def _basis(self, theta):
        """T_+Delta, T_-Delta and their theta-derivatives at one theta (mpmath complex)."""
        out = []
        with mpmath.workdps(self.dps):
            th = mpmath.mpf(float(theta))
            q = mpmath.cot(th)
            z = (q - 1j) / (q + 1j)
            dz = -2j * z  # dz/dtheta
            for D in (self.delta, -self.delta):
                alpha = mpmath.mpf(1) / 4 + D / 2
                a = (1 + D + self.delta_star) / 2
                b = (1 + D - self.delta_star) / 2
                c = 1 + D
                F = mpmath.hyp2f1(a, b, c, z)
                dF = a * b / c * mpmath.hyp2f1(a + 1, b + 1, c + 1, z)
                za = mpmath.power(z, alpha)
                T = za * F
                dT = (alpha * za / z * F + za * dF) * dz
                out.append((T, dT))
        return out

    def _eval(self, theta):
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        w = np.empty(theta.shape)
        dw = np.empty(theta.shape)
        for i, th in enumerate(theta.flat):
            (Tp, dTp), (Tm, dTm) = self._basis(th)
            w.flat[i] = float(mpmath.re(self.A1 * Tp + self.A2 * Tm))
            dw.flat[i] = float(mpmath.re(self.A1 * dTp + self.A2 * dTm))
        return w, dw

    def omega_zeta(self, theta):
        """Spin omega_zeta at inclination theta [rad] -> [1/tau]."""
        return self._eval(theta)[0]

    def omega_eta(self, theta):
        """omega_eta = phi' sin(theta) from Eq. B.2 [1/tau]."""
        w, dw = self._eval(theta)
        return self.eta_a * dw + self.eta_b * w

    def log_coefficients(self):
        """Coefficients of log(1 - z) in T_+Delta, T_-Delta as theta -> 0 (A&S 15.3.10).

        F(a, b; a + b; z) = -Gamma(a + b)/(Gamma(a) Gamma(b)) log(1 - z) + O(1):
        here c = a + b, so each basis function diverges logarithmically at full
        contact; only one combination of them stays finite.
        """
        out = []
        with mpmath.workdps(self.dps):
            for D in (self.delta, -self.delta):
                a = (1 + D + self.delta_star) / 2
                b = (1 + D - self.delta_star) / 2
                out.append(-mpmath.gamma(1 + D) * mpmath.rgamma(a) * mpmath.rgamma(b))
        return tuple(out)

    def finite_parts(self):
        """Limits of T_+-Delta + L_+- log(1 - z) as theta -> 0 (A&S 15.3.10).

        ``F(a, b; a + b; z) + Gamma(a+b)/(Gamma(a)Gamma(b)) log(1 - z) ->
        -Gamma(a+b)/(Gamma(a)Gamma(b)) (psi(a) + psi(b) + 2 gamma)``.
        """
        out = []
        with mpmath.workdps(self.dps):
            for D in (self.delta, -self.delta):
                a = (1 + D + self.delta_star) / 2
                b = (1 + D - self.delta_star) / 2
                L = -mpmath.gamma(1 + D) * mpmath.rgamma(a) * mpmath.rgamma(b)
                out.append(L * (mpmath.digamma(a) + mpmath.digamma(b) + 2 * mpmath.euler))
        return tuple(out)

    def spin_at_contact(self):
        """omega_zeta at theta -> 0 [1/tau]; finite only if the log terms cancel (impact)."""
        Lp, Lm = self.log_coefficients()
        Fp, Fm = self.finite_parts()
        return float(mpmath.re(self.A1 * Fp + self.A2 * Fm)), complex(self.A1 * Lp + self.A2 * Lm)


def appell_solution(theta0, dphi0, dpsi0, column, dps=30):
    """The Appendix B solution through the initial state, A1 and A2 fitted.

    A1, A2 are fitted to omega_zeta = phi'0 cos(theta0) + psi'0 (Eq. 3) and to
    d omega_zeta/d theta at theta0, which Eq. B.2 gives from
    omega_eta = phi'0 sin(theta0). theta'0 does not enter: the rates are
    functions of theta alone.

    Parameters
    ----------
    theta0 : float
        Initial inclination [rad].
    dphi0, dpsi0 : float
        phi'0, psi'0 [1/tau].
    column : Column or sequence
    dps : int
        Decimal digits of mpmath's working precision.

    Returns
    -------
    AppellSolution
    """
    _, _, delta, delta_star = appell_parameters(column)
    ea, eb = _eta_coefficients(column)
    w0 = dphi0 * np.cos(theta0) + dpsi0
    eta0 = dphi0 * np.sin(theta0)
    dw0 = (eta0 - eb * w0) / ea
    sol = AppellSolution(1, 0, delta, delta_star, ea, eb, dps)
    (Tp, dTp), (Tm, dTm) = sol._basis(theta0)
    with mpmath.workdps(dps):
        A = mpmath.matrix([[Tp, Tm], [dTp, dTm]])
        A1, A2 = mpmath.lu_solve(A, mpmath.matrix([w0, dw0]))
    return AppellSolution(A1, A2, delta, delta_star, ea, eb, dps)


def impact_ratio_exact(theta0, column, dps=30):
    """(psi'0/phi'0) for which free motion from rest at theta0 reaches theta = 0.

    Exact for the full free equations (no small-angle approximation): the
    ratio for which the Appendix B spin has no log(1 - z) term at full
    contact. The rates are linear in (phi'0, psi'0), so the condition is
    linear in the ratio.

    Parameters
    ----------
    theta0 : float
        Initial inclination [rad].
    column : Column or sequence

    Returns
    -------
    float
    """
    # log coefficient L(phi'0, psi'0) is linear: L = phi'0 L_phi + psi'0 L_psi
    def log_coeff(dphi0, dpsi0):
        sol = appell_solution(theta0, dphi0, dpsi0, column, dps)
        return sol.spin_at_contact()[1]

    L_phi = log_coeff(1.0, 0.0)
    L_psi = log_coeff(0.0, 1.0)
    ratio = -L_phi / L_psi
    return float(np.real(ratio))


def impact_velocity_exact(theta0, dphi0, dpsi0, dtheta0, column, dps=30):
    """theta' at full contact on an impacting motion, from energy and Appendix B [1/tau].

    ``-sqrt((2 E0 - I_z omega_zeta(0)^2 - h k1) / I_y)`` with the exact spin at
    contact (omega_eta -> 0 there); compare :func:`impact_velocity`, which
    uses the small-angle spin -c1.
    """
    Iy, Iz, hk1 = _constants(column)
    w_contact, _ = appell_solution(theta0, dphi0, dpsi0, column, dps).spin_at_contact()
    E0 = total_energy(theta0, dphi0, dtheta0, dpsi0, column)
    arg = (2.0 * E0 - Iz * w_contact**2 - hk1) / Iy
    return -np.sqrt(arg) if arg >= 0 else np.nan


__all__ = [
    "AppellSolution",
    "appell_parameters",
    "appell_solution",
    "coupling_matrix",
    "eigenvalue_product",
    "impact_ratio",
    "impact_ratio_exact",
    "impact_ratio_series",
    "impact_residual",
    "impact_spin",
    "impact_velocity",
    "impact_velocity_exact",
    "perturbation_eigenvalues",
    "ps_product",
    "rate_sum",
    "rocking_acceleration",
    "spin_approx",
    "rates_along_theta",
    "total_energy",
    "turning_inclination",
    "wobbling_constants",
    "wobbling_p",
    "wobbling_rates",
    "wobbling_rates_approx",
    "wobbling_s",
]
