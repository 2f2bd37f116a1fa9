"""The ``deformlab`` command: build, release, grade, gradescope, check, demo."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from grader.sandbox.process_limit import DEFAULT_MAX_PROCESSES

if TYPE_CHECKING:
    from grader.pipeline.run import GradeOptions

#: GiB of address space below which no kernel starts.
MIN_MEMORY_GIB = 0.5

DESCRIPTION = """\
DeformLab's course kit: build and release the notebooks, grade submissions in a sandbox.

A first run (from a checkout, `make demo` grades a small synthetic class first):
  deformlab release                       build, release and check the student notebooks
  deformlab grade SUBMITTED --out OUT     grade nbgrader's SUBMITTED/<student>/<assignment>/*.ipynb

'deformlab COMMAND --help' explains each command."""


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be a positive integer, got {text!r}")
    return value


def _non_negative_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = -1
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be a whole number of 0 or more, got {text!r}")
    return value


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not value > 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"must be a positive number, got {text!r}")
    return value


def _memory_gib(text: str) -> float:
    value = _positive_float(text)
    if value < MIN_MEMORY_GIB:
        # Below this, python + numpy cannot start and every notebook would be a grader error.
        raise argparse.ArgumentTypeError(f"a kernel needs at least {MIN_MEMORY_GIB:g} GiB, got {text!r}")
    return value


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("deformlab")
    except PackageNotFoundError:  # run from a checkout that was never installed
        return "unknown (not installed)"


def _cmd_build(args) -> int:
    from grader.build.release import add_course_files
    from grader.build.source_notebook import build_sources
    from grader.paths import course_paths

    paths = course_paths()
    for path in build_sources(paths.source, args.assignment):
        print(f"wrote {path.relative_to(paths.root)}")
    add_course_files(paths, args.assignment)
    print(f"copied starter/ and data/ into {(paths.source / args.assignment).relative_to(paths.root)}/ (released with the notebooks)")
    return 0


def _cmd_release(args) -> int:
    from grader.build.release import release

    return 0 if release(assignment=args.assignment, execute=not args.no_execute).ok else 1


def _late_policy(args):
    """(due date, plugin, late-day budget) of a grade run: the flags, else the course's gradebook and nbgrader_config.py."""
    from grader import late_policy
    from grader.paths import course_paths

    try:
        paths = course_paths()
    except FileNotFoundError:  # grading itself says so
        paths = None
    db = args.db or (paths.gradebook_url if paths is not None and (paths.course / "gradebook.db").is_file() else None)
    due = late_policy.parse_due(args.due) if args.due else (late_policy.gradebook_due(db, args.assignment) if db else None)
    if due is None:
        if args.late_policy is not None or args.late_days is not None:
            raise ValueError(f"--{'late-policy' if args.late_policy is not None else 'late-days'} needs a due date: --due, "
                             f"or the gradebook's (nbgrader db assignment add {args.assignment} --duedate=...)")
        return None, None, 0
    config = paths.course / "nbgrader_config.py" if paths is not None else None
    budget = args.late_days if args.late_days is not None else late_policy.configured_late_days(config)
    if args.late_policy is not None:
        return due, late_policy.make_plugin(args.late_policy), budget
    return due, late_policy.configured_plugin(config), budget


def grade_options(args) -> GradeOptions:
    """``deformlab grade``'s options: its flags, else the course's ``c.Grading.*`` settings, else the defaults."""
    from grader.paths import course_paths
    from grader.pipeline.run import GradeOptions
    from grader.settings import grading_settings

    configured = grading_settings(course_paths().course)

    def given(flag, setting):
        return setting if flag is None else flag

    return GradeOptions(
        workers=given(args.workers, configured.workers or None),
        timeout=given(args.timeout, configured.cell_timeout),
        memory_gb=given(args.memory, configured.memory_gib),
        max_processes=given(args.max_processes, configured.max_processes),
        db_url=args.db,
        seed=args.seed,
        assignment=args.assignment,
        wall=given(args.wall, configured.notebook_wall),
        disk_bytes=given(args.disk, configured.disk_mib) * 2**20,
        student=args.student,
        scheduler=args.scheduler,
        allow_unsandboxed=args.allow_unsandboxed,
    )


