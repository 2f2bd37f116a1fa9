"""starter.meshes: the course meshes load clean, with their handles, and bad names fail clearly."""

import shutil
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

# Imported from the submodules: under pytest, tests/starter can shadow the
# package's __init__ as a namespace package (test_plotting checks the
# package exports in a clean interpreter).
from starter import meshes, shapes
from starter.meshes import load_handles, load_mesh, mesh_names
from starter.validation import check_no_degenerate_triangles

DATA = Path(meshes.__file__).resolve().parent.parent / "data"

# name -> (dimension, Euler characteristic, connected components, boundary loops)
TOPOLOGY = {
    "bar": (3, 2, 1, 0),
    "bar_coarse": (3, 2, 1, 0),
    "bar_fine": (3, 2, 1, 0),
    "cylinder": (3, 2, 1, 0),
    "character": (2, 1, 1, 1),
    "character_fine": (2, 1, 1, 1),
    "torus": (3, 0, 1, 0),
    "disc_with_holes": (2, -1, 1, 3),
    "ant": (3, 30, 15, 0),
    "nut": (3, 0, 1, 0),
    "sphere": (3, 2, 1, 0),
}
# Tetrahedral meshes: name -> (Euler characteristic of the boundary surface, volume)
TETS = {"bar_tet": (2, 4.0), "hand_tet": (2, 0.704)}


@pytest.fixture(autouse=True)
def default_data_folder(monkeypatch):
    monkeypatch.delenv("DEFORMLAB_DATA", raising=False)


def test_mesh_names_are_the_npz_files_of_the_data_folder():
    assert mesh_names() == sorted(p.stem for p in DATA.glob("*.npz"))
    assert set(mesh_names()) == set(TOPOLOGY) | set(TETS)


@pytest.mark.parametrize("name", sorted(TOPOLOGY))
def test_course_mesh_is_clean_with_the_documented_topology(name):
    d, chi, components, loops = TOPOLOGY[name]
    V, F = load_mesh(name)
    assert V.dtype == np.float64 and V.shape[1] == d
    assert F.dtype == np.int64 and F.shape[1] == 3
    assert np.array_equal(np.unique(F), np.arange(len(V))), "unreferenced vertices"
    assert len(np.unique(V, axis=0)) == len(V), "duplicate points"
    check_no_degenerate_triangles(V, F)
    half = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    assert len(np.unique(half, axis=0)) == len(half), "not consistently oriented / not edge-manifold"
    E, uses = np.unique(np.sort(half, axis=1), axis=0, return_counts=True)
    assert len(V) - len(E) + len(F) == chi
    adjacency = sp.coo_matrix((np.ones(len(E)), (E[:, 0], E[:, 1])), shape=(len(V), len(V)))
    assert connected_components(adjacency, directed=False)[0] == components
    B = E[uses == 1]
    boundary = sp.coo_matrix((np.ones(len(B)), (B[:, 0], B[:, 1])), shape=(len(V), len(V)))
    labels = connected_components(boundary, directed=False)[1]
    assert len(np.unique(labels[np.unique(B)])) == loops


@pytest.mark.parametrize("name", sorted(TETS))
def test_tet_mesh_is_conforming_positively_oriented_with_a_closed_boundary(name):
    chi, volume = TETS[name]
    V, T = load_mesh(name)
    assert V.dtype == np.float64 and V.shape[1] == 3
    assert T.dtype == np.int64 and T.shape[1] == 4
    assert np.array_equal(np.unique(T), np.arange(len(V))), "unreferenced vertices"
    assert len(np.unique(V, axis=0)) == len(V), "duplicate points"
    signed = np.linalg.det(np.stack([V[T[:, k]] - V[T[:, 0]] for k in (1, 2, 3)], axis=2)) / 6
    assert signed.min() > 0, "a tetrahedron is flat or negatively oriented"
    assert np.isclose(signed.sum(), volume)
    # the outward faces of a positively oriented tet; a conforming mesh meets each interior face twice, reversed
    faces = np.concatenate([T[:, [1, 2, 3]], T[:, [0, 3, 2]], T[:, [0, 1, 3]], T[:, [0, 2, 1]]])
    _, which, count = np.unique(np.sort(faces, axis=1), axis=0, return_inverse=True, return_counts=True)
    assert count.max() <= 2, "a face is shared by three tetrahedra"
    B = faces[count[which.ravel()] == 1]
    half = np.concatenate([B[:, [0, 1]], B[:, [1, 2]], B[:, [2, 0]]])
    assert len(np.unique(half, axis=0)) == len(half), "boundary not consistently oriented / not edge-manifold"
    assert set(map(tuple, half[:, ::-1].tolist())) == set(map(tuple, half.tolist())), "boundary not closed"
    E = np.unique(np.sort(half, axis=1), axis=0)
    assert len(np.unique(B)) - len(E) + len(B) == chi
    # the divergence theorem: the boundary encloses the tetrahedra's volume (outward orientation)
    enclosed = np.einsum("ij,ij->i", V[B[:, 0]], np.cross(V[B[:, 1]], V[B[:, 2]])).sum() / 6
    assert np.isclose(enclosed, volume)


