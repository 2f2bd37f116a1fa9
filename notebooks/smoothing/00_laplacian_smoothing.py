# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3 (ipykernel)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 00 · Laplacian smoothing
#
# A scanned surface is noisy: every vertex sits a little off the true surface.
# **Smoothing** lets the positions diffuse, as heat does: each coordinate
# function $u$ on the surface follows the diffusion (heat) equation
#
# $$\frac{\partial u}{\partial t} = \Delta u ,$$
#
# $\Delta$ the Laplace–Beltrami operator of the surface. Noise is rough, so its
# Laplacian is large and it decays fast; the overall shape is smooth and decays
# slowly. On a triangle mesh, $\Delta$ becomes a sparse matrix: this notebook
# builds two of them (the **uniform** and the **cotangent** Laplacian), steps the
# equation forward in time **explicitly** and **implicitly**, and measures what
# each choice does: tangential drift, instability, shrinkage.
#
# **Sign convention**, used everywhere below (and by libigl's `igl.cotmatrix`): a
# Laplacian $L$ has the edge weights off the diagonal and minus their sum on the
# diagonal, so every row sums to zero and $L$ is *negative* semidefinite. With
# the lumped mass matrix $M = \operatorname{diag}(m)$ (one positive mass per
# vertex), $M^{-1} L \approx \Delta$ and the discrete diffusion equation is
#
# $$M \frac{dU}{dt} = L\, U, \qquad U \text{ the } (n, d) \text{ array of positions.}$$
#
# **How to work.** Write each function in the cell below its explanation,
# replacing `raise NotImplementedError()`, then run the tests cell under it.
# Those tests are there to help you; your functions are graded on more inputs
# than they show (the contract, `CONTRACT.md`, says exactly what each one
# returns and when it raises). Before each experiment you are asked to
# **predict** what it will show: write your guess down, then run it.

# %%
import igl
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from starter import load_mesh, plotting

rng = np.random.default_rng(0)


def vertex_masses(V, F):
    """Barycentric lumped masses, (n,): a third of the area of every triangle around each vertex."""
    third_of_area = igl.doublearea(V, F) / 6.0
    return np.bincount(np.asarray(F).ravel(), weights=np.repeat(third_of_area, 3), minlength=len(V))


def enclosed_volume(U, F):
    """Volume inside a closed, outward-oriented triangle mesh (divergence theorem), float."""
    a, b, c = U[F[:, 0]], U[F[:, 1]], U[F[:, 2]]
    return float(np.sum(a * np.cross(b, c)) / 6.0)


# pyvista's sphere: latitude-longitude rings, radius about 126. Scaled to radius 1
# about its centre, so that curvatures and step sizes read as plain numbers.
V_sphere, F_sphere = load_mesh("sphere")
V_sphere = V_sphere - V_sphere.mean(axis=0)
V_sphere = V_sphere / np.linalg.norm(V_sphere, axis=1).mean()
normals = V_sphere / np.linalg.norm(V_sphere, axis=1)[:, None]  # a sphere's outward normals
V_noisy = V_sphere + 0.03 * rng.standard_normal(len(V_sphere))[:, None] * normals
m_sphere = vertex_masses(V_sphere, F_sphere)
print(f"sphere: {len(V_sphere)} vertices, {len(F_sphere)} triangles, total mass {m_sphere.sum():.4f} (4π = {4 * np.pi:.4f})")

# the planar character of the deformation course: an irregular 2D triangulation
V_character, F_character = load_mesh("character")
boundary = np.unique(igl.boundary_loop(F_character))
interior = np.setdiff1d(np.arange(len(V_character)), boundary)
plotting.show_meshes([(V_noisy, F_sphere), (V_character, F_character)], titles=["noisy unit sphere", "character (2D)"], link_views=False)

# %% [markdown]
# ## 1. The uniform Laplacian
#
# The simplest Laplacian ignores the geometry and looks only at the graph of
# the mesh: vertex $i$ moves towards the average of its neighbours $N(i)$,
#
# $$(L U)_i = \sum_{j \in N(i)} (u_j - u_i), \qquad
# L = A - D,$$
#
# $A$ the adjacency matrix ($A_{ij} = 1$ if $(i, j)$ is an edge) and $D$ the
# diagonal matrix of the degrees $\deg(i) = |N(i)|$. Divided by the degree,
# $\frac{1}{\deg(i)} (L U)_i = \bar u_{N(i)} - u_i$ is the **umbrella vector**:
# from the vertex to the centroid of its neighbours. Every row of $L$ sums to
# zero (a constant function has no Laplacian), and
# $x^\top L x = -\sum_{\text{edges } (i,j)} (x_i - x_j)^2 \le 0$.
#
# `uniform_laplacian(V, F)` returns $L$ as a sparse `(n, n)` matrix, `n = len(V)`
# (a vertex in no triangle gets a zero row). Careful: an interior edge belongs
# to **two** triangles, but it is one edge, with weight 1. Raise a `ValueError`
# if `F` is not `(f, 3)` or indexes a vertex outside `0 … n-1`.

# %% deformlab={"solution": "uniform_laplacian"}
import numpy as np
import scipy.sparse as sp


