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
# *Workload: about 5.2 hours for 5 graded functions (18 points) and 5 written answers (an estimate for a student who attended the lecture).*
#
# ARAP (stage 03) solves an optimization problem for every pose. Games and
# animation tools need hundreds of poses per second for meshes with many
# thousands of vertices, and they use a much simpler rule: every handle $j$
# carries an affine transformation $T_j = [A_j \mid t_j] \in \mathbb R^{d \times (d+1)}$,
# and every vertex moves by a weighted blend of the handles' transformations,
#
# $$
# x'_i \;=\; \sum_{j=1}^{m} w_j(x_i)\; T_j \begin{bmatrix} x_i \\ 1 \end{bmatrix}
# \;=\; \sum_{j=1}^{m} w_{ij}\,(A_j x_i + t_j).
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
# Green coordinates), and $x'_i = \sum_j w_{ij}\, c'_j$ for the moved cage
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

from starter import load_handles, load_mesh, plotting, shapes
from starter.posing import CHARACTER_PARENTS, bone_joints, bone_transforms

rng = np.random.default_rng(5)

# %% [markdown]
# ## 1 · LBS as one matrix product
#
# Transpose the formula for one vertex and collect the handles side by side:
#
# $$
# {x'_i}^\top \;=\; \sum_j w_{ij}\, [x_i^\top \; 1]\; T_j^\top
# \;=\; \underbrace{\bigl[\, w_{i1}[x_i^\top \; 1] \;\; w_{i2}[x_i^\top \; 1] \;\cdots\; w_{im}[x_i^\top \; 1] \,\bigr]}_{\text{row } i \text{ of } A}
# \begin{bmatrix} T_1^\top \\ \vdots \\ T_m^\top \end{bmatrix}.
# $$
#
# So $U = A\,T_{\text{stack}}$ with $A$ of size $n \times m(d+1)$,
# $M_{i,\,j(d+1)+c} = w_{ij}\,[x_i; 1]_c$, and $T_{\text{stack}}$ of size
# $m(d+1) \times d$. $A$ depends only on the rest pose and the weights: it is
# computed **once**. Every new pose then costs a single dense product, $O(n\,m\,d^2)$
# operations with no solve and no branching, which is why skinning runs in a GPU
# vertex shader at any frame rate.
#
# (We call it $A$: in stage 04, $M$ is the mass matrix.)
#
# **Your task.** `lbs_matrix(V, W)` returns $A$ (as a dense array). Build it
# with broadcasting: an `(n, m, d+1)` array of
# the products $w_{ij}[x_i;1]_c$ reshaped to `(n, m(d+1))`.

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
        ``A[i, j(d+1) + c] = W[i, j] · [x_i; 1][c]``, so that ``U = A @ vstack(T_jᵀ)``.
    """
    ### BEGIN SOLUTION
    V, W = np.asarray(V, dtype=float), np.asarray(W, dtype=float)
    n, m = W.shape
    V_homogeneous = np.hstack([V, np.ones((n, 1))])  # rows [x_iᵀ 1]
    # (n, m, d+1): w_ij [x_i; 1]_c, then the handles side by side
    return (W[:, :, None] * V_homogeneous[:, None, :]).reshape(n, -1)
    ### END SOLUTION

# %% deformlab={"tests": "lbs_matrix", "points": 4}
_A = lbs_matrix(np.array([[1.0, 2.0]]), np.array([[0.25, 0.75]]))
_expected = np.array([[0.25, 0.5, 0.25, 0.75, 1.5, 0.75]])
assert _A.shape == (1, 6), f"one vertex in 2D with two handles gives A of shape (1, 2·3) = (1, 6), got {_A.shape}"
assert np.allclose(_A, _expected), (
    f"for v = (1, 2) and w = (0.25, 0.75) the row is [w_1·(1, 2, 1), w_2·(1, 2, 1)] = {_expected.ravel().tolist()}, "
    f"got {np.round(_A, 6).ravel().tolist()}"
    + (": the 1 goes last, [x_i; 1]" if np.allclose(_A, [[0.25, 0.25, 0.5, 0.75, 0.75, 1.5]]) else "")
    + (": the 1 is weighted too, W[i, j]·1" if np.allclose(_A, [[0.25, 0.5, 1.0, 0.75, 1.5, 1.0]]) else "")
    + (": the columns go handle by handle, not coordinate by coordinate"
       if np.allclose(_A, [[0.25, 0.75, 0.5, 1.5, 0.25, 0.75]]) else "")
    + (": the weight enters once, w_ij·[x_i; 1]" if np.allclose(_A, [[0.0625, 0.125, 0.0625, 0.5625, 1.125, 0.5625]]) else "")
)

_V, _F = load_mesh("character")
_W = rng.uniform(size=(len(_V), 4))
_W /= _W.sum(axis=1, keepdims=True)
_A = lbs_matrix(_V, _W)
assert _A.shape == (len(_V), 4 * 3), f"for n = {len(_V)}, m = 4, d = 2 expected shape {(len(_V), 12)}, got {_A.shape}"
_identity = np.tile(np.eye(2, 3), (4, 1, 1))
_U = _A @ _identity.transpose(0, 2, 1).reshape(-1, 2)
assert np.allclose(_U, _V), "the rows of W sum to 1, so with every T_j = [I | 0] A @ vstack(T_jᵀ) must give V back"
_W2 = rng.uniform(size=_W.shape)
assert np.allclose(lbs_matrix(_V, _W + 3 * _W2), _A + 3 * lbs_matrix(_V, _W2)), "A is linear in W"

_V, _F = load_mesh("cylinder")
_T = rng.normal(size=(2, 3, 4))
_owner = rng.integers(2, size=len(_V))
_U = lbs_matrix(_V, np.eye(2)[_owner]) @ np.vstack([_T[0].T, _T[1].T])
_err = np.linalg.norm(_U - (np.einsum("iab,ib->ia", _T[_owner, :, :3], _V) + _T[_owner, :, 3]), axis=1)
assert _err.max() < 1e-10, (
    f"with one-hot weight rows, A @ vstack(T_jᵀ) must move each vertex by its own handle's transform; "
    f"in 3D vertex {_err.argmax()} is off by {_err.max():.2e}"
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
#   every handle gets the same $T$, then $x'_i = \sum_j w_{ij}\,T[x_i; 1] = T[x_i; 1]$:
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
        ``x'_i = Σ_j W[i, j] T_j [x_i; 1]``.
    """
    ### BEGIN SOLUTION
    V, W, T = (np.asarray(x, dtype=float) for x in (V, W, T))
    V_homogeneous = np.hstack([V, np.ones((len(V), 1))])
    moved = np.einsum("jdc,ic->ijd", T, V_homogeneous)  # T_j [x_i; 1] for every vertex and handle
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
# x'_i is linear in the transforms and in the weights
_T2 = rng.normal(size=_T.shape)
_err = np.linalg.norm(lbs(_V, _W, _T + 2 * _T2) - (_U + 2 * lbs(_V, _W, _T2)), axis=1)
assert _err.max() < 1e-10, f"lbs must be linear in T: lbs(V, W, T + 2 T2) = lbs(V, W, T) + 2 lbs(V, W, T2); vertex {_err.argmax()} is off by {_err.max():.2e}"
_W2 = rng.uniform(size=_W.shape)
_err = np.linalg.norm(lbs(_V, _W + _W2, _T) - (_U + lbs(_V, _W2, _T)), axis=1)
assert _err.max() < 1e-10, f"lbs must be linear in W (no normalization inside); vertex {_err.argmax()} is off by {_err.max():.2e}"

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
    """Harmonic weights, one column per handle vertex set (w = 1 on the set, 0 on the other sets), by libigl."""
    b = np.concatenate(handle_sets)
    owner = np.repeat(np.arange(len(handle_sets)), [len(h) for h in handle_sets])
    return igl.harmonic(V, F, b, np.eye(len(handle_sets))[owner], 1)


