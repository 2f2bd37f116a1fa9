"""Write the fixture inputs of one contract function for the kernel to read."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np


@dataclass(frozen=True)
class Ref:
    """The result of an earlier step of the same case."""

    step: int


@dataclass
class Step:
    """One call ``function(*args, **kwargs)`` in the student's kernel."""

    function: str
    args: tuple = ()
    kwargs: dict = field(default_factory=dict)


@dataclass
class Case:
    """One hidden input. The output checked is the result of the last step.

    Attributes
    ----------
    label : str
        Shown in feedback, e.g. ``"planar point set"``.
    steps : list of Step
        Usually one call; a step that uses a precomputation is ``[precompute(...), step(Ref(0), ...)]``.
    context : dict
        Grader-side data for verification and pictures; never sent to the kernel.
    """

    label: str
    steps: list[Step]
    context: dict = field(default_factory=dict)

    @classmethod
    def call(cls, label: str, function: str, *args, **kwargs) -> "Case":
        return cls(label, [Step(function, args, kwargs)])

    @property
    def function(self) -> str:
        return self.steps[-1].function

    def args(self, step: int = -1) -> tuple:
        return self.steps[step].args


def _encode(value: Any, arrays: dict[str, np.ndarray]) -> dict:
    if isinstance(value, Ref):
        return {"ref": value.step}
    if isinstance(value, np.ndarray):
        key = f"a{len(arrays)}"
        arrays[key] = np.array(value, order="C")  # not ascontiguousarray: it makes 0-d arrays 1-d
        return {"a": key}
    if isinstance(value, list):
        return {"list": [_encode(v, arrays) for v in value]}
    if isinstance(value, tuple):
        return {"tuple": [_encode(v, arrays) for v in value]}
    if isinstance(value, (np.integer, np.floating)):
        value = value.item()
    if value is None or isinstance(value, (bool, int, float, str)):
        return {"v": value}
    raise TypeError(f"cannot send a {type(value).__name__} to the kernel")


def write_fixtures(function: str, cases: list[Case], directory: Path, record: dict | None = None) -> None:
    """Write ``directory/<function>.json`` and ``.npz`` describing ``cases``.

    ``record`` is what the collector records of the other course functions the
    student's function calls (``grader.checks.callees.record_plan``).
    """
    arrays: dict[str, np.ndarray] = {}
    manifest = {
        "function": function,
        "record": record or {},
        "cases": [
            {
                "label": case.label,
                "steps": [
                    {
                        "function": s.function,
                        "args": [_encode(a, arrays) for a in s.args],
                        "kwargs": {k: _encode(v, arrays) for k, v in s.kwargs.items()},
                    }
                    for s in case.steps
                ],
            }
            for case in cases
        ],
    }
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    np.savez(directory / f"{function}.npz", **arrays)
    (directory / f"{function}.json").write_text(json.dumps(manifest))
