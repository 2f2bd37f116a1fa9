"""Execution time of each instructor notebook with the reference solution, pictures on.

Target (issue 3): each notebook <= 20 s wall on 2 cores, the set <= 90 s.
"""

from __future__ import annotations

import os
import tempfile
import time
from pathlib import Path

import nbformat
from nbclient import NotebookClient

from grader.build.release import QUIET_KERNEL
from grader.build.source_notebook import build_sources
from grader.paths import course_paths


def main() -> dict:
    paths = course_paths()
    figures: dict = {}
    with tempfile.TemporaryDirectory(prefix="dl-bench-nb-") as tmp:
        sources = build_sources(paths.notebooks, Path(tmp), "deformation")
        os.environ["DEFORMLAB_NO_PLOTS"] = "0"  # as a student sees it
        total = 0.0
        for path in sources:
            nb = nbformat.read(path, as_version=4)
            start = time.perf_counter()
            NotebookClient(nb, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(path.parent)}},
                           extra_arguments=QUIET_KERNEL).execute()
            seconds = time.perf_counter() - start
            total += seconds
            figures[f"{path.stem} (s)"] = seconds
            print(f"{path.stem:<22} {seconds:6.1f} s (target <= 20 s)")
        figures["all notebooks (s)"] = total
        print(f"{'all notebooks':<22} {total:6.1f} s (target <= 90 s)")
    return figures


if __name__ == "__main__":
    main()
