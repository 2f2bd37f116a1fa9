"""Stage 07, tetrahedra: linear finite elements on a tetrahedral mesh.

With the piecewise-linear hat functions ``φ_i`` of a tetrahedral mesh, the
stiffness matrix ``∫ ∇φ_i · ∇φ_j`` is minus the cotangent Laplacian (its
off-diagonal entries are ``l_kl cot θ_kl / 6``, the opposite edge's length
times the cotangent of its dihedral angle), and the lumped mass matrix gives
each vertex a quarter of the volume of every tetrahedron around it: libigl's
``igl.cotmatrix`` and ``igl.massmatrix`` (barycentric, its default on tets).
"""

import numpy as np
import scipy.sparse as sp

from starter.validation import as_vertices

# The six edges of a tetrahedron in libigl's order (``igl.cotmatrix_entries``).
TET_EDGES = np.array([[1, 2], [2, 0], [0, 1], [3, 0], [3, 1], [3, 2]])


def as_tets(T, n_vertices, name="T"):
    """Check ``(f, 4)`` tetrahedra indexing ``n_vertices`` vertices.

    Parameters
    ----------
    T : array_like of int
        ``(f, 4)``; any integer dtype.
    n_vertices : int

    Returns
    -------
    numpy.ndarray
        ``(f, 4)`` int64 copy.
    """
    if sp.issparse(T):
        raise ValueError(f"{name} must be a dense integer array, got a sparse matrix")
    a = np.asarray(T)
    if a.dtype == bool or not np.issubdtype(a.dtype, np.integer):
        raise ValueError(f"{name} must be an integer array of vertex indices, got dtype {a.dtype}")
    if a.ndim != 2 or a.shape[1] != 4 or a.shape[0] == 0:
        raise ValueError(f"{name} must have shape (f, 4) with f >= 1 (one tetrahedron per row), got shape {a.shape}")
    a = np.array(a, dtype=np.int64, copy=True)
    out = (a < 0) | (a >= n_vertices)
    if out.any():
        t, k = np.argwhere(out)[0]
        raise ValueError(
            f"{name} has a vertex index out of range: {name}[{t}, {k}] = {a[t, k]}, "
            f"but there are {n_vertices} vertices"
        )
    repeated = (np.sort(a, axis=1)[:, 1:] == np.sort(a, axis=1)[:, :-1]).any(axis=1)
    if repeated.any():
        t = int(np.flatnonzero(repeated)[0])
        raise ValueError(f"{name} has a tetrahedron with a repeated vertex: {name}[{t}] = {a[t].tolist()}")
    return a


def as_tet_mesh(V, T, rel_tol=1e-12, name="T"):
    """Check a tetrahedral mesh: 3D positions, ``(f, 4)`` indices, no flat tetrahedron.

    Returns
    -------
    V : (n, 3) numpy.ndarray of float64
    T : (f, 4) numpy.ndarray of int64
    """
    V = as_vertices(V)
    if V.shape[1] != 3:
        raise ValueError(f"V must have shape (n, 3) for a tetrahedral mesh, got {V.shape}")
    T = as_tets(T, len(V), name)
    volume = np.abs(tet_volumes_unchecked(V, T))
    longest = max(float(np.ptp(V[T.ravel()], axis=0).max()), np.finfo(float).tiny)
    flat = volume <= rel_tol * longest**3
    if flat.any():
        t = int(np.flatnonzero(flat)[0])
        raise ValueError(
            f"{name} has a flat tetrahedron (zero volume, so its gradients are undefined): "
            f"{name}[{t}] = {T[t].tolist()}"
        )
    return V, T


def tet_volumes_unchecked(V, T):
    """Signed volumes ``det[v1 - v0, v2 - v0, v3 - v0] / 6`` of checked arrays."""
    a, b, c = (V[T[:, k]] - V[T[:, 0]] for k in (1, 2, 3))
    return np.einsum("ta,ta->t", a, np.cross(b, c)) / 6.0


def tet_volumes(V, T):
    """Signed volumes of tetrahedra.

    Parameters
    ----------
    V : (n, 3) array_like of float
    T : (f, 4) array_like of int

    Returns
    -------
    vol : (f,) numpy.ndarray
        ``det[v1 - v0, v2 - v0, v3 - v0] / 6``: positive when the
        tetrahedron is positively oriented (``v1, v2, v3`` turn
        counter-clockwise seen from outside, across from ``v0``); ``igl.volume``.
    """
    V = as_vertices(V)
    if V.shape[1] != 3:
        raise ValueError(f"V must have shape (n, 3) for a tetrahedral mesh, got {V.shape}")
    return tet_volumes_unchecked(V, as_tets(T, len(V)))


