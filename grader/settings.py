"""The kit's settings of a course: ``c.DeformLab.*`` in the course's ``nbgrader_config.py``.

One configuration system, nbgrader's own (traitlets): a course folder's
``nbgrader_config.py`` configures nbgrader and the kit alike. :class:`DeformLab`
declares every setting of the kit (a wrong type is refused naming the file and
the setting); :func:`course_settings` reads them for a course folder.
Command-line flags override them for one run.
"""

from __future__ import annotations

import functools
from pathlib import Path

from traitlets import Dict, List, TraitError, Unicode
from traitlets.config import Config, Configurable

__all__ = ["DeformLab", "SettingsError", "course_settings", "course_config"]

CONFIG_FILE = "nbgrader_config.py"


class SettingsError(ValueError):
    """A setting of ``nbgrader_config.py`` the kit cannot use; the message names the file and the setting."""


class DeformLab(Configurable):
    """What a course configures of the kit (``c.DeformLab.<setting>``)."""

    course_root = Unicode(
        None, allow_none=True,
        help="where the course kit is (data/, notebooks/), relative to the folder of nbgrader_config.py",
    ).tag(config=True)
    course_packs = List(
        Unicode(), default_value=None, allow_none=True,
        help="the course's assignments: course pack folders, relative to assignments/ or absolute "
             "(default: every assignments/*/assignment.toml)",
    ).tag(config=True)
    default_assignment = Unicode(
        None, allow_none=True, help="the assignment commands use when --assignment is omitted (default: the first pack)",
    ).tag(config=True)
    stages = Dict(
        key_trait=Unicode(), value_trait=List(Unicode(), minlen=1),
        help="the stages an assignment includes, by assignment: {'geometry': ['00_intro', '02_curves']}; "
             "building, releasing, grading, the bundle, reports and exports follow it (default: every stage)",
    ).tag(config=True)


def course_config(folder: str | Path) -> Config:
    """Everything ``folder/nbgrader_config.py`` configures (an empty config without the file).

    Raises
    ------
    SettingsError
        If the file cannot be run.
    """
    config_file = Path(folder) / CONFIG_FILE
    if not config_file.is_file():
        return Config()
    return _load(config_file.resolve(), config_file.stat().st_mtime_ns)


@functools.lru_cache(maxsize=16)
def _load(config_file: Path, mtime_ns: int) -> Config:
    from traitlets.config.loader import PyFileConfigLoader

    try:
        return PyFileConfigLoader(config_file.name, path=str(config_file.parent)).load_config()
    except Exception as exc:  # noqa: BLE001 - a course's file: say which and why
        raise SettingsError(f"{config_file}: cannot be read: {type(exc).__name__}: {exc}") from exc


def course_settings(folder: str | Path) -> DeformLab:
    """The kit's settings in ``folder/nbgrader_config.py`` (defaults without the file).

    Raises
    ------
    SettingsError
        If a setting has the wrong type or names an unknown setting of the kit.
    """
    config = course_config(folder)
    section = config.get("DeformLab", {})
    unknown = sorted(set(section) - set(DeformLab.class_trait_names(config=True)))
    if unknown:
        known = sorted(DeformLab.class_trait_names(config=True))
        raise SettingsError(f"{Path(folder) / CONFIG_FILE}: c.DeformLab.{unknown[0]} is not a setting of the kit (its settings: {known})")
    try:
        return DeformLab(config=config)
    except TraitError as exc:
        raise SettingsError(f"{Path(folder) / CONFIG_FILE}: {exc}") from None
