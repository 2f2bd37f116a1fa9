"""Stage 00, meshes: edges and the Euler–Poincaré formula ``χ = 2(c - g) - b``."""

import numpy as np
import scipy.sparse as sp

from starter.validation import as_faces, as_vertices, unreferenced_vertex


def edges(F):
    """Unique undirected edges of a triangle mesh.

    Parameters
    ----------
    F : (f, 3) array_like of int
        Triangles as vertex indices.

    Returns
    -------
    E : (e, 2) numpy.ndarray of int64
        Each undirected edge once, each row sorted ascending, rows sorted
        lexicographically.
    """
    F_in = np.asarray(F)
    # Only F is given, so the vertex count is the largest index + 1; a wrong
    # dtype or shape is reported by as_faces before the count matters.
    n = max(int(F_in.max()) + 1, 0) if F_in.size and np.issubdtype(F_in.dtype, np.integer) else 0
    F = as_faces(F, n)
    half_edges = F[:, [[1, 2], [2, 0], [0, 1]]].reshape(-1, 2)
    return np.unique(np.sort(half_edges, axis=1), axis=0)


def euler_characteristic(V, F):
    """Euler characteristic ``χ = #vertices - #edges + #faces``.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions, ``d`` in {2, 3}.
    F : (f, 3) array_like of int
        Triangles indexing ``V``.

    Returns
    -------
    chi : int
    """
    V = as_vertices(V)
    F = as_faces(F, len(V))
    return int(len(V) - len(edges(F)) + len(F))


def boundary_loop_count(F):
    """Number of boundary loops of an edge-manifold triangle mesh.

    A boundary edge is used by exactly one triangle. On a manifold mesh every
    boundary vertex has exactly two boundary edges, so the boundary edges
    form disjoint cycles: the loops are the connected components of the
    graph of boundary edges.

    Parameters
    ----------
    F : (f, 3) array_like of int
        Triangles as vertex indices.

    Returns
    -------
    b : int
        Number of boundary loops (0 for a closed surface).

    Raises
    ------
    ValueError
        If ``F`` is malformed or an edge is shared by more than two triangles.
    """
    F_in = np.asarray(F)
    # Only F is given, so the vertex count is the largest index + 1; a wrong
    # dtype or shape is reported by as_faces before the count matters.
    n = max(int(F_in.max()) + 1, 0) if F_in.size and np.issubdtype(F_in.dtype, np.integer) else 0
    F = as_faces(F, n)
    half_edges = np.sort(F[:, [[1, 2], [2, 0], [0, 1]]].reshape(-1, 2), axis=1)
    E, uses = np.unique(half_edges, axis=0, return_counts=True)
    if (uses > 2).any():
        i = int(np.flatnonzero(uses > 2)[0])
        raise ValueError(
            f"F is not edge-manifold: edge {E[i].tolist()} is shared by {int(uses[i])} triangles"
        )
    B = E[uses == 1]
    if len(B) == 0:
        return 0
    loop_vertices, local = np.unique(B, return_inverse=True)
    local = local.reshape(B.shape)
    graph = sp.coo_array(
        (np.ones(len(B)), (local[:, 0], local[:, 1])), shape=(len(loop_vertices),) * 2
    )
    n_loops, _ = sp.csgraph.connected_components(graph, directed=False)
    return int(n_loops)


def genus(V, F):
    """Genus of an orientable manifold triangle mesh, from ``χ = 2(c - g) - b``.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions, ``d`` in {2, 3}; every vertex is used by a triangle.
    F : (f, 3) array_like of int
        Triangles indexing ``V``.

    Returns
    -------
    g : int
        Total genus (sum over the ``c`` connected components; faces sharing a
        vertex are connected).

    Raises
    ------
    ValueError
        If the inputs are malformed, a vertex is unreferenced, or the formula
        gives a non-integer genus (the mesh is not an orientable manifold).
    """
    V = as_vertices(V)
    F = as_faces(F, len(V))
    i = unreferenced_vertex(F, len(V))
    if i is not None:
        raise ValueError(f"V has an unreferenced vertex: V[{i}] is used by no triangle in F")
    chi = euler_characteristic(V, F)
    b = boundary_loop_count(F)
    E = edges(F)
    graph = sp.coo_array((np.ones(len(E)), (E[:, 0], E[:, 1])), shape=(len(V), len(V)))
    c, _ = sp.csgraph.connected_components(graph, directed=False)
    twice_g = 2 * c - b - chi
    if twice_g % 2:
        raise ValueError(
            f"F is not an orientable manifold: chi = {chi}, c = {c}, b = {b} "
            f"give genus {twice_g / 2} in chi = 2(c - g) - b"
        )
    return int(twice_g // 2)
