"""Throughput of ``deformlab grade`` vs stock ``nbgrader autograde``, same class, same machine.

N correct submissions of the whole assignment (default 20; ``DEFORMLAB_BENCH_STUDENTS``)
are graded twice: by stock nbgrader, one student after another, and by
``deformlab grade`` (sandboxed, verified, ``--workers`` = cores). Target (issue 4):
throughput ratio >= 2x on 2 cores. Also printed: the per-notebook overhead of the
grading pipeline over the bare execution time of the student's functions.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import nbformat

from grader.build.authored import BEGIN_SOLUTION, END_SOLUTION
from grader.gradebook import generate_assignment
from grader.build.source_notebook import build_sources
from grader.paths import CoursePaths, course_paths
from grader.pipeline.run import GradeOptions, grade_class


def student_version(source: Path, release: Path) -> nbformat.NotebookNode:
    """The release notebook with every solution cell filled as a student would: reference code, no markers."""
    src = {c.metadata.get("nbgrader", {}).get("grade_id"): c for c in nbformat.read(source, as_version=4).cells}
    nb = nbformat.read(release, as_version=4)
    for cell in nb.cells:
        meta = cell.metadata.get("nbgrader") or {}
        if meta.get("solution") and cell.cell_type == "code":
            lines = src[meta["grade_id"]].source.splitlines()
            cell.source = "\n".join(l for l in lines if l.strip() not in (BEGIN_SOLUTION, END_SOLUTION))
    return nb


def main(students: int | None = None) -> dict:
    students = students or int(os.environ.get("DEFORMLAB_BENCH_STUDENTS", "20"))
    repo = course_paths()
    with tempfile.TemporaryDirectory(prefix="dl-bench-grade-") as tmp:
        root = Path(tmp)
        paths = CoursePaths(root)
        (root / "assignments").mkdir()
        # A course of its own (the checkout's notebooks, starter/, data/, reference/), so that both graders
        # grade the sources built here, never an instructor build left in the checkout.
        for name in ("notebooks", "starter", "data", "reference"):
            (root / name).symlink_to(repo.root / name)
        sources = build_sources(paths.source, "deformation")
        db = f"sqlite:///{root}/stock.db"
        generate_assignment(paths, "deformation", db)
        submitted = paths.course / "submitted"
        for k in range(students):
            target = submitted / f"student{k:02d}" / "deformation"
            target.mkdir(parents=True)
            for src in sources:
                nbformat.write(student_version(src, paths.release / "deformation" / src.name), target / src.name)
        (paths.course / "nbgrader_config.py").write_text(
            f"c = get_config()\nc.CourseDirectory.root = {str(paths.course)!r}\nc.CourseDirectory.db_url = {db!r}\n"
            "c.ExecutePreprocessor.timeout = 600\n"
        )
        from nbgrader.api import Gradebook

        with Gradebook(db) as gb:
            for k in range(students):
                gb.update_or_create_student(f"student{k:02d}")

        env = dict(os.environ, DEFORMLAB_ROOT=str(repo.root))
        start = time.perf_counter()
        proc = subprocess.run(
            [sys.executable, "-m", "nbgrader", "autograde", "deformation", "--force"],
            cwd=paths.course, env=env, capture_output=True, text=True,
        )
        stock = time.perf_counter() - start
        if proc.returncode != 0:
            print(proc.stderr[-3000:])
        ours_db = f"sqlite:///{root}/ours.db"
        start = time.perf_counter()
        results = grade_class(submitted, root / "out", GradeOptions(db_url=ours_db, seed=1, progress=False, autograded=root / "ours-autograded"),
                              paths=paths)
        ours = time.perf_counter() - start
        shutil.rmtree(paths.course / "autograded", ignore_errors=True)

    units = [r for r in results if r["status"].startswith("graded")]
    full = sum(r["score"] == r["max_score"] for r in units)
    function_s = [sum((c.get("seconds") or 0) for t in r["tests"] for c in t["cases"]) for r in units]
    mean_unit = sum(r["duration_s"] for r in units) / max(len(units), 1)
    mean_fn = sum(function_s) / max(len(function_s), 1)
    figures = {
        "students": students,
        "notebooks graded": len(results),
        "stock nbgrader autograde, sequential (s)": stock,
        "stock nbgrader exit code": proc.returncode,
        "deformlab grade, sandboxed, workers=cores (s)": ours,
        "throughput ratio (stock time / ours)": stock / ours,
        "notebooks with full marks (ours)": f"{full}/{len(units)}",
        "mean unit wall time (s)": mean_unit,
        "mean time in student functions per notebook (s)": mean_fn,
        "mean per-notebook overhead (s)": mean_unit - mean_fn,
    }
    for k, v in figures.items():
        print(f"{k:<52} {v:.3g}" if isinstance(v, float) else f"{k:<52} {v}")
    return figures


if __name__ == "__main__":
    main()
