"""Stage 03, as-rigid-as-possible deformation: cotangent weights, the local step and the global step.

The energy is the lecture's "spokes and rims" energy (libigl's
``ARAP_ENERGY_TYPE_SPOKES_AND_RIMS``): every vertex ``i`` has a rotation ``R_i``
and its cell is every triangle around it, all three edges of each:

    E(U, R) = Σ_i Σ_{t ∋ i} Σ_k C[t, k] ‖e'_tk - R_i e_tk‖²,

``e_tk`` the rest edge opposite corner ``k`` of triangle ``t`` and ``e'_tk`` the
same edge in the deformed mesh ``U``.
"""

import types

import cholespy
import numpy as np
import scipy.sparse as sp

from reference.sign_correction import optimal_rotation
from starter.validation import (
    component_without,
    as_corner_weights,
    as_faces,
    as_float_array,
    as_handle_positions,
    as_handles,
    as_vertices,
    check_no_degenerate_triangles,
)


def cotangent_weights(V, F):
    """Half cotangents of the triangle corners.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions, ``d`` in {2, 3}.
    F : (f, 3) array_like of int
        Triangles; none may have zero area.

    Returns
    -------
    C : (f, 3) numpy.ndarray
        ``C[t, k] = ½ cot`` of the angle at corner ``k`` of triangle ``t``, the
        weight of the opposite edge ``(F[t, (k+1)%3], F[t, (k+2)%3])``.
    """
    V = as_vertices(V)
    F = as_faces(F, len(V))
    check_no_degenerate_triangles(V, F)
    corners = V[F]
    # edges from each corner to the next two corners
    to_next = np.roll(corners, -1, axis=1) - corners
    to_after = np.roll(corners, -2, axis=1) - corners
    dot = np.einsum("tkd,tkd->tk", to_next, to_after)
    e1, e2 = to_next[:, 0], to_after[:, 0]
    if V.shape[1] == 2:
        double_area = np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    else:
        double_area = np.linalg.norm(np.cross(e1, e2), axis=1)
    # cot = cos / sin = (u · v) / |u x v|, and |u x v| is twice the area at every corner
    return 0.5 * dot / double_area[:, None]


def cotangent_laplacian(V, F):
    """Cotangent Laplacian (equals ``igl.cotmatrix``).

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions, ``d`` in {2, 3}.
    F : (f, 3) array_like of int
        Triangles; none may have zero area.

    Returns
    -------
    L : (n, n) scipy.sparse.csr_matrix
        Symmetric: ``L[i, j]`` is the sum of ``cotangent_weights`` over the
        triangle edges ``(i, j)``, ``L[i, i] = -Σ_{j≠i} L[i, j]``; negative
        semi-definite, with the constants in its kernel.
    """
    V = as_vertices(V)
    F = as_faces(F, len(V))
    C = cotangent_weights(V, F)
    n = len(V)
    rows = np.concatenate([F[:, [1, 2, 0]].ravel(), F[:, [2, 0, 1]].ravel()])
    cols = np.concatenate([F[:, [2, 0, 1]].ravel(), F[:, [1, 2, 0]].ravel()])
    W = sp.csr_matrix((np.concatenate([C.ravel(), C.ravel()]), (rows, cols)), shape=(n, n))
    return (W - sp.diags(np.asarray(W.sum(axis=1)).ravel())).tocsr()


def arap_covariances(V, U, F, C):
    """Per-vertex covariance matrices of the ARAP cells.

    Parameters
    ----------
    V : (n, d) array_like of float
        Rest positions, ``d`` in {2, 3}.
    U : (n, d) array_like of float
        Deformed positions.
    F : (f, 3) array_like of int
        Triangles.
    C : (f, 3) array_like of float
        Corner weights, e.g. ``cotangent_weights(V, F)``.

    Returns
    -------
    S : (n, d, d) numpy.ndarray
        ``S_i = Σ_{t ∋ i} Σ_k C[t, k] e_tk e'_tkᵀ``: the same triangle matrix
        ``T_t = Σ_k C[t, k] e_tk e'_tkᵀ`` goes to each of the three corners.
    """
    V = as_vertices(V)
    U = as_float_array(U, "U", ndim=2)
    if U.shape != V.shape:
        raise ValueError(f"U must have the shape of V, {V.shape}, got {U.shape}")
    F = as_faces(F, len(V))
    C = as_corner_weights(C, len(F))
    n, d = V.shape
    # edge opposite corner k: from vertex F[t, (k+2)%3] to F[t, (k+1)%3]
    E = V[np.roll(F, -1, axis=1)] - V[np.roll(F, -2, axis=1)]
    E_def = U[np.roll(F, -1, axis=1)] - U[np.roll(F, -2, axis=1)]
    T = np.einsum("tk,tka,tkb->tab", C, E, E_def).reshape(len(F), d * d)
    S = np.empty((n, d * d))
    corner_of = F.ravel()
    for j in range(d * d):
        S[:, j] = np.bincount(corner_of, weights=np.repeat(T[:, j], 3), minlength=n)
    return S.reshape(n, d, d)


