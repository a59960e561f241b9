"""Symbolic derivation of the frustum's equations of motion (sympy).

This script is the source of truth for the compiled right-hand side in
:mod:`pipeline.dynamics.rigid.frustum`; ``tests/dynamics/test_derivation.py`` checks
that the compiled code evaluates exactly what is derived here.

Model (the paper's assumptions a-c, Section 2)
------------------------------------------------
A homogeneous rigid conical frustum (bottom radius R, top radius r, height h)
touches a horizontal plane at one point P of the rim of its base and rolls on it
without slipping. The plane translates with acceleration
``a_g = (a_X, a_Y, a_Z)``; we write the equations in the frame of the plane
(non-inertial, translating), where the plane is at rest and every mass element
feels the extra uniform field ``-a_g``. Gravity plus that field is
``g_eff = (-a_X, -a_Y, -g - a_Z)``.

Coordinates are the paper's (its Figure 2): Z-X-Z Euler angles
``(phi, theta, psi)`` = (precession, inclination, spin) of the body's symmetry
axis, and the contact point ``(X_P, Y_P)`` measured on the plane. The body
frame ``C(xi, eta, zeta)`` has ``xi`` along the line of nodes (horizontal),
``zeta`` along the symmetry axis, ``eta = zeta x xi``. The contact point is the
lowest point of the base rim, ``P = B - R e_eta`` with ``B`` the centre of the
base; so the column leans *towards* P and ``theta = 0`` is full base contact.

Rather than Lagrange multipliers (the paper's Eq. 8), we use Newton-Euler:

* ``m a_C = F + m g_eff``             (F: contact force on the column)
* ``dH_C/dt = (P - C) x F``           (H_C: angular momentum about C)
* rolling: the material point at P has the plane's velocity, so in the plane's
  frame ``v_C = omega x (C - P)``.

Eliminating F gives three equations, linear in ``(phi'', theta'', psi'')``.
Everything is made dimensionless as in the paper's Eq. 9: lengths by R, time by
sqrt(R/g), mass by m, so accelerations are in units of g and forces of m g.
The derivation uses three geometric constants only:

* ``Iy`` = I_y^P / (m R^2): the paper's transverse inertia "at P",
  ``A/(mR^2) + zc^2 + 1`` with A the central transverse moment;
* ``Iz`` = I_z^P / (m R^2) = ``C/(mR^2) + 1`` with C the axial moment;
* ``zc`` = z_cm / R = h_hat k1 / 2, the height of the centre of mass.

Running ``python -m pipeline.dynamics.derivation`` prints the mass matrix, the
right-hand side, the energy and the comparison with the printed coefficients
of the paper (see ``docs/misprints.md``).
"""

from functools import lru_cache

import sympy as sp

# Symbols ---------------------------------------------------------------------
tau = sp.Symbol("tau", real=True)
Iy, Iz, zc = sp.symbols("Iy Iz zc", positive=True)
ax, ay, az = sp.symbols("a_x a_y a_z", real=True)  # ground acceleration / g
phi_f, theta_f, psi_f = (sp.Function(n, real=True)(tau) for n in ("phi", "theta", "psi"))

# Plain symbols for states, used in the final expressions.
phi, theta, psi = sp.symbols("phi theta psi", real=True)
dphi, dtheta, dpsi = sp.symbols("dphi dtheta dpsi", real=True)
ddphi, ddtheta, ddpsi = sp.symbols("ddphi ddtheta ddpsi", real=True)

_TO_SYMBOLS = {
    sp.Derivative(phi_f, (tau, 2)): ddphi,
    sp.Derivative(theta_f, (tau, 2)): ddtheta,
    sp.Derivative(psi_f, (tau, 2)): ddpsi,
}
_TO_SYMBOLS_1 = {
    sp.Derivative(phi_f, tau): dphi,
    sp.Derivative(theta_f, tau): dtheta,
    sp.Derivative(psi_f, tau): dpsi,
}
_TO_SYMBOLS_0 = {phi_f: phi, theta_f: theta, psi_f: psi}


