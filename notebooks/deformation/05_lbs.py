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
# # 05 · Linear blend skinning
#
# ARAP (stage 03) solves an optimization problem for every pose. Games and
# animation tools need hundreds of poses per second for meshes with many
# thousands of vertices, and they use a much simpler rule: every handle $j$
# carries an affine transformation $T_j = [A_j \mid t_j] \in \mathbb R^{d \times (d+1)}$,
# and every vertex moves by a weighted blend of the handles' transformations,
#
# $$
# u_i \;=\; \sum_{j=1}^{m} w_j(v_i)\; T_j \begin{bmatrix} v_i \\ 1 \end{bmatrix}
# \;=\; \sum_{j=1}^{m} w_{ij}\,(A_j v_i + t_j).
# $$
#
# This is *linear blend skinning* (LBS). The weights $w_{ij}$ are computed once,
# in the rest pose (stage 04 computed bounded biharmonic weights for exactly this);
# a pose is nothing but the $m$ transformations.
#
# **Handles.** The same formula serves several kinds of handles; only the
# transformations the user edits differ:
#
# * a **point handle** is a single vertex; moving it sets a translation $t_j$
#   (and, optionally, a rotation or scaling about the point);
# * a **bone** is a segment (a chain of vertices in our meshes); posing a skeleton
#   rotates each bone about its joint, $T_j\,[x; 1] = R_j (x - p_j) + p'_j$ with
#   $p_j$ the joint's rest position and $p'_j$ where it ends up;
# * a **region** is a set of vertices moved together by one rigid or affine map.
#
# **Cages** fit the same mould: the vertices of a coarse polygon (or polyhedron)
# enclosing the shape are point handles that only translate, the weights are
# *generalized barycentric coordinates* of the cage (mean-value, harmonic or
# Green coordinates), and $u_i = \sum_j w_{ij}\, c'_j$ for the moved cage
# vertices $c'_j$. Stage 04 (§9) builds one with `bbw`: the weights are
# constrained to be linear along the cage's edges instead of one-hot.
#
# **Notation.** `V` `(n, d)` rest positions, `W` `(n, m)` weights (one column per
# handle, every row summing to one), `T` `(m, d, d+1)` one affine transformation
# per handle.

# %%
import time

import igl
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from starter import load_handles, load_mesh, plotting, shapes
from starter.posing import CHARACTER_PARENTS, bone_joints, bone_transforms

rng = np.random.default_rng(5)

# %% [markdown]
# ## 1 · LBS as one matrix product
#
# Transpose the formula for one vertex and collect the handles side by side:
#
# $$
# u_i^\top \;=\; \sum_j w_{ij}\, [v_i^\top \; 1]\; T_j^\top
# \;=\; \underbrace{\bigl[\, w_{i1}[v_i^\top \; 1] \;\; w_{i2}[v_i^\top \; 1] \;\cdots\; w_{im}[v_i^\top \; 1] \,\bigr]}_{\text{row } i \text{ of } A}
# \begin{bmatrix} T_1^\top \\ \vdots \\ T_m^\top \end{bmatrix}.
# $$
#
# So $U = A\,T_{\text{stack}}$ with $A$ of size $n \times m(d+1)$,
# $M_{i,\,j(d+1)+c} = w_{ij}\,[v_i; 1]_c$, and $T_{\text{stack}}$ of size
# $m(d+1) \times d$. $A$ depends only on the rest pose and the weights: it is
# computed **once**. Every new pose then costs a single dense product, $O(n\,m\,d^2)$
# operations with no solve and no branching, which is why skinning runs in a GPU
# vertex shader at any frame rate.
#
# (We call it $A$: in stage 04, $M$ is the mass matrix.)
#
# **Your task.** `lbs_matrix(V, W)` returns $A$ (as a dense array; it equals
# `igl.lbs_matrix(V, W)`). Build it with broadcasting: an `(n, m, d+1)` array of
# the products $w_{ij}[v_i;1]_c$ reshaped to `(n, m(d+1))`.

# %% deformlab={"solution": "lbs_matrix"}
import numpy as np


