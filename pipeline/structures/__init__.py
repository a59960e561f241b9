"""What is simulated, as geometry: one home for every structure the models run.

* :mod:`pipeline.structures.column`: ``Column``, the rigid conical frustum (R, r, h) and its
  derived quantities (mass, inertia, centre of mass, critical tilt, the paper's k1, k2, k3);
* :mod:`pipeline.structures.drums`: ``DrumColumn``, a column cut into drums, and ``Capital``;
* :mod:`pipeline.structures.named`: the named real columns of ``pipeline/data/columns.toml``.

Nothing here imports a model, a kernel or anything above the ground floor (units, errors).
"""

from pipeline.structures.column import Column
from pipeline.structures.drums import Capital, DrumColumn, named_drum_column
from pipeline.structures.named import named_columns

__all__ = ["Column", "DrumColumn", "Capital", "named_drum_column", "named_columns"]
