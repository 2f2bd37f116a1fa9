"""Forward kinematics of a planar skeleton: per-bone rotation angles to per-bone affine transforms.

A skeleton is a set of bones, each turning about its **joint** (its first
vertex: the course characters' bones are vertex chains ordered from start to
end), and a **parent** array saying which bone each bone hangs on. A bone's
transform is its own rotation about its joint followed by its parent's
transform, so turning the spine carries the arms along; the root bones (no
parent) share an optional translation that moves the whole character.

The transforms are ``(m, 2, 3)`` affine maps ``[A | t]``, ready for linear
blend skinning: ``u = Σ_j w_j T_j [v; 1]``.
"""

from __future__ import annotations

import numpy as np

from starter.validation import as_float_array, as_points

__all__ = ["CHARACTER_PARENTS", "bone_joints", "bone_transforms"]

CHARACTER_PARENTS = (-1, 0, 0, -1, -1)
"""Parents of the course characters' bones (spine, left arm, right arm, left leg,
right leg): the arms hang on the spine, the spine and the legs are roots."""


def bone_joints(V, bones):
    """The joint of every bone: the position of its first vertex.

    Parameters
    ----------
    V : (n, 2) array_like of float
        Rest positions.
    bones : sequence of (k_j,) array_like of int
        One vertex chain per bone, ordered from the joint to the tip
        (``load_handles(name)["bones"]``).

    Returns
    -------
    (m, 2) numpy.ndarray of float64
        ``V[bones[j][0]]`` for every bone ``j``.
    """
    V = as_points(V, "V", dims=(2,))
    if isinstance(bones, (str, bytes)) or not hasattr(bones, "__len__") or len(bones) == 0:
        raise ValueError("bones must be a non-empty sequence of vertex index arrays, one per bone")
    firsts = []
    for j, bone in enumerate(bones):
        a = np.asarray(bone)
        if a.ndim != 1 or a.size == 0 or a.dtype == bool or not np.issubdtype(a.dtype, np.integer):
            raise ValueError(f"bones[{j}] must be a non-empty 1-D integer array of vertex indices, got shape {a.shape} and dtype {a.dtype}")
        if not 0 <= a[0] < len(V):
            raise ValueError(f"bones[{j}][0] = {int(a[0])} is out of range: there are {len(V)} vertices")
        firsts.append(int(a[0]))
    return V[firsts]


def _parents(parents, m: int) -> np.ndarray:
    """Check a parent array: ``(m,)`` integers, ``-1`` for a root, otherwise another bone, no cycle."""
    a = np.asarray(parents)
    if a.ndim != 1 or len(a) != m:
        raise ValueError(f"parents must have one entry per bone ({m}), got shape {a.shape}")
    if a.size and (a.dtype == bool or not np.issubdtype(a.dtype, np.integer)):
        raise ValueError(f"parents must be integers (a bone index, or -1 for a root), got dtype {a.dtype}")
    a = a.astype(np.int64)
    bad = (a < -1) | (a >= m)
    if bad.any():
        j = int(np.flatnonzero(bad)[0])
        raise ValueError(f"parents[{j}] = {a[j]} is neither -1 (a root) nor a bone index in [0, {m})")
    # Following parent links m times from every bone ends at -1 unless the links loop.
    ancestor = a.copy()
    for _ in range(m):
        ancestor = np.where(ancestor >= 0, a[np.maximum(ancestor, 0)], -1)
    if (ancestor >= 0).any():
        j = int(np.flatnonzero(ancestor >= 0)[0])
        raise ValueError(f"parents has a cycle: following the parents of bone {j} never reaches a root (-1)")
    return a


def bone_transforms(joints, angles, parents, translation=None):
    """Forward kinematics: one affine transform per bone from per-bone angles.

    Bone ``j`` turns by ``angles[j]`` about its rest joint ``joints[j]``, then
    moves with its parent:

    ``T_j = T_{parents[j]} ∘ R_j``, with ``R_j [x; 1] = Rot(angles[j]) (x - joints[j]) + joints[j]``,

    and a root bone (``parents[j] == -1``) is moved by the root translation:
    ``T_j = Trans(translation) ∘ R_j``. Angles are therefore relative to the
    parent, and a child's joint moves exactly as its parent's transform moves it.

    Parameters
    ----------
    joints : (m, 2) array_like of float
        Rest position of every bone's joint (see :func:`bone_joints`).
    angles : (m,) array_like of float
        Counter-clockwise rotation of every bone about its joint, in radians.
    parents : (m,) array_like of int
        The bone each bone hangs on, ``-1`` for a root; no cycles. Parents may
        come after their children.
    translation : (2,) array_like of float, optional
        Translation applied to the roots (and so to every bone); default zero.

    Returns
    -------
    T : (m, 2, 3) numpy.ndarray of float64
        ``T[j] = [A_j | t_j]``, a rigid motion (``A_j`` a rotation).

    Raises
    ------
    ValueError
        If a shape does not match, a value is not finite, or ``parents`` has an
        index out of range or a cycle.
    """
    joints = as_points(joints, "joints", dims=(2,))
    m = len(joints)
    angles = as_float_array(angles, "angles", ndim=1)
    if len(angles) != m:
        raise ValueError(f"angles must have one entry per bone ({m}), got {len(angles)}")
    parents = _parents(parents, m)
    shift = np.zeros(2) if translation is None else as_float_array(translation, "translation", ndim=1)
    if shift.shape != (2,):
        raise ValueError(f"translation must have shape (2,), got {shift.shape}")

    c, s = np.cos(angles), np.sin(angles)
    local = np.zeros((m, 3, 3))
    local[:, 0, 0], local[:, 0, 1], local[:, 1, 0], local[:, 1, 1] = c, -s, s, c
    local[:, :2, 2] = joints - np.einsum("jab,jb->ja", local[:, :2, :2], joints)
    local[:, 2, 2] = 1.0

    # Compose level by level: every bone of depth k has its parent (depth k - 1) done.
    depth = np.zeros(m, dtype=np.int64)
    ancestor = parents.copy()
    while (ancestor >= 0).any():
        depth += ancestor >= 0
        ancestor = np.where(ancestor >= 0, parents[np.maximum(ancestor, 0)], -1)
    world = np.empty_like(local)
    roots = parents < 0
    world[roots] = local[roots]
    world[roots, :2, 2] += shift
    for level in range(1, int(depth.max()) + 1):
        bones = np.flatnonzero(depth == level)
        world[bones] = world[parents[bones]] @ local[bones]
    return world[:, :2, :]
