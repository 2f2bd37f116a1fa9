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
   shipped in the student bundle, run top to bottom and show their widget and animation.
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

import nbformat

from grader.build.authored import read_authored, referenced_names, solution_body
from grader.build.source_notebook import HIDDEN_MARKERS, authored_notebooks, build_sources
from grader.contract import ASSIGNMENT, CONTRACT_NAMES, is_bonus, reference_function
from grader.paths import COURSE_ID, CoursePaths, course_paths

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


STUDENT_README = """# Deformation assignment

Eight notebooks, one per stage: `00_meshes` (warm-up), `01_shape_matching`,
`02_sign_correction`, `03_arap`, `04_bbw`, `05_lbs`, `06_fast` for bonus
points (ARAP in the skinning subspace), and `07_tetrahedra`, which takes the
lecture to volumes: finite elements and ARAP on tetrahedral meshes. In each, fill in one
function at a time where it says `YOUR CODE HERE`, then run the tests cell below
it: its messages say what is wrong.

## Install (once)

    python3 -m venv .venv
    .venv/bin/pip install -r requirements.txt
    .venv/bin/jupyter lab

Pictures render off screen; on a machine without OpenGL they fall back to
matplotlib with a one-line warning.

## Check your work

    .venv/bin/python check_notebook.py 03_arap.ipynb

runs the notebook top to bottom and prints, per function, whether its public
tests pass. Hidden tests on other inputs decide the grade, so passing the
public tests is necessary, not sufficient.

Keep `starter/` and `data/` next to the notebooks; do not rename the notebooks.

Grades measure your own work: `LIBRARY_POLICY.md` (and the top of each
notebook) lists the library routines each function may not use, because they
compute its answer. A function that calls one, even through a helper, scores 0;
its tests cell and `check_notebook.py` name the call.

`demo_skinning.ipynb` is not graded: libigl's demo 403 (pose a character with
sliders, linear blend skinning follows in real time, export the animation as a
GIF). Run it in JupyterLab after `05_lbs`. `demo_arap.ipynb` is not graded
either: libigl's tutorial 405 (drag the handles of a bar, ARAP follows in real
time); run it after `03_arap`.

When grading, your solution cells and the cells that only set things up run;
tests cells and cells that call the graded functions at top level (pictures,
experiments) do not. Keep everything a function needs inside the function or
in a cell that does not call a graded function.
"""


#: A local kernel's own notice about unencrypted TCP, printed at every start, is noise here.
QUIET_KERNEL = ["--IPKernelApp.log_level=ERROR"]


#: The ungraded demos in the student bundle: ``notebooks/<name>/<name>.py``, shipped as ``<name>.ipynb``.
DEMOS = ("demo_skinning", "demo_arap")
DEMO = DEMOS[0]


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


def generate_assignment(paths: CoursePaths, assignment: str, db_url: str | None = None) -> None:
    """Run nbgrader's own ``generate_assignment`` (release notebooks + gradebook entries)."""
    from nbgrader.apps import NbGraderAPI
    from nbgrader.coursedir import CourseDirectory
    from traitlets.config import Config

    config = Config()
    config.CourseDirectory.root = str(paths.course)
    config.CourseDirectory.db_url = db_url or paths.gradebook_url
    config.CourseDirectory.course_id = COURSE_ID
    api = NbGraderAPI(coursedir=CourseDirectory(config=config), config=config)
    result = api.generate_assignment(assignment, force=True, create=True)
    if not result.get("success"):
        log = (result.get("log") or "")[-4000:]
        raise ReleaseError(f"nbgrader generate_assignment failed:\n{log}\n{(result.get('error') or '')[-2000:]}")


_CHECKER_CALL = re.compile(r"^[\w, ]+ = (as_\w+|check_\w+)\(|^check_\w+\(")
#: A body's line shorter than this (whitespace collapsed) is too generic to count as a leak.
MIN_LEAK_CHARS = 30


def _normalized(line: str) -> str:
    """``line`` stripped, runs of whitespace as one space (markdown and reformatting change spacing only)."""
    return " ".join(line.split())


def _calls_a_contract_function(line: str) -> bool:
    """Whether ``line`` only calls one contract function on names and constants (``data = arap_precompute(V, F, h)``).

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
        isinstance(call, ast.Call) and isinstance(call.func, ast.Name) and call.func.id in CONTRACT_NAMES
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


def reference_body(name: str) -> str:
    """The body of ``reference``'s contract function ``name``, after its docstring."""
    source = inspect.getsource(reference_function(name))
    func = ast.parse(textwrap.dedent(source)).body[0]
    first = func.body[1] if ast.get_docstring(func) is not None else func.body[0]
    return textwrap.dedent("\n".join(textwrap.dedent(source).splitlines()[first.lineno - 1 :]))


