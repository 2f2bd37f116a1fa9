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
# # 03 · As-rigid-as-possible deformation: the energy and the local step
#
# *Workload: about 4.2 hours for 5 graded functions (10 points) and 1 written answer (an estimate for a student who attended the lecture).*
#
# A user grabs a few *handles* of a shape, here the two ends of a bar, and moves
# them. Every other vertex should follow so that the shape looks the same up
# close: locally it may rotate, but it should not stretch, shear or squash.
# As-rigid-as-possible (ARAP) deformation turns that wish into an energy and
# minimizes it by alternating two steps: fitting rotations (the *local* step,
# stage 02's problem once per vertex) and solving a sparse linear system (the
# *global* step). This notebook builds the energy and the local step, and uses
# them to judge deformations written down by hand; stage 03b builds the global
# step and the solver on your functions from here.
#
# **Notation** (the lecture's letters; the code's names are the contract's):
#
# | symbol | meaning | in code |
# |---|---|---|
# | $x_i \in \mathbb R^d$ | rest position of vertex $i$ ($d = 2$ planar, $d = 3$ surface) | row `i` of `V` `(n, d)` |
# | $x'_i$ | deformed position of vertex $i$ | row `i` of `U` `(n, d)` |
# | $\mathbf x'$ | all deformed positions, one row per vertex | `U` |
# | $R_i$ | rotation of vertex $i$'s cell | `R[i]`, `R` `(n, d, d)` |
# | $c_{jk}$ | weight of edge $(j, k)$ in a triangle: $\tfrac12 \cot$ of the opposite angle | `C` `(f, 3)` |
# | $S_i = U \Sigma \tilde U^\top$ | cell $i$'s covariance and its SVD | `U_svd, sigma, U_tilde_T = np.linalg.svd(S)` |
# | $L$ | cotangent Laplacian (libigl's sign: negative semi-definite) | `cotangent_laplacian(V, F)` |
#
# One letter clashes, and the table settles it: in the lecture $U$ is also the
# SVD's left factor, while the contract calls the deformed positions `U`; the
# code therefore names the SVD factors `U_svd` and `U_tilde`.
#
# **The energy.** Each vertex $i$ owns a *cell*: the triangles around it. The cell
# should move rigidly, by a rotation $R_i \in SO(d)$ of its own. We measure how far
# it is from that with every edge of every triangle of the cell, the "spokes"
# (edges through $i$) and the "rims" (the opposite edges). The lecture's slide
# writes the sum unweighted; we weight each edge by $c_{jk}$ (§2 says why: with
# $c_{jk} = 1$ the energy would depend on how the surface is triangulated), as
# the original ARAP paper and libigl do:
#
# $$
# E(\mathbf x', R) \;=\; \sum_i \; \sum_{T \ni i} \; \sum_{(j,k) \in T} c_{jk}
# \,\bigl\| (x'_j - x'_k) - R_i (x_j - x_k) \bigr\|^2 .
# $$
#
# ARAP deformation minimizes $E$ over the positions $x'$ (with the handles where
# the user put them) and the rotations $R$ together. Since the rotations are
# unknowns too, $E$ does not care how the shape is oriented: a rigid motion of
# the whole mesh costs nothing.
#
# This notebook builds the pieces one function at a time: the weights $c_{jk}$,
# the Laplacian, the local step (rotations) and the energy; §6 then measures
# what the energy sees. Run the first cell, then fill in each solution cell and
# run its tests.
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
# With the lecture's SVD $S = U \Sigma \tilde U^\top$ the answer is
#
# $$
# R = \tilde U \, D \, U^\top, \qquad D = \operatorname{diag}\bigl(1, \dots, 1, \det(\tilde U U^\top)\bigr),
# $$
#
# i.e. the best orthogonal matrix $\tilde U U^\top$, with the column of $U$ of the
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
        Covariance matrix or matrices, ``S = U Σ Ũᵀ``.

    Returns
    -------
    R : numpy.ndarray, the shape of ``S``
        ``R = Ũ diag(1, …, 1, det(Ũ Uᵀ)) Uᵀ``: orthogonal with ``det R = +1``.
    """
    ### BEGIN SOLUTION
    # np.linalg.svd and det act on the last two axes, so one code path serves (d, d) and (k, d, d).
    U_svd, sigma, U_tilde_T = np.linalg.svd(np.asarray(S, dtype=float))  # S = U Σ Ũᵀ
    U_tilde = np.swapaxes(U_tilde_T, -1, -2)
    sign = np.where(np.linalg.det(U_tilde @ np.swapaxes(U_svd, -1, -2)) < 0, -1.0, 1.0)  # -1 where Ũ Uᵀ is a reflection
    # Flip the column of U of the smallest singular value (numpy's last column): the cheapest fix.
    U_svd = U_svd.copy()
    U_svd[..., -1] *= sign[..., None]
    return U_tilde @ np.swapaxes(U_svd, -1, -2)  # R = Ũ D Uᵀ
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
try:
    _R = optimal_rotation(_S)
except Exception as _exc:  # noqa: BLE001 - a single-matrix code path fails on a stack with numpy's own words
    raise AssertionError(
        f"optimal_rotation fails on a stack of shape {np.shape(_S)}: {type(_exc).__name__}: {_exc}. It must take a stack "
        "(k, d, d) as well as one matrix: np.linalg.svd and det act on the last two axes, so transpose with "
        "np.swapaxes(A, -1, -2) instead of .T, index the last column with [..., -1] and multiply it by sign[..., None]"
    ) from None
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
    + (": det(S) = 0 says nothing about the sign; take it from det(Ũ Uᵀ)" if abs(np.linalg.det(_R) - 1) > 1e-8 else "")
)

# %% [markdown]
# ## 2 · Cotangent weights
#
# Which weights $c_{jk}$? Take one triangle $T$ and suppose $x'$ is linear on it,
# $x'(p) = J_T\, p + t$ for the points $p$ of $T$, so that every edge maps as $x'_j - x'_k = J_T (x_j - x_k)$.
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
# Applying this to each coordinate of the linear map $p \mapsto (J_T - R_i)\,p$,
# which sends the edge $x_j - x_k$ to $(x'_j - x'_k) - R_i (x_j - x_k)$, gives exactly
#
# $$
# \sum_{(j,k) \in T} c_{jk} \,\| (x'_j - x'_k) - R_i (x_j - x_k) \|^2 = A_T \,\|J_T - R_i\|_F^2
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
    + (": the right values in the wrong columns; C[t, k] is the angle AT corner k, between the two edges "
       "leaving F[t, k] (it weights the edge opposite k)"
       if any(np.allclose(_C, np.roll([[0.0, 1.0, 0.25]], _r, axis=1)) for _r in (1, 2)) else "")
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
# (-L x')_j = \sum_k L_{jk}\,(x'_j - x'_k) = \sum_{T \ni j} \sum_{(j,k) \in T} c^T_{jk}\,(x'_j - x'_k).
# $$
#
# A good check of your indexing: the Laplacian of a *linear* function $f$ vanishes
# at every interior vertex $j$ of a planar mesh (*linear precision*). Indeed
# $(-Lf)_j = \int \nabla f \cdot \nabla\varphi_j \, dA$, $\nabla f$ is constant, and
# $\int \nabla\varphi_j \, dA = 0$ for a hat function that vanishes on the boundary.
#
# **Your task.** `cotangent_laplacian(V, F)` returns the `(n, n)` sparse matrix.
# Build it from `cotangent_weights` without a loop over triangles. A
# `scipy.sparse.coo_matrix` built from (row, column, value) triples adds up
# repeated entries, which is what an interior edge with two triangles needs;
# the diagonal then follows from the rows summing to zero.

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



def _laplacian_with_weights_on(edge_of_corner):
    """The 3x3 Laplacian of the triangle above if C[0, k] were put on the edge edge_of_corner(k)."""
    _W = np.zeros((3, 3))
    for _k, _c in enumerate([0.0, 1.0, 0.25]):
        _i, _j = edge_of_corner(_k)
        _W[_i, _j] += _c
        _W[_j, _i] += _c
    return _W - np.diag(_W.sum(axis=1))


_wrong_edge = any(
    np.allclose(_L.toarray(), _laplacian_with_weights_on(_e))
    for _e in (lambda k: (k, (k + 1) % 3), lambda k: ((k + 2) % 3, k))
)
assert np.allclose(_L.toarray(), _expected), (
    f"for the triangle (0,0), (2,0), (0,1) expected L =\n{_expected}\ngot\n{np.round(_L.toarray(), 6)}"
    + ("\nthe diagonal has the wrong sign: L_ii = -Σ_j L_ij, so that every row sums to zero"
       if np.allclose(_L.toarray(), np.abs(_expected)) else "")
    + ("\neach weight sits on an edge through its corner: C[t, k] belongs to the edge OPPOSITE corner k, "
       "(F[t, (k+1)%3], F[t, (k+2)%3])" if _wrong_edge else "")
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
# Fix the positions $x'$. Then $E$ is a sum of independent terms, one per vertex,
# each depending on its own rotation only. Expand one edge term using
# $\|R_i e\| = \|e\|$ and $e'^\top R_i e = \operatorname{tr}(R_i\, e\, e'^\top)$, where
# $e = x_j - x_k$ and $e' = x'_j - x'_k$:
#
# $$
# \sum_{T \ni i} \sum_{(j,k) \in T} c_{jk} \|e' - R_i e\|^2
# = \text{const} - 2 \operatorname{tr}(R_i S_i),
# \qquad
# S_i = \sum_{T \ni i} \sum_{(j,k) \in T} c_{jk}\,(x_j - x_k)(x'_j - x'_k)^\top .
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
# third. So compute one `(d, d)` matrix per triangle first, vectorized over the
# triangles, and only then add each to its corners (mind that a vertex is a
# corner of many triangles: plain fancy-index assignment would keep only one).
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
# To watch the optimization we need $E(\mathbf x', R)$ itself. Regroup it by triangles: the
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
# ## 6 · What the energy sees
#
# Nothing moves on its own yet (stage 03b solves for the positions), but the
# energy can already judge deformations written down by hand. With every $R_i$
# fitted by the local step, $E(\mathbf x') = \min_R E(\mathbf x', R)$ is a
# function of the positions alone. Three deformations of the bar:
#
# * a **rigid motion**: the whole bar turned and moved;
# * a uniform **stretch** by 10 %, $x' = 1.1\,x$;
# * a **twist** by 90°: every cross-section turned about the bar's axis by an
#   angle that grows linearly from 0° at the left end to 90° at the right.
#
# For the stretch, §2 predicts the number. Every triangle's edges satisfy
# $\sum_k c_k\, e_k e_k^\top = A_T\, \Pi_T$ (the identity of §2 for every $J_T$),
# so each $S_i$ is $1.1$ times a symmetric positive semi-definite matrix, the
# best rotation is $R_i = I$, and each triangle costs $A_T \|0.1\,\Pi_T\|_F^2 =
# 0.02\,A_T$ in each of the three cells it belongs to: $E = 0.06 \times$ the
# area, on any mesh of the bar.
#
# **Predict first.** Which of the three costs nothing? For the twist, how much
# does fitting the rotations save over holding every $R_i = I$, and by how much
# does a cell half way along the bar turn?

# %%
def rotation(axis, angle):
    """Rotation matrix by ``angle`` (radians) about the 3D vector ``axis`` (Rodrigues)."""
    a = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    K = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
    return np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * K @ K


def twisted(V, angle):
    """The bar (its axis the x-axis, from x = 0 to x = 4) with each cross-section turned by ``angle`` × x / 4."""
    center = V.mean(axis=0)
    U = np.empty_like(V)
    for i, (x, p) in enumerate(zip(V[:, 0], V - center)):
        U[i] = rotation([1.0, 0.0, 0.0], angle * x / 4.0) @ p + center
    return U


def turn_degrees(R):
    """The angle (degrees) each 3D rotation turns by: cos θ = (tr R - 1) / 2."""
    return np.degrees(np.arccos(np.clip((np.trace(R, axis1=1, axis2=2) - 1.0) / 2.0, -1.0, 1.0)))


def area(V, F):
    return 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1).sum()


for name in ("bar_coarse", "bar"):
    Vm, Fm = load_mesh(name)
    Cm = cotangent_weights(Vm, Fm)
    U = 1.1 * Vm
    E = arap_energy(Vm, U, Fm, Cm, arap_rotations(Vm, U, Fm, Cm))
    print(f"{name:10s} ({len(Vm)} vertices) stretched by 10 %: E = {E:.4f}, E / area = {E / area(Vm, Fm):.4f}")

V, F = load_mesh("bar_coarse")
C = cotangent_weights(V, F)
motions = {
    "rigid motion": V @ rotation([1.0, 2.0, 3.0], 1.0).T + [0.5, -1.0, 2.0],
    "twist by 90°": twisted(V, np.pi / 2),
}
pictures = []
for label, U in motions.items():
    R = arap_rotations(V, U, F, C)
    fitted, identity = arap_energy(V, U, F, C, R), arap_energy(V, U, F, C, np.tile(np.eye(3), (len(V), 1, 1)))
    print(f"{label:12s}: E = {fitted:.4f} with the fitted rotations, {identity:.4f} with every R_i = I")
middle = np.abs(V[:, 0] - 2.0) < 1e-9
print(f"twist: the cells half way along the bar turned by {turn_degrees(R[middle]).mean():.1f}° on average "
      f"(the cross-section there turned by 45°), those at the right end by {turn_degrees(R[V[:, 0] > 4.0 - 1e-9]).mean():.1f}°")
plotting.show_meshes([(V, F), (U, F, turn_degrees(R))], titles=["rest", "twisted by 90°"],
                     label="angle of the fitted R_i (°)")

# %% [markdown]
# The stretch costs the same per unit of area on both meshes
# (<span class="measured">0.0600</span>), as §2 promised, and the rigid motion costs nothing.
# The fitted rotations follow the twist: a cell half way along the bar turns by
# <span class="measured">45.7</span>° on average, about as much as its cross-section, and one at
# the right end by <span class="measured">89.8</span>°. What the energy measures is what is left
# after each cell's rotation, the shear and bending of the bar's sides: the
# twist costs <span class="measured">1.1794</span>, about as much as the 10 % stretch of the same
# bar (<span class="measured">1.0800</span>), though it moves the right end much farther. Measured
# against $R_i = I$ instead, the same twist costs <span class="measured">49.4314</span> and even the
# rigid motion <span class="measured">70.5308</span>: without fitted rotations the energy would
# punish every turn.
#
# **Predict first.** Now the 2D character is mirrored, $x' = (-x, y)$. The cell
# below measures it twice: with your `arap_rotations`, and with the best
# *orthogonal* matrix of stage 01 in the local step (no sign correction). What
# energy do you expect from each, and how many of the $R_i$ will be
# reflections?

# %%
V2, F2 = load_mesh("character")
C2 = cotangent_weights(V2, F2)
mirrored = V2 * [-1.0, 1.0]


def best_orthogonal(S):
    """Stage 01's Ũ Uᵀ for a stack of S: possibly reflections."""
    U_svd, _, U_tilde_T = np.linalg.svd(S)
    return np.swapaxes(U_tilde_T, -1, -2) @ np.swapaxes(U_svd, -1, -2)


