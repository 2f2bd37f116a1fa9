"""Turn an authored notebook into the nbgrader source (instructor) notebook.

Solution cells are the authored teaching solutions; tests cells get their
nbgrader grade metadata and a hidden section that runs the trusted checks of
``grader/checks`` against the notebook's own functions, so an instructor running
the source notebook sees the teaching solutions match ``reference/`` on the hidden
cases. The tests cell of a function graded in an earlier stage stays an ungraded
public check: a bug is charged once. The course's library policy
(``starter/library_policy.py``) follows the notebook's first text, with a cell that
installs its recorder, and every tests cell checks it (``watch`` ... ``verdict``).
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import nbformat

from grader.build.authored import AuthoredNotebook, AuthoringError, read_authored
from grader.course_pack import Assignment, pack
from grader.grade_ids import answer_grade_id, exercise_grade_id, public_check_id, solution_grade_id, tests_grade_id
from starter import library_policy

BEGIN_HIDDEN = "### BEGIN HIDDEN TESTS"
END_HIDDEN = "### END HIDDEN TESTS"
#: Text that only instructor material contains; the release scan looks for it.
HIDDEN_MARKERS = (BEGIN_HIDDEN, END_HIDDEN, "run_hidden_checks", "grader.checks")

KERNELSPEC = {"display_name": "Python 3 (ipykernel)", "language": "python", "name": "python3"}


def _nbgrader(grade_id: str, *, grade: bool, solution: bool, locked: bool, points: float | None = None) -> dict:
    meta = {"grade": grade, "grade_id": grade_id, "locked": locked, "schema_version": 3, "solution": solution}
    if points is not None:
        meta["points"] = points
    return {"nbgrader": meta}


def hidden_section(function: str, assignment: str) -> str:
    return "\n".join(
        [
            BEGIN_HIDDEN,
            "# Graded in the grading process on fresh hidden inputs (grader/checks); here the",
            "# same checks run against this notebook's functions.",
            "from grader.checks import run_hidden_checks as _run_hidden_checks",
            f"_hidden_result = _run_hidden_checks({function!r}, globals(), assignment={assignment!r})",
            END_HIDDEN,
        ]
    )


POLICY_INSTALL = (
    "# The course's library policy (above): this records calls of those routines made inside\n"
    "# your functions; each tests cell reports them. It never changes what a routine returns.\n"
    "from starter import library_policy\n"
    "\n"
    "library_policy.install()"
)


def policy_install(course: Assignment) -> str:
    """The cell that installs the library policy; a pack with its own ``[policy]`` declares its rows first."""
    if not course.policy:
        return POLICY_INSTALL
    own = {f: list(course.policy[f]) for f in course.functions}
    builds_on = {f: list(course.builds_on.get(f, ())) for f in course.functions}
    return POLICY_INSTALL.replace(
        "library_policy.install()",
        f"library_policy.declare(\n    {own!r},\n    {builds_on!r},\n)\nlibrary_policy.install()",
    )


def grading_rules(course: Assignment, notebook: str, functions: list[str]) -> str:
    """How the notebook's functions are graded: each on its own work (``grader/checks/callees.py``), once."""
    graded = set(course.stage_functions(notebook)) if notebook in course.stage_names else set(functions)
    copied = [f for f in functions if f not in graded]
    lines = [
        "**How your functions are graded.** Each function is graded on its own work, on hidden inputs.",
        "When one of your functions calls another function of the course, a mistake in the one it calls",
        "costs that function's points only: the grader records what your callee returned and judges the",
        "caller against the reference run on those same outputs. A bug is charged once.",
    ]
    if copied:
        lines.append(
            "The functions you copy over from an earlier stage ("
            + ", ".join(f"`{f}`" for f in copied)
            + ") earn no points here: they were graded in their own stage."
        )
    for f in functions:
        if f.endswith("_precompute") and f in graded:
            step = f.replace("_precompute", "_global_step")
            lines.append(
                f"What `{f}` returns is your own design: it is checked through your own `{step}`, and the"
                " functions that take it as input are graded with it, so a mistake in it (or in the global"
                " step) costs each of them."
            )
    return "\n".join(lines)


def policy_cells(course: Assignment, notebook: str, functions: list[str]) -> list[nbformat.NotebookNode]:
    """How the notebook is graded and its library policy (``starter.library_policy``'s table), and the cell that installs the policy."""
    text = grading_rules(course, notebook, functions) + "\n\n" + library_policy.markdown(functions)
    # the install cell's grade id is the notebook's own: a grade id shared by every notebook would
    # let another stage's notebook pass for this one (sanitize matches submissions by grade ids)
    return [nbformat.v4.new_markdown_cell(text), _provided_cell(policy_install(course), 0, salt=notebook)]


