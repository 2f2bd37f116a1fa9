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
# # 02 · Sign correction: from the best orthogonal map to the best rotation
#
# *Workload: about 1.9 hours for 2 graded functions (7 points) and 1 written answer (an estimate for a student who attended the lecture).*
#
# In stage 01 you found the orthogonal $R$ and the translation $t$ minimizing
#
# $$E(R, t) = \sum_i w_i \,\lVert R p_i + t - q_i \rVert^2 :$$
#
# $t = \bar q - R \bar p$, and $R = \tilde U U^\top$ maximizes $\operatorname{tr}(RS)$,
# where $S = \sum_i w_i\, v_i {v'_i}^{\top} = U \Sigma \tilde U^\top$ is the
# covariance matrix of the centred points. That $R$ is orthogonal, and it may be a
# **reflection**, $\det R = -1$. A deformation needs **rotations**
# ($R^\top R = I$ and $\det R = +1$). This notebook finds out when the reflection
# happens and derives the best rotation.
#
# **How to work.** Write each function in the cell below its explanation,
# replacing `raise NotImplementedError()`, then run the tests cell under it.
# Those tests are there to help you; your functions are graded on more inputs
# than they show. Each notebook stands on its own, so the first two functions are
# the ones you wrote in stage 01: copy them over. They were graded in stage 01;
# here their tests only help you check the copy, and a mistake in them costs no
# points twice.

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
# ## 0. From stage 01: centroids and the covariance matrix
#
# `centroid(P, w=None)` returns the weighted mean $\bar p = \sum_i w_i p_i / \sum_i w_i$, shape `(d,)`.

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

# %% deformlab={"tests": "centroid"}
_P = np.array([[0.0, 0.0], [4.0, 0.0], [0.0, 2.0], [4.0, 2.0]])
_c = centroid(_P)
assert np.shape(_c) == (2,) and np.allclose(_c, [2.0, 1.0]), (
    f"centroid of the corners of [0, 4] x [0, 2]: expected [2, 1] of shape (2,), got {_c}"
)
_w = np.array([1.0, 3.0, 0.0, 0.0])
_c = centroid(_P, 10 * _w)
assert np.allclose(_c, [3.0, 0.0]), (
    f"weights {(10 * _w).tolist()}: expected (10·[0, 0] + 30·[4, 0]) / 40 = [3, 0], got {_c}"
    + (": the weights are ignored" if np.allclose(_c, [2.0, 1.0]) else "")
)

# %% [markdown]
# `covariance_matrix(P, Q, w=None)` returns $S = \sum_i w_i (p_i - \bar p)(q_i - \bar q)^\top$,
# shape `(d, d)`, with the weighted centroids.

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

# %% deformlab={"tests": "covariance_matrix"}
_P = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 2.0], [0.0, -2.0]])
_Q = _P @ rotation_2d(np.pi / 2).T
_S = covariance_matrix(_P + [5.0, -1.0], _Q + [10.0, 3.0])
assert np.shape(_S) == (2, 2) and np.allclose(_S, [[0.0, 2.0], [-8.0, 0.0]]), (
    f"P turned by 90 degrees, then P and Q translated: expected S = [[0, 2], [-8, 0]], got {np.round(_S, 6).tolist()}"
    + (": translating P and Q changed S, subtract the centroids before multiplying"
       if np.allclose(covariance_matrix(_P, _Q), [[0.0, 2.0], [-8.0, 0.0]]) else "")
)
_w = np.array([2.0, 0.0, 2.0, 0.0])
_S = covariance_matrix(_P, _Q, _w)
assert np.allclose(_S, [[2.0, 1.0], [-4.0, -2.0]]), (
    f"weights {_w.tolist()}: expected S = [[2, 1], [-4, -2]], got {np.round(_S, 6).tolist()}"
)

