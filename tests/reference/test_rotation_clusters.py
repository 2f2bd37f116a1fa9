import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings, strategies as st

from reference.fast import rotation_clusters

seeds = st.integers(0, 2**32 - 1)
meshes = st.sampled_from(["bar_coarse", "character"])


def assert_lloyd_fixed_point(W, labels, k):
    """Every label in ``range(k)`` is used and every row is nearest to the mean of its own cluster."""
    assert labels.shape == (len(W),) and labels.dtype == np.int64
    np.testing.assert_array_equal(np.unique(labels), np.arange(k))
    means = np.array([W[labels == c].mean(axis=0) for c in range(k)])
    D = np.sum((W[:, None, :] - means[None]) ** 2, axis=2)
    # the weights are at most 1: squared distances are exact to ~1e-16
    assert (D[np.arange(len(W)), labels] <= D.min(axis=1) + 1e-14).all()


@settings(max_examples=25, deadline=None)
@given(meshes, st.integers(1, 40), seeds)
def test_every_label_is_used_and_every_row_is_nearest_to_its_cluster_mean(skinned_mesh, mesh, k, seed):
    W = skinned_mesh(mesh)[2]
    assert_lloyd_fixed_point(W, rotation_clusters(W, k, seed), k)


@pytest.mark.parametrize("k", [55, 89])
def test_near_equal_rows_neither_leave_a_cluster_empty_nor_stop_the_iteration_from_ending(skinned_mesh, k):
    # the bar's symmetry makes its weight rows equal up to ~1e-17 in 53 groups: with
    # more clusters than that, Lloyd's iteration empties clusters and rounding alone
    # would move rows back and forth
    W = skinned_mesh("bar_coarse")[2]
    assert len(np.unique(np.round(W, 12), axis=0)) == 53 < k <= len(np.unique(W, axis=0))
    for seed in range(3):
        assert_lloyd_fixed_point(W, rotation_clusters(W, k, seed), k)


@pytest.mark.parametrize("mesh", ["bar_coarse", "character"])
def test_one_hot_weights_in_as_many_clusters_as_handles_group_the_vertices_by_handle(skinned_mesh, mesh):
    W = skinned_mesh(mesh)[2]
    m = W.shape[1]
    handle = W.argmax(axis=1)
    labels = rotation_clusters(np.eye(m)[handle], m, seed=3)
    # one label per handle and one handle per label
    assert len(np.unique(np.c_[labels, handle], axis=0)) == m
    assert len(np.unique(labels)) == m


def test_one_cluster_holds_every_vertex(skinned_mesh):
    W = skinned_mesh("character")[2]
    np.testing.assert_array_equal(rotation_clusters(W, 1, seed=5), np.zeros(len(W), dtype=np.int64))


def test_the_seed_makes_the_clustering_deterministic(skinned_mesh):
    W = skinned_mesh("character")[2]
    first = rotation_clusters(W, 12, seed=7)
    np.testing.assert_array_equal(rotation_clusters(W.copy(), 12, seed=7), first)
    np.testing.assert_array_equal(rotation_clusters(W, 12), rotation_clusters(W, 12, seed=0))


def test_as_many_clusters_as_distinct_rows_put_each_distinct_row_alone(skinned_mesh):
    # weights rounded to 0.1: rows are equal or at least 0.1 apart
    W = np.round(skinned_mesh("character")[2], 1)
    rows = np.unique(W, axis=0)
    labels = rotation_clusters(W, len(rows), seed=11)
    for c in range(len(rows)):
        assert len(np.unique(W[labels == c], axis=0)) == 1


def test_inputs_are_not_modified(skinned_mesh):
    W = skinned_mesh("character")[2]
    copy = W.copy()
    rotation_clusters(W, 10, seed=1)
    np.testing.assert_array_equal(W, copy)


@pytest.mark.parametrize(
    "change, message",
    [
        ({"k": 0}, r"k must be an integer between 1 and the number of distinct rows of W \(5\), got 0"),
        ({"k": 6}, r"k must be an integer between 1 and the number of distinct rows of W \(5\), got 6"),
        ({"k": 2.0}, "k must be an integer between 1 and"),
        ({"k": True}, "k must be an integer between 1 and"),
        ({"k": "3"}, "k must be an integer between 1 and"),
        ({"seed": -1}, "seed must be a non-negative integer, got -1"),
        ({"seed": 1.5}, "seed must be a non-negative integer"),
        ({"seed": True}, "seed must be a non-negative integer"),
        ({"seed": None}, "seed must be a non-negative integer"),
        ({"W": np.ones(10)}, "W must be a 2-D array"),
        ({"W": np.zeros((0, 5))}, "W must have at least one row and one column"),
        ({"W": np.full((10, 5), np.nan)}, "W contains NaN or inf"),
        ({"W": sp.eye(5).tocsr()}, "W must be a dense array"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(skinned_mesh, change, message):
    W = skinned_mesh("character")[2]
    args = {"W": np.eye(5)[W.argmax(axis=1)], "k": 3, "seed": 0}
    args.update(change)
    with pytest.raises(ValueError, match=message):
        rotation_clusters(**args)
