"""Laplacian smoothing: the uniform and cotangent Laplacians, explicit and implicit smoothing steps.

Smoothing integrates the diffusion (heat) equation ``M dU/dt = L U`` on the
vertex positions ``U``, ``L`` a discrete Laplacian (negative semidefinite, zero
row sums) and ``M = diag(m)`` a lumped mass matrix:

- explicit (forward Euler) step: ``U' = U + h M⁻¹ L U``, stable only for small ``h``;
- implicit (backward Euler) step: ``(M - h L) U' = M U``, stable for every ``h >= 0``.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from starter.validation import as_faces, as_float_array, as_vertices, check_no_degenerate_triangles


def _symmetric_from_pairs(rows: np.ndarray, cols: np.ndarray, weights: np.ndarray, n: int) -> sp.csr_matrix:
    """``(n, n)`` matrix with ``weights`` summed on ``(rows, cols)`` and ``(cols, rows)``, minus its row sums on the diagonal."""
    W = sp.coo_matrix((np.r_[weights, weights], (np.r_[rows, cols], np.r_[cols, rows])), shape=(n, n)).tocsr()
    W.sum_duplicates()
    return (W - sp.diags(np.asarray(W.sum(axis=1)).ravel())).tocsr()


def uniform_laplacian(V, F):
    """The graph (uniform, "umbrella") Laplacian of a triangle mesh.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions, ``d`` in {2, 3}; only ``n`` is used.
    F : (f, 3) array_like of int
        Triangles.

    Returns
    -------
    L : (n, n) scipy.sparse.csr_matrix
        ``L[i, j] = 1`` for every edge ``(i, j)`` of ``F`` (once, however many
        triangles share it), ``L[i, i] = -deg(i)``, zero elsewhere: symmetric,
        negative semidefinite, zero row sums. A vertex in no triangle has a zero row.

    Raises
    ------
    ValueError
        If ``V`` or ``F`` is malformed or ``F`` indexes outside ``V``.
    """
    n = len(as_vertices(V))
    F = as_faces(F, n)
    # each undirected edge once, as the pair (smaller, larger) packed into one integer
    pairs = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    keys = np.unique(np.min(pairs, axis=1) * n + np.max(pairs, axis=1))
    return _symmetric_from_pairs(keys // n, keys % n, np.ones(len(keys)), n)


def cotangent_matrix(V, F):
    """The cotangent Laplacian (stiffness matrix of linear finite elements), equal to ``igl.cotmatrix``.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions, ``d`` in {2, 3}.
    F : (f, 3) array_like of int
        Triangles, none of zero area; 2D triangles may have either orientation.

    Returns
    -------
    L : (n, n) scipy.sparse.csr_matrix
        ``L[i, j] = ½ (cot α_ij + cot β_ij)``, the angles opposite edge
        ``(i, j)`` in its one or two triangles; ``L[i, i] = -Σ_{j≠i} L[i, j]``.
        Symmetric, zero row sums, negative semidefinite on Delaunay meshes.

    Raises
    ------
    ValueError
        If ``V`` or ``F`` is malformed, ``F`` indexes outside ``V``, or a triangle has zero area.
    """
    V = as_vertices(V)
    F = as_faces(F, len(V))
    check_no_degenerate_triangles(V, F)
    # squared length of the edge opposite each corner k: between corners k+1 and k+2
    opposite = V[F[:, [1, 2, 0]]] - V[F[:, [2, 0, 1]]]
    sq = np.einsum("tkd,tkd->tk", opposite, opposite)
    a, b = opposite[:, 0], opposite[:, 1]
    double_area = np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]) if V.shape[1] == 2 else np.linalg.norm(np.cross(a, b), axis=1)
    # law of cosines: cot γ = (p² + q² − r²) / (4 area), r opposite γ; half of it is the edge's weight
    half_cot = (sq.sum(axis=1, keepdims=True) - 2.0 * sq) / (4.0 * double_area[:, None])
    rows = F[:, [1, 2, 0]].ravel()
    cols = F[:, [2, 0, 1]].ravel()
    return _symmetric_from_pairs(rows, cols, half_cot.ravel(), len(V))


def _step_inputs(U, L, m, h):
    """Check and convert a smoothing step's inputs: ``(U, L as CSR, m, h)``."""
    U = as_float_array(U, "U", ndim=2)
    n = len(U)
    if n == 0:
        raise ValueError("U has no rows: there is nothing to smooth")
    if not (sp.issparse(L) or isinstance(L, np.ndarray)):
        L = np.asarray(L)
    if L.ndim != 2 or L.shape != (n, n):
        raise ValueError(f"L must be an (n, n) matrix with n = {n} (the rows of U), got shape {L.shape}")
    L = sp.csr_matrix(L, dtype=np.float64)
    if not np.all(np.isfinite(L.data)):
        raise ValueError("L contains NaN or inf")
    m = as_float_array(m, "m", ndim=1)
    if m.shape != (n,):
        raise ValueError(f"m must hold one mass per vertex ({n}), got shape {m.shape}")
    if np.any(m <= 0):
        i = int(np.flatnonzero(m <= 0)[0])
        raise ValueError(f"the masses must be positive, got m[{i}] = {m[i]}")
    h = as_float_array(h, "h", ndim=0)
    if h < 0:
        raise ValueError(f"the step size h must be non-negative, got {float(h)}")
    return U, L, m, float(h)


def explicit_smoothing_step(U, L, m, h):
    """One forward-Euler step of ``M dU/dt = L U``.

    Parameters
    ----------
    U : (n, d) array_like of float
        Current positions.
    L : (n, n) scipy.sparse matrix or array_like
        A Laplacian (symmetric, zero row sums; not checked).
    m : (n,) array_like of float
        Positive vertex masses, the diagonal of ``M``.
    h : float
        Step size, ``h >= 0``.

    Returns
    -------
    U_next : (n, d) numpy.ndarray
        ``U + h M⁻¹ L U``.

    Raises
    ------
    ValueError
        If a shape disagrees, a mass is not positive, or ``h`` is negative or not finite.
    """
    U, L, m, h = _step_inputs(U, L, m, h)
    return U + (h / m)[:, None] * (L @ U)


def implicit_smoothing_step(U, L, m, h):
    """One backward-Euler step of ``M dU/dt = L U``: the solution of ``(M - h L) U' = M U``.

    Parameters
    ----------
    U : (n, d) array_like of float
        Current positions.
    L : (n, n) scipy.sparse matrix or array_like
        A Laplacian: symmetric and negative semidefinite, so that ``M - h L`` is
        positive definite (not checked).
    m : (n,) array_like of float
        Positive vertex masses, the diagonal of ``M``.
    h : float
        Step size, ``h >= 0``.

    Returns
    -------
    U_next : (n, d) numpy.ndarray

    Raises
    ------
    ValueError
        If a shape disagrees, a mass is not positive, or ``h`` is negative or not finite.
    """
    U, L, m, h = _step_inputs(U, L, m, h)
    A = (sp.diags(m) - h * L).tocsc()
    return np.asarray(spla.splu(A).solve(m[:, None] * U)).reshape(U.shape)
