"""Course packs: what the engine grades, declared by a course, never written in the engine.

A course pack is a folder holding ``assignment.toml`` (one nbgrader assignment:
its stages and graded functions, bonus stages, reference package, hidden checks,
kernel preloads, library policy, student bundle) and the Python code the file
names (its ``checks`` package, optional ``pictures``). The deformation course's
pack is ``assignments/deformation/``; a second course adds a folder beside it,
or anywhere, and edits no file of ``grader/``.

Discovery, by configuration: ``c.DeformLab.course_packs = ["deformation", "/srv/packs/smoothing"]``
in the course's ``assignments/nbgrader_config.py`` (entries relative to that
folder); without the setting, every ``assignments/*/assignment.toml``.
``c.DeformLab.default_assignment`` names the assignment commands use when none
is given (else the first pack). ``c.DeformLab.stages = {"geometry": ["00_intro", "02_curves"]}``
keeps only those stages of an assignment (an instructor's schedule): the
assignment a pack lookup returns has only them, so building, releasing, grading,
the bundle, reports and exports follow (:mod:`grader.settings` declares every setting).

A pack's Python code is imported as ``deformlab_packs.<name>`` (a finder on
``sys.meta_path`` maps that package to the pack's folder), so its modules import
each other relatively, pickle by name, and load the same way in a grading
worker, a Dask worker or a test.

``assignment.toml``::

    name = "smoothing"                     # the nbgrader assignment
    title = "Laplacian smoothing"
    notebooks = "../../notebooks/smoothing" # jupytext sources NN_stage.py, relative to this file
    reference = "reference"                 # a package exporting every graded function (hidden in the sandbox)
    checks = "checks"                       # a package of this folder: every FunctionChecks subclass in it
    pictures = "pictures"                   # optional module of this folder: feedback pictures
    contract = "CONTRACT.md"                # optional: the students' contract, shipped in the bundle
    hidden_packages = ["reference"]         # masked inside the sandbox (beside grader)
    preload = ["igl", "starter"]            # imported by the kernel template before it forks
    data = ["bar.npz"]                      # files of the course's data/ the notebooks load
    [bundle]
    readme = "README.student.md"            # the bundle's README, in this folder
    files = ["../../LIBRARY_POLICY.md"]     # more files for the bundle, relative to this folder
    demos = ["demo_skinning"]               # ungraded notebooks/<demo>/<demo>.py shipped as <demo>.ipynb
    [policy]                                # library routines a graded function may not call
    umbrella_operator = ["igl.adjacency_matrix"]
    backward_euler_step = []
    [builds_on]                             # graded functions a function builds on (it may not call what they may not)
    backward_euler_step = ["umbrella_operator"]
    [grading]                               # optional: the pack's own steps of a unit, after verification
    steps = ["notes:written_answers_left"]  # module:function of this folder, step(unit) (grader/pipeline/unit.py)
    [[stages]]
    notebook = "00_smoothing"
    functions = ["umbrella_operator", "backward_euler_step"]
    reference = "reference.laplacian_smoothing"  # optional: the stage's reference module (default: the pack's)
    bonus = false

A pack without ``[policy]`` uses the rows ``starter/library_policy.py`` holds for its
functions (the deformation course's); a pack with one declares it to the policy on
both sides: here, and in each notebook's cell that installs the policy.
"""

from __future__ import annotations

import functools
import importlib
import importlib.abc
import importlib.machinery
import importlib.util
import os
import re
import sys
import tomllib
import types
import dataclasses
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

from grader.paths import ROOT_VARIABLE, course_paths
from grader.settings import CONFIG_FILE, SettingsError, course_settings

PACKAGE = "deformlab_packs"
MANIFEST = "assignment.toml"
_NAME = re.compile(r"^[a-z][a-z0-9_]{0,63}$")
# two digits, and a letter for a stage inserted between two (02b_ sorts after 02_, before 03_)
_STAGE = re.compile(r"^[0-9]{2}[a-z]?_[a-z][a-z0-9_]{0,63}$")
_STEP = re.compile(r"^[A-Za-z_][A-Za-z0-9_.]{0,99}:[A-Za-z_][A-Za-z0-9_]{0,99}$")
_FUNCTION = re.compile(r"^[A-Za-z_][A-Za-z0-9_]{0,99}$")
_KEYS = {"name", "title", "notebooks", "reference", "checks", "pictures", "contract", "hidden_packages", "preload", "data",
         "bundle", "policy", "builds_on", "stages", "grading"}
