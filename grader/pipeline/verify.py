"""Step 4: hidden cases per graded function, and verdicts on the collected outputs.

Cases depend only on the run's seed and the function, so every student of a run
gets the same hidden inputs and the reference runs once per function per
process.
"""

from __future__ import annotations

import zlib
from dataclasses import dataclass
from typing import Any

import nbformat

from grader.checks import FunctionResult, all_checks, charge_policy, evaluate, record_plan, seeded_cases
from grader.checks.base import Case
from grader.grade_ids import tested_function
from grader.harness.outputs import Collected, OutputError


@dataclass(frozen=True)
class GradedCell:
    """An autograded tests cell of the source notebook."""

    grade_id: str
    function: str
    points: float


def graded_cells(source: nbformat.NotebookNode) -> list[GradedCell]:
    """The autograded tests cells of a source notebook, in order."""
    cells = []
    for cell in source.cells:
        meta = cell.metadata.get("nbgrader") or {}
        gid = meta.get("grade_id", "")
        function = tested_function(gid)
        if cell.cell_type == "code" and meta.get("grade") and function is not None:
            cells.append(GradedCell(gid, function, float(meta.get("points", 0))))
    return cells


def _seed(function: str, seed: int) -> tuple[int, int]:
    # the function's name mixed in, so that functions drawing the same kinds of input still get different ones
    return (seed, zlib.crc32(function.encode()))


def recording(function: str, seed: int, assignment: str | None = None) -> dict:
    """What the collector records of the course functions ``function`` calls (``grader.checks.record_plan``)."""
    return record_plan(function, _seed(function, seed), assignment)


def hidden_cases(function: str, seed: int, assignment: str | None = None) -> tuple[list[Case], list[Any]]:
    """The hidden cases of ``function`` for a run's ``seed`` and the reference's outputs on them.

    The function's name is mixed into the seed so that functions drawing the
    same kinds of input still get different ones.
    """
    return seeded_cases(function, _seed(function, seed), assignment)


def verify(function: str, seed: int, collected: Collected | None, failure: str | None, assignment: str | None = None) -> FunctionResult:
    """Verdicts for one function from what its collection produced.

    Parameters
    ----------
    collected : Collected or None
        The outputs read back, or None when collection failed (then ``failure`` says why).
    """
    cases, expected = hidden_cases(function, seed, assignment)
    if collected is None:
        return FunctionResult(function, error=failure or "no outputs")
    if len(collected.cases) != len(cases):
        raise OutputError(f"{function}: {len(collected.cases)} outputs for {len(cases)} cases")
    result = evaluate(all_checks(assignment)[function], cases, collected.cases, expected, _seed(function, seed))
    # the library-call policy (starter/library_policy.py): a forbidden routine scores the function 0
    return charge_policy(result, collected.policy_violations)
