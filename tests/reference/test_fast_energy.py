import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.stats import special_ortho_group

from reference.arap import arap_energy, arap_precompute, arap_rotations
from reference.bounded_biharmonic_weights import bbw, handle_constraints
from reference.fast import fast_energy, fast_precompute, rotation_clusters
from reference.linear_blend_skinning import lbs
from reference.tetrahedra import TET_EDGES, tet_cotangent_weights
from starter.meshes import load_handles, load_mesh

seeds = st.integers(0, 2**32 - 1)
meshes = st.sampled_from(["bar_coarse", "character"])


def energy_scale(V, U, F, C, R):
    """``3 Σ C ‖e'‖² + Σ_i Σ_{t ∋ i} Σ_k C ‖R_i e‖²``: the size of the energy's terms, so of its rounding."""
    return arap_energy(V, U, F, C, np.zeros_like(R)) + arap_energy(V, np.zeros_like(U), F, C, R)


@settings(max_examples=30, deadline=None)
@given(meshes, st.integers(1, 30), st.booleans(), st.floats(0.0, 2.0), seeds)
def test_equals_the_arap_energy_of_the_skinned_mesh_with_the_cluster_rotations(
    skinned_mesh, mesh, k, rotations, size, seed
):
    V, F, W, fixed = skinned_mesh(mesh)
    n, d = V.shape
    rng = np.random.default_rng(seed)
    clusters = rotation_clusters(W, k, seed)
    data = fast_precompute(V, F, W, clusters, fixed)
    T = np.eye(d, d + 1) + size * rng.normal(size=(W.shape[1], d, d + 1))
    # any matrices, not only rotations: the rest term is Σ_c tr(R_c E_c R_cᵀ)
    if rotations:
        R = special_ortho_group.rvs(d, size=k, random_state=rng).reshape(k, d, d)
    else:
        R = rng.normal(size=(k, d, d))
    energy = fast_energy(data, T, R)
    assert isinstance(energy, float)
    U = lbs(V, W, T)
    expected = arap_energy(V, U, F, data.C, R[clusters])
    assert abs(energy - expected) <= 1e-12 * energy_scale(V, U, F, data.C, R[clusters])


@pytest.mark.parametrize("mesh", ["bar_coarse", "character"])
def test_with_every_vertex_its_own_cluster_it_is_the_arap_energy_with_per_vertex_rotations(skinned_mesh, mesh):
    V, F, W, fixed = skinned_mesh(mesh)
    d = V.shape[1]
    data = fast_precompute(V, F, W, np.arange(len(V)), fixed)
    T = np.eye(d, d + 1) + 0.3 * np.random.default_rng(1).normal(size=(W.shape[1], d, d + 1))
    U = lbs(V, W, T)
    R = arap_rotations(V, U, F, data.C)
    assert fast_energy(data, T, R) == pytest.approx(arap_energy(V, U, F, data.C, R), rel=1e-11)


@settings(max_examples=20, deadline=None)
@given(meshes, st.integers(1, 12), seeds)
def test_a_rigid_motion_with_its_rotation_in_every_cluster_costs_nothing(skinned_mesh, mesh, k, seed):
    # the weights are a partition of unity: the same [Q | t] for every handle moves the mesh rigidly
    V, F, W, fixed = skinned_mesh(mesh)
    d = V.shape[1]
    rng = np.random.default_rng(seed)
    Q = special_ortho_group.rvs(d, random_state=rng)
    data = fast_precompute(V, F, W, rotation_clusters(W, k, seed), fixed)
    T = np.tile(np.c_[Q, rng.normal(size=d)], (W.shape[1], 1, 1))
    R = np.tile(Q, (k, 1, 1))
    U = lbs(V, W, T)
    assert abs(fast_energy(data, T, R)) <= 1e-12 * energy_scale(V, U, F, data.C, R[data.clusters])


def test_inputs_are_not_modified(skinned_mesh):
    V, F, W, fixed = skinned_mesh("bar_coarse")
    data = fast_precompute(V, F, W, rotation_clusters(W, 4), fixed)
    T = np.tile(np.eye(3, 4), (5, 1, 1)) + 0.1
    R = np.tile(np.eye(3), (4, 1, 1)) + 0.1
    copies = (T.copy(), R.copy(), data.quadratic.copy())
    fast_energy(data, T, R)
    for a, b in zip((T, R, data.quadratic), copies):
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize(
    "change, message",
    [
        ({"T": np.ones((4, 3, 4))}, r"T must have shape \(5, 3, 4\), one affine transform per handle"),
        ({"T": np.ones((5, 3, 3))}, r"T must have shape \(5, 3, 4\)"),
        ({"T": np.ones((5, 12))}, "T must be a 3-D array"),
        ({"T": np.full((5, 3, 4), np.nan)}, "T contains NaN or inf"),
        ({"R": np.ones((3, 3, 3))}, r"R must have shape \(4, 3, 3\), one matrix per cluster"),
        ({"R": np.eye(3)}, "R must be a 3-D array"),
        ({"R": np.full((4, 3, 3), np.inf)}, "R contains NaN or inf"),
        ({"data": None}, "data must be the result of fast_precompute"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(skinned_mesh, change, message):
    V, F, W, fixed = skinned_mesh("bar_coarse")
    args = {
        "data": fast_precompute(V, F, W, rotation_clusters(W, 4), fixed),
        "T": np.tile(np.eye(3, 4), (5, 1, 1)),
        "R": np.tile(np.eye(3), (4, 1, 1)),
    }
    args.update(change)
    with pytest.raises(ValueError, match=message):
        fast_energy(**args)


def test_stage_03_data_is_not_mistaken_for_fast_data(skinned_mesh):
    V, F, W, _ = skinned_mesh("bar_coarse")
    with pytest.raises(ValueError, match="data must be the result of fast_precompute"):
        fast_energy(arap_precompute(V, F, np.r_[0, 1]), np.tile(np.eye(3, 4), (5, 1, 1)), np.tile(np.eye(3), (4, 1, 1)))


def tet_spokes_and_rims_energy(V, U, T, C, R):
    """``Σ_i Σ_{t ∋ i} Σ_e C[t, e] ‖e'_te - R_i e_te‖²`` over the 6 edges of each tetrahedron, by loops."""
    total = 0.0
    for t, tet in enumerate(T):
        for i in tet:
            for e, (a, b) in enumerate(TET_EDGES):
                rest, deformed = V[tet[a]] - V[tet[b]], U[tet[a]] - U[tet[b]]
                total += C[t, e] * np.sum((deformed - R[i] @ rest) ** 2)
    return total


@settings(max_examples=5, deadline=None)
@given(st.integers(1, 20), seeds)
def test_on_tetrahedra_it_is_the_spokes_and_rims_energy_over_the_six_edges(k, seed):
    V, T = load_mesh("hand_tet")
    bones = load_handles("hand_tet")["bones"]
    W = bbw(V, T, *handle_constraints(bones[:3]))
    rng = np.random.default_rng(seed)
    clusters = rotation_clusters(W, k)
    data = fast_precompute(V, T, W, clusters, [0])
    transforms = np.tile(np.eye(3, 4), (3, 1, 1)) + 0.3 * rng.standard_normal((3, 3, 4))
    R = special_ortho_group.rvs(3, size=k + 1, random_state=rng)[:k]
    expected = tet_spokes_and_rims_energy(V, lbs(V, W, transforms), T, tet_cotangent_weights(V, T), R[clusters])
    assert fast_energy(data, transforms, R) == pytest.approx(expected, rel=1e-9)
