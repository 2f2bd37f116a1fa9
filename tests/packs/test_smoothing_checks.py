"""The smoothing pack's hidden checks pass the reference and the teaching solutions, fail every buggy corpus entry, and its public tests name each bug first.

The pack is loaded by the engine (``grader.course_pack``, ``grader.checks.all_checks``):
every ``FunctionChecks`` subclass of its ``checks`` package, keyed by (assignment, function). Outputs go through the kernel wire's conversion
(``grader.checks.wire``), so the verdicts are those grading would give.
"""

from __future__ import annotations

import importlib.util
import tomllib
from pathlib import Path

import jupytext
import numpy as np
import pytest

import reference.laplacian_smoothing as ref
from grader.checks import all_checks, evaluate, wire
from grader.course_pack import pack
from grader.checks.base import run_steps
from grader.harness.outputs import CaseOutput

REPO = Path(__file__).resolve().parents[2]
PACK = REPO / "assignments" / "smoothing"
TOML = tomllib.loads((PACK / "assignment.toml").read_text())
NOTEBOOK = (PACK / TOML["notebooks"] / f"{TOML['stages'][0]['notebook']}.py").resolve()
FUNCTIONS = TOML["stages"][0]["functions"]
CORPUS = REPO / "tests" / "corpus" / "smoothing"
#: buggy entry -> words the failing public test's message must contain: it names the mistake, not only the numbers
HINTS = {
    "cot_clamped": "a negative cotangent is kept as is",
    "cot_signed_area": "use its absolute value",
    "explicit_times_mass": "multiplied by the masses",
    "implicit_flat_column": "reshape it to U's shape",
    "implicit_rhs_without_mass": "the right-hand side is M U",
    "uniform_edges_counted_per_triangle": "counted once per triangle",
}


CHECKS = all_checks("smoothing")
_CASES: dict[tuple[str, int], tuple] = {}


def cases_and_expected(function: str, seed: int = 0):
    if (function, seed) not in _CASES:
        cases = CHECKS[function].cases(np.random.default_rng(seed))
        expected = [None if "raises" in c.context else run_steps(c, lambda n: getattr(ref, n)) for c in cases]
        _CASES[function, seed] = (cases, expected)
    return _CASES[function, seed]


def grade(function: str, namespace: dict, seed: int = 0):
    cases, expected = cases_and_expected(function, seed)
    outputs = []
    for case in cases:
        try:
            outputs.append(CaseOutput(wire(run_steps(case, lambda n: namespace[n])), None, None))
        except Exception as exc:  # noqa: BLE001 - a failing implementation fails its case
            outputs.append(CaseOutput(None, f"{type(exc).__name__}: {exc}", None))
    return evaluate(CHECKS[function], cases, outputs, expected)


def authored_cells():
    """``(kind, function, source)`` of every cell of the authored notebook, by its ``deformlab`` metadata."""
    cells = []
    for cell in jupytext.read(NOTEBOOK).cells:
        meta = cell.metadata.get("deformlab") or {}
        if cell.cell_type == "markdown":
            continue
        kind = next((k for k in ("solution", "tests", "exercise") if k in meta), "provided")
        cells.append((kind, meta.get(kind), cell.source))
    return cells


def teaching_namespace() -> dict:
    namespace: dict = {}
    for kind, _, source in authored_cells():
        if kind == "solution":
            exec(compile(source, NOTEBOOK.name, "exec"), namespace)
    return namespace


def corpus_entries(kind: str) -> list[Path]:
    return sorted((CORPUS / kind).glob("*.py"))


