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
# # 07 · Tetrahedra: finite elements and ARAP on a volume
#
# *Workload: about 5.9 hours for 9 graded functions (22 bonus points) and 3 written answers (an estimate for a student who attended the lecture).*
#
# Every mesh so far was a surface: a 2D region cut into triangles, or the skin of
# a 3D shape. The lecture mentions volumes once, on the BBW slides: the weights'
# energy is discretized with finite elements, "2D → triangle mesh, 3D → tet
# mesh". This notebook works that remark out, for the Laplacian and the
# biharmonic energy the weights need, and carries ARAP over to tetrahedra too
# (the ARAP slides themselves only show surfaces). Two things go wrong on a skin
# alone, and you have seen both:
#
# * ARAP on a surface keeps the skin's edges, not the volume inside: in stage 05
#   the surface ARAP elbow folded, and a strongly twisted bar caves its walls in
#   (nothing in the energy sees the inside);
# * weights computed on a skin do not know which points are close *through the
#   body*.
#
# A **tetrahedral mesh** fills the volume: `V` `(n, 3)` vertices (on the skin and
# inside) and `T` `(f, 4)` tetrahedra. The course has two, made by
# `data/make_meshes.py` from grid cubes, each split into 6 tetrahedra: the
# volumetric bar `bar_tet` and a blocky hand `hand_tet` with six bones (libigl's
# tutorial 403 does bounded biharmonic weights on a tetrahedral hand; so will we).
#
# Each function's docstring states exactly what it must return.
#
# **Symbols** this notebook adds to the lecture's $x_i$ (rest, row `i` of `V`) and
# $x'_i$ (deformed, row `i` of `U`):
#
# | symbol | meaning | in code |
# |---|---|---|
# | $T$ | tetrahedra, four vertex indices each | `T` `(f, 4)` |
# | $D_t$, $D'_t$ | rest and deformed edges from corner 0, as columns | `(f, 3, 3)` |
# | $\operatorname{vol}_t$ | signed volume $\tfrac16 \det D_t$ | `tet_volumes(V, T)` |
# | $\varphi_k$ | the hat function of a corner $k$ | rows of `np.linalg.inv(D)` are $\nabla\varphi_1..3$ |
# | $J_t$ | deformation gradient, $J_t D_t = D'_t$ | `deformation_gradients(V, U, T)` |
# | $R_t$ | the rotation of tetrahedron $t$ | `R` `(f, 3, 3)` |
# | $K = -L$, $M$ | stiffness and lumped mass matrix | `tet_cotangent_laplacian`, `tet_mass_matrix` |

# %%
import time

import igl
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from starter import load_handles, load_mesh, plotting

rng = np.random.default_rng(7)


def boundary_faces(T, owners=False):
    """The skin of a tetrahedral mesh: faces of exactly one tetrahedron, seen from outside.

    For a positively oriented tetrahedron (x0, x1, x2, x3), the faces (1, 2, 3),
    (0, 3, 2), (0, 1, 3), (0, 2, 1) have outward normals; an inner face belongs to
    two tetrahedra, once in each direction. With ``owners``, also the index of the
    tetrahedron each face belongs to.
    """
    T = np.asarray(T)
    faces = np.concatenate([T[:, [1, 2, 3]], T[:, [0, 3, 2]], T[:, [0, 1, 3]], T[:, [0, 2, 1]]])
    _, which, count = np.unique(np.sort(faces, axis=1), axis=0, return_inverse=True, return_counts=True)
    skin = count[which.ravel()] == 1
    return (faces[skin], np.tile(np.arange(len(T)), 4)[skin]) if owners else faces[skin]


V_bar, T_bar = load_mesh("bar_tet")
V_hand, T_hand = load_mesh("hand_tet")
F_bar, F_hand = boundary_faces(T_bar), boundary_faces(T_hand)
print(f"bar_tet: {len(V_bar)} vertices ({len(np.unique(F_bar))} on the skin), {len(T_bar)} tetrahedra")
print(f"hand_tet: {len(V_hand)} vertices ({len(np.unique(F_hand))} on the skin), {len(T_hand)} tetrahedra")
# The inside, shown by pulling the tetrahedra apart: those of the bar's first third of a unit
# (x < 1/3, two grid cubes deep), each shrunk to 60 % about its centre.
chunk = T_bar[V_bar[T_bar].mean(axis=1)[:, 0] < 1 / 3]
centres = V_bar[chunk].mean(axis=1, keepdims=True)
V_apart = (centres + 0.6 * (V_bar[chunk] - centres)).reshape(-1, 3)
F_apart = np.arange(len(V_apart)).reshape(-1, 4)[:, [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]]].reshape(-1, 3)
plotting.show_meshes(
    [(V_bar, F_bar), (V_apart, F_apart), (V_hand, F_hand)],
    titles=["bar_tet", "x < 1/3, tetrahedra shrunk to 60 %", "hand_tet"],
    link_views=False,
)

# %% [markdown]
# ## 1 · Volumes
#
# The tetrahedron $(x_0, x_1, x_2, x_3)$ is spanned by the three edges from
# $x_0$; stack them as the columns of $D = [x_1 - x_0,\; x_2 - x_0,\; x_3 - x_0]$.
# The parallelepiped they span has volume $|\det D|$, and the tetrahedron is
# a sixth of it:
#
# $$
# \operatorname{vol} = \tfrac16 \det D .
# $$
#
# Without the absolute value the volume is **signed**: positive when $x_1, x_2,
# x_3$ turn counter-clockwise seen from outside (the face opposite $x_0$ seen
# from the side away from $x_0$), negative when two corners are swapped. A
# deformation that turns a tetrahedron inside out flips its sign, which is how
# we will count inverted tetrahedra.
#
# **Your task.** `tet_volumes(V, T)` returns the `(f,)` signed volumes.

# %% deformlab={"solution": "tet_volumes"}
import numpy as np


def tet_volumes(V, T):
    """Signed volumes of tetrahedra.

    Parameters
    ----------
    V : (n, 3) array_like of float
    T : (f, 4) array_like of int

    Returns
    -------
    vol : (f,) numpy.ndarray
        ``det[x1 - x0, x2 - x0, x3 - x0] / 6`` for each tetrahedron.
    """
    ### BEGIN SOLUTION
    V, T = np.asarray(V, dtype=float), np.asarray(T)
    D = np.stack([V[T[:, k]] - V[T[:, 0]] for k in (1, 2, 3)], axis=2)  # edge columns
    return np.linalg.det(D) / 6
    ### END SOLUTION

