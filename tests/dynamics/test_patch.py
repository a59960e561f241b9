"""The contact patch's closed forms (:mod:`pipeline.dynamics.rigid.patch`) against quadrature.

The segment of the unit disc within w of the tangent at a rim point P: with s the distance
from the tangent (inwards) and x the distance along it, the disc is ``x^2 <= 2 s - s^2``.
Every integral below is done here by scipy's adaptive quadrature over that region, so a wrong
coefficient or sign in the closed forms fails whatever the form they are written in.
"""

import math

import pytest
from scipy import integrate

from pipeline.dynamics.rigid import patch

# scipy.integrate.dblquad's default tolerances (1.49e-8 absolute and relative) on smooth
# integrands of size O(1): 1e-7 is above its error and far below any coefficient's.
TOL = 1e-7
HEIGHTS = [0.01, 0.2, 0.7, 1.0, 1.3, 1.9, 2.0]


def _over_segment(f, w):
    """``int f(s, x) dA`` over the segment of height w (s from 0 to w, |x| <= sqrt(2 s - s^2))."""
    half = lambda s: math.sqrt(max(0.0, 2.0 * s - s * s))  # noqa: E731
    value, _ = integrate.dblquad(lambda x, s: f(s, x), 0.0, w, lambda s: -half(s), half, epsabs=1e-10,
                                 epsrel=1e-10)
    return value


@pytest.mark.parametrize("w", HEIGHTS)
def test_segment_integrals_are_the_quadratures(w):
    area, s1, jn, jx, lever = patch.segment(w)
    assert area == pytest.approx(_over_segment(lambda s, x: 1.0, w), abs=TOL)
    assert s1 == pytest.approx(_over_segment(lambda s, x: s, w), abs=TOL)
    assert jn == pytest.approx(_over_segment(lambda s, x: s * s, w), abs=TOL)
    assert jx == pytest.approx(_over_segment(lambda s, x: x * x, w), abs=TOL)
    assert lever == pytest.approx(_over_segment(lambda s, x: (w - s) * abs(x), w), abs=TOL)


def test_whole_base_limits():
    """w = 2 is the whole disc: area pi, first moment pi (about a tangent), x^2 moment pi / 4."""
    area, s1, jn, jx, lever = patch.segment(2.0)
    assert area == pytest.approx(math.pi, rel=1e-14)
    assert s1 == pytest.approx(math.pi, rel=1e-14)
    assert jn == pytest.approx(1.25 * math.pi, rel=1e-14)  # pi/4 about the centre + pi 1^2
    assert jx == pytest.approx(0.25 * math.pi, rel=1e-14)
    assert patch.segment(3.0) == patch.segment(2.0)  # clipped


@pytest.mark.parametrize("load,theta,theta_k", [(1.0, 0.02, 0.001), (0.7, 0.005, 0.002), (1.2, 0.1, 1e-5),
                                                (1.0, 0.0011, 0.001)])
def test_depth_carries_the_load(load, theta, theta_k):
    """The pressure k_n theta (w - s) over the segment sums to the load: (theta / theta_k) F(w) / pi = N."""
    w = patch.depth(load, theta, theta_k)
    assert 0.0 < w < 2.0
    f = _over_segment(lambda s, x: w - s, w)
    assert theta / theta_k * f / math.pi == pytest.approx(load, rel=1e-7)


def test_depth_limits():
    """No load, no patch; a load the whole base takes at that tilt (or no tilt) presses all of it."""
    assert patch.depth(0.0, 0.1, 0.001) == 0.0
    assert patch.depth(1.0, 0.0, 0.001) == patch.FULL
    # F(2) = pi: below theta = theta_k the weight keeps the whole base pressed
    assert patch.depth(1.0, 0.0009, 0.001) == patch.FULL
    # a shallow patch: F ~ (8 sqrt 2 / 15) w^(5/2)
    w = patch.depth(1.0, 1.0, 1e-6)
    assert (8.0 * math.sqrt(2.0) / 15.0) * w ** 2.5 == pytest.approx(math.pi * 1e-6, rel=2 * w)


def test_couples_damping_drilling_and_their_caps():
    """The damping couple is c_n J about the centroid times the rate, capped by N times the extent;
    the drilling capacity is mu N times the pressure-weighted lever."""
    load, theta, theta_k, mu = 1.0, 0.02, 0.001, 0.6
    w = patch.depth(load, theta, theta_k)
    area = _over_segment(lambda s, x: 1.0, w)
    s_bar = _over_segment(lambda s, x: s, w) / area
    j_centroid = _over_segment(lambda s, x: (s - s_bar) ** 2, w)
    j_along = _over_segment(lambda s, x: x * x, w)
    pressure = _over_segment(lambda s, x: w - s, w)
    r_d = _over_segment(lambda s, x: (w - s) * abs(x), w) / pressure
    small = 1e-3  # damping small enough to stay under the caps
    m_xi, m_n, drill = patch.couples(load, theta, theta_k, small, mu, 0.5, -2.0)
    assert m_xi == pytest.approx(-small * j_centroid * 0.5, rel=1e-6)
    assert m_n == pytest.approx(small * j_along * 2.0, rel=1e-6)
    assert drill == pytest.approx(mu * load * r_d, rel=1e-6)
    # capped: a pressure redistribution cannot pass N times the patch's depth (across) or half chord (along)
    m_xi, m_n, _ = patch.couples(load, theta, theta_k, 1e6, mu, 0.5, -2.0)
    assert m_xi == pytest.approx(-load * w)
    assert m_n == pytest.approx(load * math.sqrt(w * (2.0 - w)))
    assert patch.couples(0.0, theta, theta_k, small, mu, 0.5, -2.0) == (0.0, 0.0, 0.0)
