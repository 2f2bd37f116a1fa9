"""The ``deformlab`` command: build, release, grade, gradescope, check, demo."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from grader.contract import ASSIGNMENT
from grader.sandbox.process_limit import DEFAULT_MAX_PROCESSES


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be a positive integer, got {text!r}")
    return value


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("deformlab")
    except PackageNotFoundError:
        return "unknown (not installed)"


def _cmd_build(args) -> int:
    from grader.build.source_notebook import build_sources
    from grader.paths import course_paths

    paths = course_paths()
    for path in build_sources(paths.notebooks, paths.source, args.assignment):
        print(f"wrote {path.relative_to(paths.root)}")
    return 0


def _cmd_release(args) -> int:
    from grader.build.release import release

    return 0 if release(assignment=args.assignment, execute=not args.no_execute).ok else 1


def _cmd_grade(args) -> int:
    from grader.pipeline.run import GradeOptions, grade_class

    options = GradeOptions(
        workers=args.workers,
        timeout=args.timeout,
        memory_gb=args.memory,
        max_processes=args.max_processes,
        db_url=args.db,
        seed=args.seed,
        assignment=args.assignment,
        scheduler=args.scheduler,
        allow_unsandboxed=args.allow_unsandboxed,
    )
    grade_class(Path(args.submitted), Path(args.out), options)
    return 0


def _cmd_gradescope(args) -> int:
    from grader.gradescope import build_autograder_zip

    print(f"wrote {build_autograder_zip(Path(args.out))}")
    return 0


def _cmd_check(args) -> int:
    from grader.student_check import check_notebook

    return check_notebook(Path(args.notebook), timeout=args.timeout)


def _cmd_demo(args) -> int:
    from grader.demo import run_demo

    return run_demo(Path(args.out), workers=args.workers)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="deformlab", description=__doc__)
    parser.add_argument("--version", action="version", version=f"%(prog)s {_version()}")
    parser.add_argument(
        "--course",
        default=None,
        help="the course kit's folder (with data/, notebooks/, assignments/); default: see grader.paths.course_paths",
    )
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("build", help="build the instructor notebooks (assignments/source) from notebooks/ and reference/")
    p.add_argument("--assignment", default=ASSIGNMENT)
    p.set_defaults(run=_cmd_build)

    p = sub.add_parser("release", help="build, generate the student release and bundle, and check that nothing leaked")
    p.add_argument("--assignment", default=ASSIGNMENT)
    p.add_argument("--no-execute", action="store_true", help="skip the execution checks (faster, for editing prose)")
    p.set_defaults(run=_cmd_release)

    p = sub.add_parser("grade", help="grade SUBMITTED/<student_id>/<assignment>/<notebook>.ipynb in a sandbox")
    p.add_argument("submitted", help="folder with one sub-folder per student")
    p.add_argument("--out", required=True, help="where grades.csv, feedback/ and log.jsonl go")
    p.add_argument("--workers", type=int, default=None, help="parallel notebooks (default: number of cores)")
    p.add_argument("--timeout", type=float, default=60.0, help="seconds per cell before the kernel is killed")
    p.add_argument("--memory", type=float, default=4.0, help="GiB of address space per kernel")
    p.add_argument(
        "--max-processes",
        type=_positive_int,
        default=DEFAULT_MAX_PROCESSES,
        help="processes and threads a kernel may run at once (a pids cgroup, where the host allows one)",
    )
    p.add_argument("--db", default=None, help="SQLAlchemy URL of the nbgrader gradebook (default: the course's SQLite)")
    p.add_argument("--seed", type=int, default=None, help="seed of the hidden inputs (default: fresh, recorded in the log)")
    p.add_argument("--assignment", default=ASSIGNMENT)
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

    p = sub.add_parser("gradescope", help="build a Gradescope autograder zip")
    p.add_argument("--out", required=True)
    p.set_defaults(run=_cmd_gradescope)

    p = sub.add_parser("check", help="run a notebook's public tests and print a table per function")
    p.add_argument("notebook")
    p.add_argument("--timeout", type=float, default=120.0)
    p.set_defaults(run=_cmd_check)

    p = sub.add_parser("demo", help="release, grade a small synthetic class, print the table")
    p.add_argument("--out", default="demo-out")
    p.add_argument("--workers", type=int, default=None)
    p.set_defaults(run=_cmd_demo)

    args = parser.parse_args(argv)
    try:
        if args.course:
            from grader.paths import use_course

            use_course(args.course)
        return args.run(args)
    except KeyboardInterrupt:
        return 130
    except (ValueError, FileNotFoundError) as exc:
        print(f"deformlab {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
