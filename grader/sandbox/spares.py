"""Sandboxes started ahead of time: each grading thread's next unit boots while the last one is verified.

A :class:`SparePool` holds at most one spare per thread that grades (a Dask
worker may run several): a kernel is tied to the thread that launched it (bwrap
``--die-with-parent``), and a spare taken by one unit is gone for every other.
A spare is new (workspace, kernel, process cap) and serves exactly one unit,
the next one of its thread, if that unit has the limits it was started with
(its *key*); otherwise it is discarded.

A grading process opens one pool (:func:`open_pool`, what grading workers do)
and closes it at exit; a lone ``grade_unit`` call, with no pool open, leaves
nothing running. A grading process killed outright takes its spares' sandboxes
with it (``--die-with-parent``); their workspaces are swept by the next run
(:func:`grader.sandbox.workspace.remove_stale_workspaces`).
"""

from __future__ import annotations

import atexit
import contextlib
import logging
import multiprocessing.util
import threading
from collections.abc import Callable, Hashable
from dataclasses import dataclass

from grader.sandbox.kernel import SandboxedKernelManager
from grader.sandbox.workspace import Workspace, workspace

__all__ = ["Spare", "SparePool", "open_pool", "close_pool", "pool"]

log = logging.getLogger(__name__)


@dataclass
class Spare:
    """A sandbox started ahead of time for its thread's next unit: a workspace and a kernel of its own.

    Attributes
    ----------
    key : hashable
        What it was started for (the unit's limits and the paths it may read).
    ws : Workspace
    km : SandboxedKernelManager
        Launched in ``ws``; its kernel may still be booting.
    """

    key: Hashable
    stack: contextlib.ExitStack  # holds the workspace
    ws: Workspace
    km: SandboxedKernelManager

    def close(self) -> None:
        """Kill the sandbox and remove the workspace."""
        try:
            if self.km.has_kernel:
                self.km.shutdown_kernel(now=True)
        finally:
            self.stack.close()


class SparePool:
    """The spares of one grading process, one per grading thread.

    ``launch`` replaces the calling thread's spare, ``take`` hands it out (or
    discards it), ``close`` discards every spare; a closed pool launches nothing.
    """

    def __init__(self):
        self._spares: dict[int, Spare] = {}
        self._lock = threading.Lock()
        self.closed = False

    def _pop(self) -> Spare | None:
        with self._lock:
            return self._spares.pop(threading.get_ident(), None)

    def peek(self) -> Spare | None:
        """This thread's spare, left in the pool (for tests and benchmarks)."""
        with self._lock:
            return self._spares.get(threading.get_ident())

    def take(self, key: Hashable) -> Spare | None:
        """This thread's spare, removed from the pool, if it was started for ``key`` and its kernel lives; else discarded.

        Returns
        -------
        Spare or None
            The caller owns it and closes it after its unit.
        """
        spare = self._pop()
        if spare is not None and (spare.key != key or not spare.km.is_alive()):
            spare.close()
            spare = None
        return spare

    def launch(self, key: Hashable, disk_bytes: int, start: Callable[[Workspace], SandboxedKernelManager]) -> None:
        """Replace this thread's spare by a new one: a workspace of ``disk_bytes`` and ``start(ws)``'s kernel launched in it.

        A failure costs nothing but the spare (the next unit starts its own sandbox); a warning says why.
        """
        old = self._pop()
        if old is not None:
            old.close()
        if self.closed:
            return
        stack = contextlib.ExitStack()
        try:
            ws = stack.enter_context(workspace(disk_bytes))
            km = start(ws)
        except Exception:  # noqa: BLE001 - the next unit starts its own sandbox, as without a spare
            stack.close()
            log.warning("could not pre-start the next unit's sandbox", exc_info=True)
            return
        spare = Spare(key, stack, ws, km)
        with self._lock:
            if not self.closed:
                self._spares[threading.get_ident()] = spare
                return
        spare.close()  # closed meanwhile, from another thread

    def complete_launch(self) -> None:
        """Fork the kernel of this thread's spare into its sandbox (``launch`` may have built only the sandbox)."""
        spare = self.peek()
        if spare is None:
            return
        try:
            spare.km.complete_launch()
        except Exception:  # noqa: BLE001 - the next unit starts its own sandbox, as without a spare
            log.warning("could not start the next unit's kernel", exc_info=True)
            spare = self._pop()
            if spare is not None:
                spare.close()

    def close(self) -> None:
        """Discard every spare (every thread's) and launch no more."""
        with self._lock:
            self.closed = True
            spares = list(self._spares.values())
            self._spares.clear()
        for spare in spares:
            spare.close()


_pool: SparePool | None = None
_pool_lock = threading.Lock()
_registered = False


def pool() -> SparePool | None:
    """This process's open pool, or ``None`` (pre-starting is off)."""
    return _pool


def open_pool() -> SparePool:
    """Open this process's pool (if not open): each later unit's sandbox is launched while the one before is verified.

    Grading workers open it (:func:`grader.pipeline.workers.init_worker`); it is closed,
    its spares discarded, at this process's exit or by :func:`close_pool`.
    """
    global _pool, _registered
    with _pool_lock:
        if _pool is None:
            _pool = SparePool()
        if not _registered:
            atexit.register(close_pool)
            multiprocessing.util.Finalize(None, close_pool, exitpriority=100)  # pool workers exit without atexit
            _registered = True
        return _pool


def close_pool() -> None:
    """Close this process's pool, if open: every spare is discarded, nothing is pre-started any more."""
    global _pool
    with _pool_lock:
        closing, _pool = _pool, None
    if closing is not None:
        closing.close()