def test_hand_bones_are_straight_rows_of_vertices_inside_the_hand():
    V, _ = load_mesh("hand_tet")
    bones = load_handles("hand_tet")["bones"]
    assert len(bones) == 6 and len(np.unique(np.concatenate(bones))) == sum(len(b) for b in bones)
    for bone in bones:
        assert bone.dtype == np.int64 and len(bone) >= 5
        steps = np.diff(V[bone], axis=0)
        assert np.allclose(steps, steps[0]) and np.isclose(np.linalg.norm(steps[0]), 0.1)
        assert np.allclose(V[bone, 2], 0.2)


@pytest.mark.parametrize("name", ["bar", "bar_coarse", "bar_fine", "cylinder", "bar_tet"])
def test_end_handles_are_all_vertices_on_the_end_planes(name):
    V, _ = load_mesh(name)
    handles = load_handles(name)
    assert sorted(handles) == ["left", "right"]
    assert np.array_equal(handles["left"], np.flatnonzero(V[:, 0] == 0.0))
    assert np.array_equal(handles["right"], np.flatnonzero(V[:, 0] == 4.0))
    assert all(h.dtype == np.int64 for h in handles.values())


@pytest.mark.parametrize("name", ["character", "character_fine"])
def test_character_handles_are_stored_as_computed_from_the_mesh(name):
    V, _ = load_mesh(name)
    stored = load_handles(name)
    expected = shapes.character_2d_handles(V)
    assert sorted(stored) == ["bones", "points", "regions"]
    assert stored["points"].dtype == np.int64 and np.array_equal(stored["points"], expected["points"])
    for kind, count in (("bones", 5), ("regions", 3)):
        assert isinstance(stored[kind], list) and len(stored[kind]) == count
        for got, want in zip(stored[kind], expected[kind]):
            assert got.dtype == np.int64 and np.array_equal(got, want)


@pytest.mark.parametrize("name", ["torus", "disc_with_holes", "ant", "nut", "sphere"])
def test_meshes_without_handles_give_an_empty_dict(name):
    assert load_handles(name) == {}


@pytest.mark.parametrize("bad", ["armadillo", "", "bar.npz", 3, None])
def test_unknown_name_raises_value_error_listing_the_meshes(bad):
    for load in (load_mesh, load_handles):
        with pytest.raises(ValueError, match=r"name must be one of .*'bar'.*'torus'"):
            load(bad)


def test_data_folder_comes_from_deformlab_data_when_set(tmp_path, monkeypatch):
    shutil.copy(DATA / "torus.npz", tmp_path / "ring.npz")
    monkeypatch.setenv("DEFORMLAB_DATA", str(tmp_path))
    assert mesh_names() == ["ring"]
    V, F = load_mesh("ring")
    with np.load(DATA / "torus.npz") as z:
        assert np.array_equal(V, z["V"]) and np.array_equal(F, z["F"])
    with pytest.raises(ValueError, match="'ring'"):
        load_mesh("torus")


def test_missing_data_folder_error_says_where_it_looked(tmp_path, monkeypatch):
    missing = tmp_path / "nowhere"
    monkeypatch.setenv("DEFORMLAB_DATA", str(missing))
    with pytest.raises(FileNotFoundError, match=str(missing)):
        load_mesh("bar")
