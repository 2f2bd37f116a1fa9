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
