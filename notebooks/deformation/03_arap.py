# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 03 · As-rigid-as-possible deformation
#
# A user grabs a few *handles* of a shape, here the two ends of a bar, and moves
# them. Every other vertex should follow so that the shape looks the same up
# close: locally it may rotate, but it should not stretch, shear or squash.
# As-rigid-as-possible (ARAP) deformation turns that wish into an energy and
# minimizes it by alternating two steps you already know how to take: fitting
# rotations (stage 02) and solving a sparse linear system.
#
# **Notation.** The rest mesh has vertices $v_i \in \mathbb R^d$ ($d = 2$ for planar
# meshes, $d = 3$ for surfaces) and triangles $T$; the deformed mesh has the same
# triangles and vertices $u_i$. The handles are a set $\mathcal H$ of vertices
# with prescribed positions $u_h = \hat u_h$, $h \in \mathcal H$. In code `V` and
# `U` are `(n, d)` arrays, `F` is `(f, 3)`, `handles` is an index array and
# `handle_positions` is `(len(handles), d)`.
#
# **The energy.** Each vertex $i$ owns a *cell*: the triangles around it. The cell
# should move rigidly, by a rotation $R_i \in SO(d)$ of its own. We measure how far
# it is from that with every edge of every triangle of the cell, the "spokes"
# (edges through $i$) and the "rims" (the opposite edges):
#
# $$
# E(u, R) \;=\; \sum_i \; \sum_{T \ni i} \; \sum_{(j,k) \in T} c_{jk}
# \,\bigl\| (u_j - u_k) - R_i (v_j - v_k) \bigr\|^2 .
# $$
#
# ARAP deformation minimizes $E$ over the positions $u$ (with $u_h = \hat u_h$) and
# the rotations $R$ together. Since the rotations are unknowns too, $E$ does not
# care how the shape is oriented: a rigid motion of the whole mesh costs nothing.
#
# This notebook builds the pieces one function at a time: the weights $c_{jk}$,
# the Laplacian, the local step (rotations), the energy, the global step (a linear
# solve) and the loop that alternates them. Run the first cell, then fill in each
# solution cell and run its tests.

# %%
import time

import numpy as np
import scipy.sparse as sp

from starter import load_handles, load_mesh, plotting, shapes

rng = np.random.default_rng(3)

# %% [markdown]
# ## 1 · The best rotation (from stage 02)
#
# The local step of ARAP is the problem of stage 02, once per vertex: given a
# $d \times d$ matrix $S$, find the rotation maximizing $\operatorname{tr}(R S)$.
# With the SVD $S = \tilde U \Sigma \tilde V^\top$ the answer is
#
# $$
# R = \tilde V \, D \, \tilde U^\top, \qquad D = \operatorname{diag}\bigl(1, \dots, 1, \det(\tilde V \tilde U^\top)\bigr),
# $$
#
# i.e. the best orthogonal matrix $\tilde V \tilde U^\top$, with the direction of the
# smallest singular value flipped when that matrix is a reflection. ARAP calls it
# for thousands of vertices per iteration, so make it accept a stack `(k, d, d)`
# and work on the whole stack at once: `np.linalg.svd` and `np.linalg.det` both
# broadcast over leading axes. Bring your solution from stage 02 (it was graded
# there; its tests here only help you check the copy).

# %% deformlab={"solution": "optimal_rotation"}
import numpy as np


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
    ### BEGIN SOLUTION
    # np.linalg.svd and det act on the last two axes, so one code path serves (d, d) and (k, d, d).
    U_tilde, sigma, V_tilde_T = np.linalg.svd(np.asarray(S, dtype=float))
    V_tilde = np.swapaxes(V_tilde_T, -1, -2).copy()
    U_tilde_T = np.swapaxes(U_tilde, -1, -2)
    sign = np.where(np.linalg.det(V_tilde @ U_tilde_T) < 0, -1.0, 1.0)  # -1 where Ṽ Ũᵀ is a reflection
    # Flip the singular vector of the smallest singular value (numpy's last column): the cheapest fix.
    V_tilde[..., -1] *= sign[..., None]
    return V_tilde @ U_tilde_T
    ### END SOLUTION

# %% deformlab={"tests": "optimal_rotation"}
def _rot2(a):
    return np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])


# A reflection would give tr = 6; the best rotation flips the smallest singular direction.
_S = np.diag([1.0, 2.0, -3.0])
_R = optimal_rotation(_S)
assert _R.shape == (3, 3), f"a (3, 3) input must give a (3, 3) rotation, got shape {_R.shape}"
assert np.isclose(np.linalg.det(_R), 1.0), f"det R must be +1 (a rotation), got {np.linalg.det(_R):.6f}"
assert np.isclose(np.trace(_R @ _S), 4.0), (
    f"for S = diag(1, 2, -3) the best rotation gives tr(R S) = 4, got {np.trace(_R @ _S):.6f}"
)

_S = rng.normal(size=(50, 3, 3))
_R = optimal_rotation(_S)
assert _R.shape == (50, 3, 3), f"a (50, 3, 3) stack must give a (50, 3, 3) stack, got shape {_R.shape}"
_err = np.abs(np.transpose(_R, (0, 2, 1)) @ _R - np.eye(3)).max(axis=(1, 2))
assert _err.max() < 1e-10, f"R[{_err.argmax()}] is not orthogonal: max |RᵀR - I| = {_err.max():.2e}"
_det = np.linalg.det(_R)
assert np.allclose(_det, 1.0), f"R[{np.abs(_det - 1).argmax()}] has det {_det[np.abs(_det - 1).argmax()]:.3f}, not +1"
# No other rotation may do better.
_best = np.einsum("kij,kji->k", _R, _S)
for _ in range(20):
    # random rotations: QR of Gaussian matrices, one column flipped where det = -1
    _Q, _ = np.linalg.qr(rng.normal(size=(50, 3, 3)))
    _Q[np.linalg.det(_Q) < 0, :, 0] *= -1
    _other = np.einsum("kij,kji->k", _Q, _S)
    _k = (_other - _best).argmax()
    assert _other[_k] <= _best[_k] + 1e-9, (
        f"for S[{_k}] another rotation gives a larger tr(R S) ({_other[_k]:.4f} > {_best[_k]:.4f}): is R transposed?"
    )

_S = _rot2(0.7) @ np.diag([3.0, 1.0])
assert np.allclose(optimal_rotation(_S), _rot2(-0.7)), "for S = R(0.7)·diag(3, 1) the best rotation is R(-0.7)"

# A singular S (coplanar points): det(S) = 0, yet the best rotation is B for S = diag(3, 0, 2) Bᵀ.
_B = np.array([[0.0, 0.6, 0.8], [1.0, 0.0, 0.0], [0.0, 0.8, -0.6]])  # a rotation
_R = optimal_rotation(np.diag([3.0, 0.0, 2.0]) @ _B.T)
assert np.allclose(_R, _B, atol=1e-10), (
    f"S = diag(3, 0, 2) Bᵀ (B a rotation) is singular and its best rotation is B; got R with det {np.linalg.det(_R):.6f}"
    + (": det(S) = 0 says nothing about the sign; take it from det(Ṽ Ũᵀ)" if abs(np.linalg.det(_R) - 1) > 1e-8 else "")
)