def teaching_bodies(notebooks_dir: Path, assignment: str) -> dict[str, str]:
    """``"teaching <function> (<notebook>)"`` -> the body of every solution cell of the authored notebooks."""
    bodies = {}
    for path in authored_notebooks(notebooks_dir, assignment):
        for cell in read_authored(path).cells:
            if cell.kind == "solution":
                bodies[f"teaching {cell.function} ({path.stem})"] = solution_body(cell.source)
            elif cell.kind == "exercise":
                bodies[f"exercise {cell.answer_id} ({path.stem})"] = solution_body(cell.source)
    return bodies


def scan_for_leaks(texts: dict[str, str], teaching: dict[str, str] | None = None, public: set[str] = frozenset()) -> list[str]:
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
    """
    solutions = {f"reference {name}": reference_body(name) for name in sorted(CONTRACT_NAMES)} | (teaching or {})
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
        errors = _errors(_execute(path, env))
        report.timings[f"source {path.stem}"] = time.monotonic() - started
        for i, why in errors.items():
            report.problems.append(f"source {path.name}, cell {i + 1} fails with the teaching solutions: {why}")


def check_release_execution(released: list[Path], report: ReleaseReport) -> None:
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
                uses_contract = bool(referenced_names(cell.source) & CONTRACT_NAMES)
            if meta.get("grade") and i not in errors:
                report.problems.append(f"release {path.name}: tests cell {meta.get('grade_id')} passes with the stubs (vacuous test)")
            elif i in errors and not uses_contract and not meta.get("grade"):
                report.problems.append(f"release {path.name}, cell {i + 1} fails although it uses no student function: {errors[i]}")


def check_grades(sources: list[Path], submission_dir: Path, expect_full: bool, report: ReleaseReport, label: str, paths: CoursePaths) -> None:
    """Grade ``submission_dir``'s notebooks with the real pipeline; full marks or zero expected."""
    from grader.pipeline.run import GradeOptions, grade_class

    with tempfile.TemporaryDirectory(prefix="dl-release-") as tmp:
        submitted = Path(tmp) / "submitted"
        target = submitted / label / ASSIGNMENT
        target.mkdir(parents=True)
        for src in sources:
            shutil.copy(submission_dir / src.name, target / src.name)
        started = time.monotonic()
        # grade_class prints a summary naming this scratch folder, which is deleted right after: keep it quiet.
        with contextlib.redirect_stdout(io.StringIO()):
            results = grade_class(
                submitted,
                Path(tmp) / "out",
                GradeOptions(db_url=f"sqlite:///{tmp}/gradebook.db", progress=False, autograded=Path(tmp) / "autograded"),
                paths,
            )
        report.timings[f"grade {label}"] = time.monotonic() - started
    for r in results:
        for t in r["tests"]:
            if expect_full and t["score"] < t["points"]:
                report.problems.append(f"the teaching solutions lose points on {r['notebook']}:{t['grade_id']}: {t['summary']}")
            if not expect_full and t["score"] > 0:
                report.problems.append(f"a blank submission earns {t['score']} on {r['notebook']}:{t['grade_id']}")


def check_points(sources: list[Path], report: ReleaseReport) -> None:
    for path in sources:
        nb = nbformat.read(path, as_version=4)
        total = manual = 0.0
        for cell in nb.cells:
            meta = cell.metadata.get("nbgrader") or {}
            if meta.get("grade"):
                gid, points = meta.get("grade_id", ""), meta.get("points")
                if not points or points <= 0:
                    report.problems.append(f"{path.name}: graded cell {gid} has no points")
                if cell.cell_type == "code" and not (gid.startswith("test_") and gid[5:] in CONTRACT_NAMES):
                    report.problems.append(f"{path.name}: autograded cell has an unstable grade_id {gid!r}")
                if cell.cell_type == "code":
                    total += float(points or 0)
                else:
                    manual += float(points or 0)
        report.points[path.stem] = total
        report.manual_points[path.stem] = manual


def demo_notebook(paths: CoursePaths, name: str = DEMO) -> nbformat.NotebookNode:
    """An ungraded demo, converted from its jupytext source ``notebooks/<name>/<name>.py``.

    It ships in the student bundle as ``<name>.ipynb``, not in
    ``release/<assignment>``: nbgrader rewrites that folder whenever its
    ``generate_assignment`` runs, as grading with a fresh gradebook does.
    """
    import jupytext

    return jupytext.read(paths.notebooks / name / f"{name}.py")


