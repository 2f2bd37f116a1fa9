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
# # 01 · Shape matching: the best orthogonal map between two point sets
#
# *Workload: about 2.4 hours for 4 graded functions (11 points) and 1 written answer (an estimate for a student who attended the lecture).*
#
# You are given $k$ points $p_1, \dots, p_k$ (the rows of `P`, shape `(k, d)`),
# the same points after some motion, $q_1, \dots, q_k$ (the rows of `Q`, with
# $q_i$ corresponding to $p_i$), and weights $w_i \ge 0$ saying how much each
# pair counts. Find the orthogonal matrix $R$ ($R^\top R = I$) and the
# translation $t$ that explain the motion best in the least-squares sense:
#
# $$E(R, t) = \sum_{i=1}^{k} w_i \,\lVert R p_i + t - q_i \rVert^2 \;\to\; \min.$$
#
# This small problem is the heart of as-rigid-as-possible deformation (stage 03):
# there, it is solved for the neighbourhood of every vertex, in every iteration.
# Here we allow every orthogonal $R$; stage 02 restricts it to rotations.
#
# The derivation splits the problem in two: first $t$ for a fixed $R$, then $R$.
#
# **How to work.** Write each function in the cell below its explanation,
# replacing `raise NotImplementedError()`, then run the tests cell under it.
# Those tests are there to help you; your functions are graded on more inputs
# than they show. Later cells use your earlier functions.

# %% [markdown]
# **Symbols.** The lecture's letters, plus the two this notebook adds (marked *new*):
#
# | symbol | meaning | in code |
# |---|---|---|
# | $p_i$, $q_i$ | corresponding source and target points | rows of `P`, `Q` `(k, d)` |
# | $w_i$ (*new*) | the weight of pair $i$ (the lecture has all $w_i = 1$) | `w` `(k,)` |
# | $\bar p$, $\bar q$ | (weighted) centroids | `centroid(P, w)` |
# | $v_i = p_i - \bar p$, $v'_i = q_i - \bar q$ | centred points; the columns of $\mathbf V$, $\mathbf V'$ | rows of `P - centroid(P, w)`, … |
# | $S$ (*new*) | $\sum_i w_i v_i {v'_i}^\top$, the lecture's $\mathbf V \mathbf V'^\top$ | `covariance_matrix(P, Q, w)` |
# | $U \Sigma \tilde U^\top$ | the SVD of $S$ | `U_svd, sigma, U_tilde_T = np.linalg.svd(S)` |
# | $R$, $t$ | the orthogonal map and the translation | `R`, `t` |

# %%
import numpy as np

from starter import load_mesh, plotting

rng = np.random.default_rng(0)


