import igl
import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st
from scipy.stats import ortho_group, special_ortho_group

from reference.sign_correction import rigid_align
from starter.meshes import load_mesh

dims = st.sampled_from([2, 3])
seeds = st.integers(0, 2**32 - 1)


def objective(R, t, P, Q, w):
    return float(w @ np.sum((P @ R.T + t - Q) ** 2, axis=1))


def real_points(d):
    return load_mesh("ant")[0][:, :d]


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("mirrored", [False, True])
def test_matches_igl_procrustes_on_a_noisy_real_mesh(d, mirrored):
    rng = np.random.default_rng(7)
    P = real_points(d)
    Q0 = ortho_group.rvs(d, random_state=rng)
    Q0 = Q0 * np.sign(np.linalg.det(Q0)) * (-1.0 if mirrored and d == 3 else 1.0)
    if mirrored and d == 2:
        Q0 = Q0 @ np.diag([1.0, -1.0])
    Q = P @ Q0.T + rng.normal(size=d) + 0.05 * rng.normal(size=P.shape)
    R, t = rigid_align(P, Q)
    # libigl minimizes |s X R + t - Y|² with row vectors: its R is our transpose
    scale, R_igl, t_igl = igl.procrustes(P, Q, False, False)
    assert scale == 1.0
    np.testing.assert_allclose(R, R_igl.T, rtol=0, atol=1e-12)
    np.testing.assert_allclose(t, t_igl, rtol=0, atol=1e-10 * np.abs(Q).max())
    assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-12)


@settings(max_examples=200, deadline=None)
@given(dims, st.integers(0, 20), seeds)
def test_recovers_a_known_rotation_and_translation(d, extra, seed):
    rng = np.random.default_rng(seed)
    P = rng.normal(size=(d + 1 + extra, d))
    assume(np.linalg.svd(P - P.mean(axis=0), compute_uv=False)[-1] > 1e-2)
    R0 = special_ortho_group.rvs(d, random_state=rng)
    t0 = rng.uniform(-10, 10, size=d)
    R, t = rigid_align(P, P @ R0.T + t0)
    assert R.shape == (d, d) and t.shape == (d,)
    np.testing.assert_allclose(R, R0, rtol=0, atol=1e-9)
    np.testing.assert_allclose(t, t0, rtol=0, atol=1e-9)


@settings(max_examples=100, deadline=None)
@given(dims, st.booleans(), seeds)
def test_no_rotation_and_translation_align_better(d, weighted, seed):
    rng = np.random.default_rng(seed)
    P = rng.normal(size=(15, d))
    Q = rng.normal(size=(15, d)) + P @ ortho_group.rvs(d, random_state=rng).T
    w = rng.uniform(0.0, 3.0, size=15) if weighted else np.ones(15)
    R, t = rigid_align(P, Q, w if weighted else None)
    assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-12)
    best = objective(R, t, P, Q, w)
    for R_other in special_ortho_group.rvs(d, size=30, random_state=rng):
        # for a fixed rotation the best translation matches the weighted centroids
        t_other = w @ (Q - P @ R_other.T) / w.sum()
        assert objective(R_other, t_other, P, Q, w) >= best - 1e-9 * max(best, 1.0)
    # and for the chosen rotation, moving the translation only makes it worse
    for dt in rng.normal(size=(5, d)):
        assert objective(R, t + 1e-3 * dt, P, Q, w) > best


@settings(max_examples=100, deadline=None)
@given(dims, seeds)
def test_zero_weight_outliers_do_not_disturb_the_recovery(d, seed):
    rng = np.random.default_rng(seed)
    P = rng.normal(size=(12, d))
    assume(np.linalg.svd(P[:8] - P[:8].mean(axis=0), compute_uv=False)[-1] > 1e-2)
    R0 = special_ortho_group.rvs(d, random_state=rng)
    t0 = rng.uniform(-10, 10, size=d)
    Q = P @ R0.T + t0
    Q[8:] = rng.uniform(-100, 100, size=(4, d))
    w = np.r_[rng.uniform(0.1, 5.0, size=8), np.zeros(4)]
    R, t = rigid_align(P, Q, w)
    np.testing.assert_allclose(R, R0, rtol=0, atol=1e-9)
    np.testing.assert_allclose(t, t0, rtol=0, atol=1e-9)


@pytest.mark.parametrize("d", [2, 3])
def test_a_mirror_image_is_aligned_by_a_rotation_not_the_mirror(d):
    P = real_points(d)
    mirror = np.diag([1.0] * (d - 1) + [-1.0])
    R, t = rigid_align(P, P @ mirror)
    assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(R.T @ R, np.eye(d), atol=1e-12)


def test_input_is_not_modified():
    rng = np.random.default_rng(0)
    P, Q, w = rng.normal(size=(6, 3)), rng.normal(size=(6, 3)), rng.uniform(size=6)
    copies = (P.copy(), Q.copy(), w.copy())
    rigid_align(P, Q, w)
    for a, b in zip((P, Q, w), copies):
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize(
    "P, Q, w, message",
    [
        (np.ones((4, 4)), np.ones((4, 4)), None, "P must have 2 or 3 columns"),
        (np.ones((4, 3)), np.ones((5, 3)), None, "Q must have the same shape as P"),
        (np.ones((4, 3)), np.ones((4, 2)), None, "Q must have the same shape as P"),
        (np.full((4, 3), np.nan), np.ones((4, 3)), None, "P contains NaN"),
        (np.ones((4, 3)), np.full((4, 3), np.inf), None, "Q contains NaN or inf"),
        (np.ones((4, 3)), np.ones((4, 3)), np.ones(3), "w must have one weight per point"),
        (np.ones((4, 3)), np.ones((4, 3)), -np.ones(4), "w must be non-negative"),
        (np.ones((4, 3)), np.ones((4, 3)), np.zeros(4), "w must have a positive sum"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(P, Q, w, message):
    with pytest.raises(ValueError, match=message):
        rigid_align(P, Q, w)
