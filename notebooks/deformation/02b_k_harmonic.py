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
# # 02b · Harmonic and biharmonic deformation: the linear baseline
#
# *Workload: about 2.7 hours for 3 graded functions (9 points) and 1 written answer (an estimate for a student who attended the lecture).*
#
# A user grabs a few *handles* of a shape, here the two ends of a bar, and moves
# them. Before ARAP (stage 03), try the simplest answer: give every handle vertex
# its **displacement** and spread the displacements smoothly over the rest of the
# shape. Smooth means that a *k-harmonic energy* of the displacement field is as
# small as it can be; the minimizer is one linear solve, and because the matrix
# never changes, one factorization serves every drag of the mouse. This is the
# "naïve Laplacian editing" of the lecture made smooth, libigl's tutorials 401
# and 402, and the linear method the lecture contrasts ARAP with: §4 shows
# what it cannot do.
#
# **Notation** (the lecture's letters; the code's names are the ones the
# functions' docstrings below define):
#
# | symbol | meaning | in code |
# |---|---|---|
# | $x_i \in \mathbb R^d$ | rest position of vertex $i$ | row `i` of `V` `(n, d)` |
# | $x'_i$ | deformed position of vertex $i$ | row `i` of `V + D` |
# | $d_i = x'_i - x_i$ | displacement of vertex $i$ | row `i` of `D` `(n, d)` |
# | $\mathcal H$, $\hat d_h$ | the handles and their prescribed displacements | `handles`, `handle_displacements` |
# | $L$ | cotangent matrix (libigl's sign: negative semi-definite) | `L = igl.cotmatrix(V, F)` |
# | $M$ | lumped (Voronoi) mass matrix, $m_i$ the area around vertex $i$ | `M = igl.massmatrix(V, F, ...)` |
# | $Q_k$ | matrix of the k-harmonic energy | `k_harmonic_operator(L, M, k)` |
# | $f$, $h$ | the free vertices and the handles (row and column blocks) | `Q[free][:, free]`, ... |
# | $\mathbf b$ | right-hand side of the solve | `-Q_fh @ D_h` |
#
# **The energies.** For a displacement field $d$ on the surface, the
# **harmonic** energy measures how fast $d$ changes and the **biharmonic** energy
# how fast its *slope* changes:
#
# $$E_1(d) = \tfrac12 \int \lVert \nabla d \rVert^2, \qquad E_2(d) = \tfrac12 \int \lVert \Delta d \rVert^2 .$$
#
# Their minimizers with $d$ fixed on the handles solve $\Delta d = 0$ and
# $\Delta^2 d = 0$ away from the handles. On a triangle mesh (each coordinate of
# $d$ linear on every triangle), $\int \lVert \nabla d \rVert^2 = -d^\top L d$ (the
# cotangent formula of stage 03) and $\Delta d \approx M^{-1} L d$, so
# $\int \lVert \Delta d \rVert^2 \approx (M^{-1} L d)^\top M (M^{-1} L d) = d^\top L M^{-1} L d$.
# With $-L$ (positive semi-definite) as the building block, every $k$ reads
#
# $$E_k(D) = \tfrac12 \operatorname{tr}(D^\top Q_k D), \qquad Q_k = (-L)\,\bigl(M^{-1}(-L)\bigr)^{k-1}:
# \quad Q_1 = -L,\;\; Q_2 = L M^{-1} L .$$
#
# The columns of $D$ (its $x$, $y$, $z$ parts) do not interact: one solve
# handles all of them at once.
#
# **How to work.** Write each function in the cell below its explanation,
# replacing `raise NotImplementedError()`, then run the tests cell under it.
# Those tests are there to help you; your functions are graded on more inputs
# than they show.

# %%
import igl
import numpy as np
import scipy.sparse as sp

from starter import load_handles, load_mesh, plotting

V, F = load_mesh("bar")  # the box [0, 4] x [0, 1] x [0, 1]: a closed surface
ends = load_handles("bar")  # the vertices of its two end faces
left, right = ends["left"], ends["right"]
handles = np.r_[left, right]
L = igl.cotmatrix(V, F)
M = igl.massmatrix(V, F, igl.MASSMATRIX_TYPE_VORONOI)
print(f"bar: {len(V)} vertices, {len(F)} triangles; handles: {len(left)} + {len(right)} vertices of the two ends")