def _cmd_grade(args) -> int:
    from grader.pipeline.run import grade_class
    from grader.paths import course_paths
    from grader.report.class_report import collusion_of_run, write_class_report
    from grader.report.scores import class_summary

    options = grade_options(args)
    due, plugin, late_days = _late_policy(args)
    from grader.late_policy import apply_late_policy, keep_late_columns, previous_late_columns

    # A --student run keeps everybody else's late columns as it keeps their scores.
    previous = previous_late_columns(Path(args.out)) if args.student is not None else None
    results = grade_class(Path(args.submitted), Path(args.out), options)
    if due is None and previous:  # no due date this time: the late columns stay as the last run wrote them
        keep_late_columns(Path(args.out), previous)
    if due is not None:
        late = apply_late_policy(Path(args.out), Path(args.submitted), args.assignment, due, plugin,
                                 args.db or course_paths().gradebook_url, late_days=late_days, only=args.student, previous=previous)
        late = {s: t for s, t in late.items() if t.seconds_late > 0}
        print(f"late: {len(late)} student(s) submitted after {due:%Y-%m-%d %H:%M} UTC (extensions included)"
              + (f"; late days spent (budget {late_days}): " + ", ".join(f"{s!r} {t.late_days}" for s, t in sorted(late.items())[:20])
                 if late and late_days else "")
              + ("; penalties (points): " + ", ".join(f"{s!r} {t.penalty:g}" for s, t in sorted(late.items())[:20]) if late else ""))
    print()
    print(class_summary(results))
    evidence = collusion_of_run(Path(args.out), Path(args.submitted), args.assignment, course_paths().source_notebooks(args.assignment))
    print(f"class report: {write_class_report(Path(args.out), collusion=evidence)} ({evidence.summary()})")
    errors = [r for r in results if r["status"] == "grader-error"]
    if errors:
        print(f"{len(errors)} notebook(s) could not be graded (grader-error, scored 0): see log.jsonl's reasons; "
              "a re-run into the same OUT grades only those again", file=sys.stderr)
        return 1
    return 0


def _cmd_report(args) -> int:
    from grader.paths import course_paths
    from grader.report.class_report import collusion_of_run, write_class_report

    evidence = None
    if args.submitted:
        evidence = collusion_of_run(Path(args.out), Path(args.submitted), args.assignment, course_paths().source_notebooks(args.assignment))
    page = write_class_report(Path(args.out), Path(args.to) if args.to else None, collusion=evidence)
    print(f"class report: {page}" + (f" ({evidence.summary()})" if evidence is not None else
                                     " (no collusion evidence: pass --submitted to compare the submissions)"))
    return 0


def _export_gradebook(args) -> dict:
    """The gradebook's submissions for an export (``--db``, else the course's SQLite if it exists), or {} with a warning."""
    from grader.exports.gradebook import read_gradebook
    from grader.paths import course_paths

    db = args.db
    if db is None:
        try:
            paths = course_paths()
        except FileNotFoundError:
            paths = None
        if paths is not None and (paths.course / "gradebook.db").is_file():
            db = paths.gradebook_url
    held = read_gradebook(db, args.assignment) if db else {}
    if not held:
        print(f"warning: no gradebook with {args.assignment!r} found (--db): points graded by hand in formgrader are not included",
              file=sys.stderr)
    return held


