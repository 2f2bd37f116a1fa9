import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st
from scipy.stats import ortho_group, special_ortho_group

from reference.shape_matching import orthogonal_align
from starter.meshes import load_mesh

dims = st.sampled_from([2, 3])
seeds = st.integers(0, 2**32 - 1)


def random_orthogonal(d, reflect, rng):
    R = special_ortho_group.rvs(d, random_state=rng)
    return R @ np.diag([-1.0] + [1.0] * (d - 1)) if reflect else R


def objective(R, t, P, Q, w):
    return float(w @ np.sum((P @ R.T + t - Q) ** 2, axis=1))


def direct_svd_solution(P, Q, w):
    """Orthogonal Procrustes written out independently: SVD of ``Σ w (q - q̄)(p - p̄)ᵀ``."""
    p_bar = w @ P / w.sum()
    q_bar = w @ Q / w.sum()
    H = (Q - q_bar).T @ ((P - p_bar) * w[:, None])
    U, _, Vt = np.linalg.svd(H)
    R = U @ Vt
    return R, q_bar - R @ p_bar


def real_points(d):
    return load_mesh({2: "character", 3: "nut"}[d])[0]


@settings(max_examples=200)
@given(dims, st.integers(0, 20), st.booleans(), seeds)
def test_recovers_a_known_orthogonal_map_and_translation(d, extra, reflect, seed):
    rng = np.random.default_rng(seed)
    P = rng.normal(size=(d + 1 + extra, d))
    assume(np.linalg.svd(P - P.mean(axis=0), compute_uv=False)[-1] > 1e-2)
    R0 = random_orthogonal(d, reflect, rng)
    t0 = rng.uniform(-10, 10, size=d)
    R, t = orthogonal_align(P, P @ R0.T + t0)
    assert R.shape == (d, d) and t.shape == (d,)
    np.testing.assert_allclose(R, R0, rtol=0, atol=1e-9)
    np.testing.assert_allclose(t, t0, rtol=0, atol=1e-9)
    assert np.linalg.det(R) == pytest.approx(-1.0 if reflect else 1.0)


@settings(max_examples=100)
@given(dims, st.booleans(), seeds)
def test_zero_weight_outliers_do_not_disturb_the_recovery(d, reflect, seed):
    rng = np.random.default_rng(seed)
    P = rng.normal(size=(12, d))
    assume(np.linalg.svd(P[:8] - P[:8].mean(axis=0), compute_uv=False)[-1] > 1e-2)
    R0 = random_orthogonal(d, reflect, rng)
    t0 = rng.uniform(-10, 10, size=d)
    Q = P @ R0.T + t0
    Q[8:] = rng.uniform(-100, 100, size=(4, d))
    w = np.r_[rng.uniform(0.1, 5.0, size=8), np.zeros(4)]
    R, t = orthogonal_align(P, Q, w)
    np.testing.assert_allclose(R, R0, rtol=0, atol=1e-9)
    np.testing.assert_allclose(t, t0, rtol=0, atol=1e-9)


@pytest.mark.parametrize("reflect", [False, True])
@pytest.mark.parametrize("d", [2, 3])
def test_matches_the_direct_svd_solution_on_a_noisy_real_mesh(d, reflect):
    rng = np.random.default_rng(5)
    P = real_points(d)
    Q = P @ random_orthogonal(d, reflect, rng).T + rng.normal(size=d) + 0.05 * rng.normal(size=P.shape)
    w = rng.uniform(0.0, 2.0, size=len(P))
    for weights in (None, w):
        R, t = orthogonal_align(P, Q, weights)
        R_svd, t_svd = direct_svd_solution(P, Q, np.ones(len(P)) if weights is None else weights)
        np.testing.assert_allclose(R, R_svd, rtol=0, atol=1e-12)
        np.testing.assert_allclose(t, t_svd, rtol=0, atol=1e-12 * np.abs(Q).max())


@settings(max_examples=50)
@given(dims, seeds)
def test_no_orthogonal_map_or_translation_fits_better(d, seed):
    rng = np.random.default_rng(seed)
    P = rng.normal(size=(15, d))
    Q = rng.normal(size=(15, d))
    w = rng.uniform(0.0, 2.0, size=15)
    R, t = orthogonal_align(P, Q, w)
    np.testing.assert_allclose(R.T @ R, np.eye(d), rtol=0, atol=1e-12)
    best = objective(R, t, P, Q, w)
    tol = 1e-12 * max(best, 1.0)
    for other in ortho_group.rvs(d, size=30, random_state=rng):
        t_other = w @ (Q - P @ other.T) / w.sum()
        assert best <= objective(other, t_other, P, Q, w) + tol
    for dt in rng.normal(scale=1e-3, size=(10, d)):
        assert best <= objective(R, t + dt, P, Q, w) + tol


def test_inputs_are_not_modified():
    P = real_points(3)
    Q = P[::-1].copy()
    w = np.linspace(0.0, 1.0, len(P))
    copies = P.copy(), Q.copy(), w.copy()
    orthogonal_align(P, Q, w)
    for before, after in zip(copies, (P, Q, w)):
        np.testing.assert_array_equal(before, after)


P_OK = np.arange(12.0).reshape(4, 3)


@pytest.mark.parametrize(
    "P, Q, w, message",
    [
        (P_OK, P_OK[:3], None, r"Q must have the same shape as P .* got P \(4, 3\) and Q \(3, 3\)"),
        (P_OK, P_OK[:, :2], None, r"Q must have the same shape as P"),
        (P_OK.ravel(), P_OK, None, "P must be a 2-D array"),
        (np.where(P_OK == 0, np.nan, P_OK), P_OK, None, "P contains NaN or inf"),
        (P_OK, np.where(P_OK == 0, np.inf, P_OK), None, "Q contains NaN or inf"),
        (P_OK, np.full((4, 3), "q"), None, "Q must be a numeric array"),
        (P_OK, P_OK, [1.0, 1.0], r"w must have one weight per point \(4\), got 2"),
        (P_OK, P_OK, [1.0, 1.0, -0.5, 1.0], r"w must be non-negative, got w\[2\] = -0.5"),
        (P_OK, P_OK, [1.0, np.nan, 1.0, 1.0], "w contains NaN or inf"),
    ],
)
def test_bad_inputs_raise_value_error_naming_the_argument(P, Q, w, message):
    with pytest.raises(ValueError, match=message):
        orthogonal_align(P, Q, w)
