"""The library-call policy: its table is the contract file's, and its wrappers record exactly who called what."""

from __future__ import annotations

import importlib
import json
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from grader.course_pack import pack
_COURSE = pack("deformation")
CONTRACT_NAMES = _COURSE.function_names
from starter import library_policy
from starter.library_policy import BUILDS_ON, OWN, ROUTINES, forbidden

ROOT = Path(__file__).resolve().parents[2]
POLICY_MD = ROOT / "LIBRARY_POLICY.md"


def _names(cell: str) -> tuple[str, ...]:
    return tuple(re.findall(r"`([^`]+)`", cell))


def test_library_policy_md_lists_exactly_the_table_of_starter_library_policy():
    rows = {}
    for line in POLICY_MD.read_text().splitlines():
        found = re.match(r"^\| `([a-z_]+)` \|(.*)\|(.*)\|$", line)
        if found:
            assert found[1] not in rows, f"{found[1]} has two rows"
            rows[found[1]] = (_names(found[2]), _names(found[3]))
    # the deformation course's table (other packs declare their own rows: test below)
    assert rows == {f: (OWN[f], BUILDS_ON[f]) for f in CONTRACT_NAMES}


def test_every_graded_function_of_the_three_contract_files_has_a_policy_and_builds_only_on_graded_functions():
    assert set(CONTRACT_NAMES) <= set(OWN) and set(OWN) == set(BUILDS_ON)
    assert all(set(BUILDS_ON[f]) <= set(CONTRACT_NAMES) for f in CONTRACT_NAMES)
    for function in OWN:  # no cycle: forbidden() terminates and contains each base's routines
        assert all(set(forbidden(b)) <= set(forbidden(function)) for b in BUILDS_ON[function])


def test_every_routine_of_the_policy_exists_where_its_students_would_call_it():
    for routine in sorted(ROUTINES):
        module, _, name = routine.rpartition(".")
        owner = None
        while module:  # the longest importable prefix is the module, the rest are attributes (a class)
            try:
                owner = importlib.import_module(module)
                break
            except ImportError:
                module, _, outer = module.rpartition(".")
                name = f"{outer}.{name}"
        for part in name.split("."):
            owner = getattr(owner, part)
        assert callable(owner), routine


def test_the_issues_shortcuts_are_forbidden_and_general_tools_are_not():
    assert "igl.cotmatrix" in forbidden("cotangent_laplacian") and "igl.cotmatrix" in forbidden("biharmonic_matrix")
    assert "igl.massmatrix" not in forbidden("biharmonic_matrix")  # the contract defines M with it
    assert "igl.massmatrix" in forbidden("tet_biharmonic_matrix")  # tet_mass_matrix is graded
    assert "scipy.linalg.polar" in forbidden("tet_arap_rotations") and "scipy.linalg.polar" in forbidden("arap_solve")
    assert "scipy.spatial.transform.Rotation.from_matrix" not in forbidden("dual_quaternions")
    for function in CONTRACT_NAMES:
        assert not {r for r in forbidden(function) if r.startswith(("numpy.", "scipy.sparse", "scipy.optimize"))}


def test_a_course_pack_declares_its_own_rows_and_a_conflicting_row_is_refused():
    from grader.course_pack import pack

    smoothing = pack("smoothing")  # discovery declared its [policy] table
    assert set(smoothing.functions) <= set(OWN)
    assert "igl.cotmatrix" in forbidden("cotangent_matrix") and "scipy.sparse.csgraph.laplacian" in forbidden("uniform_laplacian")
    library_policy.declare(smoothing.policy, smoothing.builds_on)  # the same rows again: nothing changes
    with pytest.raises(ValueError, match="already has 'cotangent_laplacian' with other routines"):
        library_policy.declare({"cotangent_laplacian": ()})
    with pytest.raises(ValueError, match=r"knows no graded function \['nowhere'\]"):
        library_policy.declare({"fresh_function": ()}, {"fresh_function": ("nowhere",)})
    assert "fresh_function" not in OWN


def test_the_message_names_the_function_the_routine_and_the_function_to_call_instead():
    assert library_policy.message("cotangent_laplacian", "igl.cotmatrix") == (
        "cotangent_laplacian calls igl.cotmatrix, which computes its answer or its defining step: "
        "the course's library policy (LIBRARY_POLICY.md) does not allow it here"
    )
    assert "call your own cotangent_laplacian" in library_policy.message("biharmonic_matrix", "igl.cotmatrix")


