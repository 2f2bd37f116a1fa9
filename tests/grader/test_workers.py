"""A grading worker's set-up: its own module, which the pool and the Dask side import without importing each other."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

PIPELINE = Path(__file__).resolve().parents[2] / "grader" / "pipeline"


def _imported(path: Path) -> set[str]:
    """Every module a file imports, at its top or inside functions."""
    names = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            names |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module:
            names |= {node.module, *(f"{node.module}.{a.name}" for a in node.names)}
    return names


def test_the_dask_side_never_imports_the_run_which_imports_it():
    assert "grader.pipeline.distributed" in _imported(PIPELINE / "run.py")
    assert not {n for n in _imported(PIPELINE / "distributed.py") if n.split(".")[:3] == ["grader", "pipeline", "run"]}


def test_the_worker_set_up_imports_neither_the_run_nor_the_dask_side():
    assert not {n for n in _imported(PIPELINE / "workers.py") if n.split(".")[:3] in (["grader", "pipeline", "run"], ["grader", "pipeline", "distributed"])}


def test_a_worker_whose_parent_is_already_gone_exits_at_once():
    # The parent-death signal cannot fire for a parent that died before it was armed: the worker checks.
    code = "from grader.pipeline.workers import init_worker\ninit_worker(1)\nprint('grading')\n"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert (done.returncode, done.stdout) == (1, "")
    code = "import os\nfrom grader.pipeline.workers import init_worker\ninit_worker(os.getppid())\nprint('grading')\n"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert (done.returncode, done.stdout) == (0, "grading\n"), done.stderr[-2000:]