_STAGE_KEYS = {"notebook", "functions", "bonus", "reference"}
_BUNDLE_KEYS = {"readme", "files", "demos"}
_GRADING_KEYS = {"steps"}


class PackError(ValueError):
    """A course pack that cannot be used; the message names the file and the key."""


@dataclass(frozen=True)
class Stage:
    """One graded notebook of an assignment.

    Attributes
    ----------
    notebook : str
        The notebook's stem, ``NN_name`` (its source is ``<notebooks>/NN_name.py``).
    functions : tuple of str
        The graded functions, in the order the notebook teaches them.
    bonus : bool
        Whether its points are extra credit, outside the regular maximum.
    reference : str or None
        The module of its functions' reference implementations (None: the pack's ``reference``).
    """

    notebook: str
    functions: tuple[str, ...]
    bonus: bool = False
    reference: str | None = None


@dataclass(frozen=True)
class Assignment:
    """One course pack: an nbgrader assignment and everything needed to build, grade and ship it."""

    name: str
    title: str
    folder: Path
    notebooks: Path
    stages: tuple[Stage, ...]
    reference: str = "reference"
    checks: str = "checks"
    pictures: str | None = None
    contract: Path | None = None
    hidden_packages: tuple[str, ...] = ()
    preload: tuple[str, ...] = ()
    data: tuple[str, ...] = ()
    readme: Path | None = None
    bundle_files: tuple[Path, ...] = ()
    demos: tuple[str, ...] = ()
    policy: dict[str, tuple[str, ...]] = field(default_factory=dict)
    builds_on: dict[str, tuple[str, ...]] = field(default_factory=dict)
    steps: tuple[str, ...] = ()

    # --- the contract ---------------------------------------------------------------------------
    @property
    def stage_names(self) -> tuple[str, ...]:
        return tuple(s.notebook for s in self.stages)

    @property
    def functions(self) -> tuple[str, ...]:
        """Every graded function, stage by stage in teaching order."""
        return tuple(f for s in self.stages for f in s.functions)

    @property
    def function_names(self) -> frozenset[str]:
        return frozenset(self.functions)

    def stage(self, notebook: str) -> Stage:
        for s in self.stages:
            if s.notebook == notebook:
                return s
        raise KeyError(f"assignment {self.name!r} has no stage {notebook!r} (its stages: {list(self.stage_names)})")

    def stage_functions(self, notebook: str) -> tuple[str, ...]:
        """The functions ``notebook`` teaches and grades (none for a notebook that is not a stage)."""
        return next((s.functions for s in self.stages if s.notebook == notebook), ())

    def stage_of(self, function: str) -> str:
        """The stage that teaches and grades ``function``."""
        for s in self.stages:
            if function in s.functions:
                return s.notebook
        raise KeyError(f"{function!r} is not a graded function of assignment {self.name!r}")

    def is_bonus(self, notebook: str) -> bool:
        return any(s.bonus for s in self.stages if s.notebook == notebook)

    # --- the pack's code ------------------------------------------------------------------------
    @property
    def package(self) -> str:
        """The import name of the pack's folder."""
        return f"{PACKAGE}.{self.name}"

    def module(self, name: str) -> types.ModuleType:
        """Import the pack's module ``name`` (relative to its folder)."""
        _install_finder()
        return importlib.import_module(f"{self.package}.{name}")

    def reference_function(self, name: str) -> Callable:
        """The reference implementation of graded function ``name``."""
        if name not in self.function_names:
            raise ValueError(f"{name!r} is not a graded function of assignment {self.name!r}")
        module = next(s.reference for s in self.stages if name in s.functions) or self.reference
        return getattr(importlib.import_module(module), name)

    def reference_modules(self) -> list[types.ModuleType]:
        """The modules that define the reference's graded functions (their globals are where callees resolve)."""
        names = sorted({self.reference_function(f).__module__ for f in self.functions})
        return [importlib.import_module(n) for n in names]

    def reference_packages(self) -> tuple[str, ...]:
        """The top-level packages of the reference modules (the sandbox hides them)."""
        return tuple(sorted({(s.reference or self.reference).split(".")[0] for s in self.stages}))

    def grading_steps(self) -> tuple[Callable, ...]:
        """The pack's own grading steps (``[grading] steps``), run after verification: ``step(unit) -> None``.

        Raises
        ------
        PackError
            If a step's module or function is missing, naming the manifest and the step.
        """
        found = []
        for step in self.steps:
            module, function = step.split(":")
            try:
                found.append(getattr(self.module(module), function))
            except (ImportError, AttributeError) as exc:
                raise _fail(self.folder / MANIFEST, f"[grading] steps: {step!r} cannot be loaded: {exc}") from None
        return tuple(found)

    def checks_module(self) -> types.ModuleType:
        return self.module(self.checks)

    def pictures_module(self) -> types.ModuleType | None:
        return None if self.pictures is None else self.module(self.pictures)