# %% [markdown]
# ## 1. When is the best orthogonal map a reflection?
#
# $\det(\tilde U U^\top) = \det \tilde U \det U = \pm 1$, and which sign comes out
# depends on the data:
#
# - **Mirrored data.** If the target is (close to) a mirror image of the source,
#   the reflection simply fits better than any rotation. You saw it in stage 01
#   with the mirrored character.
# - **Degenerate data.** Suppose all source points lie in a plane with unit normal
#   $n$ (3D), or on a line (2D, with $n$ its normal). Then $v_i^\top n = 0$,
#   so $S^\top n = \sum_i w_i\, v'_i (v_i^\top n) = 0$: $S$ is singular,
#   $\sigma_d = 0$, and $n$ is its last left singular vector (up to sign). The
#   mirror across that plane (or line), $H = I - 2 n n^\top$, fixes every
#   $v_i$, so $R$ and $R H$ move the points identically and fit equally
#   well, yet $\det(RH) = -\det R$. The SVD has to pick a sign for the singular vectors of
#   $\sigma_d = 0$, and nothing in the data prefers one: $\det(\tilde U U^\top)$ is
#   an accident of the algorithm.
# - **Noise.** Nearly degenerate data (a flat patch of a surface, a thin
#   neighbourhood) have a tiny $\sigma_d$, and a little noise, or a large
#   deformation, decides the sign of the determinant.
#
# The degenerate case, measured: the flat (waving) character of stage 01, put
# into 3D and rotated. $R_0$ and its mirrored twin $R_0 H$ fit exactly equally well.

# %%
V_character, _ = load_mesh("character")
P2 = V_character[::10].copy()  # the waving character of stage 01
arm = (P2[:, 0] > 0.4) & (P2[:, 1] > 0.6)
shoulder = np.array([0.3, 1.05])
P2[arm] = (P2[arm] - shoulder) @ rotation_2d(1.0).T + shoulder
P3 = np.column_stack([P2, np.zeros(len(P2))])  # flat: every point in the plane z = 0
R0 = rotation_3d([1.0, 1.0, 0.0], 1.0)
Q3 = P3 @ R0.T
H = np.diag([1.0, 1.0, -1.0])  # the mirror across the plane of the points
S3 = covariance_matrix(P3, Q3)
print("singular values of S:", np.linalg.svd(S3, compute_uv=False))
for label, R_candidate in [("R0    ", R0), ("R0 H  ", R0 @ H)]:
    fit = np.sum((P3 @ R_candidate.T - Q3) ** 2)
    print(f"{label} det = {np.linalg.det(R_candidate):+.0f}   E = {fit:.2e}   tr(R S) = {np.trace(R_candidate @ S3):.6f}")

# %% [markdown]
# And noise: give the flat character a thickness of about $0.001$ (it is about
# $2$ tall), move it by $R_0$, perturb the targets, and count how often the best
# orthogonal map $\tilde U U^\top$ comes out as a reflection.

# %%
P_thin = P3 + np.column_stack([np.zeros((len(P3), 2)), 0.001 * rng.standard_normal(len(P3))])
trials = 200
for noise in [0.0, 0.003, 0.01, 0.03, 0.1]:
    reflections = 0
    for trial in range(trials):
        Q_noisy = P_thin @ R0.T + noise * rng.standard_normal(P_thin.shape)
        U_svd, sigma, U_tilde_T = np.linalg.svd(covariance_matrix(P_thin, Q_noisy))
        reflections += np.linalg.det(U_tilde_T.T @ U_svd.T) < 0
    print(f"noise {noise:5.3f}: sigma_3 = {sigma[2]:.1e}, a reflection in {reflections / trials:4.0%} of {trials} trials")

# %% [markdown]
# With little noise (up to 0.003, three times the thickness) the thin character
# comes out turned, not mirrored, in every trial: a reflection in <span class="measured">0%</span> of them.
# With more, $\sigma_3$ measures the noise rather than the shape and the sign goes
# either way: <span class="measured">8%</span> of the trials at noise 0.01, <span class="measured">36%</span> at 0.03 and
# <span class="measured">52%</span> at 0.1, about a coin toss.

