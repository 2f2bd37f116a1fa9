"""Input checks shared by the reference solution, the notebooks and students.

Every checker takes the value and the argument's name, returns a clean copy
(float64 or int64, C-contiguous, never a view of the caller's array) and raises
``ValueError`` naming the argument and the problem otherwise. Students may call
them from their own solutions to get the same error messages as the reference.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = [
    "as_float_array",
    "as_points",
    "as_vertices",
    "as_faces",
    "as_weights",
    "as_handles",
    "as_handle_positions",
    "as_square_matrices",
    "as_corner_weights",
    "check_no_degenerate_triangles",
    "as_labels",
    "as_handle_indices",
]


def _describe(a) -> str:
    a = np.asarray(a)
    return f"shape {a.shape} and dtype {a.dtype}"


def as_float_array(x, name: str, ndim: int | None = None) -> np.ndarray:
    """Convert ``x`` to a finite float64 array, optionally of a given ``ndim``.

    Parameters
    ----------
    x : array_like
    name : str
        The argument's name, used in error messages.
    ndim : int, optional
        Required number of dimensions.

    Returns
    -------
    numpy.ndarray
        float64 copy of ``x``.
    """
    if sp.issparse(x):
        raise ValueError(f"{name} must be a dense array, got a sparse matrix")
    try:
        a = np.array(x, dtype=np.float64, order="C")  # a C-ordered copy; keeps 0-d arrays 0-d
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be a numeric array: {exc}") from None
    if ndim is not None and a.ndim != ndim:
        raise ValueError(f"{name} must be a {ndim}-D array, got {_describe(a)}")
    if not np.all(np.isfinite(a)):
        bad = np.argwhere(~np.isfinite(a))[0]
        raise ValueError(f"{name} contains NaN or inf (first at index {tuple(int(i) for i in bad)})")
    return a


def as_points(P, name: str = "P", dims=(2, 3), min_count: int = 1) -> np.ndarray:
    """Check a ``(k, d)`` point set with ``d`` in ``dims`` and ``k >= min_count``.

    Returns
    -------
    numpy.ndarray
        ``(k, d)`` float64.
    """
    a = as_float_array(P, name, ndim=2)
    if a.shape[1] not in dims:
        raise ValueError(f"{name} must have {' or '.join(map(str, dims))} columns (one point per row), got {_describe(a)}")
    if a.shape[0] < min_count:
        raise ValueError(f"{name} must have at least {min_count} row(s), got {a.shape[0]}")
    return a


def as_vertices(V, name: str = "V") -> np.ndarray:
    """Check ``(n, d)`` vertex positions, ``d`` in {2, 3}, ``n >= 1``."""
    return as_points(V, name, dims=(2, 3), min_count=1)


def as_faces(F, n_vertices: int, name: str = "F") -> np.ndarray:
    """Check ``(f, 3)`` triangle indices into ``n_vertices`` vertices.

    Parameters
    ----------
    F : array_like of int
        ``(f, 3)``; any integer dtype is accepted.
    n_vertices : int
        Number of vertices the indices refer to.

    Returns
    -------
    numpy.ndarray
        ``(f, 3)`` int64 copy.
    """
    if sp.issparse(F):
        raise ValueError(f"{name} must be a dense integer array, got a sparse matrix")
    a = np.asarray(F)
    if a.dtype == bool or not np.issubdtype(a.dtype, np.integer):
        raise ValueError(f"{name} must be an integer array of vertex indices, got {_describe(a)}")
    if a.ndim != 2 or a.shape[1] != 3 or a.shape[0] == 0:
        raise ValueError(f"{name} must have shape (f, 3) with f >= 1 (one triangle per row), got {_describe(a)}")
    a = np.array(a, dtype=np.int64, copy=True)
    out = (a < 0) | (a >= n_vertices)
    if out.any():
        t, k = np.argwhere(out)[0]
        raise ValueError(
            f"{name} has a vertex index out of range: {name}[{t}, {k}] = {a[t, k]}, "
            f"but there are {n_vertices} vertices"
        )
    repeated = (a[:, 0] == a[:, 1]) | (a[:, 1] == a[:, 2]) | (a[:, 2] == a[:, 0])
    if repeated.any():
        t = int(np.flatnonzero(repeated)[0])
        raise ValueError(f"{name} has a triangle with a repeated vertex: {name}[{t}] = {a[t].tolist()}")
    return a


def check_no_degenerate_triangles(V: np.ndarray, F: np.ndarray, name: str = "F", rel_tol: float = 1e-14) -> None:
    """Raise if a triangle has (numerically) zero area.

    Cotangents divide by twice the area, so a zero-area triangle makes them
    infinite. ``rel_tol`` is relative to the squared bounding-box diagonal.
    """
    e1 = V[F[:, 1]] - V[F[:, 0]]
    e2 = V[F[:, 2]] - V[F[:, 0]]
    if V.shape[1] == 2:
        area2 = np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    else:
        area2 = np.linalg.norm(np.cross(e1, e2), axis=1)
    scale = float(np.sum((V.max(axis=0) - V.min(axis=0)) ** 2))
    bad = area2 <= rel_tol * max(scale, np.finfo(float).tiny)
    if bad.any():
        t = int(np.flatnonzero(bad)[0])
        raise ValueError(
            f"{name} has a zero-area triangle: {name}[{t}] = {F[t].tolist()} "
            f"({int(bad.sum())} in total); cotangent weights are undefined there"
        )


def as_weights(w, k: int, name: str = "w") -> np.ndarray:
    """Check per-point weights: ``None`` means all ones; else ``(k,)``, ``>= 0``, not all zero."""
    if w is None:
        return np.ones(k)
    a = as_float_array(w, name, ndim=1)
    if a.shape[0] != k:
        raise ValueError(f"{name} must have one weight per point ({k}), got {a.shape[0]}")
    if (a < 0).any():
        i = int(np.flatnonzero(a < 0)[0])
        raise ValueError(f"{name} must be non-negative, got {name}[{i}] = {a[i]}")
    if a.sum() <= 0:
        raise ValueError(f"{name} must have a positive sum, got all zeros")
    return a


def _distinct_indices(indices, n: int, name: str, noun: str, empty: str, plural: str) -> np.ndarray:
    """A non-empty 1-D int64 copy of distinct indices in ``[0, n)``; messages name ``noun`` indices."""
    a = np.asarray(indices)
    if a.ndim != 1:
        raise ValueError(f"{name} must be a 1-D array of {noun} indices, got {_describe(a)}")
    if a.size == 0:
        raise ValueError(f"{name} is empty: {empty}")
    if a.dtype == bool or not np.issubdtype(a.dtype, np.integer):
        raise ValueError(f"{name} must be an integer array of {noun} indices, got {_describe(a)}")
    a = np.array(a, dtype=np.int64, copy=True)
    out = (a < 0) | (a >= n)
    if out.any():
        i = int(np.flatnonzero(out)[0])
        raise ValueError(f"{name}[{i}] = {a[i]} is out of range: there are {n} {plural}")
    uniq, counts = np.unique(a, return_counts=True)
    if (counts > 1).any():
        raise ValueError(f"{name} has duplicate {noun} {int(uniq[counts > 1][0])}")
    return a


def as_handles(handles, n_vertices: int, name: str = "handles") -> np.ndarray:
    """Check a non-empty 1-D array of distinct vertex indices in ``[0, n_vertices)``.

    Returns
    -------
    numpy.ndarray
        ``(h,)`` int64 copy, in the caller's order.
    """
    return _distinct_indices(handles, n_vertices, name, "vertex", "at least one vertex must be constrained", "vertices")


def unreferenced_vertex(F: np.ndarray, n_vertices: int) -> int | None:
    """The smallest vertex index that no cell of ``F`` uses, or None.

    Parameters
    ----------
    F : (f, k) numpy.ndarray of int
        Cells (triangles ``k = 3``, tetrahedra ``k = 4``), already checked.
    n_vertices : int

    Returns
    -------
    int or None
        An unused vertex has no area or volume around it (zero mass, no Euler characteristic share).
    """
    used = np.zeros(n_vertices, dtype=bool)
    used[F.ravel()] = True
    return None if used.all() else int(np.flatnonzero(~used)[0])


def component_without(F: np.ndarray, n_vertices: int, constrained: np.ndarray) -> int | None:
    """A vertex of a connected component of the mesh with no vertex in ``constrained``, or None.

    Parameters
    ----------
    F : (f, k) numpy.ndarray of int
        Cells (triangles ``k = 3``, tetrahedra ``k = 4``), already checked.
    n_vertices : int
    constrained : (c,) numpy.ndarray of int
        Vertices whose values are fixed (handles, ``b``).

    Returns
    -------
    int or None
        The smallest vertex of the first component no constraint reaches: the
        values there are undetermined.
    """
    # corner i joined to corner i+1 of every cell joins all of its corners
    adjacency = sp.coo_matrix((np.ones(F.size), (F.ravel(), np.roll(F, 1, axis=1).ravel())), shape=(n_vertices, n_vertices))
    _, component = sp.csgraph.connected_components(adjacency, directed=False)
    free = np.setdiff1d(component, component[constrained])
    return int(np.flatnonzero(component == free[0])[0]) if free.size else None


def as_handle_positions(handle_positions, n_handles: int, d: int, name: str = "handle_positions") -> np.ndarray:
    """Check ``(n_handles, d)`` target positions."""
    a = as_float_array(handle_positions, name, ndim=2)
    if a.shape != (n_handles, d):
        raise ValueError(
            f"{name} must have shape ({n_handles}, {d}), one row per handle, got {a.shape}"
        )
    return a


def as_square_matrices(S, name: str = "S", dims=(2, 3)) -> np.ndarray:
    """Check a ``(d, d)`` matrix or a ``(k, d, d)`` stack, ``d`` in ``dims``."""
    a = as_float_array(S, name)
    if a.ndim not in (2, 3) or a.shape[-1] != a.shape[-2] or a.shape[-1] not in dims:
        raise ValueError(
            f"{name} must be a (d, d) matrix or a (k, d, d) stack with d in {tuple(dims)}, got {_describe(a)}"
        )
    return a


def as_corner_weights(C, n_faces: int, name: str = "C") -> np.ndarray:
    """Check ``(f, 3)`` per-corner weights (e.g. half cotangents)."""
    a = as_float_array(C, name, ndim=2)
    if a.shape != (n_faces, 3):
        raise ValueError(f"{name} must have shape ({n_faces}, 3), one row per triangle, got {a.shape}")
    return a


def as_labels(labels, n_items: int, name: str = "labels") -> np.ndarray:
    """Check ``(n_items,)`` non-negative integer labels, one per item (e.g. a cluster per vertex).

    Returns
    -------
    numpy.ndarray
        ``(n_items,)`` int64 copy.
    """
    if sp.issparse(labels):
        raise ValueError(f"{name} must be a dense integer array, got a sparse matrix")
    a = np.asarray(labels)
    if a.dtype == bool or not np.issubdtype(a.dtype, np.integer):
        raise ValueError(f"{name} must be an integer array of labels, got {_describe(a)}")
    if a.shape != (n_items,):
        raise ValueError(f"{name} must have shape ({n_items},), one label per item, got {_describe(a)}")
    a = np.array(a, dtype=np.int64, copy=True)
    if (a < 0).any():
        i = int(np.flatnonzero(a < 0)[0])
        raise ValueError(f"{name} must be non-negative, got {name}[{i}] = {a[i]}")
    return a


def as_handle_indices(indices, n_handles: int, name: str = "handles") -> np.ndarray:
    """Check a non-empty 1-D array of distinct handle indices (columns of ``W``) in ``[0, n_handles)``.

    Returns
    -------
    numpy.ndarray
        ``(h,)`` int64 copy, in the caller's order.
    """
    if sp.issparse(indices):
        raise ValueError(f"{name} must be a dense integer array, got a sparse matrix")
    return _distinct_indices(indices, n_handles, name, "handle", "at least one handle must be given", "handles (columns of W)")
