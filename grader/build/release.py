"""``deformlab release``: build, generate the student version, bundle it, and prove it is sound.

Checks, each failing the release loudly:

1. the source notebooks execute top to bottom (their hidden sections run the
   trusted checks, which compare the teaching solutions with ``reference/`` on the
   hidden cases) and, graded by the real pipeline, the teaching solutions earn
   every point;
2. no release file contains reference code, teaching solutions, hidden tests or
   grader internals;
3. the release notebooks execute with the stubs, where only cells that use a
   contract function fail, every tests cell fails, and a blank submission scores 0;
4. every autograded cell has points and the stable ``grade_id`` ``test_<function>``;
5. the ungraded demo notebooks (``notebooks/demo_skinning``, ``notebooks/demo_arap``),
   shipped in the student bundle, run top to bottom and show their widget and animation;
6. every ``data/`` file and every document (``*.md``) a notebook or demo names is in the
   student bundle (``--no-execute`` makes this check too).
"""

from __future__ import annotations

import ast
import gc
import inspect
import json
import os
import contextlib
import functools
import io
import re
import shutil
import tempfile
import textwrap
import time
import tokenize
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

import jupytext
import nbformat

from grader.build.authored import read_authored, referenced_names, solution_body
from grader.build.quoted_measurements import unprinted_quotes
from grader.build.source_notebook import HIDDEN_MARKERS, authored_notebooks, build_sources
from grader.course_pack import Assignment, pack, packs
from grader.gradebook import generate_assignment
from grader.grade_ids import tested_function
from grader.paths import CoursePaths, course_paths

#: What a student installs; pinned at release time as constraints.txt pins it (see ``student_requirements``).
STUDENT_PACKAGES = ("numpy", "scipy", "libigl", "pyvista", "matplotlib", "pillow", "ipywidgets", "ipyevents", "jupyterlab",
                    "ipykernel", "nbclient", "nbformat")


def student_requirements(paths: CoursePaths) -> str:
    """The bundle's ``requirements.txt``: each package at the version ``constraints.txt`` pins, else at the one the release ran with.

    Students then compute with the numeric stack the grader checks them against.
    """
    from importlib.metadata import PackageNotFoundError, version

    pinned = {}
    constraints = paths.root / "constraints.txt"
    if constraints.is_file():
        for line in constraints.read_text().splitlines():
            name, sep, ver = line.split("#", 1)[0].strip().partition("==")
            if sep:
                pinned[name.lower().replace("_", "-")] = ver.strip()
    lines = []
    for name in STUDENT_PACKAGES:
        ver = pinned.get(name)
        if ver is None:
            try:
                ver = version(name)
            except PackageNotFoundError:
                raise ReleaseError(f"{name} is neither pinned in constraints.txt nor installed: cannot pin the bundle's requirements") from None
        lines.append(f"{name}=={ver}")
    return "# The versions this assignment was released and checked with (as constraints.txt pins them).\n" + "\n".join(lines) + "\n"


#: A local kernel's own notice about unencrypted TCP, printed at every start, is noise here.
QUIET_KERNEL = ["--IPKernelApp.log_level=ERROR"]




class ReleaseError(RuntimeError):
    """A release check failed."""


@dataclass
class ReleaseReport:
    problems: list[str] = field(default_factory=list)
    points: dict[str, float] = field(default_factory=dict)  # autograded points per notebook, as grades.csv counts them
    manual_points: dict[str, float] = field(default_factory=dict)  # points of the answers graded by hand in formgrader
    executed: bool = False  # whether the execution and grading checks ran
    timings: dict[str, float] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return not self.problems


_CHECKER_CALL = re.compile(r"^[\w, ]+ = (as_\w+|check_\w+)\(|^check_\w+\(")
#: A body's line shorter than this (whitespace collapsed) is too generic to count as a leak.
MIN_LEAK_CHARS = 30


def _normalized(line: str) -> str:
    """``line`` stripped, runs of whitespace as one space (markdown and reformatting change spacing only)."""
    return " ".join(line.split())


def _graded_names() -> frozenset[str]:
    """The graded functions of every assignment of the course."""
    return frozenset(n for course in packs().values() for n in course.function_names)