# %% [markdown]
# ## 2. The best rotation
#
# We now maximize $\operatorname{tr}(RS)$ over rotations only. As in stage 01,
# write $\operatorname{tr}(RS) = \operatorname{tr}(\Sigma M) = \sum_i \sigma_i m_{ii}$
# with $M = \tilde U^\top R\, U$. For a rotation,
#
# $$\det M = \det \tilde U^\top \det R \det U = \det(\tilde U U^\top) =: s .$$
#
# **If $s = +1$**, $M = I$ is allowed, and $R = \tilde U U^\top$ is already a
# rotation: nothing to correct.
#
# **If $s = -1$**, we must maximize $\sum_i \sigma_i m_{ii}$ over orthogonal $M$
# with $\det M = -1$. Such an $M$ has the eigenvalue $-1$: its eigenvalues have
# modulus $1$, the non-real ones come in conjugate pairs whose products
# $\lambda \bar\lambda = 1$ are positive, so the real ones ($\pm 1$) must multiply
# to $-1$. The trace is the sum of the eigenvalues, whose real parts are at most
# $1$, hence $\operatorname{tr} M \le -1 + (d - 1) = d - 2$. Split the sum using
# $\sigma_i - \sigma_d \ge 0$ and $m_{ii} \le 1$:
#
# $$\sum_i \sigma_i m_{ii}
# = \sum_i (\sigma_i - \sigma_d)\, m_{ii} + \sigma_d \operatorname{tr} M
# \;\le\; \sum_i (\sigma_i - \sigma_d) + \sigma_d (d - 2)
# = \sigma_1 + \dots + \sigma_{d-1} - \sigma_d .$$
#
# The bound is reached by $M = \operatorname{diag}(1, \dots, 1, -1)$. Both cases
# together:
#
# $$\boxed{R = \tilde U \operatorname{diag}\big(1, \dots, 1, \det(\tilde U U^\top)\big)\, U^\top}$$
#
# In words: **flip the sign of the singular vector of the smallest singular value**
# (the last column of $U$, as the lecture says; flipping the last column of
# $\tilde U$ instead gives the same $R$). Compared with the best orthogonal map, $\operatorname{tr}(RS)$ drops
# by $2\sigma_d$, the least any rotation can lose: flipping the direction of
# $\sigma_i$ instead would lose $2\sigma_i \ge 2\sigma_d$. In the degenerate case
# $\sigma_d = 0$ the correction costs nothing at all: it just picks, of the two
# equally good maps, the rotation.
#
# `optimal_rotation(S)` returns that $R$. It takes a single `(d, d)` matrix **or a
# stack** `(k, d, d)` of them and returns the same shape: ARAP (stage 03) needs
# one rotation per vertex, thousands per iteration, so no Python loop.
# `np.linalg.svd` and `np.linalg.det` work on stacks (they act on the last two
# axes); transpose the last two axes with `np.swapaxes(A, -1, -2)` and index
# columns with `[..., -1]` so that one code path serves both shapes. numpy returns
# the singular values in decreasing order, so the smallest is the last.

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

# %% deformlab={"tests": "optimal_rotation", "points": 4}
_S = np.diag([3.0, 2.0, -1.0])
_R = optimal_rotation(_S)
assert np.shape(_R) == (3, 3), f"R must have the shape of S, (3, 3); got {np.shape(_R)}"
assert abs(np.linalg.det(_R) - 1) < 1e-8, (
    f"S = diag(3, 2, -1): det(R) = {np.linalg.det(_R):.6f}, a rotation has det +1: did you correct the sign?"
)
assert np.allclose(_R, np.eye(3), atol=1e-10), (
    f"S = diag(3, 2, -1): the best rotation is the identity (tr(R S) = 3 + 2 - 1 = 4), got "
    f"{np.round(_R, 6).tolist()} with tr(R S) = {np.trace(_R @ _S):.6f}: flip the singular vector of the "
    "smallest singular value"
)

# A singular S (points in a plane, or on a line in 2D): the sign must still make a rotation.
_S = np.diag([3.0, 2.0, 0.0])
_R = optimal_rotation(_S)
assert np.allclose(_R.T @ _R, np.eye(3), atol=1e-10) and abs(np.linalg.det(_R) - 1) < 1e-8, (
    f"S = diag(3, 2, 0) is singular (coplanar points): R must still be a rotation, got {np.round(_R, 6).tolist()}"
    + (": det(S) = 0 says nothing about the sign; take it from det(Ũ Uᵀ)" if abs(np.linalg.det(_R)) < 1e-8 else "")
)

