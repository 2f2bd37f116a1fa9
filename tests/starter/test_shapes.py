"""starter.shapes: the procedural meshes are clean, closed or bounded as documented, and deterministic."""

import math

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.sparse.csgraph import connected_components

from starter import shapes
from starter.validation import check_no_degenerate_triangles

SMALL = settings(max_examples=25, deadline=None)


def undirected_edges(F):
    half = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    return np.unique(np.sort(half, axis=1), axis=0, return_counts=True)


def assert_clean(V, F, d):
    """Types, no unreferenced vertex, no zero-area triangle, edge-manifold, consistently oriented."""
    assert V.dtype == np.float64 and V.ndim == 2 and V.shape[1] == d and V.flags.c_contiguous
    assert F.dtype == np.int64 and F.ndim == 2 and F.shape[1] == 3 and F.flags.c_contiguous
    assert np.array_equal(np.unique(F), np.arange(len(V))), "unreferenced vertices or bad indices"
    check_no_degenerate_triangles(V, F)
    half = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    # A directed edge used twice means two triangles disagree on orientation
    # or an edge has more than two triangles.
    assert len(np.unique(half, axis=0)) == len(half), "not oriented consistently / not edge-manifold"
    assert len(np.unique(V, axis=0)) == len(V), "duplicate points"


def euler(V, F):
    E, _ = undirected_edges(F)
    return len(V) - len(E) + len(F)


def boundary_loops(V, F):
    E, uses = undirected_edges(F)
    B = E[uses == 1]
    if len(B) == 0:
        return 0
    A = sp.coo_matrix((np.ones(len(B)), (B[:, 0], B[:, 1])), shape=(len(V), len(V)))
    _, label = connected_components(A + A.T)
    return len(np.unique(label[np.unique(B)]))


def signed_volume(V, F):
    return float(np.einsum("ij,ij->i", V[F[:, 0]], np.cross(V[F[:, 1]], V[F[:, 2]])).sum() / 6.0)


def signed_areas(V, F):
    e1 = V[F[:, 1]] - V[F[:, 0]]
    e2 = V[F[:, 2]] - V[F[:, 0]]
    return 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])


def min_angle_degrees(V, F):
    T = V[F]
    angles = []
    for k in range(3):
        u = T[:, (k + 1) % 3] - T[:, k]
        v = T[:, (k + 2) % 3] - T[:, k]
        cos = np.sum(u * v, axis=1) / np.linalg.norm(u, axis=1) / np.linalg.norm(v, axis=1)
        angles.append(np.degrees(np.arccos(np.clip(cos, -1, 1))))
    return float(np.min(angles))


extent = st.floats(0.25, 8.0)


@SMALL
@given(st.integers(1, 7), st.integers(1, 7), st.integers(1, 7), extent, extent, extent)
def test_bar_is_the_closed_outward_box_surface_with_grid_faces(nx, ny, nz, length, width, height):
    V, F = shapes.bar(length, width, height, nx, ny, nz)
    assert_clean(V, F, 3)
    assert len(V) == (nx + 1) * (ny + 1) * (nz + 1) - (nx - 1) * (ny - 1) * (nz - 1)
    assert len(F) == 4 * (nx * ny + ny * nz + nz * nx)
    assert euler(V, F) == 2 and boundary_loops(V, F) == 0
    assert signed_volume(V, F) == pytest.approx(length * width * height, rel=1e-12)
    assert np.array_equal(V.min(axis=0), [0, 0, 0]) and np.array_equal(V.max(axis=0), [length, width, height])
    assert np.count_nonzero(V[:, 0] == 0.0) == np.count_nonzero(V[:, 0] == length) == (ny + 1) * (nz + 1)
    on_box = (V == 0.0) | (V == [length, width, height])
    assert on_box.any(axis=1).all(), "a vertex is not on the box surface"


def test_bar_scales_to_fifty_thousand_vertices():
    V, F = shapes.bar(nx=200, ny=50, nz=50)
    assert len(V) == 45002
    assert_clean(V, F, 3)
    assert euler(V, F) == 2


@SMALL
@given(st.integers(3, 12), st.integers(1, 6), st.floats(0.5, 6.0), st.floats(0.1, 2.0))
def test_capped_cylinder_is_a_closed_outward_prism(n_around, n_along, length, radius):
    V, F = shapes.cylinder(length, radius, n_around, n_along, caps=True)
    assert_clean(V, F, 3)
    assert len(V) == (n_along + 1) * n_around + 2
    assert euler(V, F) == 2 and boundary_loops(V, F) == 0
    polygon_area = 0.5 * n_around * radius**2 * math.sin(2 * math.pi / n_around)
    assert signed_volume(V, F) == pytest.approx(polygon_area * length, rel=1e-12)
    assert np.count_nonzero(V[:, 0] == 0.0) == np.count_nonzero(V[:, 0] == length) == n_around + 1


@SMALL
@given(st.integers(3, 12), st.integers(1, 6))
def test_open_cylinder_is_an_outward_tube_with_two_boundary_loops(n_around, n_along):
    V, F = shapes.cylinder(n_around=n_around, n_along=n_along, caps=False)
    assert_clean(V, F, 3)
    assert euler(V, F) == 0 and boundary_loops(V, F) == 2
    normal = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    radial = V[F].mean(axis=1) * [0.0, 1.0, 1.0]
    assert (np.einsum("ij,ij->i", normal, radial) > 0).all()


@SMALL
@given(st.integers(3, 16), st.integers(3, 16), st.floats(0.05, 0.9))
def test_torus_is_a_closed_outward_genus_one_surface(n_major, n_minor, ratio):
    V, F = shapes.torus(1.0, ratio, n_major, n_minor)
    assert_clean(V, F, 3)
    assert len(V) == n_major * n_minor and len(F) == 2 * n_major * n_minor
    assert euler(V, F) == 0 and boundary_loops(V, F) == 0
    assert signed_volume(V, F) > 0


