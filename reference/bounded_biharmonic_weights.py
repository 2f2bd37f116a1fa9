"""Stage 04, bounded biharmonic weights: smooth, bounded skinning weights per handle."""

import igl
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from reference.arap import cotangent_laplacian
from reference.box_qp import box_qp
from reference.tetrahedra import _tet_biharmonic_matrix, as_tet_mesh
from starter.validation import (
    component_without,
    as_faces,
    as_float_array,
    as_handles,
    as_points,
    as_vertices,
    check_no_degenerate_triangles,
    unreferenced_vertex,
)


def as_cells(V, F):
    """Check a mesh of triangles ``(f, 3)`` or tetrahedra ``(f, 4)``, dispatching on the cell size.

    Returns
    -------
    V : (n, d) numpy.ndarray of float64
    F : (f, 3) or (f, 4) numpy.ndarray of int64
        Triangles without zero area, or tetrahedra (then ``d = 3``) without zero volume.
    """
    V = as_vertices(V)
    if np.ndim(F) == 2 and np.shape(F)[1] == 4:
        return as_tet_mesh(V, F, name="F")
    try:
        F = as_faces(F, len(V))
    except ValueError as error:
        if "must have shape" not in str(error):
            raise
        raise ValueError(
            f"F must have shape (f, 3) (triangles) or (f, 4) (tetrahedra) with f >= 1, got shape {np.shape(F)}"
        ) from None
    check_no_degenerate_triangles(V, F)
    return V, F


def biharmonic_matrix(V, F):
    """Discrete biharmonic energy matrix ``Q = L M⁻¹ L``.

    ``½ wᵀ Q w`` approximates ``½ ∫ (Δw)²``: ``L`` is the cotangent Laplacian
    and ``M`` the lumped mass matrix (libigl's defaults: Voronoi on
    triangles, barycentric on tetrahedra).

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions, ``d`` in {2, 3} (3 for tetrahedra); every vertex is
        used by a cell.
    F : (f, 3) or (f, 4) array_like of int
        Triangles indexing ``V``, none of zero area, or tetrahedra, none of
        zero volume.

    Returns
    -------
    Q : (n, n) scipy.sparse.csc_matrix
        Symmetric positive semi-definite; constants are in its null space.
    """
    return _biharmonic_matrix(*as_cells(V, F))


def _biharmonic_matrix(V, F):
    """``biharmonic_matrix`` of a mesh already checked by ``as_cells``."""
    if F.shape[1] == 4:
        return sp.csc_matrix(_tet_biharmonic_matrix(V, F))
    i = unreferenced_vertex(F, len(V))
    if i is not None:
        # an unreferenced vertex has zero mass, so M⁻¹ does not exist
        raise ValueError(f"V has an unreferenced vertex: V[{i}] is used by no cell in F")
    L = sp.csc_matrix(cotangent_laplacian(V, F))
    return sp.csc_matrix(L @ sp.diags(1.0 / igl.massmatrix(V, F).diagonal()) @ L)


