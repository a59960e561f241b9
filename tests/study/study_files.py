"""The study files the study tests share (imported by name: ``from study_files import SMALL_STUDY``).

A module of their own, not the conftest: with several conftest.py files in tests/, ``from conftest
import`` finds whichever was imported first (tests/cli's when both folders run together).
"""

# A small study: two short synthetic records (a Ricker wavelet and Kanai-Tajimi
# noise), a named column, an explicit column and a 2-column grid, 3 angles,
# 3 scales, both models. 4 x 2 x 3 x 3 x 2 = 144 results, 96 simulations.
SMALL_STUDY = """\
title = "small test study"
output = "small.nc"
models = ["3d", "2d"]

[[columns]]
named = "paper"

[[columns]]
name = "squat"
R = 0.6
r = 0.5
h = 3.0

[column_grid]
R = 0.4
slenderness = [7.0, 9.0]
beta = 0.9

[records]
synthetic = [
  {generator = "ricker_wavelet", id = "ricker", ap = 4.0, fp = 2.0, dt = 0.01},
  {generator = "kanai_tajimi", id = "kt-1", seed = 1, duration = 6.0, dt = 0.01, pga = 3.0},
]

[excitation]
angles = [0.0, 30.0, 90.0]
scales = [0.5, 1.0, 2.0]

[options]
tail = 2.0

[execution]
block_columns = 2
"""


# A small study of the compliant model: a monolith and the same column as two drums, a 1.5-s
# Ricker wavelet, 2 angles: 2 tasks (one column each) of 2 compliant runs (~1 s each) and one 3d run.
DRUM_STUDY = """\
title = "drums on a cluster"
output = "drums.nc"
models = ["3d", "3d-compliant"]

[[columns]]
named = "paper"

[[columns]]
name = "two-drums"
R = 0.5
r = 0.4
h = 4.0
drums = 2

[records]
synthetic = [{generator = "ricker_wavelet", id = "ricker", ap = 8.0, fp = 2.0, dt = 0.01, duration = 1.5}]

[excitation]
angles = [0.0, 30.0]
scales = [1.0]

[options]
tail = 0.5
contact_sectors = 16
joint_friction = 0.4

[execution]
block_columns = 1
"""