V, F = load_mesh("character")
character_handles = load_handles("character")
bones = character_handles["bones"]  # spine, left arm, right arm, left leg, right leg
W_bones = harmonic_weights(V, F, bones)
print(f"character: {len(V)} vertices; weights in [{W_bones.min():.3g}, {W_bones.max():.3g}], "
      f"row sums within {np.abs(W_bones.sum(axis=1) - 1).max():.1e} of 1")
plotting.show_weights(V, F, W_bones, handles=bones,
                      titles=[f"harmonic: {name}" for name in ("spine", "left arm", "right arm", "left leg", "right leg")])

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
# ## 4 · Twisting a cylinder
#
# Now twist. The cylinder (`load_mesh("cylinder")`, its axis along $x$ through
# the origin) has two handles, its end caps; the left one stays, the right one
# turns by $\theta$ about the cylinder's axis. The weight of the right handle
# rises smoothly from 0 to 1 along the axis (a cubic smooth step $3s^2 - 2s^3$ of
# the normalized position $s$), the left one is its complement, so the ring of
# vertices half way along the axis has the weights $(\tfrac12, \tfrac12)$.
#
# **Predict first.** Before you write the next cell: when the right end turns by
# 90°, and then by 180°, by how much does the middle ring turn, and what is its
# radius compared with the rest pose (×1, ×0.9, ×0.7, ×0.5, ×0)? Sketch the
# cylinder at 180°.

# %% [markdown] deformlab={"answer": "predict_candy_wrapper", "points": 1}
# The middle ring turns by half the angle (45°, then 90°), but it also shrinks:
# ×0.71 at 90° and ×0 at 180°, where the middle collapses onto the axis: the
# cylinder is pinched in the middle like a candy wrapper. (Any prediction with a
# reason earns the point; the measurement decides.)

# %% [markdown]
# **Your turn.** Write `twist_transforms(theta)`: the two handles'
# transformations `T` `(2, 3, 4)`, the left one the identity, the right one the
# turn by $\theta$ (radians) about the $x$ axis, no translation. The cell after
# it skins the cylinder with them and **your** `lbs`, and measures the middle
# ring's mean distance from the axis divided by its rest value.

# %%
V, F = load_mesh("cylinder")
along = (V[:, 0] - V[:, 0].min()) / np.ptp(V[:, 0])  # 0 at the left cap, 1 at the right one
W_cylinder = np.stack([1.0 - (3 * along**2 - 2 * along**3), 3 * along**2 - 2 * along**3], axis=1)
middle = np.abs(along - 0.5) < 1e-9  # the ring of vertices half way along the axis

# %% deformlab={"exercise": "candy_wrapper"}
def twist_transforms(theta):
    """(2, 3, 4) transforms: the left handle still, the right one turned by ``theta`` about the x axis."""
    ### BEGIN SOLUTION
    turn_x = np.array([[1.0, 0.0, 0.0], [0.0, np.cos(theta), -np.sin(theta)], [0.0, np.sin(theta), np.cos(theta)]])
    return np.stack([np.eye(3, 4), np.hstack([turn_x, np.zeros((3, 1))])])
    ### END SOLUTION


# %%
twisted = []
for degrees in (0, 90, 135, 180):
    U = lbs(V, W_cylinder, twist_transforms(np.radians(degrees)))
    radius = np.linalg.norm(U[middle, 1:], axis=1).mean() / np.linalg.norm(V[middle, 1:], axis=1).mean()
    print(f"twist {degrees:3d}°: middle ring radius × {radius:.4f}")
    twisted.append((U, F))
