"""The authoring rules of notebooks/README.md are enforced with messages naming the cell."""

import pytest

from grader.course_pack import pack
from grader.build.authored import AuthoringError, read_authored, solution_body
from grader.build.source_notebook import build_source_notebook

HEADER = "# %% [markdown]\n# Title\n\n# %%\nimport numpy as np\n\n"

CENTROID = '''# %% deformlab={"solution": "centroid"}
def centroid(P, w=None):
    """The mean of the rows of P."""
    ### BEGIN SOLUTION
    return np.mean(P, axis=0)
    ### END SOLUTION
'''

CENTROID_TESTS = '''
# %% deformlab={"tests": "centroid", "points": 2}
_c = centroid(np.ones((3, 2)))
assert _c.shape == (2,)
'''


def write(tmp_path, body: str, name: str = "09_example"):
    path = tmp_path / f"{name}.py"
    path.write_text(HEADER + body)
    return path


def test_a_well_formed_notebook_lists_its_functions_in_order(tmp_path):
    nb = read_authored(write(tmp_path, CENTROID + CENTROID_TESTS + '''
# %% [markdown] deformlab={"answer": "why", "points": 1}
# Because.
'''))
    assert nb.functions == ["centroid"]
    assert [c.kind for c in nb.cells] == ["text", "provided", "solution", "tests", "answer"]


def test_the_solution_cell_is_the_teaching_code_and_its_body_is_what_the_release_drops(tmp_path):
    nb = read_authored(write(tmp_path, CENTROID + CENTROID_TESTS))
    solution = next(c for c in nb.cells if c.kind == "solution")
    assert solution.source.strip() == CENTROID.split("\n", 1)[1].strip()
    assert solution_body(solution.source).strip() == "return np.mean(P, axis=0)"
    cell = build_source_notebook(nb).cells[4]  # after the text, the policy's section and its cell, the provided cell
    assert cell.source == solution.source and cell.metadata["nbgrader"]["grade_id"] == "solution_centroid"


def test_an_exercise_cell_is_student_code_that_nothing_grades(tmp_path):
    nb = read_authored(write(tmp_path, CENTROID + CENTROID_TESTS + '''
# %% deformlab={"exercise": "twist"}
for k in range(2):
    ### BEGIN SOLUTION
    c = centroid(np.ones((3, 2)) * k)
    ### END SOLUTION
    print(c)
'''))
    exercise = nb.cells[-1]
    assert exercise.kind == "exercise" and solution_body(exercise.source).strip() == "c = centroid(np.ones((3, 2)) * k)"
    meta = build_source_notebook(nb).cells[-1].metadata["nbgrader"]
    assert meta["grade_id"] == "exercise_twist"
    assert meta["solution"] and not meta["grade"] and not meta["locked"]
    assert nb.functions == ["centroid"]


def _solution(body: str) -> str:
    return '# %% deformlab={"solution": "centroid"}\n' + body + CENTROID_TESTS


@pytest.mark.parametrize(
    "body, message",
    [
        (_solution(""), "only imports and def centroid"),
        (_solution("x = 1\n"), "only imports and def centroid"),
        (_solution("def centroid(P, w=None):\n    ### BEGIN SOLUTION\n    return P\n    ### END SOLUTION\n"), "needs a docstring"),
        (_solution('def centroid(P, w=None):\n    """Mean."""\n    return P\n'), "needs one ### BEGIN SOLUTION"),
        (_solution('def centroid(P, w=None):\n    """Mean."""\n    P = P\n    ### BEGIN SOLUTION\n    return P\n    ### END SOLUTION\n'),
         "must enclose the whole body"),
        (_solution('def centroid(P, w=None):\n    """Mean."""\n    ### BEGIN SOLUTION\n    return centroid_of(P)\n    ### END SOLUTION\n\n\n'
                   'def centroid_of(P):\n    return P\n'), "only imports and def centroid"),
        (_solution('def centroid(P, w=None):\n    """Mean."""\n    ### BEGIN SOLUTION\n    return covariance_matrix(P, P)\n    ### END SOLUTION\n'),
         "uses covariance_matrix before its solution cell"),
        ('# %% deformlab={"solution": "no_such_function"}\n', "not a contract function"),
        ('# %%\ndef centroid(P):\n    return P\n', "defines the contract name"),
        ('# %%\ncentroid(np.ones((2, 2)))\n', "before its solution cell"),
        (CENTROID + '\n# %% deformlab={"tests": "centroid", "points": 0}\nassert True\n', "positive points"),
        (CENTROID + '\n# %% deformlab={"tests": "centroid", "points": 1}\nresult = 1\n', "must start with '_'"),
        (CENTROID, "no tests cell for centroid"),
        (CENTROID + "\n" + CENTROID, "second solution cell"),
        ('# %% deformlab={"exercise": "twist"}\nx = 1\n', "exercise cell needs one non-empty"),
        ('# %% deformlab={"exercise": "twist"}\n### BEGIN SOLUTION\n### END SOLUTION\n', "exercise cell needs one non-empty"),
        (CENTROID + CENTROID_TESTS + '\n# %% deformlab={"exercise": "twist"}\n### BEGIN SOLUTION\ndef centroid(P):\n    return P\n'
         '### END SOLUTION\n', "an exercise cell defines the contract name"),
    ],
)
def test_broken_rules_are_refused_with_a_message_naming_them(tmp_path, body, message):
    with pytest.raises(AuthoringError, match=message):
        read_authored(write(tmp_path, body))