def uniform_laplacian(V, F):
    """The uniform (graph) Laplacian ``L = A - D`` of a triangle mesh.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions; only their number ``n`` matters.
    F : (f, 3) array_like of int
        Triangles.

    Returns
    -------
    L : (n, n) scipy.sparse matrix
        ``L[i, j] = 1`` for every edge ``(i, j)`` (once), ``L[i, i] = -deg(i)``.
    """
    ### BEGIN SOLUTION
    n = len(V)
    F = np.asarray(F)
    if F.ndim != 2 or F.shape[1] != 3 or len(F) == 0 or not np.issubdtype(F.dtype, np.integer):
        raise ValueError(f"F must be an integer array of shape (f, 3), got {F.dtype} {F.shape}")
    if F.min() < 0 or F.max() >= n:
        raise ValueError(f"F indexes a vertex outside 0..{n - 1}")
    # the three edges of every triangle, sorted so that the two triangles of an edge name it alike
    E = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    E = np.unique(E, axis=0)  # each edge once
    i, j = E[:, 0], E[:, 1]
    A = sp.coo_matrix((np.ones(2 * len(E)), (np.r_[i, j], np.r_[j, i])), shape=(n, n)).tocsr()
    degree = np.asarray(A.sum(axis=1)).ravel()
    return A - sp.diags(degree)
    ### END SOLUTION

# %% deformlab={"tests": "uniform_laplacian", "points": 3}
_V = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
_L = uniform_laplacian(_V, np.array([[0, 1, 2]]))
assert sp.issparse(_L), f"L must be a scipy.sparse matrix (a mesh of 10⁵ vertices has 10¹⁰ entries), got {type(_L).__name__}"
_want = np.array([[-2.0, 1.0, 1.0], [1.0, -2.0, 1.0], [1.0, 1.0, -2.0]])
assert _L.shape == (3, 3) and np.allclose(_L.toarray(), _want), (
    f"one triangle: expected L = {_want.tolist()}, got {np.round(_L.toarray(), 6).tolist()}"
    + (": the diagonal has the wrong sign, L[i, i] = -deg(i) (rows sum to zero)" if np.allclose(_L.toarray(), np.abs(_want)) else "")
    + (": the diagonal is missing, L = A - D" if np.allclose(_L.toarray(), _want - np.diag(np.diag(_want))) else "")
)

# A square of two triangles: the diagonal (0, 2) is shared.
_V = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
_L = uniform_laplacian(_V, np.array([[0, 1, 2], [0, 2, 3]])).toarray()
assert _L[0, 2] == 1.0 and _L[0, 0] == -3.0, (
    f"two triangles sharing the edge (0, 2): expected L[0, 2] = 1 and L[0, 0] = -3, got {_L[0, 2]} and {_L[0, 0]}"
    + (": the shared edge is counted once per triangle; an edge is one edge, weight 1" if _L[0, 2] == 2.0 else "")
)
assert np.allclose(_L, _L.T) and np.allclose(_L.sum(axis=1), 0.0), f"L must be symmetric with zero row sums, got {_L.tolist()}"

# Vertex 4 is in no triangle: n comes from V, and its row is zero.
_L = uniform_laplacian(np.zeros((5, 3)), np.array([[0, 1, 2], [0, 2, 3]]))
assert _L.shape == (5, 5), f"V has 5 vertices (vertex 4 in no triangle): L must be (5, 5), got {_L.shape}; n = len(V), not F.max() + 1"
assert not _L.toarray()[4].any(), "vertex 4 is in no triangle: its row must be zero"

_L = uniform_laplacian(V_sphere, F_sphere)
_valence = np.bincount(np.unique(np.sort(np.r_[F_sphere[:, :2], F_sphere[:, 1:], F_sphere[:, ::2]], axis=1), axis=0).ravel())
assert np.allclose(_L.diagonal(), -_valence), "on the sphere: L[i, i] must be minus the number of neighbours of vertex i"
assert abs(_L - _L.T).max() == 0 and np.allclose(np.asarray(_L.sum(axis=1)).ravel(), 0.0), "on the sphere: L must be symmetric with zero row sums"

for _F in (np.array([[0, 1, 5]]), np.array([[0, 1, 2, 3]])):
    try:
        uniform_laplacian(np.zeros((4, 2)), _F)
    except ValueError:
        pass
    else:
        raise AssertionError(f"F = {_F.tolist()} with 4 vertices: expected a ValueError (index out of range, or not (f, 3))")

# %% [markdown]
# **Predict** before you run the next cell. On a perfect sphere, in which
# direction do you expect the umbrella vector (from a vertex to the centroid of
# its neighbours) to point? Is it the same near the poles of this
# latitude-longitude sphere, where the triangles are long and thin and a vertex
# has many neighbours on its own ring?
#
# The cell splits each umbrella vector into its part along the normal and its
# part in the tangent plane and colours the sphere by the ratio
# tangential / normal.