plotting.show_meshes(twisted, titles=["0°", "90°", "135°", "180°"])

# %% [markdown]
# **Question.** Could better weights remove the candy wrapper, for instance
# bounded biharmonic weights, or weights that change more slowly along the axis?
# Argue for the 180° twist, whatever weight function goes from the left handle
# to the right one (the text after your answer explains the middle ring's
# numbers).

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
# **Why.** A vertex half way, $w = (\tfrac12, \tfrac12)$, is moved by the
# blended *matrix* $\tfrac12 (I + R_\theta)$. In the plane perpendicular to the
# axis, with complex numbers for rotations,
#
# $$
# \tfrac12\,\bigl(1 + e^{i\theta}\bigr) = \cos\tfrac{\theta}{2}\; e^{i\theta/2} ,
# $$
#
# so the blend does turn the cross-section by the expected $\theta/2$, but it also
# **scales it by $\cos(\theta/2)$** (compare with your measurements: <span class="measured">0.7071</span> at
# 90°, <span class="measured">0.3827</span> at 135°): at $\theta = 180°$ the middle of the cylinder collapses
# to its axis, like the twisted ends of a candy wrapper. The reason is general: a
# weighted average of rotation matrices is not a rotation (rotations do not form
# a linear space), and LBS averages matrices. Skinning methods that blend
# rotations instead, such as dual-quaternion skinning (section 5), do not
# collapse this way. ARAP reached in small steps (stage 03b) collapses much less,
# but it does shrink too: a surface has no volume to preserve, and a stepwise
# 180° twist of the bar still narrows its middle (stage 03b measures by how much).

# %% [markdown]
# **Question.** Partition of unity makes LBS reproduce every common motion
# (section 2). Does it also make LBS independent of where the origin is? Move
# the rest shape by $c$ (so $x_i$ becomes $x_i + c$) and express every handle's
# motion in the moved coordinates ($T_j$ becomes "move back by $c$, apply $T_j$,
# move by $c$"): is the result the old deformed shape moved by $c$? Answer for
# rows summing to one and for rows summing to $s_i \ne 1$.

# %% [markdown] deformlab={"answer": "partition_of_unity", "points": 2}
# In the moved frame the handle j maps x_i + c to T_j[x_i; 1] + c (the same
# motion, expressed around the new origin), so
# x̃′_i = Σ_j w_ij (T_j[x_i; 1] + c) = x′_i + s_i c with s_i = Σ_j w_ij. With rows
# summing to one, x̃′_i = x′_i + c: the deformation does not depend on where the
# origin is, as a deformation of a shape should not. With s_i ≠ 1 the result
# moves by s_i c instead of c, differently at every vertex: the same pose of
# the same shape gives different shapes depending on the coordinate frame the
# rig was built in (and even the identity pose scales the shape about the
# origin by s_i).

# %% [markdown]
# ## 5 · Dual-quaternion skinning
#
# The candy wrapper comes from averaging *matrices*. Kavan et al. (2008) average
# rigid motions instead, in a representation where a weighted sum of rigid
# motions is, after normalizing, again a rigid motion: **unit dual quaternions**.
#
# **Quaternions.** A quaternion $q = (w, \mathbf v) = w + xi + yj + zk$ is stored
# scalar first, `(w, x, y, z)`. The product of $p = (w_1, \mathbf v_1)$ and
# $q = (w_2, \mathbf v_2)$ is
#
# $$
# p\,q = \bigl(w_1 w_2 - \mathbf v_1 \cdot \mathbf v_2,\;\; w_1 \mathbf v_2 + w_2 \mathbf v_1 + \mathbf v_1 \times \mathbf v_2\bigr),
# $$
#
# which does not commute ($\mathbf v_1 \times \mathbf v_2$ changes sign). A unit
# quaternion $q = (\cos\tfrac\theta2, \sin\tfrac\theta2\,\mathbf a)$ is the rotation
# by $\theta$ about the unit axis $\mathbf a$, $x \mapsto q\,(0, x)\,\bar q$ with the
# conjugate $\bar q = (w, -\mathbf v)$. As a matrix,
#
# $$
# R(q) = (w^2 - \mathbf v \cdot \mathbf v)\, I + 2\,\mathbf v \mathbf v^\top + 2w\,[\mathbf v]_\times ,
# $$
#
# so $\operatorname{tr} R = 4w^2 - 1$, $R_{00} = 2x^2 + w^2 - \mathbf v\cdot\mathbf v$,
# and $R - R^\top = 4w\,[\mathbf v]_\times$, $R + R^\top$ holds the products $4xy$, $4xz$, $4yz$.
# $q$ and $-q$ are the same rotation.
#
# **Dual quaternions.** With a symbol $\varepsilon$ such that $\varepsilon^2 = 0$,
# a dual quaternion is $\hat q = q_0 + \varepsilon\, q_e$ (stored as a `(2, 4)` array
# `[q_0, q_e]`). The rigid motion $x \mapsto R x + t$ is the unit dual quaternion
#
# $$
# \hat q = q_0 + \varepsilon\, \tfrac12\,(0, t)\, q_0 , \qquad q_0 \text{ the unit quaternion of } R ,
# $$
#
# and back: $t = 2\operatorname{vec}(q_e\,\bar q_0)$ (the vector part of the product).
#
# **Blending.** Dual-quaternion skinning (DQS) replaces the blend of matrices by
# a blend of dual quaternions, then normalizes:
#
# $$
# \hat b_i = \sum_j w_{ij}\, s_j\, \hat q_j, \qquad
# \hat c_i = \hat b_i / \lVert b_{i,0} \rVert, \qquad
# x'_i = T(\hat c_i)\,[x_i; 1].
# $$
#
# Every vertex moves by a **rigid** motion, whatever the weights: no shrinking.
# The signs $s_j = \pm 1$ matter: $\hat q_j$ and $-\hat q_j$ are the same transform but
# not the same summand. Averaging $q$ with $-q$ would give zero; DQS puts every
# handle on the same side as a *pivot*, handle 0, by flipping $\hat q_j$ when
# $q_{j,0} \cdot q_{0,0} < 0$ (as libigl's `igl::dqs` does). What each function returns
# is in the docstrings of `dual_quaternions` and `dqs` below; DQS is 3D only.
#
# **Your task.** `dual_quaternions(T)` returns the `(m, 2, 4)` unit dual
# quaternions of the rigid transforms `T` `(m, 3, 4)`. Read $q_0$ off $R$ with the
# identities above: of $w^2, x^2, y^2, z^2$ (the diagonal ones) take the largest,
# so that you never divide by a number close to zero (a half turn has $w = 0$),
# and get the other three components from the products with it.

