from contextlib import contextmanager

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings, strategies as st

import reference.box_qp as box_qp_module
from reference.bounded_biharmonic_weights import biharmonic_matrix, handle_constraints
from reference.box_qp import box_qp
from starter.meshes import load_handles, load_mesh

seeds = st.integers(0, 2**32 - 1)


def kkt_residual(H, g, x):
    """Largest entry of the projected gradient of ``½ xᵀHx - gᵀx`` on ``[0, 1]``, relative to ``H``'s row sums.

    The gradient must vanish where ``0 < x < 1``, be ``≥ 0`` where ``x = 0``
    and ``≤ 0`` where ``x = 1``.
    """
    gradient = H @ x - g
    projected = np.where(x <= 0, np.minimum(gradient, 0.0), np.where(x >= 1, np.maximum(gradient, 0.0), gradient))
    return np.abs(projected).max() / abs(H).sum(axis=1).max()


def random_dense_problem(seed, n, m):
    """A random SPD ``H`` (condition number up to ~1e4) and ``g`` whose unconstrained minimizer leaves the box."""
    rng = np.random.default_rng(seed)
    Q, _ = np.linalg.qr(rng.normal(size=(n, n)))
    H = (Q * np.logspace(0, rng.uniform(0, 4), n)) @ Q.T
    H = 0.5 * (H + H.T)
    return H, H @ rng.normal(0.5, 1.5, size=(n, m))


def chain_biharmonic(n):
    """``L Lᵀ + 1e-6 I`` with ``L`` the path graph's Laplacian: sparse, banded, badly conditioned, like BBW's ``H``."""
    L = sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1])
    return sp.csc_matrix(L @ L.T + 1e-6 * sp.eye(n))


@contextmanager
def sparse_branch_calls():
    """Count the calls of the sparse branch (``_sparse_active_set``), one per problem that takes it."""
    calls = []
    original = box_qp_module._sparse_active_set

    def spy(*args):
        calls.append(1)
        return original(*args)

    box_qp_module._sparse_active_set = spy
    try:
        yield calls
    finally:
        box_qp_module._sparse_active_set = original


@settings(max_examples=60, deadline=None)
@given(seeds, st.integers(1, 12), st.integers(1, 3))
def test_random_dense_problems_meet_the_kkt_conditions(seed, n, m):
    H, G = random_dense_problem(seed, n, m)
    X = box_qp(H, G)
    assert X.shape == G.shape
    assert X.min() >= 0.0 and X.max() <= 1.0
    for x, g in zip(X.T, G.T):
        assert kkt_residual(H, g, x) <= 1e-10


@settings(max_examples=10, deadline=None)
@given(seeds, st.integers(1, 3))
def test_many_bounds_broken_take_the_sparse_branch_and_meet_the_kkt_conditions(seed, m):
    n = 400
    H = chain_biharmonic(n)
    # oscillating targets: the unconstrained minimizer leaves [0, 1] almost everywhere
    rng = np.random.default_rng(seed)
    t = np.linspace(0, 1, n)[:, None]
    G = H @ (0.5 + 3 * np.sin(2 * np.pi * rng.uniform(2, 8, m) * t + rng.uniform(0, 6, m)))
    with sparse_branch_calls() as calls:
        X = box_qp(H, G)
    assert len(calls) == m
    assert X.min() >= 0.0 and X.max() <= 1.0
    for x, g in zip(X.T, G.T):
        assert kkt_residual(H, g, x) <= 1e-9


@settings(max_examples=10, deadline=None)
@given(seeds)
def test_a_few_bounds_broken_take_the_dense_branch_exactly(seed):
    n = 400
    H = chain_biharmonic(n)
    t = np.linspace(0, 1, n)
    # inside the box but for one bump above 1 near the middle
    target = 0.5 + 0.6 * np.exp(-(((t - np.random.default_rng(seed).uniform(0.3, 0.7)) / 0.02) ** 2))
    g = H @ target
    with sparse_branch_calls() as calls:
        x = box_qp(H, g)
    assert not calls
    assert (x == 1.0).any() and x.min() >= 0.0 and x.max() <= 1.0
    # the dense branch solves exactly: round-off only, far below the sparse branch's tolerance
    assert kkt_residual(H, g, x) <= 1e-11


def test_a_minimizer_inside_the_box_is_returned_unchanged():
    H = chain_biharmonic(50)
    target = np.linspace(0.1, 0.9, 50)
    np.testing.assert_allclose(box_qp(H, H @ target), target, atol=1e-9)


def test_columns_are_independent_problems():
    H, G = random_dense_problem(7, 10, 3)
    X = box_qp(H, G)
    for j in range(3):
        np.testing.assert_allclose(box_qp(H, G[:, j]), X[:, j], atol=1e-12)