# %%
L_uniform = uniform_laplacian(V_sphere, F_sphere)
degree = -L_uniform.diagonal()
umbrella = (L_uniform @ V_sphere) / degree[:, None]
along_normal = np.einsum("ij,ij->i", umbrella, normals)
tangential = np.linalg.norm(umbrella - along_normal[:, None] * normals, axis=1)
ratio = tangential / np.abs(along_normal)
print(f"umbrella vectors: normal part median {np.median(np.abs(along_normal)):.4f} (pointing inward: {np.mean(along_normal < 0):.0%}),")
print(f"                  tangential / normal: median {np.median(ratio):.2f}, largest {ratio.max():.2f} (at degree {degree[np.argmax(ratio)]:.0f})")
plotting.show_mesh(V_sphere, F_sphere, scalars=ratio, title="umbrella: tangential / normal")

# %% [markdown]
# ## 2. The cotangent Laplacian and the mass matrix
#
# The uniform Laplacian does not know the shape of the triangles, so it also
# moves vertices *along* the surface, towards an evenly spaced graph. The
# geometric Laplacian comes from the **Dirichlet energy** of a function $u$ that
# is linear on each triangle (values $u_i$ at the vertices): on a triangle $T$
# with corners $i, j, k$,
#
# $$\int_T \lVert \nabla u \rVert^2 = \tfrac12 \left( \cot\theta_k\, (u_i - u_j)^2 + \cot\theta_i\, (u_j - u_k)^2 + \cot\theta_j\, (u_k - u_i)^2 \right),$$
#
# $\theta_k$ the angle at corner $k$, opposite the edge $(i, j)$. Summing over
# the triangles, $\int \lVert \nabla u \rVert^2 = -u^\top L u$ with the
# **cotangent matrix**
#
# $$L_{ij} = \tfrac12 (\cot \alpha_{ij} + \cot \beta_{ij}), \qquad L_{ii} = -\sum_{j \ne i} L_{ij},$$
#
# $\alpha_{ij}, \beta_{ij}$ the two angles opposite the edge $(i, j)$ (only one
# on a boundary edge). For two edge vectors $a, b$ leaving a corner,
# $\cot\theta = \dfrac{a \cdot b}{\lVert a \times b \rVert}$ (in 2D, $a \times b$
# is the number $a_x b_y - a_y b_x$; take its absolute value: angles have no
# orientation). An obtuse angle has a **negative** cotangent: keep it.
#
# $L u$ is an *integrated* Laplacian: $(L u)_i \approx \int_{A_i} \Delta u$ over a
# region $A_i$ around vertex $i$. Dividing by the region's area gives $\Delta u$
# itself; the simplest choice of region, **barycentric lumping**, gives vertex
# $i$ a third of the area of each triangle around it: that is the mass
# $m_i$ of the provided `vertex_masses(V, F)` above, and $M = \operatorname{diag}(m)$
# is the **lumped mass matrix**. So $\Delta u \approx M^{-1} L u$, and for the
# positions themselves $M^{-1} L V \approx \Delta x = -2 H\, n$, the **mean
# curvature normal** ($H$ the mean curvature, $n$ the outward unit normal; a
# unit sphere has $H = 1$).
#
# `cotangent_matrix(V, F)` returns this $L$, sparse `(n, n)`, for `d = 2` or `3`
# (it equals `igl.cotmatrix`, which you may use in your own experiments but not
# inside this function). Raise a `ValueError` for a malformed `F` (as before) and
# for a triangle of zero area, whose cotangents are undefined.

# %% deformlab={"solution": "cotangent_matrix"}
import numpy as np
import scipy.sparse as sp


def cotangent_matrix(V, F):
    """The cotangent Laplacian ``L[i, j] = ½ (cot α_ij + cot β_ij)``, ``L[i, i] = -Σ_j L[i, j]``.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions, ``d`` in {2, 3}.
    F : (f, 3) array_like of int
        Triangles, none of zero area.

    Returns
    -------
    L : (n, n) scipy.sparse matrix
        Symmetric, zero row sums.
    """
    ### BEGIN SOLUTION
    V = np.asarray(V, dtype=float)
    F = np.asarray(F)
    n = len(V)
    if F.ndim != 2 or F.shape[1] != 3 or len(F) == 0 or not np.issubdtype(F.dtype, np.integer):
        raise ValueError(f"F must be an integer array of shape (f, 3), got {F.dtype} {F.shape}")
    if F.min() < 0 or F.max() >= n:
        raise ValueError(f"F indexes a vertex outside 0..{n - 1}")
    rows, cols, weights = [], [], []
    for k in range(3):  # corner k of every triangle, opposite the edge (i, j)
        o, i, j = F[:, k], F[:, (k + 1) % 3], F[:, (k + 2) % 3]
        a, b = V[i] - V[o], V[j] - V[o]
        if V.shape[1] == 2:
            cross = np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])  # unsigned: angles have no orientation
        else:
            cross = np.linalg.norm(np.cross(a, b), axis=1)
        if np.any(cross == 0):
            raise ValueError("F has a triangle of zero area: its cotangents are undefined")
        half_cot = 0.5 * np.sum(a * b, axis=1) / cross
        rows += [i, j]
        cols += [j, i]
        weights += [half_cot, half_cot]
    W = sp.coo_matrix((np.concatenate(weights), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)).tocsr()
    return W - sp.diags(np.asarray(W.sum(axis=1)).ravel())
    ### END SOLUTION