def _calls_a_contract_function(line: str) -> bool:
    """Whether ``line`` only calls one contract function on names and constants (``data = precompute(V, F, handles)``).

    Notebooks call graded functions everywhere by design; such a call says nothing about how they are computed.
    """
    try:
        tree = ast.parse(line)
    except SyntaxError:
        return False
    if len(tree.body) != 1 or not isinstance(tree.body[0], (ast.Assign, ast.Expr, ast.Return)):
        return False
    call = tree.body[0].value
    plain = (ast.Name, ast.Constant, ast.Attribute)
    return (
        isinstance(call, ast.Call) and isinstance(call.func, ast.Name) and call.func.id in _graded_names()
        and all(isinstance(a, plain) for a in call.args) and all(isinstance(k.value, plain) for k in call.keywords)
    )


def _without_comment(line: str) -> str:
    """``line`` without a trailing ``#`` comment (a quote of the code rarely quotes the comment)."""
    try:
        for token in tokenize.generate_tokens(io.StringIO(line).readline):
            if token.type == tokenize.COMMENT:
                return line[: token.start[1]].rstrip()
    except (tokenize.TokenError, SyntaxError):  # a line of a multi-line statement
        pass
    return line


def _distinctive_lines(text: str) -> set[str]:
    """Lines long and specific enough that finding one elsewhere means the code was copied (whitespace collapsed).

    A trailing comment is dropped. Trivial lines do not count: shorter than ``MIN_LEAK_CHARS``, comments, imports,
    docstring quotes, ``raise ValueError`` messages, calls of the public input
    checkers (``starter.validation``, shared with students on purpose) and lines
    that only call a contract function (``_calls_a_contract_function``).
    """
    lines = set()
    for line in text.splitlines():
        s = _without_comment(_normalized(line))
        if (len(s) >= MIN_LEAK_CHARS and not s.startswith(("#", "import ", "from ", '"""', "raise ValueError"))
                and not _CHECKER_CALL.match(s) and not _calls_a_contract_function(s)):
            lines.add(s)
    return lines


def public_lines(paths: CoursePaths) -> set[str]:
    """Every line of the course's public code (the Python files of ``course_files``), whitespace collapsed.

    Students get that code as it is, so a body's line it also holds (``F = np.asarray(F,
    dtype=np.int64)``) reveals nothing. Read from the course folder, never from the
    release being scanned.
    """
    return {_normalized(line) for path, _ in course_files(paths) if path.suffix == ".py" for line in path.read_text().splitlines()}


def _readable_text(text: str) -> str:
    """A notebook's code, markdown and text outputs as plain lines; any other text as it is."""
    try:
        nb = json.loads(text)
    except ValueError:
        return text
    if not isinstance(nb, dict) or not isinstance(nb.get("cells"), list):
        return text
    parts = []
    for cell in nb["cells"]:
        source = cell.get("source", "")
        parts.append("".join(source) if isinstance(source, list) else str(source))
        for out in cell.get("outputs", []):
            for value in [out.get("text", "")] + list(out.get("data", {}).values()):
                parts.append("".join(value) if isinstance(value, list) else str(value))
    return "\n".join(parts)


def reference_body(name: str, course: Assignment | None = None) -> str:
    """The body of the reference's graded function ``name`` (of ``course``, default the default assignment), after its docstring."""
    source = inspect.getsource((course or pack()).reference_function(name))
    func = ast.parse(textwrap.dedent(source)).body[0]
    first = func.body[1] if ast.get_docstring(func) is not None else func.body[0]
    return textwrap.dedent("\n".join(textwrap.dedent(source).splitlines()[first.lineno - 1 :]))


def teaching_bodies(assignment: str) -> dict[str, str]:
    """``"teaching <function> (<notebook>)"`` -> the body of every solution cell of the authored notebooks."""
    bodies = {}
    course = pack(assignment)
    for path in authored_notebooks(assignment):
        for cell in read_authored(path, course).cells:
            if cell.kind == "solution":
                bodies[f"teaching {cell.function} ({path.stem})"] = solution_body(cell.source)
            elif cell.kind == "exercise":
                bodies[f"exercise {cell.answer_id} ({path.stem})"] = solution_body(cell.source)
    return bodies


