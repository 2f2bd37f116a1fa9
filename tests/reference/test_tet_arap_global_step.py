import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from reference.tetrahedra import tet_arap_energy, tet_arap_global_step, tet_arap_precompute

seeds = st.integers(0, 2**32 - 1)


@settings(max_examples=10, deadline=None)
@given(seed=seeds)
def test_global_step_minimizes_the_energy_for_its_rotations(tet_mesh, random_rotation, seed):
    V, T = tet_mesh("hand_tet", seed)
    rng = np.random.default_rng(seed)
    handles = rng.choice(len(V), 5, replace=False)
    data = tet_arap_precompute(V, T, handles)
    R = np.stack([random_rotation(s) for s in rng.integers(0, 2**32, len(T))])
    targets = V[handles] + rng.standard_normal((5, 3))
    U = tet_arap_global_step(data, R, targets)
    assert np.array_equal(U[handles], targets)
    best = tet_arap_energy(V, U, T, R)
    # any change of the free vertices costs energy, and the gradient vanishes: quadratic growth
    for _ in range(3):
        step = rng.standard_normal(U.shape)
        step[handles] = 0
        for h in (1e-2, 1e-3):
            worse = tet_arap_energy(V, U + h * step, T, R)
            assert worse >= best
            assert worse - best == pytest.approx(h**2 * -np.sum(step * (data.L @ step)), rel=1e-6)


def test_r_must_have_one_rotation_per_tetrahedron(tet_mesh):
    V, T = tet_mesh("bar_tet")
    data = tet_arap_precompute(V, T, [0, 1])
    with pytest.raises(ValueError, match=r"R must have shape \(5184, 3, 3\), one rotation per tetrahedron"):
        tet_arap_global_step(data, np.zeros((len(V), 3, 3)), V[:2])