# %% [markdown]
# ## 2 · Cotangent weights
#
# Which weights $c_{jk}$? Take one triangle $T$ and suppose $u$ is linear on it,
# $u(x) = J_T x + t$, so that every edge maps as $u_j - u_k = J_T (v_j - v_k)$.
# We would like the triangle's share of the energy to be the integral
# $\int_T \|J_T - R_i\|_F^2 \, dA = A_T \|J_T - R_i\|_F^2$: then the energy measures
# the deformation of the *surface*, an integral over its area, rather than a sum
# over however many edges the triangulation happens to have. The weights that
# achieve this come from the finite-element Laplacian. The gradient of the linear "hat"
# function $\varphi_k$ of corner $k$ is $\nabla\varphi_k = e_k^\perp / (2A_T)$,
# where $e_k$ is the edge opposite corner $k$ and $\perp$ turns it by 90° inside
# the triangle. For the other two corners $j, k$ with the angle $\alpha_i$ between
# their opposite edges,
#
# $$
# \int_T \nabla\varphi_j \cdot \nabla\varphi_k \, dA
# = \frac{e_j \cdot e_k}{4 A_T}
# = \frac{-\|e_j\|\|e_k\|\cos\alpha_i}{2\,\|e_j\|\|e_k\|\sin\alpha_i}
# = -\tfrac12 \cot\alpha_i ,
# $$
#
# Since the hat functions sum to one, the rows of this matrix sum to zero, and the
# Dirichlet energy of a linear function $g$ on $T$ is
# $\int_T \|\nabla g\|^2 \, dA = \sum_{(j,k) \in T} \tfrac12 \cot\alpha_{jk}\,(g_j - g_k)^2$.
# Applying this to each coordinate of the linear map $x \mapsto (J_T - R_i)\,x$,
# which sends the edge $v_j - v_k$ to $(u_j - u_k) - R_i (v_j - v_k)$, gives exactly
#
# $$
# \sum_{(j,k) \in T} c_{jk} \,\| (u_j - u_k) - R_i (v_j - v_k) \|^2 = A_T \,\|J_T - R_i\|_F^2
# \qquad\text{with}\qquad c_{jk} = \tfrac12 \cot \alpha_{jk},
# $$
#
# where $\alpha_{jk}$ is the angle of $T$ *opposite* the edge $(j, k)$. Note the
# factor ½, and note that the weight belongs to the triangle: an interior edge
# gets one weight from each of its two triangles.
#
# The identity is exact in 2D. On a triangle of a surface in 3D, the edges only
# define what $J_T$ does *within the triangle's plane*, and the left side equals
# $A_T \|(J_T - R_i)\,\Pi_T\|_F^2$ with $\Pi_T$ the orthogonal projection onto
# that plane: what $R_i$ does to the triangle's normal costs nothing.
#
# **Your task.** `cotangent_weights(V, F)` returns the `(f, 3)` array
# `C[t, k]` $= \tfrac12\cot$ of the angle at corner `k` of triangle `t`, the weight
# of the opposite edge `(F[t, (k+1)%3], F[t, (k+2)%3])`. For the corner with edge
# vectors $a, b$ leaving it, $\cot\alpha = \dfrac{a\cdot b}{\|a\times b\|}$ (in 2D,
# $a\times b$ is the scalar $a_x b_y - a_y b_x$; take its absolute value so that
# the orientation of the triangle does not matter). Obtuse angles give negative
# weights; that is expected. Vectorize over all triangles and corners.

# %% deformlab={"solution": "cotangent_weights"}
import numpy as np


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
    ### BEGIN SOLUTION
    V, F = np.asarray(V, dtype=float), np.asarray(F, dtype=np.int64)
    C = np.empty(F.shape)
    for k in range(3):
        # the two edges leaving corner k
        a = V[F[:, (k + 1) % 3]] - V[F[:, k]]
        b = V[F[:, (k + 2) % 3]] - V[F[:, k]]
        cos_part = np.sum(a * b, axis=1)  # |a| |b| cos θ
        if V.shape[1] == 2:
            sin_part = np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])  # |a| |b| sin θ
        else:
            sin_part = np.linalg.norm(np.cross(a, b), axis=1)
        C[:, k] = 0.5 * cos_part / sin_part
    return C
    ### END SOLUTION

# %% deformlab={"tests": "cotangent_weights", "points": 2}
# A right triangle with angles 90°, arctan(1/2), arctan(2): ½cot = 0, 1, 1/4.
_V = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 1.0]])
_F = np.array([[0, 1, 2]])
_C = cotangent_weights(_V, _F)
assert _C.shape == (1, 3), f"C must have one row per triangle and one column per corner, got shape {_C.shape}"
assert np.allclose(_C, [[0.0, 1.0, 0.25]]), (
    f"for the triangle (0,0), (2,0), (0,1) expected C = [[0, 1, 0.25]] (½cot of the angle at "
    f"corners 0, 1, 2), got {np.round(_C, 6).tolist()}"
    + (": that is cot, not ½cot" if np.allclose(_C, [[0.0, 2.0, 0.5]]) else "")
)
assert np.allclose(cotangent_weights(_V, _F[:, ::-1]), _C[:, ::-1]), (
    "a clockwise triangle must get the same weights at the same corners (use |a × b|)"
)
# The same triangle rotated into 3D and scaled: cotangents only see angles.
_Q = np.array([[0.0, 0.6, 0.8], [1.0, 0.0, 0.0], [0.0, 0.8, -0.6]])  # a rotation
_V3 = 5.0 * np.hstack([_V, np.zeros((3, 1))]) @ _Q.T
assert np.allclose(cotangent_weights(_V3, _F), _C), "a rotated, scaled copy of a triangle in 3D must get the same weights"
# An obtuse corner gets a negative weight.
_C = cotangent_weights(np.array([[0.0, 0.0], [1.0, 0.0], [0.5, 0.1]]), _F)
assert _C[0, 2] < 0 < min(_C[0, 0], _C[0, 1]), f"only the obtuse corner 2 should get a negative weight, got {_C.tolist()}"

_V, _F = load_mesh("bar_coarse")
_C = cotangent_weights(_V, _F)
assert _C.shape == (len(_F), 3) and np.isfinite(_C).all(), f"expected finite weights of shape {(len(_F), 3)}"

# %% [markdown]
# ## 3 · The cotangent Laplacian
#
# Collecting the weights per edge gives the (sparse, symmetric) cotangent
# Laplacian: $L_{jk} = \sum_{T \ni (j,k)} c^T_{jk}$ for every edge $(j, k)$, and
# $L_{jj} = -\sum_{k \ne j} L_{jk}$, so every row sums to zero. With this sign
# convention (libigl's), $-L$ is the finite-element stiffness
# matrix of §2: $f^\top(-L)f = \int \|\nabla f\|^2 \ge 0$, and
#
# $$
# (-L u)_j = \sum_k L_{jk}\,(u_j - u_k) = \sum_{T \ni j} \sum_{(j,k) \in T} c^T_{jk}\,(u_j - u_k).
# $$
#
# A good check of your indexing: the Laplacian of a *linear* function $f$ vanishes
# at every interior vertex $j$ of a planar mesh (*linear precision*). Indeed
# $(-Lf)_j = \int \nabla f \cdot \nabla\varphi_j \, dA$, $\nabla f$ is constant, and
# $\int \nabla\varphi_j \, dA = 0$ for a hat function that vanishes on the boundary.
#
# **Your task.** `cotangent_laplacian(V, F)` returns the `(n, n)` sparse matrix.
# Build it from `cotangent_weights` in one go: list the `3f` (row, column, value)
# triples of the edges in both directions, let `scipy.sparse.coo_matrix` (or
# `csr_matrix`) sum the duplicates, then subtract the row sums on the diagonal.