def _fail(path: Path, message: str) -> PackError:
    return PackError(f"{path}: {message}")


def _strings(path: Path, table: dict, key: str, pattern: re.Pattern | None = None) -> tuple[str, ...]:
    value = table.get(key, [])
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise _fail(path, f"{key} must be a list of strings, got {value!r}")
    bad = [v for v in value if pattern is not None and not pattern.match(v)]
    if bad:
        raise _fail(path, f"{key} holds names that are not identifiers: {bad!r}")
    return tuple(value)


def _string(path: Path, table: dict, key: str, default: str | None = None) -> str | None:
    value = table.get(key, default)
    if value is not None and not isinstance(value, str):
        raise _fail(path, f"{key} must be a string, got {value!r}")
    return value


def _file(path: Path, relative: str | None, key: str) -> Path | None:
    if relative is None:
        return None
    target = (path.parent / relative).resolve()
    if not target.exists():
        raise _fail(path, f"{key} = {relative!r}: {target} does not exist")
    return target


def load_pack(folder: str | Path) -> Assignment:
    """Read and check the course pack in ``folder`` (its ``assignment.toml``).

    Raises
    ------
    PackError
        Naming the file and the key, for a missing or malformed manifest, a
        missing file it names, or a function graded by two stages.
    """
    path = Path(folder).resolve() / MANIFEST
    if not path.is_file():
        raise PackError(f"{path.parent}: not a course pack (it has no {MANIFEST})")
    try:
        table = tomllib.loads(path.read_text(encoding="utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise _fail(path, f"not valid TOML: {exc}") from None
    unknown = sorted(set(table) - _KEYS)
    if unknown:
        raise _fail(path, f"unknown keys {unknown} (a pack declares {sorted(_KEYS)})")
    name = _string(path, table, "name")
    if name is None or not _NAME.match(name):
        raise _fail(path, f"name must be a lower-case identifier (it names the nbgrader assignment), got {name!r}")
    stages = []
    raw_stages = table.get("stages", [])
    if not isinstance(raw_stages, list) or not raw_stages:
        raise _fail(path, "[[stages]] must list at least one stage")
    seen: dict[str, str] = {}
    for i, raw in enumerate(raw_stages):
        if not isinstance(raw, dict):
            raise _fail(path, f"stages[{i}] must be a table")
        if set(raw) - _STAGE_KEYS:
            raise _fail(path, f"stages[{i}] has unknown keys {sorted(set(raw) - _STAGE_KEYS)} (a stage declares {sorted(_STAGE_KEYS)})")
        notebook = _string(path, raw, "notebook")
        if notebook is None or not _STAGE.match(notebook):
            raise _fail(path, f"stages[{i}].notebook must read NN_name or NNa_name (two digits, a letter for a stage "
                               f"inserted between two, an identifier), got {notebook!r}")
        functions = _strings(path, raw, "functions", _FUNCTION)
        for f in functions:
            if f in seen:
                raise _fail(path, f"function {f!r} is graded by two stages: {seen[f]} and {notebook}")
            seen[f] = notebook
        bonus = raw.get("bonus", False)
        if not isinstance(bonus, bool):
            raise _fail(path, f"stages[{i}].bonus must be true or false, got {bonus!r}")
        stages.append(Stage(notebook, functions, bonus, _string(path, raw, "reference")))
    if len({s.notebook for s in stages}) != len(stages):
        raise _fail(path, "two stages have the same notebook")
    bundle, policy, builds_on, grading = (table.get(key, {}) for key in ("bundle", "policy", "builds_on", "grading"))
    if not all(isinstance(t, dict) for t in (bundle, policy, builds_on, grading)):
        raise _fail(path, "[bundle], [policy], [builds_on] and [grading] must be tables")
    if set(grading) - _GRADING_KEYS:
        raise _fail(path, f"[grading] has unknown keys {sorted(set(grading) - _GRADING_KEYS)} (it declares {sorted(_GRADING_KEYS)})")
    steps = _strings(path, grading, "steps")
    bad_steps = [s for s in steps if not _STEP.match(s)]
    if bad_steps:
        raise _fail(path, f"[grading] steps must read 'module:function' (a module of the pack's folder), got {bad_steps!r}")
    if set(bundle) - _BUNDLE_KEYS:
        raise _fail(path, f"[bundle] has unknown keys {sorted(set(bundle) - _BUNDLE_KEYS)} (it declares {sorted(_BUNDLE_KEYS)})")
    for key, rows in (("policy", policy), ("builds_on", builds_on)):
        stray = sorted(set(rows) - set(seen))
        if stray:
            raise _fail(path, f"[{key}] names functions no stage grades: {stray}")
    if policy and set(policy) != set(seen):
        raise _fail(path, f"[policy] must give every graded function a row (missing: {sorted(set(seen) - set(policy))})")
    notebooks = _file(path, _string(path, table, "notebooks", f"../../notebooks/{name}"), "notebooks")
    return Assignment(
        name=name,
        title=_string(path, table, "title", name) or name,
        folder=path.parent,
        notebooks=notebooks,
        stages=tuple(stages),
        reference=_string(path, table, "reference", "reference") or "reference",
        checks=_string(path, table, "checks", "checks") or "checks",
        pictures=_string(path, table, "pictures"),
        contract=_file(path, _string(path, table, "contract"), "contract"),
        hidden_packages=_strings(path, table, "hidden_packages", _FUNCTION),
        preload=_strings(path, table, "preload"),
        data=_strings(path, table, "data"),
        readme=_file(path, _string(path, bundle, "readme"), "bundle.readme"),
        bundle_files=tuple(_file(path, f, "bundle.files") for f in _strings(path, bundle, "files")),
        demos=_strings(path, bundle, "demos", _FUNCTION),
        policy={f: _strings(path, policy, f) for f in policy},
        builds_on={f: _strings(path, builds_on, f, _FUNCTION) for f in builds_on},
        steps=steps,
    )


# --- discovery ---------------------------------------------------------------------------------


@functools.lru_cache(maxsize=8)
def _discover(course: Path) -> tuple[tuple[Assignment, ...], str | None]:
    try:
        settings = course_settings(course)
    except SettingsError as exc:
        raise PackError(str(exc)) from None
    config_file = course / CONFIG_FILE
    if settings.course_packs is None:
        folders = sorted(p.parent for p in course.glob(f"*/{MANIFEST}"))
    else:
        folders = [(course / p).resolve() for p in settings.course_packs]
    found = tuple(load_pack(f) for f in folders)
    names = [a.name for a in found]
    if len(set(names)) != len(names):
        raise PackError(f"{course}: two course packs declare the same assignment: {names}")
    for declared in found:
        if declared.policy:
            _declare_policy(declared)
    default = settings.default_assignment
    if default is not None and default not in names:
        raise PackError(f"{config_file}: c.DeformLab.default_assignment = {default!r} is not a pack ({names})")
    stray = sorted(set(settings.stages) - set(names))
    if stray:
        raise PackError(f"{config_file}: c.DeformLab.stages names {stray[0]!r}, which is not an assignment of the course ({names})")
    found = tuple(_selected(a, settings.stages[a.name], config_file) if a.name in settings.stages else a for a in found)
    return found, default


def _selected(course: Assignment, chosen: list[str], config_file: Path) -> Assignment:
    """``course`` with only the stages ``chosen`` (``c.DeformLab.stages``), kept in teaching order."""
    unknown = [s for s in chosen if s not in course.stage_names]
    if unknown:
        raise PackError(f"{config_file}: c.DeformLab.stages[{course.name!r}] names {unknown[0]!r}, "
                        f"which is not a stage of {course.name} (its stages: {list(course.stage_names)})")
    if len(set(chosen)) != len(chosen):
        raise PackError(f"{config_file}: c.DeformLab.stages[{course.name!r}] names a stage twice: {chosen}")
    return dataclasses.replace(course, stages=tuple(s for s in course.stages if s.notebook in chosen))


def _declare_policy(course: Assignment) -> None:
    """The pack's ``[policy]`` rows in the library policy of this process (the kernels get them from the notebooks)."""
    from starter import library_policy

    try:
        library_policy.declare(course.policy, course.builds_on)
    except ValueError as exc:
        raise _fail(course.folder / MANIFEST, f"[policy]: {exc}") from None


def _course_folder() -> Path:
    """The course folder of this process, resolved once per (DEFORMLAB_ROOT, working folder):
    grading asks for packs per case and per row, and resolving may read nbgrader_config.py."""
    return _resolved_course(os.environ.get(ROOT_VARIABLE), os.getcwd())


@functools.lru_cache(maxsize=8)
def _resolved_course(root: str | None, cwd: str) -> Path:
    return course_paths().course.resolve()


def packs() -> dict[str, Assignment]:
    """Every assignment of the course this process grades, by name."""
    return {a.name: a for a in _discover(_course_folder())[0]}


def default_assignment() -> str:
    """The assignment commands use when none is given."""
    found, default = _discover(_course_folder())
    if not found:
        raise PackError(f"{_course_folder()}: the course has no course pack (no */{MANIFEST})")
    return default or found[0].name


def pack(name: str | None = None) -> Assignment:
    """The course pack of assignment ``name`` (the default assignment for ``None``).

    Raises
    ------
    PackError
        If the course has no pack of that name.
    """
    name = default_assignment() if name is None else name
    found = packs()
    if name not in found:
        raise PackError(f"no course pack declares assignment {name!r} (the course's assignments: {sorted(found)})")
    return found[name]


def pack_of_source(path: str | Path) -> Assignment:
    """The course pack whose notebooks folder holds the authored notebook ``path``.

    Raises
    ------
    PackError
        If no pack of the course lists that folder.
    """
    folder = Path(path).resolve().parent
    for found in packs().values():
        if found.notebooks == folder:
            return found
    raise PackError(f"{path}: no course pack of the course takes its notebooks from {folder}")


def is_bonus(assignment: str | None, notebook: str) -> bool:
    """Whether ``notebook``'s points are extra credit in ``assignment`` (None: the default assignment; False for an unknown one)."""
    found = packs().get(default_assignment() if assignment is None else assignment)
    return found is not None and found.is_bonus(notebook)


def forget() -> None:
    """Drop what discovery cached (after a test or a command changes the course folder)."""
    _resolved_course.cache_clear()
    _discover.cache_clear()


# --- importing a pack's code ---------------------------------------------------------------------


class _PackFinder(importlib.abc.MetaPathFinder):
    """``deformlab_packs`` is an empty package; ``deformlab_packs.<name>`` is the folder of that pack."""

    def find_spec(self, fullname: str, path: Any = None, target: Any = None):
        if fullname == PACKAGE:
            return _namespace(PACKAGE, [])
        parent, _, name = fullname.rpartition(".")
        if parent != PACKAGE:
            return None
        found = packs().get(name)
        if found is None:
            return None
        init = found.folder / "__init__.py"
        if init.is_file():
            return importlib.util.spec_from_file_location(fullname, init, submodule_search_locations=[str(found.folder)])
        return _namespace(fullname, [str(found.folder)])


def _namespace(name: str, locations: list[str]) -> importlib.machinery.ModuleSpec:
    spec = importlib.machinery.ModuleSpec(name, importlib.machinery.NamespaceLoader(name, locations, None), is_package=True)
    spec.submodule_search_locations = locations
    return spec


_FINDER = _PackFinder()


def _install_finder() -> None:
    if _FINDER not in sys.meta_path:
        sys.meta_path.append(_FINDER)

_install_finder()