_S = np.array([[0.0, 2.0], [-8.0, 0.0]])  # points turned by 90 degrees: no correction needed
_R = optimal_rotation(_S)
assert np.allclose(_R, rotation_2d(np.pi / 2), atol=1e-10), (
    f"S = [[0, 2], [-8, 0]] comes from points turned by 90 degrees: expected R = [[0, -1], [1, 0]], "
    f"got {np.round(_R, 6).tolist()}"
    + (": that is the transpose; R = Ũ D Uᵀ, and np.linalg.svd's third output is already Ũᵀ"
       if np.allclose(_R, rotation_2d(np.pi / 2).T, atol=1e-10) else "")
)

_S = np.array([[0.3, -1.2, 0.5], [0.9, 0.4, -0.7], [-0.2, 0.8, 0.6]])
_S = _S * np.array([1.0, 1.0, -1.0])  # det S < 0, so det(Ũ Uᵀ) = -1: the sign needs correcting
_sigma = np.linalg.svd(_S, compute_uv=False)
_R = optimal_rotation(_S)
assert np.allclose(_R.T @ _R, np.eye(3), atol=1e-10), f"R must be orthogonal, but RᵀR = {np.round(_R.T @ _R, 6).tolist()}"
assert abs(np.linalg.det(_R) - 1) < 1e-8, f"det(R) = {np.linalg.det(_R):.6f}, a rotation has det +1: did you correct the sign?"
assert np.isclose(np.trace(_R @ _S), _sigma[0] + _sigma[1] - _sigma[2], atol=1e-10), (
    f"tr(R S) = {np.trace(_R @ _S):.6f}, but the best rotation reaches sigma_1 + sigma_2 - sigma_3 = "
    f"{_sigma[0] + _sigma[1] - _sigma[2]:.6f}: "
    + ("you return the transpose of the best rotation (Rᵀ reaches it); R = Ũ D Uᵀ"
       if np.isclose(np.trace(_R.T @ _S), _sigma[0] + _sigma[1] - _sigma[2], atol=1e-10)
       else "flip the singular vector of the smallest singular value (numpy's last), and check R = Ũ D Uᵀ")
)

_stack = np.random.default_rng(3).normal(size=(6, 3, 3))
try:
    _R = optimal_rotation(_stack)
except Exception as _exc:  # noqa: BLE001 - a single-matrix code path fails on a stack with numpy's own words
    raise AssertionError(
        f"optimal_rotation fails on a stack of shape {np.shape(_stack)}: {type(_exc).__name__}: {_exc}. It must take a stack "
        "(k, d, d) as well as one matrix: np.linalg.svd and det act on the last two axes, so transpose with "
        "np.swapaxes(A, -1, -2) instead of .T, index the last column with [..., -1] and multiply it by sign[..., None]"
    ) from None
assert np.shape(_R) == (6, 3, 3), f"a stack of 6 matrices (6, 3, 3) must give a stack of 6 rotations, got shape {np.shape(_R)}"
for _i in range(len(_stack)):
    _sigma = np.linalg.svd(_stack[_i], compute_uv=False)
    _best = _sigma.sum() - (2 * _sigma[-1] if np.linalg.det(_stack[_i]) < 0 else 0.0)
    assert abs(np.linalg.det(_R[_i]) - 1) < 1e-8, f"stack entry {_i}: det(R) = {np.linalg.det(_R[_i]):.6f}, expected +1"
    assert np.isclose(np.trace(_R[_i] @ _stack[_i]), _best, atol=1e-10), (
        f"stack entry {_i}: tr(R S) = {np.trace(_R[_i] @ _stack[_i]):.6f}, the best rotation reaches {_best:.6f}"
    )
_R = optimal_rotation(np.stack([np.diag([2.0, -1.0]), np.diag([2.0, 1.0])]))
assert np.shape(_R) == (2, 2, 2) and np.allclose(_R, np.eye(2), atol=1e-10), (
    f"the stack [diag(2, -1), diag(2, 1)] must give two identities, got {np.round(_R, 6).tolist()}"
)
# Singular S whose SVD gives det(Ũ Uᵀ) = -1: the flip is needed although det(S) = 0.
for _axis, _angle in [([1.0, -2.0, 0.5], 2.0), ([0.0, 1.0, 1.0], 0.7), ([2.0, 1.0, -1.0], 1.3)]:
    _B = rotation_3d(_axis, _angle)
    _S = np.diag([3.0, 0.0, 2.0]) @ _B.T  # coplanar points; the zero row makes det(S) exactly 0
    _R = optimal_rotation(_S)
    assert np.allclose(_R, _B, atol=1e-10), (
        f"S = diag(3, 0, 2) Bᵀ (B a rotation) is singular, and its best rotation is B itself (tr(B S) = 5); got R "
        f"with det {np.linalg.det(_R):.6f} and tr(R S) = {np.trace(_R @ _S):.6f}"
        + (": det(S) = 0 says nothing about the sign; take it from det(Ũ Uᵀ), which is -1 here"
           if abs(np.linalg.det(_R) - 1) > 1e-8 else ": that is Bᵀ, the transpose; R = Ũ D Uᵀ" if np.allclose(_R, _B.T) else "")
    )