# %% deformlab={"solution": "cotangent_laplacian"}
import numpy as np
import scipy.sparse as sp


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
    ### BEGIN SOLUTION
    F = np.asarray(F, dtype=np.int64)
    n = len(V)
    C = cotangent_weights(V, F)
    # weight C[t, k] belongs to the edge opposite corner k
    i = np.concatenate([F[:, (k + 1) % 3] for k in range(3)])
    j = np.concatenate([F[:, (k + 2) % 3] for k in range(3)])
    c = np.concatenate([C[:, k] for k in range(3)])
    off_diagonal = sp.coo_matrix((c, (i, j)), shape=(n, n))  # repeated (i, j) entries add up
    off_diagonal = (off_diagonal + off_diagonal.T).tocsr()
    return off_diagonal - sp.diags(np.asarray(off_diagonal.sum(axis=1)).ravel())
    ### END SOLUTION

# %% deformlab={"tests": "cotangent_laplacian", "points": 2}
_V = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 1.0]])
_L = cotangent_laplacian(_V, np.array([[0, 1, 2]]))
assert sp.issparse(_L), f"L must be a scipy.sparse matrix, got {type(_L).__name__}"
_expected = np.array([[-1.25, 0.25, 1.0], [0.25, -0.25, 0.0], [1.0, 0.0, -1.0]])
assert np.allclose(_L.toarray(), _expected), (
    f"for the triangle (0,0), (2,0), (0,1) expected L =\n{_expected}\ngot\n{np.round(_L.toarray(), 6)}"
    + ("\nthe diagonal has the wrong sign: L_ii = -Σ_j L_ij, so that every row sums to zero"
       if np.allclose(_L.toarray(), np.abs(_expected)) else "")
)


def _dirichlet(V, F, a):
    """∫ ‖∇f‖² of the linear function f = V a over the mesh: Σ_t area_t ‖a projected onto t's plane‖²."""
    e1, e2 = V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]
    if V.shape[1] == 2:
        return np.sum(0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])) * (a @ a)
    n = np.cross(e1, e2)
    area = 0.5 * np.linalg.norm(n, axis=1)
    return np.sum(area * (a @ a - (n @ a / (2 * area)) ** 2))


_V, _F = load_mesh("character")
_L = sp.csr_matrix(cotangent_laplacian(_V, _F))
assert _L.shape == (len(_V), len(_V)), f"L must be (n, n) = {(len(_V), len(_V))}, got {_L.shape}"
assert abs(_L - _L.T).max() < 1e-12, "L must be symmetric"
_rows = np.abs(np.asarray(_L.sum(axis=1))).ravel()
assert _rows.max() < 1e-10, f"every row of L must sum to 0; row {_rows.argmax()} sums to {_rows.max():.3e}"
# Linear functions are exact: for f = V a, -fᵀ L f is the integral of ‖∇f‖² = ‖a‖² × area.
for _name in ("character", "bar_coarse"):
    _V, _F = load_mesh(_name)
    _L = sp.csr_matrix(cotangent_laplacian(_V, _F))
    for _a in np.eye(_V.shape[1])[:2] + 0.5:
        _f = _V @ _a
        _want, _got = _dirichlet(_V, _F, _a), -_f @ (_L @ _f)
        assert np.isclose(_got, _want, rtol=1e-9), (
            f"{_name}: for the linear function f = V·{_a.tolist()}, -fᵀ L f must be its Dirichlet energy ∫‖∇f‖² = "
            f"{_want:.10g}, got {_got:.10g}: is each weight on the edge opposite its corner?"
        )

# %% [markdown]
# ## 4 · The local step: one rotation per cell
#
# Fix the positions $u$. Then $E$ is a sum of independent terms, one per vertex,
# each depending on its own rotation only. Expand one edge term using
# $\|R_i e\| = \|e\|$ and $e'^\top R_i e = \operatorname{tr}(R_i\, e\, e'^\top)$, where
# $e = v_j - v_k$ and $e' = u_j - u_k$:
#
# $$
# \sum_{T \ni i} \sum_{(j,k) \in T} c_{jk} \|e' - R_i e\|^2
# = \text{const} - 2 \operatorname{tr}(R_i S_i),
# \qquad
# S_i = \sum_{T \ni i} \sum_{(j,k) \in T} c_{jk}\,(v_j - v_k)(u_j - u_k)^\top .
# $$
#
# So the best $R_i$ maximizes $\operatorname{tr}(R_i S_i)$: it is
# `optimal_rotation(S_i)`, one $d \times d$ SVD per vertex. This is stage 01–02's
# shape matching of the cell's rest edges onto its deformed edges, weighted by
# $c_{jk}$.
#
# **Your task.** `arap_covariances(V, U, F, C)` returns the `(n, d, d)` stack of
# the $S_i$, with $e_{tk}$ the rest edge opposite corner $k$ of triangle $t$ and
# $e'_{tk}$ the same edge in `U` (orient them the same way; the sign then cancels).
# Every triangle contributes the *same* matrix $\sum_k C_{tk}\, e_{tk} e'^\top_{tk}$
# to each of its three corners: its spokes for two corners, its rim for the
# third. Compute these `(f, d, d)` triangle matrices with one `np.einsum`, then
# accumulate them at the corners (`np.add.at`, or a sparse `n × f` incidence
# matrix times the matrices flattened to `(f, d²)`).
# `arap_rotations(V, U, F, C)` is then the local step itself.

# %% deformlab={"solution": "arap_covariances"}
import numpy as np
import scipy.sparse as sp


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
    ### BEGIN SOLUTION
    V, U = np.asarray(V, dtype=float), np.asarray(U, dtype=float)
    F, C = np.asarray(F, dtype=np.int64), np.asarray(C, dtype=float)
    d = V.shape[1]
    # One triangle's sum over its three edges, the same for each of its three vertices' cells.
    S_triangle = np.zeros((len(F), d, d))
    for k in range(3):
        a, b = F[:, (k + 1) % 3], F[:, (k + 2) % 3]
        e_rest, e_deformed = V[b] - V[a], U[b] - U[a]
        S_triangle += C[:, k, None, None] * e_rest[:, :, None] * e_deformed[:, None, :]
    # Sum over the triangles around each vertex: a product with the vertex-triangle incidence matrix.
    n, f = len(V), len(F)
    around = sp.csr_matrix((np.ones(3 * f), (F.ravel(), np.repeat(np.arange(f), 3))), shape=(n, f))
    return (around @ S_triangle.reshape(f, d * d)).reshape(n, d, d)
    ### END SOLUTION

# %% deformlab={"tests": "arap_covariances", "points": 2}
# One triangle with hand-made weights: S = 0.1 e0 e0ᵀ + 0.2 e1 e1ᵀ + 0.3 e2 e2ᵀ for
# e0 = v2 - v1 = (-1, 1), e1 = v0 - v2 = (0, -1), e2 = v1 - v0 = (1, 0).
_V = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
_F = np.array([[0, 1, 2]])
_C = np.array([[0.1, 0.2, 0.3]])
_S = arap_covariances(_V, _V, _F, _C)
_expected = np.array([[0.4, -0.1], [-0.1, 0.3]])
assert _S.shape == (3, 2, 2), f"expected one (2, 2) matrix per vertex, shape (3, 2, 2), got {_S.shape}"
for _i in range(3):
    assert np.allclose(_S[_i], _expected), (
        f"vertex {_i}: expected S = {_expected.tolist()} (every corner of a triangle gets all three "
        f"of its edges), got {np.round(_S[_i], 6).tolist()}"
    )

