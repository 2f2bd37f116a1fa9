import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.stats import special_ortho_group

from reference.arap import arap_energy, arap_rotations, cotangent_laplacian, cotangent_weights
from starter.meshes import load_mesh

seeds = st.integers(0, 2**32 - 1)
meshes = st.sampled_from(["bar_coarse", "character"])


def energy_by_definition(V, U, F, C, R):
    """``Σ_i Σ_{t ∋ i} Σ_k C[t, k] ‖e'_tk - R_i e_tk‖²``, one term at a time."""
    total = 0.0
    for t, tri in enumerate(F):
        for k in range(3):
            a, b = tri[(k + 1) % 3], tri[(k + 2) % 3]
            for i in tri:
                r = (U[a] - U[b]) - R[i] @ (V[a] - V[b])
                total += C[t, k] * r @ r
    return total


def identities(n, d):
    return np.broadcast_to(np.eye(d), (n, d, d))


@pytest.mark.parametrize("mesh", ["bar_coarse", "character"])
def test_matches_the_definition_summed_term_by_term(mesh):
    V, F = load_mesh(mesh)
    d = V.shape[1]
    rng = np.random.default_rng(0)
    U = V + 0.1 * rng.normal(size=V.shape)
    C = rng.uniform(-0.2, 1.0, size=F.shape)
    R = rng.normal(size=(len(V), d, d))
    E = arap_energy(V, U, F, C, R)
    assert isinstance(E, float)
    assert E == pytest.approx(energy_by_definition(V, U, F, C, R), rel=1e-12)


@settings(max_examples=30, deadline=None)
@given(meshes, seeds)
def test_a_rigid_motion_with_its_rotation_everywhere_costs_nothing(mesh, seed):
    V, F = load_mesh(mesh)
    d = V.shape[1]
    rng = np.random.default_rng(seed)
    Q = special_ortho_group.rvs(d, random_state=rng)
    C = cotangent_weights(V, F)
    E = arap_energy(V, V @ Q.T + rng.normal(size=d), F, C, np.broadcast_to(Q, (len(V), d, d)))
    assert E == pytest.approx(0.0, abs=1e-20 + 1e-13 * arap_energy(V, 2 * V, F, C, identities(len(V), d)))


@pytest.mark.parametrize("mesh", ["bar_coarse", "character"])
def test_doubling_the_mesh_costs_three_times_its_dirichlet_energy(mesh):
    # e' - I e = e, and every triangle belongs to the cells of its three corners
    V, F = load_mesh(mesh)
    C = cotangent_weights(V, F)
    dirichlet = -np.sum(V * (cotangent_laplacian(V, F) @ V))
    assert arap_energy(V, 2.0 * V, F, C, identities(*V.shape)) == pytest.approx(3.0 * dirichlet, rel=1e-12)
    assert arap_energy(V, V, F, C, identities(*V.shape)) == 0.0


@settings(max_examples=20, deadline=None)
@given(meshes, seeds)
def test_never_negative_with_nonnegative_weights_and_scales_quadratically(mesh, seed):
    V, F = load_mesh(mesh)
    rng = np.random.default_rng(seed)
    C = np.abs(cotangent_weights(V, F))
    U = V + 0.1 * rng.normal(size=V.shape)
    R = arap_rotations(V, U, F, C)
    E = arap_energy(V, U, F, C, R)
    assert E >= 0.0
    assert arap_energy(2.0 * V, 2.0 * U, F, C, R) == pytest.approx(4.0 * E, rel=1e-12)


def test_inputs_are_not_modified():
    V, F = load_mesh("bar_coarse")
    U, C, R = V + 0.1, cotangent_weights(V, F), np.tile(np.eye(3), (len(V), 1, 1))
    copies = [a.copy() for a in (V, U, F, C, R)]
    arap_energy(V, U, F, C, R)
    for a, b in zip((V, U, F, C, R), copies):
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize(
    "change, message",
    [
        ({"R": np.eye(3)}, r"R must be a 3-D array"),
        ({"R": np.ones((452, 2, 2))}, r"R must have shape \(452, 3, 3\)"),
        ({"R": np.ones((451, 3, 3))}, r"R must have shape \(452, 3, 3\)"),
        ({"R": np.full((452, 3, 3), np.nan)}, "R contains NaN or inf"),
        ({"U": np.ones((452, 2))}, "U must have the shape of V"),
        ({"C": np.ones((900, 2))}, r"C must have shape \(900, 3\)"),
        ({"F": np.array([[0, 1, 452]])}, "F has a vertex index out of range"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(change, message):
    V, F = load_mesh("bar_coarse")
    args = {"V": V, "U": V, "F": F, "C": cotangent_weights(V, F), "R": np.tile(np.eye(3), (len(V), 1, 1))}
    args.update(change)
    if "F" in change:
        args["C"] = np.ones((1, 3))
    with pytest.raises(ValueError, match=message):
        arap_energy(**args)
