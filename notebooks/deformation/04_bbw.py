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
# # 04 · Bounded biharmonic weights
#
# *Workload: about 5.5 hours for 5 graded functions (13 points) and 2 written answers (an estimate for a student who attended the lecture).*
#
# Linear blend skinning (stage 05) moves every vertex by a blend of the handles'
# transformations, $x' = \sum_j w_j(x)\, T_j [x; 1]$. The pose is only the $m$
# transformations; everything the shape "knows" about how it bends is in the
# **weight functions** $w_j$, one per handle, computed once on the rest shape.
# What should they look like?
#
# * **interpolation:** $w_j = 1$ on handle $j$ and $0$ on every other handle, so
#   that a handle moves exactly as the user says;
# * **smoothness:** the deformation is as smooth as the weights, also *at* the
#   handles;
# * **partition of unity:** $\sum_j w_j = 1$, so that moving every handle by the
#   same rigid motion moves the shape rigidly;
# * **non-negativity and locality:** $0 \le w_j \le 1$, and $w_j$ is large only
#   near handle $j$ and fades to zero where other handles take over;
# * **shape awareness:** "near" is measured inside the shape, not through the
#   air: a hand should not pull the leg next to it.
#
# Bounded biharmonic weights (BBW, Jacobson et al. 2011) get all of these from one
# optimization: for each handle $j$,
#
# $$
# w_j = \arg\min_{w} \; \tfrac12 \int_\Omega (\Delta w)^2 \, dA
# \quad\text{subject to}\quad w|_{H_k} = \delta_{jk},\;\; 0 \le w \le 1,
# $$
#
# followed by normalizing every vertex's weights to sum to one. This notebook
# discretizes the biharmonic energy with the finite-element matrices of stage 03,
# compares naive inverse-distance weights and unconstrained biharmonic weights,
# and then adds the bounds.

# %%
import numpy as np
import scipy.sparse as sp

from starter import load_handles, load_mesh, plotting, shapes

rng = np.random.default_rng(4)

# %% [markdown]
# ## 1 · The cotangent Laplacian (from stage 03)
#
# Bring `cotangent_weights` and `cotangent_laplacian` from stage 03 (they were
# graded there; their tests here only help you check the copy). As a
# reminder: `C[t, k]` $= \tfrac12\cot$ of the angle at corner `k` of triangle `t`,
# weighting the opposite edge; $L_{jk} = \sum_{T \ni (j,k)} c^T_{jk}$ and
# $L_{jj} = -\sum_{k\ne j} L_{jk}$. On a triangle mesh, $-L$ is the finite-element
# *stiffness matrix* of piecewise-linear "hat" functions $\varphi_j$:
# $-L_{jk} = \int_\Omega \nabla\varphi_j \cdot \nabla\varphi_k \, dA$.

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

# %% deformlab={"tests": "cotangent_weights"}
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
_V3 = np.hstack([_V, np.zeros((3, 1))]) @ np.array([[0.0, 0.6, 0.8], [1.0, 0.0, 0.0], [0.0, 0.8, -0.6]])
assert np.allclose(cotangent_weights(3.0 * _V3, _F), _C), "a rotated, scaled copy of a triangle in 3D must get the same weights"

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

# %% deformlab={"tests": "cotangent_laplacian"}
_V = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 1.0]])
_L = cotangent_laplacian(_V, np.array([[0, 1, 2]]))
assert sp.issparse(_L), f"L must be a scipy.sparse matrix, got {type(_L).__name__}"
_expected = np.array([[-1.25, 0.25, 1.0], [0.25, -0.25, 0.0], [1.0, 0.0, -1.0]])
assert np.allclose(_L.toarray(), _expected), (
    f"for the triangle (0,0), (2,0), (0,1) expected L =\n{_expected}\ngot\n{np.round(_L.toarray(), 6)}"
    + ("\nthe diagonal has the wrong sign: L_ii = -Σ_j L_ij, so that every row sums to zero"
       if np.allclose(_L.toarray(), np.abs(_expected)) else "")
)
_V, _F = load_mesh("character")
_L = sp.csr_matrix(cotangent_laplacian(_V, _F))
assert abs(_L - _L.T).max() < 1e-12, "L must be symmetric"
_rows = np.abs(np.asarray(_L.sum(axis=1))).ravel()
assert _rows.max() < 1e-10, f"every row of L must sum to 0; row {_rows.argmax()} sums to {_rows.max():.3e}"
# Linear functions are exact: for f = V a, -fᵀ L f is the integral of ‖∇f‖² = ‖a‖² × area.
_e1, _e2 = _V[_F[:, 1]] - _V[_F[:, 0]], _V[_F[:, 2]] - _V[_F[:, 0]]
_area = np.sum(0.5 * np.abs(_e1[:, 0] * _e2[:, 1] - _e1[:, 1] * _e2[:, 0]))
_f = _V @ np.array([1.0, -0.5])
assert np.isclose(-_f @ (_L @ _f), 1.25 * _area, rtol=1e-9), (
    f"for the linear function f = x - y/2, -fᵀ L f must be ∫‖∇f‖² = 1.25 × area = {1.25 * _area:.10g}, "
    f"got {-_f @ (_L @ _f):.10g}"
)

