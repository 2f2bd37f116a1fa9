"""``deformlab demo``: release the assignment, grade a small synthetic class, print the table.

The class (in ``OUT/submitted``) hands in all six notebooks per student:

- ``reference``: the instructor notebooks with their solutions, as a student would submit them;
- three students with one realistic bug each and a cheater who monkeypatches
  numpy, from the corpus in ``tests/corpus`` (the reference for their other notebooks);
- ``blank``: the release notebooks untouched.

It runs from a checkout: the corpus files live in ``tests/``.
"""

from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path

import nbformat

from grader.contract import ASSIGNMENT
from grader.corpus import CorpusEntry, build_submission, load_entry, student_notebook
from grader.paths import course_paths
from grader.report.scores import score_table

#: Corpus entries of the demo class: three bugs in three stages and one cheat.
DEMO_ENTRIES = (
    "buggy/no_sign_correction",
    "buggy/cot_not_halved",
    "buggy/bbw_clip_unconstrained",
    "hostile/numpy_monkeypatched",
)


def demo_student_id(entry: CorpusEntry) -> str:
    return entry.name.replace("_", "-")


def build_class(submitted: Path, sources: list[Path], released: Path, entries: list[CorpusEntry]) -> list[str]:
    """Write the demo class into ``submitted``; returns the student ids in table order.

    Parameters
    ----------
    submitted : Path
        Emptied and refilled: ``submitted/<student>/deformation/<notebook>.ipynb``.
    sources : list of Path
        The instructor notebooks.
    released : Path
        Folder of the release (student) notebooks.
    entries : list of CorpusEntry
        One student each: the entry's notebook, the reference for the others.
    """
    shutil.rmtree(submitted, ignore_errors=True)
    reference = {p.stem: student_notebook(nbformat.read(p, as_version=4), {}) for p in sources}
    students = ["reference", *(demo_student_id(e) for e in entries), "blank"]
    for sid in students:
        (submitted / sid / ASSIGNMENT).mkdir(parents=True)
    for stem, nb in reference.items():
        nbformat.write(nb, submitted / "reference" / ASSIGNMENT / f"{stem}.ipynb")
        shutil.copy(released / f"{stem}.ipynb", submitted / "blank" / ASSIGNMENT / f"{stem}.ipynb")
    for entry in entries:
        for stem, nb in reference.items():
            if stem != entry.notebook:
                nbformat.write(nb, submitted / demo_student_id(entry) / ASSIGNMENT / f"{stem}.ipynb")
        build_submission(entry, sources[0].parent, submitted, demo_student_id(entry))
    return students


def run_demo(out: Path, workers: int | None = None) -> int:
    """Release, grade the demo class into ``out``, print the score table and where the reports are.

    Parameters
    ----------
    out : Path
        Output folder: ``submitted/``, ``grades.csv``, ``feedback/``, ``log.jsonl``, ``gradebook.db``.
    workers : int, optional
        Parallel notebooks (default: number of cores).

    Returns
    -------
    int
        0 on success, 1 if the release checks failed.
    """
    from grader.build.release import release
    from grader.pipeline.run import GradeOptions, grade_class
    from grader.report.class_report import collusion_of_run, write_class_report

    # nbgrader's gradebook runs this environment's `alembic` script by name
    os.environ["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}"
    out = Path(out).resolve()
    paths = course_paths()
    corpus = paths.root / "tests" / "corpus"
    if not corpus.is_dir():
        raise FileNotFoundError(f"the demo needs a checkout: no corpus at {corpus}")

    print("== release ==")
    report = release(execute=False, paths=paths)
    if not report.ok:
        return 1
    sources = paths.source_notebooks(ASSIGNMENT)
    entries = [load_entry(corpus / f"{name}.py") for name in DEMO_ENTRIES]
    students = build_class(out / "submitted", sources, paths.release / ASSIGNMENT, entries)

    print("\n== the class ==")
    print("  reference: the instructor solutions; blank: the release notebooks as handed out")
    for entry in entries:
        print(f"  {demo_student_id(entry)}: {entry.notebook}: {entry.description}")

    print("\n== grading ==")
    db = out / "gradebook.db"
    results = grade_class(out / "submitted", out, GradeOptions(workers=workers, db_url=f"sqlite:///{db}"))

    print("\n== scores (autograded points; short answers are graded by hand in formgrader) ==")
    print(score_table(results, students, [p.stem for p in sources]))
    print("\n== reports ==")
    evidence = collusion_of_run(out, out / "submitted", ASSIGNMENT, sources)
    print(f"  class report: {write_class_report(out, collusion=evidence)} ({evidence.summary()})")
    print(f"  grades:    {out / 'grades.csv'}")
    print(f"  feedback:  {out / 'feedback'}/<student>/<notebook>.html")
    print(f"  log:       {out / 'log.jsonl'}")
    print(f"  gradebook: sqlite:///{db}")
    print(f"  executed notebooks: {paths.course / 'autograded'}/<student>/{ASSIGNMENT}/")
    return 0
