"""What is simulated, as geometry: one home for every structure the models run.

* :mod:`pipeline.structures.column`: ``Column``, the rigid conical frustum (R, r, h) and its
  derived quantities (mass, inertia, centre of mass, critical tilt, the paper's k1, k2, k3);
* :mod:`pipeline.structures.drums`: ``DrumColumn``, a column cut into drums, and ``Capital``;
* :mod:`pipeline.structures.colonnade`: ``Colonnade``, columns in a row carrying an epistyle of
  blocks, its blocks, bearings and head joints, and the rigid frame's equivalent block;
* :mod:`pipeline.structures.named`: the named real columns of ``pipeline/data/columns.toml``
  (the named colonnades of ``pipeline/data/colonnades.toml``: ``named_colonnade``);
* :mod:`pipeline.structures.kinds`: the kinds of structure a model declares it runs;
* :mod:`pipeline.structures.description`: what a structure is in words and attributes, and its
  bodies' and joints' labels, written once for every file, report, figure and summary.

Nothing here imports a model, a kernel or anything above the ground floor (units, errors).
"""

from pipeline.structures.colonnade import Colonnade, FrameBlock, RigidColumn, frame_block, named_colonnade, \
    named_colonnades, rigid_column
from pipeline.structures.column import Column
from pipeline.structures.drums import Capital, DrumColumn, named_drum_column
from pipeline.structures.kinds import KINDS, kind_of
from pipeline.structures.named import named_columns

__all__ = ["Column", "DrumColumn", "Capital", "named_drum_column", "named_columns", "Colonnade", "FrameBlock",
           "RigidColumn", "frame_block", "rigid_column", "named_colonnade", "named_colonnades", "KINDS", "kind_of"]
