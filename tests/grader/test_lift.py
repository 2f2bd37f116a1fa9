"""Reference functions become solution cells with exactly the imports they need."""

import ast

import pytest

from grader.build.lift import BEGIN_SOLUTION, END_SOLUTION, LiftError, lift
from grader.contract import CONTRACT_NAMES, MODULE_OF


@pytest.mark.parametrize("name", sorted(CONTRACT_NAMES))
def test_every_contract_function_lifts_into_a_self_contained_cell(name):
    lifted = lift(name)
    tree = ast.parse(lifted.source)
    defs = [n.name for n in tree.body if isinstance(n, ast.FunctionDef)]
    assert defs == [name], "a solution cell defines exactly its function"
    assert all(isinstance(n, (ast.Import, ast.ImportFrom, ast.FunctionDef)) for n in tree.body)
    assert lifted.source.count(BEGIN_SOLUTION) == 1 and lifted.source.count(END_SOLUTION) == 1
    assert lifted.calls <= CONTRACT_NAMES - {name}
    # Executing the cell with the contract functions it calls defines a working function.
    import reference

    namespace = {c: getattr(reference, c) for c in lifted.calls}
    exec(compile(lifted.source, f"<{name}>", "exec"), namespace)
    assert callable(namespace[name])


def test_the_docstring_stays_outside_the_solution_region():
    source = lift("optimal_rotation").source
    assert source.index('"""') < source.index(BEGIN_SOLUTION)


def test_a_function_using_a_private_module_helper_is_refused(monkeypatch, tmp_path):
    import sys
    import types

    module = types.ModuleType("reference.fake_stage")
    code = "import numpy as np\n_SCALE = 2\n\ndef centroid(P, w=None):\n    return np.mean(P, axis=0) * _SCALE\n"
    path = tmp_path / "fake_stage.py"
    path.write_text(code)
    module.__file__ = str(path)
    exec(compile(code, str(path), "exec"), module.__dict__)
    monkeypatch.setitem(sys.modules, "reference.fake_stage", module)
    monkeypatch.setitem(MODULE_OF, "centroid", "fake_stage")
    with pytest.raises(LiftError, match="_SCALE"):
        lift("centroid")