_V, _F = load_mesh("bar_coarse")
_C = cotangent_weights(_V, _F)
_S0 = arap_covariances(_V, _V, _F, _C)
_A = rng.normal(size=(3, 3))
_S = arap_covariances(_V, _V @ _A.T + [1.0, -2.0, 0.5], _F, _C)
assert np.allclose(_S, _S0 @ _A.T), (
    "for U = V Aᵀ + t every deformed edge is A e, so S_i(V, U) = S_i(V, V) Aᵀ; this fails: "
    + ("you computed Σ c e' eᵀ instead of Σ c e e'ᵀ" if np.allclose(_S, _A @ _S0) else "check the edges and weights")
)
# A vertex of two triangles sums both: on a square split along its diagonal (0, 2),
# vertex 0 lies in both triangles, vertices 1 and 3 in one each.
_V = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
_F = np.array([[0, 1, 2], [0, 2, 3]])
_S = arap_covariances(_V, _V + rng.normal(scale=0.1, size=_V.shape), _F, rng.uniform(size=(2, 3)))
assert np.allclose(_S[0], _S[1] + _S[3]) and np.allclose(_S[0], _S[2]), (
    "on two triangles (0,1,2) and (0,2,3), S_0 = S_2 must be the sum of the triangles' matrices, S_1 + S_3"
)

# %% deformlab={"solution": "arap_rotations"}
def arap_rotations(V, U, F, C):
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
    ### BEGIN SOLUTION
    return optimal_rotation(arap_covariances(V, U, F, C))
    ### END SOLUTION

# %% deformlab={"tests": "arap_rotations", "points": 2}
def _random_rotations(k, d):
    # QR of Gaussian matrices, columns flipped to make det = +1
    _q, _r = np.linalg.qr(rng.normal(size=(k, d, d)))
    _q = _q * np.sign(np.diagonal(_r, axis1=1, axis2=2))[:, None, :]
    _q[np.linalg.det(_q) < 0, :, 0] *= -1
    return _q


# A rigid motion is reproduced exactly by every cell.
for _name in ("bar_coarse", "character"):
    _V, _F = load_mesh(_name)
    _d = _V.shape[1]
    _Q = _random_rotations(1, _d)[0]
    _R = arap_rotations(_V, _V @ _Q.T + 0.3, _F, cotangent_weights(_V, _F))
    assert _R.shape == (len(_V), _d, _d), f"{_name}: expected shape {(len(_V), _d, _d)}, got {_R.shape}"
    _err = np.abs(_R - _Q).max(axis=(1, 2))
    assert _err.max() < 1e-8, (
        f"{_name}: U is V rotated by Q, so every R_i must be Q; vertex {_err.argmax()} is off by {_err.max():.2e}"
        + (" (you return Qᵀ: R_i must maximize tr(R S_i))" if np.allclose(_R, _Q.T) else "")
    )

# On a real deformation each R_i beats any other rotation at its own cell.
_V, _F = load_mesh("bar_coarse")
_C = cotangent_weights(_V, _F)
_U = _V + 0.05 * rng.normal(size=_V.shape)
_R = arap_rotations(_V, _U, _F, _C)
_S = arap_covariances(_V, _U, _F, _C)
assert np.allclose(np.linalg.det(_R), 1.0), "every R_i must be a rotation (det +1)"
_best = np.einsum("kij,kji->k", _R, _S)
_other = np.einsum("kij,kji->k", _random_rotations(len(_S), 3), _S)
assert (_other <= _best + 1e-9).all(), f"at vertex {(_other - _best).argmax()} a random rotation gives a larger tr(R S)"

# %% [markdown]
# ## 5 · The energy
#
# To watch the optimization we need $E(u, R)$ itself. Regroup it by triangles: the
# edge opposite corner $k$ of triangle $t$ is measured once for each of the three
# corners $i$ of $t$, against that corner's rotation,
#
# $$
# E = \sum_t \sum_{k=0}^{2} C_{tk} \sum_{i \in t} \|e'_{tk} - R_i\, e_{tk}\|^2 .
# $$
#
# **Your task.** `arap_energy(V, U, F, C, R)` returns this float for given `R`
# (`(n, d, d)`). An array `(f, 3, 3)` indexed by (triangle, corner whose rotation,
# edge) does it in one `einsum`. The energy is zero exactly when every cell moves
# rigidly with its rotation.

# %% deformlab={"solution": "arap_energy"}
import numpy as np


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
    ### BEGIN SOLUTION
    V, U, R = (np.asarray(x, dtype=float) for x in (V, U, R))
    F, C = np.asarray(F, dtype=np.int64), np.asarray(C, dtype=float)
    a, b = F[:, [1, 2, 0]], F[:, [2, 0, 1]]  # (f, 3): the ends of the edge opposite each corner
    e_rest, e_deformed = V[b] - V[a], U[b] - U[a]  # (f, 3, d)
    energy = 0.0
    for corner in range(3):  # every edge belongs to the cells of all three corners of its triangle
        R_i = R[F[:, corner]]  # (f, d, d)
        residual = e_deformed - e_rest @ np.swapaxes(R_i, 1, 2)  # rows (R_i e)ᵀ = eᵀ R_iᵀ
        energy += np.sum(C * np.sum(residual**2, axis=2))
    return float(energy)
    ### END SOLUTION

# %% deformlab={"tests": "arap_energy", "points": 2}
_V = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
_F = np.array([[0, 1, 2]])
_C = np.array([[0.1, 0.2, 0.3]])  # squared edge lengths 2, 1, 1: Σ_k C_k |e_k|² = 0.7
_I = np.tile(np.eye(2), (3, 1, 1))
_E = arap_energy(_V, _V, _F, _C, _I)
assert np.isclose(_E, 0.0), f"the rest pose with R_i = I has zero energy, got {_E}"
_E = arap_energy(_V, 2 * _V, _F, _C, _I)
assert np.isclose(_E, 2.1), (
    f"scaling the triangle by 2 with R_i = I: each of the 3 corners sees |2e - e|² per edge, "
    f"E = 3 · 0.7 = 2.1, got {_E}" + (" (did you count each edge for one corner only?)" if np.isclose(_E, 0.7) else "")
    + (": that is 3 Σ |e|², without the weights; weight each edge's term by its C[t, k]" if np.isclose(_E, 12.0) else "")
)
_R = _I.copy()
_R[0] = [[0.0, -1.0], [1.0, 0.0]]
_E = arap_energy(_V, _V, _F, _C, _R)
assert np.isclose(_E, 1.4), (
    f"with U = V and vertex 0's cell rotated by 90°, only vertex 0's terms count, each |e - R e|² = 2|e|²: "
    f"E = 2 · 0.7 = 1.4, got {_E}"
)

_V, _F = load_mesh("bar_coarse")
_C = cotangent_weights(_V, _F)
_Q = np.array([[0.0, 0.6, 0.8], [1.0, 0.0, 0.0], [0.0, 0.8, -0.6]])  # a rotation
_E = arap_energy(_V, _V @ _Q.T + 1.0, _F, _C, np.tile(_Q, (len(_V), 1, 1)))
assert abs(_E) < 1e-9, f"a rigid motion with every R_i equal to its rotation has zero energy, got {_E:.3e}"
_E = arap_energy(_V, _V @ _Q.T, _F, _C, np.tile(np.eye(3), (len(_V), 1, 1)))
assert _E > 1.0, f"the bar turned by Q but measured against R_i = I must have a large energy, got {_E:.3e}"

