"""The teaching solutions in the notebooks match reference/ on every hidden case, and stay plain.

The release proves the same through the real pipeline (tests/grader/test_release.py, slow);
this runs the trusted checks in process, one notebook at a time.
"""

import re
import ast
from pathlib import Path

import pytest

from grader.build.authored import read_authored, solution_body
from grader.checks import check_namespace
from grader.course_pack import pack
_COURSE = pack("deformation")
LECTURE_NAMES = frozenset(re.findall(r"^\| `([a-z_]+)\(", (Path(__file__).resolve().parents[2] / "LECTURE_CONTRACT.md").read_text(), flags=re.M))
STAGES = _COURSE.stage_names
stage_functions = _COURSE.stage_functions
CONTRACT_NAMES = _COURSE.function_names
stage_of = _COURSE.stage_of
from grader.pipeline.sanitize import _calls_contract_at_top_level

NOTEBOOKS = Path(__file__).resolve().parents[2] / "notebooks" / "deformation"
#: One screen: a teaching solution's body longer than this is not read in one go.
MAX_BODY_LINES = 50


def _namespace(notebook: str) -> dict:
    """The notebook's setup cells and solution cells, executed as grading runs them."""
    namespace: dict = {}
    for cell in read_authored(NOTEBOOKS / f"{notebook}.py").cells:
        if cell.kind == "solution" or (cell.kind == "provided" and not _calls_contract_at_top_level(cell.source, CONTRACT_NAMES)):
            exec(compile(cell.source, f"{notebook}.py", "exec"), namespace)
    return namespace


@pytest.mark.parametrize("notebook", sorted(STAGES))
def test_the_teaching_solutions_pass_every_hidden_case(notebook):
    namespace = _namespace(notebook)
    for function in stage_functions(notebook):
        result = check_namespace(function, namespace)
        assert result.fraction == 1.0, f"{notebook}: {function}: {result.summary()}"


@pytest.mark.parametrize("notebook", sorted(STAGES))
def test_teaching_solutions_are_short_and_name_no_oracle_internals(notebook):
    for cell in read_authored(NOTEBOOKS / f"{notebook}.py").cells:
        if cell.kind != "solution":
            continue
        body = solution_body(cell.source)
        lines = [line for line in body.splitlines() if line.strip()]
        assert len(lines) <= MAX_BODY_LINES, f"{notebook}: {cell.function} has {len(lines)} lines"
        tree = ast.parse(cell.source)
        imported = {a.name for n in ast.walk(tree) if isinstance(n, (ast.Import, ast.ImportFrom)) for a in n.names}
        modules = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
        assert not ({"reference", "starter.validation", "grader"} & (imported | modules)), f"{notebook}: {cell.function} imports {imported | modules}"
        docstring = ast.get_docstring(tree.body[-1])
        # quaternions are what dual-quaternion skinning teaches; elsewhere they are the oracle's Horn method
        banned = ("Horn", "Newton", "benchmarks", "starter.validation", "reference") + (() if cell.function in LECTURE_NAMES else ("quaternion",))
        for word in banned:
            assert word not in docstring, f"{notebook}: {cell.function}'s docstring (what students see) mentions {word!r}"


def test_a_function_taught_in_several_notebooks_has_one_teaching_solution():
    """Later notebooks carry copies of earlier functions (each notebook stands alone): the copies must not drift."""
    cells: dict[str, dict[str, str]] = {}
    for notebook in sorted(STAGES):
        for cell in read_authored(NOTEBOOKS / f"{notebook}.py").cells:
            if cell.kind == "solution":
                cells.setdefault(cell.function, {})[notebook] = cell.source
    for function, copies in cells.items():
        owner = stage_of(function)
        for notebook, source in copies.items():
            assert source == copies[owner], f"{function} in {notebook} differs from its teaching solution in {owner}"
