"""check_notebook.py names the library routine a student's function may not use, and only that function fails."""

import copy

import nbformat

from grader.build.authored import BEGIN_SOLUTION, END_SOLUTION
from grader.cli import main
from starter.library_policy import message

PROCRUSTES = '''import numpy as np
from scipy.linalg import orthogonal_procrustes


def optimal_orthogonal(S):
    return orthogonal_procrustes(np.eye(len(S)), np.asarray(S, dtype=float).T)[0]
'''


def test_a_function_calling_a_forbidden_routine_fails_its_tests_cell_with_the_policys_message(source_notebooks, tmp_path, capsys):
    from nbgrader.preprocessors import ClearHiddenTests

    nb, _ = ClearHiddenTests().preprocess(copy.deepcopy(nbformat.read(source_notebooks["01_shape_matching"], as_version=4)), {})
    for cell in nb.cells:  # the teaching solutions, as a student hands them in; one shortcut
        grade_id = (cell.metadata.get("nbgrader") or {}).get("grade_id", "")
        if grade_id == "solution_optimal_orthogonal":
            cell.source = PROCRUSTES
        elif grade_id.startswith("solution_"):
            cell.source = "\n".join(l for l in cell.source.splitlines() if l.strip() not in (BEGIN_SOLUTION, END_SOLUTION))
    path = tmp_path / "01_shape_matching.ipynb"
    nbformat.write(nb, path)
    assert main(["check", str(path)]) == 1
    out = capsys.readouterr().out
    rows = {line.split()[0]: line.split()[1] for line in out.splitlines()[1:-2] if len(line.split()) > 1 and not line.startswith(" ")}
    assert rows == {"centroid": "pass", "covariance_matrix": "pass", "optimal_orthogonal": "FAIL", "orthogonal_align": "pass"}
    expected = message("optimal_orthogonal", "scipy.linalg.orthogonal_procrustes")
    assert expected.split(",")[0] in out and "LIBRARY_POLICY.md" in out
    assert out.strip().splitlines()[-2].startswith("library policy: optimal_orthogonal calls a routine LIBRARY_POLICY.md")
    assert out.strip().splitlines()[-1] == "3 passed, 1 failed"