def test_a_tighter_tolerance_gives_a_smaller_residual():
    H = chain_biharmonic(400)
    g = H @ (0.5 + 3 * np.sin(2 * np.pi * 5 * np.linspace(0, 1, 400)))
    loose, tight = box_qp(H, g, tol=1e-6), box_qp(H, g, tol=1e-12)
    assert kkt_residual(H, g, loose) <= 1e-6
    assert kkt_residual(H, g, tight) <= 1e-12


def test_inputs_are_not_modified():
    H, G = random_dense_problem(3, 8, 2)
    copies = H.copy(), G.copy()
    box_qp(H, G)
    np.testing.assert_array_equal(H, copies[0])
    np.testing.assert_array_equal(G, copies[1])


@pytest.mark.parametrize(
    "H, G, tol, message",
    [
        (np.ones((2, 3)), np.ones(2), 1e-10, r"H must be a non-empty square matrix, got shape \(2, 3\)"),
        (np.eye(3), np.ones(2), 1e-10, r"G must have shape \(3,\) or \(3, m\) to match H, got \(2,\)"),
        (np.eye(2), np.ones((2, 2, 2)), 1e-10, r"G must have shape \(2,\) or \(2, m\)"),
        (np.eye(2), [1.0, np.nan], 1e-10, "G contains NaN or inf"),
        (sp.csc_matrix(np.array([[1.0, np.inf], [np.inf, 1.0]])), np.ones(2), 1e-10, "H contains NaN or inf"),
        (np.eye(2), np.ones(2), 0.0, "tol must be positive"),
        (np.array([[2.0, 1.0], [0.0, 2.0]]), np.ones(2), 1e-10, "H must be symmetric"),
        (np.array([[1.0, 2.0], [2.0, 1.0]]), np.ones(2), 1e-10, "H must be positive definite"),
        (np.zeros((2, 2)), np.ones(2), 1e-10, "H must be positive definite"),
    ],
)
def test_bad_input_raises_value_error_naming_the_problem(H, G, tol, message):
    with pytest.raises(ValueError, match=message):
        box_qp(H, G, tol=tol)


def test_the_admm_start_saves_active_set_steps_on_the_tetrahedral_hand(monkeypatch):
    """The sparse branch starts from ADMM's bounds: fewer free-block factorizations than from the unconstrained minimizer's."""
    V, T = load_mesh("hand_tet")
    b, bc = handle_constraints(list(load_handles("hand_tet")["bones"]))
    free = np.setdiff1d(np.arange(len(V)), b)
    Q = sp.csr_matrix(biharmonic_matrix(V, T))
    H, G = Q[free][:, free].tocsc(), -(Q[free][:, b] @ bc)
    steps = []
    factor = box_qp_module._factor

    def counting_factor(A, permc_spec):
        steps.append(permc_spec == "NATURAL")  # the free blocks, in H's order
        return factor(A, permc_spec)

    monkeypatch.setattr(box_qp_module, "_factor", counting_factor)

    def solve_counting_steps():
        steps.clear()
        with sparse_branch_calls() as calls:
            X = box_qp(H, G)
        assert len(calls) == G.shape[1]
        return X, sum(steps)

    X_admm, steps_admm = solve_counting_steps()
    monkeypatch.setattr(box_qp_module, "_admm_active_sets", lambda H, G, X0, lu, scale: (X0 < 0, X0 > 1))
    X_plain, steps_plain = solve_counting_steps()
    assert steps_admm < 0.8 * steps_plain
    for X in (X_admm, X_plain):
        for x, g in zip(X.T, G.T):
            assert kkt_residual(H, g, x) <= 1e-9
    # both meet the KKT tolerance; H's conditioning turns that into ~1e-8 in x
    np.testing.assert_allclose(X_admm, X_plain, atol=1e-7)


@settings(max_examples=40, deadline=None)
@given(seeds, st.integers(1, 60), st.floats(0.0, 1.0))
def test_principal_submatrices_equal_scipy_indexing_and_come_sorted(seed, n, keep_fraction):
    rng = np.random.default_rng(seed)
    A = sp.random(n, n, density=0.2, random_state=rng, format="csc")
    A = (A + A.T + sp.eye(n)).tocsc()
    A.sort_indices()
    keep = rng.random(n) < keep_fraction
    keep[rng.integers(n)] = True
    columns = np.repeat(np.arange(n), np.diff(A.indptr))
    block = box_qp_module._principal_submatrix(A, columns, keep)
    np.testing.assert_array_equal(block.toarray(), A.toarray()[np.ix_(keep, keep)])
    for start, stop in zip(block.indptr[:-1], block.indptr[1:]):
        assert (np.diff(block.indices[start:stop]) > 0).all()
