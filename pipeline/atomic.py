"""Files that appear only once complete: write to a temporary name beside the target, then rename."""

import contextlib
import os
import tempfile


@contextlib.contextmanager
def atomic_path(path, suffix=""):
    """Yield a temporary path beside ``path``; renamed to ``path`` on success, removed on failure.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write; its folder is created if needed.
    suffix : str
        Suffix of the temporary name (writers that pick a format by suffix
        need the real one, e.g. ``".nc"``, ``".png"``).

    The file gets the permissions a plain ``open()`` would give it
    (0666 less the umask), not the private 0600 of a temporary file.
    """
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=".partial-", suffix=suffix, dir=folder)
    os.close(fd)
    os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes it private (0600); the file gets what open() would give
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


__all__ = ["atomic_path"]
