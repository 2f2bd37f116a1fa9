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
        columns (the others are zero).

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
    ``arap_covariances`` (same matrices, one sparse product). The energy uses
    ``E = 3 (Σ C ‖e'‖² + Σ C ‖e‖²) - 2 Σ_i tr(R_i S_i(U))`` with
    ``Σ C ‖e'‖² = -tr(Uᵀ L U)``, and ``S(U_k)`` is the next local step's input.
    ``-tr(Uᵀ L U)`` comes from the global step's own system
    ``-L_ff U_f = b_R + L_fh U_h``: it is ``tr(U_fᵀ (b_R - L_fh U_h)) - tr(U_hᵀ L_hh U_h)``.
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
    handle_rhs = data.L_free_handles @ handle_positions
    handle_dirichlet = np.einsum("ij,ij->", handle_positions, data.L_handles @ handle_positions)
    # the cells inside handle regions: one fit per solve (their covariances do not change)
    S_still = (data.covariance_still @ handle_positions).reshape(-1, d, d)
    still_fit = np.einsum("kij,kji->", optimal_rotation(S_still), S_still) if len(S_still) else 0.0
    S = (data.covariance_moving @ U_p).reshape(cells, d, d)
    for k in range(int(iterations)):
        if cells:
            R = optimal_rotation(S)
            Rt = R.transpose(0, 2, 1).reshape(cells * d, d)
            rotation_rhs = data.rhs_moving @ Rt
        else:
            Rt, rotation_rhs = np.empty((0, d)), np.zeros((m, d))
        if m:
            data.solver.solve_into(rotation_rhs + handle_rhs, U_p[:m])
        S = (data.covariance_moving @ U_p).reshape(cells, d, d)
        # -Uᵀ L U from the solve's -L_ff U_f = rotation_rhs + L_fh U_h (einsum, not
        # BLAS's dot: OpenBLAS's threads would spin on the other core)
        dirichlet = np.einsum("ij,ij->", U_p[:m], rotation_rhs - handle_rhs) - handle_dirichlet
        # Σ_i tr(R_i S_i) = Σ_i Σ_ab (R_iᵀ)_ba (S_i)_ba
        fit = np.einsum("i,i->", Rt.ravel(), S.ravel()) + still_fit
        energies[k] = 3.0 * (dirichlet + data.rest_dirichlet) - 2.0 * fit
    U[data.free] = U_p[:m]
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