def with_policy_check(function: str, source: str) -> str:
    """A tests cell's source between the policy's ``watch`` and ``verdict`` for ``function``."""
    return (
        "from starter import library_policy as _library_policy\n\n"
        f"_library_policy.watch({function!r})  # the library policy: routines it may not use\n"
        f"{source.rstrip()}\n"
        f"_library_policy.verdict({function!r})"
    )


def _provided_cell(source: str, number: int, salt: str = "") -> nbformat.NotebookNode:
    digest = hashlib.sha1((salt + source).encode()).hexdigest()[:8]
    return nbformat.v4.new_code_cell(
        source, metadata=_nbgrader(f"provided_{number:02d}_{digest}", grade=False, solution=False, locked=True)
    )


def build_source_notebook(authored: AuthoredNotebook, course: Assignment | None = None) -> nbformat.NotebookNode:
    """Assemble the nbgrader source notebook of an authored notebook of ``course``.

    ``course`` defaults to the course's default assignment. Its metadata carry what grading reads from it: the assignment, whether its
    points are bonus, and every graded function of the assignment (cells that call
    one at top level are experiments, not run when grading).
    """
    course = course or pack()
    nb = nbformat.v4.new_notebook()
    nb.metadata["kernelspec"] = dict(KERNELSPEC)
    nb.metadata["language_info"] = {"name": "python"}
    nb.metadata["deformlab"] = {
        "notebook": authored.name,
        "assignment": course.name,
        "bonus": course.is_bonus(authored.name),
        "functions": sorted(course.function_names),
    }
    provided = 0
    functions = [c.function for c in authored.cells if c.kind == "solution"]
    for cell in authored.cells:
        if cell.kind == "text":
            nb.cells.append(nbformat.v4.new_markdown_cell(cell.source))
            if len(nb.cells) == 1:  # the policy follows the notebook's first text
                nb.cells += policy_cells(course, authored.name, functions)
        elif cell.kind == "answer":
            nb.cells.append(
                nbformat.v4.new_markdown_cell(
                    cell.source,
                    metadata=_nbgrader(answer_grade_id(cell.answer_id), grade=True, solution=True, locked=False, points=cell.points),
                )
            )
        elif cell.kind == "provided":
            provided += 1
            nb.cells.append(_provided_cell(cell.source, provided))
        elif cell.kind == "exercise":  # the student writes the part between the markers; nothing grades it
            nb.cells.append(
                nbformat.v4.new_code_cell(
                    cell.source,
                    metadata=_nbgrader(exercise_grade_id(cell.answer_id), grade=False, solution=True, locked=False),
                )
            )
        elif cell.kind == "solution":
            nb.cells.append(
                nbformat.v4.new_code_cell(
                    cell.source,
                    metadata=_nbgrader(solution_grade_id(cell.function), grade=False, solution=True, locked=False),
                )
            )
        elif cell.kind == "tests" and not cell.points:
            nb.cells.append(
                nbformat.v4.new_code_cell(
                    with_policy_check(cell.function, cell.source),
                    metadata=_nbgrader(public_check_id(cell.function), grade=False, solution=False, locked=True),
                )
            )
        elif cell.kind == "tests":
            source = with_policy_check(cell.function, cell.source) + "\n\n" + hidden_section(cell.function, course.name)
            nb.cells.append(
                nbformat.v4.new_code_cell(
                    source,
                    metadata=_nbgrader(tests_grade_id(cell.function), grade=True, solution=False, locked=True, points=cell.points),
                )
            )
    for i, c in enumerate(nb.cells):  # ids stable across builds, so diffs of the output stay small
        c["id"] = f"{authored.name}-{i:03d}"
    return nb


def authored_notebooks(assignment: str) -> list[Path]:
    """The authored notebooks (``NN_stage.py``) of ``assignment``'s stages, in teaching order.

    Only the stages the course includes (``c.DeformLab.stages``, else every stage of its pack).

    Raises
    ------
    AuthoringError
        If a stage has no authored notebook in the pack's notebooks folder.
    """
    course = pack(assignment)
    paths = [course.notebooks / f"{stage}.py" for stage in course.stage_names]
    missing = [p.name for p in paths if not p.is_file()]
    if missing or not paths:
        raise AuthoringError(f"{course.notebooks}: no authored notebook for stage(s) {missing or '(none declared)'} of {assignment}")
    return paths


def build_sources(source_dir: Path, assignment: str) -> list[Path]:
    """Write ``source_dir/<assignment>/NN_stage.ipynb`` for every authored notebook.

    Returns
    -------
    list of Path
        The notebooks written.
    """
    out_dir = Path(source_dir) / assignment
    out_dir.mkdir(parents=True, exist_ok=True)
    written = []
    course = pack(assignment)
    for path in authored_notebooks(assignment):
        nb = build_source_notebook(read_authored(path, course), course)
        target = out_dir / f"{path.stem}.ipynb"
        nbformat.write(nb, target)
        written.append(target)
    for stale in out_dir.glob("*.ipynb"):  # a stage the course no longer includes
        if stale not in written:
            stale.unlink()
    return written