# %% deformlab={"tests": "tet_volumes", "points": 2}
_V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
_vol = np.asarray(tet_volumes(_V, np.array([[0, 1, 2, 3], [0, 2, 1, 3]])))
assert _vol.shape == (2,), f"two tetrahedra give 2 volumes, got shape {_vol.shape}"
assert np.isclose(abs(_vol[0]), 1 / 6), (
    f"the unit corner tetrahedron has volume 1/6, got {_vol[0]:.6g}"
    + (": divide det by 6" if np.isclose(abs(_vol[0]), 1) else "")
)
assert np.isclose(_vol[0], 1 / 6) and np.isclose(_vol[1], -1 / 6), (
    f"swapping two corners flips the sign: expected [1/6, -1/6], got {_vol.tolist()}"
    + (" (keep the sign: no abs)" if _vol[1] > 0 else "")
)
_vol = np.asarray(tet_volumes(V_bar, T_bar))
assert np.isclose(_vol.sum(), 4.0) and _vol.min() > 0, (
    f"bar_tet is [0, 4] x [0, 1] x [0, 1], positively oriented: volumes > 0 summing to 4, got sum {_vol.sum():.6g}"
)

# %% [markdown]
# ## 2 · Finite elements on tetrahedra: the Laplacian and the mass matrix
#
# As on triangles, a function on the mesh is piecewise linear:
# $f(p) = \sum_i f_i\, \varphi_i(p)$ with the **hat function** $\varphi_i$ equal
# to 1 at vertex $i$, 0 at the others, and linear on each tetrahedron. Inside a
# tetrahedron $\varphi_{k}$ ($k$ = its corner) is linear, so its gradient
# $\nabla\varphi_k$ is a constant vector. Since $\varphi_1, \varphi_2, \varphi_3$
# are the coordinates of $p - x_0$ in the basis of $D$'s columns,
#
# $$
# \begin{bmatrix} \nabla\varphi_1^\top \\ \nabla\varphi_2^\top \\ \nabla\varphi_3^\top \end{bmatrix} = D^{-1},
# \qquad
# \nabla\varphi_0 = -(\nabla\varphi_1 + \nabla\varphi_2 + \nabla\varphi_3)
# $$
#
# (the four hat functions sum to 1, so their gradients sum to zero).
#
# **Stiffness.** The Dirichlet energy $\int \lVert\nabla f\rVert^2 = f^\top K f$ with
# $K_{ij} = \int \nabla\varphi_i \cdot \nabla\varphi_j$: on one tetrahedron the
# gradients are constant, so its $4 \times 4$ block is
# $|\operatorname{vol}_t|\,\nabla\varphi_a \cdot \nabla\varphi_b$. The cotangent
# Laplacian is $L = -K$. In 3D its off-diagonal entries are again cotangent
# weights: $-|\operatorname{vol}|\,\nabla\varphi_i\cdot\nabla\varphi_j = \tfrac16\, \ell_{kl} \cot\theta_{kl}$,
# the length of the **opposite edge** $kl$ times the cotangent of the
# **dihedral angle** there (the 2D formula had the opposite *angle*). As in 2D
# they can be negative and the rows sum to zero.
#
# **Your task.** `tet_cotangent_laplacian(V, T)`: compute the gradients of all
# tetrahedra at once (`np.linalg.inv` works on a stack), the `(f, 4, 4)` local
# blocks, and add them into a sparse `(n, n)` matrix (duplicate entries of a
# `coo`/`csr` constructor are summed).

# %% deformlab={"solution": "tet_cotangent_laplacian"}
import numpy as np
import scipy.sparse as sp


def tet_cotangent_laplacian(V, T):
    """Cotangent Laplacian of a tetrahedral mesh, minus the linear elements' stiffness matrix.

    Parameters
    ----------
    V : (n, 3) array_like of float
    T : (f, 4) array_like of int

    Returns
    -------
    L : (n, n) scipy.sparse matrix
        ``L[i, j] = -Σ_t |vol_t| ∇φ_i · ∇φ_j``; rows sum to zero.
    """
    ### BEGIN SOLUTION
    V, T = np.asarray(V, dtype=float), np.asarray(T)
    D = np.stack([V[T[:, k]] - V[T[:, 0]] for k in (1, 2, 3)], axis=2)
    B = np.linalg.inv(D)  # rows: ∇φ_1, ∇φ_2, ∇φ_3
    G = np.concatenate([-B.sum(axis=1, keepdims=True), B], axis=1)  # (f, 4, 3): ∇φ of the 4 corners
    vol = np.abs(np.linalg.det(D)) / 6
    K = vol[:, None, None] * (G @ G.transpose(0, 2, 1))  # (f, 4, 4) local stiffness blocks
    rows, cols = np.repeat(T, 4, axis=1), np.tile(T, (1, 4))  # entry (a, b) of block t goes to (T[t, a], T[t, b])
    return -sp.csr_matrix((K.ravel(), (rows.ravel(), cols.ravel())), shape=(len(V), len(V)))
    ### END SOLUTION

# %% deformlab={"tests": "tet_cotangent_laplacian", "points": 4}
_V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
_L = sp.csr_matrix(tet_cotangent_laplacian(_V, np.array([[0, 1, 2, 3]]))).toarray()
_want = np.array([[-3, 1, 1, 1], [1, -1, 0, 0], [1, 0, -1, 0], [1, 0, 0, -1]]) / 6
assert _L.shape == (4, 4), f"4 vertices give L of shape (4, 4), got {_L.shape}"
_hint = ""
if np.allclose(_L, -_want):
    _hint = ": the signs are flipped (L = -K: off-diagonal entries -|vol| ∇φ_i·∇φ_j, here +1/6)"
elif np.allclose(_L, 6 * _want):
    _hint = ": six times too large (the volume is det / 6)"
assert np.allclose(_L, _want), f"unit corner tetrahedron: expected 1/6 ×\n{6 * _want}\ngot 1/6 ×\n{np.round(6 * _L, 4)}{_hint}"
_L = sp.csr_matrix(tet_cotangent_laplacian(V_hand, T_hand))
assert abs(_L - _L.T).max() < 1e-12 and np.abs(_L @ np.ones(len(V_hand))).max() < 1e-10, "L must be symmetric with rows summing to 0"
_G = np.array([[0.0, 0.6, 0.8], [1.0, 0.0, 0.0], [0.0, 0.8, -0.6]])  # a rotation
assert abs(sp.csr_matrix(tet_cotangent_laplacian(2.0 * V_hand @ _G.T + 1.0, T_hand)) - 2.0 * _L).max() < 1e-10, (
    "moving the hand rigidly and scaling it by 2 must scale L by 2 (|vol| ∇φ_i·∇φ_j has the units of a length)"
)
_u = V_hand @ np.array([1.0, -2.0, 0.5])  # a linear function: its gradient (1, -2, 0.5) everywhere
assert np.isclose(-_u @ (_L @ _u), 5.25 * 0.704), "for linear u, -uᵀ L u = ∫ ‖∇u‖² = ‖∇u‖² × volume (0.704)"

# %% [markdown]
# **Mass.** The lumped mass matrix gives each vertex a quarter of the volume of
# every tetrahedron around it (the "barycentric" lumping, libigl's default on
# tetrahedra): $M = \operatorname{diag}(m_i)$, $m_i = \sum_{t \ni i} |\operatorname{vol}_t| / 4$.
# Its entries sum to the volume of the mesh, and $\int f \approx \sum_i m_i f_i$.
#
# **Your task.** `tet_mass_matrix(V, T)` returns the sparse diagonal $M$. Use
# `tet_volumes` and `np.bincount` with weights.

