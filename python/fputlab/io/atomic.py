"""File-system primitives every writer of fputlab uses: a file appears whole or not at all
(written under a unique temporary name in its own directory, flushed to disk, renamed), an
exclusive creation that two racing processes cannot both win, leftover temporaries cleaned, and
one lock per directory (fcntl.lockf) so that two runners never share a work directory.

Only the standard library, numpy and h5py: every layer may write through this module."""
from __future__ import annotations

import contextlib
import errno
import os
import secrets
from pathlib import Path

__all__ = ["temporary_name", "write_atomic", "write_h5_atomic", "write_bytes_atomic",
           "create_exclusive", "remove_temporaries", "DirectoryLock", "DirectoryBusy"]

#: every temporary this module makes ends so (and starts with a dot)
TMP_SUFFIX = ".fputlab-tmp"


def temporary_name(path) -> Path:
    """A name next to `path` that no other process or thread uses: the pid and 64 random bits
    (a shared name such as `.x.tmp` lets one writer replace another's half-written file)."""
    path = Path(path)
    return path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(8)}{TMP_SUFFIX}")


def _fsync_dir(directory: Path) -> None:
    with contextlib.suppress(OSError):
        fd = os.open(directory, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


def write_atomic(path, write) -> None:
    """Call ``write(tmp_path)`` to fill a temporary file, then rename it to `path`: readers see
    the old file or the new one, never a part. The temporary is removed on any error."""
    path = Path(path)
    tmp = temporary_name(path)
    try:
        write(tmp)
        with open(tmp, "rb+") as f:
            os.fsync(f.fileno())
        os.replace(tmp, path)
        _fsync_dir(path.parent)
    finally:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()


def write_bytes_atomic(path, data: bytes) -> None:
    """`data` as the whole content of `path`, atomically (see `write_atomic`)."""
    write_atomic(path, lambda tmp: Path(tmp).write_bytes(data))


def write_h5_atomic(path, fill) -> None:
    """An HDF5 file filled by ``fill(h5py.File)``, atomically (see `write_atomic`)."""
    import h5py

    def write(tmp):
        with h5py.File(tmp, "w") as f:
            fill(f)
    write_atomic(path, write)


def create_exclusive(path, data: bytes) -> bool:
    """Create `path` with `data` unless it exists: True if this call created it. The content is
    complete before the name appears (hard link of a finished temporary), and of several
    processes racing to create it exactly one wins."""
    path = Path(path)
    tmp = temporary_name(path)
    try:
        tmp.write_bytes(data)
        with open(tmp, "rb+") as f:
            os.fsync(f.fileno())
        try:
            os.link(tmp, path)
        except FileExistsError:
            return False
        _fsync_dir(path.parent)
        return True
    finally:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()


def remove_temporaries(directory) -> int:
    """Remove the temporaries a killed writer left in `directory` (call it holding the
    directory's lock, so no live writer owns them). Returns how many."""
    n = 0
    for p in Path(directory).glob(f".*{TMP_SUFFIX}"):
        with contextlib.suppress(FileNotFoundError):
            p.unlink()
            n += 1
    return n


class DirectoryBusy(RuntimeError):
    """Another process holds the lock of a work directory."""


#: the directories this process holds locks on (POSIX locks are per process: a second lock from
#: the same process would succeed, so this process's own holders are refused here)
_HELD: set = set()


class DirectoryLock:
    """An exclusive lock on ``directory/.lock``, held while the object is open: a POSIX record
    lock (fcntl.lockf), which the kernel drops when the process dies (a killed runner never leaves
    a stale lock) and which forked workers do not inherit (a killed runner's orphaned pool
    workers never hold it); within one process a second holder is refused too. A second locker
    is refused at once with `DirectoryBusy` naming the holder's pid."""

    def __init__(self, directory, what: str = "work directory"):
        self.directory = Path(directory)
        self.what = what
        self._fd = None
        self._key = None

    def _busy(self, holder: str) -> DirectoryBusy:
        return DirectoryBusy(
            f"{self.what} {str(self.directory)!r} is in use by another runner"
            f"{f' (pid {holder})' if holder else ''}: wait for it to finish or stop it; "
            "two runners on one directory would duplicate work")

    def acquire(self) -> "DirectoryLock":
        import fcntl
        key = os.path.realpath(self.directory)
        if key in _HELD:
            raise self._busy(str(os.getpid()))
        path = self.directory / ".lock"
        fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
        try:
            fcntl.lockf(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as err:
            holder = ""
            with contextlib.suppress(OSError, ValueError):
                holder = os.pread(fd, 64, 0).decode().strip()
            os.close(fd)
            if err.errno in (errno.EAGAIN, errno.EACCES, errno.EWOULDBLOCK):
                raise self._busy(holder) from None
            raise
        os.ftruncate(fd, 0)
        os.pwrite(fd, str(os.getpid()).encode(), 0)
        self._fd, self._key = fd, key
        _HELD.add(key)
        return self

    def release(self) -> None:
        if self._fd is not None:
            with contextlib.suppress(OSError):
                os.ftruncate(self._fd, 0)
            os.close(self._fd)        # closing drops the lock
            _HELD.discard(self._key)
            self._fd = None

    def __enter__(self):
        return self.acquire()

    def __exit__(self, *exc):
        self.release()
