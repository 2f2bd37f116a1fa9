NOTEBOOK = '03_arap'
DESCRIPTION = '05 beginner following the lecture step by step: law-of-cosines cotangents, named intermediate arrays, one corner at a time'
SOLUTIONS = {
    'optimal_rotation': r'''import numpy as np


def optimal_rotation(S):
    """The rotation maximizing ``tr(R S)``, for one matrix or a stack of them.

    Parameters
    ----------
    S : (d, d) or (k, d, d) array_like of float
        Covariance matrix or matrices, ``S = Ũ Σ Ṽᵀ``.

    Returns
    -------
    R : numpy.ndarray, the shape of ``S``
        ``R = Ṽ diag(1, …, 1, det(Ṽ Ũᵀ)) Ũᵀ``: orthogonal with ``det R = +1``.
    """
    # step 1: the SVD works on stacks too (it broadcasts over the first axis)
    S = np.array(S, dtype=float)
    U_tilde, sigma, V_tilde_transposed = np.linalg.svd(S)
    # step 2: transpose the last two axes to get V_tilde and U_tilde^T
    V_tilde = np.swapaxes(V_tilde_transposed, -1, -2)
    U_tilde_transposed = np.swapaxes(U_tilde, -1, -2)
    # step 3: the best orthogonal matrix and its determinant (+1 or -1)
    best_orthogonal = V_tilde @ U_tilde_transposed
    determinant = np.linalg.det(best_orthogonal)
    # step 4: D = diag(1, ..., 1, det), one for every matrix in the stack
    dimension = S.shape[-1]
    D = np.zeros(S.shape)
    for i in range(dimension - 1):
        D[..., i, i] = 1.0
    D[..., dimension - 1, dimension - 1] = determinant
    # step 5: R = V_tilde D U_tilde^T
    R = V_tilde @ D @ U_tilde_transposed
    return R
''',
    'cotangent_weights': r'''import numpy as np


def cotangent_weights(V, F):
    """Half the cotangent of every triangle corner.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions, ``d`` in {2, 3}.
    F : (f, 3) array_like of int
        Triangles, none of zero area.

    Returns
    -------
    C : (f, 3) numpy.ndarray
        ``C[t, k] = ½ cot`` of the angle at corner ``k`` of triangle ``t``: the weight of
        the opposite edge ``(F[t, (k+1)%3], F[t, (k+2)%3])``.
    """
    # step 1: arrays
    vertices = np.array(V, dtype=float)
    triangles = np.array(F, dtype=int)
    # step 2: the three corners of every triangle
    corner_0 = vertices[triangles[:, 0]]
    corner_1 = vertices[triangles[:, 1]]
    corner_2 = vertices[triangles[:, 2]]
    # step 3: squared lengths of the edges opposite each corner
    length_sq_0 = np.sum((corner_2 - corner_1) ** 2, axis=1)
    length_sq_1 = np.sum((corner_0 - corner_2) ** 2, axis=1)
    length_sq_2 = np.sum((corner_1 - corner_0) ** 2, axis=1)
    # step 4: twice the area of every triangle, |a x b|
    edge_a = corner_1 - corner_0
    edge_b = corner_2 - corner_0
    if vertices.shape[1] == 2:
        twice_area = np.abs(edge_a[:, 0] * edge_b[:, 1] - edge_a[:, 1] * edge_b[:, 0])
    else:
        twice_area = np.linalg.norm(np.cross(edge_a, edge_b), axis=1)
    # step 5: law of cosines: cot(alpha) = (b^2 + c^2 - a^2) / (4 * area) = (b^2 + c^2 - a^2) / (2 * twice_area)
    # and we want half of the cotangent
    half_cot_0 = (length_sq_1 + length_sq_2 - length_sq_0) / (4.0 * twice_area)
    half_cot_1 = (length_sq_2 + length_sq_0 - length_sq_1) / (4.0 * twice_area)
    half_cot_2 = (length_sq_0 + length_sq_1 - length_sq_2) / (4.0 * twice_area)
    # step 6: one column per corner
    C = np.stack([half_cot_0, half_cot_1, half_cot_2], axis=1)
    return C
''',
    'cotangent_laplacian': r'''import numpy as np
from scipy.sparse import coo_matrix


def cotangent_laplacian(V, F):
    """The cotangent Laplacian (libigl's sign: negative semi-definite).

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions.
    F : (f, 3) array_like of int
        Triangles.

    Returns
    -------
    L : (n, n) scipy.sparse matrix
        Symmetric; ``L[i, j]`` is the sum of the cotangent weights of edge ``(i, j)``,
        ``L[i, i] = -Σ_{j≠i} L[i, j]``.
    """
    # step 1: the weights and the sizes
    weights = cotangent_weights(V, F)
    triangles = np.array(F, dtype=int)
    number_of_vertices = len(V)
    # step 2: the edge opposite corner k goes from (k+1)%3 to (k+2)%3
    start = np.concatenate([triangles[:, 1], triangles[:, 2], triangles[:, 0]])
    end = np.concatenate([triangles[:, 2], triangles[:, 0], triangles[:, 1]])
    values = np.concatenate([weights[:, 0], weights[:, 1], weights[:, 2]])
    # step 3: every edge in both directions (+c) and on both diagonals (-c),
    # so that the rows sum to zero; coo_matrix adds the duplicates
    all_rows = np.concatenate([start, end, start, end])
    all_columns = np.concatenate([end, start, start, end])
    all_values = np.concatenate([values, values, -values, -values])
    L = coo_matrix((all_values, (all_rows, all_columns)), shape=(number_of_vertices, number_of_vertices))
    # step 4: convert to a format that is good for computing
    L = L.tocsr()
    return L
''',
    'arap_covariances': r'''import numpy as np


def arap_covariances(V, U, F, C):
    """The covariance matrix of every vertex's cell (the triangles around it).

    Parameters
    ----------
    V, U : (n, d) array_like of float
        Rest and deformed positions.
    F : (f, 3) array_like of int
        Triangles.
    C : (f, 3) array_like of float
        Cotangent weights, ``C[t, k]`` for the edge opposite corner ``k``.

    Returns
    -------
    S : (n, d, d) numpy.ndarray
        ``S_i = Σ_{t ∋ i} Σ_k C[t, k] e_tk e'_tkᵀ``, ``e_tk`` the rest edge opposite corner
        ``k`` and ``e'_tk`` the same edge in ``U``.
    """
    # step 1: arrays
    rest = np.array(V, dtype=float)
    deformed = np.array(U, dtype=float)
    triangles = np.array(F, dtype=int)
    weights = np.array(C, dtype=float)
    number_of_vertices, dimension = rest.shape
    number_of_triangles = triangles.shape[0]
    # step 2: the matrix of every triangle, sum over its three edges
    triangle_matrices = np.zeros((number_of_triangles, dimension, dimension))
    for k in range(3):
        first = triangles[:, (k + 1) % 3]
        second = triangles[:, (k + 2) % 3]
        rest_edge = rest[second] - rest[first]
        deformed_edge = deformed[second] - deformed[first]
        # outer product e e'^T for every triangle, times its weight
        outer = rest_edge[:, :, np.newaxis] * deformed_edge[:, np.newaxis, :]
        triangle_matrices = triangle_matrices + weights[:, k, np.newaxis, np.newaxis] * outer
    # step 3: give each triangle's matrix to its three corners
    S = np.zeros((number_of_vertices, dimension, dimension))
    for corner in range(3):
        np.add.at(S, triangles[:, corner], triangle_matrices)
    return S
''',
    'arap_rotations': r'''def arap_rotations(V, U, F, C):
    """The local step: the best rotation of every vertex's cell.

    Parameters
    ----------
    V, U : (n, d) array_like of float
        Rest and deformed positions.
    F : (f, 3) array_like of int
        Triangles.
    C : (f, 3) array_like of float
        Cotangent weights.

    Returns
    -------
    R : (n, d, d) numpy.ndarray
        ``R_i = optimal_rotation(S_i)`` with ``S = arap_covariances(V, U, F, C)``.
    """
    # step 1: the covariance of every cell
    S = arap_covariances(V, U, F, C)
    # step 2: the best rotation for each of them
    R = optimal_rotation(S)
    return R
''',
    'arap_energy': r'''import numpy as np


def arap_energy(V, U, F, C, R):
    """The ARAP energy of positions ``U`` measured against one rotation per vertex.

    Parameters
    ----------
    V, U : (n, d) array_like of float
        Rest and deformed positions.
    F : (f, 3) array_like of int
        Triangles.
    C : (f, 3) array_like of float
        Cotangent weights.
    R : (n, d, d) array_like of float
        The rotation of every vertex's cell.

    Returns
    -------
    E : float
        ``Σ_i Σ_{t ∋ i} Σ_k C[t, k] ‖e'_tk - R_i e_tk‖²``.
    """
    # step 1: arrays
    rest = np.array(V, dtype=float)
    deformed = np.array(U, dtype=float)
    triangles = np.array(F, dtype=int)
    weights = np.array(C, dtype=float)
    rotations = np.array(R, dtype=float)
    energy = 0.0
    # step 2: each edge k of each triangle is compared with the rotation of each corner i
    for k in range(3):
        first = triangles[:, (k + 1) % 3]
        second = triangles[:, (k + 2) % 3]
        rest_edge = rest[second] - rest[first]
        deformed_edge = deformed[second] - deformed[first]
        for i in range(3):
            corner_rotation = rotations[triangles[:, i]]
            rotated_rest_edge = np.matmul(corner_rotation, rest_edge[:, :, np.newaxis])[:, :, 0]
            difference = deformed_edge - rotated_rest_edge
            squared_length = np.sum(difference ** 2, axis=1)
            energy = energy + np.sum(weights[:, k] * squared_length)
    return float(energy)
''',
}
LOSES = set()