# %% deformlab={"solution": "tet_mass_matrix"}
import numpy as np
import scipy.sparse as sp


def tet_mass_matrix(V, T):
    """Lumped (barycentric) mass matrix of a tetrahedral mesh.

    Parameters
    ----------
    V : (n, 3) array_like of float
    T : (f, 4) array_like of int

    Returns
    -------
    M : (n, n) scipy.sparse matrix
        Diagonal; ``M[i, i]`` is a quarter of the volume of every tetrahedron around vertex ``i``.
    """
    ### BEGIN SOLUTION
    T = np.asarray(T)
    quarter = np.abs(tet_volumes(V, T)) / 4  # a negatively oriented tetrahedron still has mass
    mass = np.bincount(T.ravel(), weights=np.repeat(quarter, 4), minlength=len(V))
    return sp.diags(mass)
    ### END SOLUTION

# %% deformlab={"tests": "tet_mass_matrix", "points": 2}
_V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]])
_M = sp.csr_matrix(tet_mass_matrix(_V, np.array([[0, 1, 2, 3], [1, 3, 2, 4]]))).toarray()
assert _M.shape == (5, 5) and np.allclose(_M, np.diag(np.diag(_M))), "M must be a (5, 5) diagonal matrix here"
assert np.all(np.diag(_M) > 0), f"masses must be positive, got {np.diag(_M).tolist()}: use |vol| (the second tetrahedron is negatively oriented)"
assert np.allclose(np.diag(_M), [1 / 24, 1 / 8, 1 / 8, 1 / 8, 1 / 12]), (
    f"each vertex gets a quarter of each tetrahedron's volume (1/6 and 1/3): expected "
    f"[1/24, 1/8, 1/8, 1/8, 1/12], got {np.round(np.diag(_M), 5).tolist()}"
)
_M = sp.csr_matrix(tet_mass_matrix(V_hand, T_hand))
assert np.isclose(_M.sum(), 0.704), f"the masses sum to the hand's volume 0.704, got {_M.sum():.6g}"
_M2 = sp.csr_matrix(tet_mass_matrix(2.0 * V_hand + 1.0, T_hand))
assert abs(_M2 - 8.0 * _M).max() < 1e-12, "scaling the hand by 2 (and moving it) must multiply every mass by 8"

# %% [markdown]
# ## 3 · ARAP with tetrahedral cells
#
# In stage 03 every vertex had a rotation and its cell was the fan of
# triangles around it. On a volume the natural cell is the **tetrahedron**
# itself (libigl's `ARAP_ENERGY_TYPE_ELEMENTS`): a deformation $\mathbf x'$ moves
# tetrahedron $t$ by an affine map $p \mapsto J_t p + b_t$, and
#
# $$
# E(\mathbf x', R) = \sum_t |\operatorname{vol}_t|\, \lVert J_t - R_t \rVert_F^2 .
# $$
#
# $J_t$ is the **deformation gradient**: it maps the rest edges to the
# deformed ones, $J_t D_t = D'_t$ with $D'_t = [x'_1 - x'_0,\; x'_2 - x'_0,\; x'_3 - x'_0]$
# (corners of $t$), so
#
# $$
# J_t = D'_t\, D_t^{-1} = \sum_k x'_{T[t,k]}\, \nabla\varphi_k^\top .
# $$
#
# **Local step.** For fixed $\mathbf x'$ each $R_t$ is the rotation nearest to
# $J_t$. Since $\lVert J_t - R \rVert_F^2 = \text{const} - 2 \operatorname{tr}(R\, J_t^\top)$,
# that is stage 02's problem with $S = J_t^\top$: with the lecture's SVD
# $J_t^\top = U \Sigma \tilde U^\top$, $R_t = \tilde U U^\top$, and if
# $\det(\tilde U U^\top) = -1$ (a reflection) flip the sign of the column of $U$ of
# the smallest singular value first: stage 02's sign correction, now needed for
# every **inverted** tetrahedron ($\det J_t < 0$).
#
# **Global step.** For fixed $R$ the energy is quadratic in $\mathbf x'$: one sparse
# solve with your tetrahedral Laplacian, derived below. As in stage 03b, neither
# step can increase $E$.
#
# **Your tasks.** `deformation_gradients(V, U, T)` `(f, 3, 3)`;
# `tet_arap_rotations(V, U, T)` `(f, 3, 3)`; `tet_arap_energy(V, U, T, R)`;
# then, below, the global step.

# %% deformlab={"solution": "deformation_gradients"}
import numpy as np


def deformation_gradients(V, U, T):
    """Deformation gradient of every tetrahedron.

    Parameters
    ----------
    V, U : (n, 3) array_like of float
        Rest and deformed positions.
    T : (f, 4) array_like of int

    Returns
    -------
    J : (f, 3, 3) numpy.ndarray
        ``J_t D_t = D'_t``: the rest edges ``D_t = [x1 - x0, x2 - x0, x3 - x0]`` go to the deformed ones.
    """
    ### BEGIN SOLUTION
    V, U, T = np.asarray(V, dtype=float), np.asarray(U, dtype=float), np.asarray(T)
    D = np.stack([V[T[:, k]] - V[T[:, 0]] for k in (1, 2, 3)], axis=2)
    D_deformed = np.stack([U[T[:, k]] - U[T[:, 0]] for k in (1, 2, 3)], axis=2)
    return D_deformed @ np.linalg.inv(D)
    ### END SOLUTION

# %% deformlab={"tests": "deformation_gradients", "points": 3}
_A = np.array([[1.0, 2.0, 0.0], [0.0, 1.0, 0.0], [0.5, 0.0, 3.0]])
_J = np.asarray(deformation_gradients(V_hand, V_hand @ _A.T + [1.0, 2.0, 3.0], T_hand))
assert _J.shape == (len(T_hand), 3, 3), f"one 3x3 matrix per tetrahedron: expected {(len(T_hand), 3, 3)}, got {_J.shape}"
_hint = ""
if np.allclose(_J, _A.T):
    _hint = ": each J_t is transposed (J_t maps rest edges to deformed edges: J (x_k - x_0) = x'_k - x'_0)"
elif np.allclose(_J, np.linalg.inv(_A)):
    _hint = ": this is J⁻¹ (multiply the deformed edges by the inverse of the rest edges: D' D⁻¹)"
assert np.allclose(_J, _A), f"an affine map x -> A x + b has J_t = A in every tetrahedron{_hint}"
_U = V_bar + 0.05 * rng.normal(size=V_bar.shape)
_J = np.asarray(deformation_gradients(V_bar, _U, T_bar))
_e = V_bar[T_bar[:, 3]] - V_bar[T_bar[:, 1]]
assert np.allclose(np.einsum("tab,tb->ta", _J, _e), _U[T_bar[:, 3]] - _U[T_bar[:, 1]]), "J_t must map every rest edge of t (here x3 - x1) to the deformed edge"

