import igl
import igl.triangle
import numpy as np
import pytest
import pyvista as pv
from hypothesis import given, settings, strategies as st
from pyvista import examples

from reference.meshes import genus
from deformlab_packs.deformation.checks.generators import perforated_slab
from starter import shapes
from starter.meshes import load_mesh


def vertices_faces(mesh):
    """Vertices and triangles of a pyvista surface."""
    mesh = mesh.triangulate().clean()
    return np.asarray(mesh.points, dtype=np.float64), mesh.regular_faces.astype(np.int64)


def moebius_strip(n=24):
    """Triangulated Möbius strip: ``n`` quads, the last one glued back with a half twist."""
    s = np.linspace(0, 2 * np.pi, n, endpoint=False)
    V = np.concatenate(
        [np.c_[(1 + r * np.cos(s / 2)) * np.cos(s), (1 + r * np.cos(s / 2)) * np.sin(s), r * np.sin(s / 2)] for r in (-0.3, 0.3)]
    )
    i = np.arange(n)
    lower, upper = i, i + n
    next_lower, next_upper = (i + 1) % n, (i + 1) % n + n
    # the twist swaps the two sides where the strip closes
    next_lower[-1], next_upper[-1] = n, 0
    F = np.concatenate([np.c_[lower, next_lower, next_upper], np.c_[lower, next_upper, upper]])
    return V, F


# topology of the course meshes, as documented in data/README.md
COURSE_MESHES = {
    "sphere": 0,
    "bar": 0,
    "cylinder": 0,
    "ant": 0,
    "torus": 1,
    "nut": 1,
    "character": 0,
    "disc_with_holes": 0,
}


@pytest.mark.parametrize("name", COURSE_MESHES)
def test_genus_of_course_meshes(name):
    result = genus(*load_mesh(name))
    assert isinstance(result, int)
    assert result == COURSE_MESHES[name]


@pytest.mark.parametrize("mesh, expected", [(pv.Icosphere(nsub=2), 0), (pv.ParametricTorus(u_res=40, v_res=20), 1)])
def test_genus_of_pyvista_surfaces(mesh, expected):
    assert genus(*vertices_faces(mesh)) == expected


@settings(max_examples=10, deadline=None)
@given(n_holes=st.integers(0, 5))
def test_disc_with_holes_has_genus_zero(n_holes):
    assert genus(*shapes.disc_with_holes(n_holes, max_area=0.01)) == 0


@settings(max_examples=10, deadline=None)
@given(n_holes=st.integers(0, 5))
def test_closed_slab_has_one_handle_per_hole(n_holes):
    V, F = perforated_slab(n_holes)
    assert igl.is_edge_manifold(F)[0]
    assert genus(V, F) == n_holes


def test_genus_adds_up_over_components():
    V, F = load_mesh("torus")
    shift = 2 * np.ptp(V, axis=0)
    assert genus(np.vstack([V, V + shift]), np.vstack([F, F + len(V)])) == 2


def test_open_cylinder_has_genus_zero():
    assert genus(*vertices_faces(pv.Cylinder(capping=False, resolution=24))) == 0


def test_moebius_strip_is_rejected_as_non_orientable():
    V, F = moebius_strip()
    with pytest.raises(ValueError, match="F is not an orientable manifold"):
        genus(V, F)


def test_unreferenced_vertex_is_rejected():
    V, F = load_mesh("sphere")
    with pytest.raises(ValueError, match=rf"V has an unreferenced vertex: V\[{len(V)}\]"):
        genus(np.vstack([V, [[0.0, 0.0, 0.0]]]), F)


def test_non_edge_manifold_mesh_is_rejected():
    with pytest.raises(ValueError, match="F is not edge-manifold"):
        genus(*vertices_faces(examples.load_airplane()))


def test_bad_inputs_raise_value_error_naming_the_argument():
    V, F = load_mesh("sphere")
    with pytest.raises(ValueError, match="V contains NaN or inf"):
        genus(np.where(np.arange(len(V))[:, None] == 3, np.inf, V), F)
    with pytest.raises(ValueError, match="V must have 2 or 3 columns"):
        genus(V[:, :1], F)
    with pytest.raises(ValueError, match=r"F has a vertex index out of range: F\[0, 0\] = -1"):
        genus(V, np.vstack([[[-1, 0, 1]], F]))
    with pytest.raises(ValueError, match="F must be an integer array"):
        genus(V, F.astype(np.float32))