def arap_rotations(V, U, F, C):
    """The ARAP local step: the best rotation of every cell.

    Parameters
    ----------
    V : (n, d) array_like of float
        Rest positions, ``d`` in {2, 3}.
    U : (n, d) array_like of float
        Deformed positions.
    F : (f, 3) array_like of int
        Triangles.
    C : (f, 3) array_like of float
        Corner weights, e.g. ``cotangent_weights(V, F)``.

    Returns
    -------
    R : (n, d, d) numpy.ndarray
        ``R_i = optimal_rotation(S_i)`` for ``S = arap_covariances(V, U, F, C)``:
        the rotation minimizing ``arap_energy`` for fixed ``U``.
    """
    return optimal_rotation(arap_covariances(V, U, F, C))


def arap_energy(V, U, F, C, R):
    """Spokes-and-rims ARAP energy.

    Parameters
    ----------
    V : (n, d) array_like of float
        Rest positions, ``d`` in {2, 3}.
    U : (n, d) array_like of float
        Deformed positions.
    F : (f, 3) array_like of int
        Triangles.
    C : (f, 3) array_like of float
        Corner weights, e.g. ``cotangent_weights(V, F)``.
    R : (n, d, d) array_like of float
        One matrix per vertex (rotations, but any matrices are accepted).

    Returns
    -------
    float
        ``Σ_i Σ_{t ∋ i} Σ_k C[t, k] ‖e'_tk - R_i e_tk‖²``.
    """
    V = as_vertices(V)
    U = as_float_array(U, "U", ndim=2)
    if U.shape != V.shape:
        raise ValueError(f"U must have the shape of V, {V.shape}, got {U.shape}")
    F = as_faces(F, len(V))
    C = as_corner_weights(C, len(F))
    n, d = V.shape
    R = as_float_array(R, "R", ndim=3)
    if R.shape != (n, d, d):
        raise ValueError(f"R must have shape ({n}, {d}, {d}), one matrix per vertex, got {R.shape}")
    E = V[np.roll(F, -1, axis=1)] - V[np.roll(F, -2, axis=1)]
    E_def = U[np.roll(F, -1, axis=1)] - U[np.roll(F, -2, axis=1)]
    energy = 0.0
    for corner in range(3):
        residual = E_def - np.einsum("tab,tkb->tka", R[F[:, corner]], E)
        energy += float(np.sum(C * np.einsum("tka,tka->tk", residual, residual)))
    return energy


