"""k-harmonic displacement deformation (stage 02b): the linear baseline ARAP is contrasted with.

Handle vertices get prescribed displacements ``D_h``; the free vertices'
displacements minimize the discrete k-harmonic energy ``½ tr(Dᵀ Q_k D)`` with
``Q_k = (-L) (M⁻¹ (-L))^(k-1)`` (``L`` the cotangent matrix, negative
semidefinite as ``igl.cotmatrix``; ``M`` the lumped mass matrix): ``k = 1``
harmonic, ``k = 2`` biharmonic (libigl's tutorials 401 and 402, ``igl.harmonic``).
The minimizer solves ``Q_ff D_f = -Q_fh D_h``; ``Q_ff`` is factored once.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

__all__ = ["k_harmonic_operator", "k_harmonic_precompute", "k_harmonic_solve"]


def _square_sparse(A, name: str) -> sp.csr_matrix:
    A = sp.csr_matrix(A, dtype=float) if sp.issparse(A) else sp.csr_matrix(np.asarray(A, dtype=float))
    if A.ndim != 2 or A.shape[0] != A.shape[1]:
        raise ValueError(f"{name} must be a square (n, n) matrix, got shape {A.shape}")
    if not np.all(np.isfinite(A.data)):
        raise ValueError(f"{name} holds a value that is not finite")
    return A


def _masses(M, n: int) -> np.ndarray:
    M = _square_sparse(M, "M")
    if M.shape[0] != n:
        raise ValueError(f"M must be ({n}, {n}) like L, got {M.shape}")
    off = M - sp.diags(M.diagonal())
    if off.count_nonzero():
        raise ValueError("M must be diagonal (a lumped mass matrix)")
    m = M.diagonal()
    if np.any(m <= 0):
        raise ValueError(f"M's diagonal must be positive, got {m.min():g} at vertex {int(np.argmin(m))}")
    return m


def k_harmonic_operator(L, M, k):
    """The k-harmonic energy's matrix ``Q_k = (-L) (M⁻¹ (-L))^(k-1)``.

    Parameters
    ----------
    L : (n, n) sparse or dense
        Cotangent matrix (symmetric, negative semidefinite, zero row sums).
    M : (n, n) sparse or dense
        Diagonal lumped mass matrix, positive diagonal.
    k : int
        At least 1.

    Returns
    -------
    Q : (n, n) scipy.sparse.csr_matrix
        Symmetric positive semidefinite.

    Raises
    ------
    ValueError
        If ``k`` is not an integer of at least 1, or ``L``/``M`` are not square of one size, ``M`` not positive diagonal.
    """
    if isinstance(k, bool) or not isinstance(k, numbers.Integral) or k < 1:
        raise ValueError(f"k must be an integer of at least 1, got {k!r}")
    minus_L = -_square_sparse(L, "L")
    m = _masses(M, minus_L.shape[0])
    Q = minus_L
    step = sp.diags(1.0 / m) @ minus_L
    for _ in range(int(k) - 1):
        Q = Q @ step
    Q = Q.tocsr()
    return ((Q + Q.T) * 0.5).tocsr()  # exactly symmetric: the products round differently on each side


@dataclass
class KHarmonicData:
    """What ``k_harmonic_solve`` needs: the partition of the vertices and ``Q_ff`` factored."""

    n: int
    handles: np.ndarray
    free: np.ndarray
    Q_free_handles: sp.csr_matrix
    factor: object  # splu of Q_ff, or None when every vertex is a handle


def k_harmonic_precompute(Q, handles):
    """Factor ``Q_ff`` for the free vertices of ``handles``.

    Parameters
    ----------
    Q : (n, n) sparse or dense
        Symmetric positive semidefinite (``k_harmonic_operator``); ``Q_ff`` must be nonsingular
        (every connected component holds a handle).
    handles : (h,) array_like of int
        Distinct vertices in ``0 … n-1``, at least one.

    Returns
    -------
    KHarmonicData

    Raises
    ------
    ValueError
        If ``handles`` is empty, repeats a vertex or is out of range, or ``Q_ff`` is singular.
    """
    Q = _square_sparse(Q, "Q")
    n = Q.shape[0]
    handles = np.asarray(handles)
    if handles.ndim != 1 or handles.size == 0 or not np.issubdtype(handles.dtype, np.integer):
        raise ValueError(f"handles must be a non-empty 1D array of vertex indices, got {handles.dtype} {handles.shape}")
    if handles.min() < 0 or handles.max() >= n:
        raise ValueError(f"handles must index vertices 0..{n - 1}, got {handles.min()}..{handles.max()}")
    if np.unique(handles).size != handles.size:
        raise ValueError("handles repeats a vertex")
    handles = handles.astype(np.int64)
    is_free = np.ones(n, dtype=bool)
    is_free[handles] = False
    free = np.flatnonzero(is_free)
    Q_free = Q[free]
    factor = None
    if free.size:
        try:
            factor = spla.splu(Q_free[:, free].tocsc())
        except RuntimeError as exc:  # "Factor is exactly singular"
            raise ValueError(f"Q restricted to the free vertices is singular ({exc}): a component without a handle?") from None
    return KHarmonicData(n, handles, free, Q_free[:, handles].tocsr(), factor)


def k_harmonic_solve(data, handle_displacements):
    """Displacements minimizing ``½ tr(Dᵀ Q D)`` with ``D[handles] = handle_displacements`` exactly.

    Parameters
    ----------
    data : KHarmonicData
        From ``k_harmonic_precompute``.
    handle_displacements : (h, d) array_like of float
        In the order of ``handles``.

    Returns
    -------
    D : (n, d) ndarray of float

    Raises
    ------
    ValueError
        If ``handle_displacements`` does not have one row per handle.
    """
    B = np.asarray(handle_displacements, dtype=float)
    if B.ndim != 2 or len(B) != len(data.handles):
        raise ValueError(f"handle_displacements must be ({len(data.handles)}, d), one row per handle, got {B.shape}")
    D = np.zeros((data.n, B.shape[1]))
    D[data.handles] = B
    if data.factor is not None:
        D[data.free] = data.factor.solve(-(data.Q_free_handles @ B))
    return D
