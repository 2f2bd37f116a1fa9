"""starter.posing: forward kinematics of the course character's skeleton and of random bone forests."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from starter.meshes import load_handles, load_mesh
from starter.posing import CHARACTER_PARENTS, bone_joints, bone_transforms

SETTINGS = settings(max_examples=60, deadline=None)
angle = st.floats(-2 * np.pi, 2 * np.pi, allow_nan=False)
coordinate = st.floats(-3.0, 3.0, allow_nan=False)


@pytest.fixture(scope="module")
def character():
    V, _ = load_mesh("character")
    return V, load_handles("character")["bones"]


@st.composite
def skeletons(draw, max_bones=7):
    """``(joints, angles, parents, translation)``: a random forest, bones in a random order."""
    m = draw(st.integers(1, max_bones))
    # Parents before children first, then a random relabelling so that order does not matter.
    ordered = [draw(st.integers(-1, j - 1)) for j in range(m)]
    perm = np.array(draw(st.permutations(range(m))))  # new label of old bone k is perm[k]
    parents = np.full(m, -1)
    for k, p in enumerate(ordered):
        parents[perm[k]] = -1 if p < 0 else perm[p]
    joints = np.array(draw(st.lists(st.tuples(coordinate, coordinate), min_size=m, max_size=m)))
    angles = np.array(draw(st.lists(angle, min_size=m, max_size=m)))
    translation = np.array(draw(st.tuples(coordinate, coordinate)))
    return joints, angles, parents, translation


def apply(T, x):
    """``T [x; 1]`` for one ``(2, 3)`` transform and one point."""
    return T[:, :2] @ x + T[:, 2]


def homogeneous(T):
    H = np.zeros((3, 3))
    H[:2], H[2, 2] = T, 1.0
    return H


@SETTINGS
@given(skeletons())
def test_the_zero_pose_is_the_identity_for_every_bone(skeleton):
    joints, _, parents, _ = skeleton
    T = bone_transforms(joints, np.zeros(len(joints)), parents)
    assert np.array_equal(T, np.tile(np.eye(2, 3), (len(joints), 1, 1)))


@SETTINGS
@given(skeletons())
def test_every_transform_is_a_rotation_plus_translation(skeleton):
    T = bone_transforms(*skeleton)
    A = T[:, :, :2]
    assert np.allclose(A.transpose(0, 2, 1) @ A, np.eye(2), atol=1e-12)
    assert np.allclose(np.linalg.det(A), 1.0, atol=1e-12)


@SETTINGS
@given(skeletons())
def test_a_childs_joint_moves_exactly_as_its_parents_transform_moves_it(skeleton):
    joints, angles, parents, translation = skeleton
    T = bone_transforms(joints, angles, parents, translation)
    for j in np.flatnonzero(parents >= 0):
        assert np.allclose(apply(T[j], joints[j]), apply(T[parents[j]], joints[j]), atol=1e-10)
    for j in np.flatnonzero(parents < 0):  # a root's joint only moves by the translation
        assert np.allclose(apply(T[j], joints[j]), joints[j] + translation, atol=1e-12)


@SETTINGS
@given(skeletons())
def test_a_bone_turns_by_its_own_angle_after_its_ancestors(skeleton):
    joints, angles, parents, translation = skeleton
    T = bone_transforms(joints, angles, parents, translation)
    for j in range(len(joints)):
        own = bone_transforms(joints[j:j + 1], angles[j:j + 1], [-1])[0]
        parent = (
            homogeneous(bone_transforms(joints[:1], [0.0], [-1], translation)[0])
            if parents[j] < 0 else homogeneous(T[parents[j]])
        )
        # First the bone's own rotation about its joint, then the parent's motion (not the other way round).
        assert np.allclose(T[j], (parent @ homogeneous(own))[:2], atol=1e-10)
        total = angles[j] + (0.0 if parents[j] < 0 else np.arctan2(T[parents[j], 1, 0], T[parents[j], 0, 0]))
        assert np.allclose(T[j, :, :2], [[np.cos(total), -np.sin(total)], [np.sin(total), np.cos(total)]], atol=1e-10)


@SETTINGS
@given(skeletons(), st.data())
def test_relabelling_the_bones_relabels_the_transforms(skeleton, data):
    joints, angles, parents, translation = skeleton
    m = len(joints)
    perm = np.array(data.draw(st.permutations(range(m))))  # new bone k is old bone perm[k]
    inverse = np.argsort(perm)
    relabelled = np.where(parents[perm] < 0, -1, inverse[np.maximum(parents[perm], 0)])
    T = bone_transforms(joints, angles, parents, translation)
    assert np.allclose(bone_transforms(joints[perm], angles[perm], relabelled, translation), T[perm], atol=1e-12)


@SETTINGS
@given(st.lists(angle, min_size=5, max_size=5), st.tuples(coordinate, coordinate))
def test_the_character_pose_matches_the_lbs_notebooks_hierarchy(character, angles, translation):
    V, bones = character
    joints = bone_joints(V, bones)
    T = bone_transforms(joints, angles, CHARACTER_PARENTS, translation)
    shift = np.hstack([np.eye(2), np.array(translation)[:, None]])
    turn = [homogeneous(bone_transforms(joints[j:j + 1], [a], [-1])[0]) for j, a in enumerate(angles)]
    spine = homogeneous(shift) @ turn[0]
    expected = [spine, spine @ turn[1], spine @ turn[2], homogeneous(shift) @ turn[3], homogeneous(shift) @ turn[4]]
    assert np.allclose(T, np.array(expected)[:, :2], atol=1e-12)


def test_joints_are_the_first_vertices_of_the_bones(character):
    V, bones = character
    joints = bone_joints(V, bones)
    assert joints.shape == (5, 2)
    assert np.array_equal(joints, V[[bone[0] for bone in bones]])
    # The character's spine starts at the pelvis, the arms at the shoulders.
    assert np.array_equal(joints[0], [0.0, 0.62])
    assert joints[1, 0] < 0 < joints[2, 0] and joints[1, 1] == joints[2, 1]


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(joints=np.zeros((2, 3))), "joints must have 2 columns"),
        (dict(angles=[0.0]), "angles must have one entry per bone (2)"),
        (dict(angles=[0.0, np.nan]), "angles contains NaN"),
        (dict(parents=[-1]), "parents must have one entry per bone (2)"),
        (dict(parents=[-1.0, 0.0]), "parents must be integers"),
        (dict(parents=[-1, 2]), "parents[1] = 2 is neither -1"),
        (dict(parents=[-2, 0]), "parents[0] = -2 is neither -1"),
        (dict(parents=[1, 0]), "parents has a cycle"),
        (dict(parents=[-1, 1]), "parents has a cycle"),
        (dict(translation=[1.0, 2.0, 3.0]), "translation must have shape (2,)"),
        (dict(translation=[[1.0, 2.0]]), "translation must be a 1-D array"),
    ],
)
def test_bad_input_is_refused_naming_the_argument(kwargs, message):
    args = dict(joints=np.zeros((2, 2)), angles=[0.1, 0.2], parents=[-1, 0], translation=None) | kwargs
    with pytest.raises(ValueError) as info:
        bone_transforms(**args)
    assert message in str(info.value)


@pytest.mark.parametrize(
    "bones, message",
    [
        ([], "bones must be a non-empty sequence"),
        ([np.array([0, 1]), np.array([], dtype=np.int64)], "bones[1] must be a non-empty 1-D integer array"),
        ([np.array([0.0, 1.0])], "bones[0] must be a non-empty 1-D integer array"),
        ([np.array([10**6])], "bones[0][0] = 1000000 is out of range"),
    ],
)
def test_bad_bones_are_refused_naming_the_bone(character, bones, message):
    V, _ = character
    with pytest.raises(ValueError) as info:
        bone_joints(V, bones)
    assert message in str(info.value)
