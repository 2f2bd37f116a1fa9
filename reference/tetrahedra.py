"""Stage 07, tetrahedra: linear finite elements on a tetrahedral mesh.

With the piecewise-linear hat functions ``φ_i`` of a tetrahedral mesh, the
stiffness matrix ``∫ ∇φ_i · ∇φ_j`` is minus the cotangent Laplacian (its
off-diagonal entries are ``l_kl cot θ_kl / 6``, the opposite edge's length
times the cotangent of its dihedral angle), and the lumped mass matrix gives
each vertex a quarter of the volume of every tetrahedron around it: libigl's
``igl.cotmatrix`` and ``igl.massmatrix`` (barycentric, its default on tets).

ARAP whose cells are tetrahedra: each tetrahedron ``t`` is a cell with its own rotation (libigl's
``ARAP_ENERGY_TYPE_ELEMENTS``). A deformation ``U`` is affine on ``t``, with
deformation gradient ``J_t = Σ_k u_{T[t, k]} ∇φ_kᵀ`` (``= I`` at rest), and

    E(U, R) = Σ_t |vol_t| ‖J_t - R_t‖²_F.

Local step: for fixed ``U`` the best ``R_t`` maximizes ``tr(R_t J_tᵀ)``, the
sign-corrected rotation of ``J_tᵀ`` (a 3x3 problem per tetrahedron). Global
step: for fixed ``R`` the energy is quadratic in ``U`` with matrix
``Σ_t |vol_t| G_tᵀ G_t = -L`` (the cotangent Laplacian), so the free vertices
solve ``-L_ff U_f = B_f + L_fh U_h`` with ``B_i = Σ_{t ∋ i} |vol_t| R_t ∇φ_i``,
one prefactored sparse solve per iteration. Neither step increases ``E``.
"""

import types

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from reference.sign_correction import optimal_rotation
from starter.validation import (
    as_float_array,
    as_handle_positions,
    as_handles,
    as_vertices,
    component_without,
    unreferenced_vertex,
)

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
    used = np.zeros(len(V), dtype=bool)
    used[T.ravel()] = True
    longest = max(float(np.ptp(V[used], axis=0).max()), np.finfo(float).tiny)
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


# Each public function below checks its input with as_tet_mesh once and hands
# it to a private twin that trusts it, so that chains of them (the biharmonic
# matrix, deformation gradients, ARAP's precomputation) check it only once.
def _barycentric_gradients(V, T):
    """``(f, 4, 3)``: ``G[t, k] = ∇φ_{T[t, k]}`` on tetrahedron ``t`` (the four sum to zero); row ``k ≥ 1`` is
    row ``k - 1`` of ``[v1 - v0, v2 - v0, v3 - v0]⁻¹``. No tetrahedron may be flat."""
    return _gradients_and_volumes(V, T)[0]


def _gradients_and_volumes(V, T):
    """``(G, volume)``: ``_barycentric_gradients`` and the unsigned volumes, from one determinant."""
    # the rows of [e1 e2 e3]⁻¹ are e2 × e3, e3 × e1, e1 × e2 over the
    # determinant: 3x faster than a batched inverse, the same to roundoff;
    # written out component by component (the hand's 4,224 tetrahedra: 0.84
    # ms, 1.07 ms through np.cross and np.stack)
    e = V[T[:, 1:]] - V[T[:, :1]]  # (f, 3, 3): e1, e2, e3
    x, y, z = e[:, :, 0], e[:, :, 1], e[:, :, 2]
    G = np.empty((len(T), 4, 3))
    for k, (a, b) in enumerate(((1, 2), (2, 0), (0, 1)), start=1):
        G[:, k, 0] = y[:, a] * z[:, b] - z[:, a] * y[:, b]
        G[:, k, 1] = z[:, a] * x[:, b] - x[:, a] * z[:, b]
        G[:, k, 2] = x[:, a] * y[:, b] - y[:, a] * x[:, b]
    determinant = np.einsum("ta,ta->t", e[:, 0], G[:, 1])
    G[:, 1:] /= determinant[:, None, None]
    G[:, 0] = -G[:, 1:].sum(axis=1)
    return G, np.abs(determinant) / 6.0


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
    return _tet_cotangent_weights(*as_tet_mesh(V, T))


def _tet_cotangent_weights(V, T):
    G, volume = _gradients_and_volumes(V, T)
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
    return _tet_cotangent_laplacian(*as_tet_mesh(V, T))


def _tet_cotangent_laplacian(V, T):
    return _assembled_laplacian(*_gradients_and_volumes(V, T), T, len(V))


def _assembled_laplacian(G, volume, T, n):
    # one COO -> CSR pass over each tetrahedron's 4x4 block -|vol| G Gᵀ: the
    # cotangent weights off the diagonal and, as G's rows sum to zero, minus
    # their row sums on it
    blocks = (G @ G.transpose(0, 2, 1)) * -volume[:, None, None]
    return sp.csr_matrix((blocks.ravel(), (np.repeat(T, 4, axis=1).ravel(), np.tile(T, (1, 4)).ravel())), shape=(n, n))


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
    return _tet_mass_matrix(*as_tet_mesh(V, T))