def cell_rotations_transposed(S):
    """``optimal_rotation`` of a stack of 3x3 matrices, transposed, by the polar formula of their signed invariants.

    Parameters
    ----------
    S : (k, 3, 3) numpy.ndarray of float
        Covariance matrices, e.g. the ARAP local step's (finite).

    Returns
    -------
    Rt : (k, 3, 3) numpy.ndarray
        ``Rt[i] = R_iᵀ`` for ``R_i`` the rotation maximizing ``tr(R_i S_i)``:
        the lecture's sign-corrected ``Ũ D Uᵀ`` to ``1e-12`` (``optimal_rotation(S)``
        within that function's own accuracy), in the layout the global step's
        right-hand side multiplies, so no transposed copy is made.

    Notes
    -----
    For the SVD ``S = U Σ Ũᵀ``, let ``σ₃`` carry the sign of ``det S`` and
    ``I₁ = σ₁ + σ₂ + σ₃``, ``I₂ = σ₁σ₂ + σ₁σ₃ + σ₂σ₃``, ``I₃ = σ₁σ₂σ₃ = det S``.
    ``S``, ``cof S`` and ``S Sᵀ S`` are ``U diag(f(σ)) Ũᵀ`` for ``f(σ) = σ,
    I₃/σ, σ³``, and by Cayley-Hamilton ``(I₁² - I₂) σ + I₁ I₃/σ - σ³ = I₁ I₂ - I₃``
    at each ``σᵢ``, so ``Rᵀ = U D Ũᵀ = ((I₁² - I₂) S + I₁ cof S - S Sᵀ S) / (I₁ I₂ - I₃)``
    with ``D = diag(1, 1, sign det S)``, the lecture's sign correction. ``I₁`` is
    the best trace, the largest root ``λ`` of Horn's quartic
    ``(λ² - ‖S‖²)² - 8 λ det S - 4 ‖cof S‖²`` (as in ``optimal_rotation``),
    found by Newton's method from above; ``I₂ = (I₁² - ‖S‖²) / 2``. On
    ``‖S‖ = 1`` the denominator ``(σ₁ + σ₂)(σ₁ + σ₃)(σ₂ + σ₃)`` is ``p'(λ) / 8``
    for the quartic ``p``, ``0 ≤ λ - I₁ ≤ 4 p / p'``, and an error ``δ`` in
    ``λ`` moves ``Rᵀ``'s entries by less than ``7 δ / (I₁ I₂ - I₃)``; a matrix
    whose bound ``256 (|p| + 5e-15) / p'²`` (rounding of ``p`` included) is
    below ``1e-12`` is trusted, the others (the denominator below ~0.14: rank
    ≤ 1, strongly stretched cells, or nearly a reflection with two equal small
    singular values) take the SVD. About 30% less time than ``optimal_rotation``'s quaternion
    eigenvector on the ARAP local step's stacks (``benchmarks/bench_arap.py``).
    """
    k = len(S)
    Rt = np.empty((k, 9))
    trusted = np.empty(k, dtype=bool)
    # blocks that stay in the CPU cache through the ~200 elementwise passes
    block = 8192
    for start in range(0, k, block):
        stop = min(start + block, k)
        # one contiguous row per matrix entry
        X = S[start:stop].reshape(-1, 9).T.copy()
        trusted[start:stop] = _polar_rotations_transposed(X, Rt[start:stop].T)
    if not trusted.all():
        U, _, Vt = np.linalg.svd(S[~trusted])
        Vt[np.linalg.det(U @ Vt) < 0, -1, :] *= -1.0
        Rt[~trusted] = (U @ Vt).reshape(-1, 9)
    return Rt.reshape(k, 3, 3)


def _polar_rotations_transposed(X, Rt):
    """``cell_rotations_transposed`` of the ``(9, m)`` rows of entries ``X`` (scaled in place) into the rows of ``Rt``; returns the trust mask."""
    norm2 = np.einsum("im,im->m", X, X)
    if not ((norm2 > 1e-200) & (norm2 < 1e200)).all():
        big = np.abs(X).max(axis=0)
        X /= np.where(big > 0, big, 1.0)
        norm2 = np.einsum("im,im->m", X, X)
    # ‖S‖ = 1 makes the tolerances absolute; zero matrices stay zero (and untrusted)
    X *= 1.0 / np.sqrt(np.where(norm2 > 0, norm2, 1.0))
    s00, s01, s02, s10, s11, s12, s20, s21, s22 = X
    cof = (
        s11 * s22 - s12 * s21, s12 * s20 - s10 * s22, s10 * s21 - s11 * s20,
        s02 * s21 - s01 * s22, s00 * s22 - s02 * s20, s01 * s20 - s00 * s21,
        s01 * s12 - s02 * s11, s02 * s10 - s00 * s12, s00 * s11 - s01 * s10,
    )
    det = s00 * cof[0] + s01 * cof[1] + s02 * cof[2]
    b = sum(c * c for c in cof)
    # an upper bound of λ, exact when det S = 0 (see optimal_rotation)
    lam = np.sqrt(1.0 + 2.0 * np.sqrt(3.0 * b))
    lam = np.sqrt(1.0 + 2.0 * np.sqrt(b + 2.0 * np.abs(det) * lam))
    b4, det8 = 4.0 * b, 8.0 * det
    # three Newton steps reach rounding on the ARAP stacks; the trust test runs from then on. Those
    # not trusted after eight are near a double root (strongly stretched cells), where it crawls: SVD.
    for step in range(9):
        l2a = lam * lam - 1.0
        p = l2a * l2a - b4 - det8 * lam
        dp = 4.0 * lam * l2a - det8
        if step >= 3:
            dp2 = dp * dp
            trusted = 256.0 * (np.abs(p) + 5e-15) < 1e-12 * dp2
            # p' only decreases towards the root: below 1.28 a matrix can never be trusted
            if step == 8 or (trusted | (dp2 < 1.28)).all():
                break
        # from above, Newton never overshoots the largest root: a floored p' only shortens the step
        lam -= p / np.maximum(dp, 0.01)
    i2 = 0.5 * (lam * lam - 1.0)
    g = 1.0 / np.where(trusted, lam * i2 - det, 1.0)
    alpha, beta = (lam * lam - i2) * g, lam * g
    # Rᵀ = M S + β cof S with the symmetric M = α I - g S Sᵀ
    m00 = alpha - g * (s00 * s00 + s01 * s01 + s02 * s02)
    m11 = alpha - g * (s10 * s10 + s11 * s11 + s12 * s12)
    m22 = alpha - g * (s20 * s20 + s21 * s21 + s22 * s22)
    m01 = -g * (s00 * s10 + s01 * s11 + s02 * s12)
    m02 = -g * (s00 * s20 + s01 * s21 + s02 * s22)
    m12 = -g * (s10 * s20 + s11 * s21 + s12 * s22)
    for r, (ma, mb, mc) in enumerate(((m00, m01, m02), (m01, m11, m12), (m02, m12, m22))):
        for c in range(3):
            np.add(ma * X[c] + mb * X[3 + c] + mc * X[6 + c], beta * cof[3 * r + c], out=Rt[3 * r + c])
    return trusted