def handle_constraints(handles):
    """Boundary conditions ``(b, bc)`` of skinning weights for a set of handles.

    Parameters
    ----------
    handles : list of array_like of int
        One entry per handle: a single vertex index for a point handle, several
        for a bone or a region. No vertex may belong to two handles.

    Returns
    -------
    b : (k,) numpy.ndarray of int64
        The handles' vertices, concatenated in order.
    bc : (k, m) numpy.ndarray
        ``bc[i, j] = 1`` if ``b[i]`` belongs to handle ``j``, else 0; ``m = len(handles)``.
    """
    try:
        parts = [np.atleast_1d(np.asarray(h)) for h in handles]
    except TypeError:
        raise ValueError(
            f"handles must be a list of integer arrays, one per handle, got {type(handles).__name__}"
        ) from None
    if not parts:
        raise ValueError("handles is empty: at least one handle is needed")
    for j, h in enumerate(parts):
        if h.size == 0:
            raise ValueError(f"handles[{j}] is empty: every handle needs at least one vertex")
        if h.ndim != 1 or h.dtype == bool or not np.issubdtype(h.dtype, np.integer):
            raise ValueError(
                f"handles[{j}] must be a 1-D integer array of vertex indices, "
                f"got shape {h.shape} and dtype {h.dtype}"
            )
        if (h < 0).any():
            raise ValueError(f"handles[{j}] has a negative vertex index {int(h[h < 0][0])}")
    b = np.concatenate(parts).astype(np.int64)
    owner = np.repeat(np.arange(len(parts)), [len(h) for h in parts])
    uniq, counts = np.unique(b, return_counts=True)
    if (counts > 1).any():
        v = int(uniq[counts > 1][0])
        j, k = owner[b == v][:2]
        where = f"twice in handles[{j}]" if j == k else f"in handles[{j}] and handles[{k}]"
        raise ValueError(f"handles must not share vertices: vertex {v} is {where}")
    bc = np.zeros((len(b), len(parts)))
    bc[np.arange(len(b)), owner] = 1.0
    return b, bc


def inverse_distance_weights(V, handle_points, power=2):
    """Shepard (inverse-distance) weights of every vertex for a set of handle points.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions, ``d`` in {2, 3}.
    handle_points : (m, d) array_like of float
        Distinct handle positions (more than 2e-12 apart, so no vertex is
        within 1e-12 of two of them).
    power : float, optional
        Positive fall-off exponent.

    Returns
    -------
    W : (n, m) numpy.ndarray
        ``W[i, j] ∝ ‖v_i - h_j‖^-power``, rows summing to 1; a vertex within
        1e-12 of a handle point gets that handle's one-hot row.
    """
    V = as_vertices(V)
    H = as_points(handle_points, "handle_points", dims=(V.shape[1],))
    p = float(as_float_array(power, "power", ndim=0))
    if not p > 0:
        raise ValueError(f"power must be positive, got {p}")
    gaps = np.linalg.norm(H[:, None] - H[None], axis=2)
    close = np.argwhere(np.triu(gaps <= 2e-12, k=1))
    if len(close):
        i, j = close[0]
        raise ValueError(
            f"handle_points must be distinct: rows {i} and {j} are {gaps[i, j]:.3g} apart "
            f"(at most 2e-12), so the weights near them are undefined"
        )
    D = np.linalg.norm(V[:, None] - H[None], axis=2)
    nearest = D.argmin(axis=1)
    d_min = D[np.arange(len(V)), nearest]
    on_handle = d_min <= 1e-12
    # (d_min / d)^p is d^-p rescaled per row: it lies in [0, 1], so large
    # powers or tiny distances cannot overflow
    W = (d_min[:, None] / np.where(on_handle[:, None], 1.0, D)) ** p
    W[on_handle] = 0.0
    W[on_handle, nearest[on_handle]] = 1.0
    return W / W.sum(axis=1, keepdims=True)


def unconstrained_biharmonic_weights(V, F, b, bc):
    """Biharmonic weights without bounds: ``argmin ½ tr(Wᵀ Q W)`` s.t. ``W[b] = bc``.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions, ``d`` in {2, 3} (3 for tetrahedra).
    F : (f, 3) or (f, 4) array_like of int
        Triangles or tetrahedra indexing ``V`` (see ``biharmonic_matrix``).
    b : (k,) array_like of int
        Distinct constrained vertices; every connected component of the mesh
        needs at least one.
    bc : (k, m) array_like of float
        Values of the ``m`` weight functions at ``b``.

    Returns
    -------
    W : (n, m) numpy.ndarray
        ``W[b] = bc``; ``Q W = 0`` on the other rows, ``Q = biharmonic_matrix(V, F)``.
    """
    V, F = as_cells(V, F)
    b = as_handles(b, len(V), "b")
    bc = as_float_array(bc, "bc", ndim=2)
    if bc.shape[0] != len(b) or bc.shape[1] == 0:
        raise ValueError(
            f"bc must have shape ({len(b)}, m) with m >= 1: one row per vertex in b "
            f"and one column per weight function, got {bc.shape}"
        )
    Q = _biharmonic_matrix(V, F)
    n = len(V)
    i = component_without(F, n, b)
    if i is not None:
        raise ValueError(
            f"b must contain a vertex of every connected component of the mesh: "
            f"the component of vertex {i} has none, so its weights are undetermined"
        )
    free = np.setdiff1d(np.arange(n), b)
    W = np.zeros((n, bc.shape[1]))
    W[b] = bc
    if free.size:
        Q_free = Q[free]
        # Q is symmetric positive definite on the free vertices: symmetric
        # mode with diagonal pivots factors it far faster than partial pivoting
        lu = spla.splu(
            Q_free[:, free].tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
            options={"SymmetricMode": True},
        )
        W[free] = lu.solve(-(Q_free[:, b] @ bc))
    return W