# %% [markdown]
# ## 6 · The global step: one Laplacian solve
#
# Now fix the rotations. $E$ is a quadratic function of $u$, so its minimum is a
# linear solve. Since the edge opposite corner $k$ of triangle $t$ is measured
# against the three corner rotations, and
# $\sum_{i \in t}\|x - y_i\|^2 = 3\|x - \bar y\|^2 + \text{const}$ for the mean
# $\bar y$, only the triangle's mean rotation
# $\bar R_t = \tfrac13 \sum_{i \in t} R_i$ matters for $u$:
#
# $$
# E = 3 \sum_t \sum_{(a,b) \in t} c^t_{ab} \,\bigl\|(u_a - u_b) - \bar R_t (v_a - v_b)\bigr\|^2 + \text{const}.
# $$
#
# Setting the gradient with respect to a free vertex $u_a$ to zero, the first
# part is $(-L u)_a$ from §3:
#
# $$
# -L\,U = B, \qquad
# B_a = \sum_{t \ni a} \sum_{(a,b) \in t} c^t_{ab} \,\bar R_t\,(v_a - v_b)
# $$
#
# (rows of the `(n, d)` arrays $U$ and $B$; all $d$ coordinates share the matrix).
# The handles are not free: split the vertices into free ones $f$ and handles
# $h$, move the known columns to the right, and solve only for the free rows:
#
# $$
# (-L)_{ff}\, U_f = B_f + L_{fh}\, \hat U_h .
# $$
#
# $-L$ is the stiffness matrix of §2: symmetric positive semi-definite, with the
# constants as its null space. Once a handle pins every connected piece,
# $(-L)_{ff}$ is positive definite. **It depends neither on $R$ nor on the handle
# positions**, so it can be factorized once (`scipy.sparse.linalg.splu`, or
# `scipy.sparse.linalg.factorized`, on a CSC matrix) and every iteration, and
# every frame of an interactive session, costs only a back-substitution.
#
# **Your tasks.**
# `arap_precompute(V, F, handles)` returns an object of your design (a `dict` or
# `types.SimpleNamespace` works well) holding everything the iterations need:
# the rest mesh, `C`, `L`, the handle and free indices, and the factorization.
# `arap_global_step(data, R, handle_positions)` assembles $B$ for the given
# rotations (vectorized over triangles, like the energy), solves, and returns the
# full `(n, d)` array `U` with `U[handles] = handle_positions`.

# %% deformlab={"solution": "arap_precompute"}
import types

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


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
    ### BEGIN SOLUTION
    V, F = np.array(V, dtype=float), np.array(F, dtype=np.int64)  # copies: later edits cannot reach the caller
    handles = np.array(handles, dtype=np.int64).reshape(-1)
    if handles.size == 0 or handles.min() < 0 or handles.max() >= len(V) or len(np.unique(handles)) != handles.size:
        raise ValueError(f"handles must be distinct vertex indices in range({len(V)}), at least one; got {handles.tolist()}")
    free = np.setdiff1d(np.arange(len(V)), handles)
    C = cotangent_weights(V, F)
    K = -cotangent_laplacian(V, F).tocsr()  # the stiffness matrix -L
    # The 3f edges (a, b), opposite corners 0, 1, 2 of every triangle, and the signed incidence
    # matrix that adds a per-edge vector to B at a and subtracts it at b.
    a, b = F[:, [1, 2, 0]].ravel(), F[:, [2, 0, 1]].ravel()
    edge = np.arange(len(a))
    D = sp.csr_matrix((np.r_[np.ones(len(a)), -np.ones(len(a))], (np.r_[a, b], np.r_[edge, edge])), shape=(len(V), len(a)))
    return types.SimpleNamespace(
        V=V, F=F, C=C, handles=handles, free=free, a=a, b=b, D=D,
        K_fh=K[free][:, handles],
        # (-L)_ff is the same for every rotation and every handle position: factorize it once.
        K_ff=spla.splu(K[free][:, free].tocsc()),
    )
    ### END SOLUTION

# %% deformlab={"tests": "arap_precompute", "points": 2}
_V, _F = load_mesh("bar_coarse")
_ends = load_handles("bar_coarse")
_h = np.concatenate([_ends["left"], _ends["right"]])
_copies = (_V.copy(), _F.copy(), _h.copy())
_data = arap_precompute(_V, _F, _h)
assert all(np.array_equal(_a, _b) for _a, _b in zip((_V, _F, _h), _copies)), "arap_precompute must not modify V, F or handles"
for _bad, _why in (
    ([0, 0], "repeated: the caller's mistake; dropping repeats with np.unique would also sort the handles, "
             "and handle_positions would go to the wrong vertices"),
    ([len(_V)], "out of range"),
    ([], "empty"),
):
    try:
        arap_precompute(_V, _F, np.array(_bad, dtype=np.int64))
    except ValueError:
        pass
    except Exception as _exc:  # noqa: BLE001 - any other error is not the one asked for
        raise AssertionError(f"handles {_bad} ({_why}) must raise ValueError, got {type(_exc).__name__}: {_exc}") from None
    else:
        raise AssertionError(f"handles {_bad} ({_why}) must raise ValueError")

# %% deformlab={"solution": "arap_global_step"}
import numpy as np


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
    ### BEGIN SOLUTION
    V, a, b = data.V, data.a, data.b
    # Only a triangle's mean rotation R̄_t = (R_a + R_b + R_c) / 3 matters for the positions.
    R_mean = np.asarray(R, dtype=float)[data.F].mean(axis=1)
    # c R̄_t (v_a - v_b) for every edge (a, b) of every triangle t, in the edge order of data.a, data.b
    pull = data.C.ravel()[:, None] * np.einsum("tij,tj->ti", np.repeat(R_mean, 3, axis=0), V[a] - V[b])
    B = data.D @ pull  # B_a gets +pull, B_b gets -pull
    U = np.empty_like(V)
    U[data.handles] = handle_positions
    U[data.free] = data.K_ff.solve(B[data.free] - data.K_fh @ U[data.handles])
    return U
    ### END SOLUTION

# %% deformlab={"tests": "arap_global_step", "points": 3}
_V, _F = load_mesh("bar_coarse")
_ends = load_handles("bar_coarse")
_h = np.concatenate([_ends["left"], _ends["right"]])
_C = cotangent_weights(_V, _F)
_data = arap_precompute(_V, _F, _h)
_n = len(_V)

_U = arap_global_step(_data, np.tile(np.eye(3), (_n, 1, 1)), _V[_h])
assert _U.shape == _V.shape, f"U must have the shape of V, {_V.shape}, got {_U.shape}"
_err = np.linalg.norm(_U - _V, axis=1)
assert _err.max() < 1e-8, f"with R_i = I and the handles at rest the answer is V; vertex {_err.argmax()} is off by {_err.max():.2e}"

_Q = np.array([[0.0, 0.6, 0.8], [1.0, 0.0, 0.0], [0.0, 0.8, -0.6]])  # a rotation
_t = np.array([0.5, -1.0, 2.0])
_U = arap_global_step(_data, np.tile(_Q, (_n, 1, 1)), _V[_h] @ _Q.T + _t)
_err = np.linalg.norm(_U - (_V @ _Q.T + _t), axis=1)
assert _err.max() < 1e-8, f"with every R_i = Q and the handles moved rigidly by Q, U must be V moved rigidly; vertex {_err.argmax()} is off by {_err.max():.2e}"

# Rotations from a real deformation and handles somewhere new.
_R = arap_rotations(_V, _V + 0.1 * rng.normal(size=_V.shape), _F, _C)
_target = _V[_h] + 0.2 * rng.normal(size=(len(_h), 3))
_U = arap_global_step(_data, _R, _target)
assert np.array_equal(_U[_h], _target), "U[handles] must equal handle_positions exactly"
# E is quadratic in U, so at its constrained minimum E(U + D) = E(U - D) for any D that keeps the handles.
_E = arap_energy(_V, _U, _F, _C, _R)
for _ in range(3):
    _D = 0.01 * rng.normal(size=_V.shape)
    _D[_h] = 0.0
    _plus, _minus = arap_energy(_V, _U + _D, _F, _C, _R), arap_energy(_V, _U - _D, _F, _C, _R)
    assert min(_plus, _minus) >= _E - 1e-9 * _E and abs(_plus - _minus) <= 1e-7 * (_plus + _minus), (
        f"U does not minimize the energy for the given rotations: moving the free vertices by ±D "
        f"gives {_minus:.8g} and {_plus:.8g} against {_E:.8g} (check B: the mean rotation of each triangle, "
        f"½cot weights, and the handle columns moved to the right-hand side)"
    )

