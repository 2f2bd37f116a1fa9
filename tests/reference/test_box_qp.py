from contextlib import contextmanager

import igl.triangle
import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.sparse.csgraph import shortest_path
from hypothesis import given, settings, strategies as st
from threadpoolctl import threadpool_info

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


def hand_problem():
    """The tetrahedral hand's BBW problem with its six bones: ``(H, G)``, ``H`` ``(n, n)`` sparse, ``G`` ``(n, 6)``."""
    V, T = load_mesh("hand_tet")
    b, bc = handle_constraints(list(load_handles("hand_tet")["bones"]))
    free = np.setdiff1d(np.arange(len(V)), b)
    Q = sp.csr_matrix(biharmonic_matrix(V, T))
    return Q[free][:, free].tocsc(), -(Q[free][:, b] @ bc)


def solve_counting(monkeypatch, H, G):
    """``box_qp(H, G)``, with its active-set steps and its factorizations of free blocks counted."""
    steps, factorizations = [], []
    solve, refactor = box_qp_module._FreeBlockSolver.solve, box_qp_module._FreeBlockSolver._refactor

    def counting_solve(self, free, r):
        steps.append(1)
        return solve(self, free, r)

    def counting_refactor(self, free):
        factorizations.append(1)
        return refactor(self, free)

    monkeypatch.setattr(box_qp_module._FreeBlockSolver, "solve", counting_solve)
    monkeypatch.setattr(box_qp_module._FreeBlockSolver, "_refactor", counting_refactor)
    with sparse_branch_calls() as calls:
        X = box_qp(H, G)
    assert len(calls) == G.shape[1]
    return X, len(steps), len(factorizations)


def test_the_admm_start_saves_active_set_steps_on_the_tetrahedral_hand(monkeypatch):
    """The sparse branch starts from ADMM's bounds: fewer active-set steps than from the unconstrained minimizer's."""
    H, G = hand_problem()
    # all of ADMM_STEPS, as on a graph many rings across (the hand's 17 rings
    # would get 8 steps, which save less there and cost less)
    monkeypatch.setattr(box_qp_module, "_admm_steps", lambda H: box_qp_module.ADMM_STEPS)
    X_admm, steps_admm, _ = solve_counting(monkeypatch, H, G)
    monkeypatch.setattr(box_qp_module, "_admm_active_sets", lambda H, G, X0, rho, steps: (X0 < 0, X0 > 1, X0))
    X_plain, steps_plain, _ = solve_counting(monkeypatch, H, G)
    assert steps_admm < 0.8 * steps_plain
    for X in (X_admm, X_plain):
        for x, g in zip(X.T, G.T):
            assert kkt_residual(H, g, x) <= 1e-9
    # both meet the KKT tolerance; H's conditioning turns that into ~1e-8 in x
    np.testing.assert_allclose(X_admm, X_plain, atol=1e-7)


def test_releasing_at_admms_iterate_before_the_first_factorization_saves_steps_on_the_hand(monkeypatch):
    """The first step's releases, taken where ADMM stopped, put most of the missed front in the first block."""
    H, G = hand_problem()
    X, steps, factorizations = solve_counting(monkeypatch, H, G)
    original = box_qp_module._sparse_active_set
    monkeypatch.setattr(box_qp_module, "_sparse_active_set", lambda *args: original(*args[:7]))  # no start
    X_late, steps_late, factorizations_late = solve_counting(monkeypatch, H, G)
    assert steps < steps_late and factorizations < factorizations_late
    for x, g in zip(X.T, G.T):
        assert kkt_residual(H, g, x) <= 1e-9
    np.testing.assert_allclose(X, X_late, atol=1e-7)


def test_bordered_free_blocks_save_factorizations_and_give_the_same_weights(monkeypatch):
    """Steps whose free set moved a little reuse the last factorization: same minimizer, far fewer factorizations."""
    H, G = hand_problem()
    X, steps, factorizations = solve_counting(monkeypatch, H, G)
    monkeypatch.setattr(box_qp_module, "BORDER_BUDGET", 0.0)
    X_refactored, steps_refactored, factorizations_refactored = solve_counting(monkeypatch, H, G)
    assert factorizations_refactored == steps_refactored
    assert factorizations <= 0.6 * steps
    for x, g in zip(X.T, G.T):
        assert kkt_residual(H, g, x) <= 1e-9
    np.testing.assert_allclose(X, X_refactored, atol=1e-7)


