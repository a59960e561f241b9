"""The compliant model's joint damping, calibrated to a coefficient of restitution of planar rocking.

The dashpots of a bed are not measured physics: :func:`calibrated_damping` finds the normal
damping per unit area that gives a column's outline, as a monolith on the bed, the planar
restitution the rigid model uses (or the study's ``restitution``), by releasing it tilted
and measuring its rebound (:func:`planar_restitution`). Cached per process.
"""

import math
from dataclasses import replace
from functools import lru_cache

import numpy as np
from scipy.optimize import brentq

from pipeline.compliant.integrate import integrate
from pipeline.compliant.layouts import outline_of
from pipeline.compliant.rest import released_state
from pipeline.compliant.tables import assemble
from pipeline.dynamics.compliant.layout import H_TILT
from pipeline.errors import InputError
from pipeline.models.compliant import COMPLIANT_DRUMS
from pipeline.settings import ModelSettings, housner_restitution
from pipeline.units import G

__all__ = ["calibrated_damping", "critical_damping", "planar_restitution", "MAX_DAMPING_RATIO"]

# -- damping from a coefficient of restitution -------------------------------------------------

# Largest damping the calibration considers: critical damping of the column bouncing on its
# full base. Beyond it the restitution hardly changes (docs/model.md) and the stiff dashpot
# only shortens the steps.
MAX_DAMPING_RATIO = 1.0
RELEASE_TILT = 0.3  # release tilt of the calibration, per theta_crit


def critical_damping(structure, settings):
    """Normal damping per unit area [Pa s/m] that critically damps a column's bounce.

    ``2 sqrt(k_n A M) / A`` for the column (mass M, its capital included; a colonnade's first
    column) on its full base (area A).
    """
    stack = outline_of(structure, whole=True)
    c = stack.column
    mass = stack.density * c.volume + (stack.capital.mass(stack.density) if stack.capital else 0.0)
    area = math.pi * c.R**2 * (1.0 - settings.base_anathyrosis**2)
    return 2.0 * math.sqrt(settings.normal_stiffness * mass / area)


def planar_restitution(column, settings, damping, amplitude=RELEASE_TILT):
    """Coefficient of restitution of planar rocking of the compliant monolith [1].

    The column is released still, tilted by ``amplitude`` theta_crit towards a rim point; it
    falls, lands on its base and rocks up on the other side. As in the rigid model,
    ``theta'_after = e theta'_before``; the rebound peak theta_1 gives it through the energy
    of rocking: ``e^2 = (cos(a - theta_1) - cos a) / (cos(a - theta_0) - cos a)``,
    a = theta_crit.

    Parameters
    ----------
    column : Column, DrumColumn or Colonnade
        Its outline (a colonnade's first column's) is used, as one body.
    settings : pipeline.settings.ModelSettings
    damping : float
        Normal damping per unit area c_n [Pa s/m].
    amplitude : float
        Release tilt per theta_crit [1].

    Returns
    -------
    float
    """
    outline = outline_of(column)
    asm = assemble(outline, settings, damping)
    params = asm.params()
    alpha = outline.critical_tilt
    theta0 = amplitude * alpha
    y0 = released_state(asm, params, theta0, settings.integrator)
    # the rigid column falls in (1/p) acosh(alpha / (alpha - theta0)) (linearised rocking)
    fall = math.acosh(alpha / (alpha - theta0)) / outline.frequency_parameter()
    tilt, _raw = _run_free(asm, params, y0, 2.6 * fall, monitor=min(2e-4, fall / 200.0), settings=settings)
    low = int(np.argmax(tilt < 0.5 * theta0))
    bottom = low + int(np.argmax(np.diff(tilt[low:]) > 0.0))
    top = bottom + int(np.argmax(np.diff(tilt[bottom:]) < 0.0))
    if top <= bottom or top >= len(tilt) - 1:
        raise InputError(_unmeasurable(outline, settings, "the released column did not rock back up "
                                                          "(no rebound peak)"))
    theta1 = _parabola_peak(tilt[top - 1:top + 2])
    drop = math.cos(alpha - theta0) - math.cos(alpha)
    return math.sqrt(max(0.0, math.cos(alpha - theta1) - math.cos(alpha)) / drop)


