import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.stats import special_ortho_group

from reference.arap import arap_covariances, cotangent_weights
from starter.meshes import load_mesh

seeds = st.integers(0, 2**32 - 1)
meshes = st.sampled_from(["bar_coarse", "character"])


def covariances_by_definition(V, U, F, C):
    """``S_i = Σ_{t ∋ i} Σ_k C[t, k] e_tk e'_tkᵀ``, one triangle and one corner at a time."""
    d = V.shape[1]
    S = np.zeros((len(V), d, d))
    for t, tri in enumerate(F):
        for k in range(3):
            a, b = tri[(k + 1) % 3], tri[(k + 2) % 3]
            outer = C[t, k] * np.outer(V[a] - V[b], U[a] - U[b])
            for i in tri:
                S[i] += outer
    return S


@pytest.mark.parametrize("mesh", ["bar_coarse", "character"])
def test_matches_the_definition_summed_triangle_by_triangle(mesh):
    V, F = load_mesh(mesh)
    rng = np.random.default_rng(2)
    U = V + 0.1 * rng.normal(size=V.shape)
    C = rng.uniform(-0.5, 1.0, size=F.shape)
    S = arap_covariances(V, U, F, C)
    assert S.shape == (len(V), V.shape[1], V.shape[1]) and S.dtype == np.float64
    np.testing.assert_allclose(S, covariances_by_definition(V, U, F, C), rtol=0, atol=1e-13)


@settings(max_examples=30, deadline=None)
@given(meshes, seeds)
def test_a_linear_map_of_the_rest_pose_multiplies_every_covariance(mesh, seed):
    # e' = A e for U = V Aᵀ + t, so S_i(U) = S_i(V) Aᵀ
    V, F = load_mesh(mesh)
    d = V.shape[1]
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(d, d))
    C = cotangent_weights(V, F)
    S_rest = arap_covariances(V, V, F, C)
    S = arap_covariances(V, V @ A.T + rng.normal(size=d), F, C)
    np.testing.assert_allclose(S, S_rest @ A.T, rtol=0, atol=1e-12 * np.abs(S_rest).max() * np.abs(A).max())


@settings(max_examples=30, deadline=None)
@given(meshes, seeds)
def test_linear_in_the_deformed_positions_and_in_the_weights(mesh, seed):
    V, F = load_mesh(mesh)
    rng = np.random.default_rng(seed)
    U1, U2 = rng.normal(size=(2, *V.shape))
    C1, C2 = rng.normal(size=(2, *F.shape))
    a, b = rng.normal(size=2)
    combined = arap_covariances(V, a * U1 + b * U2, F, C1)
    np.testing.assert_allclose(combined, a * arap_covariances(V, U1, F, C1) + b * arap_covariances(V, U2, F, C1), atol=1e-10)
    combined = arap_covariances(V, U1, F, a * C1 + b * C2)
    np.testing.assert_allclose(combined, a * arap_covariances(V, U1, F, C1) + b * arap_covariances(V, U1, F, C2), atol=1e-10)


def test_the_rest_covariances_of_a_rigidly_moved_mesh_are_rotated():
    V, F = load_mesh("bar_coarse")
    Q = special_ortho_group.rvs(3, random_state=np.random.default_rng(3))
    C = cotangent_weights(V, F)
    S = arap_covariances(V, V, F, C)
    # S_i = Σ C e eᵀ is symmetric; moving only U by Q multiplies by Qᵀ on the right
    np.testing.assert_allclose(S, np.swapaxes(S, 1, 2), atol=1e-15)
    np.testing.assert_allclose(arap_covariances(V, V @ Q.T + 5.0, F, C), S @ Q.T, atol=1e-13)


def test_inputs_are_not_modified():
    V, F = load_mesh("bar_coarse")
    U = V + 0.1
    C = cotangent_weights(V, F)
    copies = [a.copy() for a in (V, U, F, C)]
    arap_covariances(V, U, F, C)
    for a, b in zip((V, U, F, C), copies):
        np.testing.assert_array_equal(a, b)


def bad_inputs():
    V, F = load_mesh("bar_coarse")
    C = cotangent_weights(V, F)
    nan = V.copy()
    nan[3, 1] = np.nan
    return [
        (V, V[:-1], F, C, r"U must have the shape of V"),
        (V, V[:, :2], F, C, r"U must have the shape of V"),
        (V, nan, F, C, "U contains NaN or inf"),
        (nan, V, F, C, "V contains NaN or inf"),
        (V, V, F, C[:-1], r"C must have shape \(900, 3\)"),
        (V, V, F, np.where(C > 0.3, np.inf, C), "C contains NaN or inf"),
        (V, V, F + len(V), C, "F has a vertex index out of range"),
    ]


@pytest.mark.parametrize("case", range(7))
def test_bad_inputs_raise_value_error_naming_the_argument(case):
    V, U, F, C, message = bad_inputs()[case]
    with pytest.raises(ValueError, match=message):
        arap_covariances(V, U, F, C)