def random_sparse_spd(rng, n, density):
    """``A Aᵀ + D`` ``(n, n)`` CSC, ``A`` sparse random with ``density``, ``D`` a positive diagonal in [0.1, 2]."""
    A = sp.random(n, n, density=density, random_state=rng, format="csc")
    return (A @ A.T + sp.diags(rng.uniform(0.1, 2.0, n))).tocsc()


def cholesky_factor(H):
    """The pattern of ``H``'s upper triangular Cholesky factor in its natural order, CSC with unit entries."""
    return sp.csc_matrix((np.linalg.cholesky(H.toarray()).T != 0).astype(np.float64))


def free_block_solver(H):
    """``_FreeBlockSolver`` for ``H`` (CSC, sorted)."""
    return box_qp_module._FreeBlockSolver(H, np.repeat(np.arange(H.shape[0]), np.diff(H.indptr)), cholesky_factor(H))


@settings(max_examples=60, deadline=None)
@given(seeds, st.integers(2, 80), st.integers(0, 12), st.integers(0, 12))
def test_bordered_solves_equal_factorizations_of_the_moved_free_blocks(seed, n, n_added, n_removed):
    """Two steps bordering one base block (the second reuses the first's slots, both may grow them)."""
    rng = np.random.default_rng(seed)
    H = random_sparse_spd(rng, n, 0.15)
    H.sort_indices()
    base = rng.random(n) < 0.6
    base[rng.integers(n)] = True
    check_bordered_solves(H, free_block_solver(H), base, rng, n_added, n_removed)


def check_bordered_solves(H, blocks, base, rng, n_added, n_removed):
    n = H.shape[0]
    r = rng.normal(size=n)
    np.testing.assert_allclose(blocks.solve(base, r), spla.spsolve(H[base][:, base].tocsc(), r[base]), rtol=1e-8, atol=1e-10)
    blocks.budget = np.inf  # the bordered path, however much moved
    for _ in range(2):
        free = base.copy()
        free[rng.permutation(np.flatnonzero(~base))[:n_added]] = True
        removable = np.flatnonzero(base)
        free[rng.permutation(removable)[:min(n_removed, len(removable) - 1)]] = False
        r = rng.normal(size=n)
        x = blocks.solve(free, r)
        assert np.array_equal(blocks.base, base)
        expected = np.atleast_1d(spla.spsolve(H[free][:, free].tocsc(), r[free]))
        np.testing.assert_allclose(x, expected, rtol=1e-7, atol=1e-9 * np.abs(expected).max())


def test_a_free_set_moved_past_the_budget_is_factored_anew():
    H = chain_biharmonic(40)
    H.sort_indices()
    blocks = free_block_solver(H)
    base = np.arange(40) < 30
    blocks.solve(base, np.ones(40))
    blocks.budget = 3
    moved = np.arange(40) < 34
    x = blocks.solve(moved, np.ones(40))
    assert np.array_equal(blocks.base, moved)
    np.testing.assert_allclose(H[:34, :34] @ x, np.ones(34), atol=1e-8)


def test_box_qp_runs_blas_on_one_thread(monkeypatch):
    """Its dense steps are small: OpenBLAS's threads would only spin (0.36 s instead of 0.10 s on the hand)."""
    seen = []
    solve = box_qp_module._solve

    def spy(H, G, tol):
        seen.extend(pool["num_threads"] for pool in threadpool_info() if pool["user_api"] == "blas")
        return solve(H, G, tol)

    monkeypatch.setattr(box_qp_module, "_solve", spy)
    H, G = random_dense_problem(0, 5, 2)
    box_qp(H, G)
    assert seen and set(seen) == {1}


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