def _to_symbols(expr):
    """Replace the functions of tau and their derivatives by plain symbols."""
    return expr.subs(_TO_SYMBOLS).subs(_TO_SYMBOLS_1).subs(_TO_SYMBOLS_0)


def _frame(ph, th):
    """Unit vectors e_xi, e_eta, e_zeta in the plane's frame (X, Y, Z)."""
    e_xi = sp.Matrix([sp.cos(ph), sp.sin(ph), 0])
    e_eta = sp.Matrix([-sp.sin(ph) * sp.cos(th), sp.cos(ph) * sp.cos(th), sp.sin(th)])
    e_zeta = sp.Matrix([sp.sin(ph) * sp.sin(th), -sp.cos(ph) * sp.sin(th), sp.cos(th)])
    return e_xi, e_eta, e_zeta


@lru_cache(maxsize=None)
def kinematics():
    """Angular velocity, centre-of-mass position and velocity (functions of tau).

    Returns
    -------
    dict
        ``omega`` (plane frame), ``omega_body`` (xi, eta, zeta components),
        ``r_PC`` (from P to C), ``v_C`` (velocity of C relative to the plane),
        frame vectors ``e_xi``, ``e_eta``, ``e_zeta``, and ``Z_C``.
    """
    e_xi, e_eta, e_zeta = _frame(phi_f, theta_f)
    e_Z = sp.Matrix([0, 0, 1])
    d = lambda f: sp.diff(f, tau)  # noqa: E731
    omega = d(phi_f) * e_Z + d(theta_f) * e_xi + d(psi_f) * e_zeta
    omega_body = sp.Matrix([omega.dot(e_xi), omega.dot(e_eta), omega.dot(e_zeta)]).applyfunc(
        sp.simplify
    )
    r_PC = e_eta + zc * e_zeta  # R = 1
    v_C = omega.cross(r_PC)
    return {
        "omega": omega,
        "omega_body": omega_body,
        "r_PC": r_PC,
        "v_C": v_C,
        "e_xi": e_xi,
        "e_eta": e_eta,
        "e_zeta": e_zeta,
        "Z_C": r_PC[2],
    }


@lru_cache(maxsize=None)
def equations_of_motion():
    """Mass matrix and forcing of the rolling frustum, ``M qdd = f``.

    Returns
    -------
    M : sympy.Matrix, 3x3
        Coefficients of ``(phi'', theta'', psi'')``, rows are the Euler
        equations projected on ``(xi, eta, zeta)`` rearranged so that M is
        symmetric (it equals the Hessian of the kinetic energy in the rates).
    f : sympy.Matrix, 3x1
        Everything else (gyroscopic, gravity, ground acceleration terms).
    F : sympy.Matrix, 3x1
        Contact force on the column per m g, in the plane's frame, as a
        function of states and accelerations ``ddphi, ddtheta, ddpsi``.
    """
    k = kinematics()
    e_xi, e_eta, e_zeta = k["e_xi"], k["e_eta"], k["e_zeta"]
    A = Iy - 1 - zc**2  # central transverse inertia / (m R^2)
    C = Iz - 1  # central axial inertia / (m R^2)
    w = k["omega"]
    H_C = A * w.dot(e_xi) * e_xi + A * w.dot(e_eta) * e_eta + C * w.dot(e_zeta) * e_zeta
    a_C = sp.diff(k["v_C"], tau)
    g_eff = sp.Matrix([-ax, -ay, -1 - az])
    F = a_C - g_eff  # m = 1
    residual = sp.diff(H_C, tau) - (-k["r_PC"]).cross(F)
    # Project on the moving axes: the equations take their simplest form there.
    eqs = [_to_symbols(residual.dot(e)) for e in (e_xi, e_eta, e_zeta)]
    eqs = [sp.expand(sp.simplify(e)) for e in eqs]
    qdd = sp.Matrix([ddphi, ddtheta, ddpsi])
    M_rows = sp.Matrix([[sp.diff(e, v) for v in qdd] for e in eqs])
    f_rows = -sp.Matrix([e.subs({ddphi: 0, ddtheta: 0, ddpsi: 0}) for e in eqs])
    # The xi-row is the theta equation; the eta and zeta rows mix phi and psi.
    # Recombine into the symmetric (Lagrangian) form: the generalized force
    # for phi is the Z-moment, for theta the xi-moment, for psi the zeta-moment.
    # Z = sin(theta) e_eta + cos(theta) e_zeta.
    T_rows = sp.Matrix(
        [
            [0, sp.sin(theta), sp.cos(theta)],  # phi  <- Z component
            [1, 0, 0],  # theta <- xi
            [0, 0, 1],  # psi  <- zeta
        ]
    )
    M = (T_rows * M_rows).applyfunc(lambda x: sp.simplify(sp.expand_trig(x)))
    f = (T_rows * f_rows).applyfunc(lambda x: sp.simplify(sp.expand_trig(x)))
    F_sym = _to_symbols(F).applyfunc(sp.expand)
    return M, f, F_sym


