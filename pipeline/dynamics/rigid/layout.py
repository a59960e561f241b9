"""Layouts that the rigid models' event-driven runs share: phases, summary, events, numerical thresholds.

Kernel layer, no compiled code. The phase flag of each output row
(``PHASE_*``), the indices of the summary array that both runs fill (``S_*``,
``N_SUMMARY``), the terminal events of the phases (``EV_*``) with their
directions, the safety nets of the run loops, and the numerical thresholds
with their defaults (``NUMERICS``, carried at run time in the options array).
Read by :mod:`pipeline.dynamics.rigid.run3d` (the three-dimensional frustum),
:mod:`pipeline.dynamics.rigid.run2d` (planar rocking) and the layer above.
"""

import numpy as np


PHASE_REST, PHASE_ROLLING, PHASE_OVERTURNED, PHASE_SLIDING, PHASE_SLIPPING, PHASE_FLIGHT = range(6)

# Indices of the summary array filled by the runs.
(
    S_STATUS,  # 0 done, < 0 integration failure (integrator status)
    S_PEAK_THETA,  # [rad]
    S_PEAK_TIME,  # [tau]
    S_OVERTURN_TIME,  # [tau], nan if it stands
    S_UPLIFT_TIME,  # first uplift [tau], nan if never
    S_N_IMPACTS,
    S_PEAK_MU,  # largest mobilized friction |F_t|/N while in contact [1]
    S_MIN_NORMAL,  # lowest normal force while in contact [m g]
    S_TRANSITION,  # energy jumps at contact transitions [m g R]
    S_NFEV,
    S_STEPS,
    S_END_TIME,  # [tau]
    S_ROTATION,  # body rotation about the vertical at the end, phi + psi [rad]
    S_BASE_X,  # base centre at the end [R]
    S_BASE_Y,
    S_SLIDE_TIME,  # first slip of the base or of the rim [tau], nan if never
    S_FLIGHT_TIME,  # first lift-off [tau], nan if never
    S_FINAL_PHASE,  # phase at the end (PHASE_OVERTURNED if it lay down)
    S_ENERGY_START,  # mechanical energy at the start [m g R]
    S_ENERGY_END,  # at the end (when it lies down: then) [m g R]
    S_WORK,  # work done by the ground motion [m g R]
    S_DISSIPATED,  # removed by the contact couples [m g R]
    S_FRICTION,  # removed by sliding friction [m g R]
) = range(23)
N_SUMMARY = 23

# Safety net against a Zeno cascade of transitions.
MAX_TRANSITIONS = 1_000_000
MAX_STEPS = 50_000_000
# Consecutive event stops without advancing time that end a run (status -11)
# instead of looping: a safety net, never reached in the tests.
MAX_STALLS = 100
STATUS_STALLED = -11

EV_LAND, EV_LIE, EV_TURN, EV_LIFT, EV_SLIP, EV_STICK, EV_MODE, EV_PIVOT = range(8)
# landing/touch-down falling, lying down rising, turning point of theta both
# ways, normal force falling to 0, friction margin falling to 0, slip velocity
# falling to 0, slip speed crossing the slaved-direction layer, the drilling
# friction letting the pivot go (or its turning stopping)
EVENT_DIRECTIONS = np.array([-1.0, 1.0, 0.0, -1.0, -1.0, -1.0, -1.0, -1.0])

# Numerical thresholds (defaults; carried in the options array, OPT_*, so that
# studies/thresholds can vary them). No physical result may depend on them:
# studies/thresholds/results.md shows that none does.
#
# slave_time [tau]: the direction of a two-dimensional Coulomb slip relaxes
# towards the consistent one (slip acceleration along the slip) at the rate
# k / s, k of order mu N: at slip onset and stop (s -> 0) that is infinitely
# fast, and no explicit step survives it. Below s = slave_time mu N the
# direction is therefore slaved: taken as the consistent direction, solved at
# every evaluation (an error of the order of the lag slave_time x the turning
# rate of that direction); above it the direction is a state. The layer is
# left at slave_time mu N and entered again below half of it.
#
# look_ahead [tau]: a phase that starts on a bound (stick after a slip stops,
# say) is checked a little ahead as well: the integrator reads the event signs
# only after a restart window of 1e-7 of its first step, and a bound left
# within it would not be seen (the phase would then violate it until the next
# crossing).
#
# landing_margin [1]: rolling starts at theta_c; the landing surface lies a
# hair below it, (1 - landing_margin) theta_c, so a column that uplifts on the
# verge of the threshold (theta'' ~ 0) does not start on the landing surface,
# where round-off would trip the event at once.
#
# min_rebound [rad]: a rebound that would rise less than this above theta_c is
# a settling: shorter excursions than an integration step could slip past the
# landing event (and with theta_c = 0 the column would never settle otherwise).
#
# slaved_turn [rad]: where the contact frame turns fast (phi' ~ 1e6 near the
# vertical) a lag of slave_time would let it turn far; the layer's edge shrinks
# so that the frame turns at most about slaved_turn within the lag (layer_edge).
NUMERICS = {"landing_margin": 1e-3, "min_rebound": 1e-8, "slave_time": 1e-6, "look_ahead": 1e-7,
            "slaved_turn": 1e-3}
