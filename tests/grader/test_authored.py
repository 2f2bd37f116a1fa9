"""The authoring rules of notebooks/README.md are enforced with messages naming the cell."""

import textwrap

import pytest

from grader.build.authored import AuthoringError, read_authored

HEADER = "# %% [markdown]\n# Title\n\n# %%\nimport numpy as np\n\n"


def write(tmp_path, body: str):
    path = tmp_path / "09_example.py"
    path.write_text(HEADER + textwrap.dedent(body))
    return path


def test_a_well_formed_notebook_lists_its_functions_in_order(tmp_path):
    nb = read_authored(write(tmp_path, '''
        # %% deformlab={"solution": "centroid"}

        # %% deformlab={"tests": "centroid", "points": 2}
        _c = centroid(np.ones((3, 2)))
        assert _c.shape == (2,)

        # %% [markdown] deformlab={"answer": "why", "points": 1}
        # Because.
        '''))
    assert nb.functions == ["centroid"]
    assert [c.kind for c in nb.cells] == ["text", "provided", "solution", "tests", "answer"]


@pytest.mark.parametrize(
    "body, message",
    [
        ('# %% deformlab={"solution": "centroid"}\nx = 1\n', "must be empty"),
        ('# %% deformlab={"solution": "no_such_function"}\n', "not a contract function"),
        ('# %%\ndef centroid(P):\n    return P\n', "defines the contract name"),
        ('# %%\ncentroid(np.ones((2, 2)))\n', "before its solution cell"),
        ('# %% deformlab={"solution": "centroid"}\n\n# %% deformlab={"tests": "centroid", "points": 0}\nassert True\n', "positive points"),
        ('# %% deformlab={"solution": "centroid"}\n\n# %% deformlab={"tests": "centroid", "points": 1}\nresult = 1\n', "must start with '_'"),
        ('# %% deformlab={"solution": "centroid"}\n', "no tests cell for centroid"),
        ('# %% deformlab={"solution": "centroid"}\n\n# %% deformlab={"solution": "centroid"}\n', "second solution cell"),
    ],
)
def test_broken_rules_are_refused_with_a_message_naming_them(tmp_path, body, message):
    with pytest.raises(AuthoringError, match=message):
        read_authored(write(tmp_path, body))


def test_a_reference_call_without_its_own_solution_cell_is_refused(tmp_path):
    from grader.build.source_notebook import build_source_notebook

    # rigid_align's reference uses other contract functions that this notebook lacks.
    from grader.build.lift import lift

    if not lift("rigid_align").calls:
        pytest.skip("the reference rigid_align calls no other contract function")
    nb = read_authored(write(tmp_path, '''
        # %% deformlab={"solution": "rigid_align"}

        # %% deformlab={"tests": "rigid_align", "points": 2}
        assert rigid_align is not None
        '''))
    with pytest.raises(AuthoringError, match="need their own solution cells"):
        build_source_notebook(nb)


def test_a_lecture_contract_solution_written_in_the_notebook_is_used_as_written(tmp_path):
    from grader.build.source_notebook import build_source_notebook

    solution = 'def dual_quaternions(T):\n    """Doc."""\n    ### BEGIN SOLUTION\n    return T\n    ### END SOLUTION'
    path = tmp_path / "09_example.py"
    path.write_text(
        HEADER + f'# %% deformlab={{"solution": "dual_quaternions"}}\n{solution}\n\n'
        '# %% deformlab={"tests": "dual_quaternions", "points": 1}\nassert dual_quaternions(1) == 1\n'
    )
    nb = read_authored(path)
    source = build_source_notebook(nb)
    assert [c.source for c in source.cells if c.metadata.get("nbgrader", {}).get("grade_id") == "solution_dual_quaternions"] == [solution]


@pytest.mark.parametrize(
    "function, source, message",
    [
        ("centroid", "def centroid(P, w=None):\n    ### BEGIN SOLUTION\n    return P\n    ### END SOLUTION", "must be empty"),
        ("dqs", "def dqs(V, W, T):\n    return V", "needs ### BEGIN/END SOLUTION markers"),
    ],
)
def test_a_written_solution_needs_a_lecture_contract_function_and_markers(tmp_path, function, source, message):
    body = f'# %% deformlab={{"solution": "{function}"}}\n{source}\n'
    path = tmp_path / "09_example.py"
    path.write_text(HEADER + body)
    with pytest.raises(AuthoringError, match=message):
        read_authored(path)