def _tet_mass_matrix(V, T):
    return sp.diags(_lumped_mass(np.abs(tet_volumes_unchecked(V, T)), T, len(V))).tocsr()


def _lumped_mass(volume, T, n):
    return np.bincount(T.ravel(), weights=np.repeat(volume / 4.0, 4), minlength=n)


def tet_biharmonic_matrix(V, T):
    """Discrete biharmonic energy matrix ``Q = L M⁻¹ L`` of a tetrahedral mesh.

    ``½ wᵀ Q w`` approximates ``½ ∫ (Δw)²`` over the volume: the matrix of
    bounded biharmonic weights on tetrahedra (``igl.bbw``) and of
    ``igl.harmonic(V, T, b, bc, 2)``.

    Parameters
    ----------
    V : (n, 3) array_like of float
        Every vertex is used by a tetrahedron.
    T : (f, 4) array_like of int
        No tetrahedron may be flat.

    Returns
    -------
    Q : (n, n) scipy.sparse.csr_matrix
        Symmetric positive semi-definite; constants are in its null space.
    """
    return _tet_biharmonic_matrix(*as_tet_mesh(V, T))


def _tet_biharmonic_matrix(V, T):
    i = unreferenced_vertex(T, len(V))
    if i is not None:
        # an unreferenced vertex has zero mass, so M⁻¹ does not exist
        raise ValueError(f"V has an unreferenced vertex: V[{i}] is in no tetrahedron of T")
    G, volume = _gradients_and_volumes(V, T)
    L = _assembled_laplacian(G, volume, T, len(V))
    # M⁻¹ L by scaling L's rows (no product with a diagonal matrix)
    scaled = L.copy()
    scaled.data /= np.repeat(_lumped_mass(volume, T, len(V)), np.diff(L.indptr))
    return (L @ scaled).tocsr()


def _as_deformed(U, n):
    U = as_float_array(U, "U", ndim=2)
    if U.shape != (n, 3):
        raise ValueError(f"U must have the shape of V, {(n, 3)}, got {U.shape}")
    return U


def deformation_gradients(V, U, T):
    """Deformation gradient of every tetrahedron.

    Parameters
    ----------
    V : (n, 3) array_like of float
        Rest positions.
    U : (n, 3) array_like of float
        Deformed positions.
    T : (f, 4) array_like of int
        Tetrahedra; none may be flat at rest.

    Returns
    -------
    J : (f, 3, 3) numpy.ndarray
        The linear part of the affine map taking tetrahedron ``t`` at rest to
        its deformed copy: ``J_t [v1 - v0, v2 - v0, v3 - v0] = [u1 - u0, u2 - u0, u3 - u0]``.
    """
    V, T = as_tet_mesh(V, T)
    U = _as_deformed(U, len(V))
    return np.einsum("tka,tkb->tab", U[T], _barycentric_gradients(V, T))


def tet_arap_rotations(V, U, T):
    """The local step: the rotation nearest to every tetrahedron's deformation gradient.

    Parameters
    ----------
    V, U : (n, 3) array_like of float
        Rest and deformed positions.
    T : (f, 4) array_like of int

    Returns
    -------
    R : (f, 3, 3) numpy.ndarray
        ``R_t`` minimizes ``‖J_t - R_t‖_F`` over rotations (``det R_t = +1``):
        ``optimal_rotation(J_tᵀ)``.
    """
    return optimal_rotation(deformation_gradients(V, U, T).transpose(0, 2, 1))


def tet_arap_energy(V, U, T, R):
    """ARAP energy with one rotation per tetrahedron.

    Parameters
    ----------
    V, U : (n, 3) array_like of float
        Rest and deformed positions.
    T : (f, 4) array_like of int
    R : (f, 3, 3) array_like of float
        One matrix per tetrahedron (rotations, but any matrices are accepted).

    Returns
    -------
    float
        ``Σ_t |vol_t| ‖J_t - R_t‖²_F``.
    """
    V, T = as_tet_mesh(V, T)
    J = deformation_gradients(V, U, T)
    R = as_float_array(R, "R", ndim=3)
    if R.shape != J.shape:
        raise ValueError(f"R must have shape {J.shape}, one 3x3 matrix per tetrahedron, got {R.shape}")
    return float(np.abs(tet_volumes_unchecked(V, T)) @ np.sum((J - R) ** 2, axis=(1, 2)))


