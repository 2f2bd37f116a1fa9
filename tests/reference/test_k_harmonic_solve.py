"""``k_harmonic_solve``: handles met exactly, (Q D)[free] = 0, equal to libigl's ``igl.harmonic``, linear in the handles."""

import igl
import numpy as np
from hypothesis import given, settings, strategies as st

from reference.k_harmonic import k_harmonic_operator, k_harmonic_precompute, k_harmonic_solve
from starter import load_handles, load_mesh

seeds = st.integers(0, 2**32 - 1)
V, F = load_mesh("bar_coarse")
ENDS = load_handles("bar_coarse")
HANDLES = np.r_[ENDS["left"], ENDS["right"]]
L = igl.cotmatrix(V, F)
M = igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_VORONOI)
FREE = np.setdiff1d(np.arange(len(V)), HANDLES)


@settings(max_examples=10)
@given(seeds, st.integers(1, 3))
def test_the_solve_meets_the_handles_exactly_is_stationary_elsewhere_and_equals_igl_harmonic(seed, k):
    D_h = np.random.default_rng(seed).normal(size=(len(HANDLES), 3))
    Q = k_harmonic_operator(L, M, k)
    D = k_harmonic_solve(k_harmonic_precompute(Q, HANDLES), D_h)
    assert np.array_equal(D[HANDLES], D_h)
    assert np.abs((Q @ D)[FREE]).max() <= 1e-8 * abs(Q).max() * np.abs(D_h).max()
    assert np.abs(D - igl.harmonic(V, F, HANDLES, D_h, k)).max() <= 1e-7 * np.abs(D_h).max()


@settings(max_examples=10)
@given(seeds)
def test_the_displacements_are_linear_in_the_handles_and_a_translation_moves_every_vertex_by_itself(seed):
    rng = np.random.default_rng(seed)
    data = k_harmonic_precompute(k_harmonic_operator(L, M, 2), HANDLES)
    A, B = rng.normal(size=(2, len(HANDLES), 3))
    a, b = rng.normal(size=2)
    assert np.allclose(k_harmonic_solve(data, a * A + b * B), a * k_harmonic_solve(data, A) + b * k_harmonic_solve(data, B), atol=1e-9)
    t = rng.normal(size=3)
    assert np.abs(k_harmonic_solve(data, np.tile(t, (len(HANDLES), 1))) - t).max() <= 1e-9 * np.abs(t).max()


def test_a_wrong_number_of_handle_rows_is_refused():
    import pytest

    data = k_harmonic_precompute(k_harmonic_operator(L, M, 1), HANDLES)
    with pytest.raises(ValueError, match="one row per handle"):
        k_harmonic_solve(data, np.zeros((len(HANDLES) - 1, 3)))