# %% deformlab={"tests": "cotangent_matrix", "points": 4}
# A right isosceles triangle: cot 90° = 0 and cot 45° = 1.
_V = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
_L = cotangent_matrix(_V, np.array([[0, 1, 2]]))
assert sp.issparse(_L), f"L must be a scipy.sparse matrix, got {type(_L).__name__}"
_want = np.array([[-1.0, 0.5, 0.5], [0.5, -0.5, 0.0], [0.5, 0.0, -0.5]])
_got = _L.toarray()
assert _L.shape == (3, 3) and np.allclose(_got, _want), (
    f"right angle at vertex 0: expected L = {_want.tolist()}, got {np.round(_got, 6).tolist()}"
    + (": these are cot, the weight is ½ cot" if np.allclose(_got, 2 * _want) else "")
    + (": the signs are flipped; off the diagonal +½ cot, on it minus the row's sum" if np.allclose(_got, -_want) else "")
    + (": the weight of edge (1, 2) is ½ cot of the angle *opposite* it, at vertex 0 (90°)" if not np.isclose(_got[1, 2], 0.0) else "")
)
_got = cotangent_matrix(_V, np.array([[0, 2, 1]])).toarray()  # the same triangle, clockwise
assert np.allclose(_got, _want), (
    f"the same triangle ordered clockwise must give the same L, got {np.round(_got, 6).tolist()}"
    + (": the cross product's sign flips with the orientation; use its absolute value" if np.allclose(_got, -_want) else "")
)

# An obtuse triangle: the angle at vertex 2 is about 157°, its cotangent negative.
_V = np.array([[0.0, 0.0], [2.0, 0.0], [1.0, 0.2]])
_got = cotangent_matrix(_V, np.array([[0, 1, 2]])).toarray()
_cot = lambda a, b: np.dot(a, b) / abs(a[0] * b[1] - a[1] * b[0])  # noqa: E731
assert np.isclose(_got[0, 1], 0.5 * _cot(_V[0] - _V[2], _V[1] - _V[2])) and _got[0, 1] < 0, (
    f"obtuse angle at vertex 2: L[0, 1] = ½ cot(157°) = {0.5 * _cot(_V[0] - _V[2], _V[1] - _V[2]):.4f} < 0, got {_got[0, 1]:.4f}"
    + (": a negative cotangent is kept as is (no abs, no clamping)" if _got[0, 1] >= 0 else "")
)

# 3D meshes and the 2D character against libigl (allowed here, in a test).
for _name, _Vt, _Ft in [("sphere", V_sphere, F_sphere), ("character", V_character, F_character)]:
    _L, _want = cotangent_matrix(_Vt, _Ft), igl.cotmatrix(_Vt, _Ft)
    _diff = abs(sp.csr_matrix(_L) - _want).max()
    assert _diff < 1e-10, f"{_name}: L differs from igl.cotmatrix by up to {_diff:.3g}"

_V = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
try:
    cotangent_matrix(_V, np.array([[0, 1, 2], [0, 1, 3]]))
except ValueError:
    pass
else:
    raise AssertionError("triangle [0, 1, 2] has its corners on a line (zero area): expected a ValueError")

# %% [markdown]
# **Predict** before you run the next cell. The character is flat: its
# coordinates $x$ and $y$ are linear functions on the plane, and a linear
# function has zero Laplacian. At the *interior* vertices of its irregular
# triangulation, which of the two Laplacians gives $L V = 0$? And on the unit
# sphere, what should the length of $M^{-1} L V$ be?

# %%
L_cot_character = cotangent_matrix(V_character, F_character)
L_uniform_character = uniform_laplacian(V_character, F_character)
cot_interior = np.linalg.norm(L_cot_character @ V_character, axis=1)[interior]
umbrella_interior = np.linalg.norm((L_uniform_character @ V_character) / -L_uniform_character.diagonal()[:, None], axis=1)[interior]
print(f"character, interior vertices: |L_cot V| at most {cot_interior.max():.1e}; the umbrella vector up to {umbrella_interior.max():.3f}")
print(f"   (median edge length {np.median(np.linalg.norm(V_character[F_character[:, 0]] - V_character[F_character[:, 1]], axis=1)):.3f})")

L_cot = cotangent_matrix(V_sphere, F_sphere)
curvature_normal = (L_cot @ V_sphere) / m_sphere[:, None]
length = np.linalg.norm(curvature_normal, axis=1)
print(f"unit sphere: |M⁻¹ L V| median {np.median(length):.3f}, from {length.min():.3f} to {length.max():.3f} (2H = 2);"
      f" pointing inward at {np.mean(np.einsum('ij,ij->i', curvature_normal, normals) < 0):.0%} of the vertices")
umbrella_everywhere = np.zeros(len(V_character))
umbrella_everywhere[interior] = umbrella_interior
plotting.show_meshes(
    [(V_character, F_character, umbrella_everywhere), (V_sphere, F_sphere, length)],
    titles=["character: umbrella length", "sphere: |M⁻¹ L V|, 2H = 2"],
    link_views=False,
)

