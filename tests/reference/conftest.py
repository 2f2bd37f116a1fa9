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
