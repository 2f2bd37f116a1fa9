"""The stage 04 checks fail realistic mistakes and accept correct variations."""

from __future__ import annotations

import importlib

import igl
import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import reference.arap as stage03
from grader.checks import check_namespace, seeded_cases, all_checks, evaluate, wire
from grader.harness.outputs import CaseOutput

# The package re-exports the function bbw(), which hides the module attribute ``reference.bounded_biharmonic_weights``.
ref = importlib.import_module("reference.bounded_biharmonic_weights")


def grade(function, implementation, seed=0):
    """The checks' result for the reference with ``function`` replaced by ``implementation``."""
    return check_namespace(function, {**vars(ref), function: implementation}, seed)


def failed(result):
    return result.failed_verdicts()


def failed_in_every_case(result, verdict):
    return all(any(v.name == verdict and not v.passed for v in c.verdicts) for c in result.cases)


def _solve_with_fixed_rows(A, b, bc):
    """``argmin ½ tr(Wᵀ A W)`` with ``W[b] = bc`` for a symmetric ``A``."""
    n = A.shape[0]
    free = np.setdiff1d(np.arange(n), b)
    A = sp.csr_matrix(A)
    W = np.zeros((n, bc.shape[1]))
    W[b] = bc
    W[free] = spla.spsolve(sp.csc_matrix(A[free][:, free]), -(A[free][:, b] @ bc)).reshape(len(free), -1)
    return W


def _normalized(W):
    return W / W.sum(axis=1, keepdims=True)


def harmonic_weights(V, F, b, bc):
    """Minimizers of the Dirichlet energy: bounded by the maximum principle (up to obtuse angles), but not biharmonic."""
    return _normalized(np.clip(_solve_with_fixed_rows(-stage03.cotangent_laplacian(V, F), b, bc), 0.0, 1.0))


def clipped_unconstrained_weights(V, F, b, bc):
    """Unconstrained biharmonic weights clipped to [0, 1] and normalized: feasible, but not the bounded minimizer."""
    return _normalized(np.clip(ref.unconstrained_biharmonic_weights(V, F, b, bc), 0.0, 1.0))


def libigl_bbw_unnormalized(V, F, b, bc):
    return igl.bbw(V, F, b, bc)


def libigl_bbw_normalized(V, F, b, bc):
    # libigl's active set stops with weights down to about -3e-9: clipping that is part of a correct solution.
    return _normalized(np.clip(igl.bbw(V, F, b, bc), 0.0, 1.0))


def biharmonic_without_mass(V, F):
    L = sp.csr_matrix(stage03.cotangent_laplacian(V, F))
    return L @ L


def biharmonic_with_barycentric_mass(V, F):
    L = sp.csr_matrix(stage03.cotangent_laplacian(V, F))
    M = igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_BARYCENTRIC)
    return L @ sp.diags(1.0 / M.diagonal()) @ L


def handle_constraints_sorted(handles):
    b, bc = ref.handle_constraints(handles)
    order = np.argsort(b)
    return b[order], bc[order]


def penalty_biharmonic_weights(V, F, b, bc, weight=1e6):
    """Constraints held by a penalty: ``W[b]`` only close to ``bc``."""
    Q = sp.csr_matrix(ref.biharmonic_matrix(V, F))
    P = sp.coo_matrix((np.full(len(b), weight), (b, b)), shape=Q.shape)
    rhs = np.zeros((len(V), bc.shape[1]))
    rhs[b] = weight * bc
    return spla.spsolve(sp.csc_matrix(Q + P), rhs).reshape(len(V), -1)


