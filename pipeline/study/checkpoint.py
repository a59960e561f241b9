"""A study's checkpoint: every finished task kept on disk, so that a killed run resumes.

Each finished task is written, atomically, to a checkpoint folder next to the output
(``OUTPUT.checkpoint/``) by the process that drives the study; a rerun of the same study (same
file bytes, records, software version, task layout: :func:`checkpoint_key`) skips the tasks
found there. Only the driving process writes, so workers need no shared disk.
"""

import contextlib
import hashlib
import json
import os
import shutil
import sys

import numpy as np

from pipeline import __version__
from pipeline.atomic import PARTIAL_PREFIX, atomic_open
from pipeline.errors import InputError
from pipeline.locking import try_lock
from pipeline.study.grid import block_size
from pipeline.study.results import result_shape, result_variables


class Checkpoint:
    """Per-study folder of finished tasks (``task-NNNNNN.npz``, written atomically).

    Parameters
    ----------
    folder : str
    key : str
        Identity of the computation (study digest, record digests, software
        version, task layout). A folder holding another key is emptied.
    """

    def __init__(self, folder, key):
        self.folder = folder
        self.key = key
        os.makedirs(folder, exist_ok=True)
        # one run per checkpoint at a time; the kernel releases the lock if the run dies
        self._lock = try_lock(os.path.join(folder, ".lock"))
        if self._lock is None:
            raise InputError(f"{folder}: another run of this study is writing here; wait for it to finish "
                             "(or give another --out)") from None
        manifest = os.path.join(folder, "manifest.json")
        old = None
        if os.path.exists(manifest):
            try:
                with open(manifest, encoding="utf-8") as f:
                    old = json.load(f).get("key")
            except (OSError, ValueError):
                old = None
        if old != key:
            for name in os.listdir(folder):
                if name.startswith("task-") or name.startswith(PARTIAL_PREFIX):
                    os.unlink(os.path.join(folder, name))
            self._atomic(manifest, json.dumps({"key": key, "software": __version__}).encode())

    def _path(self, index):
        return os.path.join(self.folder, f"task-{index:06d}.npz")

    def _atomic(self, path, payload):
        with atomic_open(path, "wb", fsync=True) as f:
            f.write(payload)

    def done(self):
        """Indices of the finished tasks found in the folder."""
        return {int(n[5:11]) for n in os.listdir(self.folder) if n.startswith("task-") and n.endswith(".npz")}

    def save(self, result):
        """Write one task's result (atomic: temporary name, then rename)."""
        import io

        buf = io.BytesIO()
        meta = {k: result.get(k) for k in ("index", "record", "start", "stop", "runs", "seconds", "cpu_seconds",
                                           "errors")}
        np.savez(buf, meta=np.array(json.dumps(meta)), **result["arrays"])
        self._atomic(self._path(result["index"]), buf.getvalue())

    def load(self, index, shape=None, n_joints=0):
        """Read one task's result back (same layout as :func:`run_task` returns).

        A file that cannot be read whole (truncated by a full disk or a crash
        of the file system, edited, of another layout) is reported on stderr by
        name and deleted, and None is returned: its task is computed again.

        Parameters
        ----------
        index : int
        shape : tuple, optional
            The task's (columns, angles, scales, models); a file whose arrays
            differ (in names or shapes, :func:`result_variables`) is damaged.
        n_joints : int
            The task's ``joint`` dimension (0: no compliant model).
        """
        path = self._path(index)
        try:
            with np.load(path) as f:
                meta = json.loads(str(f["meta"]))
                meta["arrays"] = {name: f[name] for name in f.files if name != "meta"}
            arrays = meta["arrays"]
            if meta.get("index") != index or (shape is not None and (
                    set(arrays) != set(result_variables(n_joints))
                    or any(a.shape != result_shape(name, shape, n_joints) for name, a in arrays.items()))):
                raise ValueError("its contents belong to another task layout")
        except Exception as exc:  # noqa: BLE001 - zipfile, numpy, json and OS errors alike mean "damaged"
            print(f"frustum: warning: checkpoint file {path} is damaged ({type(exc).__name__}: "
                  f"{' '.join(str(exc).split())}); its task is computed again", file=sys.stderr)
            with contextlib.suppress(OSError):
                os.unlink(path)
            return None
        return meta

    def release(self):
        """Let another run use the folder."""
        self._lock.release()

    def remove(self, results=None):
        """Delete the folder and release it (once the results file is written).

        Parameters
        ----------
        results : str, optional
            The results file: flushed to disk first, its folder's entry (the
            rename that put it in place) too, so that a power cut never finds
            the checkpoint gone and the file not yet on the disk.
        """
        if results is not None:
            _sync(results)
            _sync(os.path.dirname(os.path.abspath(results)))
        self.release()
        shutil.rmtree(self.folder, ignore_errors=True)


def _sync(path):
    """Flush a file (or a folder's entries) to the disk; a file system that cannot is left as it is."""
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:  # e.g. a folder on a file system that does not sync folders
        pass
    finally:
        os.close(fd)


def checkpoint_key(study, motions, tasks):
    """Identity of a study's computation, for the checkpoint."""
    h = hashlib.sha256()
    for part in [study.digest, __version__, str(block_size(study)), str(len(tasks))]:
        h.update(part.encode())
    for m in motions:
        h.update(m.sha256().encode())
    return h.hexdigest()