def scan_for_leaks(
    texts: dict[str, str], teaching: dict[str, str] | None = None, public: set[str] = frozenset(), course: Assignment | None = None
) -> list[str]:
    """Problems for every release text that holds solution code, hidden tests or grader internals.

    A text leaks a body when it holds one of the body's distinctive lines that
    public code does not also hold, anywhere in a line (a markdown hint may quote
    code inside a sentence), or two of its distinctive lines of any kind.

    Parameters
    ----------
    texts : dict
        Release file name -> its text.
    teaching : dict, optional
        Label -> body of a teaching solution (``teaching_bodies``); the bodies of
        ``reference/`` are always looked for.
    public : set of str, optional
        Lines students get as public code (``public_lines``).
    course : Assignment, optional
        Whose reference bodies are looked for (default: the default assignment's).
    """
    course = course or pack()
    solutions = {f"reference {name}": reference_body(name, course) for name in sorted(course.function_names)} | (teaching or {})
    bodies = {label: _distinctive_lines(body) for label, body in solutions.items()}
    forbidden = (*HIDDEN_MARKERS, "import reference", "from reference", "BEGIN SOLUTION", "END SOLUTION")
    problems = []
    for fname, text in texts.items():
        text = _readable_text(text)
        for marker in forbidden:
            if marker in text:
                problems.append(f"{fname} contains {marker!r}")
        flat = "\n".join(_normalized(line) for line in text.splitlines())
        for name, lines in bodies.items():
            found = sorted(line for line in lines if line in flat)
            secret = [line for line in found if line not in public]
            if secret or len(found) >= 2:
                problems.append(f"{fname} contains the code of {name}: {(secret or found)[0]!r} ({len(found)} lines)")
    return problems


def _execute(path: Path, env_extra: dict[str, str], timeout: float = 300) -> nbformat.NotebookNode:
    """Execute a notebook in a fresh (unsandboxed: it is our own code) kernel; errors are kept as outputs."""
    from nbclient import NotebookClient

    nb = nbformat.read(path, as_version=4)
    old = {k: os.environ.get(k) for k in env_extra}
    os.environ.update(env_extra)
    try:
        NotebookClient(
            nb, timeout=timeout, allow_errors=True, kernel_name="python3", resources={"metadata": {"path": str(path.parent)}},
            extra_arguments=QUIET_KERNEL,
        ).execute()
    finally:
        for k, v in old.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
        gc.collect()  # see grader.pipeline.execute: kernel clients must not be finalized inside ast.parse
    return nb


def _errors(nb) -> dict[int, str]:
    found = {}
    for i, cell in enumerate(nb.cells):
        for out in cell.get("outputs", []):
            if out.get("output_type") == "error":
                found[i] = f"{out.get('ename')}: {str(out.get('evalue'))[:300]}"
    return found


def check_source_execution(sources: list[Path], report: ReleaseReport, paths: CoursePaths) -> None:
    env = {"DEFORMLAB_NO_PLOTS": "1", "DEFORMLAB_ROOT": str(paths.root)}
    for path in sources:
        started = time.monotonic()
        nb = _execute(path, env)
        report.timings[f"source {path.stem}"] = time.monotonic() - started
        for i, why in _errors(nb).items():
            report.problems.append(f"source {path.name}, cell {i + 1} fails with the teaching solutions: {why}")
        # the prose's measured numbers, as this run of the experiments printed them
        report.problems += [f"source {path.name}: {why}" for why in unprinted_quotes(nb)]


def check_release_execution(released: list[Path], report: ReleaseReport, course: Assignment) -> None:
    env = {"DEFORMLAB_NO_PLOTS": "1"}
    for path in released:
        started = time.monotonic()
        nb = _execute(path, env)
        report.timings[f"release {path.stem}"] = time.monotonic() - started
        errors = _errors(nb)
        for i, cell in enumerate(nb.cells):
            if cell.cell_type != "code":
                continue
            meta = cell.metadata.get("nbgrader") or {}
            if meta.get("solution"):  # an exercise's stub raises until the student writes it
                uses_contract = str(meta.get("grade_id", "")).startswith("exercise_")
            else:
                uses_contract = bool(referenced_names(cell.source) & course.function_names)
            if meta.get("grade") and i not in errors:
                report.problems.append(f"release {path.name}: tests cell {meta.get('grade_id')} passes with the stubs (vacuous test)")
            elif i in errors and not uses_contract and not meta.get("grade"):
                report.problems.append(f"release {path.name}, cell {i + 1} fails although it uses no student function: {errors[i]}")


