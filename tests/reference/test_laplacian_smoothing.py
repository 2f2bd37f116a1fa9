"""The smoothing reference: Laplacians with the contract's sign convention, and steps that are the formula or solve they claim."""

import igl
import numpy as np
import pytest
import scipy.sparse as sp
import scipy.spatial
from hypothesis import given, settings, strategies as st

from reference.laplacian_smoothing import cotangent_matrix, explicit_smoothing_step, implicit_smoothing_step, uniform_laplacian
from starter import shapes
from starter.meshes import load_mesh

seeds = st.integers(0, 2**32 - 1)
course_meshes = st.sampled_from(["torus", "nut", "sphere", "character", "disc_with_holes", "bar_coarse", "ant"])


def delaunay_mesh(seed: int, n: int = 40, lift: bool = False):
    """A Delaunay triangulation of the unit square (optionally lifted onto a smooth height field).

    The boundary is sampled every 0.1 and the random interior points keep 0.1
    away from it, so every angle opposite a boundary edge is acute (at most
    2 atan(0.05 / 0.1) = 53°): all planar cotangent weights are then non-negative.
    """
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, 11)[:-1]
    square = np.vstack([np.c_[t, 0 * t], np.c_[1 + 0 * t, t], np.c_[1 - t, 1 + 0 * t], np.c_[0 * t, 1 - t]])
    P = np.vstack([square, rng.uniform(0.1, 0.9, (n, 2))])
    F = scipy.spatial.Delaunay(P).simplices.astype(np.int64)
    if lift:
        return np.c_[P, 0.3 * np.sin(3 * P[:, 0]) * np.cos(2 * P[:, 1])], F
    return P, F


def masses(V, F):
    return igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_BARYCENTRIC).diagonal()


def components(F, n):
    A = sp.coo_matrix((np.ones(F.size), (np.repeat(F[:, 0], 3), F.ravel())), shape=(n, n))
    return sp.csgraph.connected_components(A + A.T, directed=False)[0]


# --- uniform_laplacian ---


@settings(max_examples=30, deadline=None)
@given(course_meshes)
def test_uniform_laplacian_is_adjacency_minus_degrees(mesh):
    V, F = load_mesh(mesh)
    L = uniform_laplacian(V, F)
    A = igl.adjacency_matrix(F)  # an independent oracle, outside the graded code
    assert sp.issparse(L) and L.shape == (len(V), len(V))
    assert abs(L - (A - sp.diags(np.asarray(A.sum(axis=1)).ravel()))).max() == 0


@settings(max_examples=30, deadline=None)
@given(seeds, st.booleans())
def test_uniform_laplacian_is_symmetric_negative_semidefinite_with_constants_in_its_kernel(seed, lift):
    V, F = delaunay_mesh(seed, lift=lift)
    L = uniform_laplacian(V, F).toarray()
    assert np.array_equal(L, L.T)
    assert np.array_equal(L.sum(axis=1), np.zeros(len(V)))
    eigenvalues = np.linalg.eigvalsh(L)
    assert eigenvalues.max() < 1e-10 * len(V)
    # one zero eigenvalue per connected component: the constants on each
    assert np.sum(np.abs(eigenvalues) < 1e-9) == components(F, len(V)) == 1


@settings(max_examples=20, deadline=None)
@given(seeds)
def test_uniform_laplacian_follows_a_relabelling_of_the_vertices(seed):
    V, F = shapes.torus(n_major=16, n_minor=8)
    perm = np.random.default_rng(seed).permutation(len(V))
    new_index = np.argsort(perm)  # vertex perm[k] becomes vertex k
    L, L_relabelled = uniform_laplacian(V, F), uniform_laplacian(V[perm], new_index[F])
    assert abs(L_relabelled - L[perm][:, perm]).max() == 0


def test_uniform_laplacian_counts_an_edge_once_and_gives_a_lonely_vertex_a_zero_row():
    V = np.zeros((6, 3))
    F = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])  # three triangles on the edge (0, 1); vertex 5 unused
    L = uniform_laplacian(V, F).toarray()
    assert L[0, 1] == 1 and L[0, 0] == -4 and L[2, 2] == -2
    assert not L[5].any() and not L[:, 5].any()


@pytest.mark.parametrize(
    "F, message",
    [(np.array([[0, 1, 4]]), "out of range"), (np.array([[0, 1, 2, 3]]), "shape"), (np.array([[0.0, 1.0, 2.0]]), "integer"), (np.array([[0, 1, -1]]), "out of range")],
)
def test_uniform_laplacian_rejects_bad_triangles(F, message):
    with pytest.raises(ValueError, match=message):
        uniform_laplacian(np.zeros((4, 2)), F)


