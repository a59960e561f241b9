"""Atomic file writing: a temporary name beside the target, then a rename.

A reader never sees a half-written file, and a run that fails or is
interrupted leaves none behind. The temporary file is created like any file
(``open`` with mode 0666, or by the library that writes it), so the umask
decides its permissions: 0644 under umask 022. ``tempfile.mkstemp`` is not
used because it creates files with mode 0600 whatever the umask.

Temporary names are ``.partial-XXXXXXXX-NAME`` in the target's folder (same
file system, so the rename is atomic; the name keeps the target's suffix for
writers that infer the format from it).

A folder of several files (a report) is written whole into a temporary
folder beside it (:func:`atomic_folder`); only when every file is written are
they renamed into place, so a failure half-way leaves the target as it was.
"""

import contextlib
import os
import secrets
import shutil

__all__ = ["PARTIAL_PREFIX", "atomic_path", "atomic_open", "atomic_folder"]

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


@contextlib.contextmanager
def atomic_folder(path):
    """Yield a temporary folder beside ``path``; its files move into ``path`` on success, all removed on failure.

    On success every file of the temporary folder is renamed to the same
    name under ``path`` (created if missing, sub-folders too), replacing a
    file of that name; other files already in ``path`` are kept (a report
    written into a study's folder leaves its study file alone). On failure,
    ``path`` is left as it was.

    Parameters
    ----------
    path : str or os.PathLike
        The final folder; its parent is created if needed.
    """
    path = os.path.abspath(os.fspath(path))
    parent, name = os.path.split(path)
    os.makedirs(parent, exist_ok=True)
    tmp = os.path.join(parent, f"{PARTIAL_PREFIX}{secrets.token_hex(4)}-{name}")
    os.mkdir(tmp)  # mode 0777 less the umask, like any folder
    try:
        yield tmp
        for root, _, files in os.walk(tmp):
            target = os.path.join(path, os.path.relpath(root, tmp))
            os.makedirs(target, exist_ok=True)
            for file in files:  # same file system: each rename is atomic
                os.replace(os.path.join(root, file), os.path.join(target, file))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