def rotation_about_y(angle):
    """Rotation by ``angle`` radians about the y axis, (3, 3)."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


# %% [markdown]
# ## 1 · The energy's matrix
#
# `k_harmonic_operator(L, M, k)` returns $Q_k = (-L)\,(M^{-1}(-L))^{k-1}$ as a
# sparse `(n, n)` matrix, for any integer $k \ge 1$ (raise a `ValueError`
# otherwise). `L` and `M` may arrive sparse or dense (`sp.csr_matrix(A)` takes
# either); $M$ is diagonal, so $M^{-1}$ is `sp.diags(1 / M.diagonal())`. Never
# invert a matrix that is not diagonal: $M^{-1} L$ is sparse, $L^{-1}$ would be
# dense. $Q_k$ is symmetric: $(-L)$ and $M^{-1}$ are, and the product is a
# palindrome.

# %% deformlab={"solution": "k_harmonic_operator"}
import numpy as np
import scipy.sparse as sp


def k_harmonic_operator(L, M, k):
    """The k-harmonic energy's matrix ``Q_k = (-L) (M⁻¹ (-L))^(k-1)``.

    Parameters
    ----------
    L : (n, n) sparse or dense
        Cotangent matrix (negative semi-definite).
    M : (n, n) sparse or dense
        Diagonal lumped mass matrix.
    k : int
        At least 1.

    Returns
    -------
    Q : (n, n) scipy.sparse matrix
    """
    ### BEGIN SOLUTION
    if not isinstance(k, (int, np.integer)) or isinstance(k, bool) or k < 1:
        raise ValueError(f"k must be an integer of at least 1, got {k!r}")
    minus_L = -sp.csr_matrix(L, dtype=float)
    M_inverse = sp.diags(1.0 / sp.csr_matrix(M, dtype=float).diagonal())
    Q = minus_L
    for _ in range(k - 1):
        Q = Q @ M_inverse @ minus_L
    return sp.csr_matrix(Q)
    ### END SOLUTION

# %% deformlab={"tests": "k_harmonic_operator", "points": 3}
# A path of three vertices: L has the edge weights 1 and 2, M the masses 1, 2, 4.
_L = np.array([[-1.0, 1.0, 0.0], [1.0, -3.0, 2.0], [0.0, 2.0, -2.0]])
_M = np.diag([1.0, 2.0, 4.0])
_Q1 = k_harmonic_operator(_L, _M, 1)
assert sp.issparse(_Q1), f"Q must be a scipy.sparse matrix (a mesh of 10⁵ vertices has 10¹⁰ entries), got {type(_Q1).__name__}"
_Q1 = _Q1.toarray()
assert not np.allclose(_Q1, _L), "k = 1: Q_1 = -L, positive semi-definite; you returned L itself (the sign)"
assert not np.allclose(_Q1, _L @ np.linalg.inv(_M) @ _L), "k = 1: you returned L M⁻¹ L; k is off by one: Q_1 = -L has one factor -L, Q_k has k"
assert np.allclose(_Q1, -_L), f"k = 1: expected Q_1 = -L = {(-_L).tolist()}, got {np.round(_Q1, 6).tolist()}"
_Q2 = k_harmonic_operator(sp.csr_matrix(_L), sp.csr_matrix(_M), 2).toarray()
_want = _L @ np.linalg.inv(_M) @ _L
assert not np.allclose(_Q2, _L @ _L), f"k = 2: you returned L L; M⁻¹ is missing between the factors, Q_2 = (-L) M⁻¹ (-L) = {_want.tolist()}"
assert not np.allclose(_Q2, -_want), "k = 2: you returned -(L M⁻¹ L): the sign, Q_k is built from -L and is positive semi-definite"
assert not np.allclose(_Q2, -_L) and not np.allclose(_Q2, -_L @ np.linalg.inv(_M) @ _L @ np.linalg.inv(_M) @ _L), (
    "k = 2: k is off by one: Q_1 = -L has one factor -L, Q_2 two, Q_k has k"
)
assert np.allclose(_Q2, _want), f"k = 2: expected Q_2 = L M⁻¹ L = {_want.tolist()}, got {np.round(_Q2, 6).tolist()}"
_Q3 = k_harmonic_operator(_L, _M, 3).toarray()
_want3 = -_L @ np.linalg.inv(_M) @ _L @ np.linalg.inv(_M) @ _L
assert np.allclose(_Q3, _want3), f"k = 3: expected (-L) M⁻¹ (-L) M⁻¹ (-L) = {np.round(_want3, 6).tolist()}, got {np.round(_Q3, 6).tolist()}"
assert np.allclose(_Q3, _Q3.T), "Q_3 must be symmetric"

# On the bar: Q_2 is positive semi-definite, and constants are in its kernel (rows of L sum to zero).
_Q = k_harmonic_operator(L, M, 2)
_x = np.random.default_rng(1).normal(size=len(V))
assert _x @ (_Q @ _x) > 0, "on the bar: xᵀ Q_2 x must be positive for a random x (Q_k is positive semi-definite)"
assert np.abs(_Q @ np.ones(len(V))).max() < 1e-8 * abs(_Q).max(), "on the bar: Q_2 times a constant must be zero"

for _k in (0, -1, 1.5):
    try:
        k_harmonic_operator(_L, _M, _k)
    except ValueError:
        pass
    except Exception as _exc:
        raise AssertionError(f"k = {_k}: expected a ValueError (k must be an integer of at least 1), got {type(_exc).__name__}: {_exc}") from None
    else:
        raise AssertionError(f"k = {_k}: expected a ValueError (k must be an integer of at least 1)")

# %% [markdown]
# ## 2 · Solving with the handles fixed
#
# Split the vertices into the free ones $f$ and the handles $h$, and $Q$ into the
# matching blocks. With $D_h = \hat d$ fixed,
#
# $$E(D) = \tfrac12 \operatorname{tr}\left(D_f^\top Q_{ff} D_f\right) + \operatorname{tr}\left(D_f^\top Q_{fh} D_h\right) + \text{const},$$
#
# and setting its gradient with respect to $D_f$ to zero gives the lecture's
# $\mathbf L \mathbf x' = \mathbf b$ shape again:
#
# $$Q_{ff}\, D_f = \mathbf b = -\,Q_{fh}\, D_h .$$
#
# $Q_{ff}$ is symmetric positive definite as long as every connected piece of
# the mesh holds a handle, and it depends on the handles but **not** on where they
# are dragged: factor it once, and each new drag costs two triangular solves. So
# the work is split in two:
#
# - `k_harmonic_precompute(Q, handles)` checks the handles (a `ValueError` if
#   there is none, one repeats or is out of range), finds the free vertices,
#   keeps $Q_{fh}$ and factors $Q_{ff}$ (`scipy.sparse.linalg.splu` of a CSC
#   matrix, or `factorized`). What it returns is yours to design.
# - `k_harmonic_solve(data, handle_displacements)` returns the whole $D$, `(n, d)`:
#   the handles' rows exactly as given (copied, never solved for), the free rows
#   from the factored system.
#
# Both are graded together through `k_harmonic_solve` (the data is yours), so a
# mistake in either costs both.

# %% deformlab={"solution": "k_harmonic_precompute"}
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def k_harmonic_precompute(Q, handles):
    """What every solve with these handles shares: the free vertices, ``Q_fh`` and ``Q_ff`` factored.

    Parameters
    ----------
    Q : (n, n) sparse or dense
        ``k_harmonic_operator``'s matrix.
    handles : (h,) array_like of int
        Distinct vertices, at least one.

    Returns
    -------
    data : any object of your design, passed to ``k_harmonic_solve``.
    """
    ### BEGIN SOLUTION
    Q = sp.csr_matrix(Q, dtype=float)
    n = Q.shape[0]
    handles = np.asarray(handles)
    if handles.ndim != 1 or len(handles) == 0:
        raise ValueError("handles must list at least one vertex")
    if handles.min() < 0 or handles.max() >= n:
        raise ValueError(f"handles must be vertices 0..{n - 1}")
    if len(np.unique(handles)) < len(handles):
        raise ValueError("handles repeats a vertex")
    free = np.setdiff1d(np.arange(n), handles)
    return {
        "n": n,
        "handles": handles,
        "free": free,
        "Q_fh": Q[free][:, handles],
        "solve_ff": spla.factorized(Q[free][:, free].tocsc()) if len(free) else None,
    }
    ### END SOLUTION

# %% deformlab={"solution": "k_harmonic_solve"}
import numpy as np


def k_harmonic_solve(data, handle_displacements):
    """The displacements minimizing ``½ tr(Dᵀ Q D)`` with ``D[handles] = handle_displacements``.

    Parameters
    ----------
    data : what ``k_harmonic_precompute`` returned.
    handle_displacements : (h, d) array_like of float
        One row per handle, in the order of ``handles``.

    Returns
    -------
    D : (n, d) numpy.ndarray of float
    """
    ### BEGIN SOLUTION
    D_h = np.asarray(handle_displacements, dtype=float)
    if D_h.ndim != 2 or len(D_h) != len(data["handles"]):
        raise ValueError(f"handle_displacements must have one row per handle, got shape {D_h.shape}")
    D = np.zeros((data["n"], D_h.shape[1]))
    D[data["handles"]] = D_h
    if data["solve_ff"] is not None:
        b = -(data["Q_fh"] @ D_h)
        D[data["free"]] = np.column_stack([data["solve_ff"](b[:, j]) for j in range(D_h.shape[1])])
    return D
    ### END SOLUTION

# %% deformlab={"tests": "k_harmonic_precompute", "points": 3}
_path_Q = sp.csr_matrix(np.array([[1.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]]))  # -L of a path of 3
for _bad, _why in (([], "no handle"), ([0, 0], "a handle repeated"), ([0, 3], "a handle out of range")):
    try:
        k_harmonic_precompute(_path_Q, np.array(_bad, dtype=int))
    except ValueError:
        pass
    except Exception as _exc:
        raise AssertionError(f"handles = {_bad} ({_why}): expected a ValueError naming the problem, got {type(_exc).__name__}: {_exc}") from None
    else:
        raise AssertionError(f"handles = {_bad} ({_why}): expected a ValueError")
_data = k_harmonic_precompute(_path_Q, np.array([2, 0]))
_first = k_harmonic_solve(_data, np.array([[1.0], [0.0]]))
_second = k_harmonic_solve(_data, np.array([[0.0], [4.0]]))
assert np.allclose(_first.ravel(), [0.0, 0.5, 1.0]) and np.allclose(_second.ravel(), [4.0, 2.0, 0.0]), (
    f"one precomputation, two solves on a path 0 - 1 - 2 with handles [2, 0]: expected [0, 0.5, 1] and [4, 2, 0], got "
    f"{np.round(_first.ravel(), 6).tolist()} and {np.round(_second.ravel(), 6).tolist()} (the data must serve any number of solves)"
    + ("; the displacements went to the handles in ascending order: row j of handle_displacements belongs to handles[j], "
       "so keep the caller's order (np.unique would also sort the handles)"
       if np.allclose(_first.ravel(), [1.0, 0.5, 0.0]) else "")
)

# %% deformlab={"tests": "k_harmonic_solve", "points": 3}
# The path 0 - 1 - 2 - 3 with Q = -L (unit weights): harmonic means linear between the handles.
_Q = sp.csr_matrix(np.array([[1.0, -1.0, 0, 0], [-1.0, 2.0, -1.0, 0], [0, -1.0, 2.0, -1.0], [0, 0, -1.0, 1.0]]))
_D = k_harmonic_solve(k_harmonic_precompute(_Q, np.array([0, 3])), np.array([[0.0, 0.0], [3.0, -6.0]]))
assert np.shape(_D) == (4, 2), f"D must have one row per vertex and one column per coordinate, (4, 2), got {np.shape(_D)}"
assert np.allclose(_D[[0, 3]], [[0.0, 0.0], [3.0, -6.0]]), "the handles' rows must be their displacements, exactly as given"
assert not np.allclose(_D[1:3], 0.0), (
    "every free vertex stays put: the right-hand side is b = -Q_fh D_h; the handles' columns belong there"
)
assert not np.allclose(_D[1:3], -np.array([[1.0, -2.0], [2.0, -4.0]])), "the free part has the wrong sign: Q_ff D_f = -Q_fh D_h"
assert np.allclose(_D[1:3], [[1.0, -2.0], [2.0, -4.0]]), f"harmonic on a path is linear: expected D[1:3] = [[1, -2], [2, -4]], got {np.round(_D[1:3], 6).tolist()}"

# On the bar, biharmonic: every handle moved by one vector moves every vertex by it (Q's rows sum to zero),
# and the energy is stationary at every free vertex.
_Q2 = k_harmonic_operator(L, M, 2)
_data = k_harmonic_precompute(_Q2, handles)
_D = k_harmonic_solve(_data, np.tile([0.3, -0.2, 0.5], (len(handles), 1)))
assert np.abs(_D - [0.3, -0.2, 0.5]).max() < 1e-8, "every handle moved by (0.3, -0.2, 0.5): every vertex must move by it (a translation costs no energy)"
_D_h = np.zeros((len(handles), 3))
_D_h[len(left):, 2] = 1.0
_D = k_harmonic_solve(_data, _D_h)
_free = np.flatnonzero(~np.isin(np.arange(len(V)), handles))
assert np.abs((_Q2 @ _D)[_free]).max() < 1e-8 * abs(_Q2).max(), "on the bar: (Q D) must vanish at every free vertex (the energy is stationary there)"

# %% [markdown]
# ## 3 · Harmonic or biharmonic: lifting one end
#
# **Predict** before you run the next cell. The left end of the bar stays put and
# the right end is lifted by 1 (displacement $(0, 0, 1)$). Along the bar, how
# does the lift grow from 0 to 1 for $k = 1$ and for $k = 2$? In particular, how
# steep is the bar just next to each end, compared with the average slope
# $1/4$? Which one would you call a *bend*, and which a *kink*?
#
# The cell averages the lift over thin slices across the bar and prints the
# slope next to each end, divided by the average slope.

# %%
lift = np.zeros((len(handles), 3))
lift[len(left):, 2] = 1.0
solutions = {}
for k in (1, 2):
    data = k_harmonic_precompute(k_harmonic_operator(L, M, k), handles)
    solutions[k] = k_harmonic_solve(data, lift)

slices = np.linspace(0.0, 4.0, 41)
centres = 0.5 * (slices[:-1] + slices[1:])
which = np.clip(np.searchsorted(slices, V[:, 0]) - 1, 0, len(centres) - 1)
for k, D in solutions.items():
    profile = np.bincount(which, weights=D[:, 2], minlength=len(centres)) / np.bincount(which, minlength=len(centres))
    slope = np.diff(profile) / np.diff(centres)
    print(f"k = {k}: lift at x = 1, 2, 3: {profile[9]:.2f}, {profile[19]:.2f}, {profile[29]:.2f}; "
          f"slope next to the left end {slope[0] / 0.25:.2f} x the average, next to the right end {slope[-1] / 0.25:.2f} x")
plotting.show_meshes([(V + solutions[1], F, solutions[1][:, 2]), (V + solutions[2], F, solutions[2][:, 2])],
                     titles=["k = 1 (harmonic), left end fixed, right end lifted by 1", "k = 2 (biharmonic), same handles"], label="lift (z displacement)", clim=(0.0, 1.0))

# %% [markdown]
# Harmonic displacements spread like heat along a rod: the lift grows almost
# linearly (<span class="measured">0.24</span>, <span class="measured">0.49</span>, <span class="measured">0.74</span> at a quarter, half and three quarters of the way),
# and next to each end it is even steeper than on average (<span class="measured">1.48</span> times the
# average slope): the bar **kinks** where it leaves the handles. The biharmonic
# energy also penalizes changes of slope, so the bar leaves each end almost flat
# (<span class="measured">0.26</span> times the average slope, measured over the first slice) and bends
# smoothly, like an elastic beam clamped at both ends. That is why editing tools use $k = 2$ (or 3, which also matches the
# curvature at the handles).
#
# ## 4 · The limit of every linear method: turning one end
#
# **Predict** before you run the next cell. Now the right end is *turned* by
# 90° about the y axis and moved to where the end of a bar bent into a quarter
# circle of its own length would be. Biharmonic displacements and ARAP
# (libigl's, stage 03's energy) get the same handles. The displacements of the
# right end are those of a rotation; what do you expect the biharmonic solution
# to do to the triangles on the inside and on the outside of the bend, and to the
# bar's length? And ARAP?
#
# The cell prints the range of the triangles' area change (deformed / rest) and
# the length of the bar's centre line (through the centroids of 40 slices of the
# rest bar), and colours each triangle by its area change. ARAP starts from the
# biharmonic pose and runs until no vertex moves by more than $10^{-6}$ in 50
# iterations (the cell prints how many it took).

# %%
turn = rotation_about_y(-np.pi / 2)  # the end's outward normal +x becomes +z
centre = V[right].mean(axis=0)
radius = 4.0 / (np.pi / 2)  # a quarter circle as long as the bar: where a bent bar of unchanged length ends
end_centre = V[left].mean(axis=0) + [radius, 0.0, radius]
target = (V[right] - centre) @ turn.T + end_centre
turned = np.zeros((len(handles), 3))
turned[len(left):] = target - V[right]

biharmonic = V + k_harmonic_solve(k_harmonic_precompute(k_harmonic_operator(L, M, 2), handles), turned)
arap_data = igl.ARAPData()
arap_data.energy = igl.ARAP_ENERGY_TYPE_SPOKES_AND_RIMS
arap_data.max_iter = 50
igl.arap_precomputation(V, F, 3, handles.astype(np.int32), arap_data)
arap, iterations, moved = biharmonic.copy(), 0, np.inf
while moved > 1e-6 and iterations < 2000:
    previous, arap = arap, igl.arap_solve(np.r_[V[left], target], arap_data, arap)
    iterations, moved = iterations + 50, float(np.abs(arap - previous).max())
print(f"ARAP: {iterations} iterations from the biharmonic pose; the last 50 moved no vertex by more than {moved:.1e}")


def centre_line_length(X):
    """Length of the polyline through the centroids of the 40 slices of the rest bar."""
    points = np.array([X[which == s].mean(axis=0) for s in range(len(centres))])
    return float(np.linalg.norm(np.diff(points, axis=0), axis=1).sum())


area_rest = igl.doublearea(V, F)
print(f"rest: centre line {centre_line_length(V):.2f} long")
for name, X in (("biharmonic", biharmonic), ("ARAP", arap)):
    change = igl.doublearea(X, F) / area_rest
    print(f"{name:>10}: triangle areas x {change.min():.2f} to x {change.max():.2f} (1 % of them below x "
          f"{np.percentile(change, 1):.2f}); centre line {centre_line_length(X):.2f} long")
plotting.show_meshes([(biharmonic, F, igl.doublearea(biharmonic, F) / area_rest), (arap, F, igl.doublearea(arap, F) / area_rest)],
                     titles=["k = 2 (biharmonic), left end fixed, right end turned by 90°", "ARAP (libigl, converged), same handles"],
                     label="area change (deformed / rest)", clim=(0.0, 2.0), cmap="coolwarm")

# %% [markdown]
# **Question.** Explain what the cell shows: why do the biharmonic
# displacements crush triangles on one side of the bend and stretch them on the
# other when the end turns, but move every slice of the bar rigidly when it is
# only lifted (§3)? Would $k = 3$, or a finer mesh, fix it? What does ARAP
# compute that no choice of $Q$ in $\tfrac12 \operatorname{tr}(D^\top Q D)$ can?

# %% [markdown] deformlab={"answer": "linear_limits", "points": 2}
# A k-harmonic solve is linear in the handles' displacements: it blends them
# with weights that depend on the rest shape only, and a blend of displacements
# is not a rotation. Lifting (§3) is a translation of the right end: the same
# vector at every handle vertex, so each slice, whose vertices get about the
# same weight, moves by that vector times the weight, rigidly. Turning the end
# gives its vertices different displacements, those of x ↦ R x + t. A vertex
# that gets weight w moves to x + w (R x + t − x) = ((1 − w) I + w R) x + w t,
# and (1 − w) I + w R is not a rotation: for w = ½ and a 90° turn it is a
# rotation by 45° scaled by cos 45° ≈ 0.71 in the plane of the bend. So the
# middle of the bar turns only halfway and shrinks in the plane of the bend:
# triangles on the inside of the bend are crushed (area down to × <span class="measured">0.00</span>, 1 %
# below × <span class="measured">0.13</span>), those on the outside stretched (up to × <span class="measured">1.90</span>), and the centre
# line is <span class="measured">3.76</span> long instead of <span class="measured">3.96</span>. k = 3 changes the weights but not the
# linearity, and neither does refinement: every linear method reproduces
# translations of the handles and no rotations. ARAP estimates a rotation R_i
# for every cell from the current pose (the local step) and asks the edges to be
# rotated copies of the rest edges, so the bar turns along its length and its
# triangles keep their size (× <span class="measured">0.83</span> to × <span class="measured">1.19</span>, the length <span class="measured">4.01</span>). That is a
# nonlinear problem: the price is the alternation of stage 03, here more than a
# thousand iterations from the biharmonic pose to convergence (the cell prints how many).