def tet_arap_precompute(V, T, handles):
    """Everything the tetrahedral ARAP iterations reuse, factorization included.

    Parameters
    ----------
    V : (n, 3) array_like of float
        Rest positions.
    T : (f, 4) array_like of int
        Tetrahedra; none may be flat.
    handles : (h,) array_like of int
        Distinct constrained vertices, at least one in every connected
        component of the mesh.

    Returns
    -------
    data : types.SimpleNamespace
        ``V``, ``T``, ``L`` (``tet_cotangent_laplacian``), ``handles``,
        ``free`` (the other vertices, ascending), ``volumes`` (``|vol_t|``),
        ``gradients`` (``(f, 4, 3)``, ``∇φ`` per corner); ``solver``, the
        sparse LU factors of ``-L[free][:, free]`` (symmetric positive
        definite), or ``None`` when every vertex is a handle;
        ``L_free_handles = L[free][:, handles]``; ``scatter``, ``(n, 4 f)``
        sparse, summing corner rows onto their vertices.
    """
    V, T = as_tet_mesh(V, T)
    n = len(V)
    handles = as_handles(handles, n)
    vertex = component_without(T, n, handles)
    if vertex is not None:
        raise ValueError(
            f"handles must include a vertex of every connected component of the mesh: "
            f"the component of vertex {vertex} has none, so its position is undetermined"
        )
    G, volume = _gradients_and_volumes(V, T)
    L = _assembled_laplacian(G, volume, T, n)
    free = np.setdiff1d(np.arange(n), handles)
    L_free = L[free]
    solver = None
    if free.size:
        solver = spla.splu(
            -L_free[:, free].tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
            options={"SymmetricMode": True},
        )
    scatter = sp.csr_matrix((np.ones(T.size), (T.ravel(), np.arange(T.size))), shape=(n, T.size))
    return types.SimpleNamespace(
        V=V, T=T, L=L, handles=handles, free=free, solver=solver,
        volumes=volume, gradients=G,
        L_free_handles=L_free[:, handles].tocsr(), scatter=scatter,
    )


def _check_data(data):
    if not isinstance(data, types.SimpleNamespace) or not hasattr(data, "gradients"):
        raise ValueError(f"data must be the result of tet_arap_precompute(V, T, handles), got {type(data).__name__}")


def tet_arap_global_step(data, R, handle_positions):
    """The global step: the best positions for given per-tetrahedron rotations.

    Parameters
    ----------
    data : types.SimpleNamespace
        From ``tet_arap_precompute(V, T, handles)``.
    R : (f, 3, 3) array_like of float
        One rotation per tetrahedron.
    handle_positions : (h, 3) array_like of float
        Targets of the handles, in the order of ``handles``.

    Returns
    -------
    U : (n, 3) numpy.ndarray
        Minimizes ``tet_arap_energy(V, U, T, R)`` subject to
        ``U[handles] = handle_positions`` (exactly).
    """
    _check_data(data)
    n, f = len(data.V), len(data.T)
    R = as_float_array(R, "R", ndim=3)
    if R.shape != (f, 3, 3):
        raise ValueError(f"R must have shape ({f}, 3, 3), one rotation per tetrahedron, got {R.shape}")
    handle_positions = as_handle_positions(handle_positions, len(data.handles), 3)
    U = np.empty((n, 3))
    U[data.handles] = handle_positions
    if data.solver is not None:
        # B_i = Σ_{t ∋ i} |vol_t| R_t ∇φ_i: the gradient of Σ_t |vol_t| tr(R_tᵀ J_t(U))
        corners = np.einsum("t,tab,tkb->tka", data.volumes, R, data.gradients).reshape(-1, 3)
        B = data.scatter @ corners
        U[data.free] = data.solver.solve(B[data.free] + data.L_free_handles @ handle_positions)
    return U


def tet_arap_solve(data, handle_positions, U0=None, iterations=10):
    """Tetrahedral ARAP deformation by alternating local and global steps.

    Parameters
    ----------
    data : types.SimpleNamespace
        From ``tet_arap_precompute(V, T, handles)``.
    handle_positions : (h, 3) array_like of float
        Targets of the handles, in the order of ``handles``.
    U0 : (n, 3) array_like of float, optional
        Start; default the rest positions. Its handle rows are replaced by
        ``handle_positions`` before the first local step.
    iterations : int
        Number of local-global iterations, ``>= 0``.

    Returns
    -------
    U : (n, 3) numpy.ndarray
        Positions after the last iteration; ``U[handles] = handle_positions``.
    energies : (iterations,) numpy.ndarray
        ``energies[k] = tet_arap_energy(V, U_k, T, R_k)`` after iteration
        ``k``'s global step with the rotations it used; non-increasing (up to
        rounding).
    """
    _check_data(data)
    n = len(data.V)
    handle_positions = as_handle_positions(handle_positions, len(data.handles), 3)
    if isinstance(iterations, (bool, np.bool_)) or not isinstance(iterations, (int, np.integer)) or iterations < 0:
        raise ValueError(f"iterations must be a non-negative integer, got {iterations!r}")
    if U0 is None:
        U = data.V.copy()
    else:
        U = as_float_array(U0, "U0", ndim=2)
        if U.shape != (n, 3):
            raise ValueError(f"U0 must have the shape of V, {(n, 3)}, got {U.shape}")
    U[data.handles] = handle_positions
    energies = np.empty(int(iterations))
    for k in range(int(iterations)):
        J = np.einsum("tka,tkb->tab", U[data.T], data.gradients)
        R = optimal_rotation(J.transpose(0, 2, 1))
        U = tet_arap_global_step(data, R, handle_positions)
        J = np.einsum("tka,tkb->tab", U[data.T], data.gradients)
        energies[k] = data.volumes @ np.sum((J - R) ** 2, axis=(1, 2))
    return U, energies
