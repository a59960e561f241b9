"""Synthetic motions: determinism, definitions, direction option."""

import math
import subprocess
import sys

import numpy as np
import pytest

from pipeline.groundmotion import (clough_penzien, intensity as im, kanai_tajimi, mavroeidis_papageorgiou,
                                   rectangular_pulse, ricker_wavelet)
from pipeline.groundmotion.synthesis import mavroeidis_papageorgiou_velocity

CODE = ("from pipeline.groundmotion import kanai_tajimi, clough_penzien;"
        "print(kanai_tajimi(42, duration=8.0).sha256(), clough_penzien(7, duration=8.0, envelope='jennings').sha256())")


def test_stochastic_identical_across_runs_and_processes():
    here = (kanai_tajimi(42, duration=8.0).sha256(), clough_penzien(7, duration=8.0, envelope="jennings").sha256())
    again = (kanai_tajimi(42, duration=8.0).sha256(), clough_penzien(7, duration=8.0, envelope="jennings").sha256())
    other = subprocess.run([sys.executable, "-c", CODE], capture_output=True, text=True, check=True).stdout.split()
    assert here == again == tuple(other)
    assert kanai_tajimi(43, duration=8.0).sha256() != here[0]


def test_stochastic_pair_and_scaling():
    gm = kanai_tajimi(1, duration=10.0, pga=3.0)
    assert max(im.pga(gm.acc_x), im.pga(gm.acc_y)) == pytest.approx(3.0, rel=1e-12)
    assert not np.allclose(gm.acc_x, gm.acc_y)  # independent realisations
    one = kanai_tajimi(1, duration=10.0, independent_y=False)
    assert np.all(one.acc_y == 0.0)
    assert gm.metadata["parameters"]["seed"] == 1 and "synthesised kanai_tajimi" in gm.processing[0]
    # The Clough-Penzien high-pass bounds the drift of the displacement that
    # the Kanai-Tajimi spectrum (non-zero at omega = 0) lets grow.
    kt = kanai_tajimi(3, duration=20.0, independent_y=False)
    cp = clough_penzien(3, duration=20.0, independent_y=False)
    assert im.pgd(cp.acc_x, cp.dt) < im.pgd(kt.acc_x, kt.dt)


def test_mavroeidis_papageorgiou_velocity_matches_closed_form():
    A, fp, gamma, nu = 0.6, 0.8, 2.5, math.pi / 3
    gm = mavroeidis_papageorgiou(A, fp, gamma, nu, dt=1e-4)
    v = im.velocity(gm.acc_x, gm.dt)
    t0 = gamma / (2 * fp)
    ref = mavroeidis_papageorgiou_velocity(gm.time, A, fp, gamma, nu, t0)
    # The pulse starts at v(0) = A/2 (1 + cos(-pi)) cos(...) = 0, so integrating
    # the exact derivative from rest recovers v to the trapezoidal error
    # O((2 pi fp dt)^2) ~ 1e-6 of A.
    np.testing.assert_allclose(v, ref, atol=1e-5 * A)


def test_ricker_and_rectangular():
    r = ricker_wavelet(2.0, 3.0, dt=1e-3)
    assert im.pga(r.acc_x) == pytest.approx(2.0, rel=1e-12)  # central peak at t0 on the grid
    assert abs(im.velocity(r.acc_x, r.dt)[-1]) < 1e-6  # zero net velocity (second derivative of a Gaussian)
    rect = rectangular_pulse(1.5, 0.2, dt=1e-3, duration=0.5)
    # Half-value sample at t_p makes the trapezoidal impulse exact: v_end = a_p t_p.
    assert im.velocity(rect.acc_x, rect.dt)[-1] == pytest.approx(1.5 * 0.2, rel=1e-12)
    with pytest.raises(ValueError, match="tp=0.2005 s is not a whole number of steps"):
        rectangular_pulse(1.0, 0.2005, dt=1e-3)


def test_direction_option():
    x_only = ricker_wavelet(1.0, 2.0, dt=0.01)
    assert np.all(x_only.acc_y == 0.0)
    d = ricker_wavelet(1.0, 2.0, dt=0.01, direction=30.0)  # degrees
    np.testing.assert_allclose(d.acc_x, x_only.acc_x * math.cos(math.radians(30)))
    np.testing.assert_allclose(d.acc_y, x_only.acc_x * math.sin(math.radians(30)))