def check_grades(
    sources: list[Path], submission_dir: Path, expect_full: bool, report: ReleaseReport, label: str, paths: CoursePaths,
    assignment: str | None = None,
) -> None:
    """Grade ``submission_dir``'s notebooks with the real pipeline; full marks or zero expected."""
    from grader.pipeline.run import GradeOptions, grade_class

    assignment = pack(assignment).name
    with tempfile.TemporaryDirectory(prefix="dl-release-") as tmp:
        submitted = Path(tmp) / "submitted"
        target = submitted / label / assignment
        target.mkdir(parents=True)
        for src in sources:
            shutil.copy(submission_dir / src.name, target / src.name)
        started = time.monotonic()
        # grade_class prints a summary naming this scratch folder, which is deleted right after: keep it quiet.
        with contextlib.redirect_stdout(io.StringIO()):
            results = grade_class(
                submitted,
                Path(tmp) / "out",
                GradeOptions(db_url=f"sqlite:///{tmp}/gradebook.db", progress=False, autograded=Path(tmp) / "autograded",
                             assignment=assignment),
                paths,
            )
        report.timings[f"grade {label}"] = time.monotonic() - started
    for r in results:
        for t in r["tests"]:
            if expect_full and t["score"] < t["points"]:
                report.problems.append(f"the teaching solutions lose points on {r['notebook']}:{t['grade_id']}: {t['summary']}")
            if not expect_full and t["score"] > 0:
                report.problems.append(f"a blank submission earns {t['score']} on {r['notebook']}:{t['grade_id']}")


def _string_constants(source: str) -> set[str]:
    try:
        tree = ast.parse(source)
    except SyntaxError:
        return set()
    return {n.value for n in ast.walk(tree) if isinstance(n, ast.Constant) and isinstance(n.value, str)}


def _student_sources(paths: CoursePaths, course: Assignment) -> list[Path]:
    """The jupytext sources of every notebook students get: the pack's stages and its demos."""
    return [*authored_notebooks(course.name), *(paths.notebooks / d / f"{d}.py" for d in course.demos)]


def check_course_files(paths: CoursePaths, course: Assignment, report: ReleaseReport) -> None:
    """Every file of ``data/`` a notebook or demo names (``load_mesh("bar")``, ``"bar.npz"``) is shipped in the bundle.

    A notebook that loads a course file missing from the bundle fails for every
    student; this check needs no execution, so ``--no-execute`` makes it too.
    """
    shipped = set(course.data)
    files = {f.name: f for f in paths.data.iterdir() if f.is_file()} if paths.data.is_dir() else {}
    for path in _student_sources(paths, course):
        named = set()
        for cell in jupytext.read(path).cells:
            if cell.cell_type == "code":
                named |= _string_constants(cell.source)
        for name, f in sorted(files.items()):
            if (name in named or f.stem in named) and name not in shipped:
                report.problems.append(
                    f"{path.name} loads data/{name}, which the student bundle does not ship: "
                    f"add it to data in {course.folder / 'assignment.toml'}"
                )


#: A document a notebook's text names, e.g. ``LIBRARY_POLICY.md``.
_DOCUMENT = re.compile(r"(?<![\w./-])([\w.-]+\.md)\b")


def check_named_documents(paths: CoursePaths, course: Assignment, report: ReleaseReport) -> None:
    """Every document (``*.md``) a notebook or demo tells students to read is in the student bundle.

    The bundle holds ``README.md``, ``LIBRARY_POLICY.md``, the pack's contract and its
    ``[bundle] files``; a notebook that sends students to any other file sends them
    nowhere. Needs no execution, so ``--no-execute`` makes it too.
    """
    shipped = {"LIBRARY_POLICY.md", *(f.name for f in (course.contract, *course.bundle_files) if f is not None)}
    if course.readme is not None:
        shipped.add("README.md")
    for path in _student_sources(paths, course):
        named = {m.group(1) for cell in jupytext.read(path).cells for m in _DOCUMENT.finditer(cell.source)}
        for name in sorted(named - shipped):
            report.problems.append(
                f"{path.name} names {name}, which the student bundle does not ship: add it to [bundle] files "
                f"in {course.folder / 'assignment.toml'}, or name a document the bundle has ({', '.join(sorted(shipped))})"
            )


def check_points(sources: list[Path], report: ReleaseReport, course: Assignment) -> None:
    for path in sources:
        nb = nbformat.read(path, as_version=4)
        total = manual = 0.0
        for cell in nb.cells:
            meta = cell.metadata.get("nbgrader") or {}
            if meta.get("grade"):
                gid, points = meta.get("grade_id", ""), meta.get("points")
                if not points or points <= 0:
                    report.problems.append(f"{path.name}: graded cell {gid} has no points")
                if cell.cell_type == "code" and not tested_function(gid) in course.function_names:
                    report.problems.append(f"{path.name}: autograded cell has an unstable grade_id {gid!r}")
                if cell.cell_type == "code":
                    total += float(points or 0)
                else:
                    manual += float(points or 0)
        report.points[path.stem] = total
        report.manual_points[path.stem] = manual