@SMALL
@given(st.integers(1, 12), st.integers(1, 12), extent, extent)
def test_grid_2d_tiles_the_rectangle_counter_clockwise(nx, ny, width, height):
    V, F = shapes.grid_2d(nx, ny, width, height)
    assert_clean(V, F, 2)
    assert euler(V, F) == 1 and boundary_loops(V, F) == 1
    areas = signed_areas(V, F)
    assert (areas > 0).all()
    assert areas.sum() == pytest.approx(width * height, rel=1e-12)


@pytest.mark.parametrize("n_holes", [0, 1, 2, 3, 7, 12])
def test_disc_with_holes_has_one_loop_per_hole_plus_the_rim(n_holes):
    max_area = 0.004
    V, F = shapes.disc_with_holes(n_holes, max_area=max_area)
    assert_clean(V, F, 2)
    assert boundary_loops(V, F) == 1 + n_holes
    assert euler(V, F) == 1 - n_holes
    areas = signed_areas(V, F)
    assert (areas > 0).all() and areas.max() <= max_area
    assert (np.linalg.norm(V, axis=1) <= 1.0 + 1e-12).all()
    assert min_angle_degrees(V, F) >= 30.0 - 1e-9


@settings(max_examples=8, deadline=None)
@given(st.floats(2e-4, 0.05))
def test_character_is_a_quality_disc_with_its_skeleton_built_in(max_area):
    V, F = shapes.character_2d(max_area)
    assert_clean(V, F, 2)
    assert euler(V, F) == 1 and boundary_loops(V, F) == 1
    areas = signed_areas(V, F)
    assert (areas > 0).all() and areas.max() <= max_area
    assert min_angle_degrees(V, F) >= 30.0 - 1e-9

    skeleton = shapes.character_2d_skeleton()
    handles = shapes.character_2d_handles(V)
    assert np.array_equal(V[handles["points"]], skeleton["points"])
    E, uses = undirected_edges(F)
    edge_set = {tuple(e) for e in E}
    boundary = set(E[uses == 1].ravel().tolist())
    for (a, b), bone in zip(skeleton["bones"], handles["bones"]):
        assert np.array_equal(V[bone[0]], a) and np.array_equal(V[bone[-1]], b)
        # The bone is a constrained segment: a chain of mesh edges from a to b.
        assert all(tuple(sorted(pair)) in edge_set for pair in zip(bone[:-1].tolist(), bone[1:].tolist()))
        assert boundary.isdisjoint(bone.tolist())
    for kind in ("bones", "regions"):
        members = np.concatenate(handles[kind])
        assert len(np.unique(members)) == len(members), f"{kind} overlap"
    for (cx, cy, r), region in zip(skeleton["regions"], handles["regions"]):
        assert len(region) > 0
        inside = np.linalg.norm(V - [cx, cy], axis=1) <= r
        assert np.array_equal(np.flatnonzero(inside), region)


def test_character_outline_is_mirror_symmetric_in_x():
    skeleton = shapes.character_2d_skeleton()
    mirror = [-1.0, 1.0]
    assert np.array_equal(skeleton["points"][[2, 4]] * mirror, skeleton["points"][[1, 3]])
    assert np.array_equal(skeleton["bones"][[2, 4]] * mirror, skeleton["bones"][[1, 3]])
    V, F = shapes.character_2d(0.05)
    assert V[:, 0].min() == -V[:, 0].max()


@pytest.mark.parametrize("max_area, low, high", [(0.0009, 1300, 1700), (0.00013, 9000, 11000)])
def test_character_vertex_count_follows_max_area_as_documented(max_area, low, high):
    V, _ = shapes.character_2d(max_area)
    assert low <= len(V) <= high


@pytest.mark.parametrize(
    "make",
    [
        lambda: shapes.character_2d(0.0005),
        lambda: shapes.disc_with_holes(3, 0.001),
        lambda: shapes.bar(nx=9, ny=4, nz=3),
        lambda: shapes.cylinder(),
        lambda: shapes.torus(),
    ],
    ids=["character", "disc", "bar", "cylinder", "torus"],
)
def test_generators_are_bit_for_bit_deterministic(make):
    (V1, F1), (V2, F2) = make(), make()
    assert V1.tobytes() == V2.tobytes() and F1.tobytes() == F2.tobytes()


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda: shapes.bar(nx=0), "nx"),
        (lambda: shapes.bar(length=-1.0), "length"),
        (lambda: shapes.bar(height=float("nan")), "height"),
        (lambda: shapes.bar(ny=2.5), "ny"),
        (lambda: shapes.cylinder(n_around=2), "n_around"),
        (lambda: shapes.cylinder(radius=0), "radius"),
        (lambda: shapes.torus(R=1.0, r=1.0), "r must be smaller than R"),
        (lambda: shapes.torus(n_minor=True), "n_minor"),
        (lambda: shapes.grid_2d(0, 3), "nx"),
        (lambda: shapes.disc_with_holes(13), "n_holes"),
        (lambda: shapes.disc_with_holes(-1), "n_holes"),
        (lambda: shapes.character_2d(max_area=0.0), "max_area"),
        (lambda: shapes.character_2d(max_area=1e-8), "max_area"),
        (lambda: shapes.character_2d_handles(shapes.grid_2d(3, 3)[0]), "not a character_2d mesh"),
        (lambda: shapes.character_2d_handles(shapes.bar()[0]), "V"),
    ],
)
def test_bad_arguments_raise_value_error_naming_them(call, name):
    with pytest.raises(ValueError, match=name):
        call()
