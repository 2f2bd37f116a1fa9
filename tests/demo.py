"""``make demo`` (``python -m tests.demo``): release the assignment, grade a small synthetic class, print the table.

The class hands in every notebook of the assignment per student:

- ``reference``: the instructor notebooks with their solutions, as a student would submit them;
- three students with one realistic bug each and a cheater who monkeypatches
  numpy, from the corpus in ``tests/corpus`` (the reference for their other notebooks);
- ``blank``: the release notebooks untouched, handed in a day late.

The class goes where nbgrader's ``collect`` would put it (``assignments/submitted/<student>/deformation/``,
with ``timestamp.txt``) and is graded into the course's gradebook, with names and the demo's due date,
so formgrader, opened as the README says (``cd assignments && jupyter lab``), shows it: every
submission autograded, each tests cell with its verdicts, the written answers waiting for a TA.

It runs from a checkout, not from an installed kit: the class is made of the corpus in ``tests/corpus``.
"""

from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path

import nbformat

from grader.course_pack import default_assignment
from tests.corpus import CorpusEntry, build_submission, load_entry, student_notebook
from grader.paths import course_paths
from grader.report.scores import score_table

#: Corpus entries of the demo class: three bugs in three stages and one cheat.
DEMO_ENTRIES = (
    "buggy/no_sign_correction",
    "buggy/cot_not_halved",
    "buggy/bbw_clip_unconstrained",
    "hostile/numpy_monkeypatched",
)


#: The demo's due date and hand-in times (nbgrader's timestamp.txt format): ``blank`` is 26 hours late.
DEMO_DUE = "2026-11-20 23:59:00 UTC"
ON_TIME, LATE = "2026-11-20 18:00:00.000000 UTC", "2026-11-22 01:59:00.000000 UTC"
#: The demo's late policy: 10 % of a notebook's score per started day.
DEMO_LATE_FRACTION = 0.1


def demo_student_id(entry: CorpusEntry) -> str:
    return entry.name.replace("_", "-")


def build_class(submitted: Path, sources: list[Path], released: Path, entries: list[CorpusEntry]) -> list[str]:
    """Write the demo class into ``submitted`` as nbgrader's collect does; returns the student ids in table order.

    Parameters
    ----------
    submitted : Path
        ``submitted/<student>/deformation/<notebook>.ipynb`` and ``timestamp.txt``: the demo's
        students' folders are replaced, nobody else's is touched.
    sources : list of Path
        The instructor notebooks.
    released : Path
        Folder of the release (student) notebooks.
    entries : list of CorpusEntry
        One student each: the entry's notebook, the reference for the others.
    """
    reference = {p.stem: student_notebook(nbformat.read(p, as_version=4), {}) for p in sources}
    students = ["reference", *(demo_student_id(e) for e in entries), "blank"]
    for sid in students:
        shutil.rmtree(submitted / sid, ignore_errors=True)
        (submitted / sid / default_assignment()).mkdir(parents=True)
        (submitted / sid / default_assignment() / "timestamp.txt").write_text(LATE if sid == "blank" else ON_TIME)
    for stem, nb in reference.items():
        nbformat.write(nb, submitted / "reference" / default_assignment() / f"{stem}.ipynb")
        shutil.copy(released / f"{stem}.ipynb", submitted / "blank" / default_assignment() / f"{stem}.ipynb")
    for entry in entries:
        for stem, nb in reference.items():
            if stem != entry.notebook:
                nbformat.write(nb, submitted / demo_student_id(entry) / default_assignment() / f"{stem}.ipynb")
        build_submission(entry, sources[0].parent, submitted, demo_student_id(entry))
    return students


def show_in_formgrader(paths, out: Path, submitted: Path, db_url: str, students: list[str]) -> list[str]:
    """What formgrader needs beyond grades to show the demo class as a course's: names, the due date, the release.

    Every student gets a name (formgrader lists "last, first"), the due date and
    each submission's timestamp go to the gradebook with the demo's late policy
    (formgrader lists a submission as autograded when its timestamp there is the
    one in ``submitted/``), and the assignment is released to nbgrader's exchange
    where the course's configuration makes that possible (formgrader says
    "draft" until then). Returns what the TA should know, one line each.
    """
    from grader.late_policy import PerDayPenalty, apply_late_policy, parse_due
    from grader.pipeline import record

    with record.open_gradebook(db_url) as gb:
        for sid in students:
            gb.update_or_create_student(sid, first_name=sid, last_name="Demo")
    apply_late_policy(out, submitted, default_assignment(), parse_due(DEMO_DUE), PerDayPenalty(fraction_per_day=DEMO_LATE_FRACTION), db_url)
    return [_release_to_exchange(paths, db_url)]


