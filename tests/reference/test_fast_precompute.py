import numpy as np
import pytest
import scipy
from hypothesis import given, settings, strategies as st
from scipy.stats import special_ortho_group

from reference.arap import arap_covariances, arap_energy, cotangent_weights
from reference.fast import fast_precompute, rotation_clusters
from reference.linear_blend_skinning import lbs

seeds = st.integers(0, 2**32 - 1)
meshes = st.sampled_from(["bar_coarse", "character"])


def centred(data, T):
    """``Tc``: the transforms acting on the centred, scaled rest positions, stacked ``(N, d)``."""
    return np.einsum("ab,jcb->jac", data.to_centred, T).reshape(-1, T.shape[1])


def cluster_sums(S, clusters, k):
    out = np.zeros((k, *S.shape[1:]))
    np.add.at(out, clusters, S)
    return out


def random_transforms(rng, m, d, size):
    return np.eye(d, d + 1) + size * rng.normal(size=(m, d, d + 1))


@pytest.mark.parametrize("mesh", ["bar_coarse", "character"])
def test_stores_the_mesh_the_weights_and_the_split_into_fixed_and_free_handles(skinned_mesh, mesh):
    V, F, W, fixed = skinned_mesh(mesh)
    clusters = rotation_clusters(W, 7)
    data = fast_precompute(V, F, W, clusters, fixed[::-1])
    np.testing.assert_array_equal(data.fixed, fixed[::-1])
    np.testing.assert_array_equal(data.free, np.setdiff1d(np.arange(W.shape[1]), fixed))
    for stored, given_ in ((data.V, V), (data.F, F), (data.W, W), (data.clusters, clusters)):
        np.testing.assert_array_equal(stored, given_)
    np.testing.assert_array_equal(data.C, cotangent_weights(V, F))
    d = V.shape[1]
    np.testing.assert_array_equal(data.fixed_rows, ((d + 1) * fixed[::-1][:, None] + np.arange(d + 1)).ravel())
    np.testing.assert_allclose(data.from_centred @ data.to_centred, np.eye(d + 1), rtol=0, atol=1e-14)


@settings(max_examples=20, deadline=None)
@given(meshes, st.integers(1, 30), seeds)
def test_the_covariance_operator_sums_arap_covariances_over_each_cluster(skinned_mesh, mesh, k, seed):
    V, F, W, fixed = skinned_mesh(mesh)
    d = V.shape[1]
    clusters = rotation_clusters(W, k, seed)
    data = fast_precompute(V, F, W, clusters, fixed)
    T = random_transforms(np.random.default_rng(seed), W.shape[1], d, 0.5)
    S = np.einsum("caN,Nb->cab", data.covariance_operator, centred(data, T))
    expected = cluster_sums(arap_covariances(V, lbs(V, W, T), F, data.C), clusters, k)
    np.testing.assert_allclose(S, expected, rtol=0, atol=1e-12 * np.abs(expected).max())


@settings(max_examples=20, deadline=None)
@given(meshes, seeds)
def test_the_quadratic_form_is_three_times_the_dirichlet_energy_of_the_skinned_mesh(skinned_mesh, mesh, seed):
    V, F, W, fixed = skinned_mesh(mesh)
    n, d = V.shape
    data = fast_precompute(V, F, W, rotation_clusters(W, 5), fixed)
    T = random_transforms(np.random.default_rng(seed), W.shape[1], d, 0.5)
    Tc = centred(data, T)
    np.testing.assert_array_equal(data.quadratic, data.quadratic.T)
    # with every R_i = 0, arap_energy is Σ_i Σ_{t ∋ i} Σ_k C ‖e'‖² = 3 Σ_t Σ_k C ‖e'‖²
    expected = arap_energy(V, lbs(V, W, T), F, data.C, np.zeros((n, d, d)))
    assert np.sum(Tc * (data.quadratic @ Tc)) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("mesh", ["bar_coarse", "character"])
def test_the_rest_covariances_are_the_cluster_sums_at_rest(skinned_mesh, mesh):
    V, F, W, fixed = skinned_mesh(mesh)
    clusters = rotation_clusters(W, 9)
    data = fast_precompute(V, F, W, clusters, fixed)
    expected = cluster_sums(arap_covariances(V, V, F, data.C), clusters, 9)
    np.testing.assert_allclose(data.rest_covariances, expected, rtol=0, atol=1e-13 * np.abs(expected).max())


@pytest.mark.parametrize("mesh", ["bar_coarse", "character"])
def test_the_factor_solves_the_free_block_of_the_quadratic_form(skinned_mesh, mesh):
    V, F, W, fixed = skinned_mesh(mesh)
    d = V.shape[1]
    data = fast_precompute(V, F, W, rotation_clusters(W, 6), fixed)
    Q = data.quadratic
    A = Q[np.ix_(data.free_rows, data.free_rows)]
    b = np.random.default_rng(2).normal(size=(len(data.free_rows), d))
    x = scipy.linalg.cho_solve(data.solver, b)
    np.testing.assert_allclose(A @ x, b, rtol=0, atol=1e-10 * np.abs(b).max())
    np.testing.assert_array_equal(data.quadratic_free_fixed, Q[np.ix_(data.free_rows, data.fixed_rows)])


def test_every_handle_may_be_fixed(skinned_mesh):
    V, F, W, _ = skinned_mesh("bar_coarse")
    data = fast_precompute(V, F, W, rotation_clusters(W, 4), np.arange(W.shape[1]))
    assert data.free.size == 0 and data.free_rows.size == 0 and data.solver is None


