"""Where the course lives on disk (a checkout of this repository)."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from grader.contract import ASSIGNMENT


@dataclass(frozen=True)
class CoursePaths:
    """The folders of a checkout.

    Attributes
    ----------
    root : Path
        The repository root.
    """

    root: Path

    @property
    def notebooks(self) -> Path:
        return self.root / "notebooks"

    @property
    def course(self) -> Path:
        """nbgrader's course root (``nbgrader_config.py`` lives here)."""
        return self.root / "assignments"

    @property
    def source(self) -> Path:
        return self.course / "source"

    @property
    def release(self) -> Path:
        return self.course / "release"

    @property
    def data(self) -> Path:
        return self.root / "data"

    @property
    def starter(self) -> Path:
        return self.root / "starter"

    @property
    def reference(self) -> Path:
        return self.root / "reference"

    @property
    def dist(self) -> Path:
        return self.root / "dist"

    def source_notebooks(self, assignment: str = ASSIGNMENT) -> list[Path]:
        return sorted((self.source / assignment).glob("[0-9][0-9]_*.ipynb"))

    @property
    def gradebook_url(self) -> str:
        return f"sqlite:///{self.course / 'gradebook.db'}"


def course_paths() -> CoursePaths:
    """The checkout this package was installed from (or ``DEFORMLAB_ROOT``)."""
    root = os.environ.get("DEFORMLAB_ROOT")
    return CoursePaths(Path(root).resolve() if root else Path(__file__).resolve().parent.parent)