# %% [markdown]
# ## 3. Explicit steps
#
# Divide time into steps of size $h$ and replace $\frac{dU}{dt}$ by
# $\frac{U' - U}{h}$. Evaluating the right-hand side at the **current**
# positions (forward Euler) gives the **explicit step**
#
# $$U' = U + h\, M^{-1} L\, U, \qquad u'_i = u_i + \frac{h}{m_i} \sum_j L_{ij}\, u_j .$$
#
# `explicit_smoothing_step(U, L, m, h)` returns $U'$, shape of `U`. It takes the
# Laplacian `L` (sparse, or a dense numpy array: `L @ U` works for both) and the
# **vector** of masses `m` (the diagonal of $M$): no matrix inverse is needed. For
# the uniform Laplacian, `m = 1` gives $u_i + h (L U)_i$ and `m = deg` moves each
# vertex by $h$ times its umbrella vector. Raise a `ValueError` when `U` is not
# 2-D, `L` is not `(n, n)` or `m` not `(n,)` for `n = len(U)`, a mass is not
# positive, or `h` is negative or not finite.

# %% deformlab={"solution": "explicit_smoothing_step"}
import numpy as np


def explicit_smoothing_step(U, L, m, h):
    """One explicit (forward Euler) smoothing step ``U + h M⁻¹ L U``.

    Parameters
    ----------
    U : (n, d) array_like of float
        Current positions.
    L : (n, n) scipy.sparse matrix or numpy.ndarray
        A Laplacian.
    m : (n,) array_like of float
        Positive vertex masses, ``M = diag(m)``.
    h : float
        Step size, ``h >= 0``.

    Returns
    -------
    U_next : (n, d) numpy.ndarray
    """
    ### BEGIN SOLUTION
    U = np.asarray(U, dtype=float)
    m = np.asarray(m, dtype=float)
    if U.ndim != 2:
        raise ValueError(f"U must be an (n, d) array, got shape {U.shape}")
    n = len(U)
    if L.shape != (n, n) or m.shape != (n,):
        raise ValueError(f"L must be ({n}, {n}) and m ({n},), got {L.shape} and {m.shape}")
    if not np.all(m > 0):
        raise ValueError("the masses m must be positive")
    if not (np.isfinite(h) and h >= 0):
        raise ValueError(f"the step size h must be finite and >= 0, got {h}")
    return U + h * (L @ U) / m[:, None]
    ### END SOLUTION

# %% deformlab={"tests": "explicit_smoothing_step", "points": 3}
# A path 0 - 1 - 2 with the uniform Laplacian, masses (1, 2, 1), h = 1/2.
_L = sp.csr_matrix(np.array([[-1.0, 1.0, 0.0], [1.0, -2.0, 1.0], [0.0, 1.0, -1.0]]))
_m = np.array([1.0, 2.0, 1.0])
_U = np.array([[0.0], [1.0], [3.0]])  # L U = (1, 1, -2)
_got = explicit_smoothing_step(_U, _L, _m, 0.5)
assert np.shape(_got) == (3, 1), f"U' must have the shape of U, (3, 1); got {np.shape(_got)}"
_variants = {
    "the update is subtracted; L is negative semidefinite, the step adds h M⁻¹ L U": [-0.5, 0.75, 4.0],
    "the masses are ignored; divide the update by m_i": [0.5, 1.5, 2.0],
    "the update is multiplied by the masses; divide by them": [0.5, 2.0, 2.0],
    "that is the update h M⁻¹ L U alone; return the new positions U + h M⁻¹ L U": [0.5, 0.25, -1.0],
}
assert np.allclose(_got, [[0.5], [1.25], [2.0]]), (
    f"path with L U = (1, 1, -2), m = (1, 2, 1), h = 1/2: expected U' = (0.5, 1.25, 2), got {np.ravel(_got).tolist()}"
    + "".join(f": {why}" for why, wrong in _variants.items() if np.allclose(np.ravel(_got), wrong))
)
assert np.allclose(explicit_smoothing_step(_U, _L.toarray(), _m, 0.5), _got), "L given as a dense numpy array must give the same U'"
assert np.array_equal(explicit_smoothing_step(_U, _L, _m, 0.0), _U), "h = 0 must return U unchanged"

# The mass-weighted centroid stays put: Σ m_i u'_i = Σ m_i u_i, because the columns of L sum to zero.
_U = V_noisy.copy()
_got = explicit_smoothing_step(_U, L_cot, m_sphere, 1e-4)
assert np.array_equal(_U, V_noisy), "the input U was modified; return a new array"
assert np.allclose(m_sphere @ _got, m_sphere @ _U, atol=1e-12), (
    f"noisy sphere: Σ m_i u'_i = {m_sphere @ _got} moved from Σ m_i u_i = {m_sphere @ _U}: is each row's update divided by its own m_i?"
)
assert np.allclose(_got, _U + 1e-4 * (L_cot @ _U) / m_sphere[:, None]), "noisy sphere: U' differs from U + h M⁻¹ L U"

for _args, _why in [((_U, L_cot, m_sphere, -1.0), "h = -1 < 0"), ((_U, L_cot, np.r_[0.0, m_sphere[1:]], 1e-4), "m[0] = 0"),
                    ((_U, L_cot[:10, :10], m_sphere, 1e-4), "L of shape (10, 10) for 422 vertices")]:
    try:
        explicit_smoothing_step(*_args)
    except ValueError:
        pass
    else:
        raise AssertionError(f"{_why}: expected a ValueError")

