"""Step 2: repair a submitted notebook (read by :mod:`grader.pipeline.read_submission`) against the source notebook.

Tests and provided cells are read-only: whatever a student did to them (edit,
delete, duplicate) they are restored from the source, as nbgrader's checksums
and ``add_missing_cells`` would. Every cell is rebuilt from the student's text
alone: its metadata comes from the source notebook's cell of the same grade id
(points, grade ids and locks cannot be forged; a cell the source does not know
gets none), outputs are dropped (never trusted, maybe huge),
text that cannot be encoded is replaced, duplicate cell ids are repaired, and
a plan of which cells to run when grading is made.
"""

from __future__ import annotations

import ast
import copy
import re
from dataclasses import dataclass, field

import nbformat

from grader.grade_ids import grade_id, tested_function
from grader.pipeline.read_submission import SubmissionError


@dataclass
class Sanitized:
    """A repaired submission.

    Attributes
    ----------
    nb : NotebookNode
        The notebook to execute: student code cells, source tests and provided cells.
    plan : list of int
        Indices of the code cells to execute when grading, in order.
    notes : list of str
        What was repaired, for the feedback (e.g. "restored deleted cell test_lbs").
    """

    nb: nbformat.NotebookNode
    plan: list[int]
    notes: list[str] = field(default_factory=list)


def _nbgrader_meta(cell) -> dict:
    """A cell's ``nbgrader`` metadata, ``{}`` when a student's file has anything but a dict there."""
    meta = cell.get("metadata")
    meta = meta.get("nbgrader") if isinstance(meta, dict) else None
    return meta if isinstance(meta, dict) else {}


def _is_locked(cell) -> bool:
    meta = _nbgrader_meta(cell)
    return bool(meta.get("locked")) and not meta.get("solution")


def _released_source(cell) -> str:
    """The text a student received for a read-only cell: nbgrader's release clears its hidden tests."""
    from nbgrader.preprocessors import ClearHiddenTests

    released = copy.deepcopy(cell)
    ClearHiddenTests()._remove_hidden_test_region(released)
    return released.source


def graded_functions(source: nbformat.NotebookNode) -> frozenset[str]:
    """Every graded function of the source notebook's assignment, as its build wrote them in its metadata.

    A source notebook built without them: the functions of its own graded tests cells.
    """
    listed = (source.metadata.get("deformlab") or {}).get("functions")
    if isinstance(listed, list) and all(isinstance(n, str) for n in listed):
        return frozenset(listed)
    return frozenset(f for cell in source.cells if (f := tested_function(grade_id(cell))) is not None)


def _calls_contract_at_top_level(source: str, names: frozenset[str]) -> bool:
    """Whether a cell uses one of the graded functions ``names`` outside function bodies (a demo or an experiment)."""
    try:
        tree = ast.parse(source)
    except SyntaxError:
        return False
    except Exception:  # noqa: BLE001 - CPython 3.11's parser can fail with SystemError on odd input
        # Without a tree, judge by text: an unindented line calling a contract function.
        return any(
            re.match(rf"^(?!def |class |@|#)[^\n]*\b{name}\s*\(", line)
            for line in source.splitlines()
            for name in names
        )
    # Function and class bodies (with their decorators and defaults) are not walked into.
    stack: list[ast.AST] = [tree]
    while stack:
        node = stack.pop()
        if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load) and node.id in names:
            return True
        stack.extend(n for n in ast.iter_child_nodes(node) if not isinstance(n, _SCOPES))
    return False


_SCOPES = (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda, ast.ClassDef)


def grading_plan(nb: nbformat.NotebookNode, names: frozenset[str]) -> list[int]:
    """Code cells to execute when grading.

    Solution cells always run. Tests cells never run (the trusted checks replace
    them). Other cells run unless they use a graded function (``names``: the source
    notebook's :func:`graded_functions`, never the submission's own metadata) at top
    level: those are pictures and experiments, whose results nobody grades.
    """
    plan = []
    for i, cell in enumerate(nb.cells):
        if cell.cell_type != "code":
            continue
        meta = cell.metadata.get("nbgrader") or {}
        if meta.get("solution"):
            plan.append(i)
        elif meta.get("grade"):
            continue
        elif not _calls_contract_at_top_level(cell.source, names):
            plan.append(i)
    return plan