def _cmd_export(args) -> int:
    out = Path(args.out)
    if args.to == "nbgrader-feedback":
        from grader.exports.nbgrader_feedback import export_feedback
        from grader.paths import course_paths

        if not args.submitted:
            raise ValueError("--to nbgrader-feedback needs --submitted (the folder that was graded: its timestamp.txt files go along)")
        dest = Path(args.file) if args.file else course_paths().course / "feedback"
        held = _export_gradebook(args)
        if held and (out / "grades.csv").is_file():  # only students the gradebook holds as OUT graded them
            from grader.exports.lms import disagreements

            for sid in disagreements(out / "grades.csv", held):
                del held[sid]
        written, _ = export_feedback(out, Path(args.submitted), dest, args.assignment, held)
        pending = sum(s.ungraded for s in held.values())
        print(f"wrote {len(written)} feedback pages under {dest}/<student>/{args.assignment}/"
              + (f" ({pending} written answer(s) not graded by hand yet: export again once they are)" if pending else "")
              + f"; return them with: nbgrader release_feedback {args.assignment}")
        return 0
    from grader.exports.lms import canvas_csv, disagreements, moodle_csv, totals
    from grader.pipeline.record import write_text_atomic

    grades = out / "grades.csv"
    if not grades.is_file():
        raise FileNotFoundError(f"{out} is not the output folder of a grading run: it has no grades.csv")
    held = _export_gradebook(args)
    rows = totals(grades, held)
    differ = disagreements(grades, held)
    if differ:
        print(f"warning: the gradebook holds other notebooks or autograded points than {grades} for {len(differ)} student(s) "
              f"(e.g. {differ[0]!r}): was OUT graded into another gradebook (--db)? Their totals are grades.csv's, "
              "without grading by hand", file=sys.stderr)
    pending = sum(t.ungraded for t in rows)
    if pending:
        print(f"warning: {pending} written answer(s) are not graded by hand yet (formgrader): they count 0 for now",
              file=sys.stderr)
    name = args.column or args.assignment
    target = Path(args.file) if args.file else out / f"{args.to}.csv"
    if args.to == "canvas":
        text, unmatched = canvas_csv(rows, name, Path(args.roster) if args.roster else None)
        if unmatched:
            print(f"warning: {len(unmatched)} student(s) are not in the roster and were left out: {', '.join(unmatched[:10])}",
                  file=sys.stderr)
    else:
        notes = {t.student_id: t.note() for t in rows}
        text = moodle_csv(rows, name, feedback=notes if any(notes.values()) else None)
    write_text_atomic(target, text)
    print(f"wrote {target} ({len(rows)} students)")
    return 0


def _extension(args):
    """The extension the flags ask for: a duration, a new due date for this student, or None (--remove)."""
    from datetime import timedelta

    from grader import late_policy

    if args.remove or args.until is not None:
        if args.hours is not None:
            raise ValueError("--hours adds to --days; it does not go with --until or --remove")
    if args.remove:
        return None
    if args.until is not None:
        due = late_policy.gradebook_due(args.db, args.assignment)
        if due is None:
            raise ValueError(f"--until needs the assignment's due date in the gradebook (nbgrader db assignment add {args.assignment} --duedate=...)")
        until = late_policy.parse_due(args.until)
        if until <= due:
            raise ValueError(f"--until {args.until!r} is not after the assignment's due date ({due:%Y-%m-%d %H:%M} UTC)")
        return until - due
    extension = timedelta(days=args.days or 0, hours=args.hours or 0)
    if extension <= timedelta(0):
        raise ValueError("an extension needs --days, --hours or --until (or --remove to take one back)")
    return extension


def _cmd_extension(args) -> int:
    from grader import late_policy
    from grader.paths import course_paths

    args.db = args.db or course_paths().gradebook_url
    extension = _extension(args)
    for student in args.student:
        late_policy.grant_extension(args.db, args.assignment, student, extension)
    due = late_policy.gradebook_due(args.db, args.assignment)
    who = ", ".join(repr(s) for s in args.student)
    if extension is None:
        print(f"removed the extension of {who} on {args.assignment}")
    else:
        print(f"granted {who} an extension of {extension} on {args.assignment}"
              + (f": due for them {due + extension:%Y-%m-%d %H:%M} UTC" if due else " (the assignment has no due date yet)"))
    print("it applies at the next `deformlab grade` (--student ID regrades one student)")
    return 0


def _cmd_gradescope(args) -> int:
    from grader.gradescope import build_autograder_zip

    import secrets

    seed = secrets.randbits(32) if args.seed is None else args.seed
    path = build_autograder_zip(Path(args.out), seed=seed, assignment=args.assignment, allow_unsandboxed=args.allow_unsandboxed)
    print(f"wrote {path}; hidden-input seed {seed} (pass --seed {seed} to rebuild it without changing any student's inputs)")
    return 0


