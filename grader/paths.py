"""Where the course lives on disk: the course kit's folder (``data/``, ``notebooks/``, ``assignments/``).

``course_paths()`` finds it, first match wins:

1. ``deformlab --course DIR`` (the flag sets ``DEFORMLAB_ROOT`` for this process and
   the grading workers it starts);
2. the ``DEFORMLAB_ROOT`` environment variable;
3. ``c.DeformLab.course_root = "DIR"`` in the ``nbgrader_config.py`` of the current
   folder (the course's ``assignments/nbgrader_config.py`` sets it to its parent,
   so ``cd COURSE/assignments`` is enough);
4. the checkout this package was installed from (``pip install -e .``).

A non-editable install (``pip install .``, the Gradescope zip, a Dask worker)
has no checkout around the package, so it uses 1–3.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

ROOT_VARIABLE = "DEFORMLAB_ROOT"
#: nbgrader's course id of every gradebook the kit writes (``assignments/nbgrader_config.py`` says the same):
#: a PostgreSQL gradebook enforces that each assignment's course exists.
COURSE_ID = "deformlab"


@dataclass(frozen=True)
class CoursePaths:
    """The folders of a course kit.

    Attributes
    ----------
    root : Path
        The kit's folder (a checkout of this repository, or its copy).
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

    def source_notebooks(self, assignment: str) -> list[Path]:
        """The built instructor notebooks of ``assignment``."""
        return sorted((self.source / assignment).glob("*.ipynb"))

    @property
    def gradebook_url(self) -> str:
        return f"sqlite:///{self.course / 'gradebook.db'}"


def is_course(root: Path) -> bool:
    """Whether ``root`` holds a course kit (its meshes and its notebooks' sources)."""
    return (root / "data").is_dir() and (root / "notebooks").is_dir()


def use_course(root: str | Path) -> CoursePaths:
    """Select the course kit at ``root`` for this process and the workers it starts.

    Raises
    ------
    FileNotFoundError
        If ``root`` has no ``data/`` and ``notebooks/`` folders.
    """
    path = Path(root).expanduser().resolve()
    if not is_course(path):
        raise FileNotFoundError(f"--course {root}: not a DeformLab course folder (it needs data/ and notebooks/)")
    os.environ[ROOT_VARIABLE] = str(path)
    return CoursePaths(path)


def _configured_root(folder: Path) -> Path | None:
    """``c.DeformLab.course_root`` of ``folder/nbgrader_config.py``, relative to that folder."""
    from grader.settings import course_settings

    value = course_settings(folder).course_root
    return None if value is None else (folder / value).resolve()


def course_paths() -> CoursePaths:
    """The course kit this process grades (see the module's docstring for the order).

    Raises
    ------
    FileNotFoundError
        If no setting names a course and the package is not in a checkout.
    """
    root = os.environ.get(ROOT_VARIABLE)
    if root:
        return CoursePaths(Path(root).resolve())
    configured = _configured_root(Path.cwd())
    if configured is not None:
        return CoursePaths(configured)
    checkout = Path(__file__).resolve().parent.parent
    if is_course(checkout):
        return CoursePaths(checkout)
    raise FileNotFoundError(
        "cannot find the DeformLab course folder: pass deformlab --course DIR, set DEFORMLAB_ROOT=DIR, "
        "or run from COURSE/assignments (its nbgrader_config.py sets c.DeformLab.course_root)"
    )
