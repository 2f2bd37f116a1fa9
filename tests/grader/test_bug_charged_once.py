"""A bug is charged once: a caller is judged with the student's own outputs of the course functions it calls.

The collector (``grader/harness/kernel_side.py``) runs here on a namespace of
student functions, as it runs in the kernel; the grader reads what it wrote and
judges it (``grader/checks/callees.py``). The corpus (tests/corpus/buggy) shows
the same on real notebooks, graded in the sandbox.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

import grader.harness.kernel_side as kernel_side
from grader.checks import callees, seeded_cases
from grader.checks.base import run_steps
from grader.course_pack import pack
_COURSE = pack("deformation")
CONTRACT_NAMES = _COURSE.function_names
reference_function = _COURSE.reference_function
from grader.harness.fixtures import write_fixtures
from grader.harness.outputs import read_outputs
from grader.pipeline.verify import hidden_cases, recording, verify

SEED = 11
ROOT = Path(__file__).resolve().parents[2]

SIGN_FROM_DET = '''
import numpy as np


def optimal_rotation(S):
    S = np.asarray(S, dtype=float)
    U, _, Vt = np.linalg.svd(S)
    D = np.ones(U.shape[:-1])
    D[..., -1] = np.sign(np.linalg.det(S)) + (np.linalg.det(S) == 0)
    return np.swapaxes(Vt, -1, -2) @ (D[..., :, None] * np.swapaxes(U, -1, -2))
'''

PER_VERTEX_ROTATIONS = '''
import numpy as np


def arap_rotations(V, U, F, C):
    S = arap_covariances(V, U, F, C)
    return np.stack([optimal_rotation(S_i) for S_i in S])
'''

STACKED_ROTATIONS = '''
def arap_rotations(V, U, F, C):
    return optimal_rotation(arap_covariances(V, U, F, C))
'''

TRANSPOSED_ROTATIONS = '''
import numpy as np


def arap_rotations(V, U, F, C):
    return np.swapaxes(optimal_rotation(arap_covariances(V, U, F, C)), 1, 2)
'''

HALF_COT_FORGOTTEN = '''
def cotangent_weights(V, F):
    return 2.0 * _reference_cotangent_weights(V, F)
'''

LAPLACIAN_FROM_WEIGHTS = '''
import numpy as np
import scipy.sparse as sp


def cotangent_laplacian(V, F):
    C = cotangent_weights(V, F)
    F = np.asarray(F)
    i = np.concatenate([F[:, 1], F[:, 2], F[:, 0]])
    j = np.concatenate([F[:, 2], F[:, 0], F[:, 1]])
    c = np.concatenate([C[:, 0], C[:, 1], C[:, 2]])
    n = len(V)
    L = sp.coo_matrix((c, (i, j)), shape=(n, n)).tocsr()
    L = L + L.T
    return (L - sp.diags(np.asarray(L.sum(axis=1)).ravel())).tocsr()
'''


def student(*sources: str) -> dict:
    """A kernel namespace: the reference's functions (a correct student), then ``sources`` over them, then the collector."""
    namespace = {name: reference_function(name) for name in CONTRACT_NAMES}
    namespace["_reference_cotangent_weights"] = reference_function("cotangent_weights")
    for source in sources:
        exec(compile(source, "<cell>", "exec"), namespace)
    exec(compile(open(kernel_side.__file__).read(), "<kernel_side>", "exec"), namespace)
    return namespace


def grade(function: str, namespace: dict, tmp_path):
    """Collect ``function`` in ``namespace`` as grading does, read the outputs back and verify them."""
    cases, expected = hidden_cases(function, SEED)
    write_fixtures(function, cases, tmp_path / "fixtures", recording(function, SEED))
    (tmp_path / "outputs").mkdir(parents=True)
    namespace["__deformlab_collect__"](function, str(tmp_path / "fixtures"), str(tmp_path / "outputs"))
    collected = read_outputs(function, tmp_path / "outputs", len(cases), expected)
    return verify(function, SEED, collected, None), collected


@pytest.mark.parametrize("rotations", [STACKED_ROTATIONS, PER_VERTEX_ROTATIONS], ids=["stacked", "per vertex"])
def test_a_wrong_optimal_rotation_costs_arap_rotations_nothing(rotations, tmp_path):
    result, collected = grade("arap_rotations", student(SIGN_FROM_DET, rotations), tmp_path)
    assert result.fraction == 1.0
    rescued = [c for c in result.cases if c.own_work_of]
    assert rescued and all(c.own_work_of == ("optimal_rotation",) for c in rescued)
    assert "judged with your own optimal_rotation" in result.summary()
    assert all(call.name in {"optimal_rotation", "arap_covariances"} for c in collected.cases for call in c.calls)