# %% [markdown]
# ## 2 · The biharmonic energy
#
# To discretize $\int (\Delta w)^2$ we need $\Delta w$ *at the vertices*. The
# Laplacian matrix gives an *integrated* quantity: $(L w)_i = \int \Delta w\,\varphi_i \, dA$
# (up to boundary terms), an average of $\Delta w$ over the region around vertex
# $i$ weighted by the hat function, whose integral is about the area $M_{ii}$ of
# that region. The **mass matrix** $M$ turns one into the other: the pointwise
# Laplacian is $M^{-1} L w$. With the lumped (diagonal, Voronoi-area) mass matrix,
# integrating a squared function is $\int f^2 \approx f^\top M f$, so
#
# $$
# \int_\Omega (\Delta w)^2 \, dA \;\approx\; (M^{-1} L w)^\top M \,(M^{-1} L w) \;=\; w^\top Q\, w,
# \qquad Q = L\, M^{-1} L .
# $$
#
# This is a *mixed* finite-element discretization: the fourth-order operator is
# split into two second-order ones, so piecewise-linear elements suffice. $Q$ is
# symmetric and positive semi-definite ($w^\top Q w = \|Lw\|^2_{M^{-1}}$), sparse
# (two-ring neighbours), and its null space contains the constants. The outline
# gets no explicit constraint, but it is not free of assumptions either. $L$ is
# assembled with zero-Neumann conditions (a row of $L$ at the outline only sees
# the triangles inside), and squaring it bakes $\partial w / \partial n = 0$ into
# $Q$: the weights are biased near the boundary, their level lines pushed to
# meet it at right angles. Those are not the *natural* boundary conditions of
# $\int (\Delta w)^2$, and the bias does not go away under refinement (Stein,
# Grinspun, Wardetzky and Jacobson, *Natural boundary conditions for smoothing
# in geometry processing*, ACM TOG 2018). BBW, and libigl's `bbw`, use this $Q$
# all the same; prescribing $w = 0$ on the boundary instead would pin the
# outline in place.
#
# Units are a good check: in 2D, $L$ is scale-invariant (cotangents only see
# angles) while $M$ is an area. Scaling the shape by $s$ therefore scales $Q$ by
# $s^{-2}$, as it must for $\int(\Delta w)^2\,dA$.
#
# **Your task.** `biharmonic_matrix(V, F)` returns the sparse $Q$, with
# `M = igl.massmatrix(V, F)` (libigl's default, the Voronoi mass matrix) and your
# `cotangent_laplacian`. $M$ is diagonal: invert its diagonal, do not call a
# general inverse.

# %% deformlab={"solution": "biharmonic_matrix"}
import igl
import numpy as np
import scipy.sparse as sp


def biharmonic_matrix(V, F):
    """The biharmonic energy matrix ``Q = L M⁻¹ L``.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions.
    F : (f, 3) array_like of int
        Triangles.

    Returns
    -------
    Q : (n, n) scipy.sparse matrix
        ``L = cotangent_laplacian(V, F)``, ``M = igl.massmatrix(V, F)`` (Voronoi, diagonal).
    """
    ### BEGIN SOLUTION
    V, F = np.asarray(V, dtype=float), np.asarray(F, dtype=np.int64)
    L = cotangent_laplacian(V, F)
    M = igl.massmatrix(V, F)
    M_inverse = sp.diags(1.0 / M.diagonal())  # M is diagonal: invert its diagonal only
    return (L @ M_inverse @ L).tocsr()
    ### END SOLUTION

# %% deformlab={"tests": "biharmonic_matrix", "points": 2}
import igl as _igl  # noqa: E402

_V, _F = load_mesh("character")
_Q = sp.csr_matrix(biharmonic_matrix(_V, _F))
assert _Q.shape == (len(_V), len(_V)), f"Q must be (n, n) = {(len(_V), len(_V))}, got {_Q.shape}"
assert abs(_Q - _Q.T).max() < 1e-8 * abs(_Q).max(), "Q = L M⁻¹ L must be symmetric"
_ones = np.abs(_Q @ np.ones(len(_V))).max()
assert _ones < 1e-8 * abs(_Q).max(), f"constants must be in the null space of Q; |Q 1| reaches {_ones:.3e}"
_x = rng.normal(size=len(_V))
_Lx = sp.csr_matrix(cotangent_laplacian(_V, _F)) @ _x
_expected = _Lx @ (_Lx / _igl.massmatrix(_V, _F).diagonal())
assert np.isclose(_x @ _Q @ _x, _expected, rtol=1e-9), (
    f"xᵀ Q x must equal (Lx)ᵀ M⁻¹ (Lx) = {_expected:.8g} with the Voronoi mass matrix, got {_x @ _Q @ _x:.8g}"
    + (": that is (Lx)ᵀ(Lx), Q = L L; the mass matrix M⁻¹ is missing between the two Laplacians"
       if np.isclose(_x @ _Q @ _x, _Lx @ _Lx, rtol=1e-9) else "")
)
_ratio = (_x @ sp.csr_matrix(biharmonic_matrix(2.0 * _V, _F)) @ _x) / (_x @ _Q @ _x)
assert np.isclose(_ratio, 0.25), (
    f"scaling a 2D shape by 2 must scale Q by 1/4 (L is scale-invariant, M is an area); the ratio is {_ratio:.4g}"
    + (" (did you forget M⁻¹?)" if np.isclose(_ratio, 1.0) else "")
)

# %% [markdown]
# ## 3 · Handles as constraints
#
# A handle is a set of vertices: one vertex for a *point* handle, the vertices
# along a segment for a *bone*, the vertices of a patch for a *region*. All the
# weight functions are constrained on all the handle vertices at once: weight
# $j$ is 1 on the vertices of handle $j$ and 0 on those of every other handle.
# We store this as libigl does: `b`, the concatenation of the handles' vertex
# indices, and `bc`, a `(len(b), m)` array whose row for a vertex of handle $j$
# is the one-hot row $e_j$. Column $j$ of `bc` gives the values of $w_j$ at `b`.
#
# **Your task.** `handle_constraints(handles)` builds `(b, bc)` from a list of
# index arrays, one per handle.

# %% deformlab={"solution": "handle_constraints"}
import numpy as np


def handle_constraints(handles):
    """The interpolation constraints ``W[b] = bc`` of a list of handles.

    Parameters
    ----------
    handles : list of array_like of int
        One array of vertex indices per handle (one vertex for a point handle,
        several for a bone or a region).

    Returns
    -------
    b : (k,) numpy.ndarray of int
        The handles' vertices, concatenated in order.
    bc : (k, m) numpy.ndarray
        1 in the column of each vertex's own handle, 0 elsewhere.
    """
    ### BEGIN SOLUTION
    handles = [np.asarray(h, dtype=np.int64).reshape(-1) for h in handles]
    b = np.concatenate(handles)
    owner = np.concatenate([np.full(len(h), j) for j, h in enumerate(handles)])  # handle of each row of b
    bc = np.zeros((len(b), len(handles)))
    bc[np.arange(len(b)), owner] = 1.0
    return b, bc
    ### END SOLUTION