# %% deformlab={"solution": "dual_quaternions"}
import numpy as np


def dual_quaternions(T):
    """Unit dual quaternions of rigid transforms.

    Parameters
    ----------
    T : (m, 3, 4) array_like of float
        Rigid transforms ``[R_j | t_j]``.

    Returns
    -------
    Q : (m, 2, 4) numpy.ndarray
        ``Q[j, 0]`` the unit quaternion ``(w, x, y, z)`` of ``R_j`` (either sign),
        ``Q[j, 1] = ½ (0, t_j) Q[j, 0]``.
    """
    ### BEGIN SOLUTION
    T = np.asarray(T, dtype=float)
    Q = np.zeros((len(T), 2, 4))
    for j, (R, t) in enumerate(zip(T[:, :, :3], T[:, :, 3])):
        if np.abs(R.T @ R - np.eye(3)).max() > 1e-6 or np.linalg.det(R) < 0:
            raise ValueError(f"T[{j}]: the 3x3 part R is no rotation (RᵀR = I and det R = +1 are needed)")
        tr = np.trace(R)
        # P[a, b] = 4 q_a q_b for q = (w, x, y, z): the identities between R and q
        P = np.array([
            [1 + tr, R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]],
            [R[2, 1] - R[1, 2], 1 + 2 * R[0, 0] - tr, R[0, 1] + R[1, 0], R[0, 2] + R[2, 0]],
            [R[0, 2] - R[2, 0], R[0, 1] + R[1, 0], 1 + 2 * R[1, 1] - tr, R[1, 2] + R[2, 1]],
            [R[1, 0] - R[0, 1], R[0, 2] + R[2, 0], R[1, 2] + R[2, 1], 1 + 2 * R[2, 2] - tr],
        ])
        k = np.argmax(np.diag(P))  # the largest |q_k|
        q = P[k] / np.sqrt(4 * P[k, k])  # 4 q_k q_b / (4 |q_k|) = ±q_b
        w, v = q[0], q[1:]
        Q[j, 0] = q
        Q[j, 1] = 0.5 * np.r_[-t @ v, w * t + np.cross(t, v)]  # ½ (0, t) q
    return Q
    ### END SOLUTION

# %% deformlab={"tests": "dual_quaternions", "points": 3}
from scipy.spatial.transform import Rotation as _Rotation

_Q = dual_quaternions(np.eye(3, 4)[None])
assert np.shape(_Q) == (1, 2, 4), f"one transform gives Q of shape (1, 2, 4), got {np.shape(_Q)}"
assert np.allclose(np.abs(_Q[0, 0]), [1, 0, 0, 0]) and np.allclose(_Q[0, 1], 0), (
    f"the identity is q_0 = ±(1, 0, 0, 0), q_e = 0, got {np.round(_Q[0], 6).tolist()}"
    + (": the scalar w must come first, (w, x, y, z)" if np.allclose(np.abs(_Q[0, 0]), [0, 0, 0, 1]) else "")
)
# 90° about z: q_0 = ±(cos 45°, 0, 0, sin 45°)
_Q = dual_quaternions(np.array([[[0.0, -1.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]]]))
_want = np.array([1.0, 0.0, 0.0, 1.0]) / np.sqrt(2)
_hint = ""
if np.allclose(np.abs(_Q[0, 0]), np.abs(_want[[1, 2, 3, 0]])):
    _hint = ": the scalar w must come first, (w, x, y, z)"
elif np.allclose(_Q[0, 0] * np.sign(_Q[0, 0, 0]), [_want[0], 0, 0, -_want[3]]):
    _hint = ": that is the quaternion of Rᵀ (the inverse turn); check the signs of R[k, j] - R[j, k]"
assert np.allclose(_Q[0, 0], _want) or np.allclose(_Q[0, 0], -_want), (
    f"a 90° turn about z is q_0 = ±(cos 45°, 0, 0, sin 45°) = ±{np.round(_want, 4).tolist()}, got {np.round(_Q[0, 0], 4).tolist()}{_hint}"
)
# a half turn about x has w = 0: no division by w
_Q = dual_quaternions(np.array([[[1.0, 0.0, 0.0, 0.0], [0.0, -1.0, 0.0, 0.0], [0.0, 0.0, -1.0, 0.0]]]))
assert np.all(np.isfinite(_Q)) and np.allclose(np.abs(_Q[0, 0]), [0, 1, 0, 0]), (
    f"a half turn about x is q_0 = ±(0, 1, 0, 0), got {np.round(_Q[0, 0], 4).tolist()}: with w = 0, read x from the diagonal first"
)
# a translation by t = (2, 0, 0): q_e = ½ (0, t) (1, 0, 0, 0) = (0, 1, 0, 0)
_Q = dual_quaternions(np.array([[[1.0, 0.0, 0.0, 2.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]]]))
_Q = _Q * np.sign(_Q[0, 0, 0])
assert np.allclose(_Q[0, 1], [0, 1, 0, 0]), (
    f"a translation by (2, 0, 0) has q_e = ½ (0, t) q_0 = (0, 1, 0, 0), got {np.round(_Q[0, 1], 4).tolist()}"
    + (": the factor ½ is missing" if np.allclose(_Q[0, 1], [0, 2, 0, 0]) else "")
)
# random rigid transforms: q_0 must turn points as R does, x ↦ q_0 (0, x) q̄_0, and q_e = ½ (0, t) q_0