def bbw(V, F, b, bc):
    """Bounded biharmonic weights (Jacobson et al. 2011), normalized.

    For each handle ``j`` the weights minimize ``½ wᵀ Q w`` subject to
    ``w[b] = bc[:, j]`` and ``0 ≤ w ≤ 1`` (``Q = biharmonic_matrix(V, F)``);
    the rows are then divided by their sums.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions, ``d`` in {2, 3} (3 for tetrahedra).
    F : (f, 3) or (f, 4) array_like of int
        Triangles or tetrahedra indexing ``V`` (see ``biharmonic_matrix``).
    b : (k,) array_like of int
        Distinct constrained vertices; every connected component of the mesh
        needs at least one.
    bc : (k, m) array_like of float
        Values in ``[0, 1]`` of the ``m`` weight functions at ``b``, each row
        with a positive sum (e.g. from ``handle_constraints``).

    Returns
    -------
    W : (n, m) numpy.ndarray
        ``0 ≤ W ≤ 1``, rows summing to 1, ``W[b] = bc`` with its rows normalized.

    Raises
    ------
    ValueError
        On malformed input.
    RuntimeError
        If the active-set solver does not converge (it always should: the
        problem is a strictly convex box-constrained quadratic program).
    """
    V, F = as_cells(V, F)
    b = as_handles(b, len(V), "b")
    bc = as_float_array(bc, "bc", ndim=2)
    if bc.shape[0] != len(b) or bc.shape[1] == 0:
        raise ValueError(
            f"bc must have shape ({len(b)}, m) with m >= 1: one row per vertex in b "
            f"and one column per handle, got {bc.shape}"
        )
    if (bc < 0).any() or (bc > 1).any():
        i, j = np.argwhere((bc < 0) | (bc > 1))[0]
        raise ValueError(f"bc must lie in [0, 1] (the weights are bounded), got bc[{i}, {j}] = {bc[i, j]}")
    if (bc.sum(axis=1) <= 0).any():
        i = int(np.flatnonzero(bc.sum(axis=1) <= 0)[0])
        raise ValueError(f"bc must have rows with a positive sum (they are normalized), row {i} is all zeros")
    Q = _biharmonic_matrix(V, F)
    n, m = len(V), bc.shape[1]
    i = component_without(F, n, b)
    if i is not None:
        raise ValueError(
            f"b must contain a vertex of every connected component of the mesh: "
            f"the component of vertex {i} has none, so its weights are undetermined"
        )

    # each column is a box-constrained QP on the free vertices: the energy
    # ½ wᵀ Q w with w[b] = bc is ½ xᵀ H x - gᵀ x in x = w[free]
    free = np.setdiff1d(np.arange(n), b)
    W = np.zeros((n, m))
    W[b] = bc
    if free.size:
        Q_free = Q[free]
        W[free] = box_qp(Q_free[:, free], -(Q_free[:, b] @ bc))
    sums = W.sum(axis=1)
    if (sums <= 0).any():
        i = int(np.flatnonzero(sums <= 0)[0])
        raise ValueError(f"bc gives vertex {i} zero weight for every handle, so its row cannot be normalized")
    return W / sums[:, None]
