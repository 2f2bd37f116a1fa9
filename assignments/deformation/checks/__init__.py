"""The deformation course's hidden checks: one module per stage, one ``FunctionChecks`` per graded function.

The engine registers every ``FunctionChecks`` subclass of this package's modules
(``grader.checks.all_checks``), and reads ``BATCHED``, ``ALIASES`` and
``COMPOSITIONS`` here for its reruns (``grader.checks.callees``). Shared inputs
are drawn by :mod:`.generators`; verdicts more than one stage gives are in
:mod:`.verdicts`.
"""

from __future__ import annotations

from typing import Callable

import reference as _reference

from .callees import ALIASES, BATCHED, COMPOSITIONS

__all__ = ["ALIASES", "BATCHED", "COMPOSITIONS", "reference"]


def reference(name: str) -> Callable:
    """The reference implementation of graded function ``name`` (as the engine's reruns may substitute it)."""
    return getattr(_reference, name)