@lru_cache(maxsize=None)
def energy():
    """Kinetic and potential energy per (m g R), and the ground's power.

    Returns
    -------
    T, V, P_ground : sympy expressions
        ``T`` kinetic energy relative to the plane, ``V = Z_C``, and
        ``P_ground = -a_g . v_C``, the power that the field ``-a_g`` delivers,
        so that ``d(T + V)/dtau = P_ground`` along solutions.
    """
    k = kinematics()
    A = Iy - 1 - zc**2
    C = Iz - 1
    wb = k["omega_body"]
    T = sp.Rational(1, 2) * k["v_C"].dot(k["v_C"]) + sp.Rational(1, 2) * (
        A * wb[0] ** 2 + A * wb[1] ** 2 + C * wb[2] ** 2
    )
    T = sp.simplify(_to_symbols(T))
    V = _to_symbols(k["Z_C"])
    P_ground = sp.simplify(_to_symbols(-(ax * k["v_C"][0] + ay * k["v_C"][1] + az * k["v_C"][2])))
    return T, V, P_ground


@lru_cache(maxsize=None)
def accelerations():
    """Closed-form ``(phi'', theta'', psi'')`` for theta != 0.

    Returns
    -------
    tuple of sympy expressions
    """
    M, f, _ = equations_of_motion()
    sol = M.LUsolve(f)
    return tuple(sp.simplify(s) for s in sol)


@lru_cache(maxsize=None)
def couple_accelerations():
    """Accelerations caused by a couple ``M = -nu omega`` on the body.

    The generalized forces are ``Q_i = M . d(omega)/d(q_i')`` and the extra
    accelerations ``M^-1 Q`` (the mass matrix of :func:`equations_of_motion`).

    Returns
    -------
    tuple of sympy expressions
        (d phi'', d theta'', d psi'') in terms of the rates and ``nu``.
    """
    nu = sp.Symbol("nu", positive=True)
    k = kinematics()
    omega = k["omega"]
    Q = sp.Matrix(
        [_to_symbols((-nu * omega).dot(sp.diff(omega, sp.diff(q, tau)))) for q in (phi_f, theta_f, psi_f)]
    )
    M, _, _ = equations_of_motion()
    return tuple(sp.simplify(x) for x in M.LUsolve(Q)), nu


@lru_cache(maxsize=None)
def general_couple_accelerations():
    """Accelerations caused by any couple ``M = m_xi e_xi + m_eta e_eta + m_zeta e_zeta``.

    As :func:`couple_accelerations`, for a couple given by its body
    components (the contact patch's couples of :mod:`pipeline.dynamics.rigid.patch`).

    Returns
    -------
    tuple
        ``((d phi'', d theta'', d psi''), (m_xi, m_eta, m_zeta))``.
    """
    m_xi, m_eta, m_zeta = sp.symbols("m_xi m_eta m_zeta", real=True)
    k = kinematics()
    omega = k["omega"]
    couple = m_xi * k["e_xi"] + m_eta * k["e_eta"] + m_zeta * k["e_zeta"]
    Q = sp.Matrix([_to_symbols(couple.dot(sp.diff(omega, sp.diff(q, tau)))) for q in (phi_f, theta_f, psi_f)])
    M, _, _ = equations_of_motion()
    return tuple(sp.simplify(x) for x in M.LUsolve(Q)), (m_xi, m_eta, m_zeta)