# %% [markdown]
# ## 3. Rigid alignment
#
# `rigid_align(P, Q, w=None)` is `orthogonal_align` of stage 01 with the best
# rotation instead of the best orthogonal map: it returns the pair `(R, t)`
# minimizing $E$ over rotations, with $t = \bar q - R \bar p$ as before (that
# derivation held for any fixed $R$).

# %% deformlab={"solution": "rigid_align"}
def rigid_align(P, Q, w=None):
    """The rotation and translation that best move ``P`` onto ``Q``.

    Parameters
    ----------
    P, Q : (k, d) array_like of float
        Corresponding source and target points.
    w : (k,) array_like of float, optional
        Non-negative weights; all ones by default.

    Returns
    -------
    R : (d, d) numpy.ndarray
        A rotation (``det R = +1``).
    t : (d,) numpy.ndarray
        Together minimizing ``Σ w_i ‖R p_i + t - q_i‖²`` over rotations.
    """
    ### BEGIN SOLUTION
    R = optimal_rotation(covariance_matrix(P, Q, w))
    t = centroid(Q, w) - R @ centroid(P, w)
    return R, t
    ### END SOLUTION

# %% deformlab={"tests": "rigid_align", "points": 3}
_P = np.random.default_rng(4).normal(size=(12, 3))
_R0 = rotation_3d([2.0, -1.0, 1.0], 2.5)
_t0 = np.array([0.5, 1.0, -3.0])
_out = rigid_align(_P, _P @ _R0.T + _t0)
assert isinstance(_out, tuple) and len(_out) == 2, "rigid_align must return the pair (R, t)"
_R, _t = _out
assert np.allclose(_R, _R0, atol=1e-8) and np.allclose(_t, _t0, atol=1e-8), (
    f"Q is P rotated by R0 and translated by t0: expected (R0, t0), got R = {np.round(_R, 4).tolist()}, "
    f"t = {np.round(_t, 4).tolist()}"
    + (": R is R0 transposed; is S built as Σ w v v′ᵀ (P first), and R = Ũ D Uᵀ?" if np.allclose(_R, _R0.T, atol=1e-8)
       else ": R is right, so check t = q̄ - R p̄" if np.allclose(_R, _R0, atol=1e-8) else "")
)

_H = np.diag([1.0, 1.0, -1.0])
_Q = _P @ _H + _t0  # the mirror image of P: no rotation fits exactly
_R, _t = rigid_align(_P, _Q)
assert abs(np.linalg.det(_R) - 1) < 1e-8, (
    f"mirrored target: det(R) = {np.linalg.det(_R):.6f}, a rotation has det +1: did you correct the sign?"
)
_Pc, _Qc = _P - _P.mean(axis=0), _Q - _Q.mean(axis=0)
_sigma = np.linalg.svd(_Pc.T @ _Qc, compute_uv=False)
_E_best = np.sum(_Pc**2) + np.sum(_Qc**2) - 2 * (_sigma[0] + _sigma[1] - _sigma[2])
_E = np.sum((_P @ _R.T + _t - _Q) ** 2)
assert np.allclose(_R.T @ _R, np.eye(3), atol=1e-10) and np.isclose(_E, _E_best, rtol=1e-10), (
    f"mirrored target: the best rotation leaves E = {_E_best:.6f}, got E = {_E:.6f}"
)