# %% deformlab={"solution": "tet_arap_rotations"}
import numpy as np


def tet_arap_rotations(V, U, T):
    """The local step: the rotation nearest to each tetrahedron's deformation gradient.

    Parameters
    ----------
    V, U : (n, 3) array_like of float
        Rest and deformed positions.
    T : (f, 4) array_like of int

    Returns
    -------
    R : (f, 3, 3) numpy.ndarray
        Rotations (``det = +1``) minimizing ``‖J_t - R_t‖_F``.
    """
    ### BEGIN SOLUTION
    J = deformation_gradients(V, U, T)
    # stage 02 with S = Jᵀ: Jᵀ = U Σ Ũᵀ, one SVD per tetrahedron, R = Ũ Uᵀ
    U_svd, _, U_tilde_T = np.linalg.svd(np.swapaxes(J, 1, 2))
    U_tilde = np.swapaxes(U_tilde_T, 1, 2)
    flip = np.linalg.det(U_tilde @ np.swapaxes(U_svd, 1, 2)) < 0  # the nearest orthogonal map is a reflection
    U_svd[flip, :, 2] *= -1  # flip the column of U of the smallest singular value
    return U_tilde @ np.swapaxes(U_svd, 1, 2)
    ### END SOLUTION

# %% deformlab={"tests": "tet_arap_rotations", "points": 3}
_c, _s = np.cos(0.7), np.sin(0.7)
_Rz = np.array([[_c, -_s, 0.0], [_s, _c, 0.0], [0.0, 0.0, 1.0]])
_R = np.asarray(tet_arap_rotations(V_hand, 2.0 * V_hand @ _Rz.T, T_hand))
assert _R.shape == (len(T_hand), 3, 3), f"one rotation per tetrahedron: expected {(len(T_hand), 3, 3)}, got {_R.shape}"
assert np.allclose(_R, _Rz), (
    "scaling by 2 after a rotation must give that rotation in every tetrahedron"
    + (": R is transposed (R = Ũ Uᵀ for Jᵀ = U Σ Ũᵀ)" if np.allclose(_R, _Rz.T) else "")
)
_U = V_bar.copy()
_U[:, 2] *= -1  # a mirror: every tetrahedron inverted
_R = np.asarray(tet_arap_rotations(V_bar, _U, T_bar))
assert np.allclose(np.linalg.det(_R), 1.0), (
    "every R_t must be a rotation (det +1) even when the tetrahedron is inverted: "
    "flip the singular vector of the smallest singular value when det(Ũ Uᵀ) = -1"
)
_J = np.asarray(deformation_gradients(V_bar, _U, T_bar))
assert np.allclose(np.sum((_J - _R) ** 2, axis=(1, 2)), 4.0), "for a mirror J = diag(1, 1, -1) the nearest rotation is at distance² 4"

# %% deformlab={"solution": "tet_arap_energy"}
import numpy as np


def tet_arap_energy(V, U, T, R):
    """ARAP energy with one rotation per tetrahedron.

    Parameters
    ----------
    V, U : (n, 3) array_like of float
        Rest and deformed positions.
    T : (f, 4) array_like of int
    R : (f, 3, 3) array_like of float
        One matrix per tetrahedron.

    Returns
    -------
    float
        ``Σ_t |vol_t| ‖J_t - R_t‖²_F``.
    """
    ### BEGIN SOLUTION
    J = deformation_gradients(V, U, T)
    squared = np.sum((J - np.asarray(R, dtype=float)) ** 2, axis=(1, 2))  # ‖J_t - R_t‖²_F
    return float(np.abs(tet_volumes(V, T)) @ squared)
    ### END SOLUTION

# %% deformlab={"tests": "tet_arap_energy", "points": 2}
_I = np.tile(np.eye(3), (len(T_hand), 1, 1))
_E = tet_arap_energy(V_hand, 1.5 * V_hand, T_hand, _I)
assert np.ndim(_E) == 0, f"the energy is one number, got shape {np.shape(_E)}"
assert np.isclose(_E, 0.25 * 3 * 0.704), (
    f"J = 1.5 I against R = I costs ‖0.5 I‖² = 0.75 per unit volume, 0.75 × 0.704 in all; got {float(_E):.6g}"
)
_T = T_hand.copy()
_T[::2] = _T[::2][:, [1, 0, 2, 3]]  # half the tetrahedra negatively oriented
assert np.isclose(tet_arap_energy(V_hand, 1.5 * V_hand, _T, _I), _E), (
    "the energy must not depend on the corner order: weight by |vol|, not the signed volume"
)
_U = V_hand @ _Rz.T
assert tet_arap_energy(V_hand, _U, T_hand, tet_arap_rotations(V_hand, _U, T_hand)) < 1e-20, "a rotation costs nothing"

# %% [markdown]
# ### The global step
#
# Hold the rotations fixed. $J_t = \sum_k x'_{T[t,k]} \nabla\varphi_k^\top$ is
# linear in $\mathbf x'$, so $E$ is quadratic in $\mathbf x'$; its gradient with
# respect to a vertex $x'_i$ is
#
# $$
# \frac{\partial E}{\partial x'_i} = 2 \sum_{t \ni i} |\operatorname{vol}_t|\, (J_t - R_t)\, \nabla\varphi_i .
# $$
#
# The $J_t$ part sums to $\sum_j \big(\sum_t |\operatorname{vol}_t|\, \nabla\varphi_i \cdot \nabla\varphi_j\big) x'_j = (-L \mathbf x')_i$,
# with your `tet_cotangent_laplacian` $L$ from §2. Setting the gradient to zero
# at every free vertex gives the lecture's $\mathbf L \mathbf x' = \mathbf b$ (its
# $\mathbf L$ is our $-L$):
#
# $$
# -L\,\mathbf x' = \mathbf b, \qquad b_i = \sum_{t \ni i} |\operatorname{vol}_t|\, R_t\, \nabla\varphi_i ,
# $$
#
# rows of the `(n, 3)` arrays `U` and `B`. It is stage 03b's system with a new
# right-hand side: split free vertices $f$ from handles $h$ and solve
# $(-L)_{ff}\, \mathbf x'_f = \mathbf b_f + L_{fh}\, \hat{\mathbf x}'_h$. $(-L)_{ff}$ depends neither on $R$
# nor on where the handles go, so it is factorized once.
#
# **Your tasks.** `tet_arap_precompute(V, T, handles)` returns an object of your
# design with what the iterations reuse (the factorization among it), and
# `tet_arap_global_step(data, R, handle_positions)` returns the `(n, 3)` array
# `U` with `U[handles] = handle_positions` that minimizes
# `tet_arap_energy(V, U, T, R)`.