def demo_notebook(paths: CoursePaths, name: str) -> nbformat.NotebookNode:
    """An ungraded demo, converted from its jupytext source ``notebooks/<name>/<name>.py``.

    It ships in the student bundle as ``<name>.ipynb``, not in
    ``release/<assignment>``: nbgrader rewrites that folder whenever its
    ``generate_assignment`` runs, as grading with a fresh gradebook does.
    """
    return jupytext.read(paths.notebooks / name / f"{name}.py")


def check_demo_execution(demo: nbformat.NotebookNode, report: ReleaseReport, name: str) -> None:
    """Run a demo top to bottom with pictures on, in a scratch folder (it writes a GIF where it runs)."""
    with tempfile.TemporaryDirectory(prefix="dl-demo-") as tmp:
        path = Path(tmp) / f"{name}.ipynb"
        nbformat.write(demo, path)
        started = time.monotonic()
        nb = _execute(path, {"DEFORMLAB_NO_PLOTS": "0"})
        report.timings[f"demo {name}"] = time.monotonic() - started
    for i, why in _errors(nb).items():
        report.problems.append(f"demo {name}.ipynb, cell {i + 1} fails: {why}")
    shown = {mime for cell in nb.cells for out in cell.get("outputs", []) for mime in out.get("data", {})}
    for mime, what in (("application/vnd.jupyter.widget-view+json", "the widget"), ("image/gif", "the animation")):
        if mime not in shown:
            report.problems.append(f"demo {name}.ipynb does not show {what} ({mime})")


def course_files(paths: CoursePaths, course: Assignment | None = None):
    """What students need beside the notebooks: ``starter/`` and the files of ``data/`` the course pack
    lists, the files :func:`write_bundle` puts in the student bundle.

    Yields
    ------
    (Path, Path)
        Each file and its path relative to the course kit.

    Raises
    ------
    ReleaseError
        If the pack lists a data file the course does not have.

    ``course`` defaults to the course's default assignment.
    """
    for f in sorted((paths.root / "starter").rglob("*")):
        if f.is_file() and "__pycache__" not in f.parts and f.suffix in (".py", ".md"):
            yield f, f.relative_to(paths.root)
    for name in (course or pack()).data:
        f = paths.data / name
        if not f.is_file():
            raise ReleaseError(f"{course.folder / 'assignment.toml'}: data lists {name!r}, which {paths.data} does not hold")
        yield f, f.relative_to(paths.root)


def add_course_files(paths: CoursePaths, assignment: str) -> None:
    """Copy :func:`course_files` into ``source/<assignment>/``.

    nbgrader's ``generate_assignment`` (``deformlab release``, formgrader's Generate button) copies
    them into the release, so its exchange hands them out with the notebooks as the student bundle
    does: a student who fetches the assignment on a JupyterHub gets ``starter/`` and ``data/`` next
    to the notebooks, which import them.
    """
    target = paths.source / assignment
    for folder in ("starter", "data"):
        shutil.rmtree(target / folder, ignore_errors=True)  # build output: no stale file survives
    for f, relative in course_files(paths, pack(assignment)):
        (target / relative).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(f, target / relative)


def _readable(name: str) -> zipfile.ZipInfo:
    """A zip entry written from memory, mode 0644 (``writestr`` with a bare name gives 0600, unreadable to a course's group)."""
    info = zipfile.ZipInfo(name, date_time=time.localtime()[:6])
    info.compress_type = zipfile.ZIP_DEFLATED
    info.external_attr = 0o100644 << 16
    return info


def student_library_policy(course: Assignment) -> str:
    """The bundle's ``LIBRARY_POLICY.md``: every graded function's row, from ``starter.library_policy``'s table."""
    from starter.library_policy import markdown

    return "# The library-call policy\n\n" + markdown(course.functions) + "\n"


