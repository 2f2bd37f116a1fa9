"""The options of one grading run (``deformlab grade``'s flags, or ``c.Grading.*``: :func:`grader.cli.grade_options`)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from grader.sandbox.bwrap import DEFAULT_FILE_BYTES
from grader.sandbox.process_limit import DEFAULT_MAX_PROCESSES

__all__ = ["GradeOptions"]


@dataclass
class GradeOptions:
    workers: int | None = None
    timeout: float = 60.0
    memory_gb: float = 4.0
    max_processes: int = DEFAULT_MAX_PROCESSES
    db_url: str | None = None
    seed: int | None = None
    assignment: str | None = None  # None: the course's default assignment (c.DeformLab.default_assignment)
    progress: bool = True
    autograded: Path | None = None  # where executed notebooks go for formgrader; default: the course's autograded/
    wall: float = 900.0  # seconds per notebook
    disk_bytes: int = DEFAULT_FILE_BYTES  # each student's workdir
    student: str | None = None  # grade only this student again; the others' results are read from OUT as they are
    scheduler: str | None = None  # a Dask cluster: "tcp://HOST:PORT" or "local:N"; None: a local process pool
    allow_unsandboxed: bool = False  # Dask workers without bubblewrap grade anyway (they refuse units otherwise)