@settings(max_examples=60, deadline=None)
@given(seeds, st.integers(2, 60), st.floats(0.1, 0.9))
def test_idle_variables_are_the_free_components_whose_minimizer_is_exactly_zero(seed, n, free_fraction):
    """``_idle`` marks exactly the free components of ``H`` with a zero right-hand side, where the block solve gives 0."""
    rng = np.random.default_rng(seed)
    H = random_sparse_spd(rng, n, 2.0 / n)
    H.sort_indices()
    columns = np.repeat(np.arange(n), np.diff(H.indptr))
    free = rng.random(n) < free_fraction
    free[rng.integers(n)] = True
    block = H[free][:, free]
    count, labels = sp.csgraph.connected_components(block, directed=False)
    driven_components = rng.random(count) < 0.5
    r = np.zeros(n)
    r[free] = np.where(driven_components[labels], rng.normal(size=free.sum()), 0.0)
    idle = box_qp_module._idle(H, columns, free, r)
    expected = np.zeros(n, dtype=bool)
    if count > 1:
        expected[np.flatnonzero(free)[~(np.bincount(labels, weights=r[free] != 0, minlength=count) > 0)[labels]]] = True
    np.testing.assert_array_equal(idle, expected)
    assert not (idle & ~free).any()
    x = np.zeros(n)
    x[free] = np.atleast_1d(spla.spsolve(block.tocsc(), r[free]))
    assert (x[idle] == 0.0).all()


def test_idle_islands_left_out_of_the_free_blocks_give_the_same_weights_from_smaller_factorizations(monkeypatch):
    """On the tetrahedral hand, ADMM leaves islands free around the other bones; pinned, the factored blocks shrink."""
    H, G = hand_problem()
    monkeypatch.setattr(box_qp_module, "_admm_steps", lambda H: box_qp_module.ADMM_STEPS)  # as above
    sizes = []
    refactor = box_qp_module._FreeBlockSolver._refactor

    def measuring_refactor(self, free):
        sizes.append(int(free.sum()))
        return refactor(self, free)

    monkeypatch.setattr(box_qp_module._FreeBlockSolver, "_refactor", measuring_refactor)
    X = box_qp(H, G)
    pinned_sizes, sizes[:] = list(sizes), []
    monkeypatch.setattr(box_qp_module, "_idle", lambda H, columns, free, r: np.zeros_like(free))
    X_islands = box_qp(H, G)
    assert sum(pinned_sizes) < 0.8 * sum(sizes)
    for x, g in zip(X.T, G.T):
        assert kkt_residual(H, g, x) <= 1e-9
    np.testing.assert_allclose(X, X_islands, atol=1e-7)


@settings(max_examples=60, deadline=None)
@given(seeds, st.integers(2, 60), st.integers(1, 3), st.floats(0.0, 2.0))
def test_widened_starts_free_exactly_the_bound_variables_coupled_to_a_free_one_in_columns_with_a_thin_ring(
    seed, n, m, widen_max,
):
    rng = np.random.default_rng(seed)
    H = random_sparse_spd(rng, n, 2.0 / n)
    state = rng.integers(0, 3, size=(n, m))  # 0 free, 1 lower, 2 upper
    at_lower, at_upper = state == 1, state == 2
    original = box_qp_module.WIDEN_MAX
    box_qp_module.WIDEN_MAX = widen_max
    try:
        lower, upper = box_qp_module._widened(H, at_lower.copy(), at_upper.copy())
    finally:
        box_qp_module.WIDEN_MAX = original
    coupled = H.toarray() != 0
    for j in range(m):
        free = ~(at_lower[:, j] | at_upper[:, j])
        ring = coupled[:, free].any(axis=1) & ~free
        expected = ring if ring.sum() <= widen_max * free.sum() else np.zeros(n, dtype=bool)
        np.testing.assert_array_equal(lower[:, j], at_lower[:, j] & ~expected)
        np.testing.assert_array_equal(upper[:, j], at_upper[:, j] & ~expected)


def square_problem():
    """BBW on a triangulated 2 x 2 square (~1,600 vertices) with three point handles: ``(H, G)``."""
    corners = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]])
    V, F, *_ = igl.triangle.triangulate(corners, np.array([[0, 1], [1, 2], [2, 3], [3, 0]]), flags="pq30a0.002Q")
    handles = [[int(np.argmin(np.linalg.norm(V - p, axis=1)))] for p in ([0.3, 0.3], [1.7, 0.5], [1.0, 1.7])]
    b, bc = handle_constraints(handles)
    free = np.setdiff1d(np.arange(len(V)), b)
    Q = sp.csr_matrix(biharmonic_matrix(V, F))
    return Q[free][:, free].tocsc(), -(Q[free][:, b] @ bc)