# %% deformlab={"tests": "handle_constraints", "points": 2}
_b, _bc = handle_constraints([np.array([3]), np.array([5, 7]), np.array([1])])
assert np.array_equal(_b, [3, 5, 7, 1]), f"b must concatenate the handles in order, [3, 5, 7, 1], got {np.asarray(_b).tolist()}"
_expected = np.array([[1, 0, 0], [0, 1, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
assert np.array_equal(_bc, _expected), (
    f"bc must have one row per vertex of b and one column per handle, 1 in the column of the "
    f"vertex's handle:\n{_expected}\ngot\n{np.asarray(_bc)}"
    + ("\nthe columns are in reverse order: column j belongs to handles[j]"
       if np.array_equal(np.asarray(_bc), _expected[:, ::-1]) else "")
)
_regions = load_handles("character")["regions"]
_b, _bc = handle_constraints(_regions)
assert _bc.shape == (sum(len(_r) for _r in _regions), len(_regions)), f"for the 3 region handles bc must be {(len(_b), 3)}, got {_bc.shape}"
assert np.array_equal(_bc.sum(axis=1), np.ones(len(_b))), "every row of bc must be one-hot"

# %% [markdown]
# ## 4 · A naive baseline: inverse-distance weights
#
# The simplest weights that interpolate and sum to one are Shepard's
# inverse-distance weights for handle points $h_j$,
#
# $$
# w_j(x) = \frac{\|x - h_j\|^{-p}}{\sum_k \|x - h_k\|^{-p}} ,
# $$
#
# with $w_j(h_j) = 1$ as the limit. They are positive and a partition of unity,
# but they have two flaws you can see in the picture below.
#
# * **Flat spots.** For $p > 1$, $w_j$ has zero gradient at *every* handle point:
#   near its own handle it is flat at 1, near any other it is flat at 0. Each
#   handle drags a little neighbourhood rigidly and the deformation concentrates in
#   between; far from all handles every weight tends to $1/m$, so distant parts
#   move with the average of all handles.
# * **No shape awareness.** The distance is Euclidean, measured through the air:
#   a vertex gets the same weight from a handle whether the two are connected
#   through the shape or only across a gap. Handles on two fingers that nearly
#   touch pull on each other's finger, and a hole in the shape makes no
#   difference at all.
#
# **Your task.** `inverse_distance_weights(V, handle_points, power=2)` returns the
# `(n, m)` weights. Vertices closer than 1e-12 to a handle point would divide by
# zero: give them that handle's one-hot row.

# %% deformlab={"solution": "inverse_distance_weights"}
import numpy as np


def inverse_distance_weights(V, handle_points, power=2):
    """Shepard's inverse-distance weights.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions.
    handle_points : (m, d) array_like of float
        Distinct handle positions.
    power : float
        The exponent of the distance.

    Returns
    -------
    W : (n, m) numpy.ndarray
        ``W[i, j] ∝ ‖x_i - h_j‖^-power``, rows summing to 1; a vertex within 1e-12 of a
        handle point gets that handle's one-hot row.
    """
    ### BEGIN SOLUTION
    V, H = np.asarray(V, dtype=float), np.asarray(handle_points, dtype=float)
    D = np.linalg.norm(V[:, None, :] - H[None, :, :], axis=2)  # (n, m) distances
    nearest = np.argmin(D, axis=1)
    on_handle = D[np.arange(len(V)), nearest] <= 1e-12
    W = np.zeros_like(D)
    W[~on_handle] = D[~on_handle] ** -float(power)
    W[on_handle, nearest[on_handle]] = 1.0  # on a handle point: that handle alone
    return W / W.sum(axis=1, keepdims=True)
    ### END SOLUTION

# %% deformlab={"tests": "inverse_distance_weights", "points": 2}
_W = inverse_distance_weights(np.array([[1.0, 0.0], [3.0, 0.0]]), np.array([[0.0, 0.0], [4.0, 0.0]]))
_expected = np.array([[0.9, 0.1], [0.1, 0.9]])
assert np.allclose(_W, _expected), (
    f"points at distances (1, 3) and (3, 1) from two handles, power 2: weights ∝ (1, 1/9), i.e. "
    f"{_expected.tolist()}, got {np.round(_W, 6).tolist()}"
    + (": that is power 1; weight by 1 / distance**power" if np.allclose(_W, [[0.75, 0.25], [0.25, 0.75]]) else "")
)
_W = inverse_distance_weights(np.array([[1.0, 0.0]]), np.array([[0.0, 0.0], [3.0, 0.0]]), power=1)
assert np.allclose(_W, [[2 / 3, 1 / 3]]), f"power 1 at distances (1, 2): weights (2/3, 1/3), got {np.round(_W, 6).tolist()}"

_V, _F = load_mesh("character")
_points = load_handles("character")["points"]
_W = inverse_distance_weights(_V, _V[_points])
assert _W.shape == (len(_V), len(_points)), f"expected shape {(len(_V), len(_points))}, got {_W.shape}"
assert np.isfinite(_W).all(), "weights must be finite, also at the handle points themselves"
assert np.allclose(_W.sum(axis=1), 1.0), "every row must sum to 1"
assert np.allclose(_W[_points], np.eye(len(_points))), "a vertex at a handle point must get that handle's one-hot row"

# %%
V, F = load_mesh("character")
character_handles = load_handles("character")
points = character_handles["points"]  # head top, left hand, right hand, left foot, right foot
point_names = ["head", "left hand", "right hand", "left foot", "right foot"]
W_idw = inverse_distance_weights(V, V[points])
plotting.show_weights(V, F, W_idw, handles=points, titles=[f"inverse distance: {name}" for name in point_names])

# %% [markdown]
# **The fall-off.** The lecture: "inverse distance methods inherently suffer from
# the fall-off effect", every weight "approaching" the same value far from the
# handles. **Predict first.** Far from all $m = 5$ handles, what value does each
# inverse-distance weight approach, and how fast does the largest difference
# from it shrink with the distance $r$: like $1/r$, like $1/r^2$, or
# exponentially? Below, the points lie on a ray from the character's centre,
# $r$ = 1 to 64 times its height away.

# %%
centre, height = V.mean(axis=0), np.ptp(V[:, 1])
direction = np.array([1.0, 0.3]) / np.linalg.norm([1.0, 0.3])
m = len(points)
for r in (1, 4, 16, 64):
    w = inverse_distance_weights(centre + r * height * direction[None, :], V[points])[0]
    spread = np.abs(w - 1 / m).max()
    print(f"r = {r:2d} heights: weights {np.round(w, 4).tolist()}, largest |w_j - 1/m| = {spread:.5f}, "
          f"r × that = {r * spread:.4f}")
inside = inverse_distance_weights(V, V[points]).max(axis=1)
print(f"on the character itself, {np.mean(inside < 0.5):.0%} of the vertices have no weight above 0.5 "
      f"(the least dominated vertex: largest weight {inside.min():.3f}, against 1/m = {1 / m:.3f})")

# %% [markdown]
# Every weight tends to $1/m = 0.2$, and slowly: $r$ times the largest
# difference levels off (the last column: <span class="measured">0.2986</span>, <span class="measured">0.2085</span>, <span class="measured">0.1912</span>,
# <span class="measured">0.1873</span> for $r$ = 1, 4, 16, 64 heights), so the difference shrinks like
# $1/r$. Expanding $\|x - h_j\|^{-2}$ for $\|x\| = r$ much larger than the handles'
# spread gives $w_j \approx \frac1m + \frac2m\,\frac{\hat x \cdot (h_j - \bar h)}{r}$
# ($\hat x$ the direction, $\bar h$ the handles' mean): the leading correction
# is of order $1/r$. A part of a shape far from every handle therefore moves
# with the *average* of all handle transformations, whatever the shape, and
# already on the character <span class="measured">36%</span> of the vertices have no weight above 0.5.

# %% [markdown]
# ## 5 · Unconstrained biharmonic weights
#
# Now minimize the biharmonic energy with only the interpolation constraints.
# Split the vertices into the constrained ones `b` and the free ones `f`; for a
# weight column $w$ with $w_b$ fixed,
#
# $$
# \tfrac12 w^\top Q w = \tfrac12 w_f^\top Q_{ff} w_f + w_f^\top Q_{fb} w_b + \text{const}
# \quad\Longrightarrow\quad
# Q_{ff}\, W_f = -Q_{fb}\, \mathrm{bc} ,
# $$
#
# one sparse solve with $m$ right-hand sides ($Q_{ff}$ is positive definite once
# a handle pins the shape). These weights already form a partition of unity,
# with no normalization: the row sums $s = W\mathbf 1$ solve the same system with
# right-hand side $-Q_{fb}\mathbf 1$ and $s_b = 1$, and the constant 1 is that
# solution because $Q\mathbf 1 = 0$. They are smooth and shape-aware (the
# energy lives on the mesh). But they are **not positive**: a fourth-order
# problem has no maximum principle, and the minimizer overshoots around the
# handles like a bent elastic beam, with negative *lobes* where it swings back.

# %% deformlab={"solution": "unconstrained_biharmonic_weights"}
import numpy as np
import scipy.sparse.linalg as spla


def unconstrained_biharmonic_weights(V, F, b, bc):
    """The weights minimizing ``½ tr(Wᵀ Q W)`` subject to ``W[b] = bc``, without bounds.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions.
    F : (f, 3) array_like of int
        Triangles.
    b : (k,) array_like of int
        Constrained vertices.
    bc : (k, m) array_like of float
        Their values, one column per handle.

    Returns
    -------
    W : (n, m) numpy.ndarray
    """
    ### BEGIN SOLUTION
    b, bc = np.asarray(b, dtype=np.int64), np.asarray(bc, dtype=float)
    Q = biharmonic_matrix(V, F).tocsr()
    free = np.setdiff1d(np.arange(len(V)), b)
    W = np.zeros((len(V), bc.shape[1]))
    W[b] = bc
    # Q_ff W_f = -Q_fb bc: one factorization, m right-hand sides
    W[free] = spla.splu(Q[free][:, free].tocsc()).solve(-(Q[free][:, b] @ bc))
    return W
    ### END SOLUTION

# %% deformlab={"tests": "unconstrained_biharmonic_weights", "points": 3}
_V, _F = load_mesh("character")
_handles = [np.array([_p]) for _p in load_handles("character")["points"]]
_b, _bc = handle_constraints(_handles)
_W = unconstrained_biharmonic_weights(_V, _F, _b, _bc)
assert _W.shape == (len(_V), len(_handles)), f"expected shape {(len(_V), len(_handles))}, got {_W.shape}"
assert np.allclose(_W[_b], _bc), "W[b] must equal bc"
_free = np.setdiff1d(np.arange(len(_V)), _b)
_Q = sp.csr_matrix(biharmonic_matrix(_V, _F))
_residual = np.abs((_Q @ _W)[_free]).max()
assert _residual < 1e-8 * abs(_Q).max(), (
    f"at the free vertices the gradient Q W must vanish (the weights minimize ½ wᵀQw); it reaches {_residual:.3e}"
)
_sums = np.abs(_W.sum(axis=1) - 1.0).max()
assert _sums < 1e-8, f"unconstrained biharmonic weights sum to 1 by themselves; off by up to {_sums:.3e}"
assert _W.min() < -1e-3, "these weights should go negative somewhere (the lobes); did you clip or bound them?"

# %% [markdown]
# ## 6 · Bounded biharmonic weights
#
# Why do negative weights matter? Translate handle $j$ by $t$ and leave the
# others: every vertex moves by $w_j(x)\,t$. Where $w_j < 0$ the vertex moves
# **against** the handle: pull one hand up and patches around the other handles
# move down. Weights above 1 overshoot: those vertices move further than the
# handle itself. BBW adds the bounds to
# each handle's problem,
#
# $$
# \min_{w}\; \tfrac12 w^\top Q w
# \quad\text{subject to}\quad w_b = \mathrm{bc}_{:,j}, \quad 0 \le w \le 1 ,
# $$
#
# a convex quadratic program with simple bounds. Clipping the unconstrained
# weights to $[0, 1]$ is *not* its solution: cutting off a lobe leaves a kink,
# and the minimizer instead re-arranges the whole weight function so that it
# meets the bound smoothly. At the minimum, the KKT conditions say: where
# $0 < w_i < 1$ the gradient $(Qw)_i$ vanishes; where $w_i = 0$ it is
# $\ge 0$ (lowering the energy would need a negative weight); where $w_i = 1$ it
# is $\le 0$.
#
# **Solving the QP.** An active-set method solves it with a few sparse solves:
# guess the set of free vertices that sit at a bound, fix them at their bound
# like extra constraints, solve the equality-constrained problem exactly as in
# §5, then add every vertex that violates a bound and release every bound vertex
# whose gradient has the wrong sign (its multiplier says the energy would drop by
# moving it inside); repeat until nothing changes. (Do not call
# `igl.active_set`: its Python binding ignores the bounds.)
#
# **Normalization.** Each handle's problem is solved separately, so the bounded
# weights no longer sum to exactly one; dividing every row by its sum restores
# the partition of unity (and keeps the bounds and the interpolation). That is
# what makes LBS reproduce rigid motions: if every $T_j = T$ then
# $x' = \sum_j w_j T[x;1] = T[x;1]$.
#
# **Your task.** `bbw(V, F, b, bc)` returns the normalized `(n, m)` weights, within
# `[0, 1]` and summing to one to 1e-9.

# %% deformlab={"solution": "bbw"}
import numpy as np
import scipy.sparse.linalg as spla


def bbw(V, F, b, bc):
    """Bounded biharmonic weights: one bound-constrained QP per handle, then rows normalized.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions.
    F : (f, 3) array_like of int
        Triangles.
    b : (k,) array_like of int
        Constrained vertices.
    bc : (k, m) array_like of float
        Their values, one column per handle.

    Returns
    -------
    W : (n, m) numpy.ndarray
        For each handle ``j``, ``w`` minimizes ``½ wᵀ Q w`` subject to ``w[b] = bc[:, j]``
        and ``0 ≤ w ≤ 1``; then each row is divided by its sum.
    """
    ### BEGIN SOLUTION
    b, bc = np.asarray(b, dtype=np.int64), np.asarray(bc, dtype=float)
    Q = biharmonic_matrix(V, F).tocsr()
    free = np.setdiff1d(np.arange(len(V)), b)
    Q_ff = Q[free][:, free].tocsr()
    W = np.zeros((len(V), bc.shape[1]))
    W[b] = bc
    for j in range(bc.shape[1]):
        # Over the free values x: minimize ½ xᵀ Q_ff x + gᵀ x subject to 0 ≤ x ≤ 1.
        g = Q[free][:, b] @ bc[:, j]
        at_0 = np.zeros(len(free), dtype=bool)  # the active set: free values held at a bound
        at_1 = np.zeros(len(free), dtype=bool)
        for _ in range(1000):
            x = at_1.astype(float)
            inside = ~(at_0 | at_1)
            # the equality-constrained problem of §5 on the values not held at a bound
            rhs = -(g[inside] + Q_ff[inside][:, ~inside] @ x[~inside])
            # The matrix is symmetric positive definite: tell SuperLU so (no pivoting, a symmetric ordering).
            lu = spla.splu(Q_ff[inside][:, inside].tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                           options={"SymmetricMode": True})
            x[inside] = lu.solve(rhs)
            gradient = Q_ff @ x + g
            tolerance = 1e-12 * (np.abs(g).max() + 1e-300)
            # add every value that left [0, 1]; release every held value whose gradient points inside
            new_0 = (at_0 & (gradient >= -tolerance)) | (inside & (x < 0))
            new_1 = (at_1 & (gradient <= tolerance)) | (inside & (x > 1))
            if np.array_equal(new_0, at_0) and np.array_equal(new_1, at_1):
                break
            at_0, at_1 = new_0, new_1
        else:
            raise RuntimeError(f"bbw: the active set of handle {j} did not settle in 1000 rounds")
        W[free, j] = np.clip(x, 0.0, 1.0)  # inside values are in [0, 1] up to round-off
    return W / W.sum(axis=1, keepdims=True)
    ### END SOLUTION

# %% deformlab={"tests": "bbw", "points": 4}
_V, _F = load_mesh("character")
_handles = [np.array([_p]) for _p in load_handles("character")["points"]]
_b, _bc = handle_constraints(_handles)
_W = bbw(_V, _F, _b, _bc)
assert _W.shape == (len(_V), len(_handles)), f"expected shape {(len(_V), len(_handles))}, got {_W.shape}"
assert np.allclose(_W[_b], _bc), "W[b] must equal bc"
assert _W.min() >= -1e-9 and _W.max() <= 1 + 1e-9, (
    f"weights must lie in [0, 1], got values in [{_W.min():.3e}, {_W.max():.6f}]"
)
_sums = np.abs(_W.sum(axis=1) - 1.0)
assert _sums.max() < 1e-9, f"every row must sum to 1 (normalize!); row {_sums.argmax()} sums to {_W[_sums.argmax()].sum():.6f}"

# With two handles, w_2 = 1 - w_1 solves the second problem, so the rows already sum
# to one and column 0 is the bounded minimizer itself. Clipping the unconstrained
# weights gives a feasible candidate; the minimizer must have a clearly lower energy.
_b, _bc = handle_constraints([_handles[1], _handles[4]])  # left hand, right foot
_w = bbw(_V, _F, _b, _bc)[:, 0]
_Q = sp.csr_matrix(biharmonic_matrix(_V, _F))
_clipped = np.clip(unconstrained_biharmonic_weights(_V, _F, _b, _bc)[:, 0], 0.0, 1.0)
_E, _E_clipped = 0.5 * _w @ _Q @ _w, 0.5 * _clipped @ _Q @ _clipped
assert _E < 0.99 * _E_clipped, (
    f"the bounded weights must minimize ½ wᵀQw: their energy {_E:.6g} is not below that of the clipped "
    f"unconstrained weights, {_E_clipped:.6g} (clipping is feasible but not optimal: solve the bounded problem)"
)
# The minimizer's optimality conditions (KKT): the gradient g = Q w at the free vertices is >= 0
# where w = 0, <= 0 where w = 1 and 0 in between. A negative g_i means raising w_i lowers the energy,
# a positive one lowering it; w_i may only sit at the bound that blocks that move.
_free = np.setdiff1d(np.arange(len(_V)), _b)
_g, _wf = (_Q @ _w)[_free], _w[_free]
_tol = 1e-3 * np.abs(_Q @ _w).max()
_wrong = ((_g < -_tol) & (_wf < 1 - 1e-6)) | ((_g > _tol) & (_wf > 1e-6))
if _wrong.any():
    _i = np.flatnonzero(_wrong)[np.abs(_g[_wrong]).argmax()]
    _where = "w = 0" if _wf[_i] <= 1e-6 else "w = 1" if _wf[_i] >= 1 - 1e-6 else f"w = {_wf[_i]:.4f}"
    raise AssertionError(
        f"vertex {_free[_i]} has {_where} but the gradient (Q w)_i = {_g[_i]:.4g}: the weights do not minimize "
        "½ wᵀQw (at the minimum (Q w)_i ≥ 0 where w = 0, ≤ 0 where w = 1, and 0 in between)"
        + (": an active-set loop must also release a held value whose gradient points back into [0, 1]"
           if _wf[_i] <= 1e-6 or _wf[_i] >= 1 - 1e-6 else
           ": is each handle's problem solved with both bounds, 0 ≤ w ≤ 1, before the rows are normalized?")
    )

# %% [markdown]
# ## 7 · Comparing the weights
#
# First the point handles. The three panels show the weight of the left foot
# for inverse-distance, unconstrained biharmonic and bounded biharmonic weights
# (in this order; magenta marks values below 0, red above 1), then all five BBW
# weights. Look for the flat spot of the inverse-distance weight around its
# handle and how it spreads evenly over the body; the unconstrained weight
# overshooting above 1 around its own handle and dipping below 0 around the
# others; and how BBW keeps the smoothness without either.

# %%
b, bc = handle_constraints([np.array([p]) for p in points])
W_unconstrained = unconstrained_biharmonic_weights(V, F, b, bc)
W_bbw = bbw(V, F, b, bc)
for label, W in (("inverse distance", W_idw), ("unconstrained biharmonic", W_unconstrained), ("bounded biharmonic", W_bbw)):
    print(f"{label:26s} weights in [{W.min():+.3f}, {W.max():.3f}], "
          f"{np.mean((W < -1e-9).any(axis=1)):5.1%} of the vertices have a negative weight")
foot = 3
plotting.show_weights(V, F, np.stack([W_idw[:, foot], W_unconstrained[:, foot], W_bbw[:, foot]], axis=1), handles=points,
                      titles=[f"{method}: left foot" for method in ("inverse distance", "unconstrained biharmonic", "BBW")])
plotting.show_weights(V, F, W_bbw, handles=[np.array([p]) for p in points], titles=[f"BBW: {name}" for name in point_names])

# %% [markdown]
# The print says it in numbers: the unconstrained weights leave $[0, 1]$ on both
# sides (from <span class="measured">−0.016</span> to <span class="measured">1.036</span>), and <span class="measured">11.4</span>% of the vertices have a negative
# weight for at least one handle; inverse-distance and bounded biharmonic
# weights keep every weight in $[0, 1]$.
#
# Larger handles constrain more and the lobes grow. With the three region
# handles (head, left foot, right foot) the unconstrained weight of the left
# foot dips to about −0.1 over the whole right arm. Pull the left foot to the
# left and keep the other two handles: with translations only, every vertex
# moves by $w_{\text{foot}}(x)\,t$, coloured below by that weight.

# %%
regions = character_handles["regions"]
b, bc = handle_constraints(regions)
foot = 1
w_unconstrained = unconstrained_biharmonic_weights(V, F, b, bc)[:, foot]
w_bbw = bbw(V, F, b, bc)[:, foot]
t = np.array([-0.8, 0.0])
right_hand = points[2]
for label, w in (("unconstrained", w_unconstrained), ("bounded", w_bbw)):
    print(f"{label:13s}: the right hand moves by {round(w[right_hand] * t[0], 3) + 0.0:+.3f} in x while the foot moves by {t[0]:+.1f}")
plotting.show_meshes(
    [(V + w_unconstrained[:, None] * t, F, w_unconstrained), (V + w_bbw[:, None] * t, F, w_bbw)],
    titles=["unconstrained biharmonic", "bounded biharmonic"], label="weight of the left foot",
)

# %% [markdown]
# The foot goes left, and with the unconstrained weights the right hand goes
# *right* (by <span class="measured">+0.087</span>): a negative weight turns every handle motion
# around. With the bounded weights it stays put (<span class="measured">+0.000</span>).

# %% [markdown]
# **Predict first.** A fork: two prongs side by side, 0.07 apart, joined only at
# the bottom, with a point handle on top of each prong and one at the base. Pull
# the left prong's handle up by 0.3. Before running the cell, guess how far the
# top of the *right* prong moves with inverse-distance weights and with bounded
# biharmonic weights (it is about as close to the left handle, through the air,
# as to its own).

# %%
V_fork, F_fork = shapes.grid_2d(nx=60, ny=30, width=2.0, height=1.0)
centres = V_fork[F_fork].mean(axis=1)
F_fork = F_fork[~((np.abs(centres[:, 0] - 1.0) < 0.03) & (centres[:, 1] > 0.2))]  # cut the slot
used, F_fork = np.unique(F_fork, return_inverse=True)  # drop the vertices the slot left unused
V_fork, F_fork = V_fork[used], F_fork.reshape(-1, 3)
fork_points = np.array([np.argmin(np.linalg.norm(V_fork - c, axis=1)) for c in ([0.5, 1.0], [1.5, 1.0], [1.0, 0.0])])
_, bc_fork = handle_constraints([np.array([p]) for p in fork_points])
W_fork = {
    "inverse distance": inverse_distance_weights(V_fork, V_fork[fork_points]),
    "bounded biharmonic": bbw(V_fork, F_fork, fork_points, bc_fork),
}
right_prong_top = (V_fork[:, 0] > 1.0) & (V_fork[:, 1] > 0.9)
t = np.array([0.0, 0.3])
for label, W in W_fork.items():
    print(f"{label:18s}: the top of the right prong moves by up to {np.abs(W[right_prong_top, 0] * t[1]).max():.3f} "
          f"(the left handle moves by {t[1]})")
plotting.show_meshes(
    [(V_fork + W[:, :1] * t, F_fork, W[:, 0]) for W in W_fork.values()],
    titles=[f"{label}: left prong pulled up" for label in W_fork], label="weight of the left prong's handle",
    clim=(0.0, 1.0),
)

# %% [markdown]
# **Predict first.** Why biharmonic and not simply *harmonic* weights, which
# minimize $\int \|\nabla w\|^2$ (one solve with $L$ instead of $Q$, no lobes,
# and `igl.harmonic(V, F, b, bc, 1)` computes them)? At the same five point
# handles, guess the left hand's weight 0.1 away from the hand for harmonic and
# for biharmonic weights, and what happens to both on a finer mesh of the same
# character.

# %%
hand = 1  # the left hand's column
V_fine, F_fine = load_mesh("character_fine")
points_fine = np.array(load_handles("character_fine")["points"])
for name, (Vm, Fm, pm) in {"character": (V, F, points), "character_fine": (V_fine, F_fine, points_fine)}.items():
    near = np.abs(np.linalg.norm(Vm - Vm[pm[hand]], axis=1) - 0.1) < 0.01  # a ring 0.1 from the hand
    b_m, bc_m = handle_constraints([np.array([p]) for p in pm])
    harmonic = igl.harmonic(Vm, Fm, b_m, bc_m, 1)
    biharmonic = unconstrained_biharmonic_weights(Vm, Fm, b_m, bc_m)
    means = [harmonic[near, hand].mean(), biharmonic[near, hand].mean()]
    print(f"{name:15s} ({len(Vm):5d} vertices): mean left-hand weight 0.1 from the hand "
          f"{means[0]:.3f} (harmonic), {means[1]:.3f} (biharmonic)")
W_harmonic = igl.harmonic(V, F, points, np.eye(len(points)), 1)
plotting.show_weights(V, F, np.stack([W_harmonic[:, hand], W_unconstrained[:, hand]], axis=1), handles=points,
                      titles=["harmonic: left hand", "unconstrained biharmonic: left hand"])

# %% [markdown]
# **Question.** The harmonic weights of the last experiment never go negative;
# the unconstrained biharmonic ones do. Work it out in one dimension: on the
# segment $[0, 2]$, with handle values $w(0) = 1$, $w(1) = 0$, $w(2) = 0$ and no
# other condition, what are the minimizers of $\int_0^2 (w')^2$ and of
# $\int_0^2 (w'')^2$? Where is the second one negative, and by roughly how much?
# What property does the second-order problem have that the fourth-order one
# lacks?

# %% [markdown] deformlab={"answer": "negative_lobes", "points": 2}
# The minimizer of ∫ (w')² with these values is piecewise linear (w'' = 0
# between the constraints): 1 → 0 on [0, 1] and 0 on [1, 2], never negative. The
# minimizer of ∫ (w'')² is piecewise cubic (fourth derivative 0 between the
# constraints), C² at x = 1, with the natural conditions w'' = 0 at both ends:
# the natural cubic spline through (0, 1), (1, 0), (2, 0). Its second derivative
# at x = 1 is M = 1.5 (from M_0 + 4 M_1 + M_2 = 6 (1 − 2·0 + 0)), and on [1, 2]
# w(x) = M ((2 − x)³ − (2 − x)) / 6, negative on the whole open interval, lowest
# (≈ −0.096) at x = 2 − 1/√3 ≈ 1.42. The weight arrives at x = 1 with a
# negative slope and, having to stay smooth (C²), overshoots below 0 before it
# comes back, like a bent beam. Second-order (harmonic) problems obey the
# maximum principle: the minimizer takes its extremes on the constraints, so it
# stays within [0, 1]. Fourth-order problems have no maximum principle: the
# smoothness they reward is what pushes the weight beyond the values it
# interpolates.

# %% [markdown]
# **Question.** In the fork experiment, inverse-distance weights leaked across
# the slot and bounded biharmonic weights did not. Could *any* weight of the form
# $w_j(x) = f(\|x - h_j\|)$ (normalized), with a cleverer $f$, avoid the leak?
# Say what information such weights would need, and how the biharmonic weights
# get it. Then explain the harmonic weights' shares in the last experiment.

# %% [markdown] deformlab={"answer": "inverse_distance", "points": 2}
# No: two vertices at the same Euclidean distance from h_j get the same weight
# whatever f is, whether they are connected to the handle through the shape or
# only across a gap, so the top of the right prong, about as close to the left
# handle as to its own, gets a large share of the left handle's weight and
# moves with it (39 % of the left prong's motion measured: <span class="measured">0.116</span> of 0.3).
# Weights that respect the shape need its connectivity: a
# distance measured inside the shape (geodesic), or an energy defined on the
# mesh. Biharmonic weights minimize ½ wᵀQw, where Q couples only vertices within
# two rings of each other: influence spreads from neighbour to neighbour through
# the triangles, and nothing crosses the slot, where there are no triangles: the
# left handle's weight reaches the right prong only around the base.
# Harmonic weights are also shape-aware, but a point constraint is too small for
# a second-order energy: in the continuum a harmonic function cannot be pinned
# at a single point (the log singularity makes the energy of the spike vanish),
# so the weight has a spike (a cusp) at the handle and drops steeply around it,
# and more so as the mesh is refined (0.1 from the hand it falls from <span class="measured">0.884</span> on the
# character to <span class="measured">0.843</span> on the finer mesh). The biharmonic energy is fourth order: point values are well
# defined, the weight is smooth and flat at its handle (<span class="measured">0.997</span> and <span class="measured">0.988</span> at 0.1), and
# refining the mesh hardly changes it.

# %% [markdown]
# ## 8 · Every kind of handle at once
#
# Nothing in `bbw` cares what a handle looks like: a point, a bone and a region
# are all sets of constrained vertices. Below, one character carries a **point**
# (the right hand), a **bone** (every vertex along the left arm's segment) and a
# **region** (the head), with the feet as two more regions that keep the legs
# anchored. The panels show the first three weights. A bone's weight is 1 along
# the whole segment, so the arm moves rigidly with it; a point handle's weight
# peaks at one vertex; a region's plateau covers its patch and then falls off
# through the neck.

# %%
right_hand, left_arm = points[2], character_handles["bones"][1]
head, left_foot, right_foot = character_handles["regions"]
mixed = [np.array([right_hand]), left_arm, head, left_foot, right_foot]
b, bc = handle_constraints(mixed)
W_mixed = bbw(V, F, b, bc)
for label, w in zip(("point (right hand)", "bone (left arm)", "region (head)"), W_mixed.T):
    print(f"{label:18s}: weight ≥ 0.5 on {np.mean(w >= 0.5):5.1%} of the vertices")
plotting.show_weights(V, F, W_mixed, handles=mixed, columns=[0, 1, 2],
                      titles=["BBW: point (right hand)", "BBW: bone (left arm)", "BBW: region (head)"])

# %% [markdown]
# The size of a handle shows in how much of the shape it dominates: a weight of
# at least 0.5 on <span class="measured">9.0</span>% of the vertices for the point, <span class="measured">20.4</span>% for the bone and
# <span class="measured">29.0</span>% for the region.

# %% [markdown]
# ## 9 · A cage
#
# A **cage** is a coarse polygon around the shape whose vertices are the handles.
# Its constraint is not one-hot: along every cage edge the weights must be
# *linear*, so that a straight cage edge maps to a straight edge, and the weights
# of the two cage vertices at its ends share the edge as the two hat functions of
# a segment do. Here the shape is the unit square meshed by a grid, its outline
# is the cage (four corners), and every outline vertex is constrained: on the
# outline, the bilinear coordinates $(1-x)(1-y),\ x(1-y),\ xy,\ (1-x)y$ are
# exactly those linear hats. `bbw` fills in the inside; then every vertex moves
# by $\sum_j w_j\,(c'_j - c_j)$ for the moved corners $c'_j$.
#
# **Predict first.** The corners move to a general quadrilateral. Do the grid's
# straight lines stay straight: the outline? the vertical line through the
# middle? (The bilinear map would keep both straight.)

# %%
V_cage, F_cage = shapes.grid_2d(nx=24, ny=24)
corners = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
x, y = V_cage.T
bilinear = np.stack([(1 - x) * (1 - y), x * (1 - y), x * y, (1 - x) * y], axis=1)
outline = np.flatnonzero((x == 0) | (x == 1) | (y == 0) | (y == 1))
W_cage = bbw(V_cage, F_cage, outline, bilinear[outline])  # linear along every cage edge
moved = np.array([[0.0, 0.0], [1.3, 0.2], [1.0, 1.4], [-0.2, 0.9]])
U_cage = V_cage + W_cage @ (moved - corners)


def bend_of(points):
    """Largest distance of a chain of points from the straight line through its two ends."""
    ends = points[[0, -1]]
    normal = np.array([-(ends[1] - ends[0])[1], (ends[1] - ends[0])[0]]) / np.linalg.norm(ends[1] - ends[0])
    return np.abs((points - ends[0]) @ normal).max()


for label, chain in (("bottom edge of the outline", y == 0), ("vertical line x = 0.5", np.isclose(x, 0.5))):
    order = np.argsort(x[chain] + y[chain])
    print(f"{label:27s}: bends by {bend_of(U_cage[chain][order]):.4f}")
print(f"largest difference between the cage weights and the bilinear coordinates: {np.abs(W_cage - bilinear).max():.3f}")
# The difference from the bilinear map is a few hundredths: drawn at its true size it is invisible,
# so the right panel adds it ten times over (and colours its true size).
U_bilinear = V_cage + bilinear @ (moved - corners)
exaggeration = 10.0
deviation = U_cage - U_bilinear
plotting.show_meshes(
    [(U_bilinear, F_cage, np.zeros(len(V_cage))), (U_bilinear + exaggeration * deviation, F_cage, np.linalg.norm(deviation, axis=1))],
    titles=["bilinear map of the moved corners", f"BBW cage, its difference from bilinear × {exaggeration:.0f}"],
    label="distance from the bilinear map (true size)", clim=(0.0, np.linalg.norm(deviation, axis=1).max()),
)

# %% [markdown]
# The outline stays exactly straight (it bends by <span class="measured">0.0000</span>): on it the weights are
# the constrained linear hats. The middle line bends (by <span class="measured">0.0201</span>), because inside the square
# the weights are not the bilinear coordinates (they differ by up to <span class="measured">0.078</span>): the
# biharmonic energy and the bounds decide them, and nothing asks them to keep
# lines straight. At true size the bend is invisible, which is why the right
# panel multiplies the difference from the bilinear map by ten.
