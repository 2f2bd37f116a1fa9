"""A corpus of synthetic submissions: realistic bugs, correct variants and attacks.

Each entry is a small Python file ``tests/corpus/<kind>/<name>.py`` (kind is
``buggy``, ``correct`` or ``hostile``) that says how to turn the instructor
notebook into one student's submission and what grading it must give:

``NOTEBOOK``
    The notebook submitted, a stage of the entry's assignment (one per entry).
``DESCRIPTION``
    One line: the mistake or the attack.
``SOLUTIONS``
    ``{function: source}``: the whole source of that function's solution cell.
    Every other solution cell keeps the teaching solution, its
    ``### BEGIN/END SOLUTION`` marker lines removed, as a student would hand it in.
``LOSES``
    The functions whose tests cells must lose points; every other graded
    function of the notebook must keep full marks.
``EDIT`` (optional)
    ``nb -> nb`` structural tampering applied after ``SOLUTIONS``; it may
    return ``bytes`` instead, written as the file's content.
``SOURCE`` (optional)
    The instructor notebook the submission is made from when it is not
    ``NOTEBOOK`` (another stage's notebook handed in under this name).
``FILENAME`` (optional)
    The submitted file's name when it is not ``NOTEBOOK + ".ipynb"``.
``STATUS`` (optional)
    The unit status the grader must report (e.g. ``"invalid"``).
``MUST_NOT_EXIST`` (optional)
    Host paths that must not exist after grading.
``NO_PROCESS`` (optional)
    A string no process's command line may contain after grading.
``LISTENER`` (optional)
    True if the submission tries to reach a TCP listener on 127.0.0.1 that
    the harness starts; it must see no connection.
``EVENT`` (optional)
    A text one of the unit's recorded events must contain (a limit the
    sandbox enforced, say).
``NEEDS_PROCESS_CAP`` (optional)
    True if the entry is only safe where the sandbox can cap its number of
    processes (a pids cgroup); the corpus tests leave it out elsewhere.
``CHECK`` (optional)
    ``(result, autograded, params) -> list of str``: entry-specific problems
    with the unit's result dict and its executed notebook's JSON text
    (``None`` if none was written); empty when the expectation held.
``WEAK_CHECK`` (optional)
    Why the grader's checks do not catch this entry yet (which check, what
    it misses); its test is then an expected failure until the check is fixed.

Sources, paths and the listener's port are filled in per run: ``@@REPO@@``
(the checkout), ``@@PORT@@`` and ``@@TOKEN@@`` (unique per run, used in
marker file names and command lines), ``@@DECOY@@`` (a host folder the test
creates, holding ``secret.txt`` and ``victim-arg``, the latter on the command
line of a decoy process the test starts; both must be untouched and the secret
never shown) are replaced in every string above.
"""

from __future__ import annotations

import copy
import importlib.util
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import nbformat

from grader.grade_ids import solution_grade_id
from grader.course_pack import pack
from grader.grade_ids import grade_id

KINDS = ("buggy", "correct", "hostile")

_MARKER_LINE = re.compile(r"^[ \t]*### (BEGIN|END) SOLUTION[ \t]*(\n|\Z)", re.MULTILINE)


@dataclass
class CorpusEntry:
    """One synthetic submission and what grading it must give.

    Attributes
    ----------
    name : str
        File stem (``student_id`` derives the submission's student id from it).
    kind : str
        ``buggy``, ``correct`` or ``hostile``.
    notebook : str
        The notebook submitted (``NN_stage``).
    loses : frozenset of str
        Functions that must score below their points; the notebook's other
        graded functions must score full marks.

    The other attributes are the optional ones of the module docstring, lower-cased.
    """

    name: str
    kind: str
    notebook: str
    description: str
    solutions: dict[str, str]
    loses: frozenset[str]
    path: Path
    edit: Callable[[nbformat.NotebookNode], nbformat.NotebookNode | bytes] | None = None
    source: str | None = None
    filename: str | None = None
    status: str | None = None
    must_not_exist: tuple[str, ...] = ()
    no_process: str | None = None
    listener: bool = False
    event: str | None = None
    needs_process_cap: bool = False
    weak_check: str | None = None
    check: Callable[[dict, str | None, dict], list[str]] | None = None
    #: the assignment of the entry's notebook (None: the course's default assignment)
    assignment: str | None = None

    @staticmethod
    def fill(text: str, params: dict[str, str]) -> str:
        """``text`` with the ``@@NAME@@`` placeholders replaced by ``params``."""
        for key, value in params.items():
            text = text.replace(f"@@{key}@@", value)
        return text