# %% deformlab={"solution": "tet_arap_precompute"}
import types

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def tet_arap_precompute(V, T, handles):
    """What the tetrahedral ARAP iterations reuse: the rest mesh, the hat gradients and the factorized system.

    Parameters
    ----------
    V : (n, 3) array_like of float
        Rest positions.
    T : (f, 4) array_like of int
        Tetrahedra.
    handles : (h,) array_like of int
        Distinct vertex indices whose positions are prescribed; at least one.

    Returns
    -------
    data : object of your design
        Everything ``tet_arap_global_step`` needs.

    Raises
    ------
    ValueError
        If ``handles`` is empty, repeats a vertex or is out of range.
    """
    ### BEGIN SOLUTION
    V, T = np.array(V, dtype=float), np.array(T, dtype=np.int64)  # copies: later edits cannot reach the caller
    handles = np.array(handles, dtype=np.int64).reshape(-1)
    if handles.size == 0 or handles.min() < 0 or handles.max() >= len(V) or len(np.unique(handles)) != handles.size:
        raise ValueError(f"handles must be distinct vertex indices in range({len(V)}), at least one; got {handles.tolist()}")
    free = np.setdiff1d(np.arange(len(V)), handles)
    D = np.stack([V[T[:, k]] - V[T[:, 0]] for k in (1, 2, 3)], axis=2)  # columns x_k - x_0
    rows = np.linalg.inv(D)  # rows ∇φ_1, ∇φ_2, ∇φ_3
    K = -sp.csr_matrix(tet_cotangent_laplacian(V, T))  # -L
    return types.SimpleNamespace(
        V=V, T=T, handles=handles, free=free,
        volumes=np.abs(tet_volumes(V, T)),
        gradients=np.concatenate([-rows.sum(axis=1, keepdims=True), rows], axis=1),  # (f, 4, 3): ∇φ of each corner
        K_fh=K[free][:, handles],
        K_ff=spla.splu(K[free][:, free].tocsc()),  # the same for every R and every handle position
    )
    ### END SOLUTION

# %% deformlab={"tests": "tet_arap_precompute", "points": 1}
_ends = load_handles("bar_tet")
_h = np.concatenate([_ends["left"], _ends["right"]])
_copies = (V_bar.copy(), T_bar.copy(), _h.copy())
_data = tet_arap_precompute(V_bar, T_bar, _h)
assert all(np.array_equal(_a, _b) for _a, _b in zip((V_bar, T_bar, _h), _copies)), (
    "tet_arap_precompute must not modify V, T or handles"
)
for _bad, _why in (([0, 0], "repeated"), ([len(V_bar)], "out of range"), ([], "empty")):
    try:
        tet_arap_precompute(V_bar, T_bar, np.array(_bad, dtype=np.int64))
    except ValueError:
        pass
    except Exception as _exc:  # noqa: BLE001 - any other error is not the one asked for
        raise AssertionError(f"handles {_bad} ({_why}) must raise ValueError, got {type(_exc).__name__}: {_exc}") from None
    else:
        raise AssertionError(f"handles {_bad} ({_why}) must raise ValueError")

# %% deformlab={"solution": "tet_arap_global_step"}
import numpy as np


def tet_arap_global_step(data, R, handle_positions):
    """The global step: the positions minimizing the tetrahedral ARAP energy for fixed rotations.

    Parameters
    ----------
    data : object
        From ``tet_arap_precompute``.
    R : (f, 3, 3) array_like of float
        One rotation per tetrahedron.
    handle_positions : (h, 3) array_like of float
        Where the handles go.

    Returns
    -------
    U : (n, 3) numpy.ndarray
        ``U[handles] = handle_positions``; the free rows solve ``(-L)_ff x'_f = b_f - (-L)_fh x'_h``.
    """
    ### BEGIN SOLUTION
    # |vol_t| R_t ∇φ_k for every corner k of every tetrahedron t
    corner = data.volumes[:, None, None] * np.einsum("tab,tkb->tka", np.asarray(R, dtype=float), data.gradients)
    B = np.zeros_like(data.V)
    np.add.at(B, data.T.ravel(), corner.reshape(-1, 3))  # each corner's term goes to its vertex
    U = np.empty_like(data.V)
    U[data.handles] = handle_positions
    U[data.free] = data.K_ff.solve(B[data.free] - data.K_fh @ U[data.handles])
    return U
    ### END SOLUTION

# %% deformlab={"tests": "tet_arap_global_step", "points": 3}
_ends = load_handles("bar_tet")
_h = np.concatenate([_ends["left"], _ends["right"]])
_data = tet_arap_precompute(V_bar, T_bar, _h)
_f = len(T_bar)

_U = tet_arap_global_step(_data, np.tile(np.eye(3), (_f, 1, 1)), V_bar[_h])
assert _U.shape == V_bar.shape, f"U must have the shape of V, {V_bar.shape}, got {_U.shape}"
_err = np.linalg.norm(_U - V_bar, axis=1)
assert _err.max() < 1e-8, f"with R_t = I and the handles at rest the answer is V; vertex {_err.argmax()} is off by {_err.max():.2e}"

_Q = np.array([[0.0, 0.6, 0.8], [1.0, 0.0, 0.0], [0.0, 0.8, -0.6]])  # a rotation
_t = np.array([0.5, -1.0, 2.0])
_U = tet_arap_global_step(_data, np.tile(_Q, (_f, 1, 1)), V_bar[_h] @ _Q.T + _t)
_err = np.linalg.norm(_U - (V_bar @ _Q.T + _t), axis=1)
assert _err.max() < 1e-8, (
    f"with every R_t = Q and the handles moved rigidly by Q, U must be V moved rigidly; "
    f"vertex {_err.argmax()} is off by {_err.max():.2e} (B_i takes R_t ∇φ_i: R_t itself, not its transpose)"
)

# Rotations from a real deformation, handles somewhere new, half the tetrahedra negatively oriented.
_T = T_bar.copy()
_T[::2] = _T[::2][:, [1, 0, 2, 3]]
_R = tet_arap_rotations(V_bar, V_bar + 0.05 * rng.normal(size=V_bar.shape), _T)
_target = V_bar[_h] + 0.1 * rng.normal(size=(len(_h), 3))
_U = tet_arap_global_step(tet_arap_precompute(V_bar, _T, _h), _R, _target)
assert np.array_equal(_U[_h], _target), "U[handles] must equal handle_positions exactly"
# E is quadratic in U, so at its constrained minimum E(U + D) = E(U - D) for any D that keeps the handles.
_E = tet_arap_energy(V_bar, _U, _T, _R)
for _ in range(3):
    _D = 0.01 * rng.normal(size=V_bar.shape)
    _D[_h] = 0.0
    _plus, _minus = tet_arap_energy(V_bar, _U + _D, _T, _R), tet_arap_energy(V_bar, _U - _D, _T, _R)
    assert min(_plus, _minus) >= _E - 1e-9 * _E and abs(_plus - _minus) <= 1e-7 * (_plus + _minus), (
        f"U does not minimize the energy for the given rotations: moving the free vertices by ±D "
        f"gives {_minus:.8g} and {_plus:.8g} against {_E:.8g} (half the tetrahedra here are negatively "
        f"oriented: weight B by |vol_t|, and move the handle columns to the right-hand side)"
    )

