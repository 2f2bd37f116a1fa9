"""Ties a helper process's life to its owner's: nothing the grader starts outlives the process that started it.

A grading run starts helpers (pool workers, kernel templates, sandboxes, Dask
workers and their grading processes). Killed by SIGKILL, the run gets no chance
to stop them, so each helper arranges its own death:

- :func:`die_with_parent` asks Linux to send it SIGKILL when its parent goes
  (``prctl(PR_SET_PDEATHSIG)``; bubblewrap's ``--die-with-parent`` is the same);
- a helper that must not depend on which *thread* of its parent started it (the
  signal fires when that thread ends) watches its owner with :func:`owner_gone`;
- what cannot die (folders) carries its owner's :func:`mark`, and the next run
  removes those whose owner is no longer :func:`alive` (psutil: pid and start time).
"""

from __future__ import annotations

import ctypes
import functools
import os
import signal

import psutil

__all__ = ["die_with_parent", "mark", "alive", "owner_gone", "Owner"]

_PR_SET_PDEATHSIG = 1

#: ``(pid, start time)`` of a process: a pid alone may be reused by another process.
Owner = tuple[int, float]


@functools.cache
def _libc():
    return ctypes.CDLL(None, use_errno=True)


def die_with_parent(parent: int | None = None) -> None:
    """SIGKILL this process when the thread that started it ends (its parent's exit, however it ends).

    Parameters
    ----------
    parent : int, optional
        The pid this process was started by. If given and the parent is gone
        already (this process was re-parented before the request took effect),
        the process exits at once.

    Raises
    ------
    OSError
        If the kernel refuses the request.
    """
    if _libc().prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0) != 0:
        errno = ctypes.get_errno()
        raise OSError(errno, f"prctl(PR_SET_PDEATHSIG): {os.strerror(errno)}")
    if parent is not None and os.getppid() != parent:
        os._exit(1)  # the parent died before the signal was armed: nothing would ever send it


def mark(pid: int | None = None) -> Owner:
    """``(pid, start time)`` of a process (default: this one), as :func:`alive` checks it."""
    proc = psutil.Process(os.getpid() if pid is None else pid)
    return proc.pid, proc.create_time()


def alive(owner: Owner) -> bool:
    """Whether the process of ``owner`` (a :func:`mark`) still runs: same pid, same start time, not a zombie."""
    pid, started = owner
    try:
        proc = psutil.Process(int(pid))
        return abs(proc.create_time() - float(started)) < 0.01 and proc.status() != psutil.STATUS_ZOMBIE
    except (psutil.Error, ValueError, OverflowError):
        return False


def owner_gone(pid: int) -> int | None:
    """A descriptor that becomes readable when process ``pid`` has exited, or ``None`` if it is gone already.

    For a helper whose owner is its parent but that must outlive the owner's
    starting thread (which ``PR_SET_PDEATHSIG`` would not): poll the descriptor
    with the helper's own input.
    """
    try:
        fd = os.pidfd_open(pid)
    except ProcessLookupError:
        return None
    if os.getppid() != pid:  # re-parented before the descriptor was open: the owner is gone
        os.close(fd)
        return None
    return fd


def _main(argv: list[str]) -> None:
    """``python -m grader.sandbox.lifetime PARENT COMMAND...``: run COMMAND, SIGKILLed when process PARENT ends.

    For servers started by tests and scripts (``dask scheduler``, ``dask worker``):
    the request survives ``exec``, so COMMAND keeps it.
    """
    if len(argv) < 2 or not argv[0].isdigit():
        raise SystemExit("usage: python -m grader.sandbox.lifetime PARENT_PID COMMAND [ARG...]")
    die_with_parent(int(argv[0]))
    os.execvp(argv[1], argv[1:])


if __name__ == "__main__":
    import sys

    _main(sys.argv[1:])