class SparseCholesky:
    """Sparse Cholesky factor of a symmetric positive definite matrix, for repeated solves.

    CHOLMOD's supernodal factorization through ``cholespy``. Chosen on
    measurement (``benchmarks/bench_arap.py``, 50k-vertex bar, three right-hand
    sides, a busy 2-core machine): its two triangular solves took ~1.6 ms of
    CPU against ~4.3 ms for SuperLU's (``scipy.sparse.linalg.splu`` in
    minimum-degree order) and ~9 ms for ``sksparse_minimal``'s.

    Parameters
    ----------
    A : (m, m) scipy.sparse matrix
        Symmetric positive definite; only its lower triangle is read.
    """

    def __init__(self, A):
        lower = sp.tril(A, format="coo")
        self.shape = A.shape
        self._factor = cholespy.CholeskySolverD(
            A.shape[0], lower.row.astype(np.int32), lower.col.astype(np.int32),
            lower.data.astype(np.float64), cholespy.MatrixType.COO,
        )

    def solve(self, b):
        """``A⁻¹ b`` for ``b`` of shape ``(m,)`` or ``(m, k)``; a new array."""
        b = np.ascontiguousarray(b, dtype=np.float64)
        x = np.empty_like(b)
        self._factor.solve(b, x)
        return x

    def solve_into(self, b, x):
        """Write ``A⁻¹ b`` into ``x``; both C-contiguous float64 of shape ``(m,)`` or ``(m, k)``."""
        self._factor.solve(b, x)