def write_bundle(paths: CoursePaths, assignment: str) -> Path:
    """``dist/<assignment>-student.zip``: release notebooks, the demo, starter/, data/, requirements, README, self-check."""
    from grader import student_check

    course = pack(assignment)
    paths.dist.mkdir(exist_ok=True)
    target = paths.dist / f"{assignment}-student.zip"
    tmp = target.with_suffix(".zip.tmp")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        root = f"{assignment}"
        for nb in sorted((paths.release / assignment).glob("*.ipynb")):
            z.write(nb, f"{root}/{nb.name}")
        for name in course.demos:
            z.writestr(_readable(f"{root}/{name}.ipynb"), nbformat.writes(demo_notebook(paths, name)))
        for f, relative in course_files(paths, course):
            z.write(f, f"{root}/{relative}")
        for f in (course.contract, *course.bundle_files):
            if f is not None:
                z.write(f, f"{root}/{f.name}")
        z.writestr(_readable(f"{root}/requirements.txt"), student_requirements(paths))
        if course.readme is not None:
            z.write(course.readme, f"{root}/README.md")
        z.write(student_check.__file__, f"{root}/check_notebook.py")
        z.writestr(_readable(f"{root}/LIBRARY_POLICY.md"), student_library_policy(course))
    tmp.replace(target)
    return target


def release(assignment: str | None = None, execute: bool = True, paths: CoursePaths | None = None) -> ReleaseReport:
    """Build and check the release; print a report. See the module docstring for the checks."""
    paths = paths or course_paths()
    course = pack(assignment)
    assignment = course.name
    report = ReleaseReport()
    started = time.monotonic()
    say = functools.partial(print, flush=True)
    say("building the instructor notebooks and nbgrader's release ...")
    sources = build_sources(paths.source, assignment)
    add_course_files(paths, assignment)
    generate_assignment(paths, assignment)
    released = sorted((paths.release / assignment).glob("*.ipynb"))
    bundle = write_bundle(paths, assignment)

    say("scanning the release and the student bundle for leaks ...")
    texts = {f"release/{p.name}": p.read_text() for p in released}
    with zipfile.ZipFile(bundle) as z:
        for name in z.namelist():
            if name.endswith((".py", ".ipynb", ".md", ".txt")):
                texts[f"{bundle.name}:{name}"] = z.read(name).decode("utf-8", "replace")
    report.problems += scan_for_leaks(texts, teaching_bodies(assignment), public_lines(paths), course)
    check_points(sources, report, course)
    check_course_files(paths, course, report)
    check_named_documents(paths, course, report)
    if execute:
        steps = (
            ("executing the instructor notebooks", lambda: check_source_execution(sources, report, paths)),
            ("grading the teaching solutions (they must earn every point)",
             lambda: check_grades(sources, paths.source / assignment, True, report, "teaching", paths, assignment)),
            ("executing the release notebooks with their stubs", lambda: check_release_execution(released, report, course)),
            ("grading the blank release (it must earn nothing)",
             lambda: check_grades(sources, paths.release / assignment, False, report, "blank", paths, assignment)),
        ) + tuple(
            (f"executing the demo {name}", lambda name=name: check_demo_execution(demo_notebook(paths, name), report, name))
            for name in course.demos
        )
        for k, (what, step) in enumerate(steps, 1):
            say(f"[{k}/{len(steps)}] {what} ...")
            step()
        report.executed = True
    report.timings["release total"] = time.monotonic() - started

    regular = [nb for nb in report.points if not course.is_bonus(nb)]
    say(f"  {'notebook':<22} {'autograded':>10} {'by hand':>8}")
    for nb, pts in report.points.items():
        say(f"  {nb:<22} {pts:10g} {report.manual_points[nb]:8g}" + ("  (bonus)" if course.is_bonus(nb) else ""))
    say(f"  {'total':<22} {sum(report.points[nb] for nb in regular):10g} {sum(report.manual_points[nb] for nb in regular):8g}"
        f"  + {sum(p for nb, p in report.points.items() if course.is_bonus(nb)):g} bonus")
    say("  (grades.csv holds the autograded points; the answers graded by hand are scored in formgrader)")
    for what, secs in report.timings.items():
        say(f"  {what:<28} {secs:6.1f} s")
    say(f"student bundle: {bundle.relative_to(paths.root)}")
    if report.problems:
        say(f"RELEASE CHECKS FAILED ({len(report.problems)}):")
        for p in report.problems:
            say(f"  - {p}")
    elif report.executed:
        say("release checks passed: nothing leaked, the teaching solutions earn every point, a blank submission earns none")
    else:
        say("release checks passed: nothing leaked, every graded cell has points. "
            "NOT checked (--no-execute): that the notebooks run, that the teaching solutions earn every point and a blank submission none")
    return report
