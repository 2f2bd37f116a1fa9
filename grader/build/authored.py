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

from grader.contract import CONTRACT_NAMES, STAGES, stage_functions, stage_of

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


def earlier_stage(notebook: str, function: str) -> str | None:
    """The stage that grades ``function`` if it is not ``notebook``'s own (a function the student copies over)."""
    if notebook not in STAGES or function in stage_functions(notebook):
        return None
    return stage_of(function)


def solution_body(source: str) -> str:
    """The code between a solution cell's markers (what a release must never contain)."""
    inside = source.split(BEGIN_SOLUTION, 1)[1].split(END_SOLUTION, 1)[0]
    return textwrap.dedent(inside.split("\n", 1)[1] if "\n" in inside else "")


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
        raise AuthoringError(f"{where}: syntax error: {exc}") from None
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


def _classify(cell, index: int, path: Path) -> AuthoredCell:
    meta = cell.metadata.get("deformlab") or {}
    where = f"{path.name}, cell {index + 1}"
    if cell.cell_type == "markdown":
        if "answer" in meta:
            points = float(meta.get("points", 0))
            if points <= 0:
                raise AuthoringError(f"{where}: a short-answer cell needs positive points")
            return AuthoredCell("answer", cell.source, answer_id=str(meta["answer"]), points=points)
        return AuthoredCell("text", cell.source)
    if "solution" in meta:
        name = meta["solution"]
        if name not in CONTRACT_NAMES:
            raise AuthoringError(f"{where}: solution cell names {name!r}, which is not a contract function")
        check_solution_cell(cell.source, name, where)
        return AuthoredCell("solution", cell.source, function=name)
    if "tests" in meta:
        name = meta["tests"]
        if name not in CONTRACT_NAMES:
            raise AuthoringError(f"{where}: tests cell names {name!r}, which is not a contract function")
        points = float(meta.get("points", 0))
        earlier = earlier_stage(path.stem, name)
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


def read_authored(path: str | Path) -> AuthoredNotebook:
    """Parse an authored notebook and check the rules of ``notebooks/README.md``.

    Parameters
    ----------
    path : path-like
        A jupytext percent-format ``.py`` file.

    Returns
    -------
    AuthoredNotebook

    Raises
    ------
    AuthoringError
        Naming the file, the cell and the broken rule.
    """
    path = Path(path)
    nb = jupytext.read(path)
    cells = [_classify(c, i, path) for i, c in enumerate(nb.cells)]
    solved: set[str] = set()
    tested: set[str] = set()
    for i, cell in enumerate(cells):
        where = f"{path.name}, cell {i + 1}"
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
            raise AuthoringError(f"{where}: syntax error: {exc}") from None
        early = sorted((used & CONTRACT_NAMES) - solved)
        if early:
            raise AuthoringError(f"{where}: uses {', '.join(early)} before its solution cell")
        if cell.kind in ("provided", "exercise") and defined & CONTRACT_NAMES:
            raise AuthoringError(
                f"{where}: {'an exercise' if cell.kind == 'exercise' else 'a provided'} cell defines the contract name(s) {sorted(defined & CONTRACT_NAMES)}"
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