def _load_module(path: Path):
    spec = importlib.util.spec_from_file_location(f"deformlab_corpus_{path.parent.name}_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def load_entry(path: str | Path, kind: str | None = None) -> CorpusEntry:
    """Read one corpus file.

    Parameters
    ----------
    path : path-like
    kind : str, optional
        One of ``KINDS``; default the file's folder name (``tests/corpus/<kind>/``).

    Raises
    ------
    ValueError
        If a required attribute is missing or names an unknown notebook or function.
    """
    path = Path(path)
    module = _load_module(path)
    missing = [a for a in ("NOTEBOOK", "DESCRIPTION", "SOLUTIONS", "LOSES") if not hasattr(module, a)]
    if missing:
        raise ValueError(f"corpus entry {path} lacks {', '.join(missing)}")
    entry = CorpusEntry(
        name=path.stem,
        kind=kind or path.parent.name,
        notebook=module.NOTEBOOK,
        assignment=getattr(module, "ASSIGNMENT", None),
        description=module.DESCRIPTION,
        solutions=dict(module.SOLUTIONS),
        loses=frozenset(module.LOSES),
        path=path,
        edit=getattr(module, "EDIT", None),
        source=getattr(module, "SOURCE", None),
        filename=getattr(module, "FILENAME", None),
        status=getattr(module, "STATUS", None),
        must_not_exist=tuple(getattr(module, "MUST_NOT_EXIST", ())),
        no_process=getattr(module, "NO_PROCESS", None),
        listener=bool(getattr(module, "LISTENER", False)),
        event=getattr(module, "EVENT", None),
        needs_process_cap=bool(getattr(module, "NEEDS_PROCESS_CAP", False)),
        weak_check=getattr(module, "WEAK_CHECK", None),
        check=getattr(module, "CHECK", None),
    )
    course = pack(entry.assignment)
    if entry.notebook not in course.stage_names:
        raise ValueError(f"corpus entry {path}: NOTEBOOK {entry.notebook!r} is not one of {list(course.stage_names)}")
    stray = sorted((entry.loses | set(entry.solutions)) - course.function_names)
    if stray:
        raise ValueError(f"corpus entry {path}: {stray} are not contract functions")
    if entry.kind not in KINDS:
        raise ValueError(f"corpus entry {path}: its folder must be one of {KINDS}, got {entry.kind!r}")
    return entry


def load_corpus(folder: str | Path) -> list[CorpusEntry]:
    """Every entry of ``folder/{buggy,correct,hostile}/*.py``, sorted by kind then name."""
    folder = Path(folder)
    return [load_entry(p) for kind in KINDS for p in sorted((folder / kind).glob("*.py")) if not p.name.startswith("_")]


def student_notebook(source: nbformat.NotebookNode, solutions: dict[str, str]) -> nbformat.NotebookNode:
    """The instructor notebook as a student would hand it in, with ``solutions`` replacing solution cells.

    Parameters
    ----------
    source : NotebookNode
        An instructor (source) notebook.
    solutions : dict
        Function -> the whole source of its solution cell.

    Returns
    -------
    NotebookNode
        A copy; other solution cells keep the reference code without the
        ``### BEGIN/END SOLUTION`` marker lines.

    Raises
    ------
    ValueError
        If a function in ``solutions`` has no solution cell in ``source``.
    """
    nb = copy.deepcopy(source)
    by_id = {grade_id(c): c for c in nb.cells if grade_id(c)}
    for function, text in solutions.items():
        cell = by_id.get(solution_grade_id(function))
        if cell is None:
            raise ValueError(f"solutions names {function!r}, which has no solution cell in this notebook")
        cell.source = text
    for cell in nb.cells:
        if (cell.metadata.get("nbgrader") or {}).get("solution") and cell.cell_type == "code":
            cell.source = _MARKER_LINE.sub("", cell.source)
    return nb


def build_submission(
    entry: CorpusEntry,
    source_dir: str | Path,
    target_dir: str | Path,
    student_id: str | None = None,
    params: dict[str, str] | None = None,
) -> Path:
    """Write ``target_dir/<student_id>/deformation/<file>`` for one corpus entry.

    Parameters
    ----------
    entry : CorpusEntry
    source_dir : path-like
        Folder with the instructor notebooks ``NN_stage.ipynb``.
    target_dir : path-like
        The class's SUBMITTED folder.
    student_id : str, optional
        Default the entry's name.
    params : dict, optional
        Values of the ``@@NAME@@`` placeholders (``REPO``, ``PORT``, ``TOKEN``).

    Returns
    -------
    Path
        The file written.
    """
    params = params or {}
    source = nbformat.read(Path(source_dir) / f"{entry.source or entry.notebook}.ipynb", as_version=4)
    nb = student_notebook(source, entry.solutions)
    content = entry.edit(nb) if entry.edit else nb
    if not isinstance(content, bytes):
        for cell in content.cells:  # placeholders may be in solutions or in cells EDIT added
            cell.source = entry.fill(cell.source, params)
    folder = Path(target_dir) / (student_id or entry.name) / pack(entry.assignment).name
    folder.mkdir(parents=True, exist_ok=True)
    target = folder / (entry.filename or f"{entry.notebook}.ipynb")
    if isinstance(content, bytes):
        target.write_bytes(content)
    else:
        nbformat.write(content, target)
    return target


def teaching_cell(notebook: str, function: str) -> str:
    """The notebook's teaching solution of ``function`` as a student would hand it in (markers removed).

    Buggy entries start from it and change one thing, as a student who followed
    the notebook would get one thing wrong.
    """
    from grader.build.authored import read_authored

    path = Path(__file__).resolve().parents[2] / "notebooks" / "deformation" / f"{notebook}.py"
    cell = next(c for c in read_authored(path).cells if c.kind == "solution" and c.function == function)
    return _MARKER_LINE.sub("", cell.source)


def student_id(entry: CorpusEntry) -> str:
    """The entry's student id: its name, in Mixed_Case for hostile entries (ids are case-sensitive folder names)."""
    if entry.kind == "hostile":
        return "_".join(word.capitalize() for word in entry.name.split("_"))
    return entry.name