def check_demo_execution(demo: nbformat.NotebookNode, report: ReleaseReport, name: str = DEMO) -> None:
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


def course_files(paths: CoursePaths):
    """What students need beside the notebooks: ``starter/`` and ``data/`` (code, meshes, READMEs), the
    files :func:`write_bundle` puts in the student bundle.

    Yields
    ------
    (Path, Path)
        Each file and its path relative to the course kit.
    """
    for folder in ("starter", "data"):
        for f in sorted((paths.root / folder).rglob("*")):
            if f.is_file() and "__pycache__" not in f.parts and f.suffix in (".py", ".npz", ".md"):
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
    for f, relative in course_files(paths):
        (target / relative).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(f, target / relative)


def _readable(name: str) -> zipfile.ZipInfo:
    """A zip entry written from memory, mode 0644 (``writestr`` with a bare name gives 0600, unreadable to a course's group)."""
    info = zipfile.ZipInfo(name, date_time=time.localtime()[:6])
    info.compress_type = zipfile.ZIP_DEFLATED
    info.external_attr = 0o100644 << 16
    return info


def student_library_policy() -> str:
    """The bundle's ``LIBRARY_POLICY.md``: every graded function's row, from ``starter.library_policy``'s table."""
    from grader.contract import STAGES, stage_functions
    from starter.library_policy import markdown

    functions = [f for stage in STAGES for f in stage_functions(stage)]
    return "# The library-call policy\n\n" + markdown(functions) + "\n"


def write_bundle(paths: CoursePaths, assignment: str) -> Path:
    """``dist/<assignment>-student.zip``: release notebooks, the demo, starter/, data/, requirements, README, self-check."""
    from grader import student_check

    paths.dist.mkdir(exist_ok=True)
    target = paths.dist / f"{assignment}-student.zip"
    tmp = target.with_suffix(".zip.tmp")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        root = f"{assignment}"
        for nb in sorted((paths.release / assignment).glob("*.ipynb")):
            z.write(nb, f"{root}/{nb.name}")
        for name in DEMOS:
            z.writestr(_readable(f"{root}/{name}.ipynb"), nbformat.writes(demo_notebook(paths, name)))
        for f, relative in course_files(paths):
            z.write(f, f"{root}/{relative}")
        z.writestr(_readable(f"{root}/requirements.txt"), student_requirements(paths))
        z.writestr(_readable(f"{root}/README.md"), STUDENT_README)
        z.write(student_check.__file__, f"{root}/check_notebook.py")
        z.writestr(_readable(f"{root}/LIBRARY_POLICY.md"), student_library_policy())
    tmp.replace(target)
    return target


def release(assignment: str = ASSIGNMENT, execute: bool = True, paths: CoursePaths | None = None) -> ReleaseReport:
    """Build and check the release; print a report. See the module docstring for the checks."""
    paths = paths or course_paths()
    report = ReleaseReport()
    started = time.monotonic()
    say = functools.partial(print, flush=True)
    say("building the instructor notebooks and nbgrader's release ...")
    sources = build_sources(paths.notebooks, paths.source, assignment)
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
    report.problems += scan_for_leaks(texts, teaching_bodies(paths.notebooks, assignment), public_lines(paths))
    check_points(sources, report)
    if execute:
        steps = (
            ("executing the instructor notebooks", lambda: check_source_execution(sources, report, paths)),
            ("grading the teaching solutions (they must earn every point)",
             lambda: check_grades(sources, paths.source / assignment, True, report, "teaching", paths)),
            ("executing the release notebooks with their stubs", lambda: check_release_execution(released, report)),
            ("grading the blank release (it must earn nothing)",
             lambda: check_grades(sources, paths.release / assignment, False, report, "blank", paths)),
        ) + tuple(
            (f"executing the demo {name}", lambda name=name: check_demo_execution(demo_notebook(paths, name), report, name))
            for name in DEMOS
        )
        for k, (what, step) in enumerate(steps, 1):
            say(f"[{k}/{len(steps)}] {what} ...")
            step()
        report.executed = True
    report.timings["release total"] = time.monotonic() - started

    regular = [nb for nb in report.points if not is_bonus(nb)]
    say(f"  {'notebook':<22} {'autograded':>10} {'by hand':>8}")
    for nb, pts in report.points.items():
        say(f"  {nb:<22} {pts:10g} {report.manual_points[nb]:8g}" + ("  (bonus)" if is_bonus(nb) else ""))
    say(f"  {'total':<22} {sum(report.points[nb] for nb in regular):10g} {sum(report.manual_points[nb] for nb in regular):8g}"
        f"  + {sum(p for nb, p in report.points.items() if is_bonus(nb)):g} bonus")
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
