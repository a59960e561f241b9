"""One run at a time: an exclusive lock on a file, on every platform.

``filelock`` takes an operating-system lock (``fcntl.flock`` on Unix,
``msvcrt.locking`` on Windows) that the kernel releases when the process
dies, and falls back to a lock file holding the owner's process id where
neither exists; it imports on every platform, where ``import fcntl`` does not.
"""

import warnings

__all__ = ["try_lock"]


def try_lock(path):
    """Take the lock ``path`` now, without waiting.

    Parameters
    ----------
    path : str or os.PathLike
        Lock file (created if missing; its folder must exist).

    Returns
    -------
    filelock.BaseFileLock or None
        The held lock (call ``release()``), or None if another process holds it.
    """
    with warnings.catch_warnings():  # "only soft file lock is available": expected without fcntl
        warnings.simplefilter("ignore")
        import filelock

    lock = filelock.FileLock(str(path), timeout=0)
    try:
        lock.acquire()
    except filelock.Timeout:
        return None
    return lock