def arap_precompute(V, F, handles):
    """Everything the ARAP iterations reuse, factorization included.

    Parameters
    ----------
    V : (n, d) array_like of float
        Rest positions, ``d`` in {2, 3}.
    F : (f, 3) array_like of int
        Triangles; none may have zero area.
    handles : (h,) array_like of int
        Distinct constrained vertices, at least one in every connected
        component of the mesh.

    Returns
    -------
    data : types.SimpleNamespace
        ``V``, ``F``, ``C`` (``cotangent_weights``), ``L``
        (``cotangent_laplacian``), ``handles``, ``free`` (the other vertices,
        ascending); ``solver``, the ``SparseCholesky`` factor of
        ``-L[free][:, free]`` (symmetric positive definite), or ``None`` when
        every vertex is a handle; ``L_free_handles = L[free][:, handles]``;
        ``covariance_operator``, ``(n d, n)`` sparse with
        ``(covariance_operator @ U).reshape(n, d, d) = arap_covariances(V, U, F, C)``;
        ``rhs_operator``, ``(len(free), d n)`` sparse, so that the global
        step's right-hand side is ``rhs_operator @ R.transpose(0, 2, 1).reshape(n d, d)``;
        ``rest_dirichlet = Σ_t Σ_k C[t, k] ‖e_tk‖²``;
        ``L_handles = L[handles][:, handles]``; ``moving_cells``, the vertices
        with a free vertex in a triangle around them; ``covariance_moving``,
        the rows of ``covariance_operator`` of the moving cells and its columns
        in the order ``[free, handles]``; ``rhs_moving``, the columns of
        ``rhs_operator`` of the moving cells (the others are zero);
        ``covariance_still``, the rows of the other cells and the handles'
        columns (the others are zero); ``handle_fit``, the transposed
        handles' columns of ``covariance_moving``, ``(h, d cells)``.

    Notes
    -----
    With ``P_t[j] = C[t, j-1] e_t,j-1 - C[t, j+1] e_t,j+1`` (indices mod 3),
    triangle ``t`` contributes ``T_t = Σ_j P_t[j] u_{F[t, j]}ᵀ`` to the
    covariance of each of its corners, so ``S = G U`` is linear in ``U``. The
    energy is ``E = 3 Σ C ‖e'‖² + 3 Σ C ‖e‖² - 2 Σ_i tr(R_i S_i(U))`` with
    ``Σ C ‖e'‖² = -tr(Uᵀ L U)``, and ``Σ_i tr(R_i S_i(U)) = tr(Uᵀ Gᵀ R̃)`` for
    the stacked transposed rotations ``R̃``; so its gradient vanishes at the
    free vertices where ``-L U = Gᵀ R̃ / 3``: each edge sees the mean rotation
    of its triangle.
    """
    V = as_vertices(V)
    F = as_faces(F, len(V))
    check_no_degenerate_triangles(V, F)
    n, d = V.shape
    handles = as_handles(handles, n)
    vertex = component_without(F, n, handles)
    if vertex is not None:
        raise ValueError(
            f"handles must include a vertex of every connected component of the mesh: "
            f"the component of vertex {vertex} has none, so its position is undetermined"
        )
    return _precomputed(V, F, handles, cotangent_weights(V, F), cotangent_laplacian(V, F))


def _precomputed(V, F, handles, C, L, factor=None):
    """``arap_precompute``'s object for checked ``V``, ``F``, ``handles``, from corner weights ``C`` and Laplacian ``L``.

    ``factor(A)`` factors ``-L_ff`` (default :class:`SparseCholesky`; the grader passes an LU
    when it reruns a student's caller on the student's own, possibly indefinite, Laplacian).
    """
    n, d = V.shape
    L = sp.csr_matrix(L)
    is_free = np.ones(n, dtype=bool)
    is_free[handles] = False
    free = np.flatnonzero(is_free)
    L_free = L[free]
    solver = (factor or SparseCholesky)(-L_free[:, free]) if free.size else None
    E = V[np.roll(F, -1, axis=1)] - V[np.roll(F, -2, axis=1)]
    weighted = C[:, :, None] * E
    P = np.roll(weighted, 1, axis=1) - np.roll(weighted, -1, axis=1)
    # covariance_operator[d F[t, i] + a, F[t, j]] += P[t, j, a] for the corners i, j of t
    shape = (len(F), 3, 3, d)
    rows = np.broadcast_to(d * F[:, :, None, None] + np.arange(d), shape)
    cols = np.broadcast_to(F[:, None, :, None], shape)
    vals = np.broadcast_to(P[:, None, :, :], shape)
    G = sp.csr_matrix((vals.ravel(), (rows.ravel(), cols.ravel())), shape=(d * n, n))
    return types.SimpleNamespace(
        V=V, F=F, C=C, L=L, handles=handles, free=free, solver=solver,
        L_free_handles=L_free[:, handles].tocsr(),
        # column-major operators multiply (n, d) blocks ~1.5x faster here than row-major ones
        covariance_operator=G.tocsc(),
        rhs_operator=(G[:, free].T / 3.0).tocsc(),
        rest_dirichlet=float(np.sum(C * np.einsum("tka,tka->tk", E, E))),
        L_handles=L[handles][:, handles].tocsr(),
        **_moving_cells(G, F, free, handles, d),
    )