def _unmeasurable(outline, settings, what):
    """The message of a damping calibration that cannot measure a planar restitution."""
    sink = outline.density * outline.volume * G / (settings.normal_stiffness * math.pi * outline.R ** 2)
    return (f"normal_stiffness = {settings.normal_stiffness:g} Pa/m: the damping calibration could not measure a "
            f"rocking restitution on this bed ({what}; the column sinks {1e3 * sink:.3g} mm under its weight): "
            "give the joints' damping yourself, contact_damping [Pa s/m] (--contact-damping), or a stiffer bed "
            "(1e9 Pa/m and stiffer calibrate for the paper's column)")


def _parabola_peak(three):
    """Peak of the parabola through three equally spaced samples around a maximum."""
    a, b, c = three
    curv = a - 2.0 * b + c
    return b if curv >= 0.0 else b - 0.125 * (c - a) ** 2 / curv


def _run_free(asm, params, y0, duration, monitor, settings):
    """Run without ground motion; the top body's tilt every ``monitor`` seconds, and the raw run.

    The adaptive integrators run at rtol 1e-9, atol 1e-12 whatever the settings say; the
    fixed-step one at the settings' step (the calibration then matches the discrete model).
    """
    raw = integrate(asm, params, y0, duration, monitor, 1, replace(settings, rtol=1e-9, atol=1e-12),
                    histories=True)
    return raw.hist_body[:, -1, H_TILT], raw


@lru_cache(maxsize=256)
def _calibrated(outline, settings_key, target):
    settings = _settings_from_key(settings_key)
    critical = critical_damping(outline, settings)

    def e(ratio):
        return planar_restitution(outline, settings, ratio * critical)

    e_most = e(MAX_DAMPING_RATIO)
    if not 0.0 < e_most <= 1.0:
        raise InputError(_unmeasurable(outline, settings, f"with critical damping it measured {e_most:.3g}"))
    if target <= e_most:
        return MAX_DAMPING_RATIO * critical, e_most
    e_none = e(0.0)
    if not e_most <= e_none <= 1.0 + 1e-2:
        # less damping must not lose more: the bed is too soft for a rocking measurement
        raise InputError(_unmeasurable(outline, settings, f"undamped it measured {e_none:.3g}, critically "
                                                          f"damped {e_most:.3g}"))
    if target >= e_none:
        return 0.0, e_none
    ratio = brentq(lambda z: e(z) - target, 0.0, MAX_DAMPING_RATIO, xtol=1e-5, rtol=1e-6)
    return ratio * critical, e(ratio)


_CALIBRATION_FIELDS = ("normal_stiffness", "stiffness_ratio", "friction", "contact_rings", "contact_sectors",
                       "base_anathyrosis", "integrator", "step", "numerics")


def _settings_key(settings):
    return tuple(getattr(settings, name) for name in _CALIBRATION_FIELDS)


def _settings_from_key(key):
    return ModelSettings(model=COMPLIANT_DRUMS.name, **dict(zip(_CALIBRATION_FIELDS, key)))


def calibrated_damping(column, settings, target=None):
    """Normal damping per unit area that gives the column a planar restitution, and that restitution.

    Root-finding (Brent) on :func:`planar_restitution` of the column's outline as a monolith,
    for the joint stiffness, friction and contact points of ``settings``, between no damping
    and :data:`MAX_DAMPING_RATIO` of :func:`critical_damping`. A target outside what the
    compliant contact can give is met as closely as it can: a column landing flat on a disc
    of contact points spreads the impact over the landing side, so it loses less energy than
    the rigid model's point impulse at the opposite rim point (docs/model.md); the returned
    restitution says what was reached. Cached per process (outline, joint parameters, target).

    Parameters
    ----------
    column : Column, DrumColumn or Colonnade
        A colonnade's bed is its first column's.
    settings : pipeline.settings.ModelSettings
    target : float, optional
        Target restitution [1]; default ``settings.restitution``, or else the rigid model's
        own ``1 - 2 / I_y_hat`` (:func:`pipeline.settings.housner_restitution`).

    Returns
    -------
    tuple of float
        ``(c_n [Pa s/m], restitution reached [1])``.
    """
    outline = outline_of(column)
    if target is None:
        target = settings.restitution if settings.restitution is not None else housner_restitution(outline)
    return _calibrated(outline, _settings_key(settings), float(target))


# -- running -----------------------------------------------------------------------------------

