"""Read an authored notebook (``notebooks/<assignment>/NN_stage.py``) and enforce its rules.

Cell kinds come from the ``deformlab`` metadata on each ``# %%`` line
(``notebooks/README.md``): text, provided code, solution, tests, short answer,
exercise (ungraded code the student writes: an experiment's set-up).
A solution cell holds the teaching solution itself: the function, its docstring,
and its body between nbgrader's solution markers.
"""

from __future__ import annotations

import ast
import textwrap
from dataclasses import dataclass, field
from pathlib import Path

import jupytext

from grader.course_pack import Assignment, PackError, pack, pack_of_source

BEGIN_SOLUTION = "### BEGIN SOLUTION"
END_SOLUTION = "### END SOLUTION"


class AuthoringError(ValueError):
    """An authored notebook breaks a rule of notebooks/README.md."""


@dataclass
class AuthoredCell:
    kind: str  # "text" | "provided" | "solution" | "tests" | "answer" | "exercise"
    source: str
    function: str | None = None  # for solution and tests cells
    answer_id: str | None = None  # for answer and exercise cells
    points: float = 0.0  # 0 for the public checks of a function graded in an earlier stage


@dataclass
class AuthoredNotebook:
    path: Path
    cells: list[AuthoredCell]
    metadata: dict = field(default_factory=dict)

    @property
    def name(self) -> str:
        return self.path.stem

    @property
    def functions(self) -> list[str]:
        """Contract functions with a solution cell, in notebook order."""
        return [c.function for c in self.cells if c.kind == "solution"]


def top_level_definitions(source: str) -> set[str]:
    """Names a cell binds at top level (assignments, defs, classes, imports)."""
    names: set[str] = set()
    for node in ast.parse(source).body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            names.update((a.asname or a.name.split(".")[0]) for a in node.names)
        elif isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign, ast.For, ast.With)):
            for sub in ast.walk(node):
                if isinstance(sub, ast.Name) and isinstance(sub.ctx, ast.Store):
                    names.add(sub.id)
    return names


def referenced_names(source: str) -> set[str]:
    """Every name a cell reads anywhere in its code."""
    return {n.id for n in ast.walk(ast.parse(source)) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load)}


def earlier_stage(course: Assignment, notebook: str, function: str) -> str | None:
    """The stage that grades ``function`` if it is not ``notebook``'s own (a function the student copies over)."""
    if notebook not in course.stage_names or function in course.stage_functions(notebook):
        return None
    return course.stage_of(function)


def solution_body(source: str) -> str:
    """The code between a solution cell's markers (what a release must never contain)."""
    inside = source.split(BEGIN_SOLUTION, 1)[1].split(END_SOLUTION, 1)[0]
    return textwrap.dedent(inside.split("\n", 1)[1] if "\n" in inside else "")


def cell_starts(path: Path, n_cells: int) -> list[int | None]:
    """The file line (1-based) where each of the ``n_cells`` cells of a jupytext percent file begins its content.

    A cell's content starts on the first non-blank line after its ``# %%`` marker;
    None for every cell when the markers do not match the cells jupytext read.
    """
    lines = path.read_text(encoding="utf-8").splitlines()
    markers = [i for i, line in enumerate(lines) if line.startswith("# %%")]
    if len(markers) != n_cells:
        return [None] * n_cells
    starts = []
    for k, m in enumerate(markers):
        end = markers[k + 1] if k + 1 < len(markers) else len(lines)
        first = next((i for i in range(m + 1, end) if lines[i].strip()), m)
        starts.append(first + 1)
    return starts


def _where(path: Path, index: int, line: int | None, offset: int = 1) -> str:
    """``file:line`` (what an editor jumps to) and the cell's number; ``offset`` is a line inside the cell."""
    return f"{path}:{line + offset - 1} (cell {index + 1})" if line is not None else f"{path}, cell {index + 1}"


def check_solution_cell(source: str, name: str, where: str) -> None:
    """A solution cell is imports plus ``def name`` with a docstring, its body between the markers.

    Raises
    ------
    AuthoringError
        Naming the broken rule.
    """
    try:
        tree = ast.parse(source)
    except SyntaxError as exc:
        raise AuthoringError(f"{where}: syntax error: {exc.msg} (line {exc.lineno} of the cell)") from None
    others = [n for n in tree.body if not isinstance(n, (ast.Import, ast.ImportFrom, ast.FunctionDef))]
    defs = [n for n in tree.body if isinstance(n, ast.FunctionDef)]
    if others or [d.name for d in defs] != [name]:
        raise AuthoringError(f"{where}: the solution cell for {name} must hold only imports and def {name}(...)")
    func = defs[0]
    if ast.get_docstring(func) is None:
        raise AuthoringError(f"{where}: {name} needs a docstring (students see it in the release)")
    lines = source.splitlines()
    begin = [i for i, line in enumerate(lines) if line.strip() == BEGIN_SOLUTION]
    end = [i for i, line in enumerate(lines) if line.strip() == END_SOLUTION]
    if len(begin) != 1 or len(end) != 1 or begin[0] > end[0]:
        raise AuthoringError(f"{where}: the solution cell for {name} needs one {BEGIN_SOLUTION} ... {END_SOLUTION} pair")
    # Line numbers: begin/end are 0-based, the AST's 1-based. Every statement after the docstring is inside.
    after_doc = func.body[1:]
    if begin[0] < func.body[0].end_lineno or (after_doc and after_doc[0].lineno <= begin[0] + 1) or end[0] + 1 < func.end_lineno:
        raise AuthoringError(f"{where}: in {name}, the solution markers must enclose the whole body after the docstring")
    if not solution_body(source).strip():
        raise AuthoringError(f"{where}: the solution of {name} is empty")