def _moving_cells(G, F, free, handles, d):
    """What ``arap_solve`` iterates on: the cells with a free vertex in their one-ring, columns [free, handles].

    A cell whose triangles hold only handles (inside a handle region) keeps its
    covariance, rotation and energy term through a solve, and its rotation
    enters no free vertex's right-hand side (its rows of ``G`` vanish on the
    free columns): it is fitted once per solve, not once per iteration.
    """
    n = G.shape[1]
    moving = np.zeros(n, dtype=bool)
    is_free = np.zeros(n, dtype=bool)
    is_free[free] = True
    moving[F[is_free[F].any(axis=1)].ravel()] = True
    def rows(cells):
        return (d * cells[:, None] + np.arange(d)).ravel()

    cells, still = np.flatnonzero(moving), np.flatnonzero(~moving)
    G_cells = G[rows(cells)]
    return {
        "moving_cells": cells,
        # rows [free, handles]: the solve writes the free block of the iterate in place
        "covariance_moving": G_cells[:, np.concatenate([free, handles])].tocsc(),
        "rhs_moving": (G_cells[:, free].T / 3.0).tocsc(),
        "covariance_still": G[rows(still)][:, handles].tocsr(),
        # Σ_moving tr(R_i S_i) = ⟨G_cellsᵀ R̃, U⟩: its handle rows (few: the cells at a handle region's rim)
        "handle_fit": G_cells[:, handles].T.tocsr(),
    }


def arap_global_step(data, R, handle_positions):
    """The ARAP global step: the best positions for given rotations.

    Parameters
    ----------
    data : types.SimpleNamespace
        From ``arap_precompute(V, F, handles)``.
    R : (n, d, d) array_like of float
        One rotation per vertex.
    handle_positions : (h, d) array_like of float
        Targets of the handles, in the order of ``handles``.

    Returns
    -------
    U : (n, d) numpy.ndarray
        Minimizes ``arap_energy(V, U, F, C, R)`` subject to
        ``U[handles] = handle_positions`` (exactly): the free rows solve
        ``-L_ff U_f = b_f + L_fh U_h``.
    """
    if not isinstance(data, types.SimpleNamespace) or not hasattr(data, "rhs_operator"):
        raise ValueError(f"data must be the result of arap_precompute(V, F, handles), got {type(data).__name__}")
    n, d = data.V.shape
    R = as_float_array(R, "R", ndim=3)
    if R.shape != (n, d, d):
        raise ValueError(f"R must have shape ({n}, {d}, {d}), one rotation per vertex, got {R.shape}")
    handle_positions = as_handle_positions(handle_positions, len(data.handles), d)
    U = np.empty((n, d))
    U[data.handles] = handle_positions
    if data.solver is not None:
        rhs = data.rhs_operator @ R.transpose(0, 2, 1).reshape(n * d, d)
        rhs += data.L_free_handles @ handle_positions
        U[data.free] = data.solver.solve(rhs)
    return U