def test_an_unused_label_is_an_empty_cluster(skinned_mesh):
    V, F, W, fixed = skinned_mesh("character")
    clusters = rotation_clusters(W, 4) + (rotation_clusters(W, 4) >= 2)
    data = fast_precompute(V, F, W, clusters, fixed)
    assert data.covariance_operator.shape[0] == 5
    assert not data.covariance_operator[2].any() and not data.rest_covariances[2].any()


def planar_character_in_3d():
    from starter.meshes import load_handles, load_mesh
    from reference.bounded_biharmonic_weights import bbw, handle_constraints

    V, F = load_mesh("character")
    sets = load_handles("character")
    W = bbw(V, F, *handle_constraints([*sets["regions"], *sets["bones"][1:3]]))
    turn = special_ortho_group.rvs(3, random_state=np.random.default_rng(4))
    return np.c_[V, np.zeros(len(V))] @ turn.T + [3.0, -1.0, 2.0], F, W


def test_a_planar_mesh_in_3d_leaves_the_free_transforms_undetermined():
    V, F, W = planar_character_in_3d()
    clusters = rotation_clusters(W, 5)
    with pytest.raises(ValueError, match="V is planar"):
        fast_precompute(V, F, W, clusters, np.array([1, 2]))
    data = fast_precompute(V, F, W, clusters, np.arange(5))
    assert data.solver is None


@pytest.mark.parametrize("mesh", ["bar_coarse", "character"])
def test_a_vanishing_weight_column_leaves_its_free_transform_undetermined(skinned_mesh, mesh):
    V, F, W, fixed = skinned_mesh(mesh)
    W = np.c_[W, np.zeros(len(V))]
    m = W.shape[1]
    clusters = rotation_clusters(W, 5)
    with pytest.raises(ValueError, match=rf"W\[:, {m - 1}\] vanishes but handle {m - 1} is not fixed"):
        fast_precompute(V, F, W, clusters, fixed)
    fast_precompute(V, F, W, clusters, np.r_[fixed, m - 1])


@pytest.mark.parametrize(
    "extra",
    [
        lambda W: np.ones(len(W)),  # translating that handle translates every vertex
        lambda W: W[:, -1],  # two handles with the same weights: only their sum counts
    ],
)
def test_dependent_weights_leave_the_free_transforms_undetermined(skinned_mesh, extra):
    V, F, W, fixed = skinned_mesh("character")
    W = np.c_[W, extra(W)]
    message = r"W and fixed leave the transforms of the free handles \[0, 3, 4, 5\] undetermined"
    with pytest.raises(ValueError, match=message):
        fast_precompute(V, F, W, rotation_clusters(W, 5), fixed)


def test_inputs_are_not_modified(skinned_mesh):
    V, F, W, fixed = skinned_mesh("bar_coarse")
    clusters = rotation_clusters(W, 5)
    copies = [a.copy() for a in (V, F, W, clusters, fixed)]
    fast_precompute(V, F, W, clusters, fixed)
    for a, b in zip((V, F, W, clusters, fixed), copies):
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize(
    "change, message",
    [
        ({"fixed": np.array([], dtype=np.int64)}, "fixed is empty"),
        ({"fixed": np.array([0, 5])}, r"fixed\[1\] = 5 is out of range: there are 5 handles"),
        ({"fixed": np.array([-1])}, r"fixed\[0\] = -1 is out of range"),
        ({"fixed": np.array([1, 1])}, "fixed has duplicate handle 1"),
        ({"fixed": np.array([[0, 1]])}, "fixed must be a 1-D array of handle indices"),
        ({"fixed": np.array([0.0, 1.0])}, "fixed must be an integer array of handle indices"),
        ({"clusters": np.zeros(451, dtype=np.int64)}, r"clusters must have shape \(452,\)"),
        ({"clusters": np.zeros((452, 1), dtype=np.int64)}, r"clusters must have shape \(452,\)"),
        ({"clusters": np.full(452, -1)}, r"clusters must be non-negative, got clusters\[0\] = -1"),
        ({"clusters": np.zeros(452)}, "clusters must be an integer array of labels"),
        ({"W": np.ones((451, 5))}, r"W must have shape \(452, m\)"),
        ({"W": np.ones((452, 0))}, r"W must have shape \(452, m\)"),
        ({"W": np.ones(452)}, "W must be a 2-D array"),
        ({"W": np.full((452, 5), np.nan)}, "W contains NaN or inf"),
        ({"V": np.full((452, 3), np.nan)}, "V contains NaN or inf"),
        ({"V": np.ones((452, 4))}, "V must have 2 or 3 columns"),
        ({"F": np.array([[0, 1, 2], [0, 1, 1]])}, "F has a triangle with a repeated vertex"),
        ({"F": np.array([[0, 1, 500]])}, "F has a vertex index out of range"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(skinned_mesh, change, message):
    V, F, W, fixed = skinned_mesh("bar_coarse")
    args = {"V": V, "F": F, "W": W, "clusters": rotation_clusters(W, 5), "fixed": fixed}
    args.update(change)
    with pytest.raises(ValueError, match=message):
        fast_precompute(**args)


def test_zero_area_triangles_are_rejected(skinned_mesh):
    V, F, W, fixed = skinned_mesh("bar_coarse")
    V[F[0, 2]] = V[F[0, 0]]
    with pytest.raises(ValueError, match="F has a zero-area triangle"):
        fast_precompute(V, F, W, rotation_clusters(W, 5), fixed)
