"""DeformLab's instructor and TA tooling: build, release and grade (the ``deformlab`` command)."""

import os
import sys


def ensure_interpreter_bin_on_path() -> None:
    """Put this interpreter's ``bin/`` first on PATH.

    nbgrader runs ``alembic`` (and jupyter runs kernels) by name, which fails
    when the virtual environment is used without being activated.
    """
    bindir = os.path.dirname(sys.executable)
    if bindir not in os.environ.get("PATH", "").split(os.pathsep):
        os.environ["PATH"] = bindir + os.pathsep + os.environ.get("PATH", "")


ensure_interpreter_bin_on_path()

# Course packs' code imports as deformlab_packs.<assignment> (grader/course_pack.py installs the finder),
# also where a pickled check is loaded first: a grading or Dask worker.
from grader import course_pack as _course_pack  # noqa: E402,F401
