"""Fixtures for the reference's tests."""

from __future__ import annotations

import numpy as np
import pytest

from starter.meshes import load_handles, load_mesh


@pytest.fixture(scope="session")
def mesh_and_handles():
    """``mesh_and_handles(name) -> (V, F, handles)``: a course mesh with every vertex of its handle sets.

    Both bar ends for bars, the region handles for the character.
    """

    def load(mesh: str):
        V, F = load_mesh(mesh)
        sets = load_handles(mesh)
        handles = np.concatenate([sets["left"], sets["right"]]) if "left" in sets else np.concatenate(sets["regions"])
        return V, F, handles

    return load


@pytest.fixture(scope="session")
def skinned_mesh():
    """``skinned_mesh(name) -> (V, F, W, fixed)``: a course mesh with bounded biharmonic weights.

    ``bar_coarse``: five handles, the two end faces (``fixed = [0, 1]``) and the
    cross-section rings at x = 1, 2, 3; ``character``: the head, left foot and
    right foot regions and the two arm bones, the feet fixed (``[1, 2]``).
    """
    from reference.bounded_biharmonic_weights import bbw, handle_constraints

    cache = {}

    def load(mesh: str):
        if mesh not in cache:
            V, F = load_mesh(mesh)
            sets = load_handles(mesh)
            if mesh == "character":
                handles, fixed = [*sets["regions"], *sets["bones"][1:3]], np.array([1, 2])
            else:
                rings = [np.flatnonzero(V[:, 0] == x) for x in (1.0, 2.0, 3.0)]
                handles, fixed = [sets["left"], sets["right"], *rings], np.array([0, 1])
            cache[mesh] = (V, F, bbw(V, F, *handle_constraints(handles)), fixed)
        V, F, W, fixed = cache[mesh]
        return V.copy(), F.copy(), W.copy(), fixed.copy()

    return load


@pytest.fixture(scope="session")
def tet_mesh():
    """``tet_mesh(name, seed=None, jitter=0.1) -> (V, T)``: a course tetrahedral mesh.

    With a seed, every vertex moves by up to ``jitter`` of the shortest edge in
    a random direction (the tetrahedra stay positively oriented), so the
    tests do not see only the grid's right angles.
    """

    def load(name: str, seed=None, jitter=0.1):
        V, T = load_mesh(name)
        if seed is not None:
            shortest = np.linalg.norm(V[T[:, 1]] - V[T[:, 0]], axis=1).min()
            V = V + jitter * shortest * np.random.default_rng(seed).uniform(-1, 1, V.shape) / np.sqrt(3)
        return V, T

    return load


@pytest.fixture(scope="session")
def random_rotation():
    """``random_rotation(seed) -> (3, 3)``: a uniformly random rotation (QR of a Gaussian matrix, signs fixed)."""

    def draw(seed):
        Q, R = np.linalg.qr(np.random.default_rng(seed).standard_normal((3, 3)))
        Q = Q * np.sign(np.diag(R))
        return Q * np.linalg.det(Q)

    return draw