def _product(p, q):
    """Quaternion products p q, row by row, (w, x, y, z) scalar first."""
    return np.c_[p[:, 0] * q[:, 0] - np.sum(p[:, 1:] * q[:, 1:], axis=1),
                 p[:, :1] * q[:, 1:] + q[:, :1] * p[:, 1:] + np.cross(p[:, 1:], q[:, 1:])]


_R = _Rotation.random(6, random_state=3).as_matrix()
_t = rng.normal(size=(6, 3))
_Q = dual_quaternions(np.concatenate([_R, _t[:, :, None]], axis=2))
assert np.allclose(np.linalg.norm(_Q[:, 0], axis=1), 1.0, atol=1e-10), "every q_0 must be a unit quaternion"
_x = rng.normal(size=(6, 3))
_turned = _product(_product(_Q[:, 0], np.c_[np.zeros(6), _x]), _Q[:, 0] * [1, -1, -1, -1])[:, 1:]
assert np.allclose(_turned, np.einsum("jab,jb->ja", _R, _x), atol=1e-10), (
    "q_0 (0, x) q̄_0 must be R x: q_0 is not the quaternion of R"
    + ("; it is that of Rᵀ (check the signs of R[k, j] - R[j, k])"
       if np.allclose(_turned, np.einsum("jba,jb->ja", _R, _x), atol=1e-10) else "")
)
_w, _v = _Q[:, 0, :1], _Q[:, 0, 1:]
_right = 0.5 * np.c_[-np.sum(_t * _v, axis=1), _w * _t + np.cross(_t, _v)]
_left = 0.5 * np.c_[-np.sum(_t * _v, axis=1), _w * _t + np.cross(_v, _t)]
assert np.allclose(_Q[:, 1], _right, atol=1e-10), (
    "q_e must be ½ (0, t) q_0, with the same sign as q_0"
    + (": you computed ½ q_0 (0, t); quaternion products do not commute" if np.allclose(_Q[:, 1], _left, atol=1e-10) else "")
)
# A transform that is not rigid has no dual quaternion: the contract asks for a ValueError naming T[j].
for _bad, _why in ((1.5 * np.eye(3), "a rotation scaled by 1.5"), (np.diag([1.0, 1.0, -1.0]), "a reflection (det -1)")):
    try:
        dual_quaternions(np.stack([np.eye(3, 4), np.c_[_bad, np.ones(3)]]))
    except ValueError:
        pass
    except Exception as _exc:  # noqa: BLE001 - any other error is not the one asked for
        raise AssertionError(f"T[1]'s 3x3 part is {_why}: expected a ValueError, got {type(_exc).__name__}: {_exc}") from None
    else:
        raise AssertionError(f"T[1]'s 3x3 part is {_why}, not a rotation: raise a ValueError naming T[1] "
                             "(check RᵀR = I and det R = +1 to 1e-6)")

# %% [markdown]
# **Your task.** `dual_quaternion_transforms(Q)` goes back: for each dual
# quaternion `[q_0, q_e]` (not necessarily unit: DQS will pass weighted sums),
# divide both parts by $\lVert q_0 \rVert$, then $R = R(c_0)$ and
# $t = 2\operatorname{vec}(c_e \bar c_0) = 2\,(w_0 \mathbf v_e - w_e \mathbf v_0 + \mathbf v_0 \times \mathbf v_e)$,
# and return the `(k, 3, 4)` transforms `[R | t]`.

# %% deformlab={"solution": "dual_quaternion_transforms"}
import numpy as np


def dual_quaternion_transforms(Q):
    """Rigid transforms of dual quaternions, normalized first.

    Parameters
    ----------
    Q : (k, 2, 4) array_like of float
        Dual quaternions ``[q_0, q_e]``, ``q_0 != 0``.

    Returns
    -------
    T : (k, 3, 4) numpy.ndarray
        ``[R | t]`` with ``c = q / ‖q_0‖``, ``R`` the rotation of ``c_0``, ``t = 2 vec(c_e c̄_0)``.
    """
    ### BEGIN SOLUTION
    Q = np.asarray(Q, dtype=float)
    T = np.zeros((len(Q), 3, 4))
    for k, (q0, qe) in enumerate(Q):
        c0, ce = q0 / np.linalg.norm(q0), qe / np.linalg.norm(q0)
        w, v, we, ve = c0[0], c0[1:], ce[0], ce[1:]
        cross = np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])  # [v]×
        T[k, :, :3] = (w * w - v @ v) * np.eye(3) + 2 * np.outer(v, v) + 2 * w * cross
        T[k, :, 3] = 2 * (w * ve - we * v + np.cross(v, ve))
    return T
    ### END SOLUTION

# %% deformlab={"tests": "dual_quaternion_transforms", "points": 3}
from scipy.spatial.transform import Rotation as _Rotation