def lbs_matrix(V, W):
    """The linear blend skinning matrix: deformed positions are this matrix times the stacked transforms.

    Parameters
    ----------
    V : (n, d) array_like of float
        Rest positions.
    W : (n, m) array_like of float
        Weights, one column per handle.

    Returns
    -------
    A : (n, m(d+1)) numpy.ndarray
        ``A[i, j(d+1) + c] = W[i, j] · [v_i; 1][c]``, so that ``U = A @ vstack(T_jᵀ)``
        (it equals ``igl.lbs_matrix(V, W)``).
    """
    ### BEGIN SOLUTION
    V, W = np.asarray(V, dtype=float), np.asarray(W, dtype=float)
    n, m = W.shape
    V_homogeneous = np.hstack([V, np.ones((n, 1))])  # rows [v_iᵀ 1]
    # (n, m, d+1): w_ij [v_i; 1]_c, then the handles side by side
    return (W[:, :, None] * V_homogeneous[:, None, :]).reshape(n, -1)
    ### END SOLUTION

# %% deformlab={"tests": "lbs_matrix", "points": 4}
_A = lbs_matrix(np.array([[1.0, 2.0]]), np.array([[0.25, 0.75]]))
_expected = np.array([[0.25, 0.5, 0.25, 0.75, 1.5, 0.75]])
assert _A.shape == (1, 6), f"one vertex in 2D with two handles gives A of shape (1, 2·3) = (1, 6), got {_A.shape}"
assert np.allclose(_A, _expected), (
    f"for v = (1, 2) and w = (0.25, 0.75) the row is [w_1·(1, 2, 1), w_2·(1, 2, 1)] = {_expected.ravel().tolist()}, "
    f"got {np.round(_A, 6).ravel().tolist()}"
)

_V, _F = load_mesh("character")
_W = rng.uniform(size=(len(_V), 4))
_W /= _W.sum(axis=1, keepdims=True)
_A = lbs_matrix(_V, _W)
assert _A.shape == (len(_V), 4 * 3), f"for n = {len(_V)}, m = 4, d = 2 expected shape {(len(_V), 12)}, got {_A.shape}"
_diff = np.abs(_A - igl.lbs_matrix(_V, _W)).max()
assert _diff < 1e-12, f"A differs from igl.lbs_matrix by up to {_diff:.3e}"

_V, _F = load_mesh("cylinder")
_W = rng.uniform(size=(len(_V), 2))
_W /= _W.sum(axis=1, keepdims=True)
_T = rng.normal(size=(2, 3, 4))
_U = lbs_matrix(_V, _W) @ np.vstack([_T[0].T, _T[1].T])
_expected = _W[:, :1] * (_V @ _T[0, :, :3].T + _T[0, :, 3]) + _W[:, 1:] * (_V @ _T[1, :, :3].T + _T[1, :, 3])
_err = np.linalg.norm(_U - _expected, axis=1)
assert _err.max() < 1e-10, (
    f"A @ vstack(T_jᵀ) must give the skinned positions; in 3D vertex {_err.argmax()} is off by {_err.max():.2e}"
)

# %% [markdown]
# ## 2 · Skinning
#
# `lbs(V, W, T)` computes the same deformation straight from the formula, without
# building $A$: transform the rest positions by every handle and blend the
# results with the weights. Two properties of the weights make skinning behave,
# and the tests check that your `lbs` respects them:
#
# * **one-hot rows move rigidly.** A vertex with $w_{ij} = 1$ (a handle vertex)
#   follows $T_j$ exactly;
# * **partition of unity reproduces rigid motions.** If $\sum_j w_{ij} = 1$ and
#   every handle gets the same $T$, then $u_i = \sum_j w_{ij}\,T[v_i; 1] = T[v_i; 1]$:
#   the whole shape moves by $T$, undistorted. Without it, even "move
#   everything 1 cm to the left" would distort the shape.
#
# **Your task.** `lbs(V, W, T)` returns the `(n, d)` deformed positions
# (`np.einsum` over handles and coordinates does it in one line).

# %% deformlab={"solution": "lbs"}
import numpy as np


def lbs(V, W, T):
    """Linear blend skinning.

    Parameters
    ----------
    V : (n, d) array_like of float
        Rest positions.
    W : (n, m) array_like of float
        Weights, one column per handle.
    T : (m, d, d+1) array_like of float
        One affine transformation ``[A_j | t_j]`` per handle.

    Returns
    -------
    U : (n, d) numpy.ndarray
        ``u_i = Σ_j W[i, j] T_j [v_i; 1]``.
    """
    ### BEGIN SOLUTION
    V, W, T = (np.asarray(x, dtype=float) for x in (V, W, T))
    V_homogeneous = np.hstack([V, np.ones((len(V), 1))])
    moved = np.einsum("jdc,ic->ijd", T, V_homogeneous)  # T_j [v_i; 1] for every vertex and handle
    return np.einsum("ij,ijd->id", W, moved)  # blended with the weights
    ### END SOLUTION

