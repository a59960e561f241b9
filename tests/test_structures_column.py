"""Column geometry against an independent computation over the solid."""

import math

import numpy as np
import pytest
from scipy import integrate

from pipeline.errors import InputError
from pipeline.structures.column import Column
from pipeline.units import G


def _solid_moments(R, r, h):
    """Volume, first and second moments of a frustum by numerical integration.

    Integrates over the solid in cylindrical coordinates (z, rho), the
    azimuth analytically: dV = 2 pi rho drho dz. Independent of the paper's
    k1..k3 formulas.
    """
    radius = lambda z: R + (r - R) * z / h  # noqa: E731
    opts = dict(epsabs=0, epsrel=1e-13)

    def moment(f):
        val, _ = integrate.dblquad(lambda rho, z: f(rho, z) * 2 * math.pi * rho, 0, h, 0, radius, **opts)
        return val

    vol = moment(lambda rho, z: 1.0)
    z_cm = moment(lambda rho, z: z) / vol
    # axial moment per unit mass: E[x^2 + y^2] = E[rho^2]
    axial = moment(lambda rho, z: rho**2) / vol
    # transverse about the centroid: E[x^2] + E[(z - z_cm)^2], E[x^2] = E[rho^2]/2
    transverse = moment(lambda rho, z: rho**2 / 2 + (z - z_cm) ** 2) / vol
    return vol, z_cm, transverse, axial


@pytest.mark.parametrize("beta", [0.1, 0.25, 0.5, 0.8, 1.0, 1.3, 2.0])
@pytest.mark.parametrize("slenderness", [0.5, 8.0])
def test_k_coefficients_and_inertia_match_integration_over_the_solid(beta, slenderness):
    R = 0.7
    col = Column(R=R, r=beta * R, h=slenderness * R)
    vol, z_cm, A, C = _solid_moments(col.R, col.r, col.h)
    # dblquad at epsrel 1e-13 on polynomial integrands: 1e-10 leaves room
    # for its error estimate, far below any misprint (which changes O(1) terms).
    assert col.volume == pytest.approx(vol, rel=1e-10)
    assert col.k1 == pytest.approx(2 * z_cm / col.h, rel=1e-10)
    assert col.k3 == pytest.approx(2 * C / R**2, rel=1e-10)
    # k2 is defined by A = (k3/4) m R^2 + (k2/12) m h^2 (paper, Section 2.2)
    assert col.k2 == pytest.approx(12 * (A - col.k3 * R**2 / 4) / col.h**2, rel=1e-9)
    A_hat, C_hat = col.central_inertia_hat
    assert A_hat == pytest.approx(A / R**2, rel=1e-10)
    assert C_hat == pytest.approx(C / R**2, rel=1e-10)
    # inertia about a rim point of the base, transverse principal direction xi
    assert col.inertia_transverse_hat == pytest.approx((A + R**2 + z_cm**2) / R**2, rel=1e-10)
    assert col.inertia_axial_hat == pytest.approx((C + R**2) / R**2, rel=1e-10)


def test_cylinder_coefficients_are_one():
    col = Column(1.0, 1.0, 3.0)
    assert (col.k1, col.k2, col.k3, col.beta) == pytest.approx((1, 1, 1, 1), rel=1e-15)


def test_statics_of_the_paper_column():
    col = Column(R=0.5, r=0.4, h=4.0, density=2700.0)
    # Figure 4: beta = 0.8, h_hat = 8
    assert col.beta == pytest.approx(0.8) and col.slenderness == pytest.approx(8.0)
    # centre of mass above the rim point at theta_crit = atan(R / z_cm)
    theta = col.critical_tilt
    assert col.R * math.cos(theta) - col.z_cm * math.sin(theta) == pytest.approx(0.0, abs=1e-15)
    assert col.contact_to_cm_angle + col.critical_tilt == pytest.approx(math.pi / 2)
    assert col.contact_to_cm_distance == pytest.approx(math.hypot(0.5, col.z_cm))
    # uplift when a_h z_cm = g R (moment balance about the rim)
    assert col.uplift_acceleration() == pytest.approx(G * 0.5 / col.z_cm)
    assert col.uplift_acceleration(-0.5 * G) == pytest.approx(0.5 * G * 0.5 / col.z_cm)
    assert col.mass == pytest.approx(2700 * math.pi * 4 * (0.25 + 0.2 + 0.16) / 3)
    I = np.array(col.inertia_contact)
    assert np.allclose(I, I.T) and np.all(np.linalg.eigvalsh(I) > 0)


@pytest.mark.parametrize("field,value", [("R", 0), ("r", -1.0), ("h", float("nan")), ("R", float("inf")), ("h", "tall")])
def test_bad_geometry_names_the_value(field, value):
    dims = {"R": 0.5, "r": 0.4, "h": 4.0, field: value}
    with pytest.raises(InputError, match=rf"column {field} = .*{value!s}"):
        Column(**dims)


def test_parse_command_line_column():
    assert Column.parse("0.5,0.4,4") == Column(0.5, 0.4, 4.0)
    with pytest.raises(InputError, match="R,r,h"):
        Column.parse("0.5,4")