def arap_solve(data, handle_positions, U0=None, iterations=10):
    """ARAP deformation by alternating local and global steps.

    Parameters
    ----------
    data : types.SimpleNamespace
        From ``arap_precompute(V, F, handles)``.
    handle_positions : (h, d) array_like of float
        Targets of the handles, in the order of ``handles``.
    U0 : (n, d) array_like of float, optional
        Start; default the rest positions ``V``. Its handle rows are replaced
        by ``handle_positions`` before the first local step.
    iterations : int
        Number of local-global iterations, ``>= 0``.

    Returns
    -------
    U : (n, d) numpy.ndarray
        Positions after the last iteration; ``U[handles] = handle_positions``.
    energies : (iterations,) numpy.ndarray
        ``energies[k] = arap_energy(V, U_k, F, C, R_k)`` for the positions
        ``U_k`` after iteration ``k``'s global step and the rotations ``R_k``
        that step used; non-increasing (up to the rounding below).

    Notes
    -----
    The local step uses ``data.covariance_operator`` instead of
    ``arap_covariances`` (same matrices, one sparse product) and, in 3D,
    ``cell_rotations_transposed`` instead of ``optimal_rotation`` (the same
    rotations, to 1e-12 of the SVD's, transposed as the right-hand side needs
    them). The energy needs no covariances of the new positions: with the
    stacked transposed rotations ``R̃`` and ``S = G U`` (``G`` the covariance
    operator), ``E = 3 (Σ C ‖e'‖² + Σ C ‖e‖²) - 2 ⟨Gᵀ R̃, U⟩``,
    ``Σ C ‖e'‖² = -tr(Uᵀ L U)``, and the global step's own system
    ``-L_ff U_f = b`` with ``b = G_fᵀ R̃ / 3 + L_fh U_h`` turns both into
    ``-tr(Uᵀ L U) = tr(U_fᵀ (b - 2 L_fh U_h)) - tr(U_hᵀ L_hh U_h)`` and
    ``⟨Gᵀ R̃, U⟩ = 3 tr(U_fᵀ (b - L_fh U_h)) + ⟨G_hᵀ R̃, U_h⟩``, so
    ``E = 3 Σ C ‖e‖² - 3 tr(U_hᵀ L_hh U_h) - 3 tr(U_fᵀ b) - 2 ⟨G_hᵀ R̃, U_h⟩``
    (the cells inside handle regions keep their term through the solve).
    The energy agrees with ``arap_energy`` up to rounding relative to the
    Dirichlet energies (``~1e-15`` of ``3 Σ C (‖e'‖² + ‖e‖²)``).
    """
    if not isinstance(data, types.SimpleNamespace) or not hasattr(data, "rhs_operator"):
        raise ValueError(f"data must be the result of arap_precompute(V, F, handles), got {type(data).__name__}")
    n, d = data.V.shape
    handle_positions = as_handle_positions(handle_positions, len(data.handles), d)
    if isinstance(iterations, (bool, np.bool_)) or not isinstance(iterations, (int, np.integer)) or iterations < 0:
        raise ValueError(f"iterations must be a non-negative integer, got {iterations!r}")
    if U0 is None:
        U = data.V.copy()
    else:
        U = as_float_array(U0, "U0", ndim=2)
        if U.shape != (n, d):
            raise ValueError(f"U0 must have the shape of V, {(n, d)}, got {U.shape}")
    U[data.handles] = handle_positions
    energies = np.empty(int(iterations))
    if iterations == 0:
        return U, energies
    # U_p = U[[free, handles]]: the solve writes U_p's free block, a contiguous view, in place
    m, cells = data.free.size, data.moving_cells.size
    U_p = np.concatenate([U[data.free], handle_positions])
    U_f = U_p[:m]
    handle_rhs = data.L_free_handles @ handle_positions
    handle_dirichlet = np.einsum("ij,ij->", handle_positions, data.L_handles @ handle_positions)
    # the cells inside handle regions: one fit per solve (their covariances do not change)
    S_still = (data.covariance_still @ handle_positions).reshape(-1, d, d)
    still_fit = np.einsum("kij,kji->", optimal_rotation(S_still), S_still) if len(S_still) else 0.0
    # the energy's terms that stay through the solve (see the Notes)
    constant = 3.0 * (data.rest_dirichlet - handle_dirichlet) - 2.0 * still_fit
    for k in range(int(iterations)):
        if cells:
            S = (data.covariance_moving @ U_p).reshape(cells, d, d)
            # Rᵀ stacked: the rows (i, b) of the right-hand side's operand
            if d == 3:
                Rt = cell_rotations_transposed(S).reshape(cells * d, d)
            else:
                Rt = optimal_rotation(S).transpose(0, 2, 1).reshape(cells * d, d)
            rhs = data.rhs_moving @ Rt
            rim_fit = np.einsum("ij,ij->", handle_positions, data.handle_fit @ Rt)
        else:
            rhs, rim_fit = np.zeros((m, d)), 0.0
        # b = b_R + L_fh U_h, in place
        rhs += handle_rhs
        if m:
            data.solver.solve_into(rhs, U_f)
        # (einsum, not BLAS's dot: OpenBLAS's threads would spin on the other core)
        energies[k] = constant - 3.0 * np.einsum("ij,ij->", U_f, rhs) - 2.0 * rim_fit
    U[data.free] = U_f
    return U, energies


def laplacian_editing(V, F, handles, handle_positions):
    """Naive Laplacian editing: the ARAP global step with every rotation the identity.

    Parameters
    ----------
    V : (n, d) array_like of float
        Rest positions, ``d`` in {2, 3}.
    F : (f, 3) array_like of int
        Triangles; none may have zero area.
    handles : (h,) array_like of int
        Distinct constrained vertices.
    handle_positions : (h, d) array_like of float
        Targets of the handles.

    Returns
    -------
    U : (n, d) numpy.ndarray
        ``arap_global_step(arap_precompute(V, F, handles), I, handle_positions)``:
        keeps the rest edge vectors as well as possible (in the cotangent
        sense), so rotations shear and shrink the shape.
    """
    data = arap_precompute(V, F, handles)
    n, d = data.V.shape
    return arap_global_step(data, np.broadcast_to(np.eye(d), (n, d, d)), handle_positions)