def test_a_function_of_an_earlier_stage_is_checked_but_not_graded_again(tmp_path):
    public = CENTROID + '\n# %% deformlab={"tests": "centroid"}\nassert centroid(np.ones((3, 2))).shape == (2,)\n'
    nb = build_source_notebook(read_authored(write(tmp_path, public, "02_sign_correction")))
    check = nb.cells[5].metadata["nbgrader"]
    assert check == {"grade": False, "grade_id": "public_check_centroid", "locked": True, "schema_version": 3, "solution": False}
    assert "HIDDEN" not in nb.cells[5].source
    with pytest.raises(AuthoringError, match="graded in 01_shape_matching"):
        read_authored(write(tmp_path, CENTROID + CENTROID_TESTS, "02_sign_correction"))


def test_the_library_policy_follows_the_first_text_and_every_tests_cell_checks_it(tmp_path):
    from starter.library_policy import markdown

    nb = build_source_notebook(read_authored(write(tmp_path, CENTROID + CENTROID_TESTS)))
    assert nb.cells[1].source.startswith("**How your functions are graded.**")
    assert nb.cells[1].source.endswith("\n\n" + markdown(["centroid"]))
    assert "library_policy.install()" in nb.cells[2].source and nb.cells[2].metadata["nbgrader"]["locked"]
    tests = next(c for c in nb.cells if c.metadata.get("nbgrader", {}).get("grade_id") == "test_centroid")
    public = tests.source.split("### BEGIN HIDDEN TESTS")[0].strip().splitlines()
    assert public[2] == "_library_policy.watch('centroid')  # the library policy: routines it may not use"
    assert public[-1] == "_library_policy.verdict('centroid')"
    other = build_source_notebook(read_authored(write(tmp_path, CENTROID + CENTROID_TESTS, "10_other")))
    assert other.cells[2].metadata["nbgrader"]["grade_id"] != nb.cells[2].metadata["nbgrader"]["grade_id"]


def test_each_notebook_says_how_a_bug_is_charged_and_which_copied_functions_earn_nothing():
    from grader.build.source_notebook import grading_rules

    arap = grading_rules(pack("deformation"), "03b_arap_global", ["optimal_rotation", "cotangent_weights", "arap_precompute", "arap_global_step"])
    assert "A bug is charged once." in arap
    assert "(`optimal_rotation`, `cotangent_weights`) earn no points here" in arap
    assert "`arap_precompute` returns is your own design: it is checked through your own `arap_global_step`" in arap
    assert "earn no points here" not in grading_rules(pack("deformation"), "00_meshes", ["edges", "genus"])


def test_an_error_names_the_file_and_the_line_the_instructor_edits(tmp_path):
    broken = CENTROID.replace("return np.mean(P, axis=0)", "return np.mean(P, axis=0")
    path = write(tmp_path, broken + CENTROID_TESTS)
    with pytest.raises(AuthoringError) as caught:
        read_authored(path)
    lines = path.read_text().splitlines()
    first = lines.index("def centroid(P, w=None):") + 1
    assert str(caught.value).startswith(f"{path}:{first} (cell 3): syntax error")
    assert "line 4 of the cell" in str(caught.value)  # the unclosed call, on the file's line first + 3


def test_an_error_in_a_later_cell_names_that_cells_line(tmp_path):
    early = '''
# %%
_early = centroid(np.ones((2, 2)))
'''
    path = write(tmp_path, early + CENTROID + CENTROID_TESTS)
    with pytest.raises(AuthoringError, match="uses centroid before its solution cell") as caught:
        read_authored(path)
    line = path.read_text().splitlines().index("_early = centroid(np.ones((2, 2)))") + 1
    assert str(caught.value).startswith(f"{path}:{line} (cell 3)")
