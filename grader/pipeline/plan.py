"""Planning a run: one unit per student × notebook, found on this host (renamed files included).

A planned unit names host paths; :func:`unit_spec` reads the submitted bytes and
makes the self-contained :class:`grader.pipeline.unit.UnitSpec` a worker grades.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, replace
from pathlib import Path

from grader.course_pack import default_assignment
from grader.pipeline.options import GradeOptions
from grader.pipeline.read_submission import read_submission_bytes
from grader.pipeline.submitted import LINKED, linked_submission, student_folders
from grader.pipeline.unit import UnitSpec, load_submission

__all__ = ["PlannedUnit", "find_submission", "plan_units", "unit_spec"]


def find_submission(folder: Path, notebook: str) -> tuple[Path | None, list[str]]:
    """The student's file for ``notebook``, also when renamed (matched by the notebook's own metadata).

    Every candidate is the student's: read without following links, within the
    notebook size cap, and whatever fails to parse (deep nesting included) is
    passed over; it never raises for a file's content. ``folder`` is
    ``SUBMITTED/<student>/<assignment>``: if it or the student's folder is a
    link, nothing in it is graded.
    """
    return _SubmissionFolder(folder).find(notebook)


class _SubmissionFolder:
    """A student's assignment folder, listed once and each candidate's metadata read once, for all its notebooks."""

    def __init__(self, folder: Path):
        self.folder = folder
        self.linked = linked_submission(folder)
        self._listed: list[Path] | None = None
        self._named: dict[Path, object] = {}

    def listed(self) -> list[Path]:
        """The folder's ``*.ipynb`` entries, sorted; none if it is a link (never followed) or missing."""
        if self._listed is None:
            self._listed = [] if self.linked or not self.folder.is_dir() else sorted(self.folder.glob("*.ipynb"))
        return self._listed

    def find(self, notebook: str) -> tuple[Path | None, list[str]]:
        """As ``find_submission``."""
        if self.linked:
            return None, [LINKED]
        exact = self.folder / f"{notebook}.ipynb"
        if exact.is_file() or exact.is_symlink():
            return exact, []
        for candidate in self.listed():
            if self._notebook_named(candidate) == notebook:
                return candidate, [f"graded {_shown_name(candidate.name)} as {notebook}.ipynb (renamed file)"]
        return None, []

    def _notebook_named(self, candidate: Path) -> object:
        if candidate not in self._named:
            try:
                meta = json.loads(read_submission_bytes(candidate)).get("metadata", {})
                named = (meta.get("deformlab") or {}).get("notebook") if isinstance(meta, dict) else None
            except Exception:  # noqa: BLE001 - RecursionError, MemoryError, anything: not this notebook
                named = None
            self._named[candidate] = named
        return self._named[candidate]


@dataclass(frozen=True)
class PlannedUnit:
    """One student × notebook as found on this host (``unit_spec`` makes the self-contained ``UnitSpec``)."""

    student_id: str
    notebook: str
    submission: Path | None
    source: Path
    notes: tuple[str, ...] = ()
    #: False for a student of the gradebook's roster who has no folder in this run: such a row
    #: is written to grades.csv but never over what another run recorded in the gradebook.
    in_folder: bool = True


def plan_units(submitted: Path, sources: list[Path], options: GradeOptions, roster: list[str]) -> list[PlannedUnit]:
    """One unit per student × notebook: students from the folder and from the gradebook's roster.

    A student or assignment folder that is a link is not followed (its student gets rows saying so).
    """
    assignment = options.assignment or default_assignment()
    folders = student_folders(submitted, assignment)
    units = []
    for sid in sorted(set(folders) | set(roster)):
        folder = folders.get(sid)
        student = _SubmissionFolder(folder / assignment) if folder is not None else None
        first = len(units)
        for source in sources:
            notebook = source.stem
            path = None
            if student is None:
                notes = ["no submission folder for this student"]
            else:
                try:
                    path, notes = student.find(notebook)
                except OSError as exc:  # an unreadable folder costs its own student only
                    notes = [f"cannot read the submission folder: {exc.strerror}"]
            units.append(PlannedUnit(sid, notebook, path, source, tuple(notes), folder is not None))
        if student is not None:
            _name_unmatched_notebooks(units, first, student)
    return units


def _name_unmatched_notebooks(units: list[PlannedUnit], first: int, student: _SubmissionFolder) -> None:
    """Tell each of a student's missing notebooks about the files of its folder that no notebook claimed.

    A notebook saved under another name without its metadata (a fresh notebook
    the code was pasted into, an export that strips metadata) is graded as
    nothing; the TA reading "no <notebook>.ipynb was submitted" then learns which
    files were there, and can rename one and grade that student again.
    """
    try:
        present = student.listed()
    except OSError:  # already noted on each of the student's units
        return
    claimed = {u.submission for u in units[first:] if u.submission is not None}
    unmatched = [p.name for p in present if p not in claimed]
    if not unmatched:
        return
    shown = ", ".join(_shown_name(name) for name in unmatched[:5]) + (f" and {len(unmatched) - 5} more" if len(unmatched) > 5 else "")
    note = (f"{student.folder.name}/ holds {shown}, which no notebook of this assignment claims "
            "(neither by its file name nor by the notebook name in its metadata)")
    for i in range(first, len(units)):
        if units[i].submission is None and not units[i].notes:
            units[i] = replace(units[i], notes=(note,))


def _shown_name(name: str) -> str:
    """A student's file name as a TA may read it: printable, at most 60 characters, quoted."""
    printable = "".join(ch if ch.isprintable() else "?" for ch in name)
    return repr(printable if len(printable) <= 60 else printable[:57] + "...")


def unit_spec(unit: PlannedUnit, seed: int, options: GradeOptions, source_text: str) -> UnitSpec:
    """The self-contained work unit: the submitted bytes are read here, on the recording host."""
    content, digest, error = load_submission(unit.submission)
    return UnitSpec(
        student_id=unit.student_id,
        notebook=unit.notebook,
        submission=content,
        source=source_text,
        seed=seed,
        assignment=options.assignment,
        timeout=options.timeout,
        memory_bytes=int(options.memory_gb * 2**30),
        max_processes=options.max_processes,
        notes=list(unit.notes),
        submission_sha256=digest,
        submission_error=error,
        wall=options.wall,
        disk_bytes=options.disk_bytes,
    )