# %% [markdown]
# The solver, built from your functions: `tet_arap` reaches the pose in `steps`
# steps of `iterations` local–global iterations each, every step starting from
# the last one's result (as in stage 03b, with one rotation per tetrahedron
# instead of one per vertex).

# %%
def tet_arap(V, T, handles, targets_at, steps=6, iterations=10):
    """ARAP with tetrahedral cells; ``targets_at(f)`` are the handles' positions at fraction ``f`` of the pose."""
    data = tet_arap_precompute(V, T, handles)
    U, energies = np.array(V, dtype=float), []
    for step in range(1, steps + 1):
        U[handles] = targets_at(step / steps)
        for _ in range(iterations):
            R = tet_arap_rotations(V, U, T)  # local step
            U = tet_arap_global_step(data, R, U[handles])  # global step
            energies.append(tet_arap_energy(V, U, T, R))
    return U, np.array(energies)


def turn_about_x(degrees, centre):
    """(3, 3) rotation about the x axis and the translation keeping ``centre`` in place."""
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    R = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    return R, centre - R @ centre


# %% [markdown]
# ## 4 · Experiment: surface ARAP against tetrahedral ARAP on a twisted bar
#
# Twist the bar by 180°: the left end stays, the right end turns about the bar's
# axis, reached in 6 steps of 10 iterations. Two ARAP solvers get exactly the
# same handles:
#
# * **surface ARAP**: stage 03's spokes-and-rims energy on the bar's skin (the
#   boundary triangles of `bar_tet`; libigl's implementation, the interior
#   vertices dropped);
# * **tetrahedral ARAP**: your energy on the whole volume.
#
# Both then run the last step to convergence (the cell prints how that was
# judged). We measure the volume the skin encloses (in % of the rest volume 4),
# the size of the middle cross-section, and how many tetrahedra turn inside
# out, and draw each tetrahedron's volume change as colour on the half of the
# bar in front of the plane $y = 0.5$, seen from that cut (surface ARAP has no
# inside of its own: there the inside follows the skin by harmonic
# interpolation).
#
# **Predict first.** Which of the two keeps the volume better, and roughly how
# much volume do you expect each to lose: none, a few percent, a third?

# %% [markdown] deformlab={"answer": "predict_tet_experiment", "points": 1}
# The tetrahedral ARAP keeps the volume far better: every tetrahedron wants to
# stay rigid, so the inside resists being squeezed; it still loses a few
# percent (<span class="measured">5.0</span> % measured): with both ends held, a twisted fibre away from
# the axis becomes a helix between the same two end points, longer than the
# straight fibre, and the energy trades stretching those fibres against pulling
# them closer to the axis, which costs volume. Surface ARAP only keeps the skin's
# edges: the walls of the twisted bar cave in and well over a third of the
# volume is lost (<span class="measured">40.5</span> % measured, the middle's width × <span class="measured">0.833</span>), although the
# skin's triangles stay nearly rigid.

# %%
def enclosed_volume(U, F):
    """Volume enclosed by a closed, outward-oriented triangle mesh (divergence theorem)."""
    return np.einsum("ij,ij->i", U[F[:, 0]], np.cross(U[F[:, 1]], U[F[:, 2]])).sum() / 6


ends = load_handles("bar_tet")
left, right = ends["left"], ends["right"]
centre = np.array([4.0, 0.5, 0.5])
middle = np.flatnonzero(np.isclose(V_bar[:, 0], 2.0))


def twisted(f):
    R, t = turn_about_x(180 * f, centre)
    return np.vstack([V_bar[left], V_bar[right] @ R.T + t])


start = time.perf_counter()
U_tet, energies = tet_arap(V_bar, T_bar, np.r_[left, right], twisted)
seconds = time.perf_counter() - start

# surface ARAP on the skin: renumber the skin's vertices 0..k-1
skin = np.unique(F_bar)
index = np.full(len(V_bar), -1)
index[skin] = np.arange(len(skin))
V_skin, F_skin = V_bar[skin], index[F_bar]
data = igl.ARAPData()
data.energy = igl.ARAP_ENERGY_TYPE_SPOKES_AND_RIMS
data.max_iter = 10
igl.arap_precomputation(V_skin, F_skin, 3, np.r_[index[left], index[right]], data)
U_skin = V_skin.copy()
for step in range(1, 7):
    U_skin = igl.arap_solve(twisted(step / 6), data, U_skin)
# Both then run the last step to convergence. Surface ARAP, in chunks of 200 iterations of libigl's
# solver, until no skin vertex moves by 1e-6 over a chunk.
data.max_iter = 200
surface_iterations, surface_moved = 60, np.inf
while surface_moved > 1e-6 and surface_iterations < 10000:
    U_before, U_skin = U_skin, igl.arap_solve(twisted(1.0), data, U_skin)
    surface_iterations, surface_moved = surface_iterations + 200, np.abs(U_skin - U_before).max()
# Tetrahedral ARAP, with your functions, until the energy drops by less than 1e-7 of itself over 10 iterations.
data_tet = tet_arap_precompute(V_bar, T_bar, np.r_[left, right])
tet_energies = list(energies)
while len(tet_energies) < 2000:
    previous, U_before = tet_energies[-1], U_tet
    for _ in range(10):
        R = tet_arap_rotations(V_bar, U_tet, T_bar)  # local step
        U_tet = tet_arap_global_step(data_tet, R, twisted(1.0))  # global step
        tet_energies.append(tet_arap_energy(V_bar, U_tet, T_bar, R))
    if previous - tet_energies[-1] <= 1e-7 * tet_energies[-1]:
        break
tet_moved = np.abs(U_tet - U_before).max()
seconds = time.perf_counter() - start


def width(P):
    """Largest distance of a cross-section's points from their centre, in y-z."""
    return np.linalg.norm(P[:, 1:] - P[:, 1:].mean(axis=0), axis=1).max()


rest_width = width(V_bar[middle])
# within a step the handles stay put, so neither the local nor the global step may raise the energy
rises = int(np.sum(np.diff(energies.reshape(6, 10), axis=1) > 1e-12 * energies.max()))
rises += int(np.sum(np.diff(tet_energies[50:]) > 1e-12 * energies.max()))
print(f"tetrahedral ARAP: 6 steps of 10 iterations, then the last step to convergence: {len(tet_energies)} iterations, "
      f"{seconds:.1f} s with surface ARAP; last step's energy {tet_energies[50]:.4f} -> {tet_energies[-1]:.4f}, "
      f"vertices moved ≤ {tet_moved:.1e} over the last 10 iterations; "
      f"{rises} rise(s) within a step (your global step or rotations are wrong if this is not 0)")
print(f"surface ARAP: converged after {surface_iterations} iterations (vertices moved ≤ {surface_moved:.1e} over the last 200)")
middle_skin = index[middle][index[middle] >= 0]  # the middle cross-section's vertices on the skin
for name, U, F, ring in [("surface ARAP", U_skin, F_skin, middle_skin), ("tetrahedral ARAP", U_tet, F_bar, middle)]:
    print(f"{name:17s} volume {100 * (enclosed_volume(U, F) / 4.0 - 1):+6.1f} %, "
          f"middle cross-section width × {width(U[ring]) / rest_width:.3f}")