def test_the_wrong_optimal_rotation_itself_still_loses(tmp_path):
    result, _ = grade("optimal_rotation", student(SIGN_FROM_DET), tmp_path)
    assert result.fraction < 1.0


def test_a_caller_with_its_own_mistake_still_loses_beside_a_wrong_callee(tmp_path):
    result, _ = grade("arap_rotations", student(SIGN_FROM_DET, TRANSPOSED_ROTATIONS), tmp_path)
    assert result.fraction < 1.0


def test_the_same_caller_loses_when_its_callee_is_right_but_it_is_wrong(tmp_path):
    result, _ = grade("arap_rotations", student(TRANSPOSED_ROTATIONS), tmp_path)
    assert result.fraction < 1.0 and not any(c.own_work_of for c in result.cases)


def test_a_laplacian_built_from_doubled_weights_is_judged_on_its_own_assembly(tmp_path):
    result, _ = grade("cotangent_laplacian", student(HALF_COT_FORGOTTEN, LAPLACIAN_FROM_WEIGHTS), tmp_path)
    assert result.fraction == 1.0
    assert {n for c in result.cases for n in c.own_work_of} == {"cotangent_weights"}


def test_a_correct_student_records_calls_and_passes_without_a_rerun(tmp_path):
    result, collected = grade("arap_rotations", student(STACKED_ROTATIONS), tmp_path)
    assert result.fraction == 1.0 and not any(c.own_work_of for c in result.cases)
    assert any(c.calls for c in collected.cases)


def test_a_case_s_own_steps_are_not_recorded_as_calls(tmp_path):
    """arap_global_step's cases run the student's arap_precompute first: that step is not a call to substitute."""
    _, collected = grade("arap_global_step", student(), tmp_path)
    assert not any(call.name == "arap_precompute" for c in collected.cases for call in c.calls)


def test_the_collector_gives_the_student_s_functions_back_after_a_collection(tmp_path):
    namespace = student(SIGN_FROM_DET, STACKED_ROTATIONS)
    before = {n: namespace[n] for n in ("optimal_rotation", "arap_covariances")}
    grade("arap_rotations", namespace, tmp_path)
    assert all(namespace[n] is f for n, f in before.items())


COMPOSITIONS = callees.course_callees(_COURSE).compositions


@pytest.mark.parametrize("function", sorted(COMPOSITIONS))
def test_every_composition_is_the_reference_when_nothing_is_substituted(function):
    cases, expected = seeded_cases(function, 3)
    for case, ref in zip(cases, expected):
        if "raises" in case.context:  # a contract promise for bad input: nothing to compose
            continue
        composed = run_steps(case, callees.course_callees(_COURSE).resolve)
        assert callees.matches_own_work(composed, ref), case.label


def test_the_record_plan_names_the_callees_the_reference_reaches_and_never_the_function_itself():
    plan = recording("arap_solve", SEED)
    assert {"arap_rotations", "arap_global_step", "arap_energy", "optimal_rotation"} <= set(plan["names"])
    assert "arap_solve" not in plan["names"]
    assert recording("optimal_rotation", SEED)["names"] == []


finite = st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False)