def rotation_2d(angle):
    """Counter-clockwise rotation of the plane by ``angle`` radians, (2, 2)."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s], [s, c]])


def rotation_3d(axis, angle):
    """Rotation by ``angle`` radians about ``axis`` (Rodrigues' formula), (3, 3)."""
    k = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * K @ K


# %% [markdown]
# Our running example: every tenth vertex of the 2D character, waving (its
# right arm turned about the shoulder, so that the points have no mirror
# symmetry), are the points $p_i$; the $q_i$ are the same points turned, moved
# and perturbed by a little noise. Points are rows, so applying $R$ and $t$ to
# all of them at once reads `P @ R.T + t`.

# %%
V_character, _ = load_mesh("character")
P = V_character[::10].copy()
arm = (P[:, 0] > 0.4) & (P[:, 1] > 0.6)
shoulder = np.array([0.3, 1.05])
P[arm] = (P[arm] - shoulder) @ rotation_2d(1.0).T + shoulder
size = np.linalg.norm(P.max(axis=0) - P.min(axis=0))
Q = P @ rotation_2d(2.2).T + np.array([1.2, 0.4]) * size + rng.normal(scale=0.01 * size, size=P.shape)
plotting.show_points(P, Q, title="source P and target Q")

# %% [markdown]
# ## 1. The translation: centroids
#
# For a fixed $R$, $E$ is a convex quadratic function of $t$, so it is smallest
# where its gradient vanishes:
#
# $$\frac{\partial E}{\partial t} = 2 \sum_i w_i \,(R p_i + t - q_i) = 0
# \quad\Longleftrightarrow\quad
# \Big(\sum_i w_i\Big)\, t = \sum_i w_i q_i - R \sum_i w_i p_i
# \quad\Longleftrightarrow\quad
# t = \bar q - R \bar p,$$
#
# with the **weighted centroids**
#
# $$\bar p = \frac{\sum_i w_i\, p_i}{\sum_i w_i}, \qquad \bar q = \frac{\sum_i w_i\, q_i}{\sum_i w_i}.$$
#
# The best motion maps the centroid of the $p_i$ onto the centroid of the $q_i$.
#
# `centroid(P, w=None)` returns $\bar p$, shape `(d,)`; `w=None` means all weights
# are $1$. One line of numpy does it (a product with `@`, or `np.average`).

# %% deformlab={"solution": "centroid"}
import numpy as np


def centroid(P, w=None):
    """The weighted mean of a point set.

    Parameters
    ----------
    P : (k, d) array_like of float
        Points.
    w : (k,) array_like of float, optional
        Non-negative weights, not all zero; all ones by default.

    Returns
    -------
    p_bar : (d,) numpy.ndarray
        ``Σ w_i p_i / Σ w_i``.
    """
    ### BEGIN SOLUTION
    P = np.asarray(P, dtype=float)
    w = np.ones(len(P)) if w is None else np.asarray(w, dtype=float)
    w = w / np.sum(w)  # dividing first keeps very large or very small weights in range
    return w @ P
    ### END SOLUTION

# %% deformlab={"tests": "centroid", "points": 2}
_P = np.array([[0.0, 0.0], [4.0, 0.0], [0.0, 2.0], [4.0, 2.0]])
_c = centroid(_P)
assert np.shape(_c) == (2,), (
    f"the centroid of 4 points in 2D has shape (2,), got {np.shape(_c)}: average over the points (axis 0)"
)
assert np.allclose(_c, [2.0, 1.0]), f"centroid of the corners of [0, 4] x [0, 2]: expected [2, 1], got {_c}"
_c = centroid(np.eye(3))
assert np.allclose(_c, [1 / 3, 1 / 3, 1 / 3]), f"centroid of the rows of the 3x3 identity: expected [1/3, 1/3, 1/3], got {_c}"

_w = np.array([1.0, 3.0, 0.0, 0.0])
_c = centroid(_P, _w)
assert np.allclose(_c, [3.0, 0.0]), (
    f"weights {_w.tolist()}: expected (1·[0, 0] + 3·[4, 0]) / 4 = [3, 0], got {_c}"
    + (": the weights are ignored" if np.allclose(_c, [2.0, 1.0]) else "")
)
_c = centroid(_P, 10 * _w)
assert np.allclose(_c, [3.0, 0.0]), (
    f"weights {(10 * _w).tolist()} must give the same centroid [3, 0] as {_w.tolist()}, got {_c}: "
    "divide by the sum of the weights, not by the number of points"
)

# %% [markdown]
# ## 2. The rotation part: the covariance matrix
#
# Put $t = \bar q - R\bar p$ back into $E$. With the **centred** points
# $v_i = p_i - \bar p$ and $v'_i = q_i - \bar q$,
# $R p_i + t - q_i = R v_i - v'_i$, and expanding the square gives
#
# $$E = \sum_i w_i \big(v_i^\top R^\top R\, v_i - 2\, {v'_i}^{\top} R\, v_i + {v'_i}^{\top} v'_i\big)
#     = \underbrace{\sum_i w_i \big(\lVert v_i \rVert^2 + \lVert v'_i \rVert^2\big)}_{\text{independent of } R}
#       \;-\; 2 \sum_i w_i\, {v'_i}^{\top} R\, v_i,$$
#
# because $R^\top R = I$. A number is its own trace and the trace is invariant
# under cyclic permutations, so ${v'_i}^{\top} R v_i = \operatorname{tr}(R\, v_i {v'_i}^{\top})$ and
#
# $$\sum_i w_i\, {v'_i}^{\top} R\, v_i = \operatorname{tr}(R S), \qquad
# S = \sum_i w_i\, v_i {v'_i}^{\top} .$$
#
# **Minimizing $E$ over $R$ is maximizing $\operatorname{tr}(RS)$.** All that the
# points tell about the best $R$ is in the $d \times d$ matrix $S$, however many
# points there are.
#
# `covariance_matrix(P, Q, w=None)` returns $S$, shape `(d, d)`. Without a loop:
# the lecture stacks the centred points as the *columns* of $\mathbf V$ and
# $\mathbf V'$ ($d \times k$), and with $W = \operatorname{diag}(w)$ the weighted sum is
# $S = \mathbf V W \mathbf V'^\top$ (the lecture's "covariance matrix" $\mathbf V \mathbf V'^\top$
# when every $w_i = 1$). In numpy the points are rows, so the centred `P` is
# $\mathbf V^\top$: multiply its rows by $w$ with broadcasting rather than
# building $W$. Mind the order: $p$ on the left, $q$ on the right;
# the transpose of $S$ is the covariance of the reverse problem, mapping $Q$ to $P$.

# %% deformlab={"solution": "covariance_matrix"}
import numpy as np


def covariance_matrix(P, Q, w=None):
    """The weighted covariance ``S = Σ w_i (p_i - p̄)(q_i - q̄)ᵀ`` of two corresponding point sets.

    Parameters
    ----------
    P, Q : (k, d) array_like of float
        Source and target points, row ``i`` of ``P`` corresponding to row ``i`` of ``Q``.
    w : (k,) array_like of float, optional
        Non-negative weights; all ones by default. ``p̄`` and ``q̄`` are the weighted centroids.

    Returns
    -------
    S : (d, d) numpy.ndarray
    """
    ### BEGIN SOLUTION
    P, Q = np.asarray(P, dtype=float), np.asarray(Q, dtype=float)
    w = np.ones(len(P)) if w is None else np.asarray(w, dtype=float)
    P_centred = P - centroid(P, w)
    Q_centred = Q - centroid(Q, w)
    # Σ_i w_i v_i v′_iᵀ as one matrix product: (w_i v_i) as columns times v′_i as rows
    return (w[:, None] * P_centred).T @ Q_centred
    ### END SOLUTION

# %% deformlab={"tests": "covariance_matrix", "points": 3}
_P = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 2.0], [0.0, -2.0]])
_Q = _P @ rotation_2d(np.pi / 2).T  # each q_i is p_i turned by 90 degrees
_expected = np.array([[0.0, 2.0], [-8.0, 0.0]])
_S = covariance_matrix(_P, _Q)
assert np.shape(_S) == (2, 2), f"S is d x d = (2, 2) for points in 2D, whatever their number; got shape {np.shape(_S)}"
assert np.allclose(_S, _expected), (
    f"P turned by 90 degrees: expected S = {_expected.tolist()}, got {np.round(_S, 6).tolist()}"
    + (": that is the transpose, S = sum_i w_i v_i v′_iᵀ has p on the left" if np.allclose(_S, _expected.T) else "")
    + (": S is a sum, not an average" if np.allclose(_S * len(_P), _expected) else "")
)
_S = covariance_matrix(_P + [5.0, -1.0], _Q + [10.0, 3.0])
assert np.allclose(_S, _expected), (
    f"translating P and Q must not change S: expected {_expected.tolist()}, got {np.round(_S, 6).tolist()}: "
    "subtract the centroids before multiplying"
)

