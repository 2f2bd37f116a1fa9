"""Setting up a grading worker: a process that grades unit after unit for one grading run.

Both kinds of worker call :func:`init_worker` first: the local pool's processes
(``grader.pipeline.run``) and a Dask worker's grading processes
(``grader.pipeline.distributed``). A worker dies with the process that started
it, however that one ends (SIGKILL included), and takes what it started along:
its kernel template exits with it (:mod:`grader.sandbox.fork_server`), its
sandboxes die with it (bwrap ``--die-with-parent``), and the next run sweeps
its workspaces (:func:`grader.sandbox.workspace.remove_stale_workspaces`).
"""

from __future__ import annotations

import os

from grader.sandbox import spares
from grader.sandbox.lifetime import die_with_parent

__all__ = ["init_worker"]


def init_worker(parent: int | None = None) -> None:
    """Make this process a grading worker of its parent.

    Parameters
    ----------
    parent : int, optional
        The pid that started this process; default: its parent now. The worker
        gets SIGKILL when that process ends (it exits at once if it has already).
    """
    die_with_parent(os.getppid() if parent is None else parent)
    # Each worker is one of N parallel graders: one BLAS thread each keeps N cores busy, not N².
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[var] = "1"
    # A worker grades unit after unit: each next unit's sandbox boots while the last is verified.
    spares.open_pool()
