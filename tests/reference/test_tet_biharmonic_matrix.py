import igl
import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from hypothesis import given, settings, strategies as st

from reference.tetrahedra import tet_biharmonic_matrix, tet_cotangent_laplacian, tet_mass_matrix
from starter.meshes import load_handles, load_mesh

seeds = st.integers(0, 2**32 - 1)


@settings(max_examples=10, deadline=None)
@given(seed=seeds, name=st.sampled_from(["bar_tet", "hand_tet"]))
def test_q_is_symmetric_semidefinite_with_constants_in_its_null_space(tet_mesh, seed, name):
    V, T = tet_mesh(name, seed)
    Q = tet_biharmonic_matrix(V, T)
    scale = abs(Q).max()
    assert sp.issparse(Q) and Q.shape == (len(V), len(V))
    assert abs(Q - Q.T).max() <= 1e-12 * scale
    assert np.abs(Q @ np.ones(len(V))).max() <= 1e-9 * scale
    x = np.random.default_rng(seed).normal(size=len(V))
    assert x @ (Q @ x) >= 0
    # wᵀ Q w = (L w)ᵀ M⁻¹ (L w): the squared Laplacian integrated with the lumped mass
    Lx = tet_cotangent_laplacian(V, T) @ x
    assert x @ (Q @ x) == pytest.approx(Lx @ (Lx / tet_mass_matrix(V, T).diagonal()), rel=1e-10)


def test_unconstrained_weights_from_q_are_libigls_biharmonic_coordinates():
    V, T = load_mesh("hand_tet")
    bones = list(load_handles("hand_tet")["bones"])
    b = np.concatenate(bones)
    bc = np.repeat(np.eye(len(bones)), [len(bone) for bone in bones], axis=0)
    Q = tet_biharmonic_matrix(V, T)
    free = np.setdiff1d(np.arange(len(V)), b)
    W = np.zeros((len(V), len(bones)))
    W[b] = bc
    W[free] = spla.splu(Q[free][:, free].tocsc()).solve(-(Q[free][:, b] @ bc))
    np.testing.assert_allclose(W, igl.harmonic(V, T, b, bc, 2), atol=1e-10)


def test_an_unreferenced_vertex_is_named():
    V, T = load_mesh("hand_tet")
    with pytest.raises(ValueError, match=rf"V\[{len(V)}\] is in no tetrahedron"):
        tet_biharmonic_matrix(np.vstack([V, [9.0, 9.0, 9.0]]), T)
