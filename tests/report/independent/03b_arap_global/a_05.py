import runpy
from pathlib import Path

# the same student's 03 submission: its functions are copied into 03b, as the notebook asks
_STAGE_03 = runpy.run_path(str(Path(__file__).parents[1] / "03_arap" / Path(__file__).name))

NOTEBOOK = '03b_arap_global'
DESCRIPTION = _STAGE_03["DESCRIPTION"]
SOLUTIONS = {
    **_STAGE_03["SOLUTIONS"],
    'arap_precompute': r'''import numpy as np
from scipy.sparse.linalg import splu


def arap_precompute(V, F, handles):
    """What the ARAP iterations reuse: the rest mesh, the weights and the factorized system.

    Parameters
    ----------
    V : (n, d) array_like of float
        Rest positions.
    F : (f, 3) array_like of int
        Triangles.
    handles : (h,) array_like of int
        Distinct vertex indices whose positions are prescribed; at least one.

    Returns
    -------
    data : object of your design
        Everything ``arap_global_step`` and ``arap_solve`` need.

    Raises
    ------
    ValueError
        If ``handles`` is empty, repeats a vertex or is out of range.
    """
    # step 1: arrays
    rest = np.array(V, dtype=float)
    triangles = np.array(F, dtype=int)
    handle_indices = np.array(handles, dtype=int)
    number_of_vertices = rest.shape[0]
    # step 2: the weights and the Laplacian of the rest mesh (they never change)
    weights = cotangent_weights(rest, triangles)
    L = cotangent_laplacian(rest, triangles)
    # step 3: check the handles before using them
    number_of_handles = handle_indices.size
    if number_of_handles < 1:
        raise ValueError("there must be at least one handle")
    if np.any(handle_indices < 0) or np.any(handle_indices > number_of_vertices - 1):
        raise ValueError("a handle index is not a vertex of the mesh")
    different_handles = set(handle_indices.tolist())
    if len(different_handles) < number_of_handles:
        raise ValueError("the same vertex is used twice as a handle")
    # step 4: the free vertices are all the others
    all_vertices = np.arange(number_of_vertices)
    free_indices = all_vertices[np.isin(all_vertices, handle_indices, invert=True)]
    # step 5: the blocks of -L (rows of the free vertices)
    minus_L = (-1.0 * L).tocsr()
    rows_of_free = minus_L[free_indices, :]
    minus_L_ff = rows_of_free[:, free_indices]
    minus_L_fh = rows_of_free[:, handle_indices]
    # step 6: factorize once, it does not depend on R or on the handle positions
    factorization = splu(minus_L_ff.tocsc())
    data = {}
    data["rest"] = rest
    data["triangles"] = triangles
    data["weights"] = weights
    data["laplacian"] = L
    data["handle_indices"] = handle_indices
    data["free_indices"] = free_indices
    data["minus_L_fh"] = minus_L_fh
    data["factorization"] = factorization
    return data
''',
    'arap_global_step': r'''import numpy as np


def arap_global_step(data, R, handle_positions):
    """The global step: the positions minimizing the ARAP energy for fixed rotations.

    Parameters
    ----------
    data : object
        From ``arap_precompute``.
    R : (n, d, d) array_like of float
        The rotation of every vertex's cell.
    handle_positions : (h, d) array_like of float
        Where the handles go.

    Returns
    -------
    U : (n, d) numpy.ndarray
        ``U[handles] = handle_positions``; the free rows solve ``(-L)_ff U_f = B_f - (-L)_fh U_h``.
    """
    # step 1: take what we need out of data
    rest = data["rest"]
    triangles = data["triangles"]
    weights = data["weights"]
    number_of_vertices, dimension = rest.shape
    rotations = np.array(R, dtype=float)
    target = np.array(handle_positions, dtype=float)
    # step 2: the mean rotation of every triangle
    mean_rotation = (rotations[triangles[:, 0]] + rotations[triangles[:, 1]] + rotations[triangles[:, 2]]) / 3.0
    # step 3: the right-hand side B, edge by edge
    B = np.zeros((number_of_vertices, dimension))
    for k in range(3):
        a = triangles[:, (k + 1) % 3]
        b = triangles[:, (k + 2) % 3]
        rest_edge = rest[a] - rest[b]
        rotated = np.matmul(mean_rotation, rest_edge[:, :, np.newaxis])[:, :, 0]
        contribution = weights[:, k, np.newaxis] * rotated
        np.add.at(B, a, contribution)
        np.add.at(B, b, -contribution)
    # step 4: move the known handle columns to the right-hand side
    free = data["free_indices"]
    right_hand_side = B[free] - data["minus_L_fh"] @ target
    # step 5: solve and put everything together
    solution = data["factorization"].solve(right_hand_side)
    U = np.zeros((number_of_vertices, dimension))
    U[free] = solution
    U[data["handle_indices"]] = target
    return U
''',
    'arap_solve': r'''import numpy as np


def arap_solve(data, handle_positions, U0=None, iterations=10):
    """ARAP deformation: alternate the local and the global step.

    Parameters
    ----------
    data : object
        From ``arap_precompute``.
    handle_positions : (h, d) array_like of float
        Where the handles go.
    U0 : (n, d) array_like of float, optional
        The start; the rest positions by default. Its handle rows are replaced by
        ``handle_positions`` first.
    iterations : int
        Local–global iterations.

    Returns
    -------
    U : (n, d) numpy.ndarray
        The positions after the last iteration.
    energies : (iterations,) numpy.ndarray
        ``energies[k]``: the energy after iteration ``k``'s global step, with the rotations it used.
    """
    # step 1: the starting positions (np.array makes a copy, so U0 is not changed)
    if U0 is None:
        start = data["rest"]
    else:
        start = U0
    U = np.array(start, dtype=float)
    # step 2: the handles are where they belong from the start
    target = np.array(handle_positions, dtype=float)
    U[data["handle_indices"], :] = target
    # step 3: local step, global step, then the energy with the rotations of this iteration
    energies = np.zeros(iterations)
    iteration = 0
    while iteration < iterations:
        rotations = arap_rotations(data["rest"], U, data["triangles"], data["weights"])
        new_U = arap_global_step(data, rotations, target)
        energies[iteration] = arap_energy(data["rest"], new_U, data["triangles"], data["weights"], rotations)
        U = new_U
        iteration = iteration + 1
    return U, energies
''',
    'laplacian_editing': r'''import numpy as np


def laplacian_editing(V, F, handles, handle_positions):
    """Naive Laplacian editing: the global step with every rotation the identity.

    Parameters
    ----------
    V : (n, d) array_like of float
        Rest positions.
    F : (f, 3) array_like of int
        Triangles.
    handles : (h,) array_like of int
        Vertex indices.
    handle_positions : (h, d) array_like of float
        Where the handles go.

    Returns
    -------
    U : (n, d) numpy.ndarray
    """
    # step 1: precompute as for ARAP
    data = arap_precompute(V, F, handles)
    # step 2: every rotation is the identity
    number_of_vertices, dimension = data["rest"].shape
    identity_rotations = np.zeros((number_of_vertices, dimension, dimension))
    for i in range(number_of_vertices):
        identity_rotations[i] = np.eye(dimension)
    # step 3: one global step
    U = arap_global_step(data, identity_rotations, handle_positions)
    return U
''',
}
LOSES = set()