def _release_to_exchange(paths, db_url: str) -> str:
    """``nbgrader release_assignment`` with the course's nbgrader_config.py, if its exchange can be written; what happened."""
    from nbgrader.apps import NbGraderAPI
    from nbgrader.coursedir import CourseDirectory
    from traitlets.config import Config
    from traitlets.config.loader import PyFileConfigLoader

    config = Config()
    if (paths.course / "nbgrader_config.py").is_file():
        config = PyFileConfigLoader("nbgrader_config.py", path=str(paths.course)).load_config()
    config.CourseDirectory.root = str(paths.course)
    config.CourseDirectory.db_url = db_url
    exchange = Path(config.Exchange.root) if "root" in config.Exchange else Path("/usr/local/share/nbgrader/exchange")
    if not (exchange.is_dir() and os.access(exchange, os.W_OK)):
        return (f"the assignment stays 'draft' in formgrader: nbgrader's exchange {exchange} is not a writable folder "
                f"(set c.Exchange.root, then: nbgrader release_assignment {default_assignment()})")
    api = NbGraderAPI(coursedir=CourseDirectory(config=config), config=config)
    result = api.release_assignment(default_assignment())
    if not result.get("success"):
        return f"nbgrader release_assignment failed, so the assignment stays 'draft': {(result.get('error') or '')[-300:]}"
    return f"released to nbgrader's exchange {exchange}: formgrader shows the assignment as released"


def run_demo(out: Path, workers: int | None = None) -> int:
    """Release, grade the demo class into ``out``, print the score table and where the reports are.

    Parameters
    ----------
    out : Path
        Output folder: ``grades.csv``, ``feedback/``, ``log.jsonl``, ``report/``; the class and the
        gradebook are the course's (``assignments/submitted``, ``assignments/gradebook.db``).
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
    sources = paths.source_notebooks(default_assignment())
    entries = [load_entry(corpus / f"{name}.py") for name in DEMO_ENTRIES]
    submitted = paths.course / "submitted"
    students = build_class(submitted, sources, paths.release / default_assignment(), entries)

    print("\n== the class ==")
    print(f"  reference: the instructor solutions; blank: the release notebooks as handed out, a day late (due {DEMO_DUE})")
    for entry in entries:
        print(f"  {demo_student_id(entry)}: {entry.notebook}: {entry.description}")

    print("\n== grading ==")
    db = paths.gradebook_url
    results = grade_class(submitted, out, GradeOptions(workers=workers, db_url=db))
    notes = show_in_formgrader(paths, out, submitted, db, students)

    print("\n== scores (autograded points; short answers are graded by hand in formgrader) ==")
    print(score_table(results, students, [p.stem for p in sources]))
    print("\n== reports ==")
    evidence = collusion_of_run(out, submitted, default_assignment(), sources)
    print(f"  class report: {write_class_report(out, collusion=evidence)} ({evidence.summary()})")
    print(f"  grades:    {out / 'grades.csv'}")
    print(f"  feedback:  {out / 'feedback'}/<student>/<notebook>.html")
    print(f"  log:       {out / 'log.jsonl'}")
    print(f"  gradebook: {db}")
    print(f"  executed notebooks: {paths.course / 'autograded'}/<student>/{default_assignment()}/")
    print(f"  formgrader: cd {paths.course} && jupyter lab, then Nbgrader > Formgrader (written answers wait for a TA there)")
    for note in notes:
        print(f"  {note}")
    return 0


def main(argv: list[str] | None = None) -> int:
    import argparse

    parser = argparse.ArgumentParser(prog="python -m tests.demo", description="release, grade a small synthetic class, print the table")
    parser.add_argument("--out", default="demo-out", help="output folder (default: demo-out)")
    parser.add_argument("--workers", type=int, default=None, help="parallel notebooks (default: number of cores)")
    args = parser.parse_args(argv)
    if args.workers is not None and args.workers < 1:
        parser.error(f"--workers must be at least 1, got {args.workers}")
    return run_demo(Path(args.out), workers=args.workers)


if __name__ == "__main__":
    raise SystemExit(main())
