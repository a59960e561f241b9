"""Atomic file writing: a temporary name beside the target, then a rename.

A reader never sees a half-written file, and a run that fails or is
interrupted leaves none behind. The temporary file is created like any file
(``open`` with mode 0666, or by the library that writes it), so the umask
decides its permissions: 0644 under umask 022. ``tempfile.mkstemp`` is not
used because it creates files with mode 0600 whatever the umask.

Temporary names are ``.partial-XXXXXXXX-NAME`` in the target's folder (same
file system, so the rename is atomic; the name keeps the target's suffix for
writers that infer the format from it).
"""

import contextlib
import os
import secrets

__all__ = ["PARTIAL_PREFIX", "atomic_path", "atomic_open"]

#: Prefix of every temporary name (a folder's leftovers can be found by it).
PARTIAL_PREFIX = ".partial-"


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary path beside ``path``; renamed to ``path`` on success, removed on failure.

    The caller (or the library it hands the path to) creates the file.

    Parameters
    ----------
    path : str or os.PathLike
        The final file; its folder must exist.
    """
    path = os.fspath(path)
    folder, name = os.path.split(os.path.abspath(path))
    tmp = os.path.join(folder, f"{PARTIAL_PREFIX}{secrets.token_hex(4)}-{name}")
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


@contextlib.contextmanager
def atomic_open(path, mode="wb", *, fsync=False, **open_kwargs):
    """Open a temporary file beside ``path`` for writing; it becomes ``path`` when the block ends without error.

    Parameters
    ----------
    path : str or os.PathLike
    mode : {"wb", "w"}
        Binary or text.
    fsync : bool
        Flush the data to disk before the rename (for checkpoints that must
        survive a power cut).
    **open_kwargs
        Passed to :func:`open` (``encoding``, ``newline``).
    """
    if mode not in ("wb", "w"):
        raise ValueError(f"atomic_open writes new files: mode 'w' or 'wb', not {mode!r}")
    with atomic_path(path) as tmp:
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)  # the umask applies
        with open(fd, mode, **open_kwargs) as fh:
            yield fh
            if fsync:
                fh.flush()
                os.fsync(fh.fileno())
