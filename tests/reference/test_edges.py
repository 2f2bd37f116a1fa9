import igl
import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings, strategies as st

from reference.meshes import edges
from starter.meshes import load_mesh

CLOSED_SURFACES = ["sphere", "ant", "nut", "torus", "bar_coarse", "cylinder"]
COURSE_MESHES = CLOSED_SURFACES + ["disc_with_holes", "character"]


def faces(name):
    return load_mesh(name)[1]


@pytest.mark.parametrize("name", COURSE_MESHES)
def test_edges_are_igl_edges_with_sorted_rows_in_lexicographic_order(name):
    F = faces(name)
    expected = np.unique(np.sort(igl.edges(F), axis=1), axis=0)
    E = edges(F)
    assert E.dtype == np.int64
    np.testing.assert_array_equal(E, expected)


@pytest.mark.parametrize("name", COURSE_MESHES)
def test_rows_are_ascending_and_strictly_lexicographically_increasing(name):
    E = edges(faces(name))
    assert (E[:, 0] < E[:, 1]).all()
    assert (np.diff(E[:, 0]) >= 0).all()
    same_first = np.diff(E[:, 0]) == 0
    assert (np.diff(E[:, 1])[same_first] > 0).all()


@pytest.mark.parametrize("name", CLOSED_SURFACES)
def test_closed_surface_has_three_edges_per_two_faces(name):
    F = faces(name)
    assert 2 * len(edges(F)) == 3 * len(F)


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_edges_do_not_depend_on_face_order_or_orientation(seed):
    rng = np.random.default_rng(seed)
    F = faces("torus")
    shuffled = F[rng.permutation(len(F))]
    # roll each triangle's corners by a random amount and flip some of them
    shuffled = np.take_along_axis(shuffled, (np.arange(3) + rng.integers(0, 3, (len(F), 1))) % 3, axis=1)
    flip = rng.random(len(F)) < 0.5
    shuffled[flip] = shuffled[flip, ::-1]
    np.testing.assert_array_equal(edges(shuffled), edges(F))


def test_single_triangle_has_its_three_sides():
    np.testing.assert_array_equal(edges([[2, 0, 1]]), [[0, 1], [0, 2], [1, 2]])


def test_input_faces_are_not_modified():
    F = faces("sphere")
    before = F.copy()
    edges(F)
    np.testing.assert_array_equal(F, before)


@pytest.mark.parametrize(
    "F, message",
    [
        (np.array([[0.0, 1.0, 2.0]]), "F must be an integer array"),
        (np.array([[True, False, True]]), "F must be an integer array"),
        (np.array([0, 1, 2]), r"F must have shape \(f, 3\)"),
        (np.array([[0, 1, 2, 3]]), r"F must have shape \(f, 3\)"),
        (np.zeros((0, 3), dtype=np.int64), r"F must have shape \(f, 3\)"),
        (np.array([[0, 1, 2], [0, -1, 2]]), "F has a vertex index out of range"),
        (np.array([[-3, -2, -1]]), "F has a vertex index out of range"),
        (np.array([[0, 1, 1]]), "F has a triangle with a repeated vertex"),
        (sp.csr_matrix(np.array([[0, 1, 2]])), "F must be a dense integer array"),
    ],
)
def test_bad_faces_raise_value_error_naming_f(F, message):
    with pytest.raises(ValueError, match=message):
        edges(F)