def test_a_start_one_ring_wider_saves_factorizations_on_a_triangle_mesh_and_gives_the_same_weights(monkeypatch):
    """The free sets then shrink in bulk rather than grow a ring per step; the tetrahedral hand's thick rings stay out."""
    H, G = square_problem()
    X, _, factorizations = solve_counting(monkeypatch, H, G)
    monkeypatch.setattr(box_qp_module, "WIDEN_MAX", 0.0)
    X_narrow, _, factorizations_narrow = solve_counting(monkeypatch, H, G)
    assert factorizations < factorizations_narrow
    for x, g in zip(X.T, G.T):
        assert kkt_residual(H, g, x) <= 1e-9
    np.testing.assert_allclose(X, X_narrow, atol=1e-7)


def test_releasing_the_clearly_wrong_multipliers_first_saves_factorizations_and_gives_the_same_weights(monkeypatch):
    """Fewer variables leave their bounds per step, so more steps border the last factorization."""
    H, G = square_problem()
    X, _, factorizations = solve_counting(monkeypatch, H, G)
    monkeypatch.setattr(box_qp_module, "RELEASE_RANGE", 0.0)
    X_all, _, factorizations_all = solve_counting(monkeypatch, H, G)
    assert factorizations < factorizations_all
    for x, g in zip(X.T, G.T):
        assert kkt_residual(H, g, x) <= 1e-9
    np.testing.assert_allclose(X, X_all, atol=1e-7)


def test_releasing_one_ring_ahead_saves_active_set_steps_and_gives_the_same_weights(monkeypatch):
    """A step that only releases also releases the neighbours its Jacobi move would make wrong: fewer steps."""
    H, G = square_problem()
    X, steps, _ = solve_counting(monkeypatch, H, G)
    monkeypatch.setattr(box_qp_module, "_lookahead", lambda H, diagonal, gradient, lower, upper, release, tol: release)
    X_ring, steps_ring, _ = solve_counting(monkeypatch, H, G)
    assert steps < steps_ring
    for x, g in zip(X.T, G.T):
        assert kkt_residual(H, g, x) <= 1e-9
    np.testing.assert_allclose(X, X_ring, atol=1e-7)


@settings(max_examples=60, deadline=None)
@given(seeds, st.integers(3, 40))
def test_lookahead_adds_exactly_the_bound_variables_whose_predicted_multiplier_turns_wrong(seed, n):
    rng = np.random.default_rng(seed)
    H = chain_biharmonic(n)
    bound = rng.random(n) < 0.7
    lower = bound & (rng.random(n) < 0.5)
    upper = bound & ~lower
    gradient = rng.normal(size=n)
    release = (lower & (gradient < 0)) | (upper & (gradient > 0))
    tol = 1e-3
    released = box_qp_module._lookahead(H, H.diagonal(), gradient, lower, upper, release, tol)
    # each released variable moves to where its own gradient would vanish
    moved = np.zeros(n)
    moved[release] = -gradient[release] / H.diagonal()[release]
    predicted = gradient + H.toarray() @ moved
    wrong = (lower & (predicted < -tol)) | (upper & (predicted > tol))
    np.testing.assert_array_equal(released, release | wrong)
    assert not (released & ~bound).any()


@settings(max_examples=60, deadline=None)
@given(seeds, st.integers(2, 60), st.floats(0.05, 1.0))
def test_the_column_count_estimate_bounds_the_block_factor_column_by_column(seed, n, free_fraction):
    """The full factor's pattern restricted to a free block contains the block factor's: it bounds every column count."""
    rng = np.random.default_rng(seed)
    H = random_sparse_spd(rng, n, 0.1)
    H.sort_indices()
    free = rng.random(n) < free_fraction
    free[rng.integers(n)] = True
    columns = np.repeat(np.arange(n), np.diff(H.indptr))
    blocks = box_qp_module._FreeBlockSolver(H, columns, cholesky_factor(H))
    block = box_qp_module._factor(box_qp_module._principal_submatrix(H, columns, free), "NATURAL")
    # SuperLU may postorder the block's elimination tree: an equivalent order
    # with the same column counts, permuted, so compare them sorted
    column_counts = np.sort(np.diff(block.L.indptr))
    bounds = np.sort(blocks._column_counts(free))
    assert bounds.shape == column_counts.shape
    assert (bounds >= column_counts).all()


