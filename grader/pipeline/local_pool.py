"""Grading units in a local process pool, with a worker's death costing only the unit that caused it."""

from __future__ import annotations

import multiprocessing
import os
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from typing import TYPE_CHECKING

from grader.pipeline.unit import UnitSpec, grade_unit
from grader.pipeline.workers import init_worker
from grader.sandbox.process_limit import remove_stale_limits
from grader.sandbox.workspace import remove_stale_workspaces

if TYPE_CHECKING:
    from grader.pipeline.plan import PlannedUnit

__all__ = ["grade_in_pool"]


def _pool(workers: int) -> ProcessPoolExecutor:
    # spawn, not fork: a forked child inherits jupyter's event-loop thread as a dead handle and hangs.
    return ProcessPoolExecutor(max_workers=workers, initializer=init_worker, initargs=(os.getpid(),), mp_context=multiprocessing.get_context("spawn"))


def grade_in_pool(
    todo: list[PlannedUnit],
    spec_of: Callable[[PlannedUnit], UnitSpec],
    error_of: Callable[[PlannedUnit, str], dict],
    workers: int,
    readonly: list[str],
    grade: Callable = grade_unit,
) -> Iterator[tuple[PlannedUnit, dict]]:
    """Grade ``todo`` in a local process pool; yield ``(unit, result)`` in order of completion.

    At most two units per worker are in flight, so the submitted bytes of a
    large class are never all in memory. If a grading worker dies (not a
    kernel: those are handled inside the unit), only a unit the pool held can
    have killed it: each of those is graded again alone, in a pool of its own,
    so that a culprit breaks only its own pool and its neighbours keep their grades.
    """
    remaining = dict(enumerate(todo))
    while remaining:
        queue = list(remaining)
        suspects: list[int] = []
        with _pool(workers) as pool:
            pending: dict = {}
            while queue or pending:
                while queue and len(pending) < 2 * workers and not suspects:
                    try:
                        pending[pool.submit(grade, spec_of(remaining[queue[0]]), readonly)] = queue[0]
                    except BrokenProcessPool:
                        # a worker died since the last wait: what is pending fails below,
                        # and the rest of the queue goes to the next pool
                        queue.clear()
                        break
                    queue.pop(0)
                if not pending:
                    break
                done, _ = wait(pending, return_when=FIRST_COMPLETED)
                for future in done:
                    i = pending.pop(future)
                    try:
                        result = future.result()
                    except BrokenProcessPool:
                        suspects.append(i)
                        continue
                    except Exception as exc:  # noqa: BLE001 - whatever one unit raised, the others are graded
                        result = error_of(remaining[i], f"grader error: {type(exc).__name__}: {exc}")
                    yield remaining.pop(i), result
        for i in suspects:
            unit = remaining.pop(i)
            yield unit, _grade_alone(unit, spec_of, error_of, readonly, grade)
        if suspects:
            remove_stale_workspaces()  # what the dead worker held (its locks name it: swept at once)
            remove_stale_limits()


def _grade_alone(unit: PlannedUnit, spec_of, error_of, readonly: list[str], grade) -> dict:
    """Grade one unit in a pool of its own; if that pool breaks too, the unit is the culprit."""
    with _pool(1) as pool:
        try:
            return pool.submit(grade, spec_of(unit), readonly).result()
        except BrokenProcessPool:
            return error_of(unit, "the grading process died while checking this notebook's outputs; it scores 0 and your TA has been told")
        except Exception as exc:  # noqa: BLE001
            return error_of(unit, f"grader error: {type(exc).__name__}: {exc}")