# %% [markdown]
# **Predict** before you run the next cell. Write $U$ in the eigenvectors of
# $M^{-1} L$: $M^{-1} L x = -\lambda x$, $\lambda \ge 0$ (there are $n$ of them,
# $M$-orthogonal). One explicit step multiplies the part of $U$ along $x$ by
# $1 - h\lambda$. For which step sizes $h$ does some part grow instead of
# decay? Which part of the noisy sphere, smooth or rough, blows up first?
#
# The cell computes the largest $\lambda$ of the unit sphere, then runs 25 explicit
# steps from the noisy sphere just below and just above your critical step. Where on
# the mesh do you expect the trouble to start?

# %%
lambda_max = spla.eigsh(-L_cot, k=1, M=sp.diags(m_sphere), which="LM", return_eigenvectors=False)[0]
h_critical = 2.0 / lambda_max
print(f"unit sphere: largest eigenvalue λ_max = {lambda_max:.1f}, critical step 2 / λ_max = {h_critical:.2e}")
runs = {}
for factor in (0.9, 1.1):
    U = V_noisy.copy()
    for step in range(25):
        U = explicit_smoothing_step(U, L_cot, m_sphere, factor * h_critical)
    runs[factor] = U
    radius = np.linalg.norm(U, axis=1)
    print(f"h = {factor} x critical: after 25 steps the radius ranges over [{radius.min():.3g}, {radius.max():.3g}]")
# the same sphere at its stored size (radius about 126): cotangents do not change, masses grow with the area
scale = 126.0
lambda_big = spla.eigsh(-L_cot, k=1, M=sp.diags(scale**2 * m_sphere), which="LM", return_eigenvectors=False)[0]
print(f"radius {scale:.0f}: critical step {2.0 / lambda_big:.3g}, {2.0 / lambda_big / h_critical:.0f} times the unit sphere's")
# refined: every triangle split into four at its edge midpoints (same angles, a quarter of the area)
V_fine, F_fine = igl.upsample(V_sphere, F_sphere)
lambda_fine = spla.eigsh(-cotangent_matrix(V_fine, F_fine), k=1, M=sp.diags(vertex_masses(V_fine, F_fine)), which="LM",
                         return_eigenvectors=False)[0]
print(f"edges halved ({len(V_fine)} vertices): critical step {2.0 / lambda_fine:.2e}, {h_critical / (2.0 / lambda_fine):.2f} times smaller")
plotting.show_meshes([(V_noisy, F_sphere), (runs[0.9], F_sphere), (runs[1.1], F_sphere)],
                     titles=["noisy", "25 steps, h = 0.9 critical", "25 steps, h = 1.1 critical"], link_views=False)

# %% [markdown]
# **Question.** The critical step $h = 2/\lambda_{\max}$ depends on the mesh.
# How does it change when the whole mesh is scaled by a factor $s$ (the cell
# measured $s = 126$), and when the mesh is refined so that every edge is half
# as long? What does that mean for smoothing a fine scan explicitly: how does
# the work to smooth away features of a given size grow with the number of
# vertices?

# %% [markdown] deformlab={"answer": "critical_step", "points": 2}
# The cotangent weights are dimensionless (they depend on angles only), while the
# masses are areas, so M⁻¹L scales like 1/length²: scaling the mesh by s divides
# every eigenvalue by s² and multiplies the critical step by s² (126² ≈ 15900, as
# measured; h has the units of an area). Halving every edge keeps the angles (the
# midpoint split makes four similar triangles) but divides the masses by 4, so
# λ_max grows about 4-fold and the critical step shrinks about 4-fold (measured:
# 4.25): h_crit ~ ℓ² for edge length ℓ. Smoothing away features of size σ takes
# a diffusion time T ~ σ², independent of the mesh, hence T / h_crit ~ σ²/ℓ²
# explicit steps: 4 times as many steps per halving of ℓ, each on 4 times as
# many vertices, so the work grows like n² for n vertices on a surface. That is
# why explicit smoothing of a fine scan is slow, and why the next step is implicit.

# %% [markdown]
# ## 4. Implicit steps
#
# Evaluate the right-hand side at the **new** positions instead (backward Euler):
# $M \frac{U' - U}{h} = L U'$, that is
#
# $$(M - h L)\, U' = M U .$$
#
# Each step solves one sparse linear system (all $d$ columns of $U$ at once).
# $M - hL$ is symmetric positive definite when $L$ is symmetric negative
# semidefinite and $h \ge 0$, so the solution is unique, and the part of $U$
# along an eigenvector is multiplied by $\frac{1}{1 + h\lambda} \in (0, 1]$: every
# part decays, for **every** step size. The method is unconditionally stable.
#
# `implicit_smoothing_step(U, L, m, h)` returns $U'$, with the inputs and the
# `ValueError`s of the explicit step. `scipy.sparse.linalg.spsolve` solves the
# system (build $M$ with `sp.diags(m)`; convert a dense `L` with `sp.csr_matrix(L)`).
# Mind the shape: for a single column `U` `(n, 1)`, `spsolve` returns a flat `(n,)` array.