# %% [markdown]
# ## 7 · Alternating the two steps
#
# ARAP deformation alternates: rotations for the current positions (local), then
# positions for those rotations (global). Write $u^k$ for the positions after
# iteration $k$ and $R^{k+1}$ for the rotations fitted to them. **Neither step
# can increase the energy**, because each is an *exact* minimization over its
# own variables with the other ones held fixed, and the old values are among the
# candidates:
#
# $$
# E(u^{k+1}, R^{k+1}) \;\le\; E(u^k, R^{k+1}) \;\le\; E(u^k, R^k).
# $$
#
# The first inequality is the global step (it minimizes over $u$ and $u^k$
# satisfies the handle constraints), the second the local step (it minimizes
# over $R$). The energy is bounded below by zero, so the sequence of energies
# converges. It converges to a *local* minimum in general: $E$ is not convex in
# $(u, R)$ together, and the answer depends on where we start.
#
# **Your task.** `arap_solve(data, handle_positions, U0=None, iterations=10)`:
# start from `U0` (the rest pose `V` if `None`) with its handle rows replaced by
# `handle_positions`, so that the first local step already sees the handles where
# they belong; then run `iterations` local–global iterations and return the final
# `U` and the list of energies, `energies[k]` being `arap_energy` after iteration
# `k`'s global step **with the rotations that step used** (the middle term above
# for the next iteration would be lower and would hide a bug in the global step).
# On the ~2.5k-vertex bar, ten iterations should take well under a second.

# %% deformlab={"solution": "arap_solve"}
import numpy as np


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
    ### BEGIN SOLUTION
    U = np.array(data.V if U0 is None else U0, dtype=float)  # a copy: U0 is not modified
    U[data.handles] = handle_positions
    energies = []
    for _ in range(iterations):
        R = arap_rotations(data.V, U, data.F, data.C)  # local step
        U = arap_global_step(data, R, handle_positions)  # global step
        energies.append(arap_energy(data.V, U, data.F, data.C, R))
    return U, np.array(energies)
    ### END SOLUTION

# %% deformlab={"tests": "arap_solve", "points": 3}
_V, _F = load_mesh("bar_coarse")
_ends = load_handles("bar_coarse")
_h = np.concatenate([_ends["left"], _ends["right"]])
_C = cotangent_weights(_V, _F)
_data = arap_precompute(_V, _F, _h)
# Twist the right end by 60° about the x-axis through its centroid.
_c = _V[_ends["right"]].mean(axis=0)
_a = np.pi / 3
_Rx = np.array([[1, 0, 0], [0, np.cos(_a), -np.sin(_a)], [0, np.sin(_a), np.cos(_a)]])
_target = np.vstack([_V[_ends["left"]], (_V[_ends["right"]] - _c) @ _Rx.T + _c])

_U, _energies = arap_solve(_data, _target, iterations=6)
assert len(_energies) == 6, f"iterations=6 must give 6 energies, got {len(_energies)}"
assert np.array_equal(_U[_h], _target), "the handles must end exactly at handle_positions"
_rise = np.diff(_energies)
assert (_rise <= 1e-9 * _energies[0]).all(), (
    f"the energy increased from iteration {_rise.argmax()} to {_rise.argmax() + 1} by {_rise.max():.3e}: "
    "one of the steps does not minimize over its variables"
)
_U_rest, _ = arap_solve(_data, _target, U0=_V, iterations=6)
assert np.allclose(_U, _U_rest), "U0=None must start from the rest pose V"

# The start's handle rows are replaced before the first local step.
_U0 = _V + 0.05 * rng.normal(size=_V.shape)
_U0_fixed = _U0.copy()
_U0_fixed[_h] = _target
_U1, _E1 = arap_solve(_data, _target, U0=_U0, iterations=1)
assert np.allclose(_U1, arap_solve(_data, _target, U0=_U0_fixed, iterations=1)[0]), (
    "replace the handle rows of U0 by handle_positions before the first local step"
)
# energies[0] uses the rotations fitted to the start, not to the result.
_R_used = arap_rotations(_V, _U0_fixed, _F, _C)
_expected = arap_energy(_V, _U1, _F, _C, _R_used)
_refit = arap_energy(_V, _U1, _F, _C, arap_rotations(_V, _U1, _F, _C))
assert np.isclose(_E1[0], _expected, rtol=1e-9), (
    f"energies[0] must be the energy of the new U with the rotations the global step used, {_expected:.8g}; "
    f"got {_E1[0]:.8g}" + (" (you refitted the rotations to the new U)" if np.isclose(_E1[0], _refit, rtol=1e-9) else "")
)
_U2, _ = arap_solve(_data, _target, U0=_U0, iterations=2)
assert np.allclose(_U2, arap_solve(_data, _target, U0=_U1, iterations=1)[0]), (
    "two iterations must equal one iteration started from the result of the first"
)

# %% [markdown]
# ## 8 · A twisted and a bent bar
#
# Time to use it. The bar's two end caps are the handles: the left one stays, the
# right one is twisted by 90° about the bar's axis, or bent so that the bar
# becomes a quarter circle (the end turns by 90° and moves to where a bent bar of
# the same length would put it). As in an interactive session, the handle turns
# gradually, in frames of 15°, and each frame's solve starts from the previous
# frame's result (§9 shows why). The factorization is computed once for all
# frames. The handles are marked in red.

# %%
V, F = load_mesh("bar")
ends = load_handles("bar")
left, right = ends["left"], ends["right"]
handles = np.concatenate([left, right])


def rotation(axis, angle):
    """Rotation matrix by ``angle`` (radians) about the 3D vector ``axis`` (Rodrigues)."""
    a = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    K = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
    return np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * K @ K


# The bar's axis runs from the left cap's centroid to the right cap's; the
# bending direction is the coordinate axis most perpendicular to it.
x_axis = V[right].mean(axis=0) - V[left].mean(axis=0)
x_axis /= np.linalg.norm(x_axis)
y_axis = np.eye(3)[np.argmin(np.abs(x_axis))]
y_axis = y_axis - (y_axis @ x_axis) * x_axis
y_axis /= np.linalg.norm(y_axis)


def twist(V, left, right, angle):
    """Handle positions: the left cap at rest, the right cap turned by ``angle`` about the bar's axis."""
    center = V[right].mean(axis=0)
    return np.vstack([V[left], (V[right] - center) @ rotation(x_axis, angle).T + center])


def bend(V, left, right, angle):
    """Handle positions bending the bar into a circular arc that turns by ``angle``."""
    start, end = V[left].mean(axis=0), V[right].mean(axis=0)
    radius = np.linalg.norm(end - start) / angle
    end = start + radius * np.sin(angle) * x_axis + radius * (1.0 - np.cos(angle)) * y_axis
    turned = (V[right] - V[right].mean(axis=0)) @ rotation(np.cross(x_axis, y_axis), angle).T + end
    return np.vstack([V[left], turned])


def animate(data, V, motion, degrees, iterations):
    """Solve frame by frame, each frame starting from the previous one; returns the last U."""
    U = None
    for angle in np.radians(degrees):
        U, _ = arap_solve(data, motion(V, left, right, angle), U0=U, iterations=iterations)
    return U


