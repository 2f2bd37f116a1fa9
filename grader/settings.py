"""The kit's settings of a course: ``c.DeformLab.*`` and ``c.Grading.*`` in the course's ``nbgrader_config.py``.

One configuration system, nbgrader's own (traitlets): a course folder's
``nbgrader_config.py`` configures nbgrader and the kit alike. :class:`DeformLab`
and :class:`Grading` declare every setting of the kit (a wrong type is refused
naming the file and the setting); :func:`course_settings` and
:func:`grading_settings` read them for a course folder, :func:`read_config` the
whole file for the kit's other configurables (the late policy's).
Command-line flags override them for one run.
"""

from __future__ import annotations

import copy
import functools
from pathlib import Path

from traitlets import Dict, Float, Int, List, TraitError, Unicode, validate
from traitlets.config import Config, Configurable

from grader.sandbox.process_limit import DEFAULT_MAX_PROCESSES

__all__ = ["DeformLab", "Grading", "SettingsError", "course_settings", "grading_settings", "course_config", "read_config"]

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


class Grading(Configurable):
    """Each unit's limits and a run's parallelism (``c.Grading.<setting>``); ``deformlab grade``'s flags override them."""

    cell_timeout = Float(60.0, help="seconds a cell may run before its kernel is killed").tag(config=True)
    notebook_wall = Float(900.0, help="seconds a whole notebook may run, replays after restarts included").tag(config=True)
    memory_gib = Float(4.0, help="GiB of address space per kernel").tag(config=True)
    disk_mib = Int(1024, help="MiB each student's working folder may hold (a tmpfs, where the grader runs as root)").tag(config=True)
    max_processes = Int(DEFAULT_MAX_PROCESSES, help="processes and threads a kernel may run at once").tag(config=True)
    workers = Int(0, help="notebooks graded in parallel (0: one per core)").tag(config=True)

    @validate("cell_timeout", "notebook_wall", "memory_gib", "disk_mib", "max_processes")
    def _positive(self, proposal):
        if proposal["value"] <= 0:
            raise TraitError(f"c.Grading.{proposal['trait'].name} must be positive, got {proposal['value']!r}")
        return proposal["value"]

    @validate("workers")
    def _workers(self, proposal):
        if proposal["value"] < 0:
            raise TraitError(f"c.Grading.workers must be 0 (one per core) or more, got {proposal['value']!r}")
        return proposal["value"]


def read_config(config_file: str | Path | None) -> Config:
    """Everything the configuration file ``config_file`` configures (an empty config without one).

    Read once per content: grading asks per unit, and a course's file rarely changes.

    Raises
    ------
    SettingsError
        If the file cannot be run.
    """
    if config_file is None or not Path(config_file).is_file():
        return Config()
    path = Path(config_file).resolve()
    return copy.deepcopy(_load(path, path.read_bytes()))  # a copy: the cached one stays as the file says


def course_config(folder: str | Path) -> Config:
    """Everything ``folder/nbgrader_config.py`` configures (:func:`read_config`)."""
    return read_config(Path(folder) / CONFIG_FILE)


@functools.lru_cache(maxsize=16)
def _load(config_file: Path, content: bytes) -> Config:
    from traitlets.config.loader import PyFileConfigLoader

    try:
        return PyFileConfigLoader(config_file.name, path=str(config_file.parent)).load_config()
    except Exception as exc:  # noqa: BLE001 - a course's file: say which and why
        raise SettingsError(f"{config_file}: cannot be read: {type(exc).__name__}: {exc}") from exc


def _settings(cls: type[Configurable], folder: str | Path) -> Configurable:
    config = course_config(folder)
    known = sorted(cls.class_trait_names(config=True))
    unknown = sorted(set(config.get(cls.__name__, {})) - set(known))
    if unknown:
        raise SettingsError(f"{Path(folder) / CONFIG_FILE}: c.{cls.__name__}.{unknown[0]} is not a setting of the kit "
                            f"(its settings: {known})")
    try:
        return cls(config=config)
    except TraitError as exc:
        raise SettingsError(f"{Path(folder) / CONFIG_FILE}: {exc}") from None


def course_settings(folder: str | Path) -> DeformLab:
    """The kit's settings in ``folder/nbgrader_config.py`` (defaults without the file).

    Raises
    ------
    SettingsError
        If a setting has the wrong type or names an unknown setting of the kit.
    """
    return _settings(DeformLab, folder)


def grading_settings(folder: str | Path) -> Grading:
    """The grading limits in ``folder/nbgrader_config.py`` (defaults without the file).

    Raises
    ------
    SettingsError
        If a limit has the wrong type, is not positive, or is not a setting of the kit.
    """
    return _settings(Grading, folder)