# %% deformlab={"solution": "implicit_smoothing_step"}
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def implicit_smoothing_step(U, L, m, h):
    """One implicit (backward Euler) smoothing step: the solution ``U'`` of ``(M - h L) U' = M U``.

    Parameters
    ----------
    U : (n, d) array_like of float
        Current positions.
    L : (n, n) scipy.sparse matrix or numpy.ndarray
        A Laplacian (symmetric, negative semidefinite).
    m : (n,) array_like of float
        Positive vertex masses, ``M = diag(m)``.
    h : float
        Step size, ``h >= 0``.

    Returns
    -------
    U_next : (n, d) numpy.ndarray
    """
    ### BEGIN SOLUTION
    U = np.asarray(U, dtype=float)
    m = np.asarray(m, dtype=float)
    if U.ndim != 2:
        raise ValueError(f"U must be an (n, d) array, got shape {U.shape}")
    n = len(U)
    if L.shape != (n, n) or m.shape != (n,):
        raise ValueError(f"L must be ({n}, {n}) and m ({n},), got {L.shape} and {m.shape}")
    if not np.all(m > 0):
        raise ValueError("the masses m must be positive")
    if not (np.isfinite(h) and h >= 0):
        raise ValueError(f"the step size h must be finite and >= 0, got {h}")
    M = sp.diags(m)
    A = (M - h * sp.csr_matrix(L)).tocsc()
    U_next = spla.spsolve(A, M @ U)
    return np.reshape(U_next, U.shape)  # spsolve flattens a single column
    ### END SOLUTION

# %% deformlab={"tests": "implicit_smoothing_step", "points": 4}
# The path of the explicit tests: (M - h L) U' = M U with m = (1, 2, 1), h = 1/2.
_L = sp.csr_matrix(np.array([[-1.0, 1.0, 0.0], [1.0, -2.0, 1.0], [0.0, 1.0, -1.0]]))
_m = np.array([1.0, 2.0, 1.0])
_U = np.array([[0.0], [1.0], [3.0]])
_got = implicit_smoothing_step(_U, _L, _m, 0.5)
assert np.shape(_got) == (3, 1), (
    f"U' must have the shape of U, (3, 1); got {np.shape(_got)}"
    + (": spsolve returns a flat array for one column; reshape it to U's shape" if np.shape(_got) == (3,) else "")
)
_variants = {
    "the right-hand side is M U, not U": [0.25, 0.75, 2.25],
    "the masses are missing: (I - h L) U' = U solves another equation": [0.4, 1.2, 2.4],
    "that is the explicit step U + h M⁻¹ L U; the implicit one solves (M - h L) U' = M U": [0.5, 1.25, 2.0],
}
assert np.allclose(_got, [[0.375], [1.125], [2.375]]), (
    f"path, m = (1, 2, 1), h = 1/2: expected U' = (0.375, 1.125, 2.375), got {np.ravel(_got).tolist()}"
    + "".join(f": {why}" for why, wrong in _variants.items() if np.allclose(np.ravel(_got), wrong))
    + (": M + h L has the wrong sign (and is singular here); the system is (M - h L) U' = M U" if not np.all(np.isfinite(_got)) else "")
)
assert np.allclose(implicit_smoothing_step(_U, _L.toarray(), _m, 0.5), _got), (
    "L given as a dense numpy array must give the same U' (convert it with sp.csr_matrix(L))"
)
assert np.allclose(implicit_smoothing_step(_U, _L, _m, 0.0), _U), "h = 0 must return U unchanged"

# On the noisy sphere: the system holds, the weighted centroid stays, a huge step collapses to it.
_U = V_noisy.copy()
_got = implicit_smoothing_step(_U, L_cot, m_sphere, 1e-3)
assert np.array_equal(_U, V_noisy), "the input U was modified; return a new array"
assert np.shape(_got) == _U.shape, f"U' must have the shape of U, {_U.shape}; got {np.shape(_got)}"
_residual = np.abs(m_sphere[:, None] * _got - 1e-3 * (L_cot @ _got) - m_sphere[:, None] * _U).max()
assert _residual < 1e-10, f"noisy sphere, h = 1e-3: (M - h L) U' - M U is up to {_residual:.3g}, not 0"
assert np.allclose(m_sphere @ _got, m_sphere @ _U, atol=1e-12), "noisy sphere: the mass-weighted centroid Σ m_i u_i moved"
_centroid = m_sphere @ _U / m_sphere.sum()
_got = implicit_smoothing_step(_U, L_cot, m_sphere, 1e8)
assert np.allclose(_got, _centroid, atol=1e-6), (
    "noisy sphere, h = 1e8: every vertex must end (nearly) at the mass-weighted centroid, the only part that never decays;"
    f" the farthest is {np.abs(_got - _centroid).max():.3g} away"
)

for _args, _why in [((_U, L_cot, m_sphere, -1.0), "h = -1 < 0"), ((_U, L_cot, -m_sphere, 1e-3), "negative masses"),
                    ((_U[0], L_cot, m_sphere, 1e-3), "U of shape (3,), not (n, d)")]:
    try:
        implicit_smoothing_step(*_args)
    except ValueError:
        pass
    else:
        raise AssertionError(f"{_why}: expected a ValueError")