start = time.perf_counter()
data = arap_precompute(V, F, handles)
print(f"bar: {len(V)} vertices; arap_precompute {time.perf_counter() - start:.3f} s")
start = time.perf_counter()
arap_solve(data, twist(V, left, right, np.pi / 2), iterations=10)
print(f"arap_solve, 10 iterations: {time.perf_counter() - start:.3f} s")

U_twist = animate(data, V, twist, range(15, 91, 15), iterations=10)
U_bend = animate(data, V, bend, range(15, 91, 15), iterations=10)
plotting.show_meshes([(V, F), (U_twist, F), (U_bend, F)], titles=["rest", "twisted by 90°", "bent by 90°"])

# %% [markdown]
# ## 9 · Laplacian editing and the initial guess
#
# The global step with every $R_i = I$ is the classic *Laplacian editing*: it
# keeps the Laplacian coordinates $L v$ of the rest shape as well as it can
# while the handles move, $-L_{ff} U_f = -(L V)_f + L_{fh}\hat U_h$. It is a single
# linear solve and it spreads the handles' motion smoothly, but it cannot rotate
# the local details: a twisted or bent bar comes out sheared and squashed.
#
# **Your task.** `laplacian_editing(V, F, handles, handle_positions)` returns
# that `U` (use your functions from above).

# %% deformlab={"solution": "laplacian_editing"}
import numpy as np


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
    ### BEGIN SOLUTION
    V = np.asarray(V, dtype=float)
    identities = np.tile(np.eye(V.shape[1]), (len(V), 1, 1))
    return arap_global_step(arap_precompute(V, F, handles), identities, handle_positions)
    ### END SOLUTION

# %% deformlab={"tests": "laplacian_editing", "points": 2}
_V, _F = load_mesh("bar_coarse")
_ends = load_handles("bar_coarse")
_h = np.concatenate([_ends["left"], _ends["right"]])
_target = _V[_h] + 0.3 * rng.normal(size=(len(_h), 3))
_U = laplacian_editing(_V, _F, _h, _target)
assert np.array_equal(_U[_h], _target), "U[handles] must equal handle_positions exactly"
# The global step with every R_i = I: U minimizes arap_energy with identity rotations, so E(U + D) = E(U - D)
# for any D that keeps the handles.
_C, _I = cotangent_weights(_V, _F), np.tile(np.eye(3), (len(_V), 1, 1))
_E = arap_energy(_V, _U, _F, _C, _I)
for _ in range(3):
    _D = 0.01 * rng.normal(size=_V.shape)
    _D[_h] = 0.0
    _plus, _minus = arap_energy(_V, _U + _D, _F, _C, _I), arap_energy(_V, _U - _D, _F, _C, _I)
    assert min(_plus, _minus) >= _E - 1e-9 * _E and abs(_plus - _minus) <= 1e-7 * (_plus + _minus), (
        f"Laplacian editing is the global step with every R_i = I, but U does not minimize that energy: moving the "
        f"free vertices by ±D gives {_minus:.8g} and {_plus:.8g} against {_E:.8g} (the same cotangent Laplacian as "
        "the global step, not the uniform graph Laplacian)"
    )
_t = np.array([1.0, 2.0, -3.0])
assert np.allclose(laplacian_editing(_V, _F, _h, _V[_h] + _t), _V + _t), "translating every handle by t must translate the mesh by t"

# %% [markdown]
# **Predict first.** Below, the bar is twisted by 90° with Laplacian editing, and
# then ARAP runs 1, 2 and 4 iterations starting from that guess. Before you run
# the cell, write down: is the middle cross-section of the Laplacian-editing bar
# larger or smaller than at rest, by roughly how much, and after how many
# iterations do you expect it back within 2 % of its rest size?

# %%
def section_size(U):
    """RMS distance of the bar's middle ring of vertices from its centre, relative to the rest pose."""
    ring = np.abs((V - V[handles].mean(axis=0)) @ x_axis) < 1e-9
    size = lambda X: np.sqrt(np.mean(np.sum((X[ring] - X[ring].mean(axis=0)) ** 2, axis=1)))
    return size(U) / size(V)


target = twist(V, left, right, np.pi / 2)
U_guess = laplacian_editing(V, F, handles, target)
stages = [("Laplacian editing", U_guess)]
for iterations in (1, 2, 4):
    U_k, energies = arap_solve(data, target, U0=U_guess, iterations=iterations)
    stages.append((f"{iterations} iteration{'s' * (iterations > 1)}", U_k))
for label, U_k in stages:
    print(f"{label:18s} middle cross-section × {section_size(U_k):.3f}")
plotting.show_meshes([(U_k, F) for _, U_k in stages], titles=[label for label, _ in stages])

# %% [markdown]
# ARAP finds a local minimum, and how many iterations it needs depends on where
# it starts. Three initial guesses:
#
# * the **rest pose** (with the handle rows moved): the whole handle motion sits
#   in the triangles next to the moved cap, and the rotations must spread from
#   there along the bar;
# * **Laplacian editing**: the translation is spread smoothly, but with every
#   $R_i = I$ the cells are sheared rather than turned;
# * the **previous frame**: in an interactive session or an animation the handles
#   move a little per frame, and the last solution, rotations included, is
#   nearly right. Here it is the 80° pose, itself solved frame by frame.
#
# To keep this quick we use the coarse bar, and count the iterations until the
# energy is within 2 % of the lowest energy any of the runs reaches.

# %%
Vc, Fc = load_mesh("bar_coarse")
ends_c = load_handles("bar_coarse")
left_c, right_c = ends_c["left"], ends_c["right"]
handles_c = np.concatenate([left_c, right_c])
data_c = arap_precompute(Vc, Fc, handles_c)

curves = {}
for motion in (twist, bend):
    target = motion(Vc, left_c, right_c, np.pi / 2)
    previous = None
    for angle in np.radians(range(20, 81, 20)):
        previous, _ = arap_solve(data_c, motion(Vc, left_c, right_c, angle), U0=previous, iterations=10)
    guesses = {
        "rest pose": None,
        "Laplacian editing": laplacian_editing(Vc, Fc, handles_c, target),
        "previous frame (80°)": previous,
    }
    runs = {label: np.asarray(arap_solve(data_c, target, U0=U0, iterations=40)[1]) for label, U0 in guesses.items()}
    lowest = min(energies.min() for energies in runs.values())
    print(f"{motion.__name__} by 90°, lowest energy {lowest:.4g}")
    for label, energies in runs.items():
        count = np.argmax(energies <= 1.02 * lowest) + 1 if (energies <= 1.02 * lowest).any() else "> 40"
        print(f"    {label:21s} energy after one iteration {energies[0]:7.4g}, within 2 % after {count} iterations")
    if motion is twist:
        curves = runs
plotting.show_energy(curves, title="ARAP energy of the coarse bar twisted by 90°")

# %% [markdown]
# The previous frame wins by far: its rotations already point the right way.
# Laplacian editing starts much lower than the rest pose, since the handle's
# motion is already spread along the bar, yet it saves only a few iterations:
# its cells are sheared, not turned, and finding the rotations is what takes
# the iterations.
#
# ## 10 · Large rotations: one step or several
#
# A handle turned by 180° is at the same place as one turned by −180°: positions
# do not say which way it went. Asked for in a single step from the rest pose,
# the right cap is flipped across the axis at once, the first local steps see
# cells sheared through the middle of the bar, and the iteration has to break the
# tie by itself. Reached in steps of 30°, each solve starts from the previous
# frame, which already turns the intended way. We measure the middle cross-section
# of the result: how far it turned (fitting a 2D rotation with
# `optimal_rotation`, as in stage 02) and how much it shrank.