MISTAKES = {
    "biharmonic: no mass matrix": ("biharmonic_matrix", biharmonic_without_mass, "Q matches L M⁻¹ L"),
    "biharmonic: barycentric mass": ("biharmonic_matrix", biharmonic_with_barycentric_mass, "Q matches L M⁻¹ L"),
    "biharmonic: dense": ("biharmonic_matrix", lambda V, F: ref.biharmonic_matrix(V, F).toarray(), "a scipy.sparse matrix"),
    "constraints: b sorted": ("handle_constraints", handle_constraints_sorted, "b is the concatenation of the handles"),
    "constraints: handle columns reversed": (
        "handle_constraints",
        lambda handles: (ref.handle_constraints(handles)[0], ref.handle_constraints(handles)[1][:, ::-1]),
        "bc one-hot in the handle's column",
    ),
    "idw: rows not normalized": (
        "inverse_distance_weights",
        lambda V, H, power=2: ref.inverse_distance_weights(V, H, power) * 2.0,
        "W matches",
    ),
    "idw: power of the squared distance": (
        "inverse_distance_weights",
        lambda V, H, power=2: ref.inverse_distance_weights(V, H, 2 * power),
        "W matches",
    ),
    "unconstrained: harmonic instead of biharmonic": (
        "unconstrained_biharmonic_weights",
        lambda V, F, b, bc: _solve_with_fixed_rows(-stage03.cotangent_laplacian(V, F), b, bc),
        "W matches the minimizer",
    ),
    "unconstrained: constraints by a penalty": ("unconstrained_biharmonic_weights", penalty_biharmonic_weights, "W[b] = bc"),
    "bbw: libigl's weights not normalized": ("bbw", libigl_bbw_unnormalized, "rows sum to 1"),
}


@pytest.mark.parametrize("mistake", MISTAKES)
def test_realistic_mistakes_fail(mistake):
    function, implementation, verdict = MISTAKES[mistake]
    assert verdict in failed(grade(function, implementation))


@pytest.mark.parametrize("seed", [0, 1])
@pytest.mark.parametrize("implementation", [clipped_unconstrained_weights, harmonic_weights], ids=["clipped unconstrained", "harmonic"])
def test_feasible_but_not_bounded_biharmonic_weights_fail_on_energy_in_every_case(implementation, seed):
    result = grade("bbw", implementation, seed)
    assert failed_in_every_case(result, "biharmonic energy within 1% of the minimum")
    # They do satisfy the constraints: the energy is what separates them.
    assert {"0 ≤ W ≤ 1", "rows sum to 1", "W[b] = bc"}.isdisjoint(failed(result))


def test_unconstrained_weights_by_another_sparse_solver_pass():
    result = grade("unconstrained_biharmonic_weights", lambda V, F, b, bc: _solve_with_fixed_rows(ref.biharmonic_matrix(V, F), b, bc))
    assert result.fraction == 1.0


def test_an_independent_bounded_biharmonic_solver_passes():
    assert grade("bbw", libigl_bbw_normalized).fraction == 1.0


def test_nan_weights_fail_cleanly():
    cases, expected = seeded_cases("bbw")
    outputs = []
    for value in expected:
        W = wire(value).copy()
        W[0, 0] = np.nan
        outputs.append(CaseOutput(W, None, None))
    result = evaluate(all_checks()["bbw"], cases, outputs, expected)
    assert result.fraction == 0.0 and failed(result) == {"output shape"}


def test_hidden_scenes_use_both_orientations_and_a_far_scaled_copy():
    from deformlab_packs.deformation.checks.bounded_biharmonic_weights import handle_scenes

    scenes = handle_scenes(np.random.default_rng(10))
    # igl.doublearea is signed for 2D input
    orientations = {((igl.doublearea(V, F) > 0).any(), (igl.doublearea(V, F) < 0).any()) for V, F, _ in scenes.values() if V.shape[1] == 2}
    assert orientations == {(True, False), (False, True), (True, True)}
    V, F, handles = next(s for label, s in scenes.items() if "scaled by 1/100" in label)
    assert np.linalg.norm(V.mean(axis=0)) > 9.0 and np.ptp(V, axis=0).max() < 0.04
    # The copy's weights are those of the same problem at unit size near the origin: the verdicts stay comparable.
    b, bc = ref.handle_constraints(handles)
    assert np.allclose(ref.bbw(V, F, b, bc), ref.bbw((V - V.mean(axis=0)) * 100.0, F, b, bc), atol=1e-8)