@settings(max_examples=60, deadline=None)
@given(arrays(np.float64, st.tuples(st.integers(1, 12), st.integers(1, 4)), elements=finite))
def test_a_sketch_matches_rounding_and_tells_a_real_difference_apart(A):
    ours = kernel_side.__deformlab_sketch__(A, 5)
    assert callees._sketch_matches(ours, kernel_side.__deformlab_sketch__(A * (1 + 1e-13), 5))
    scale = max(np.abs(A).max(), 1.0)
    changed = A.copy()
    changed.flat[len(A.flat) // 2] += 1e-3 * scale
    assert not callees._sketch_matches(ours, kernel_side.__deformlab_sketch__(changed, 5))


@settings(max_examples=30, deadline=None)
@given(arrays(np.float64, st.tuples(st.integers(1, 9), st.integers(1, 9)), elements=finite))
def test_a_sparse_matrix_and_its_dense_copy_have_one_sketch(A):
    dense = kernel_side.__deformlab_sketch__(A, 9)
    sparse = kernel_side.__deformlab_sketch__(sp.coo_matrix(A), 9)
    assert callees._sketch_matches(dense, sparse) and callees._sketch_matches(sparse, dense)


def test_opaque_and_plain_arguments_match_by_kind():
    sketch = kernel_side.__deformlab_sketch__
    assert sketch(object(), 1) == {"opaque": True}
    assert callees._sketch_matches(sketch(None, 1), sketch(None, 1))
    assert not callees._sketch_matches(sketch(None, 1), sketch(np.zeros(3), 1))


def test_forged_call_records_are_left_out_and_never_crash_the_reading(tmp_path):
    namespace = student(SIGN_FROM_DET, STACKED_ROTATIONS)
    grade("arap_rotations", namespace, tmp_path)
    records_path = tmp_path / "outputs" / "arap_rotations.json"
    meta = json.loads(records_path.read_text())
    forged = [
        {"name": "optimal_rotation"},  # a batched call without its items
        {"name": "arap_covariances", "args": [{"shape": [-1], "norm": 1.0, "p": [0, 0]}], "output": {"kind": "array"}},
        {"name": "arap_covariances", "args": [{"shape": [3], "norm": float("nan"), "p": [0, 0]}], "output": {"kind": "array"}},
        {"name": 7, "args": []},
        "not a record",
    ] * 100
    for record in meta["records"]:
        record["calls"] = forged + record.get("calls", [])
    records_path.write_text(json.dumps(meta))
    cases, expected = hidden_cases("arap_rotations", SEED)
    collected = read_outputs("arap_rotations", tmp_path / "outputs", len(cases), expected)
    assert all(len(c.calls) == 0 for c in collected.cases)  # the forged ones fill the first 200 places
    assert verify("arap_rotations", SEED, collected, None).fraction < 1.0


def course_calls() -> set[tuple[str, str, str]]:
    """(notebook, callee, caller): every course function a teaching solution calls, where the caller is graded."""
    from grader.build.authored import read_authored, referenced_names
    from grader.course_pack import pack
    _COURSE = pack("deformation")
    stage_functions = _COURSE.stage_functions

    pairs = set()
    for path in sorted((ROOT / "notebooks" / "deformation").glob("*.py")):
        notebook = read_authored(path)
        graded = set(stage_functions(notebook.name))
        for cell in notebook.cells:
            if cell.kind == "solution" and cell.function in graded:
                for callee in referenced_names(cell.source) & CONTRACT_NAMES - {cell.function}:
                    pairs.add((notebook.name, callee, cell.function))
    return pairs


def test_every_call_between_course_functions_has_a_corpus_bug_charged_to_the_callee_alone():
    """For each (callee, caller) pair of the teaching solutions, a buggy entry breaks the callee and the caller keeps its points."""
    from tests.corpus import load_corpus

    entries = [e for e in load_corpus(ROOT / "tests" / "corpus") if e.kind == "buggy"]
    missing = [
        f"{notebook}: {callee} -> {caller}"
        for notebook, callee, caller in sorted(course_calls())
        if not any(
            e.notebook == notebook and callee in e.solutions and caller not in e.loses
            for e in entries
        )
    ]
    assert not missing, "no corpus entry shows these callers keeping their points beside a buggy callee:\n" + "\n".join(missing)


LAPLACIAN_BY_IGL = '''
import igl


def cotangent_laplacian(V, F):
    return igl.cotmatrix(V, F)
'''

BIHARMONIC_FROM_LAPLACIAN = '''
import igl
import scipy.sparse as sp


def biharmonic_matrix(V, F):
    L = cotangent_laplacian(V, F)
    return L @ sp.diags(1.0 / igl.massmatrix(V, F).diagonal()) @ L
'''


def test_a_forbidden_call_in_a_recorded_callee_is_charged_to_the_callee_alone(tmp_path):
    """The recorders the collector puts around callees do not hide the student's own frames from the library policy."""
    from starter import library_policy

    library_policy.install()
    namespace = student(LAPLACIAN_BY_IGL, BIHARMONIC_FROM_LAPLACIAN)
    callee, _ = grade("cotangent_laplacian", namespace, tmp_path / "callee")
    caller, collected = grade("biharmonic_matrix", namespace, tmp_path / "caller")
    assert callee.policy_violations == ("igl.cotmatrix",) and callee.fraction == 0.0
    assert caller.policy_violations == () and caller.fraction == 1.0
    assert any(call.name == "cotangent_laplacian" for c in collected.cases for call in c.calls)
