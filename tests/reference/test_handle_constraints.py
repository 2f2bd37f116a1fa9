import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from reference.bounded_biharmonic_weights import handle_constraints
from starter.meshes import load_handles


def assert_layout(handles, b, bc):
    """``b`` is the concatenation; ``bc`` one-hot rows in the column of each vertex's handle."""
    sizes = [len(np.atleast_1d(h)) for h in handles]
    owner = np.repeat(np.arange(len(handles)), sizes)
    assert b.dtype == np.int64 and bc.dtype == np.float64
    np.testing.assert_array_equal(b, np.concatenate([np.atleast_1d(h) for h in handles]))
    assert bc.shape == (len(b), len(handles))
    expected = np.zeros_like(bc)
    expected[np.arange(len(b)), owner] = 1.0
    np.testing.assert_array_equal(bc, expected)


def test_point_handles_give_the_identity():
    b, bc = handle_constraints([np.array([7]), np.array([3]), np.array([12])])
    np.testing.assert_array_equal(b, [7, 3, 12])
    np.testing.assert_array_equal(bc, np.eye(3))


def test_a_point_handle_may_be_a_bare_index():
    b, bc = handle_constraints([7, [3, 4]])
    np.testing.assert_array_equal(b, [7, 3, 4])
    np.testing.assert_array_equal(bc, [[1, 0], [0, 1], [0, 1]])


def test_bone_handles_of_the_character():
    bones = load_handles("character")["bones"]
    assert all(len(bone) > 1 for bone in bones)
    b, bc = handle_constraints(bones)
    assert_layout(bones, b, bc)
    np.testing.assert_array_equal(bc.sum(axis=0), [len(bone) for bone in bones])


def test_region_handles_of_the_character():
    regions = load_handles("character")["regions"]
    b, bc = handle_constraints(regions)
    assert_layout(regions, b, bc)


def test_mixed_point_bone_and_region_handles():
    handles = load_handles("character")
    mixed = [handles["bones"][0], handles["points"][1:2], handles["regions"][1]]
    b, bc = handle_constraints(mixed)
    assert_layout(mixed, b, bc)


@st.composite
def disjoint_handles(draw):
    """A list of 1 to 8 non-empty, pairwise disjoint int64 vertex sets."""
    vertices = draw(st.lists(st.integers(0, 10_000), min_size=1, max_size=40, unique=True))
    cuts = draw(st.lists(st.integers(1, len(vertices) - 1), max_size=7, unique=True)) if len(vertices) > 1 else []
    bounds = [0, *sorted(cuts), len(vertices)]
    return [np.array(vertices[i:j], dtype=np.int64) for i, j in zip(bounds, bounds[1:])]


@settings(max_examples=100, deadline=None)
@given(disjoint_handles())
def test_layout_of_any_disjoint_handles(handles):
    b, bc = handle_constraints(handles)
    assert_layout(handles, b, bc)
    # every constrained vertex belongs to exactly one handle
    np.testing.assert_array_equal(bc.sum(axis=1), 1.0)


def test_input_is_not_modified():
    handles = [np.array([5, 1]), np.array([9])]
    handle_constraints(handles)
    np.testing.assert_array_equal(handles[0], [5, 1])
    np.testing.assert_array_equal(handles[1], [9])


@pytest.mark.parametrize(
    "handles, message",
    [
        ([], "handles is empty"),
        ([[1], []], r"handles\[1\] is empty"),
        ([[1, 2], [4, 2]], r"vertex 2 is in handles\[0\] and handles\[1\]"),
        ([[3, 3]], r"vertex 3 is twice in handles\[0\]"),
        ([[0], [-4]], r"handles\[1\] has a negative vertex index -4"),
        ([[0.0, 1.0]], r"handles\[0\] must be a 1-D integer array"),
        ([[True]], r"handles\[0\] must be a 1-D integer array"),
        ([[[1, 2], [3, 4]]], r"handles\[0\] must be a 1-D integer array"),
        (5, "handles must be a list of integer arrays"),
    ],
)
def test_bad_handles_raise_value_error_naming_the_argument(handles, message):
    with pytest.raises(ValueError, match=message):
        handle_constraints(handles)