local_steps = {
    "best orthogonal (no sign correction)": best_orthogonal(arap_covariances(V2, mirrored, F2, C2)),
    "best rotation (arap_rotations)": arap_rotations(V2, mirrored, F2, C2),
}
pictures = []
for label, R in local_steps.items():
    reflections = np.linalg.det(R) < 0
    print(f"{label:37s}: energy {arap_energy(V2, mirrored, F2, C2, R):.4f}, "
          f"{reflections.sum():4d} of {len(V2)} R_i are reflections")
    pictures.append((mirrored, F2, reflections.astype(float)))
plotting.show_meshes(pictures, titles=list(local_steps), label="R_i", categories=("rotation", "reflection"))

# %% [markdown]
# **Question.** With the best orthogonal matrices the mirror image costs
# nothing; with rotations it costs a lot. Why does it cost nothing without the
# sign correction, and which of the two energies describes what a user of the
# character would call a deformation? Say what the mirror image does to every
# triangle, and what a solver built on the first local step could do where
# the handles ask for a strong bend.

# %% [markdown] deformlab={"answer": "arap_reflections", "points": 2}
# The mirror maps every rest edge e to D e with D = diag(−1, 1), so each cell's
# deformed edges are exactly its rest edges reflected: S_i = (Σ c e eᵀ) D, its
# best orthogonal matrix is the reflection D, and every term ‖D e − R_i e‖²
# vanishes (energy <span class="measured">0.0000</span>, every R_i a reflection). The energy
# only compares edge vectors, and a reflection keeps every length and angle.
# But it reverses the orientation of every triangle: the mirror image is the
# character turned inside out, which no motion in the plane reaches without
# collapsing triangles on the way. With R_i restricted to rotations, the
# energy sees that: no rotation maps a cell onto its mirror image, and the
# mirror costs <span class="measured">19.9067</span>. A solver whose local step
# may return reflections is rewarded for mirroring a cell wherever that fits
# the handles better than turning it (around a strong bend, where the edges
# cross), and then places that cell's triangles inside out.