def barycentric_gradients(V, T):
    """Gradients of the four hat functions in every tetrahedron.

    Parameters
    ----------
    V : (n, 3) array_like of float
    T : (f, 4) array_like of int
        No tetrahedron may be flat.

    Returns
    -------
    G : (f, 4, 3) numpy.ndarray
        ``G[t, k] = ∇φ_{T[t, k]}`` on tetrahedron ``t`` (constant there); the
        four sum to zero. Row ``k ≥ 1`` is row ``k - 1`` of
        ``[v1 - v0, v2 - v0, v3 - v0]⁻¹``.
    """
    V, T = as_tet_mesh(V, T)
    D = np.stack([V[T[:, k]] - V[T[:, 0]] for k in (1, 2, 3)], axis=2)
    B = np.linalg.inv(D)
    return np.concatenate([-B.sum(axis=1, keepdims=True), B], axis=1)


def tet_cotangent_weights(V, T):
    """Cotangent weights of the six edges of every tetrahedron.

    Parameters
    ----------
    V : (n, 3) array_like of float
    T : (f, 4) array_like of int
        No tetrahedron may be flat.

    Returns
    -------
    C : (f, 6) numpy.ndarray
        ``C[t, e] = -|vol_t| ∇φ_i · ∇φ_j`` for the edge ``(i, j) =
        T[t, TET_EDGES[e]]``, which equals ``l_kl cot θ_kl / 6`` (the opposite
        edge's length and the cotangent of its dihedral angle); negative for
        an obtuse dihedral angle. Equals ``igl.cotmatrix_entries``.
    """
    V, T = as_tet_mesh(V, T)
    G = barycentric_gradients(V, T)
    volume = np.abs(tet_volumes_unchecked(V, T))
    return -volume[:, None] * np.einsum("tea,tea->te", G[:, TET_EDGES[:, 0]], G[:, TET_EDGES[:, 1]])


def tet_cotangent_laplacian(V, T):
    """Cotangent Laplacian of a tetrahedral mesh (equals ``igl.cotmatrix``).

    Parameters
    ----------
    V : (n, 3) array_like of float
    T : (f, 4) array_like of int
        No tetrahedron may be flat.

    Returns
    -------
    L : (n, n) scipy.sparse.csr_matrix
        Symmetric, ``L[i, j]`` the sum of ``tet_cotangent_weights`` over the
        tetrahedra's edges ``(i, j)``, rows summing to zero; ``-L`` is the
        stiffness matrix ``∫ ∇φ_i · ∇φ_j``, so ``-uᵀ L u = ∫ ‖∇u‖²``.
    """
    V, T = as_tet_mesh(V, T)
    C = tet_cotangent_weights(V, T)
    n = len(V)
    i, j = T[:, TET_EDGES[:, 0]].ravel(), T[:, TET_EDGES[:, 1]].ravel()
    W = sp.csr_matrix((np.concatenate([C.ravel(), C.ravel()]), (np.concatenate([i, j]), np.concatenate([j, i]))),
                      shape=(n, n))
    return (W - sp.diags(np.asarray(W.sum(axis=1)).ravel())).tocsr()


def tet_mass_matrix(V, T):
    """Lumped (barycentric) mass matrix of a tetrahedral mesh.

    Parameters
    ----------
    V : (n, 3) array_like of float
    T : (f, 4) array_like of int
        No tetrahedron may be flat.

    Returns
    -------
    M : (n, n) scipy.sparse.csr_matrix
        Diagonal, ``M[i, i]`` a quarter of the volume of every tetrahedron
        around vertex ``i``; its entries sum to the mesh's volume. Equals
        ``igl.massmatrix`` (barycentric, libigl's default on tetrahedra).
    """
    V, T = as_tet_mesh(V, T)
    quarter = np.abs(tet_volumes_unchecked(V, T)) / 4.0
    mass = np.bincount(T.ravel(), weights=np.repeat(quarter, 4), minlength=len(V))
    return sp.diags(mass).tocsr()