_P_flat = np.column_stack([_P[:, :2], np.zeros(len(_P))])  # all points in the plane z = 0
_R, _t = rigid_align(_P_flat, _P_flat @ _R0.T + _t0)
assert np.allclose(_R, _R0, atol=1e-8) and np.allclose(_t, _t0, atol=1e-8), (
    f"flat points rotated by R0: R0 is the only rotation that fits, got R = {np.round(_R, 4).tolist()} "
    f"with det {np.linalg.det(_R):.3f}: both R0 and its mirror fit exactly, the sign correction must pick R0"
)

_Q_outlier = _P @ _R0.T + _t0
_Q_outlier[0] += [5.0, 5.0, 5.0]
_w = np.ones(len(_P))
_w[0] = 0.0
_R, _t = rigid_align(_P, _Q_outlier, _w)
assert np.allclose(_R, _R0, atol=1e-8) and np.allclose(_t, _t0, atol=1e-8), (
    "point 0 is an outlier with weight 0, so (R, t) must be exactly (R0, t0) as without it: are the weights used?"
)

# %% [markdown]
# The mirrored character once more. The best orthogonal map (stage 01, computed
# here in two lines) reproduces the mirror image exactly, by a reflection; the
# best rotation cannot: the grey lines from each point to its target show what
# is left of $E$.

# %%
size = np.linalg.norm(P2.max(axis=0) - P2.min(axis=0))
Q_mirror = P2 * np.array([-1.0, 1.0]) + np.array([1.2, 0.0]) * size
U_svd, sigma, U_tilde_T = np.linalg.svd(covariance_matrix(P2, Q_mirror))
R_orth = U_tilde_T.T @ U_svd.T
t_orth = Q_mirror.mean(axis=0) - R_orth @ P2.mean(axis=0)
R, t = rigid_align(P2, Q_mirror)
print(f"singular values of S: {sigma}")
print(f"best orthogonal map: det = {np.linalg.det(R_orth):+.0f}, tr(R S) = {np.trace(R_orth @ U_svd @ np.diag(sigma) @ U_tilde_T):.4f}")
print(f"best rotation:       det = {np.linalg.det(R):+.0f}, tr(R S) = {np.trace(R @ U_svd @ np.diag(sigma) @ U_tilde_T):.4f}"
      f"  (= sigma_1 - sigma_2 = {sigma[0] - sigma[1]:.4f})")
plotting.show_points(P2, Q_mirror, P2 @ R_orth.T + t_orth, title="best orthogonal map: a reflection, det = -1")
plotting.show_points(P2, Q_mirror, P2 @ R.T + t, title="best rotation: det = +1")

# %% [markdown]
# **Question.** A classmate corrects a reflection differently: whenever
# $\det(\tilde U U^\top) = -1$, return $-\tilde U U^\top$ instead. In 3D, is that a
# rotation? How much of $\operatorname{tr}(RS)$ does it give up compared with
# flipping the smallest singular direction, and what does it do to the thin
# character of §1 in a trial where the SVD came out a reflection?
# Does the trick work in 2D? Finally: what goes wrong when *two* singular values
# vanish (all points on a line in 3D), and does either correction help there?

# %% [markdown] deformlab={"answer": "least_costly_flip", "points": 2}
# In 3D, det(−M) = (−1)³ det M = +1, so −Ũ Uᵀ is a rotation, but the worst one:
# tr(−Ũ Uᵀ S) = −(σ_1 + σ_2 + σ_3), the minimum over all orthogonal maps, against
# σ_1 + σ_2 − σ_3 for the flip of the smallest direction: it gives up
# 2(σ_1 + σ_2) more. For the thin character, whose best orthogonal map is
# R_0 H (H the mirror across its plane, normal n), −R_0 H = R_0 (2 n nᵀ − I) is R_0
# followed by a half turn about n: the points are spun by 180° in their own plane
# and land on the opposite side of the centroid, far from their targets, while
# the correct flip costs only 2σ_3 (σ_3 tiny, of the order of the
# thickness times the noise). In 2D det(−M) = det M = −1: the "correction" is
# still a reflection and fixes nothing. With σ_2 = σ_3 = 0 (collinear points in
# 3D) every rotation about the line fits equally well: a whole circle of
# maximizers, and the SVD picks one of them arbitrarily. The sign correction
# still returns a rotation (det = +1), but no correction can make the answer
# unique; a method that needs R there (ARAP on a degenerate cell) must get the
# missing information elsewhere, e.g. from neighbouring cells or a previous R.
