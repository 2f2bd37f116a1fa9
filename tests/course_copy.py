"""A private course's ``assignments/`` as the checkout's: its ``nbgrader_config.py`` and its course packs."""

from __future__ import annotations

import shutil
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def copy_course_config(assignments: Path, extra: str = "") -> None:
    """Copy the checkout's ``assignments/nbgrader_config.py`` (with ``extra`` appended) and every pack folder into ``assignments``."""
    assignments = Path(assignments)
    assignments.mkdir(parents=True, exist_ok=True)
    config = (ROOT / "assignments" / "nbgrader_config.py").read_text()
    (assignments / "nbgrader_config.py").write_text(config + extra)
    for manifest in sorted((ROOT / "assignments").glob("*/assignment.toml")):
        shutil.copytree(manifest.parent, assignments / manifest.parent.name, dirs_exist_ok=True,
                        ignore=shutil.ignore_patterns("__pycache__"))
