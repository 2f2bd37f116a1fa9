"""Fixtures for the grader's tests."""

from __future__ import annotations

import gc
import shutil
import tempfile
import time
from pathlib import Path

import pytest
from tests.course_copy import copy_course_config


@pytest.fixture
def tmp_path():
    """A short temporary folder.

    Kernels talk over Unix sockets inside their workdir, and a socket path has
    at most 107 bytes; pytest's own tmp_path (with the xdist worker and the
    test's name in it) can be longer than that.
    """
    path = Path(tempfile.mkdtemp(prefix="dl-test-"))
    yield path
    shutil.rmtree(path, ignore_errors=True)


@pytest.fixture(autouse=True)
def collect_kernel_leftovers():
    """Finalize kernel clients between tests, never inside a later ``ast.parse``.

    CPython 3.11 raises "AST constructor recursion depth mismatch" when such
    finalizers run while the parser builds its tree (pytest parses lazily imported
    modules, the grader parses cells). What survives is frozen, so that the next
    collection walks only what the next test made: a full walk of the heap (libigl,
    the reference's cached outputs) took 0.15 s after each of a thousand tests.
    """
    yield
    gc.collect()
    gc.freeze()


@pytest.fixture(scope="session")
def host_cmdlines():
    """``host_cmdlines() -> list[bytes]``: the raw command line of every process on the host.

    A process that has just been started can show an empty command line:
    ``Popen`` returns once ``exec`` has passed its point of no return, a moment
    before the kernel has set up the new program's arguments. Wait for it with
    :func:`started`.
    """

    def read() -> list[bytes]:
        found = []
        for entry in Path("/proc").iterdir():
            if entry.name.isdigit():
                try:
                    found.append((entry / "cmdline").read_bytes())
                except OSError:  # the process exited while we were scanning
                    pass
        return found

    return read


@pytest.fixture(scope="session")
def started(host_cmdlines):
    """``started(cmdline, timeout=10) -> bool``: whether a host process shows ``cmdline`` within ``timeout`` s."""

    def wait(cmdline: bytes, timeout: float = 10.0) -> bool:
        deadline = time.monotonic() + timeout
        while cmdline not in host_cmdlines():
            if time.monotonic() > deadline:
                return False
            time.sleep(0.02)
        return True

    return wait


@pytest.fixture(scope="session")
def make_course(source_notebooks):
    """``make_course(folder) -> Path``: a course kit whose ``assignments/`` is private to the test.

    ``data/``, ``starter/`` and ``notebooks/`` are the checkout's (symlinked); the
    instructor notebooks and ``nbgrader_config.py`` are copied, so grading builds
    nothing and writes nothing into the checkout.
    """
    checkout = Path(__file__).resolve().parents[2]

    def make(folder: Path) -> Path:
        root = Path(folder) / "course"
        source = root / "assignments" / "source" / "deformation"
        source.mkdir(parents=True)
        for name in ("data", "starter", "notebooks"):
            (root / name).symlink_to(checkout / name)
        for path in source_notebooks.values():
            shutil.copy(path, source / path.name)
        copy_course_config(root / "assignments")
        return root

    return make