print(f"inverted tetrahedra after tetrahedral ARAP: {int(np.sum(tet_volumes(U_tet, T_bar) < 0))} of {len(T_bar)}")
rest_volumes = tet_volumes(V_bar, T_bar)
from_axis = np.linalg.norm(V_bar[T_bar].mean(axis=1)[:, 1:] - centre[1:], axis=1)  # rest distance from the bar's axis
core = from_axis < 0.25
lost = 1 - tet_volumes(U_tet, T_bar) / rest_volumes
print(f"tetrahedral ARAP: the core (within 0.25 of the axis) changes its volume by "
      f"{-100 * np.average(lost[core], weights=rest_volumes[core]):+.1f} %, the rest by "
      f"{-100 * np.average(lost[~core], weights=rest_volumes[~core]):+.1f} %")
# Volume change as colour, on the half y < 0.5 of the bar seen from the cut. Surface ARAP moves the
# skin only: its inside is filled in by harmonic interpolation of the skin's motion (one solve).
skin_motion = igl.harmonic(V_bar, T_bar, skin, U_skin - V_skin, 1)
half = np.flatnonzero(V_bar[T_bar].mean(axis=1)[:, 1] < 0.5)
F_half, owner = boundary_faces(T_bar[half], owners=True)
pictures = []
for name, U in [("surface ARAP", V_bar + skin_motion), ("tetrahedral ARAP", U_tet)]:
    change = 100 * (tet_volumes(U, T_bar) / rest_volumes - 1)
    print(f"{name:17s} tetrahedra of the half: volume change from {change[half].min():+.0f} % to {change[half].max():+.0f} %")
    pictures.append((U, F_half, change[half][owner]))
plotting.show_meshes(
    pictures, titles=["surface ARAP, twist 180°", "tetrahedral ARAP, twist 180°"],
    label="volume change (%)", clim=(-60.0, 60.0), cmap="RdBu", view=(0.5, 1.0, 0.6),
)
plotting.show_energy(tet_energies[50:], title="tetrahedral ARAP energy, the last step")

# %% [markdown]
# Both runs stopped by their own test, printed above: surface ARAP after
# <span class="measured">2260</span> iterations, once no skin vertex moved by 1e-6 over 200 of them;
# tetrahedral ARAP once 10 iterations lowered the energy by less than 1e-7 of
# itself. No tetrahedron of the tetrahedral solution is inverted (<span class="measured">0</span> of <span class="measured">5184</span>),
# and the volume it loses is not spread evenly: the core within 0.25 of the axis
# changes by <span class="measured">−7.9</span>%, the rest by <span class="measured">−4.4</span>%. Tetrahedron by tetrahedron,
# the tetrahedral solution changes volumes between <span class="measured">−12</span>% and <span class="measured">+13</span>%; the inside
# that follows the surface solution reaches <span class="measured">−171</span>% (tetrahedra turned inside
# out) and <span class="measured">+21</span>%.

# %% [markdown]
# **Question.** The tetrahedral energy does not mention volume (it has no
# $\det J$ term): why does it keep the volume nonetheless, and why only
# approximately? And why can the twisted bar not reach zero energy at all, with
# both ends held: what does the twist do to a straight fibre of material away
# from the axis?

# %% [markdown] deformlab={"answer": "tet_volume_why", "points": 2}
# The tetrahedral energy makes every tetrahedron of the inside nearly rigid: J
# close to a rotation, and a rotation keeps the volume, so a deformation with low
# energy keeps it too. Only approximately, because ‖J − R‖² penalizes every
# departure from a rotation the same way; it has no term that forbids shrinking
# (no det J = 1 constraint), so where the deformation must stretch or squeeze
# the solver trades a little volume against shear. And it must: with both ends
# held, a straight fibre at distance r from the axis becomes a helix between the
# same two end points, longer than before, the more so the farther out. Rigid
# pieces cannot lengthen fibres, so the energy cannot vanish; the minimizer
# spreads the misfit between stretching the outer fibres and pulling material
# towards the axis (the middle's width × <span class="measured">0.982</span>), and the latter costs
# volume: the measured <span class="measured">5.0</span> %.

# %% [markdown]
# ## 5 · Bounded biharmonic weights on the tetrahedral hand
#
# Stage 04's weights minimize $\tfrac12 w^\top Q w$ with $Q = L M^{-1} L$ and
# $0 \le w \le 1$. Nothing in that derivation was about triangles: $\tfrac12
# w^\top Q w$ approximates $\tfrac12 \int (\Delta w)^2$, now over the volume,
# with the $L$ and $M$ you wrote in §2 (on the hand, $M$ is the barycentric
# mass: a quarter of every tetrahedron's volume to each of its corners).
#
# **Your task.** `tet_biharmonic_matrix(V, T)`, sparse `(n, n)`. Below, the
# unconstrained biharmonic weights from your $Q$ (stage 04's
# `unconstrained_biharmonic_weights`, on the volume) are checked against
# libigl's k-harmonic weights with $k = 2$, `igl.harmonic(V, T, b, bc, 2)`, which
# minimize the same energy; and the box-constrained solve is libigl's `igl.bbw`
# (the active-set method of stage 04), which builds the same $Q$. (libigl's
# *biharmonic coordinates*, `igl::biharmonic_coordinates`, are a different
# construction: weights that reproduce affine functions of the handles'
# positions, for point and cage handles; they are not computed here.)

# %% deformlab={"solution": "tet_biharmonic_matrix"}
import numpy as np
import scipy.sparse as sp


def tet_biharmonic_matrix(V, T):
    """The biharmonic energy matrix of a tetrahedral mesh.

    Parameters
    ----------
    V : (n, 3) array_like of float
    T : (f, 4) array_like of int

    Returns
    -------
    Q : (n, n) scipy.sparse matrix
        ``L M⁻¹ L`` with ``L = tet_cotangent_laplacian(V, T)`` and ``M = tet_mass_matrix(V, T)``.
    """
    ### BEGIN SOLUTION
    L = sp.csr_matrix(tet_cotangent_laplacian(V, T))
    M = sp.csr_matrix(tet_mass_matrix(V, T))
    return L @ sp.diags(1.0 / M.diagonal()) @ L  # M is diagonal: its inverse is 1 / its diagonal
    ### END SOLUTION