# %% deformlab={"tests": "lbs", "points": 4}
_U = lbs(np.array([[1.0, 0.0]]), np.array([[1.0]]), np.array([[[0.0, -1.0, 0.0], [1.0, 0.0, 0.0]]]))
assert np.allclose(_U, [[0.0, 1.0]]), (
    f"one handle turning by 90° (A = [[0, -1], [1, 0]]) must take v = (1, 0) to A v = (0, 1), got {_U.tolist()}"
    + (": you applied Aᵀ" if np.allclose(_U, [[0.0, -1.0]]) else "")
)
# Half way between the identity and a 180° turn, the blended matrix is zero.
_U = lbs(np.array([[1.0, 0.0]]), np.array([[0.5, 0.5]]), np.array([[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], [[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]]]))
assert _U.shape == (1, 2), f"expected shape (1, 2), got {_U.shape}"
assert np.allclose(_U, 0.0), (
    f"v = (1, 0) blended half and half between I and a 180° rotation must go to ½(v - v) = (0, 0), got {_U.tolist()}"
)
_U = lbs(np.array([[1.0, 2.0]]), np.array([[0.25, 0.75]]), np.array([[[1.0, 0.0, 4.0], [0.0, 1.0, 0.0]], [[2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]]))
assert np.allclose(_U, [[2.75, 3.5]]), (
    f"0.25·((1, 2) + (4, 0)) + 0.75·(2, 4) = (2.75, 3.5), got {np.round(_U, 6).tolist()}: is t_j = T[j, :, d]?"
)

_V, _F = load_mesh("character")
_m = 5
_W = rng.uniform(size=(len(_V), _m)) ** 4
_W /= _W.sum(axis=1, keepdims=True)
_T = rng.normal(size=(_m, 2, 3))
_U = lbs(_V, _W, _T)
assert _U.shape == _V.shape, f"U must have the shape of V, {_V.shape}, got {_U.shape}"
_err = np.linalg.norm(_U - lbs_matrix(_V, _W) @ _T.transpose(0, 2, 1).reshape(-1, 2), axis=1)
assert _err.max() < 1e-10, f"lbs(V, W, T) must equal lbs_matrix(V, W) @ vstack(T_jᵀ); vertex {_err.argmax()} is off by {_err.max():.2e}"

_a = 0.8
_rigid = np.array([[np.cos(_a), -np.sin(_a), 0.3], [np.sin(_a), np.cos(_a), -1.2]])
_U = lbs(_V, _W, np.tile(_rigid, (_m, 1, 1)))
_err = np.linalg.norm(_U - (_V @ _rigid[:, :2].T + _rigid[:, 2]), axis=1)
assert _err.max() < 1e-10, f"the same rigid T for every handle must move the shape rigidly; vertex {_err.argmax()} is off by {_err.max():.2e}"

_owner = rng.integers(_m, size=len(_V))
_U = lbs(_V, np.eye(_m)[_owner], _T)
_expected = np.einsum("iab,ib->ia", _T[_owner, :, :2], _V) + _T[_owner, :, 2]
_err = np.linalg.norm(_U - _expected, axis=1)
assert _err.max() < 1e-10, f"a vertex with a one-hot weight row must follow its handle exactly; vertex {_err.argmax()} is off by {_err.max():.2e}"

# %% [markdown]
# ## 3 · Posing the character
#
# We need weights. Stage 04's bounded biharmonic weights are the method of
# choice; to keep this notebook independent of your stage 04, the cell below
# computes **harmonic** weights instead: for each handle $j$, $w_j$ solves
# $L w_j = 0$ at the free vertices, with $w_j = 1$ on handle $j$ and $0$ on the
# other handles (`igl.cotmatrix` is the cotangent Laplacian of stage 03). The
# constant function satisfies the same equations with all handles at 1, so the
# weights sum to one at every vertex automatically; and, unlike biharmonic
# weights, harmonic ones obey a maximum principle, which keeps them within
# $[0, 1]$ on a well-shaped mesh like this one (the cell prints the range). Harmonic weights
# are fine for bones and regions; for single-vertex point handles they form
# sharp spikes (a 2D harmonic function with a point constraint behaves like
# $\log r$), which is one of the reasons stage 04 uses the biharmonic energy.
#
# A bone pose rotates each bone about its joint, the bone's first vertex (the
# vertices of a bone are ordered from its start to its end): the spine turns
# about the pelvis, each leg about its hip, each arm about its shoulder. The
# bones form a small hierarchy: the arms hang on the spine, so an arm's
# transformation is the spine's applied after the arm's own rotation
# (*forward kinematics*).

# %%
def harmonic_weights(V, F, handle_sets):
    """Harmonic weights, one column per handle vertex set (w = 1 on the set, 0 on the other sets)."""
    L = igl.cotmatrix(V, F).tocsr()
    b = np.concatenate(handle_sets)
    owner = np.repeat(np.arange(len(handle_sets)), [len(h) for h in handle_sets])
    bc = np.eye(len(handle_sets))[owner]
    free = np.setdiff1d(np.arange(len(V)), b)
    W = np.zeros((len(V), len(handle_sets)))
    W[b] = bc
    W[free] = spla.spsolve(L[free][:, free].tocsc(), -(L[free][:, b] @ bc))
    return W


V, F = load_mesh("character")
character_handles = load_handles("character")
bones = character_handles["bones"]  # spine, left arm, right arm, left leg, right leg
W_bones = harmonic_weights(V, F, bones)
print(f"character: {len(V)} vertices; weights in [{W_bones.min():.3g}, {W_bones.max():.3g}], "
      f"row sums within {np.abs(W_bones.sum(axis=1) - 1).max():.1e} of 1")
plotting.show_weights(V, F, W_bones, handles=bones)

joints = bone_joints(V, bones)  # each bone's first vertex


def pose(spine, left_arm, right_arm, left_leg, right_leg):
    """One transform per bone from joint angles (radians, counter-clockwise).

    ``CHARACTER_PARENTS`` hangs the arms on the spine: an arm's transform is the
    spine's applied after the arm's own turn about its shoulder.
    """
    return bone_transforms(joints, [spine, left_arm, right_arm, left_leg, right_leg], CHARACTER_PARENTS)


poses = {
    "wave": pose(0.0, -1.2, -0.5, 0.0, 0.0),
    "jump": pose(0.0, -0.9, 0.9, -0.4, 0.4),
    "lean": pose(0.35, 0.3, 0.6, 0.0, 0.15),
}
posed = [(lbs(V, W_bones, T), F) for T in poses.values()]
plotting.show_meshes([(V, F)] + posed, titles=["rest"] + list(poses))

# %% [markdown]
# The region handles (head and feet) give a different kind of control: keep the
# feet where they are, move and turn the head, and the body leans in between.

# %%
regions = character_handles["regions"]  # head, left foot, right foot
W_regions = harmonic_weights(V, F, regions)
# independent regions (no parents): turn the head about its centre and move it, keep the feet
T = bone_transforms([V[r].mean(axis=0) for r in regions], [-0.4, 0.0, 0.0], [-1, -1, -1])
T[0, :, 2] += [0.5, -0.1]
plotting.show_deformation(V, lbs(V, W_regions, T), F, handles=np.concatenate(regions), titles=("rest", "head moved"))

# %% [markdown]
# **Real time.** With $A$ precomputed, a new pose is one matrix product. The
# cell below times an animation of 200 frames both ways.

# %%
frames = [pose(0.0, -1.2 * np.sin(k / 20), -0.5 * np.sin(k / 20), 0.0, 0.0) for k in range(200)]
start = time.perf_counter()
A = lbs_matrix(V, W_bones)
precompute = time.perf_counter() - start
start = time.perf_counter()
for T in frames:
    U = A @ T.transpose(0, 2, 1).reshape(-1, 2)
with_matrix = (time.perf_counter() - start) / len(frames)
start = time.perf_counter()
for T in frames:
    U = lbs(V, W_bones, T)
direct = (time.perf_counter() - start) / len(frames)
print(f"lbs_matrix once: {1e3 * precompute:.2f} ms; per frame: A @ T {1e6 * with_matrix:.0f} µs, lbs {1e6 * direct:.0f} µs")

# %% [markdown]
# ## 4 · The candy wrapper
#
# Now twist. The cylinder's two end caps are the handles; the left one stays,
# the right one turns by $\theta$ about the cylinder's axis. The weight of the
# right handle rises smoothly from 0 to 1 along the axis (a cubic smooth step
# $3s^2 - 2s^3$ of the normalized position $s$), the left one is its complement.
#
# Look at a vertex half way, $w = (\tfrac12, \tfrac12)$. LBS moves it by the
# blended *matrix* $\tfrac12 (I + R_\theta)$. In the plane perpendicular to the
# axis, with complex numbers for rotations,
#
# $$
# \tfrac12\,\bigl(1 + e^{i\theta}\bigr) = \cos\tfrac{\theta}{2}\; e^{i\theta/2} ,
# $$
#
# so the blend does turn the cross-section by the expected $\theta/2$, but it also
# **scales it by $\cos(\theta/2)$**: at $\theta = 180°$ the middle of the cylinder
# collapses to its axis, like the twisted ends of a candy wrapper. The reason is
# general: a weighted average of rotation matrices is not a rotation (rotations do
# not form a linear space), and LBS averages matrices. Skinning methods that
# blend rotations instead, such as dual-quaternion skinning, do not collapse
# this way. ARAP reached in small steps (stage 03) collapses much less, but it
# does shrink too: a surface has no volume to preserve, and a stepwise 180°
# twist of the bar still narrows its middle (stage 03 measures by how much).

# %%
V, F = load_mesh("cylinder")
s = (V[:, 0] - V[:, 0].min()) / np.ptp(V[:, 0])
w_right = 3 * s**2 - 2 * s**3
W_cylinder = np.stack([1.0 - w_right, w_right], axis=1)
middle = np.abs(s - 0.5) < 1e-9  # the ring of vertices half way along the axis

twisted = []
for degrees in (0, 90, 135, 180):
    theta = np.radians(degrees)
    A = np.array([[1.0, 0.0, 0.0], [0.0, np.cos(theta), -np.sin(theta)], [0.0, np.sin(theta), np.cos(theta)]])
    T = np.stack([np.hstack([np.eye(3), np.zeros((3, 1))]), np.hstack([A, np.zeros((3, 1))])])
    U = lbs(V, W_cylinder, T)
    radius = np.linalg.norm(U[middle, 1:], axis=1).mean() / np.linalg.norm(V[middle, 1:], axis=1).mean()
    print(f"twist {degrees:3d}°: middle ring radius × {radius:.4f}   (cos(θ/2) = {np.cos(theta / 2):.4f})")
    twisted.append((U, F))
plotting.show_meshes(twisted, titles=["0°", "90°", "135°", "180°"])

# %% [markdown]
# **Question.** Why does the candy wrapper appear? Explain it for the vertices in
# the middle of the cylinder, and say why better weights (for instance bounded
# biharmonic weights) cannot remove it.

# %% [markdown] deformlab={"answer": "candy_wrapper", "points": 2}
# LBS blends the transformation matrices linearly: a middle vertex with weights
# (½, ½) is moved by ½(I + R_θ). A linear combination of rotations is not a
# rotation: in the plane perpendicular to the axis ½(I + R_θ) = cos(θ/2)·R_{θ/2},
# a rotation by half the angle times a uniform scaling by cos(θ/2). The
# cross-section shrinks, and at θ = 180° the matrix is singular (zero in that
# plane) and the middle ring collapses onto the axis. Any weights must go from
# (1, 0) at the left handle to (0, 1) at the right one continuously, so some
# vertices have weights near (½, ½) whatever the weight function: the problem is
# in the blending of matrices, not in the weights. Remedies blend rotations
# properly (dual quaternions, or interpolating angles) or add more bones along
# the twist so that neighbouring handles differ only by small rotations.

# %% [markdown]
# **Question.** Every row of `W` sums to one here. What would happen to the
# character if you translated every handle by the same vector $t$ and the rows
# summed to something else, say $s_i$ at vertex $i$?

# %% [markdown] deformlab={"answer": "partition_of_unity", "points": 2}
# With T_j = [I | t] for every handle, u_i = Σ_j w_ij (v_i + t) = s_i (v_i + t).
# Unless every s_i = 1, the vertex is scaled towards or away from the origin by
# s_i and translated by s_i t instead of t: the shape distorts (it shrinks where
# s_i < 1, grows where s_i > 1) even though the user only asked for a rigid
# translation, and even the identity pose (t = 0) no longer gives the rest
# shape. With Σ_j w_ij = 1 every common affine map T, in particular every rigid
# motion, is reproduced exactly: u_i = T [v_i; 1].