_w = np.array([1.0, 0.0, 1.0, 0.0])
_expected = np.array([[1.0, 0.5], [-2.0, -1.0]])
_S = covariance_matrix(_P, _Q, _w)
assert np.allclose(_S, _expected), (
    f"weights {_w.tolist()}: expected S = {_expected.tolist()}, got {np.round(_S, 6).tolist()}: "
    "centre with the weighted centroids, and weight each term w_i v_i v′_iᵀ once"
)
_S = covariance_matrix(_P, _Q, 2 * _w)
assert np.allclose(_S, 2 * _expected), (
    f"S is a weighted sum, so doubling the weights doubles S: weights {(2 * _w).tolist()} must give "
    f"{(2 * _expected).tolist()}, got {np.round(_S, 6).tolist()}"
)

# %% [markdown]
# ## 3. The best orthogonal matrix: the SVD
#
# Take the singular value decomposition
#
# $$S = U \Sigma \tilde U^\top, \qquad U, \tilde U \text{ orthogonal}, \qquad
# \Sigma = \operatorname{diag}(\sigma_1, \dots, \sigma_d), \quad \sigma_1 \ge \dots \ge \sigma_d \ge 0$$
#
# (the lecture's letters: $U$ is the left factor, $\tilde U$ the right one; in
# code we call them `U_svd` and `U_tilde`, because `U` is the name of the
# deformed positions from stage 03 on). Then, using the
# cyclic invariance of the trace once more,
#
# $$\operatorname{tr}(R S) = \operatorname{tr}(R\, U \Sigma \tilde U^\top)
# = \operatorname{tr}(\Sigma\, \tilde U^\top R\, U) = \operatorname{tr}(\Sigma M)
# = \sum_{i=1}^d \sigma_i\, m_{ii},
# \qquad M = \tilde U^\top R\, U.$$
#
# $M$ is a product of orthogonal matrices, hence orthogonal, and every orthogonal
# $M$ comes from exactly one $R = \tilde U M U^\top$: maximizing over $R$ is
# maximizing over $M$. The columns of an orthogonal matrix are unit vectors, so
# $|m_{ii}| \le 1$ and, since $\sigma_i \ge 0$,
#
# $$\operatorname{tr}(R S) = \sum_i \sigma_i\, m_{ii} \;\le\; \sum_i \sigma_i .$$
#
# The bound is reached by $M = I$, that is
#
# $$\boxed{R = \tilde U U^\top}$$
#
# When every $\sigma_i > 0$ it is the only maximizer (equality forces every
# $m_{ii} = 1$, hence $M = I$). When $\sigma_d = 0$ (all points on a line in 2D,
# or in a plane in 3D) $m_{dd}$ does not matter and several $R$ are optimal; any
# of them is a correct answer.
#
# `optimal_orthogonal(S)` returns $R$, shape `(d, d)`. Careful with numpy:
# `U_svd, sigma, U_tilde_T = np.linalg.svd(S)` returns
# `S = U_svd @ np.diag(sigma) @ U_tilde_T`, so its
# third output is already $\tilde U^\top$. Mixing that up gives the transpose
# $R^\top = U \tilde U^\top$, the best map from $Q$ back to $P$.
#
# Note what the derivation did **not** use: $\det R = +1$. Nothing stops
# $\tilde U U^\top$ from being a reflection; that is the subject of stage 02.
# Here, return $\tilde U U^\top$ as it is.

