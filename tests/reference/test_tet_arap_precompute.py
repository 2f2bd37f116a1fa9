import numpy as np
import pytest

from reference.tetrahedra import tet_arap_precompute, tet_cotangent_laplacian


def test_precompute_keeps_the_laplacian_the_free_vertices_and_their_factorization(tet_mesh):
    V, T = tet_mesh("hand_tet", 5)
    handles = np.array([7, 3, 500])
    data = tet_arap_precompute(V, T, handles)
    assert abs(data.L - tet_cotangent_laplacian(V, T)).max() == 0
    assert np.array_equal(data.free, np.setdiff1d(np.arange(len(V)), handles))
    rhs = np.random.default_rng(0).standard_normal((len(data.free), 3))
    x = data.solver.solve(rhs)
    np.testing.assert_allclose(-data.L[data.free][:, data.free] @ x, rhs, atol=1e-8)
    np.testing.assert_allclose(data.gradients.sum(axis=1), 0.0, atol=1e-9)


def test_every_component_needs_a_handle(tet_mesh):
    V, T = tet_mesh("bar_tet")
    two = np.vstack([T, T + len(V)])
    with pytest.raises(ValueError, match=r"every connected component .* vertex 1225 has none"):
        tet_arap_precompute(np.vstack([V, V + 10.0]), two, [0])


def test_every_vertex_a_handle_needs_no_solver(tet_mesh):
    V, T = tet_mesh("bar_tet")
    assert tet_arap_precompute(V, T, np.arange(len(V))).solver is None
