import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

from reference.bounded_biharmonic_weights import inverse_distance_weights
from starter.meshes import load_handles, load_mesh

seeds = st.integers(0, 2**32 - 1)
powers = st.floats(0.25, 8.0)


def random_handle_points(V, seed, count):
    """``count`` points inside the bounding box of ``V``, none within 1e-3 of a vertex or each other."""
    rng = np.random.default_rng(seed)
    H = rng.uniform(V.min(axis=0), V.max(axis=0), size=(count, V.shape[1]))
    gaps = np.linalg.norm(H[:, None] - H[None], axis=2) + np.eye(count)
    assume(gaps.min() > 1e-3)
    assume(np.linalg.norm(V[:, None] - H[None], axis=2).min() > 1e-3)
    return H


@settings(max_examples=30, deadline=None)
@given(st.sampled_from(["character", "bar_coarse"]), seeds, st.integers(1, 6), powers)
def test_weights_are_normalized_inverse_distance_powers(mesh, seed, count, power):
    V, _ = load_mesh(mesh)
    H = random_handle_points(V, seed, count)
    W = inverse_distance_weights(V, H, power)
    assert W.shape == (len(V), count)
    assert (W > 0).all()
    np.testing.assert_allclose(W.sum(axis=1), 1.0, atol=1e-12)
    D = np.linalg.norm(V[:, None] - H[None], axis=2)
    expected = D**-power / np.sum(D**-power, axis=1, keepdims=True)
    np.testing.assert_allclose(W, expected, rtol=1e-12, atol=1e-300)


@settings(max_examples=30, deadline=None)
@given(seeds, st.integers(2, 6), powers)
def test_a_closer_handle_always_gets_more_weight(seed, count, power):
    V, _ = load_mesh("character")
    H = random_handle_points(V, seed, count)
    W = inverse_distance_weights(V, H, power)
    D = np.linalg.norm(V[:, None] - H[None], axis=2)
    closer = D[:, :, None] < D[:, None, :]
    heavier = W[:, :, None] > W[:, None, :]
    np.testing.assert_array_equal(closer, heavier)


@settings(max_examples=20, deadline=None)
@given(powers)
def test_weight_falls_off_monotonically_from_one_handle_to_the_other(power):
    H = np.array([[0.0, 0.0], [1.0, 0.5]])
    segment = H[0] + np.linspace(0.0, 1.0, 101)[:, None] * (H[1] - H[0])
    W = inverse_distance_weights(segment, H, power)
    assert W[0, 0] == 1.0 and W[-1, 0] == 0.0
    assert (np.diff(W[:, 0]) <= 0).all()
    # strictly, wherever the weight has not rounded to 0 or 1
    unsaturated = (W[:, 0] > 1e-12) & (W[:, 0] < 1.0 - 1e-12)
    assert unsaturated.sum() > 50
    assert (np.diff(W[unsaturated, 0]) < 0).all()


def test_vertices_at_a_handle_point_get_its_one_hot_row():
    V, _ = load_mesh("character")
    points = load_handles("character")["points"]
    H = V[points] + [[0.0, 5e-13], [3e-13, 0.0], [0.0, 0.0], [-7e-13, 0.0], [0.0, -9e-13]]
    W = inverse_distance_weights(V, H)
    np.testing.assert_array_equal(W[points], np.eye(len(points)))
    others = np.setdiff1d(np.arange(len(V)), points)
    assert (W[others] < 1.0).all() and (W[others] > 0.0).all()


def test_higher_powers_favour_the_nearest_handle():
    V, _ = load_mesh("character")
    H = V[load_handles("character")["points"]] + 0.01
    nearest = np.linalg.norm(V[:, None] - H[None], axis=2).argmin(axis=1)
    rows = np.arange(len(V))
    previous = inverse_distance_weights(V, H, 0.5)[rows, nearest]
    for power in (1, 2, 4, 8):
        current = inverse_distance_weights(V, H, power)[rows, nearest]
        assert (current >= previous).all()
        previous = current


def test_huge_powers_do_not_overflow():
    V, _ = load_mesh("character")
    H = V[load_handles("character")["points"]] + 1e-9
    W = inverse_distance_weights(V, H, power=400.0)
    assert np.isfinite(W).all()
    np.testing.assert_allclose(W.sum(axis=1), 1.0, atol=1e-12)
    # so sharp that each vertex follows its nearest handle alone
    nearest = np.linalg.norm(V[:, None] - H[None], axis=2).argmin(axis=1)
    np.testing.assert_array_equal(W.argmax(axis=1), nearest)


def test_default_power_is_two():
    V, _ = load_mesh("bar_coarse")
    H = np.array([[-1.0, 0.5, 0.5], [5.0, 0.5, 0.5]])
    np.testing.assert_array_equal(inverse_distance_weights(V, H), inverse_distance_weights(V, H, power=2))


def test_inputs_are_not_modified():
    V, _ = load_mesh("character")
    H = V[:3] + 0.1
    V0, H0 = V.copy(), H.copy()
    inverse_distance_weights(V, H)
    np.testing.assert_array_equal(V, V0)
    np.testing.assert_array_equal(H, H0)


@pytest.mark.parametrize(
    "H, power, message",
    [
        ([[0.0, 0.0], [0.0, 0.0]], 2, r"handle_points must be distinct: rows 0 and 1"),
        ([[0.0, 0.0], [1.0, 1.0], [1.0, 1.0 + 1e-12]], 2, r"handle_points must be distinct: rows 1 and 2"),
        ([[0.0, 0.0, 0.0]], 2, "handle_points must have 2 columns"),
        (np.zeros((0, 2)), 2, r"handle_points must have at least 1 row"),
        ([[0.0, np.inf]], 2, "handle_points contains NaN or inf"),
        ([[0.0, 0.0]], 0, "power must be positive"),
        ([[0.0, 0.0]], -1.5, "power must be positive"),
        ([[0.0, 0.0]], np.nan, "power contains NaN or inf"),
        ([[0.0, 0.0]], "two", "power must be a numeric array"),
        ([[0.0, 0.0]], [2, 3], "power must be a 0-D array"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(H, power, message):
    V, _ = load_mesh("character")
    with pytest.raises(ValueError, match=message):
        inverse_distance_weights(V, H, power)


def test_bad_vertices_raise_value_error_naming_v():
    with pytest.raises(ValueError, match="V must have 2 or 3 columns"):
        inverse_distance_weights(np.zeros((4, 1)), [[0.0]])
