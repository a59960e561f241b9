"""Layouts that the rigid models' event-driven runs share: phases, summary, events, numerical thresholds.

Kernel layer, no compiled code. The phase flag of each output row
(``PHASE_*``), the indices of the summary array that both runs fill (``S_*``,
``N_SUMMARY``), the terminal events of the phases (``EV_*``) with their
directions, the safety nets of the run loops, and the numerical thresholds
(their defaults are the models' numerics in :mod:`pipeline.models.rigid`, carried at run time in the options array).
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
    S_UNDECIDED,  # 1: the run reached its settle limit with the column still able to overturn
) = range(24)
N_SUMMARY = 24

# After the record and its tail the run goes on with the ground still until the outcome is
# decided (loop.stands_for_good), checked every SETTLE_CHUNK [tau]: the chunk changes only when
# a decided run stops, never its outcome or peak.
SETTLE_CHUNK = 1.0

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