def test_the_policy_section_of_a_notebook_lists_each_of_its_functions_once():
    text = library_policy.markdown(["centroid", "optimal_rotation"])
    assert "| `centroid` | no restriction |" in text
    assert "`scipy.linalg.polar`" in text.split("| `optimal_rotation` |")[1]


# Every way to reach a routine the issue names, in a fresh interpreter (install() changes it for good).
SCENARIOS = r"""
import functools, importlib, importlib.util, json, sys
from starter import library_policy as lp, shapes
lp.install()
import igl, numpy as np
from igl import cotmatrix as c
V, F = shapes.grid_2d(4, 3)
ns = {}
results = {}

def run(label, function, call):
    lp.reset(ns, function)
    call()
    results[label] = lp.violations()

early = c(V, F)
ns["cotangent_laplacian"] = lambda V, F: c(V, F)
run("alias taken before", "cotangent_laplacian", lambda: ns["cotangent_laplacian"](V, F))
ns["cotangent_laplacian"] = lambda V, F: getattr(igl, "cot" + "matrix")(V, F)
run("getattr", "cotangent_laplacian", lambda: ns["cotangent_laplacian"](V, F))
ns["cotangent_laplacian"] = lambda V, F: importlib.import_module("igl").cotmatrix(V, F)
run("importlib", "cotangent_laplacian", lambda: ns["cotangent_laplacian"](V, F))
ns["cotangent_laplacian"] = lambda V, F: igl.pyigl_core.cotmatrix(V, F)
run("extension module", "cotangent_laplacian", lambda: ns["cotangent_laplacian"](V, F))
del sys.modules["igl.pyigl_core"]
fresh = importlib.import_module("igl.pyigl_core")
ns["cotangent_laplacian"] = lambda V, F: fresh.cotmatrix(V, F)
run("extension module imported again", "cotangent_laplacian", lambda: ns["cotangent_laplacian"](V, F))
spec = importlib.util.spec_from_file_location("igl.pyigl_core", igl.pyigl_core.__file__)
built = importlib.util.module_from_spec(spec)
ns["cotangent_laplacian"] = lambda V, F: built.cotmatrix(V, F)
run("extension module built from its file", "cotangent_laplacian", lambda: ns["cotangent_laplacian"](V, F))
import scipy.linalg  # imported first after install(): the loaders wrap it
del sys.modules["scipy.linalg._procrustes"], sys.modules["scipy.linalg"]
import scipy.linalg
ns["optimal_orthogonal"] = lambda S: scipy.linalg.orthogonal_procrustes(np.eye(3), S.T)[0]
run("scipy imported again", "optimal_orthogonal", lambda: ns["optimal_orthogonal"](np.eye(3)))
ns["cotangent_laplacian"] = igl.cotmatrix
run("the routine under the contract name", "cotangent_laplacian", lambda: ns["cotangent_laplacian"](V, F))
ns["unconstrained_biharmonic_weights"] = functools.partial(igl.harmonic, k=2)
b = np.array([0, len(V) - 1]); bc = np.eye(2)
run("a partial", "unconstrained_biharmonic_weights", lambda: ns["unconstrained_biharmonic_weights"](V, F, b, bc))

def helper(V, F):
    return igl.cotmatrix(V, F)
def cotangent_laplacian(V, F):
    return helper(V, F)
def biharmonic_matrix(V, F):
    return cotangent_laplacian(V, F)
def lbs(V, W):  # allows igl.cotmatrix: it does not launder a call made for cotangent_laplacian
    return igl.cotmatrix(V, F)
def cotangent_laplacian_via_lbs(V, F):
    return lbs(V, None)
ns.update(cotangent_laplacian=cotangent_laplacian, biharmonic_matrix=biharmonic_matrix, lbs=lbs)
run("a helper", "cotangent_laplacian", lambda: cotangent_laplacian(V, F))
run("a graded function it calls", "biharmonic_matrix", lambda: biharmonic_matrix(V, F))
ns["cotangent_laplacian"] = cotangent_laplacian_via_lbs
run("through a function that allows it", "cotangent_laplacian", lambda: cotangent_laplacian_via_lbs(V, F))
run("at top level", None, lambda: igl.cotmatrix(V, F))
from scipy.spatial.transform import Rotation
ns["dual_quaternions"] = lambda T: Rotation.from_matrix(T).as_quat()
run("allowed conversion", "dual_quaternions", lambda: ns["dual_quaternions"](np.eye(3)))
ns["optimal_rotation"] = lambda S: Rotation.from_matrix(S.T).as_matrix()
run("the same routine where it fits", "optimal_rotation", lambda: ns["optimal_rotation"](np.eye(3)))
from concurrent.futures import ThreadPoolExecutor
ns["cotangent_laplacian"] = lambda V, F: ThreadPoolExecutor(1).submit(igl.cotmatrix, V, F).result()
run("another thread", "cotangent_laplacian", lambda: ns["cotangent_laplacian"](V, F))
results["same result"] = [bool(abs(igl.cotmatrix(V, F) - early).max() == 0)]
print(json.dumps(results))
"""