_T = dual_quaternion_transforms(np.array([[[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]]]))
assert np.shape(_T) == (1, 3, 4), f"one dual quaternion gives T of shape (1, 3, 4), got {np.shape(_T)}"
assert np.allclose(_T[0], np.c_[np.eye(3), [2.0, 0.0, 0.0]]), (
    f"[q_0, q_e] = [(1, 0, 0, 0), (0, 1, 0, 0)] is the translation by t = 2 vec(q_e) = (2, 0, 0), got {np.round(_T[0], 4).tolist()}"
)
_c = np.sqrt(0.5)
_T = dual_quaternion_transforms(np.array([[[_c, 0.0, 0.0, _c], [0.0, 0.0, 0.0, 0.0]]]))
assert np.allclose(_T[0, :, :3], [[0, -1, 0], [1, 0, 0], [0, 0, 1]]), (
    f"q_0 = (cos 45°, 0, 0, sin 45°) is the turn by 90° about z, [[0, -1, 0], [1, 0, 0], [0, 0, 1]], got {np.round(_T[0, :, :3], 4).tolist()}"
    + (": R is transposed" if np.allclose(_T[0, :, :3], [[0, 1, 0], [-1, 0, 0], [0, 0, 1]]) else "")
)
_R = _Rotation.random(5, random_state=4).as_matrix()
_T0 = np.concatenate([_R, rng.normal(size=(5, 3, 1))], axis=2)
_Q = dual_quaternions(_T0)
_err = np.abs(dual_quaternion_transforms(_Q) - _T0).max()
assert _err < 1e-10, f"dual_quaternion_transforms(dual_quaternions(T)) must give T back; off by {_err:.2e}"
_scaled = np.concatenate([3.0 * _Q[:2], -0.5 * _Q[2:]])
_T = dual_quaternion_transforms(_scaled)
_err = np.abs(_T - _T0).max()
assert _err < 1e-10, (
    f"3 q̂ and -0.5 q̂ are the same transform as q̂; off by {_err:.2e}"
    + (": divide q_e by ‖q_0‖ too" if np.allclose(_T[:, :, :3], _T0[:, :, :3], atol=1e-10) else ": divide q_0 by its norm")
)

# %% [markdown]
# **Your task.** `dqs(V, W, T)` skins `V` `(n, 3)` with the weights `W` `(n, m)`
# and rigid transforms `T` `(m, 3, 4)`: build the handles' dual quaternions,
# flip those on the other side of handle 0's, blend them with each vertex's
# weights (one matrix product: the weights are `(n, m)`, the dual quaternions
# `(m, 8)` once flattened), turn the blends into transforms and apply them.

# %% deformlab={"solution": "dqs"}
import numpy as np


def dqs(V, W, T):
    """Deform a mesh by dual-quaternion skinning.

    Parameters
    ----------
    V : (n, 3) array_like of float
        Rest positions.
    W : (n, m) array_like of float
        Skinning weights, one column per handle.
    T : (m, 3, 4) array_like of float
        One rigid transform ``[R_j | t_j]`` per handle.

    Returns
    -------
    U : (n, 3) numpy.ndarray
        Each vertex moved by the normalized blend of the handles' dual quaternions,
        every handle on the side of handle 0's.
    """
    ### BEGIN SOLUTION
    V, W = np.asarray(V, dtype=float), np.asarray(W, dtype=float)
    Q = dual_quaternions(T)
    Q[Q[:, 0] @ Q[0, 0] < 0] *= -1  # q̂ and -q̂ are the same motion: put every handle on handle 0's side
    blends = (W @ Q.reshape(len(Q), 8)).reshape(len(V), 2, 4)
    T_blend = dual_quaternion_transforms(blends)  # one rigid motion per vertex
    return np.einsum("iab,ib->ia", T_blend[:, :, :3], V) + T_blend[:, :, 3]
    ### END SOLUTION

# %% deformlab={"tests": "dqs", "points": 4}
from scipy.spatial.transform import Rotation as _Rotation


def _turn_x(degrees):
    a = np.radians(degrees)
    return np.array([[1.0, 0.0, 0.0, 0.0], [0.0, np.cos(a), -np.sin(a), 0.0], [0.0, np.sin(a), np.cos(a), 0.0]])