def paper_coefficients(h_k1):
    """The paper's printed g_ij of Eq. 12 as sympy expressions (as printed).

    ``h_k1`` is the product h_hat k1 = 2 zc. The ground acceleration enters
    as ``u'' (alpha1, alpha2)``; here we return the coefficients for a unit
    ``u''`` with ``(alpha1, alpha2) = (a_x, a_y)``.
    """
    D = 4 * (Iy - 1) * Iz - h_k1**2
    cot, csc = sp.cot(theta), sp.csc(theta)
    a_xi = ax * sp.cos(phi) + ay * sp.sin(phi)
    a_eta = -ax * sp.sin(phi) + ay * sp.cos(phi)
    return {
        "g11": 2 * (Iz - 1) * (2 * cot * Iz - h_k1) / D - 2 * cot,
        "g13": 4 * csc * (Iz - 1) * Iz / D,
        "g21": ((Iy - Iz - 1) * sp.sin(2 * theta) - h_k1 * sp.cos(2 * theta)) / (2 * Iy),
        "g22": (h_k1 * sp.sin(theta) - 2 * sp.cos(theta)) / (2 * Iy),
        "g23": -(2 * (Iz + 1) * sp.sin(theta) + h_k1 * sp.cos(theta)) / (2 * Iy),
        "g31": (
            (4 * h_k1 * sp.cos(theta) - 4 * (Iy - Iz - 1) * sp.sin(theta)) * (Iz - 1)
            + 2 * (4 * Iy * Iz - 2 * Iz**2 - 2 * Iz - h_k1**2) * csc
        )
        / D,
        "g33": -2 * (Iz - 1) * (2 * Iz * cot - h_k1) / D,
        # printed "h_1": read as h_hat k1
        "g14": 2 * h_k1 * (Iz - 1) * csc / (h_k1**2 - 4 * (Iy - 1) * Iz) * a_xi,
        "g24": (2 * sp.sin(theta) + h_k1 * sp.cos(theta)) / (2 * Iy) * a_eta,
        "g34": (4 * (Iy - 1) + 2 * (Iz - 1) * cot - h_k1**2) / D * a_xi,
    }


def derived_coefficients():
    """Our g_ij, read off the derived accelerations in the paper's form.

    With no vertical ground acceleration, phi'' = (g11 phi' + g13 psi') theta'
    + g14, theta'' = (g21 phi' + g23 psi') phi' + g22 + g24, psi'' likewise.
    """
    ddp, ddt, dds = (sp.expand(x.subs(az, 0)) for x in accelerations())
    ground = {ax: 0, ay: 0}

    def coeff(expr, *monomial):
        term = expr
        for m in monomial:
            term = sp.diff(term, m)
        return sp.simplify(term.subs({dphi: 0, dtheta: 0, dpsi: 0}).subs(ground))

    def ground_part(expr):
        return sp.simplify(expr.subs({dphi: 0, dtheta: 0, dpsi: 0}) - expr.subs(
            {dphi: 0, dtheta: 0, dpsi: 0}).subs(ground))

    return {
        "g11": coeff(ddp, dphi, dtheta),
        "g13": coeff(ddp, dpsi, dtheta),
        "g14": ground_part(ddp),
        "g21": coeff(ddt, dphi, dphi) / 2,
        "g23": coeff(ddt, dphi, dpsi),
        "g22": sp.simplify(ddt.subs({dphi: 0, dtheta: 0, dpsi: 0}).subs(ground)),
        "g24": ground_part(ddt),
        "g31": coeff(dds, dphi, dtheta),
        "g33": coeff(dds, dpsi, dtheta),
        "g34": ground_part(dds),
    }


if __name__ == "__main__":  # pragma: no cover - a report for people
    M, f, F = equations_of_motion()
    sp.pprint(M)
    sp.pprint(f)
    T, V, P = energy()
    print("T =", T)
    print("V =", V)
    print("P_ground =", P)
    for k, v in derived_coefficients().items():
        print(k, "=", v)