def _classify(cell, index: int, path: Path, course: Assignment, line: int | None = None) -> AuthoredCell:
    meta = cell.metadata.get("deformlab") or {}
    where = _where(path, index, line)
    if cell.cell_type == "markdown":
        if "answer" in meta:
            points = float(meta.get("points", 0))
            if points <= 0:
                raise AuthoringError(f"{where}: a short-answer cell needs positive points")
            return AuthoredCell("answer", cell.source, answer_id=str(meta["answer"]), points=points)
        return AuthoredCell("text", cell.source)
    if "solution" in meta:
        name = meta["solution"]
        if name not in course.function_names:
            raise AuthoringError(f"{where}: solution cell names {name!r}, which is not a contract function")
        check_solution_cell(cell.source, name, where)
        return AuthoredCell("solution", cell.source, function=name)
    if "tests" in meta:
        name = meta["tests"]
        if name not in course.function_names:
            raise AuthoringError(f"{where}: tests cell names {name!r}, which is not a contract function")
        points = float(meta.get("points", 0))
        earlier = earlier_stage(course, path.stem, name)
        if earlier and points:
            raise AuthoringError(
                f"{where}: {name} is graded in {earlier}; its tests cell here takes no points (a bug is charged once)"
            )
        if not earlier and points <= 0:
            raise AuthoringError(f"{where}: the tests cell for {name} needs positive points")
        return AuthoredCell("tests", cell.source, function=name, points=points)
    if "exercise" in meta:
        lines = [line.strip() for line in cell.source.splitlines()]
        if lines.count(BEGIN_SOLUTION) != 1 or lines.count(END_SOLUTION) != 1 or not solution_body(cell.source).strip():
            raise AuthoringError(f"{where}: an exercise cell needs one non-empty {BEGIN_SOLUTION} ... {END_SOLUTION} pair")
        return AuthoredCell("exercise", cell.source, answer_id=str(meta["exercise"]))
    return AuthoredCell("provided", cell.source)


def read_authored(path: str | Path, course: Assignment | None = None) -> AuthoredNotebook:
    """Parse an authored notebook and check the rules of ``notebooks/README.md``.

    Parameters
    ----------
    path : path-like
        A jupytext percent-format ``.py`` file.
    course : Assignment, optional
        Its course pack (default: the pack whose notebooks folder holds ``path``, else the
        course's default assignment: a draft outside every pack is checked against it).

    Returns
    -------
    AuthoredNotebook

    Raises
    ------
    AuthoringError
        Naming the file, the cell and the broken rule.
    """
    path = Path(path)
    if course is None:
        try:
            course = pack_of_source(path)
        except PackError:
            course = pack()
    nb = jupytext.read(path)
    starts = cell_starts(path, len(nb.cells))
    cells = [_classify(c, i, path, course, starts[i]) for i, c in enumerate(nb.cells)]
    solved: set[str] = set()
    tested: set[str] = set()
    for i, cell in enumerate(cells):
        where = _where(path, i, starts[i])
        if cell.kind in ("text", "answer"):
            continue
        if cell.kind == "solution":
            if cell.function in solved:
                raise AuthoringError(f"{where}: a second solution cell for {cell.function}")
            solved.add(cell.function)
        try:
            used = referenced_names(cell.source)
            defined = top_level_definitions(cell.source)
        except SyntaxError as exc:
            raise AuthoringError(f"{_where(path, i, starts[i], exc.lineno or 1)}: syntax error: {exc.msg}") from None
        early = sorted((used & course.function_names) - solved)
        if early:
            raise AuthoringError(f"{where}: uses {', '.join(early)} before its solution cell")
        if cell.kind in ("provided", "exercise") and defined & course.function_names:
            raise AuthoringError(
                f"{where}: {'an exercise' if cell.kind == 'exercise' else 'a provided'} cell defines the contract name(s) {sorted(defined & course.function_names)}"
            )
        if cell.kind == "tests":
            if cell.function in tested:
                raise AuthoringError(f"{where}: a second tests cell for {cell.function}")
            if cell.function not in solved:
                raise AuthoringError(f"{where}: tests for {cell.function} come before its solution cell")
            public = sorted(n for n in defined if not n.startswith("_"))
            if public:
                raise AuthoringError(
                    f"{where}: names defined in a tests cell must start with '_' "
                    f"(tests cells are skipped when grading): {public}"
                )
            tested.add(cell.function)
    untested = sorted(solved - tested)
    if untested:
        raise AuthoringError(f"{path.name}: no tests cell for {', '.join(untested)}")
    return AuthoredNotebook(path=path, cells=cells, metadata=dict(nb.metadata))
