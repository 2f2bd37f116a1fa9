import igl
import igl.triangle
import numpy as np
import pytest
import pyvista as pv
from hypothesis import given, settings, strategies as st

from reference.meshes import euler_characteristic
from starter import shapes
from starter.meshes import load_mesh


# topology of the course meshes, as documented in data/README.md
COURSE_MESHES = {
    "sphere": 2,
    "bar": 2,
    "cylinder": 2,
    "torus": 0,
    "nut": 0,
    "character": 1,
    "disc_with_holes": -1,
}


@pytest.mark.parametrize("name", COURSE_MESHES)
def test_euler_characteristic_of_course_meshes(name):
    result = euler_characteristic(*load_mesh(name))
    assert isinstance(result, int)
    assert result == COURSE_MESHES[name]


def test_euler_characteristic_adds_up_over_closed_components():
    V, F = load_mesh("ant")
    components = int(pv.PolyData.from_regular_faces(V, F).connectivity().point_data["RegionId"].max()) + 1
    assert components > 1
    assert euler_characteristic(V, F) == 2 * components


@settings(max_examples=10, deadline=None)
@given(n_holes=st.integers(0, 5))
def test_each_hole_in_a_disc_lowers_euler_characteristic_by_one(n_holes):
    result = euler_characteristic(*shapes.disc_with_holes(n_holes, max_area=0.01))
    assert isinstance(result, int)
    assert result == 1 - n_holes


@pytest.mark.parametrize("name", ["sphere", "ant", "nut", "disc_with_holes"])
def test_euler_characteristic_counts_vertices_edges_and_faces_like_igl(name):
    V, F = load_mesh(name)
    assert euler_characteristic(V, F) == len(V) - len(igl.edges(F)) + len(F)


@pytest.mark.parametrize("name", ["sphere", "nut", "disc_with_holes"])
def test_euler_characteristic_is_invariant_under_loop_subdivision(name):
    V, F = load_mesh(name)
    V2, F2 = igl.upsample(V, F, 2)
    assert len(F2) == 16 * len(F)
    assert euler_characteristic(V2, F2) == euler_characteristic(V, F)


def test_bad_vertices_and_faces_raise_value_error_naming_the_argument():
    V, F = load_mesh("sphere")
    with pytest.raises(ValueError, match="V must have 2 or 3 columns"):
        euler_characteristic(np.c_[V, V], F)
    with pytest.raises(ValueError, match="V must be a 2-D array"):
        euler_characteristic(V.ravel(), F)
    with pytest.raises(ValueError, match="V must be a numeric array"):
        euler_characteristic(np.full(V.shape, "x"), F)
    V_nan = V.copy()
    V_nan[5, 1] = np.nan
    with pytest.raises(ValueError, match="V contains NaN or inf"):
        euler_characteristic(V_nan, F)
    F_out = F.copy()
    F_out[7, 2] = len(V)
    with pytest.raises(ValueError, match=r"F has a vertex index out of range: F\[7, 2\]"):
        euler_characteristic(V, F_out)
    with pytest.raises(ValueError, match="F must be an integer array"):
        euler_characteristic(V, F.astype(np.float64))
    with pytest.raises(ValueError, match=r"F must have shape \(f, 3\)"):
        euler_characteristic(V, F[:, :2])
