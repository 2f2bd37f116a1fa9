"""A unit's private folder on the host: the student's size-capped workdir and the kernel's runtime files.

Layout of one workspace ``/tmp/dl-unit-XXXX/`` (mode 0700, the grader's own)::

    work/      the student's working directory, bound read-write into the sandbox;
               a tmpfs of ``size_bytes`` when the grader may mount one (root), so
               a submission can fill only its own space, never the host's disk
    kernels/   connection files and sockets of the kernel's lives (never inside
               ``work/``, so nothing the student writes is where the host reads
               or writes its own files)

While in use a workspace holds an ``flock`` on ``/tmp/dl-unit-XXXX.lock``, which
names its owner (the grading process's pid and start time). A grader killed
mid-unit releases the lock with its death, and :func:`remove_stale_workspaces`
(the first step of every grading run) removes (and unmounts) what it left behind.
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import fcntl
import functools
import logging
import os
import shutil
import tempfile
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from grader.sandbox.lifetime import Owner, alive, mark

__all__ = ["Workspace", "workspace", "remove_stale_workspaces", "PREFIX"]

log = logging.getLogger(__name__)

PREFIX = "dl-unit-"
_MNT_DETACH = 2
_MIN_STALE_SECONDS = 10


@dataclass(frozen=True)
class Workspace:
    """Paths of one unit's workspace.

    Attributes
    ----------
    root : Path
        ``/tmp/dl-unit-XXXX``, readable by the grader only.
    work : Path
        The student's working directory (``root / "work"``).
    kernels : Path
        Parent of the kernel runtime folders (``root / "kernels"``), never bound into the sandbox.
    capped : bool
        Whether ``work`` is a size-capped tmpfs.
    """

    root: Path
    work: Path
    kernels: Path
    capped: bool


@functools.cache
def _libc():
    return ctypes.CDLL(ctypes.util.find_library("c"), use_errno=True)


def _mount_tmpfs(path: Path, size_bytes: int) -> bool:
    """Mount a tmpfs of ``size_bytes`` on ``path``; False where this process may not mount."""
    if os.geteuid() != 0:
        return False
    options = f"size={int(size_bytes)},mode=0755,nr_inodes=65536".encode()
    flags = 0x2 | 0x4  # MS_NOSUID | MS_NODEV
    if _libc().mount(b"tmpfs", os.fsencode(path), b"tmpfs", flags, options) != 0:
        _warn_uncapped(os.strerror(ctypes.get_errno()))
        return False
    return True


def _unmount(path: Path) -> None:
    _libc().umount2(os.fsencode(path), _MNT_DETACH)


@functools.cache
def _warn_uncapped(why: str) -> None:
    log.warning("student workdirs are not size-capped (cannot mount a tmpfs: %s); only per-file limits apply", why)


def _is_mountpoint(path: Path) -> bool:
    try:
        return os.path.ismount(path)
    except OSError:
        return False


def _remove(root: Path) -> None:
    """Unmount and delete a workspace; ``rmtree`` never follows the links a student left."""
    work = root / "work"
    if _is_mountpoint(work):
        _unmount(work)
    shutil.rmtree(root, ignore_errors=True)


@contextlib.contextmanager
def workspace(size_bytes: int, parent: str | Path | None = None) -> Iterator[Workspace]:
    """Create a unit's workspace; unmount and delete it on exit.

    Parameters
    ----------
    size_bytes : int
        Size of the student's ``work/`` tmpfs, in bytes (where it can be mounted).
    parent : path-like, optional
        Where to create it; default the system's temporary folder.

    Yields
    ------
    Workspace
    """
    root = Path(tempfile.mkdtemp(prefix=PREFIX, dir=parent))
    lock = open(root.with_name(root.name + ".lock"), "w")  # noqa: SIM115 - held for the whole block
    try:
        fcntl.flock(lock, fcntl.LOCK_EX)
        lock.write("%d %r\n" % mark())
        lock.flush()
        work, kernels = root / "work", root / "kernels"
        work.mkdir()
        kernels.mkdir(mode=0o700)
        capped = _mount_tmpfs(work, size_bytes)
        yield Workspace(root, work, kernels, capped)
    finally:
        _remove(root)
        Path(lock.name).unlink(missing_ok=True)
        lock.close()


def remove_stale_workspaces(parent: str | Path | None = None) -> list[Path]:
    """Remove workspaces whose grader died (their lock is free and its owner gone).

    Parameters
    ----------
    parent : path-like, optional
        Where workspaces are created; default the system's temporary folder.

    Returns
    -------
    list of Path
        The workspaces removed.
    """
    parent = Path(parent or tempfile.gettempdir())
    removed = []
    for lock_path in parent.glob(f"{PREFIX}*.lock"):
        root = lock_path.with_suffix("")
        try:
            fd = os.open(lock_path, os.O_RDONLY | os.O_NOFOLLOW)
        except OSError:
            continue
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            owner = _owner(fd)
            if owner is None:
                # Unmarked: a lock only seconds old may belong to a workspace being created right now.
                if time.time() - os.fstat(fd).st_mtime < _MIN_STALE_SECONDS:
                    raise BlockingIOError
            elif alive(owner):
                raise BlockingIOError
        except OSError:  # its grader is alive
            os.close(fd)
            continue
        try:
            if root.is_dir() and not root.is_symlink():
                _remove(root)
                removed.append(root)
            lock_path.unlink(missing_ok=True)
        finally:
            os.close(fd)
    return removed


def _owner(fd: int) -> Owner | None:
    """The owner a lock file names, ``None`` if it names none (yet)."""
    try:
        pid, started = os.pread(fd, 64, 0).decode("ascii").split()
        return int(pid), float(started)
    except (OSError, ValueError, UnicodeDecodeError):
        return None