_V = np.array([[0.0, 1.0, 0.0]])
_U = dqs(_V, np.array([[0.5, 0.5]]), np.stack([_turn_x(0), _turn_x(90)]))
assert np.shape(_U) == (1, 3), f"one vertex gives U of shape (1, 3), got {np.shape(_U)}"
assert np.allclose(_U, [[0.0, np.sqrt(0.5), np.sqrt(0.5)]]), (
    f"half way between 0° and 90° about x, (0, 1, 0) turns by 45° to (0, 0.7071, 0.7071), got {np.round(_U, 4).tolist()}"
    + (": that is linear blend skinning (the point moved inside the circle)" if np.allclose(_U, [[0, 0.5, 0.5]]) else "")
)
_U = dqs(_V, np.array([[0.5, 0.5]]), np.stack([_turn_x(170), _turn_x(-170)]))
assert np.allclose(_U, [[0.0, -1.0, 0.0]]), (
    f"+170° and -170° are 20° apart across the half turn: their middle is 180°, (0, -1, 0), got {np.round(_U, 4).tolist()}"
    + (": flip the dual quaternions on the other side of handle 0's (q_j,0 · q_0,0 < 0) before blending" if np.allclose(_U, _V) else "")
)
# 0° and 190° (= -170°): half way is -85°, the short way. Whether the two quaternions come out on the
# same side depends on the sign dual_quaternions picks; with this pair or the one above they do not.
_U = dqs(_V, np.array([[0.5, 0.5]]), np.stack([_turn_x(0), _turn_x(190)]))
_want = [[0.0, np.cos(np.radians(85)), -np.sin(np.radians(85))]]
assert np.allclose(_U, _want), (
    f"half way between 0° and 190° (= -170°) the short way is -85°, (0, 0.0872, -0.9962), got {np.round(_U, 4).tolist()}"
    + (": that is +95°, the long way; flip the dual quaternions on the other side of handle 0's "
       "(q_j,0 · q_0,0 < 0) before blending" if np.allclose(_U, [[0.0, np.cos(np.radians(95)), np.sin(np.radians(95))]]) else "")
)
_V, _F = load_mesh("cylinder")
_s = (_V[:, 0] - _V[:, 0].min()) / np.ptp(_V[:, 0])
_W = np.c_[1 - _s, _s]
_U = dqs(_V, _W, np.stack([_turn_x(0), _turn_x(150)]))
assert np.shape(_U) == _V.shape, f"U must have the shape of V, {_V.shape}, got {np.shape(_U)}"
_radius = np.linalg.norm(_U[:, 1:], axis=1) / np.maximum(np.linalg.norm(_V[:, 1:], axis=1), 1e-12)
_rim = np.linalg.norm(_V[:, 1:], axis=1) > 0.25
assert np.allclose(_radius[_rim], 1.0, atol=1e-10), (
    f"a twist about the cylinder's axis moves every vertex rigidly about it: the radius must stay; it changes by up to "
    f"{np.abs(_radius[_rim] - 1).max():.3f}"
)
_R = _Rotation.random(4, random_state=5).as_matrix()
_T = np.concatenate([_R, rng.normal(size=(4, 3, 1))], axis=2)
_owner = rng.integers(4, size=len(_V))
_U = dqs(_V, np.eye(4)[_owner], _T)
_err = np.abs(_U - (np.einsum("iab,ib->ia", _T[_owner, :, :3], _V) + _T[_owner, :, 3])).max()
assert _err < 1e-10, f"a vertex with a one-hot weight row must follow its handle exactly; off by {_err:.2e}"
_W = rng.uniform(size=(len(_V), 4))
_U = dqs(_V, _W, np.tile(_T[:1], (4, 1, 1)))
_err = np.abs(_U - (_V @ _T[0, :, :3].T + _T[0, :, 3])).max()
assert _err < 1e-10, f"the same rigid T for every handle must move the shape rigidly (any weights); off by {_err:.2e}"

# %% [markdown]
# ## 6 · Experiment: LBS, DQS and ARAP on a twist and on an elbow
#
# Three ways to deform the same cylinder with the same two handles:
#
# * **LBS** and **DQS** with the weights of section 4;
# * **ARAP** (stage 03's energy, here libigl's implementation of it, on the surface
#   triangles), reaching the pose in 12 small steps of 5 iterations each, each
#   step starting from the last one's result.
#
# Two poses: the **twist** of section 4, by 180° (the right end turns about the
# axis), measured by the radius of the middle ring; and an **elbow**: the left
# half stays, the right half turns by 90° about the $z$ axis through the middle
# of the axis, the weights blending over the 0.8 units around the joint (for
# ARAP, everything outside that zone is a handle moving with its half). The elbow
# is measured by the change of the tube's volume (in % of the joint zone's volume) and by the
# distance of the skin from the bent skeleton, relative to the rest radius:
# its minimum shows a collapse, its maximum a bulge.
#
# **Predict first.** Before you run the next cell, write down, for each of the three methods:
# the middle ring's radius after the 180° twist (×1, ×0.9, ×0.5, ×0?), and whether the
# elbow loses volume, keeps it, or bulges out.

# %% [markdown] deformlab={"answer": "predict_dqs_experiment", "points": 1}
# Twist: LBS collapses the middle ring to the axis (×0, since ½(I + R_180°) is
# zero across the axis); DQS keeps the radius exactly (every vertex moves by a
# rotation about the axis); ARAP in steps keeps most of it but not all (the
# surface shortens its twisted edges a little: ×<span class="measured">0.938</span> measured). Elbow: LBS loses
# volume at the joint (the inner side collapses: skin-to-bone distance ×<span class="measured">0.45</span>,
# volume <span class="measured">−13.1</span> % of the joint zone); DQS keeps the volume (<span class="measured">−0.5</span> %) but bulges on
# the outer side (×<span class="measured">1.06</span>); surface ARAP keeps the skin's edges, not the volume:
# the tube folds at the joint (<span class="measured">−37.9</span> %, the inner side down to ×<span class="measured">0.20</span>, bulge ×<span class="measured">1.25</span>).

# %%
def turn(axis, degrees):
    """(3, 4) rigid turn by ``degrees`` about the coordinate axis ``axis`` (x, y or z) through the origin."""
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    i, j = {"x": (1, 2), "y": (2, 0), "z": (0, 1)}[axis]
    R = np.eye(3)
    R[[i, i, j, j], [i, j, i, j]] = [c, -s, s, c]
    return np.c_[R, np.zeros(3)]


def arap_in_steps(V, F, handles, targets_at, steps=12, iterations=5):
    """libigl's ARAP (spokes and rims, stage 03's energy), the pose reached in ``steps`` steps."""
    data = igl.ARAPData()
    data.energy = igl.ARAP_ENERGY_TYPE_SPOKES_AND_RIMS
    data.max_iter = iterations
    igl.arap_precomputation(V, F, 3, handles.astype(np.int32), data)
    U = V.copy()
    for k in range(1, steps + 1):
        U = igl.arap_solve(targets_at(k / steps), data, U)
    return U


def volume(U, F):
    """Volume enclosed by a closed, outward-oriented triangle mesh (divergence theorem)."""
    return np.einsum("ij,ij->i", U[F[:, 0]], np.cross(U[F[:, 1]], U[F[:, 2]])).sum() / 6


V, F = load_mesh("cylinder")
ends = load_handles("cylinder")
radius = np.linalg.norm(V[:, 1:], axis=1).max()