# %% deformlab={"solution": "optimal_orthogonal"}
import numpy as np


def optimal_orthogonal(S):
    """The orthogonal matrix maximizing ``tr(R S)`` (it may be a reflection).

    Parameters
    ----------
    S : (d, d) array_like of float
        A covariance matrix, ``S = U Σ Ũᵀ`` its SVD.

    Returns
    -------
    R : (d, d) numpy.ndarray
        ``R = Ũ Uᵀ``.
    """
    ### BEGIN SOLUTION
    U_svd, sigma, U_tilde_T = np.linalg.svd(np.asarray(S, dtype=float))  # S = U Σ Ũᵀ
    return U_tilde_T.T @ U_svd.T  # R = Ũ Uᵀ
    ### END SOLUTION

# %% deformlab={"tests": "optimal_orthogonal", "points": 3}
_S = np.array([[0.0, 2.0], [-8.0, 0.0]])  # the covariance of the 90-degree example above
_R = optimal_orthogonal(_S)
_R90 = rotation_2d(np.pi / 2)
assert np.shape(_R) == (2, 2), f"R must have the shape of S, (2, 2); got {np.shape(_R)}"
assert np.allclose(_R.T @ _R, np.eye(2), atol=1e-10), f"R must be orthogonal, but RᵀR = {np.round(_R.T @ _R, 6).tolist()}"
assert np.allclose(_R, _R90, atol=1e-10), (
    f"S comes from points turned by 90 degrees, so R should be {np.round(_R90, 6).tolist()}, "
    f"got {np.round(_R, 6).tolist()}"
    + (": that is the transpose; R = Ũ Uᵀ and np.linalg.svd returns Ũᵀ as its third output" if np.allclose(_R, _R90.T) else "")
)

