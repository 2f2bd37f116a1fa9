import igl
import igl.triangle
import numpy as np
import pytest
import pyvista as pv
from hypothesis import given, settings, strategies as st
from pyvista import examples

from reference.meshes import boundary_loop_count
from starter import shapes
from starter.meshes import load_mesh


def faces(name):
    return load_mesh(name)[1]


@pytest.mark.parametrize("name", ["sphere", "ant", "nut", "torus", "bar", "cylinder"])
def test_closed_surface_has_no_boundary_loop(name):
    assert boundary_loop_count(faces(name)) == 0


@pytest.mark.parametrize("name, loops", [("character", 1), ("disc_with_holes", 3)])
def test_planar_course_meshes_have_their_boundary_loops(name, loops):
    F = faces(name)
    assert boundary_loop_count(F) == loops == len(igl.boundary_loop_all(F))


@settings(max_examples=10, deadline=None)
@given(n_holes=st.integers(0, 5))
def test_disc_with_holes_has_one_loop_per_hole_plus_the_outline(n_holes):
    _, F = shapes.disc_with_holes(n_holes, max_area=0.01)
    result = boundary_loop_count(F)
    assert isinstance(result, int)
    assert result == 1 + n_holes == len(igl.boundary_loop_all(F))


def test_open_cylinder_has_two_boundary_loops():
    F = pv.Cylinder(capping=False, resolution=24).triangulate().clean().regular_faces.astype(np.int64)
    assert boundary_loop_count(F) == 2 == len(igl.boundary_loop_all(F))


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n_removed=st.integers(1, 12))
def test_removing_faces_with_disjoint_corners_opens_one_loop_each(seed, n_removed):
    F = faces("sphere")
    rng = np.random.default_rng(seed)
    removed, used = [], set()
    for t in rng.permutation(len(F)):
        if len(removed) == n_removed:
            break
        if used.isdisjoint(F[t].tolist()):
            removed.append(t)
            used.update(F[t].tolist())
    assert len(removed) == n_removed
    assert boundary_loop_count(np.delete(F, removed, axis=0)) == n_removed


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_removing_a_vertex_star_opens_one_loop(seed):
    F = faces("torus")
    v = np.random.default_rng(seed).integers(0, F.max() + 1)
    star = (F == v).any(axis=1)
    assert star.sum() >= 3
    assert boundary_loop_count(F[~star]) == 1


def test_real_mesh_with_an_edge_in_three_triangles_is_rejected():
    # pyvista's airplane has one edge shared by three triangles
    F = examples.load_airplane().regular_faces.astype(np.int64)
    with pytest.raises(ValueError, match=r"F is not edge-manifold: edge \[\d+, \d+\] is shared by 3 triangles"):
        boundary_loop_count(F)


def test_three_triangles_on_one_edge_are_rejected():
    with pytest.raises(ValueError, match=r"F is not edge-manifold: edge \[0, 1\] is shared by 3 triangles"):
        boundary_loop_count([[0, 1, 2], [1, 0, 3], [0, 1, 4]])


@pytest.mark.parametrize(
    "F, message",
    [
        (np.array([[0.0, 1.0, 2.0]]), "F must be an integer array"),
        (np.array([[0, 1]]), r"F must have shape \(f, 3\)"),
        (np.array([[0, 1, 2], [2, 1, -4]]), "F has a vertex index out of range"),
        (np.array([[3, 3, 2]]), "F has a triangle with a repeated vertex"),
    ],
)
def test_bad_faces_raise_value_error_naming_f(F, message):
    with pytest.raises(ValueError, match=message):
        boundary_loop_count(F)