@pytest.fixture(scope="module")
def scenarios() -> dict:
    done = subprocess.run([sys.executable, "-c", SCENARIOS], capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.splitlines()[-1])


@pytest.mark.parametrize(
    "label, expected",
    [
        ("alias taken before", [["cotangent_laplacian", "igl.cotmatrix"]]),
        ("getattr", [["cotangent_laplacian", "igl.cotmatrix"]]),
        ("importlib", [["cotangent_laplacian", "igl.cotmatrix"]]),
        ("extension module", [["cotangent_laplacian", "igl.cotmatrix"]]),
        ("extension module imported again", [["cotangent_laplacian", "igl.cotmatrix"]]),
        ("extension module built from its file", [["cotangent_laplacian", "igl.cotmatrix"]]),
        ("scipy imported again", [["optimal_orthogonal", "scipy.linalg.orthogonal_procrustes"]]),
        ("the routine under the contract name", [["cotangent_laplacian", "igl.cotmatrix"]]),
        ("a partial", [["unconstrained_biharmonic_weights", "igl.harmonic"]]),
        ("a helper", [["cotangent_laplacian", "igl.cotmatrix"]]),
        ("a graded function it calls", [["cotangent_laplacian", "igl.cotmatrix"]]),
        ("through a function that allows it", [["cotangent_laplacian", "igl.cotmatrix"]]),
        ("at top level", []),
        ("allowed conversion", []),
        ("the same routine where it fits", [["optimal_rotation", "scipy.spatial.transform.Rotation.from_matrix"]]),
        ("another thread", [["cotangent_laplacian", "igl.cotmatrix"]]),
        ("same result", [True]),
    ],
)
def test_a_forbidden_routine_is_charged_to_the_graded_function_that_called_it(scenarios, label, expected):
    assert scenarios[label] == expected


CHECKS = r"""
import json
from starter import library_policy as lp, shapes
import igl
V, F = shapes.grid_2d(3, 3)
out0 = len(V) + len(F) - 1  # edges of a disk: V - E + F = 1

def cotangent_laplacian(V, F):
    return igl.cotmatrix(V, F)

def edges(F):
    return sorted({tuple(sorted((int(a), int(b)))) for t in F for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))})

out = {"expected edges": out0}
try:
    lp.check("cotangent_laplacian", cotangent_laplacian, V, F)
except AssertionError as exc:
    out["refused"] = str(exc)
out["honest"] = len(lp.check("edges", edges, F))
out["nothing left over"] = lp.violations()
print(json.dumps(out))
"""


def test_check_fails_naming_the_routine_and_returns_an_honest_functions_result():
    done = subprocess.run([sys.executable, "-c", CHECKS], capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert done.returncode == 0, done.stderr
    out = json.loads(done.stdout.splitlines()[-1])
    assert out["refused"] == library_policy.message("cotangent_laplacian", "igl.cotmatrix")
    assert out["honest"] == out["expected edges"]
    assert out["nothing left over"] == []


def test_install_wraps_every_routine_where_it_lives_also_in_modules_imported_later_and_hands_out_no_original():
    code = textwrap.dedent(
        """
        import importlib, json, sys
        import igl  # imported before install(): wrapped by it
        from starter import library_policy as lp
        lp.install()
        for name in lp._MODULES:  # imported after: wrapped by the loaders
            importlib.import_module(name)
        missing = []
        for routine in sorted(lp.ROUTINES):
            for location in lp._locations(routine):
                module, attribute = location.split(":")
                owner = sys.modules.get(module)
                for part in attribute.split("."):
                    owner = getattr(owner, part, None)
                if getattr(owner, "__deformlab_routine__", None) != routine:
                    missing.append(location)
                if hasattr(owner, "__wrapped__"):
                    missing.append(location + " hands out __wrapped__")
        print(json.dumps(missing))
        """
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout.splitlines()[-1]) == []