_S = np.random.default_rng(1).normal(size=(3, 3))
_R = optimal_orthogonal(_S)
_best = np.linalg.svd(_S, compute_uv=False).sum()
assert np.allclose(_R.T @ _R, np.eye(3), atol=1e-10), f"R must be orthogonal, but RᵀR = {np.round(_R.T @ _R, 6).tolist()}"
assert np.isclose(np.trace(_R @ _S), _best, atol=1e-10), (
    f"tr(R S) = {np.trace(_R @ _S):.6f}, but the maximum over orthogonal R is the sum of the singular values "
    f"of S, {_best:.6f}: check R = Ũ Uᵀ"
)

_S = np.diag([3.0, 2.0, -1.0])
_R = optimal_orthogonal(_S)
assert np.allclose(_R, np.diag([1.0, 1.0, -1.0]), atol=1e-10), (
    f"for S = diag(3, 2, -1) the best orthogonal R is the reflection diag(1, 1, -1) (tr(R S) = 6), "
    f"got {np.round(_R, 6).tolist()} with det {np.linalg.det(_R):.3f}: optimal_orthogonal maximizes over all "
    "orthogonal matrices, reflections included (correcting the sign is stage 02)"
)

# %% [markdown]
# ## 4. Putting it together
#
# `orthogonal_align(P, Q, w=None)` returns the pair `(R, t)` minimizing $E$ over
# orthogonal $R$: $R$ from the covariance matrix, then $t = \bar q - R \bar p$.
# Use your three functions.

# %% deformlab={"solution": "orthogonal_align"}
def orthogonal_align(P, Q, w=None):
    """The orthogonal map and translation that best move ``P`` onto ``Q``.

    Parameters
    ----------
    P, Q : (k, d) array_like of float
        Corresponding source and target points.
    w : (k,) array_like of float, optional
        Non-negative weights; all ones by default.

    Returns
    -------
    R : (d, d) numpy.ndarray
        Orthogonal (possibly a reflection).
    t : (d,) numpy.ndarray
        Together minimizing ``Σ w_i ‖R p_i + t - q_i‖²``.
    """
    ### BEGIN SOLUTION
    R = optimal_orthogonal(covariance_matrix(P, Q, w))
    t = centroid(Q, w) - R @ centroid(P, w)  # the best t for any fixed R
    return R, t
    ### END SOLUTION

# %% deformlab={"tests": "orthogonal_align", "points": 3}
_P = np.random.default_rng(2).normal(size=(10, 3))
_R0 = rotation_3d([1.0, 2.0, 2.0], 0.8)
_t0 = np.array([1.0, -2.0, 0.5])
_Q = _P @ _R0.T + _t0  # q_i = R0 p_i + t0
_out = orthogonal_align(_P, _Q)
assert isinstance(_out, tuple) and len(_out) == 2, "orthogonal_align must return the pair (R, t)"
_R, _t = _out
assert np.shape(_R) == (3, 3) and np.shape(_t) == (3,), (
    f"in 3D, R must have shape (3, 3) and t shape (3,); got {np.shape(_R)} and {np.shape(_t)}"
)
assert np.allclose(_R, _R0, atol=1e-8), (
    f"Q is P moved rigidly by R0 = {np.round(_R0, 4).tolist()}: expected R = R0, got {np.round(_R, 4).tolist()}"
    + (": that is R0ᵀ, check the order in S and R = Ũ Uᵀ" if np.allclose(_R, _R0.T, atol=1e-8) else "")
)
assert np.allclose(_t, _t0, atol=1e-8), (
    f"expected t = {_t0.tolist()}, got {np.round(_t, 6).tolist()}"
    + (": t = q̄ - R p̄, not q̄ - p̄" if np.allclose(_t, _Q.mean(axis=0) - _P.mean(axis=0)) else "")
)

_H = np.diag([1.0, 1.0, -1.0])
_R, _t = orthogonal_align(_P, _P @ _H + _t0)
assert np.allclose(_R, _H, atol=1e-8), (
    f"Q is the mirror image of P in the plane z = 0 (then translated): the best orthogonal map is the reflection "
    f"diag(1, 1, -1), got {np.round(_R, 4).tolist()} with det {np.linalg.det(_R):.3f}"
)

