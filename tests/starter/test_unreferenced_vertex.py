import numpy as np
from hypothesis import given, settings, strategies as st

from starter.validation import unreferenced_vertex


@settings(max_examples=50, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([3, 4]))
def test_the_smallest_vertex_no_cell_uses_is_found(seed, k):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(k, 30))
    F = rng.integers(0, n, size=(int(rng.integers(1, 20)), k))
    unused = np.setdiff1d(np.arange(n), F)
    assert unreferenced_vertex(F, n) == (int(unused[0]) if unused.size else None)


def test_a_mesh_using_every_vertex_has_none():
    assert unreferenced_vertex(np.array([[0, 1, 2], [2, 1, 3]]), 4) is None