def sanitize(student: nbformat.NotebookNode, source: nbformat.NotebookNode) -> Sanitized:
    """Repair ``student`` against ``source`` (the instructor notebook).

    Raises
    ------
    SubmissionError
        If the notebook shares no graded cell with the source (another assignment's notebook).
    """
    notes: list[str] = []
    source_ids = [grade_id(c) for c in source.cells]
    locked_source = {grade_id(c): c for c in source.cells if _is_locked(c) and grade_id(c)}
    if not ({g for g in source_ids if g} & {grade_id(c) for c in student.cells}):
        raise SubmissionError(
            "this notebook shares no graded cell with the assignment's notebook: "
            "is it another assignment's notebook, or were the cells' metadata removed?"
        )

    cells, seen = [], set()
    for cell in student.cells:
        gid = grade_id(cell)
        if gid and gid in seen:
            if gid in locked_source:
                notes.append(f"removed a duplicate of the read-only cell {gid}")
                continue
            # A copied solution cell keeps its code but is no longer a graded cell.
            cell = nbformat.from_dict({"cell_type": cell.cell_type, "source": cell.source, "metadata": {}})
            gid = None
        if gid:
            seen.add(gid)
        if gid in locked_source:
            original = locked_source[gid]
            # The student's copy of a tests cell lacks the hidden tests: compare with what was handed out.
            if cell.cell_type != original.cell_type or cell.source not in (original.source, _released_source(original)):
                notes.append(f"restored the edited read-only cell {gid}")
            cell = copy.deepcopy(original)
        cells.append(cell)  # rebuilt below; the student's own metadata is never copied

    # Put back deleted read-only cells after the nearest earlier cell that is still there.
    position = {grade_id(c): i for i, c in enumerate(cells) if grade_id(c)}
    for k, gid in enumerate(source_ids):
        if gid in locked_source and gid not in position:
            before = next((position[g] for g in reversed(source_ids[:k]) if g in position), -1)
            cells.insert(before + 1, copy.deepcopy(locked_source[gid]))
            notes.append(f"restored the deleted cell {gid}")
            position = {grade_id(c): i for i, c in enumerate(cells) if grade_id(c)}

    nb = nbformat.v4.new_notebook(metadata=copy.deepcopy(source.metadata))
    by_grade_id = {g: c for g, c in zip(source_ids, source.cells) if g}
    used_ids: set[str] = set()
    for i, cell in enumerate(cells):
        cid = cell.get("id")
        if not isinstance(cid, str) or cid in used_ids or not _CELL_ID.fullmatch(cid):
            cid = f"cell-{i:04d}"
            while cid in used_ids:
                cid += "x"
        used_ids.add(cid)
        nb.cells.append(_rebuilt(cell, by_grade_id.get(grade_id(cell)), cid))
    return Sanitized(nb=nb, plan=grading_plan(nb, graded_functions(source)), notes=notes)


# nbformat's own rule for cell ids.
_CELL_ID = re.compile(r"[a-zA-Z0-9-_]{1,64}")
_SURROGATE = re.compile("[\ud800-\udfff]")


def _rebuilt(cell, original, cid: str) -> nbformat.NotebookNode:
    """A fresh cell with the student's text only: type and metadata from the source's cell of the same grade id."""
    text = _SURROGATE.sub("\ufffd", cell.source)  # a lone surrogate cannot be written as UTF-8
    kind = original.cell_type if original is not None else cell.cell_type
    metadata = copy.deepcopy(original.metadata) if original is not None else {}
    # Valid by construction (parse_submission checked the text, the metadata is the source's):
    # not validated again, which cost a tenth of a unit's grader CPU.
    new = {"id": cid, "cell_type": kind, "metadata": metadata, "source": text}
    if kind == "code":
        new |= {"execution_count": None, "outputs": []}
    elif kind == "markdown" and isinstance(cell.get("attachments"), dict):
        new["attachments"] = cell["attachments"]  # pictures pasted into answers; neutralize keeps real PNGs only
    return nbformat.from_dict(new)