@settings(max_examples=40, deadline=None)
@given(seeds, st.integers(1, 60), st.integers(1, 4))
def test_a_sparse_block_factor_solves_like_a_dense_solve(seed, n, q):
    """CHOLMOD's factor, in the block's own order, reading the lower triangle only."""
    rng = np.random.default_rng(seed)
    H = random_sparse_spd(rng, n, 0.2)
    factor = box_qp_module._SparseCholesky(H)
    B = rng.normal(size=(n, q))
    expected = np.linalg.solve(H.toarray(), B)
    np.testing.assert_allclose(factor.solve(B), expected, rtol=1e-8, atol=1e-10 * np.abs(expected).max())
    assert factor.solve(B[:, 0]).shape == (n,)


@settings(max_examples=40, deadline=None)
@given(seeds, st.integers(1, 60))
def test_a_fill_reducing_factor_reads_out_its_order_and_its_lower_factor(seed, n):
    """AMD's order then CHOLMOD's postorder: ``H[order][:, order] = L Lᵀ``, ``L`` lower triangular."""
    rng = np.random.default_rng(seed)
    H = random_sparse_spd(rng, n, 0.2)
    factor = box_qp_module._SparseCholesky(H, fill_reducing=True)
    np.testing.assert_allclose(H @ factor.solve(np.ones(n)), np.ones(n), atol=1e-9)
    order, L = factor.read_out()
    assert np.array_equal(np.sort(order), np.arange(n))
    assert sp.triu(L, 1).nnz == 0
    np.testing.assert_allclose((L @ L.T).toarray(), H[order][:, order].toarray(), atol=1e-12 * abs(H).max())


def test_a_sparse_block_that_is_not_positive_definite_names_the_problem():
    with pytest.raises(ValueError, match="H must be positive definite"):
        box_qp_module._SparseCholesky(sp.csc_matrix(np.array([[1.0, 2.0], [2.0, 1.0]])))


def test_factoring_a_block_leaves_cholmods_settings_as_they_were():
    """cvxopt keeps CHOLMOD's settings in one dict that other code may use: box_qp's hold only while it factors."""
    from cvxopt import cholmod

    before = dict(cholmod.options)
    box_qp_module._SparseCholesky(chain_biharmonic(10).tocsc())
    assert dict(cholmod.options) == before


@pytest.mark.parametrize("n", [2, 3, 10, 41])
def test_rings_across_a_chain_are_its_length_in_two_neighbour_hops(n):
    """The chain's H couples each variable to two on either side: ⌈(n - 1) / 2⌉ rings from end to end."""
    assert box_qp_module._rings_across(chain_biharmonic(n)) == (n - 1 + 1) // 2


@settings(max_examples=40, deadline=None)
@given(seeds, st.integers(2, 60))
def test_rings_across_a_connected_graph_lie_between_half_its_diameter_and_its_diameter(seed, n):
    """Two breadth-first sweeps from a vertex and then from the farthest one found."""
    rng = np.random.default_rng(seed)
    A = sp.random(n, n, density=2.0 / n, random_state=rng, format="csr")
    chain = sp.diags([np.ones(n - 1)], [1], shape=(n, n))  # keeps it connected
    pattern = sp.csr_matrix(((A + A.T + chain + chain.T + sp.eye(n)) != 0).astype(np.float64))
    diameter = int(shortest_path(pattern, unweighted=True).max())
    rings = box_qp_module._rings_across(pattern)
    assert diameter <= 2 * rings
    assert rings <= diameter


def test_admm_runs_half_as_many_steps_as_the_hand_is_rings_across(monkeypatch):
    """The hand is 17 rings across: 8 ADMM steps; the family's 2D character, 70 rings across, all of ADMM_STEPS."""
    H, G = hand_problem()
    taken = []
    admm = box_qp_module._admm_active_sets

    def recording(H, G, X0, rho, steps):
        taken.append(steps)
        return admm(H, G, X0, rho, steps)

    monkeypatch.setattr(box_qp_module, "_admm_active_sets", recording)
    box_qp(H, G)
    assert box_qp_module._rings_across(H) == 17
    assert taken == [8]


@pytest.mark.parametrize("steps", [0, 5])
def test_admm_steps_change_the_path_never_the_minimizer(monkeypatch, steps):
    """ADMM only predicts the active sets: with fewer steps (or none) the solver takes more, to the same minimizer."""
    H, G = hand_problem()
    X = box_qp(H, G)
    monkeypatch.setattr(box_qp_module, "ADMM_STEPS", steps)
    X_other = box_qp(H, G)
    for x, g in zip(X_other.T, G.T):
        assert kkt_residual(H, g, x) <= 1e-9
    np.testing.assert_allclose(X, X_other, atol=1e-7)