def _cmd_check(args) -> int:
    from grader.student_check import check_notebook

    return check_notebook(Path(args.notebook), timeout=args.timeout)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="deformlab", description=DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"%(prog)s {_version()}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    assignment_help = "nbgrader assignment name (default: the course's c.DeformLab.default_assignment, else its first course pack)"
    parser.add_argument(
        "--course",
        default=None,
        help="the course kit's folder (with data/, notebooks/, assignments/); default: see grader.paths.course_paths",
    )

    p = sub.add_parser("build", help="build the instructor notebooks (assignments/source) from notebooks/ and reference/")
    p.add_argument("--assignment", default=None, help=assignment_help)
    p.set_defaults(run=_cmd_build)

    p = sub.add_parser("release", help="build, generate the student release and bundle, and check that nothing leaked")
    p.add_argument("--assignment", default=None, help=assignment_help)
    p.add_argument("--no-execute", action="store_true", help="skip the execution checks (faster, for editing prose)")
    p.set_defaults(run=_cmd_release)

    p = sub.add_parser("grade", help="grade SUBMITTED/<student_id>/<assignment>/<notebook>.ipynb in a sandbox")
    p.add_argument("submitted", help="folder with one sub-folder per student")
    p.add_argument("--out", required=True, help="where grades.csv, feedback/ and log.jsonl go")
    # Defaults: c.Grading.* in the course's nbgrader_config.py (grader/settings.py), else the values shown.
    p.add_argument("--workers", type=_positive_int, default=None,
                   help="parallel notebooks (default: c.Grading.workers, else number of cores)")
    p.add_argument("--timeout", type=_positive_float, default=None,
                   help="seconds per cell before the kernel is killed (default: c.Grading.cell_timeout, else 60)")
    p.add_argument("--memory", type=_memory_gib, default=None, help="GiB of address space per kernel (default: c.Grading.memory_gib, else 4)")
    p.add_argument("--wall", type=_positive_float, default=None,
                   help="seconds a whole notebook may run, replays after restarts included (default: c.Grading.notebook_wall, else 900)")
    p.add_argument("--disk", type=_positive_int, default=None,
                   help="MiB each student's working folder may hold: a tmpfs, where the grader runs as root "
                        "(default: c.Grading.disk_mib, else 1024)")
    p.add_argument("--max-processes", type=_positive_int, default=None,
                   help=f"processes and threads a kernel may run at once, a pids cgroup where the host allows one "
                        f"(default: c.Grading.max_processes, else {DEFAULT_MAX_PROCESSES})")
    p.add_argument("--db", default=None, help="SQLAlchemy URL of the nbgrader gradebook (default: the course's SQLite)")
    p.add_argument("--seed", type=int, default=None, help="seed of the hidden inputs (default: fresh, recorded in the log)")
    p.add_argument("--assignment", default=None, help=assignment_help)
    p.add_argument("--due", default=None,
                   help="due date, e.g. '2026-11-20 23:59:00 Europe/Paris' (default: the gradebook's, set by "
                        "'nbgrader db assignment add ASSIGNMENT --duedate=...'); lateness is read from nbgrader's timestamp.txt")
    p.add_argument("--late-policy", default=None,
                   help="penalty per late notebook, as nbgrader's late-submission plugins: none, zero, "
                        "per-day:FRACTION (e.g. per-day:0.1), or module:Class of an nbgrader plugin "
                        "(default: the plugin nbgrader_config.py sets with c.AssignLatePenalties.plugin_class, "
                        "configured there, e.g. c.LateSubmissionPlugin.penalty_method = 'zero'; nbgrader's default is none)")
    p.add_argument("--late-days", type=_non_negative_int, default=None, metavar="N",
                   help="late days each student may spend across the course's assignments before any penalty "
                        "(default: c.LateDays.budget in nbgrader_config.py, else 0)")
    p.add_argument("--student", default=None, metavar="ID",
                   help="grade this student again (e.g. after a late submission); the others' results in OUT are kept as they are")
    p.add_argument(
        "--scheduler",
        default=None,
        help="grade on a Dask cluster: tcp://HOST:PORT of a running `dask scheduler`, or local:N worker processes here",
    )
    p.add_argument(
        "--allow-unsandboxed",
        action="store_true",
        help="let Dask workers without bubblewrap grade (without filesystem/network isolation); they refuse units otherwise",
    )
    p.set_defaults(run=_cmd_grade)

    p = sub.add_parser("report", help="write the class report (HTML with plots, and CSV) of a grading run")
    p.add_argument("out", help="the grading run's output folder (grade's --out)")
    p.add_argument("--to", default=None, help="where the report goes (default: OUT/report)")
    p.add_argument("--submitted", default=None, help="the SUBMITTED folder that was graded: adds collusion evidence")
    p.add_argument("--assignment", default=None, help=assignment_help)
    p.set_defaults(run=_cmd_report)

    p = sub.add_parser("export", help="grades for Canvas or Moodle (CSV), or feedback into nbgrader's feedback/ folder")
    p.add_argument("out", help="the grading run's output folder (grade's --out)")
    p.add_argument("--to", required=True, choices=("canvas", "moodle", "nbgrader-feedback"), help="the target system")
    p.add_argument("--file", default=None,
                   help="where to write (default: OUT/canvas.csv, OUT/moodle.csv, or the course's feedback/ folder)")
    p.add_argument("--column", default=None,
                   help="the LMS's name of the assignment column, e.g. 'Deformation (12345)' for Canvas (default: the assignment)")
    p.add_argument("--roster", default=None, help="Canvas only: Canvas's gradebook export, to match students by SIS Login ID, SIS User ID or ID")
    p.add_argument("--submitted", default=None, help="nbgrader-feedback only: the SUBMITTED folder that was graded")
    p.add_argument("--db", default=None,
                   help="SQLAlchemy URL of the nbgrader gradebook whose hand grading (formgrader) the export includes "
                        "(default: the course's SQLite)")
    p.add_argument("--assignment", default=None, help=assignment_help)
    p.set_defaults(run=_cmd_export)

    p = sub.add_parser("extension", help="give students an extension on the assignment, in nbgrader's gradebook")
    p.add_argument("student", nargs="+", help="the students' nbgrader ids")
    when = p.add_mutually_exclusive_group()
    when.add_argument("--days", type=_positive_float, default=None, help="days added to the due date (with --hours: both)")
    when.add_argument("--until", default=None, help="the student's own due date, e.g. '2026-11-23 23:59:00 Europe/Paris'")
    when.add_argument("--remove", action="store_true", help="take the extension back")
    p.add_argument("--hours", type=_positive_float, default=None, help="hours added to the due date")
    p.add_argument("--db", default=None, help="SQLAlchemy URL of the nbgrader gradebook (default: the course's SQLite)")
    p.add_argument("--assignment", default=None, help=assignment_help)
    p.set_defaults(run=_cmd_extension)

    p = sub.add_parser("gradescope", help="build a Gradescope autograder zip")
    p.add_argument("--out", required=True, help="path of the zip to write")
    p.add_argument("--seed", type=int, default=None, help="the assignment's hidden-input seed (default: a fresh one, printed)")
    p.add_argument("--assignment", default=None, help=assignment_help)
    p.add_argument("--allow-unsandboxed", action="store_true",
                   help="grade even where bubblewrap cannot start (students' code then runs unconfined; default: refuse)")
    p.set_defaults(run=_cmd_gradescope)

    p = sub.add_parser("check", help="run a notebook's public tests and print a table per function")
    p.add_argument("notebook", help="the .ipynb file to check")
    p.add_argument("--timeout", type=_positive_float, default=120.0, help="seconds per cell (default: 120)")
    p.set_defaults(run=_cmd_check)

    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        if args.course:
            from grader.paths import use_course

            use_course(args.course)
        if getattr(args, "assignment", "") is None:
            from grader.course_pack import default_assignment

            args.assignment = default_assignment()
        return args.run(args)
    except KeyboardInterrupt:
        return 130
    except (ValueError, FileNotFoundError, RuntimeError) as exc:  # RuntimeError: GradingInProgress
        print(f"deformlab {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