# --- cotangent_matrix ---


@pytest.mark.parametrize("mesh", ["torus", "nut", "sphere", "character", "disc_with_holes", "bar_coarse", "ant"])
def test_cotangent_matrix_equals_igl_cotmatrix(mesh):
    V, F = load_mesh(mesh)
    L = cotangent_matrix(V, F)
    assert sp.issparse(L)
    assert abs(L - igl.cotmatrix(V, F)).max() <= 1e-12 * abs(L).max()


@settings(max_examples=30, deadline=None)
@given(seeds, st.booleans(), st.booleans())
def test_cotangent_matrix_is_the_dirichlet_energy_of_piecewise_linear_functions(seed, lift, clockwise):
    V, F = delaunay_mesh(seed, lift=lift)
    F = F[:, ::-1] if clockwise else F
    L = cotangent_matrix(V, F)
    u = np.random.default_rng(seed).normal(size=len(V))
    # ∫ |∇u|² from the per-triangle gradients (igl.grad), independent of cotangents
    G = igl.grad(V if lift else np.c_[V, np.zeros(len(V))], F)
    area = igl.doublearea(V, F) / 2 if lift else np.abs(igl.doublearea(V, F)) / 2
    grad = (G @ u).reshape(3, len(F)).T
    dirichlet = np.sum(area * np.sum(grad**2, axis=1))
    assert -u @ (L @ u) == pytest.approx(dirichlet, rel=1e-9)
    assert abs(L - L.T).max() <= 1e-14 * abs(L).max()
    assert np.abs(np.asarray(L.sum(axis=1))).max() <= 1e-12 * abs(L).max()


@settings(max_examples=30, deadline=None)
@given(seeds)
def test_cotangent_matrix_of_a_planar_delaunay_mesh_is_negative_semidefinite_with_linear_precision(seed):
    V, F = delaunay_mesh(seed)
    L = cotangent_matrix(V, F)
    # Delaunay: cot α + cot β >= 0 on every edge, so -L is a weighted graph Laplacian
    off = (L - sp.diags(L.diagonal())).toarray()
    assert off.min() >= -1e-12
    assert np.linalg.eigvalsh(L.toarray()).max() < 1e-10 * abs(L).max()
    # linear functions are harmonic at interior vertices
    boundary = np.unique(np.concatenate(igl.boundary_loop_all(F)))
    interior = np.setdiff1d(np.arange(len(V)), boundary)
    assert np.abs((L @ V)[interior]).max() <= 1e-12 * abs(L).max()


@settings(max_examples=20, deadline=None)
@given(seeds, st.floats(1e-3, 1e3))
def test_cotangent_matrix_ignores_scale_rotation_and_translation(seed, scale):
    V, F = delaunay_mesh(seed, lift=True)
    rng = np.random.default_rng(seed)
    Q, R = np.linalg.qr(rng.normal(size=(3, 3)))
    moved = scale * V @ (Q * np.sign(np.diag(R))).T + rng.normal(size=3) * 100
    L = cotangent_matrix(V, F)
    assert abs(cotangent_matrix(moved, F) - L).max() <= 1e-8 * abs(L).max()


def test_cotangent_matrix_keeps_negative_cotangents_and_rejects_zero_area():
    V = np.array([[0.0, 0.0], [2.0, 0.0], [1.0, 0.2]])
    L = cotangent_matrix(V, np.array([[0, 1, 2]])).toarray()
    a, b = V[0] - V[2], V[1] - V[2]
    assert L[0, 1] == pytest.approx(0.5 * (a @ b) / abs(a[0] * b[1] - a[1] * b[0])) and L[0, 1] < 0
    with pytest.raises(ValueError, match="zero-area"):
        cotangent_matrix(np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]), np.array([[0, 1, 2]]))


# --- the steps ---


def step_problem(seed, d=3, dense=False):
    """A noisy torus (128 vertices) with its cotangent Laplacian and barycentric masses."""
    V, F = shapes.torus(n_major=16, n_minor=8)
    rng = np.random.default_rng(seed)
    L = cotangent_matrix(V, F)
    U = np.c_[V, rng.normal(size=(len(V), max(d - 3, 0)))][:, :d] + 0.01 * rng.normal(size=(len(V), d))
    return U, (L.toarray() if dense else L), masses(V, F)