# the twist: section 4's weights (a smooth step along the axis), 180°
s = (V[:, 0] - V[:, 0].min()) / np.ptp(V[:, 0])
W_cylinder = np.c_[1 - (3 * s**2 - 2 * s**3), 3 * s**2 - 2 * s**3]
middle = np.abs(s - 0.5) < 1e-9
T = np.stack([turn("x", 0), turn("x", 180)])
right = ends["right"]
twist = {
    "LBS": lbs(V, W_cylinder, T),
    "DQS": dqs(V, W_cylinder, T),
    "ARAP, 12 steps": arap_in_steps(
        V, F, np.r_[ends["left"], right], lambda f: np.r_[V[ends["left"]], V[right] @ turn("x", 180 * f)[:, :3].T]
    ),
}
for name, U in twist.items():
    print(f"twist 180°, {name:<15} middle ring radius × {np.linalg.norm(U[middle, 1:], axis=1).mean() / radius:.3f}")
plotting.show_meshes([(U, F) for U in twist.values()], titles=[f"twist 180°: {name}" for name in twist])

# %% [markdown]
# **Your turn: the elbow's handles.** The upper arm (left half) stays; the
# forearm (right half) turns by `degrees` about the $z$ axis through the joint
# $p = (2, 0, 0)$, not through the origin: $x \mapsto R\,(x - p) + p$. Write
# `elbow_transforms(degrees)`, the two handles' `(2, 3, 4)` transforms
# $[R_j \mid t_j]$ (`turn("z", degrees)` is the turn about the origin). The next
# cell skins the cylinder with them, and ARAP moves the forearm's vertices by
# `elbow_transforms(90 * f)[1]` step by step.

# %%
joint = np.array([2.0, 0.0, 0.0])

# %% deformlab={"exercise": "elbow"}
def elbow_transforms(degrees):
    """(2, 3, 4) transforms: the upper arm still, the forearm turned by ``degrees`` about z through ``joint``."""
    ### BEGIN SOLUTION
    R = turn("z", degrees)[:, :3]
    # R (x - p) + p = R x + (p - R p)
    return np.stack([np.eye(3, 4), np.hstack([R, (joint - R @ joint)[:, None]])])
    ### END SOLUTION


# %%
def moved(P, T_j):
    """Points ``P`` (k, 3) moved by one transform ``[R | t]``."""
    return P @ T_j[:, :3].T + T_j[:, 3]


z = np.clip((V[:, 0] - 1.6) / 0.8, 0.0, 1.0)
W_elbow = np.c_[1 - (3 * z**2 - 2 * z**3), 3 * z**2 - 2 * z**3]
T = elbow_transforms(90)
upper, lower = np.flatnonzero(V[:, 0] < 1.6 - 1e-9), np.flatnonzero(V[:, 0] > 2.4 + 1e-9)
elbow = {
    "LBS": lbs(V, W_elbow, T),
    "DQS": dqs(V, W_elbow, T),
    "ARAP, 12 steps": arap_in_steps(
        V, F, np.r_[upper, lower],
        lambda f: np.r_[V[upper], moved(V[lower], elbow_transforms(90 * f)[1])],
    ),
}


def distance_to_segment(P, a, b):
    t = np.clip((P - a) @ (b - a) / ((b - a) @ (b - a)), 0.0, 1.0)
    return np.linalg.norm(P - (a + t[:, None] * (b - a)), axis=1)


hand = moved(np.array([4.0, 0.0, 0.0]), T[1])  # where the far end of the bent axis goes
skin = (np.linalg.norm(V[:, 1:], axis=1) > radius - 1e-9) & (np.abs(V[:, 0] - 2.0) <= 0.4 + 1e-9)
zone_volume = np.pi * radius**2 * 0.8
# The bend turns about z, so seen from outside the inner side of the joint hides behind the tube. Drawn
# instead: the belt of skin around the plane of the bend (rest |z| < 0.4 radius), seen down the z axis,
# whose outline is the inner and the outer side of the joint.
belt = F[np.abs(V[F][:, :, 2].mean(axis=1)) < 0.4 * radius]
pictures = []
for name, U in elbow.items():
    to_bone = np.minimum(distance_to_segment(U, np.zeros(3), joint), distance_to_segment(U, joint, hand)) / radius
    change = (volume(U, F) - volume(V, F)) / zone_volume
    print(f"elbow 90°, {name:<15} volume {100 * change:+5.1f} % of the joint zone; "
          f"skin to bone × {to_bone[skin].min():.2f} (collapse) … × {to_bone[skin].max():.2f} (bulge)")
    pictures.append((U, belt, to_bone))
plotting.show_meshes(pictures, titles=[f"elbow 90°, {name}: belt" for name in elbow], view=(0.0, 0.0, 1.0),
                     label="skin to bone / rest radius", clim=(0.0, 1.3))

# %% [markdown]
# **Question.** DQS moves every vertex rigidly, yet the elbow bulges on its outer
# side. Why? And why does ARAP, which is the most "physical" of the three on the
# twist, do worst on the elbow here?

# %% [markdown] deformlab={"answer": "dqs_bulge", "points": 2}
# A DQS vertex in the joint zone is rotated about the joint by a blended angle
# between 0° and 90°: each point keeps its distance to the joint, so the outer
# side of the zone becomes an arc around the joint instead of following the bent
# bones, and points there end up farther from the skeleton than the rest radius
# (the bulge); the inner side keeps its distance to the joint too, so it folds
# in less than with LBS (skin to bone ×<span class="measured">0.62</span> against ×<span class="measured">0.45</span>) and the volume stays. LBS moves the same vertices by averaged matrices, which
# shrink towards the joint: the inner side collapses and the volume drops. ARAP
# here acts on the surface only: its cells are fans of skin triangles, so it
# keeps the skin's edge lengths and is free to fold the tube at the joint; no
# term in its energy sees the volume. ARAP with tetrahedral cells (a volume
# mesh) penalizes exactly that.