def load_entry(path: Path):
    spec = importlib.util.spec_from_file_location(f"smoothing_corpus_{path.parent.name}_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def entry_namespace(entry) -> dict:
    namespace = teaching_namespace()
    for source in entry.SOLUTIONS.values():
        exec(compile(source, "corpus", "exec"), namespace)
    return namespace


def test_the_pack_registers_checks_for_exactly_its_functions():
    assert sorted(CHECKS) == sorted(FUNCTIONS)
    assert all(f in TOML["policy"] for f in FUNCTIONS)
    assert set(FUNCTIONS) <= {n for n in vars(ref) if not n.startswith("_")}
    # taught in this order, each in its own solution cell, and each in the students' contract
    assert [name for kind, name, _ in authored_cells() if kind == "solution"] == FUNCTIONS
    contract = (PACK / TOML["contract"]).read_text()
    assert all(f"`{f}(" in contract for f in FUNCTIONS)


def test_no_function_shares_a_name_with_the_deformation_course():
    """One installation grades both courses: a shared name would be ambiguous."""
    assert not set(FUNCTIONS) & pack("deformation").function_names


@pytest.mark.parametrize("function", FUNCTIONS)
def test_the_reference_passes_every_case(function):
    result = grade(function, vars(ref))
    assert result.fraction == 1.0, result.summary()
    assert len(result.cases) >= 8
    assert any(case.verdicts[0].name.startswith("raises") for case in result.cases), "no ValueError case"


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("function", FUNCTIONS)
def test_the_teaching_solutions_pass_every_case_for_any_seed(function, seed):
    result = grade(function, teaching_namespace(), seed)
    assert result.fraction == 1.0, result.summary()


@pytest.mark.parametrize("path", corpus_entries("buggy"), ids=lambda p: p.stem)
def test_each_buggy_entry_loses_exactly_its_functions(path):
    entry = load_entry(path)
    assert entry.ASSIGNMENT == "smoothing" and entry.NOTEBOOK == TOML["stages"][0]["notebook"]
    assert entry.LOSES and entry.LOSES <= set(FUNCTIONS)
    namespace = entry_namespace(entry)
    for function in FUNCTIONS:
        result = grade(function, namespace)
        if function in entry.LOSES:
            assert result.fraction < 1.0, f"{path.stem}: {function} passed every hidden case"
            failed = [c for c in result.cases if not c.passed]
            # a verdict that names the mistake, not only "differs"
            details = " ".join(c.error or " ".join(v.detail for v in c.verdicts if not v.passed) for c in failed)
            assert details.strip(), f"{path.stem}: failed cases carry no explanation"
        else:
            assert result.fraction == 1.0, f"{path.stem}: {function} should keep full marks: {result.summary()}"


@pytest.mark.parametrize("path", corpus_entries("correct"), ids=lambda p: p.stem)
def test_each_correct_entry_earns_full_marks(path):
    entry = load_entry(path)
    assert entry.ASSIGNMENT == "smoothing" and not entry.LOSES
    namespace = entry_namespace(entry)
    for function in FUNCTIONS:
        result = grade(function, namespace)
        assert result.fraction == 1.0, f"{path.stem}: {function}: {result.summary()}"


@pytest.mark.parametrize("path", corpus_entries("buggy"), ids=lambda p: p.stem)
def test_a_public_test_names_each_bug_first(path, monkeypatch):
    """Every bug the hidden checks catch fails the function's public tests cell, with a message."""
    monkeypatch.setenv("DEFORMLAB_NO_PLOTS", "1")
    entry = load_entry(path)
    namespace: dict = {}
    for function in entry.LOSES:
        for kind, name, source in authored_cells():
            if kind == "solution":
                source = entry.SOLUTIONS.get(name, source)
            if kind == "tests":
                if name != function:
                    continue
                with pytest.raises(AssertionError) as caught:
                    exec(compile(source, NOTEBOOK.name, "exec"), namespace)
                assert HINTS[path.stem] in str(caught.value), f"{path.stem}: the public test of {function} says {caught.value}"
                break
            exec(compile(source, NOTEBOOK.name, "exec"), namespace)


def test_the_teaching_notebook_passes_its_own_public_tests(monkeypatch):
    monkeypatch.setenv("DEFORMLAB_NO_PLOTS", "1")
    namespace: dict = {}
    for _, _, source in authored_cells():
        exec(compile(source, NOTEBOOK.name, "exec"), namespace)  # a failing assert or cell raises here
    assert namespace["radii"][-1] == pytest.approx(1.04 ** -10, rel=1e-3)  # the exercise measured the predicted shrinkage


@pytest.mark.slow
def test_the_notebook_runs_top_to_bottom_in_a_kernel_with_its_pictures(monkeypatch):
    """The authored notebook as a student runs it, teaching solutions in place: no error, every picture a PNG."""
    from nbclient import NotebookClient

    monkeypatch.delenv("DEFORMLAB_NO_PLOTS", raising=False)  # the kernel inherits it: draw the pictures
    nb = jupytext.read(NOTEBOOK)
    NotebookClient(nb, timeout=120, kernel_name="python3", resources={"metadata": {"path": str(REPO)}}).execute()
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    shows = sum(c.source.count("plotting.show_") for c in nb.cells if c.cell_type == "code")
    assert sum("image/png" in o.get("data", {}) for o in outputs) == shows == 5