@settings(max_examples=30, deadline=None)
@given(seeds, st.floats(0.0, 0.05), st.integers(1, 5))
def test_explicit_step_is_the_forward_euler_formula_and_keeps_the_weighted_centroid(seed, h, d):
    U, L, m = step_problem(seed, d)
    before = U.copy()
    out = explicit_smoothing_step(U, L, m, h)
    assert np.array_equal(U, before)  # inputs are never modified
    assert out.shape == U.shape
    Ld = L.toarray()
    assert np.allclose(out, U + h * np.linalg.solve(np.diag(m), Ld @ U), rtol=0, atol=1e-12 * max(1.0, np.abs(out).max()))
    assert np.allclose(m @ out, m @ U, rtol=0, atol=1e-12 * np.abs(m @ np.abs(U)).max())
    # a dense L gives the same step (the grader sends dense arrays)
    assert np.allclose(explicit_smoothing_step(U, Ld, m, h), out, rtol=0, atol=1e-14 * max(1.0, np.abs(out).max()))


@settings(max_examples=20, deadline=None)
@given(seeds)
def test_explicit_step_amplifies_the_top_eigenvector_just_above_the_critical_step(seed):
    U, L, m = step_problem(seed)
    # -L x = λ M x, in the symmetric form S = M^-1/2 (-L) M^-1/2
    s = 1 / np.sqrt(m)
    lam, Y = np.linalg.eigh(s[:, None] * -L.toarray() * s[None, :])
    x = (s * Y[:, -1])[:, None]
    for factor, grows in [(0.99, False), (1.01, True)]:
        h = factor * 2 / lam[-1]
        out = explicit_smoothing_step(x, L, m, h)
        assert np.allclose(out, (1 - h * lam[-1]) * x, atol=1e-9 * np.abs(x).max())
        assert (np.abs(out).max() > np.abs(x).max()) == grows


@settings(max_examples=30, deadline=None)
@given(seeds, st.floats(0.0, 1e4), st.integers(1, 4), st.booleans())
def test_implicit_step_solves_its_system_and_keeps_the_weighted_centroid(seed, h, d, dense):
    U, L, m = step_problem(seed, d, dense)
    out = implicit_smoothing_step(U, L, m, h)
    assert out.shape == U.shape
    Ld = L if dense else L.toarray()
    residual = m[:, None] * out - h * (Ld @ out) - m[:, None] * U
    assert np.abs(residual).max() <= 1e-12 * np.max(np.abs(m[:, None] * U) + h * (np.abs(Ld) @ np.abs(out)))
    assert np.allclose(m @ out, m @ U, rtol=0, atol=1e-10 * np.abs(m @ np.abs(U)).max())


@settings(max_examples=20, deadline=None)
@given(seeds, st.floats(1e-4, 10.0))
def test_implicit_step_damps_every_eigenvector_by_one_over_one_plus_h_lambda(seed, h):
    U, L, m = step_problem(seed, d=2)
    s = 1 / np.sqrt(m)
    lam, Y = np.linalg.eigh(s[:, None] * -L.toarray() * s[None, :])
    X = s[:, None] * Y  # M-orthonormal eigenvectors of -M⁻¹ L
    coefficients = X.T @ (m[:, None] * U)
    predicted = X @ (coefficients / (1 + h * np.maximum(lam, 0))[:, None])
    assert np.allclose(implicit_smoothing_step(U, L, m, h), predicted, rtol=0, atol=1e-9 * np.abs(U).max())
    # so it never raises the Dirichlet energy, for any h: unconditionally stable
    out = implicit_smoothing_step(U, L, m, h)
    assert -np.sum(out * (L @ out)) <= -np.sum(U * (L @ U)) * (1 + 1e-12)


def test_steps_of_size_zero_return_their_input_and_a_huge_implicit_step_reaches_the_centroid():
    U, L, m = step_problem(0)
    assert np.array_equal(explicit_smoothing_step(U, L, m, 0.0), U)
    assert np.allclose(implicit_smoothing_step(U, L, m, 0.0), U, rtol=0, atol=1e-15)
    out = implicit_smoothing_step(U, L, m, 1e9)
    assert np.abs(out - m @ U / m.sum()).max() < 1e-6


@pytest.mark.parametrize("step", [explicit_smoothing_step, implicit_smoothing_step])
def test_steps_reject_bad_input_by_name(step):
    U, L, m = step_problem(0)
    for args, message in [
        ((U, L, m, -1.0), "h must be non-negative"),
        ((U, L, m, np.inf), "h contains NaN or inf"),
        ((U, L, np.r_[0.0, m[1:]], 0.1), "masses must be positive"),
        ((U, L, m[:-1], 0.1), "one mass per vertex"),
        ((U, L[:-1, :-1], m, 0.1), "L must be an"),
        ((U[:, 0], L, m, 0.1), "U must be a 2-D"),
    ]:
        with pytest.raises(ValueError, match=message):
            step(*args)
