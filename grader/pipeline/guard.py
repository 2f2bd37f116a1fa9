"""Limits on the grader's own work with one unit's outputs (verification, feedback pictures).

The student decides how much data the grader handles: the outputs are bounded
when read (:mod:`grader.harness.outputs`), and this is the second line. Inside
``grader_limits`` the process may grow its address space by at most
``memory_bytes`` (``RLIMIT_AS``, soft limit, restored on exit) and run for at
most ``seconds`` (``SIGALRM``); past either, the work raises
:class:`GraderLimitExceeded` or ``MemoryError`` and costs only that unit's
function. Both need the main thread of a process that grades one unit at a
time (a pool worker): elsewhere the block runs without them.
"""

from __future__ import annotations

import contextlib
import math
import os
import resource
import signal
import threading
import time
from collections.abc import Iterator
from pathlib import Path

from grader.sandbox.limits import peak_rss_bytes as process_peak_rss_bytes
from grader.sandbox.limits import status_bytes

__all__ = [
    "GraderLimitExceeded", "grader_limits", "reset_peak_rss", "peak_rss_bytes",
    "DEFAULT_GRADER_MEMORY_BYTES", "DEFAULT_GRADER_SECONDS",
]

#: Address space the grader may add while verifying one function or drawing one unit's feedback.
DEFAULT_GRADER_MEMORY_BYTES = 2 * 2**30
DEFAULT_GRADER_SECONDS = 120.0


class GraderLimitExceeded(Exception):
    """The grader's own work on a student's outputs ran past its time limit."""


def reset_peak_rss() -> bool:
    """Start this process's resident-memory high-water mark (``VmHWM``) afresh, so it measures one unit.

    Returns
    -------
    bool
        Whether the kernel allowed it (Linux: ``/proc/self/clear_refs``).
    """
    try:
        Path("/proc/self/clear_refs").write_text("5")
        return True
    except OSError:
        return False


def peak_rss_bytes() -> int | None:
    """This process's resident-memory high-water mark (``VmHWM``) in bytes, since start or the last reset."""
    return process_peak_rss_bytes([os.getpid()])


def _on_alarm(signum, frame):
    raise GraderLimitExceeded("the grader's work on these outputs took too long")


@contextlib.contextmanager
def grader_limits(memory_bytes: int = DEFAULT_GRADER_MEMORY_BYTES, seconds: float = DEFAULT_GRADER_SECONDS) -> Iterator[bool]:
    """Run a block under a memory and a time cap of its own.

    Parameters
    ----------
    memory_bytes : int
        Address space the block may add to the process's current one.
    seconds : float
        Wall-clock time the block may take.

    Yields
    ------
    bool
        Whether the caps are in force (only in the main thread).
    """
    if threading.current_thread() is not threading.main_thread():
        yield False
        return
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    now = status_bytes(os.getpid(), "VmSize")
    cap = None if now is None else now + int(memory_bytes)
    if cap is not None and hard != resource.RLIM_INFINITY:
        cap = min(cap, hard)
    if cap is not None and (soft == resource.RLIM_INFINITY or cap < soft):
        resource.setrlimit(resource.RLIMIT_AS, (cap, hard))
    previous = signal.signal(signal.SIGALRM, _on_alarm)
    started = time.monotonic()
    outer_delay, outer_interval = signal.setitimer(signal.ITIMER_REAL, max(seconds, 0.001) if math.isfinite(seconds) else 0)
    try:
        yield True
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
        if outer_delay > 0:  # someone else's alarm (a test runner's timeout) goes on where it was
            signal.setitimer(signal.ITIMER_REAL, max(outer_delay - (time.monotonic() - started), 0.001), outer_interval)
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