# %% deformlab={"tests": "tet_biharmonic_matrix", "points": 2}
_Q = tet_biharmonic_matrix(V_hand, T_hand)
assert sp.issparse(_Q), f"Q must be a scipy.sparse matrix, got {type(_Q).__name__}"
assert _Q.shape == (len(V_hand), len(V_hand)), f"Q must be ({len(V_hand)}, {len(V_hand)}), got {_Q.shape}"
_Q = sp.csr_matrix(_Q)
assert abs(_Q - _Q.T).max() <= 1e-9 * abs(_Q).max(), "Q = L M⁻¹ L is symmetric"
assert np.abs(_Q @ np.ones(len(V_hand))).max() <= 1e-9 * abs(_Q).max(), "constants cost nothing: Q 1 = 0"
_L = sp.csr_matrix(tet_cotangent_laplacian(V_hand, T_hand))
_x = rng.normal(size=len(V_hand))
_energy, _no_mass = _x @ (_Q @ _x), (_L @ _x) @ (_L @ _x)
assert not np.isclose(_energy, _no_mass, rtol=1e-6), "Q equals L L: M⁻¹ is missing (Q = L M⁻¹ L)"
_Lx = _L @ _x
_want = _Lx @ (_Lx / sp.csr_matrix(tet_mass_matrix(V_hand, T_hand)).diagonal())
assert np.isclose(_energy, _want, rtol=1e-9), (
    f"xᵀQx must be (Lx)ᵀ M⁻¹ (Lx) = {_want:.8g}, got {_energy:.8g} (divide by the masses, do not multiply)"
)

# %% [markdown]
# The hand has six bones (palm, four fingers, thumb), each a row of vertices
# inside it; each bone is a handle.
#
# **Predict first.** The middle finger and its neighbours are 0.1 apart
# (one grid step) across the gaps, but 1.4 apart through the hand. Does the
# middle finger's bone weigh on the neighbouring fingers (a) with inverse-distance
# weights, (b) with bounded biharmonic weights on the volume? Roughly how much?

# %% [markdown] deformlab={"answer": "predict_hand_weights", "points": 1}
# (a) Inverse-distance weights measure straight-line distance, so the index and
# ring fingers, one gap away from the middle finger, take a large share of its
# weight (about a third measured at their tips: <span class="measured">0.350</span> and <span class="measured">0.331</span>). (b) BBW on the volume spreads
# weights through the hand's inside: from the middle finger to the index
# finger the path runs down to the palm and back up, so the middle bone's
# weight on the neighbouring fingers' tips is close to zero (<span class="measured">0.0000</span> at both tips).

# %%
bones = load_handles("hand_tet")["bones"]
b = np.concatenate(bones)
bc = np.repeat(np.eye(len(bones)), [len(bone) for bone in bones], axis=0)
# the unconstrained biharmonic weights from your Q: libigl's 2-harmonic weights minimize the same energy
Q = sp.csr_matrix(tet_biharmonic_matrix(V_hand, T_hand))
free = np.setdiff1d(np.arange(len(V_hand)), b)
W_unconstrained = np.zeros((len(V_hand), len(bones)))
W_unconstrained[b] = bc
W_unconstrained[free] = spla.splu(Q[free][:, free].tocsc()).solve(-(Q[free][:, b] @ bc))
assert np.abs(W_unconstrained - igl.harmonic(V_hand, T_hand, b, bc, 2)).max() < 1e-8
print(f"unconstrained biharmonic weights on the hand range over [{W_unconstrained.min():.3f}, {W_unconstrained.max():.3f}]")
W_bbw = igl.bbw(V_hand, T_hand, b, bc)
W_bbw /= W_bbw.sum(axis=1, keepdims=True)
# inverse-distance weights to the nearest vertex of each bone, power 2
distance = np.stack([np.linalg.norm(V_hand[:, None] - V_hand[bone][None], axis=2).min(axis=1) for bone in bones], axis=1)
with np.errstate(divide="ignore"):
    W_idw = 1 / distance**2
on_bone = np.isinf(W_idw).any(axis=1)
W_idw[on_bone] = np.isinf(W_idw[on_bone])  # a vertex on a bone follows that bone alone
W_idw /= W_idw.sum(axis=1, keepdims=True)
names = ["palm", "index", "middle", "ring", "little", "thumb"]
tips = {name: np.flatnonzero((V_hand[:, 1] >= V_hand[bone][:, 1].max() - 1e-9) & (np.abs(V_hand[:, 0] - V_hand[bone[0], 0]) <= 0.1 + 1e-9))
        for name, bone in zip(names[1:5], bones[1:5])}
for finger in ("index", "ring"):
    print(f"weight of the middle bone at the {finger} fingertip: inverse distance {W_idw[tips[finger], 2].max():.3f}, "
          f"BBW {abs(W_bbw[tips[finger], 2]).max():.4f}")
plotting.show_meshes(
    [(V_hand, F_hand, W_idw[:, 2]), (V_hand, F_hand, W_bbw[:, 2])],
    titles=["inverse distance: middle bone", "BBW on the volume: middle bone"], label="weight of the middle bone",
    clim=(0.0, 1.0),
)

# %% [markdown]
# The bounds matter in a volume too: the unconstrained weights on the hand,
# printed above, range over [<span class="measured">−0.308</span>, <span class="measured">1.142</span>].
#
# **Linear blend skinning of the hand** (the scenario of libigl's tutorial 403):
# curl every finger by 70° about its knuckle (the first vertex of its bone),
# turn the thumb by 40°, keep the palm; each vertex blends the bone transforms
# with its weights.

# %%
def turn_about(axis, degrees, pivot):
    """(3, 4) rigid transform: rotation by ``degrees`` about ``axis`` through ``pivot`` (Rodrigues)."""
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
    t = np.radians(degrees)
    R = np.eye(3) + np.sin(t) * K + (1 - np.cos(t)) * K @ K
    return np.c_[R, pivot - R @ pivot]


pose = [np.eye(3, 4)]
pose += [turn_about([1.0, 0.0, 0.0], -70, V_hand[bone[0]]) for bone in bones[1:5]]
pose += [turn_about([0.0, 1.0, 0.0], 40, V_hand[bones[5][0]])]
pose = np.array(pose)
U_hand = np.einsum("ij,jab,ib->ia", W_bbw, pose[:, :, :3], V_hand) + W_bbw @ pose[:, :, 3]
U_idw = np.einsum("ij,jab,ib->ia", W_idw, pose[:, :, :3], V_hand) + W_idw @ pose[:, :, 3]
print(f"inverted tetrahedra: BBW {int(np.sum(tet_volumes(U_hand, T_hand) < 0))}, "
      f"inverse distance {int(np.sum(tet_volumes(U_idw, T_hand) < 0))} of {len(T_hand)}")
plotting.show_meshes(
    [(V_hand, F_hand), (U_idw, F_hand), (U_hand, F_hand)],
    titles=["rest", "LBS, inverse-distance weights", "LBS, BBW on the volume"],
)

# %% [markdown]
# Even with BBW a few tetrahedra turn inside out (<span class="measured">3</span> of <span class="measured">4224</span>; <span class="measured">6</span> with
# inverse-distance weights). They sit at the base of a finger, where the
# finger's and the palm's weights are both about a half: there LBS averages two
# rotations 70° apart, and an average of rotations is not a rotation; it
# shrinks (stage 05's joint collapse). Better weights cannot fix that; a blend
# that stays a rotation, such as stage 05's dual quaternions, can.