_Q_outlier = _Q.copy()
_Q_outlier[0] += [5.0, 5.0, 5.0]
_w = np.ones(len(_P))
_w[0] = 0.0
_R, _t = orthogonal_align(_P, _Q_outlier, _w)
assert np.allclose(_R, _R0, atol=1e-8) and np.allclose(_t, _t0, atol=1e-8), (
    "point 0 is an outlier with weight 0, so (R, t) must be exactly (R0, t0) as without it; "
    f"got R = {np.round(_R, 4).tolist()}, t = {np.round(_t, 4).tolist()}: are the weights passed on to "
    "covariance_matrix and to both centroids?"
)

# %% [markdown]
# Back to the character: aligned, the source lands on the target up to the noise.

# %%
R, t = orthogonal_align(P, Q)
rms_before = np.sqrt(np.mean(np.sum((P - Q) ** 2, axis=1)))
rms_after = np.sqrt(np.mean(np.sum((P @ R.T + t - Q) ** 2, axis=1)))
print(f"det R = {np.linalg.det(R):+.3f}; RMS distance to Q: {rms_before:.3f} before, {rms_after:.3f} after "
      f"(the noise alone: {np.sqrt(P.shape[1]) * 0.01 * size:.3f})")
plotting.show_points(P, Q, P @ R.T + t, title="P aligned to Q by orthogonal_align")

# %% [markdown]
# The distance falls from <span class="measured">2.725</span> to <span class="measured">0.039</span>, the size of the noise
# itself (<span class="measured">0.038</span>): nothing of the misfit is left but the noise.
#
# Now let the target be the **mirror image** of the character. The fit is
# perfect, and $\det R = -1$: $R$ is a reflection, a map no rigid motion of the
# plane can perform.

# %%
Q_mirror = P * np.array([-1.0, 1.0]) + np.array([1.2, 0.0]) * size
R, t = orthogonal_align(P, Q_mirror)
rms = np.sqrt(np.mean(np.sum((P @ R.T + t - Q_mirror) ** 2, axis=1)))
print(f"det R = {np.linalg.det(R):+.3f}; RMS distance to the mirrored target: {rms:.2e}")
plotting.show_points(P, Q_mirror, P @ R.T + t, title=f"mirrored target: det R = {np.linalg.det(R):+.0f}")

# %% [markdown]
# **Question.** When does the optimal orthogonal map $\tilde U U^\top$ turn out to
# be a reflection ($\det = -1$)? Why is that bad when we use shape matching to
# deform a shape (think of the local step of ARAP, which fits one such map to the
# neighbourhood of every vertex)? Answer in a few sentences in the cell below.

# %% [markdown] deformlab={"answer": "reflection", "points": 2}
# $\det(\tilde U U^\top) = -1$ whenever a mirror image explains the data at least as
# well as any rotation: (1) the target really is (close to) a mirror image of the
# source, e.g. a neighbourhood that was flipped or folded over; (2) the data are
# degenerate, all points on a line in 2D or in a plane in 3D: then
# $\sigma_d = 0$, a rotation and its composition with the mirror across that
# line or plane fit equally well, and the sign of the last singular vectors, hence
# of $\det$, is an accident of the SVD; (3) nearly degenerate data plus noise (or
# a large deformation), where $\sigma_d$ is tiny and the noise decides the sign.
# It is bad for deformation because a reflection is not a motion of a physical
# body: it turns the local frame inside out. Where the mirror image really fits
# better (case 1, for a cell that is not flat), ARAP's local step would ask the
# global step to make the neighbourhood a mirror image of its rest shape:
# flipped (inverted) triangles and folds. For a flat cell (case 2: a planar
# neighbourhood of a surface in 3D) the mirror across the cell's own plane leaves
# every edge of the cell unchanged, so the reflection flips nothing there; but
# which of the two the SVD returns is then an accident (case 3: decided by noise),
# it can change from one iteration or one vertex to the next, and a reflection
# sends the normal to its opposite, which the neighbouring, non-flat cells then
# have to fight. We want the best *rotation*, $\det R = +1$, the motion of a
# rigid body.
