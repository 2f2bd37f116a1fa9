"""Shared fixtures: the repository's paths and built instructor notebooks."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

# One BLAS thread per test process, set before anything imports numpy: `make test` runs one xdist
# worker per core, and a multi-threaded BLAS in each made them fight (an L-BFGS-B entry of the
# public-hints test: 14.7 CPU-s with threads, 8.8 without). Grading workers do the same (workers.py).
for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import pytest
from hypothesis import settings

import grader  # noqa: F401 - installs the finder of deformlab_packs.<pack>, which test modules import directly

os.environ.setdefault("DEFORMLAB_NO_PLOTS", "1")

# No test fails for being slow on a busy machine (Hypothesis's default deadline is 200 ms per example),
# and CI draws the same examples on every run: a red CI is a bug, never bad luck (a failing example
# found on a developer's machine is pinned with @example).
settings.register_profile("deformlab", deadline=None, print_blob=True)
settings.register_profile("ci", parent=settings.get_profile("deformlab"), derandomize=True)
settings.load_profile("ci" if os.environ.get("CI") else "deformlab")

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="session")
def repo_root() -> Path:
    return ROOT


@pytest.fixture(scope="session")
def source_notebooks(tmp_path_factory) -> dict[str, Path]:
    """The instructor notebooks, built from notebooks/ and reference/ into a temporary folder."""
    from grader.build.source_notebook import build_sources

    out = tmp_path_factory.mktemp("source")
    return {p.stem: p for p in build_sources(out, "deformation")}


# Keyed by the controlling pytest process: xdist workers are its children.
SUMMARIES = Path(tempfile.gettempdir()) / (
    f"deformlab-test-summaries-{os.getppid() if os.getenv('PYTEST_XDIST_WORKER') else os.getpid()}"
)


@pytest.fixture
def report_summary():
    """``report_summary(name, text)``: print ``text`` at the end of the run, also from an xdist worker."""

    def write(name: str, text: str) -> None:
        SUMMARIES.mkdir(exist_ok=True)
        (SUMMARIES / f"{name}.txt").write_text(text)

    return write


def pytest_terminal_summary(terminalreporter):
    if os.getenv("PYTEST_XDIST_WORKER") or not SUMMARIES.is_dir():
        return
    for path in sorted(SUMMARIES.glob("*.txt")):
        terminalreporter.section(path.stem)
        terminalreporter.write_line(path.read_text())
        path.unlink()
    SUMMARIES.rmdir()
