"""Intensity measures against closed forms and an independent SDOF integration."""

import math

import numpy as np
import pytest

from pipeline.groundmotion import cycloidal_pulse, harmonic, intensity as im, one_sine_pulse
from pipeline.units import G

# Closed-form checks at dt = 1e-4 s on T_p = 1 s pulses: the trapezoidal
# error in PGV is (omega_p dt)^2 / 12 ~ 3e-8 relative, and the trapezoidal
# rule is exact (to rounding) for sin^2 and cos^2 over a whole period, so 1e-6
# (the acceptance tolerance) leaves margin.
RTOL = 1e-6
DT = 1e-4


@pytest.mark.parametrize("ap, tp", [(2.0, 1.0), (0.5 * G, 0.4)])
def test_one_sine_closed_forms(ap, tp):
    gm = one_sine_pulse(ap, tp, dt=DT * tp)
    wp = 2.0 * math.pi / tp
    assert im.pga(gm.acc_x) == pytest.approx(ap, rel=RTOL)
    assert im.pgv(gm.acc_x, gm.dt) == pytest.approx(2.0 * ap / wp, rel=RTOL)
    assert im.arias_intensity(gm.acc_x, gm.dt) == pytest.approx(math.pi * ap**2 * tp / (4.0 * G), rel=RTOL)
    assert im.pga(gm.acc_y) == 0.0


@pytest.mark.parametrize("kind", ["A", "B"])
def test_cycloidal_closed_forms(kind):
    vp, tp = 0.8, 1.0
    wp = 2.0 * math.pi / tp
    gm = cycloidal_pulse(vp, tp, kind, dt=DT)
    pga = wp * vp / 2.0 if kind == "A" else wp * vp
    arias = math.pi * (wp * vp) ** 2 * tp / (16.0 * G) if kind == "A" else math.pi * (wp * vp) ** 2 * tp / (4.0 * G)
    assert im.pga(gm.acc_x) == pytest.approx(pga, rel=RTOL)
    assert im.pgv(gm.acc_x, gm.dt) == pytest.approx(vp, rel=RTOL)
    assert im.arias_intensity(gm.acc_x, gm.dt) == pytest.approx(arias, rel=RTOL)


def test_cycloidal_phase_is_makris_and_changs():
    """phi = 0.0697 pi for C_1 (Makris & Chang 2000 print 3 digits); it solves cot(phi) = pi (n + 1/2) - phi."""
    from pipeline.groundmotion.synthesis import cycloidal_phase

    assert cycloidal_phase(1) / math.pi == pytest.approx(0.0697, abs=5e-5)
    for n in (1, 2, 3):
        phi = cycloidal_phase(n)
        assert 1.0 / math.tan(phi) == pytest.approx(math.pi * (n + 0.5) - phi, rel=1e-13)


@pytest.mark.parametrize("n", [1, 2])
def test_cycloidal_c_closed_forms(n):
    """Type C_n: PGA w v_p, PGV v_p (1 + sin phi), Arias in closed form, and the ground ends at rest where it
    started. Checked at the last sample t_k <= t_c of the pulse: from there to t_c the ground still moves by
    |v| <= w v_p (t_c - t_k) and |u| <= w v_p (t_c - t_k)^2 / 2; the trapezoidal integration adds at most
    t_c dt^2 w^3 v_p / 12 ~ 2.5e-7 m/s (and t_c times that in m), hence the 1e-6 margin."""
    from pipeline.groundmotion.synthesis import cycloidal_phase

    vp, tp = 0.8, 1.0
    wp = 2.0 * math.pi / tp
    phi = cycloidal_phase(n)
    t_c = (n + 0.5 - phi / math.pi) * tp
    gm = cycloidal_pulse(vp, tp, "C", n=n, dt=DT, duration=t_c + 1.0)
    assert im.pga(gm.acc_x) == pytest.approx(wp * vp, rel=RTOL)
    assert im.pgv(gm.acc_x, gm.dt) == pytest.approx(vp * (1.0 + math.sin(phi)), rel=RTOL)
    arias = math.pi * (wp * vp) ** 2 * (t_c / 2.0 - math.sin(2.0 * phi) / (2.0 * wp)) / (2.0 * G)
    assert im.arias_intensity(gm.acc_x, gm.dt) == pytest.approx(arias, rel=1e-3)  # the end ramp: ~ dt / t_c
    velocity = im.velocity(gm.acc_x, gm.dt)
    displacement = np.concatenate([[0.0], np.cumsum(0.5 * (velocity[1:] + velocity[:-1]) * gm.dt)])
    k = int(np.flatnonzero(gm.time <= t_c)[-1])
    gap = t_c - gm.time[k]
    assert abs(velocity[k]) <= wp * vp * gap + 1e-6
    assert abs(displacement[k]) <= wp * vp * gap**2 / 2.0 + 1e-6
    assert abs(displacement).max() > 0.1 * vp * tp  # it did move
    with pytest.raises(Exception, match="n >= 1"):
        cycloidal_pulse(vp, tp, "C", n=0)


