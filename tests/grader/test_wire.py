"""Fixtures travel to the kernel and raw outputs come back as plain, untrusted data."""

import numpy as np
import pytest
import scipy.sparse as sp

from grader.harness.fixtures import Case, Ref, Step, write_fixtures
from grader.harness.outputs import OutputError, read_outputs
import grader.harness.kernel_side as kernel_side


def collect(namespace: dict, function: str, cases, tmp_path):
    """Run the kernel side in a namespace standing in for the student's kernel."""
    fixtures, outputs = tmp_path / "fixtures", tmp_path / "outputs"
    outputs.mkdir()
    write_fixtures(function, cases, fixtures)
    source = open(kernel_side.__file__).read()
    exec(compile(source, "<kernel_side>", "exec"), namespace)
    namespace["__deformlab_collect__"](function, str(fixtures), str(outputs))
    return read_outputs(function, outputs, len(cases))


def test_arrays_scalars_tuples_and_sparse_matrices_round_trip(tmp_path):
    def f(A, k, pair):
        return (A * 2, k + 1, sp.csr_matrix(np.eye(3)), float(pair[0].sum()), [1.0, 2.0])

    case = Case.call("mixed", "f", np.arange(6.0).reshape(2, 3), 4, (np.ones(2), None))
    got = collect({"f": f}, "f", [case], tmp_path).cases[0].value
    np.testing.assert_array_equal(got[0], np.arange(6.0).reshape(2, 3) * 2)
    assert got[1].shape == () and int(got[1]) == 5
    assert sp.issparse(got[2]) and (got[2] != sp.eye(3)).nnz == 0
    assert float(got[3]) == 2.0
    np.testing.assert_array_equal(got[4], [1.0, 2.0])


def test_steps_can_use_earlier_results_and_fixtures_are_copies(tmp_path):
    def make(V):
        V[0, 0] = 99.0  # a student mutating an input must not change the next step's fixture
        return {"scale": 3.0}

    def use(data, V):
        return V * data["scale"]

    V = np.ones((2, 2))
    case = Case("chain", [Step("make", (V,)), Step("use", (Ref(0), V))])
    got = collect({"make": make, "use": use}, "use", [case], tmp_path).cases[0].value
    np.testing.assert_array_equal(got, np.full((2, 2), 3.0))


def test_exceptions_including_system_exit_fail_only_their_case(tmp_path):
    calls = iter([SystemExit(3), ValueError("bad S"), None])

    def f(x):
        exc = next(calls)
        if exc:
            raise exc
        return x

    cases = [Case.call(str(i), "f", np.ones(2)) for i in range(3)]
    out = collect({"f": f}, "f", cases, tmp_path).cases
    assert out[0].error.startswith("SystemExit") and out[1].error.startswith("ValueError: bad S")
    assert out[2].error is None


def test_lying_objects_arrive_as_plain_arrays_or_as_invalid_output(tmp_path):
    class Liar(np.ndarray):
        def __eq__(self, other):
            return True

    class Opaque:
        def __array__(self, *a, **k):
            raise RuntimeError("no")

    def f(kind):
        return np.zeros(3).view(Liar) if kind == "liar" else Opaque()

    out = collect({"f": f}, "f", [Case.call("liar", "f", "liar"), Case.call("opaque", "f", "opaque")], tmp_path).cases
    assert type(out[0].value) is np.ndarray and not np.array_equal(out[0].value, np.ones(3))
    assert out[1].error is not None and "not a numeric array" in out[1].error or "RuntimeError" in out[1].error


def test_a_missing_function_is_a_failed_case(tmp_path):
    out = collect({}, "f", [Case.call("x", "f", 1)], tmp_path).cases[0]
    assert out.error.startswith("NameError")


def test_tampered_output_files_are_refused_as_a_whole(tmp_path):
    (tmp_path / "f.json").write_text("{not json")
    (tmp_path / "f.npz").write_bytes(b"junk")
    with pytest.raises(OutputError, match="malformed"):
        read_outputs("f", tmp_path, 1)


def test_pickled_object_arrays_are_never_loaded(tmp_path):
    np.savez(tmp_path / "f.npz", c0=np.array([object()], dtype=object))
    (tmp_path / "f.json").write_text('{"records": [{"ok": true, "output": {"kind": "array"}}]}')
    out = read_outputs("f", tmp_path, 1).cases[0]
    assert out.value is None and "could not be read" in out.error