# %%
def middle_section(U):
    """Turn (degrees) and relative size of the cross-section half way along the coarse bar."""
    middle = np.abs((Vc - Vc[handles_c].mean(axis=0)) @ x_axis) < 1e-9
    in_plane = np.stack([y_axis, np.cross(x_axis, y_axis)], axis=1)  # (3, 2) basis of the cross-section
    P = (Vc[middle] - Vc[middle].mean(axis=0)) @ in_plane
    Q = (U[middle] - U[middle].mean(axis=0)) @ in_plane
    R = optimal_rotation(P.T @ Q)
    size = np.linalg.norm(Q, axis=1).mean() / np.linalg.norm(P, axis=1).mean()
    return np.degrees(np.arctan2(R[1, 0], R[0, 0])), size


one_step, E_one = arap_solve(data_c, twist(Vc, left_c, right_c, np.pi), iterations=200)
frame = None
for angle in np.radians(range(30, 181, 30)):
    frame, E_steps = arap_solve(data_c, twist(Vc, left_c, right_c, angle), U0=frame, iterations=20)
for label, U, energies in (("one step, 200 iterations", one_step, E_one), ("six steps of 30°, 20 iterations each", frame, E_steps)):
    turn, size = middle_section(U)
    print(f"180° twist in {label:38s}: energy {energies[-1]:.3g}; middle section turned {turn:+5.0f}°, size × {size:.2f}")
plotting.show_meshes([(one_step, Fc), (frame, Fc)], titles=["180° in one step", "180° in six steps"])

# %% [markdown]
# In six steps the middle turns the intended way, on its way to +90°, half the
# twist, as a twisted bar should (more iterations on the last frame get it
# there). In one step, nothing
# tells the solver which way to turn: the problem is symmetric under turning
# either way, so the middle hardly turns at all and pinches to about half its
# size instead, much like the candy wrapper of stage 05. This is a different
# local minimum, and its energy is even *lower*: the energy only sees the
# surface, and nothing in it protects the volume inside the bar, so pinching the
# neck is cheaper than twisting it. A lower energy is not a better answer to
# what the user asked. Large rotations must be reached in steps, each starting
# from the last.
#
# ## 11 · Coarse and fine meshes
#
# Finally, the same 90° twist on the coarse bar and on the bar (almost six times
# as many vertices), both from the rest pose.

# %%
curves = {}
for name, Vm, data_m in (("bar_coarse", Vc, data_c), ("bar", V, data)):
    ends_m = load_handles(name)
    _, energies = arap_solve(data_m, twist(Vm, ends_m["left"], ends_m["right"], np.pi / 2), iterations=60)
    print(f"{name:10s} {len(Vm):5d} vertices: energy after 10, 30, 60 iterations "
          f"{energies[9]:.3g}, {energies[29]:.3g}, {energies[59]:.3g}")
    curves[f"{name} ({len(Vm)} vertices)"] = energies
plotting.show_energy(curves, title="ARAP energy, 90° twist, from the rest pose")

# %% [markdown]
# Two differences. The fine bar needs many more iterations: a local step only
# sees one cell, so the rotation has to spread from the twisted cap along the bar
# through the alternation, and a finer mesh has more cells for it to cross. And
# the fine bar ends at a clearly *lower* energy: the same twist is cheaper on it,
# so the fine bar is softer than the coarse one.
#
# **Question.** Why does the stiffness of ARAP depend on the size of the cells?
# The ½cot weights were chosen so that in-plane deformations cost the same on
# every mesh; what resists the twist of this (hollow) bar, and how does that
# cost change when the cells get smaller?

# %% [markdown] deformlab={"answer": "arap_cell_size", "points": 2}
# Twisting the hollow bar warps its flat sides (a twisted strip becomes a saddle
# surface): mostly bending, with little stretching. For the in-plane part the
# ½cot weights make the energy approximate an integral (area × ‖J − R‖²) that
# does not depend on the mesh. Bending, however, is only penalized because each
# cell must follow a single rotation: on a bent surface the triangles of a cell
# (its spokes and rims) lie in different tangent planes and one rotation cannot
# fit them all. That misfit grows with the size of the cell relative to the
# change of the normal across it, so the cost of a given bend shrinks as the
# cells get smaller (here the energy of the same twist drops from about 1.1 to
# 0.7 from bar_coarse to bar). ARAP on surfaces is therefore not
# resolution-independent: coarse meshes are stiffer against bending and
# twisting, fine meshes softer; the rotation field can vary faster on a finer
# mesh.

# %% [markdown]
# ## 12 · Why the local step must return rotations
#
# **Predict first.** The 2D character's hands swap places (the head and the feet
# stay). The cell below solves this twice, with your `arap_rotations` and with
# the best *orthogonal* matrix of stage 01 in the local step (no sign
# correction), and counts the triangles that end up inside out. Before you run
# it: how many of the character's triangles do you expect flipped in each case,
# and which of the two solves reaches the *lower* energy?

# %%
V2, F2 = load_mesh("character")
points2 = np.array(load_handles("character")["points"])  # head top, left hand, right hand, left foot, right foot
target2 = V2[points2].copy()
target2[[1, 2]] = V2[points2[[2, 1]]]  # the hands swap places
C2 = cotangent_weights(V2, F2)
data2 = arap_precompute(V2, F2, points2)


def signed_areas(U):
    a, b, c = U[F2[:, 0]], U[F2[:, 1]], U[F2[:, 2]]
    return (b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]


def best_orthogonal(S):
    """Stage 01's Ṽ Ũᵀ for a stack of S: possibly reflections."""
    U_tilde, _, V_tilde_T = np.linalg.svd(S)
    return np.swapaxes(V_tilde_T, -1, -2) @ np.swapaxes(U_tilde, -1, -2)


local_steps = {
    "best orthogonal (no sign correction)": lambda U: best_orthogonal(arap_covariances(V2, U, F2, C2)),
    "best rotation (arap_rotations)": lambda U: arap_rotations(V2, U, F2, C2),
}
results = []
for label, local_step in local_steps.items():
    U = V2.copy()
    U[points2] = target2
    for _ in range(30):
        R = local_step(U)
        U = arap_global_step(data2, R, target2)
    flipped = np.sign(signed_areas(U)) != np.sign(signed_areas(V2))
    print(f"{label:37s}: {flipped.sum():4d} of {len(F2)} triangles flipped, "
          f"{np.sum(np.linalg.det(R) < 0):4d} reflections among the R_i, energy {arap_energy(V2, U, F2, C2, R):.4f}")
    results.append((U, F2, flipped.astype(float)))
plotting.show_meshes(results, titles=list(local_steps))

# %% [markdown]
# **Question.** Without the sign correction the energy comes out *lower*, yet the
# result is worse. Explain both observations: why can reflections lower this
# energy, and why do the flipped triangles follow from them? Then say what the
# monotone decrease of the energies (§7) does and does not guarantee here.

# %% [markdown] deformlab={"answer": "arap_monotone", "points": 2}
# The energy only compares each cell's deformed edges with its rest edges moved
# by R_i; it does not care whether R_i is a rotation. With the hands swapped,
# the arms must cross, and mirroring a cell (a reflection) fits such edges
# better than turning it, so allowing reflections enlarges the set the local
# step optimizes over and the minimum is lower. But a cell asked to be the
# mirror image of its rest shape is inside out: the global step then places its
# triangles with reversed orientation, hundreds of flipped triangles, while with
# rotations only a few triangles near the crossing flip. Monotonicity (each step
# minimizes exactly over its own unknowns, so E never goes up and converges)
# holds in both runs: it guarantees a non-increasing energy and convergence, not
# a good shape, not the global minimum (E is not convex in (u, R) jointly), and
# nothing about which energy is the meaningful one: minimizing over the wrong
# set (orthogonal instead of rotations) converges just as monotonically to a
# wrong answer.
