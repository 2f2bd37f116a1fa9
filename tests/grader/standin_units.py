"""Work-unit stand-ins for the pool tests: importable by spawned workers, quick, and one that kills its worker."""

from __future__ import annotations

import os
import signal
import time

import nbformat

from grader.pipeline.unit import UnitSpec, zero_result

CULPRIT = "culprit"
CULPRITS_NOTEBOOK = "00_meshes"


def kills_its_worker_for_the_culprit(spec: UnitSpec, readonly: list[str] | None = None) -> dict:
    """Like ``grade_unit`` but instant; the culprit's unit SIGKILLs its worker, as the OOM killer would."""
    time.sleep(0.2)  # every worker holds a unit when the culprit's dies
    if (spec.student_id, spec.notebook) == (CULPRIT, CULPRITS_NOTEBOOK):
        os.kill(os.getpid(), signal.SIGKILL)
    source = nbformat.reads(spec.source, as_version=4)
    return zero_result(spec, source, "graded", "stand-in", time.monotonic()) | {"feedback_html": None, "autograded_notebook": None}
