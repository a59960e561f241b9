"""Ground motions: records built on ObsPy streams, sources, processing, intensity measures.

Public interface::

    from pipeline.groundmotion import GroundMotion, load, load_set, list_sets
    gm = load("FEMA-FF-01")                  # catalog id (records/catalog.toml)
    gm = load("x.mseed", units="g")          # any obspy.read format, AT2, text/CSV, bare numbers
    gm = load(["x.AT2", "y.AT2"])            # 2-3 files, one per component
    gm = load(obspy.read("x.knet"), missing_y="zero")   # an ObsPy Stream or Trace
    gm.acc_x, gm.acc_y, gm.acc_z, gm.dt      # m/s^2, s
    gm.rotated(30.0).scaled(2.0)             # degrees; new objects, processing logged

Modules: :mod:`.record` (the type), :mod:`.files` (ObsPy formats and
streams), :mod:`.text` (plain text), :mod:`.components` (which trace is x, y,
z), :mod:`.at2` (ObsPy plugin), :mod:`.fema` (FEMA P695 sets),
:mod:`.catalog` (ids, sets, ``load``), :mod:`.checks` (warnings about
unprocessed records), :mod:`.options` (how options are named in messages),
:mod:`.synthesis`, :mod:`.processing`, :mod:`.intensity`, :mod:`.plot`.
"""

from pipeline.groundmotion import intensity, processing, synthesis
from pipeline.groundmotion.catalog import list_records, list_sets, load, load_set
from pipeline.groundmotion.record import GroundMotion
from pipeline.groundmotion.synthesis import (
    clough_penzien,
    cycloidal_pulse,
    harmonic,
    kanai_tajimi,
    mavroeidis_papageorgiou,
    one_sine_pulse,
    rectangular_pulse,
    ricker_wavelet,
)

__all__ = [
    "GroundMotion",
    "load",
    "load_set",
    "list_sets",
    "list_records",
    "intensity",
    "processing",
    "synthesis",
    "one_sine_pulse",
    "cycloidal_pulse",
    "rectangular_pulse",
    "ricker_wavelet",
    "mavroeidis_papageorgiou",
    "harmonic",
    "kanai_tajimi",
    "clough_penzien",
]