def test_pgd_cav_duration_of_harmonic():
    # a = a_p sin(w t) over n whole cycles: |a| integrates to 2 a_p n T / pi;
    # the Husid curve of sin^2 is t/2 - sin(2wt)/(4w), so D5-95 is close to
    # 0.9 of the duration (to within the sin term's 1/(4 w) wiggle).
    ap, period, n = 1.0, 0.5, 10
    gm = harmonic(ap, period, dt=1e-4, n_cycles=n)
    assert im.cav(gm.acc_x, gm.dt) == pytest.approx(2.0 * ap * n * period / math.pi, rel=1e-6)
    d, t5, t95 = im.significant_duration(gm.acc_x, gm.dt)
    assert d == pytest.approx(0.9 * n * period, abs=period / (2 * math.pi))
    # velocity ap/w (1 - cos wt), displacement ap/w (t - sin(wt)/w): PGD at the end
    w = 2 * math.pi / period
    assert im.pgd(gm.acc_x, gm.dt) == pytest.approx(ap / w * n * period, rel=1e-6)


def _newmark_sa(acc, dt, periods, damping, sub):
    """Independent reference: Newmark average acceleration at dt/sub on the
    linearly interpolated record, peak absolute acceleration over all fine steps."""
    n = acc.size
    fine = np.interp(np.arange((n - 1) * sub + 1) / sub, np.arange(n), acc)
    h = dt / sub
    w = 2 * np.pi / np.asarray(periods)
    c, k = 2 * damping * w, w * w
    beta, gamma = 0.25, 0.5
    khat = k + gamma * c / (beta * h) + 1 / (beta * h * h)
    x = np.zeros_like(w)
    v = np.zeros_like(w)
    a = -fine[0] - c * v - k * x
    peak = np.abs(c * v + k * x)
    for p in -fine[1:]:
        rhs = p + x / (beta * h * h) + v / (beta * h) + (1 / (2 * beta) - 1) * a \
            + c * (gamma * x / (beta * h) + (gamma / beta - 1) * v + h * (gamma / (2 * beta) - 1) * a)
        x_new = rhs / khat
        a_new = (x_new - x) / (beta * h * h) - v / (beta * h) - (1 / (2 * beta) - 1) * a
        v = v + h * ((1 - gamma) * a + gamma * a_new)
        x, a = x_new, a_new
        np.maximum(peak, np.abs(c * v + k * x), out=peak)
    return peak


def test_spectral_acceleration_against_newmark(fema_ff01):
    """Sa within 1 % (acceptance) of Newmark at dt/50 for T = 0.05-5 s.

    Newmark's period error at w h <= 0.025 is (w h)^2 / 12 < 1e-4 and the
    fine grid resolves peaks; Sa samples the exact response at >= 50 points
    per period (peak error <= 1 - cos(pi/50) = 0.2 %). Measured worst: 0.08 %.
    """
    acc, dt = np.asarray(fema_ff01.acc_x[:1000]), fema_ff01.dt  # first 10 s, the strong part
    periods = np.geomspace(0.05, 5.0, 12)
    sa = im.spectral_acceleration(acc, dt, periods, damping=0.05)
    ref = _newmark_sa(acc, dt, periods, 0.05, sub=50)
    rel = np.abs(sa / ref - 1)
    print(f"Sa worst relative error {rel.max():.2e} at T = {periods[rel.argmax()]:.3f} s")
    assert rel.max() < 0.01


def test_spectral_limits(fema_ff01):
    acc, dt = fema_ff01.acc_x, fema_ff01.dt
    # Very stiff oscillator follows the ground: Sa(T -> 0) -> PGA (to within
    # the tiny relative motion at T = 1 ms).
    assert im.spectral_acceleration(acc, dt, 0.001) == pytest.approx(im.pga(acc), rel=2e-3)
    # Undamped resonance with a harmonic grows linearly: after n cycles the
    # amplitude is about pi n a_p.
    gm = harmonic(1.0, 1.0, dt=0.01, n_cycles=20)
    sa = im.spectral_acceleration(gm.acc_x, gm.dt, 1.0, damping=0.0)
    assert sa == pytest.approx(math.pi * 20, rel=0.02)
    pseudo = im.spectral_acceleration(acc, dt, [0.5, 1.0], kind="pseudo")
    assert np.all(pseudo > 0)


def test_rotd(fema_ff01):
    x, y, dt = fema_ff01.acc_x, fema_ff01.acc_y, fema_ff01.dt
    r100 = im.rotd100(x, y, dt)
    r50 = im.rotd50(x, y, dt)
    # RotD100 is the peak of the vector |a| up to the 1-degree angle grid
    # (cos(0.5 deg) = 0.99996); it bounds both components and RotD50.
    assert r100 == pytest.approx(np.max(np.hypot(x, y)), rel=4e-5)
    assert r50 <= r100 and r100 >= max(im.pga(x), im.pga(y))
    # A motion on x only has the peak |a| cos(theta): RotD50 = PGA cos(45 deg).
    xo = np.asarray(x)
    assert im.rotd50(xo, np.zeros_like(xo), dt) == pytest.approx(im.pga(xo) * math.cos(math.radians(44.5)), rel=2e-2)
    sa100 = im.rotd100(x, y, dt, measure="sa", period=1.0)
    assert sa100 >= im.spectral_acceleration(x, dt, 1.0) * (1 - 1e-9)
