"""component_without: the first connected component of a mesh that no constrained vertex reaches."""

import numpy as np

from starter.validation import component_without

TWO_TRIANGLE_PAIRS = np.array([[0, 1, 2], [1, 3, 2], [4, 5, 6], [5, 7, 6]])


def test_every_component_constrained_gives_none():
    assert component_without(TWO_TRIANGLE_PAIRS, 8, np.array([0, 7])) is None


def test_the_unreached_component_is_named_by_its_smallest_vertex():
    assert component_without(TWO_TRIANGLE_PAIRS, 8, np.array([3])) == 4
    assert component_without(TWO_TRIANGLE_PAIRS, 8, np.array([6])) == 0


def test_every_corner_of_a_tetrahedron_is_joined_and_a_lone_vertex_is_its_own_component():
    T = np.array([[0, 1, 2, 3]])
    assert component_without(T, 4, np.array([3])) is None
    assert component_without(T, 5, np.array([2])) == 4
