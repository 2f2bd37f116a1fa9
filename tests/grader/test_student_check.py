"""`deformlab check` (and the bundle's check_notebook.py) tells a student which functions pass."""

import copy

import nbformat
import pytest

from grader.build.authored import BEGIN_SOLUTION, END_SOLUTION
from grader.cli import main


@pytest.fixture(scope="module")
def student_notebook(source_notebooks, tmp_path_factory):
    """01_shape_matching as a student has it after the release: stubs, public tests only."""
    from nbgrader.preprocessors import ClearHiddenTests, ClearSolutions

    source = nbformat.read(source_notebooks["01_shape_matching"], as_version=4)
    resources = {}
    nb, resources = ClearSolutions(code_stub={"python": "# YOUR CODE HERE\nraise NotImplementedError()"}).preprocess(copy.deepcopy(source), resources)
    nb, resources = ClearHiddenTests().preprocess(nb, resources)
    solutions = {(c.metadata.get("nbgrader") or {}).get("grade_id"): c.source for c in source.cells}
    return nb, tmp_path_factory.mktemp("student"), solutions


def fill(nb, function, solutions):
    """Paste the teaching solution into one solution cell, as a student would (no markers)."""
    nb = copy.deepcopy(nb)
    grade_id = f"solution_{function}"
    cell = next(c for c in nb.cells if (c.metadata.get("nbgrader") or {}).get("grade_id") == grade_id)
    cell.source = "\n".join(l for l in solutions[grade_id].splitlines() if l.strip() not in (BEGIN_SOLUTION, END_SOLUTION))
    return nb


def test_filling_one_function_makes_its_public_tests_pass_and_others_fail(student_notebook, capsys):
    nb, folder, solutions = student_notebook
    path = folder / "01_shape_matching.ipynb"
    nbformat.write(fill(nb, "centroid", solutions), path)
    code = main(["check", str(path)])
    out = capsys.readouterr().out
    lines = {line.split()[0]: line.split()[1] for line in out.splitlines()[1:] if line and line.split()[0] != "0" and len(line.split()) > 1}
    assert code == 1
    assert lines["centroid"] == "pass"
    assert lines["covariance_matrix"] == "FAIL" and "NotImplementedError" in out
    assert out.strip().splitlines()[-1] == "1 passed, 3 failed"


def test_a_complete_notebook_passes_with_exit_status_zero(student_notebook, capsys):
    nb, folder, solutions = student_notebook
    for fn in ("centroid", "covariance_matrix", "optimal_orthogonal", "orthogonal_align"):
        nb = fill(nb, fn, solutions)
    path = folder / "complete.ipynb"
    nbformat.write(nb, path)
    assert main(["check", str(path)]) == 0
    assert capsys.readouterr().out.strip().splitlines()[-1] == "4 passed, 0 failed"


def test_the_bundled_script_explains_itself(repo_root):
    import subprocess
    import sys

    done = subprocess.run([sys.executable, str(repo_root / "grader" / "student_check.py"), "--help"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "usage: python check_notebook.py" in done.stdout and "--timeout" in done.stdout


def test_a_failing_tests_cell_shows_its_whole_message(student_notebook, capsys):
    nb, folder, solutions = student_notebook
    nb = fill(nb, "centroid", solutions)
    cell = next(c for c in nb.cells if (c.metadata.get("nbgrader") or {}).get("grade_id") == "test_covariance_matrix")
    hint = "first line of the hint\n" + "a second line that is long " * 10 + "END-OF-HINT"
    cell.source = f"raise AssertionError({hint!r})"
    path = folder / "long_message.ipynb"
    nbformat.write(nb, path)
    main(["check", str(path)])
    out = capsys.readouterr().out
    assert "first line of the hint" in out and "END-OF-HINT" in out
    assert max(len(line) for line in out.splitlines()) < 140