# %% [markdown]
# **Predict** before you run the next cell. One implicit step from the noisy
# sphere with $h$ = 10 times the explicit critical step, and one with 1000 times
# it: which removes the noise? What does the larger step cost?
# Then the same with the uniform Laplacian (masses = degrees): the sphere's
# vertices should stay on their rays from the centre if the smoothing moved
# them only along the normal. Which Laplacian keeps them there?

# %%
rough = lambda U: np.std(np.linalg.norm(U, axis=1)) / np.mean(np.linalg.norm(U, axis=1))  # noqa: E731 - spread of radii
print(f"noisy sphere: relative spread of the radii {rough(V_noisy):.4f}, mean radius {np.linalg.norm(V_noisy, axis=1).mean():.4f}")
smoothed = {}
for factor in (10, 1000):
    smoothed[factor] = implicit_smoothing_step(V_noisy, L_cot, m_sphere, factor * h_critical)
    radius = np.linalg.norm(smoothed[factor], axis=1)
    print(f"one implicit step, h = {factor:4d} x critical: spread {rough(smoothed[factor]):.4f}, mean radius {radius.mean():.4f}")


def drift_degrees(U):
    """The angle between each vertex's ray from the centre before and after, in degrees."""
    before, after = V_sphere / np.linalg.norm(V_sphere, axis=1)[:, None], U / np.linalg.norm(U, axis=1)[:, None]
    return np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", before, after), -1.0, 1.0)))


U_cot, U_uniform = V_sphere.copy(), V_sphere.copy()
for step in range(20):
    U_cot = implicit_smoothing_step(U_cot, L_cot, m_sphere, 0.05)
    U_uniform = implicit_smoothing_step(U_uniform, L_uniform, degree, 1.0)
print(f"20 implicit steps on the clean sphere: cotangent drift up to {drift_degrees(U_cot).max():.2f}°, spread {rough(U_cot):.4f};"
      f" uniform drift up to {drift_degrees(U_uniform).max():.2f}°, spread {rough(U_uniform):.4f}")
plotting.show_meshes(
    [(V_noisy, F_sphere), (smoothed[10], F_sphere), (smoothed[1000], F_sphere), (U_uniform, F_sphere, drift_degrees(U_uniform))],
    titles=["noisy", "h = 10 x critical", "h = 1000 x critical", "uniform, 20 steps: drift (°)"],
)

# %% [markdown]
# ## 5. Volume shrinkage
#
# **Predict** before you run the next cell. On the unit sphere the coordinate
# functions $x, y, z$ are eigenfunctions of the Laplace–Beltrami operator:
# $\Delta x = -2x$ (that is $-2H n$ again). If $L$ and $M$ stay those of the
# starting sphere, what radius do you expect after $k$ implicit steps of size
# $h$? And what happens to the enclosed volume?
#
# **Exercise** (not graded). Run 10 implicit cotangent steps of size `h = 0.02`
# from the clean sphere, keeping `L_cot` and `m_sphere`, and append the mean
# radius and the enclosed volume after each step to `radii` and `volumes`.

# %% deformlab={"exercise": "shrinkage_measurement"}
h, steps = 0.02, 10
radii, volumes = [1.0], [enclosed_volume(V_sphere, F_sphere)]
### BEGIN SOLUTION
U = V_sphere.copy()
for step in range(steps):
    U = implicit_smoothing_step(U, L_cot, m_sphere, h)
    radii.append(float(np.linalg.norm(U, axis=1).mean()))
    volumes.append(enclosed_volume(U, F_sphere))
### END SOLUTION
for k in (0, 1, 5, 10):
    print(f"step {k:2d}: mean radius {radii[k]:.5f} (predicted (1 + 2h)^-k = {(1 + 2 * h) ** -k:.5f}), volume {volumes[k] / volumes[0]:.3f} of the start")

# %% [markdown]
# **Question.** Why does Laplacian smoothing shrink a closed surface, and where
# does it end if you keep stepping? Propose a simple fix that keeps the enclosed
# volume, and name one thing that fix cannot repair.

# %% [markdown] deformlab={"answer": "shrinkage", "points": 2}
# M⁻¹LV approximates Δx = −2H n, the mean curvature normal: on a convex (closed)
# surface it points inward, so the flow moves every vertex inward and the surface
# shrinks (the sphere by 1/(1 + 2h) per implicit step, as measured). Smoothing
# never distinguishes noise from shape: every non-constant part of U decays,
# only the constants (the kernel of L) survive, so with enough steps everything
# collapses to the mass-weighted centroid (as h = 1e8 showed). A fix: after each
# step, scale the mesh about its centroid by (V₀ / V)^(1/3) so that the enclosed
# volume stays V₀ (Desbrun et al. 1999); Taubin's λ|μ alternating steps are
# another. Rescaling is global: it cannot undo the shape change itself, e.g.
# thin parts (limbs, ears) shrink much faster than the body and rescaling only
# inflates the body, and low-frequency features still flatten out.
