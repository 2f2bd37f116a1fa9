"""The stage 06 (FAST) checks fail realistic mistakes and accept correct variations."""

from __future__ import annotations

import types

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import reference.fast as ref
from grader.checks import all_checks, check_namespace, evaluate, seeded_cases, wire
from grader.checks.base import Case
from grader.harness.outputs import CaseOutput
from reference.arap import arap_covariances, arap_energy, arap_rotations, cotangent_laplacian, cotangent_weights
from reference.linear_blend_skinning import lbs, lbs_matrix
from reference.sign_correction import optimal_rotation


def grade(function, seed=0, **replacements):
    """The checks' result for the reference with some contract functions replaced."""
    return check_namespace(function, {**vars(ref), **replacements}, seed)


def failed(result):
    return result.failed_verdicts()


# --- a student's own data, local step, global step and loop, from the contract's definitions ---


def student_precompute(V, F, W, clusters, fixed):
    """A student's data: the problem, the subspace's quadratic form ``A = -3 Mᵀ L M`` and the reference's data."""
    V, W = np.asarray(V, float), np.asarray(W, float)
    M = lbs_matrix(V, W)
    A = -3.0 * (M.T @ (cotangent_laplacian(V, F) @ M))
    return types.SimpleNamespace(
        V=V, F=F, W=W, clusters=np.asarray(clusters), fixed=np.asarray(fixed), C=cotangent_weights(V, F), M=M, A=np.asarray(A),
        k=int(np.max(clusters)) + 1, inner=ref.fast_precompute(V, F, W, clusters, fixed),
    )


def student_energy(data, T, R):
    return arap_energy(data.V, lbs(data.V, data.W, T), data.F, data.C, np.asarray(R)[data.clusters])


def cluster_covariances(data, T):
    S = arap_covariances(data.V, lbs(data.V, data.W, T), data.F, data.C)
    S_c = np.zeros((data.k, *S.shape[1:]))
    np.add.at(S_c, data.clusters, S)
    return S_c


def student_rotations(data, T):
    return optimal_rotation(cluster_covariances(data, T))


def linear_term(V, F, C, R):
    """``B`` of the energy ``-3 tr(Uᵀ L U) − 2 tr(Uᵀ B) + const`` for per-vertex rotations ``R``."""
    edge = V[F[:, [2, 0, 1]]] - V[F[:, [1, 2, 0]]]  # opposite each corner, as in the contract
    rotated = np.einsum("tij,tkj->tki", R[F].sum(axis=1), edge) * C[..., None]
    B = np.zeros_like(V)
    for k in range(3):
        np.add.at(B, F[:, (k + 2) % 3], rotated[:, k])
        np.add.at(B, F[:, (k + 1) % 3], -rotated[:, k])
    return B


def subspace_global_step(data, R, fixed_transforms, factor=3.0, transpose=False, translations_only=False):
    """Minimize over ``Tstack = vstack(T_jᵀ)`` the energy ``tr(Tᵀ A T) − 2 tr(Tᵀ Mᵀ B)``: exact, or with a usual mistake.

    ``factor`` replaces the 3 of ``A = -3 Mᵀ L M``; ``transpose`` uses ``R_cᵀ``;
    ``translations_only`` keeps the free handles' linear parts at ``I``.
    """
    V, W = data.V, data.W
    d, m = V.shape[1], W.shape[1]
    R = np.asarray(R, float)
    R = np.swapaxes(R, 1, 2) if transpose else R
    A = data.A * (factor / 3.0)
    rhs = data.M.T @ linear_term(V, data.F, data.C, R[data.clusters])
    rows = np.arange(m * (d + 1)).reshape(m, d + 1)
    T = np.tile(np.eye(d, d + 1), (m, 1, 1))
    T[data.fixed] = fixed_transforms
    stack = T.transpose(0, 2, 1).reshape(-1, d)
    free_handles = np.setdiff1d(np.arange(m), data.fixed)
    unknown = (rows[free_handles][:, d] if translations_only else rows[free_handles]).ravel()
    known = np.setdiff1d(rows.ravel(), unknown)
    stack[unknown] = np.linalg.solve(A[np.ix_(unknown, unknown)], rhs[unknown] - A[np.ix_(unknown, known)] @ stack[known])
    return stack.reshape(m, d + 1, d).transpose(0, 2, 1)


def penalty_global_step(data, R, fixed_transforms, weight=1e8):
    """The fixed transforms held by a penalty ``weight ‖T[fixed] − fixed_transforms‖²``: only approximately met."""
    d, m = data.V.shape[1], data.W.shape[1]
    rows = np.arange(m * (d + 1)).reshape(m, d + 1)[data.fixed].ravel()
    A = data.A.copy()
    A[rows, rows] += weight
    rhs = data.M.T @ linear_term(data.V, data.F, data.C, np.asarray(R)[data.clusters])
    rhs[rows] += weight * np.asarray(fixed_transforms).transpose(0, 2, 1).reshape(-1, d)
    return np.linalg.solve(A, rhs).reshape(m, d + 1, d).transpose(0, 2, 1)


def student_solve(energy_of="after", replace_fixed=True, extra_energy=False):
    """``fast_solve`` on ``student_precompute`` data, optionally with one of the usual mistakes."""

    def solve(data, fixed_transforms, T0=None, iterations=10):
        d, m = data.V.shape[1], data.W.shape[1]
        T = np.tile(np.eye(d, d + 1), (m, 1, 1)) if T0 is None else np.array(T0, float)
        if replace_fixed:
            T[data.fixed] = fixed_transforms
        energies = [student_energy(data, T, student_rotations(data, T))] if extra_energy else []
        for _ in range(iterations):
            R = student_rotations(data, T)
            before = student_energy(data, T, R)
            T = subspace_global_step(data, R, fixed_transforms)
            if energy_of == "after":
                energies.append(student_energy(data, T, R))
            elif energy_of == "fresh rotations":
                energies.append(student_energy(data, T, student_rotations(data, T)))
            else:
                energies.append(before)
        return T, energies

    return solve


STUDENT = {
    "fast_precompute": student_precompute,
    "fast_energy": student_energy,
    "fast_rotations": student_rotations,
    "fast_global_step": subspace_global_step,
    "fast_solve": student_solve(),
}


@pytest.mark.parametrize("function", ["fast_precompute", "fast_energy", "fast_rotations", "fast_global_step", "fast_solve"])
def test_a_students_own_data_and_subspace_system_pass(function):
    assert grade(function, **STUDENT).fraction == 1.0


# --- clusterings ---


def lloyd(W, labels, k, keep_empty=False):
    """Lloyd's iterations from ``labels`` until they repeat; an empty cluster keeps its mean (NaN) when ``keep_empty``."""
    for _ in range(1000):
        counts = np.bincount(labels, minlength=k)
        if counts.min() == 0 and not keep_empty:
            raise ValueError("empty cluster")
        means = np.zeros((k, W.shape[1]))
        np.add.at(means, labels, W)
        with np.errstate(invalid="ignore", divide="ignore"):
            means /= counts[:, None]
        squared = np.sum((W[:, None] - means[None]) ** 2, axis=2)
        new = np.argmin(np.where(np.isnan(squared), np.inf, squared), axis=1)
        if np.array_equal(new, labels):
            return labels
        labels = new
    raise RuntimeError("Lloyd's iterations did not settle")


def nearest_to(W, centres):
    return np.argmin(np.sum((W[:, None] - centres[None]) ** 2, axis=2), axis=1)


def kmeans_plus_plus_lloyd(init_seed):
    """A correct k-means of another design: scipy's k-means++ seeding, then Lloyd's iterations to the fixed point."""
    from scipy.cluster.vq import kmeans2

    def rotation_clusters(W, k, seed=0):
        W = np.asarray(W, float)
        centres, _ = kmeans2(W, k, minit="++", iter=1, seed=np.random.default_rng([init_seed, seed]))
        return lloyd(W, nearest_to(W, centres), k)

    return rotation_clusters


def one_assignment(W, k, seed=0):
    """Each row to the nearest of k random rows, without iterating."""
    rng = np.random.default_rng(seed)
    return nearest_to(W, W[rng.choice(len(W), k, replace=False)])


def empty_clusters_kept(W, k, seed=0):
    """Random rows as initial means (identical rows give identical means), empty clusters never refilled."""
    rng = np.random.default_rng(seed)
    W = np.asarray(W, float)
    return lloyd(W, nearest_to(W, W[rng.choice(len(W), k, replace=False)]), k, keep_empty=True)


def bunched_start(W, k, seed=0):
    """Lloyd's fixed point from the k distinct rows with most weight on handle 0: a poor local minimum."""
    W = np.asarray(W, float)
    order = np.argsort(-W[:, 0], kind="stable")
    _, first = np.unique(W[order], axis=0, return_index=True)
    return lloyd(W, nearest_to(W, W[order[np.sort(first)[:k]]]), k)


@pytest.mark.parametrize("init_seed", [0, 1, 2])
def test_a_correct_kmeans_of_another_design_passes(init_seed):
    assert grade("rotation_clusters", rotation_clusters=kmeans_plus_plus_lloyd(init_seed)).fraction == 1.0


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_lloyd_fixed_points_from_random_rows_are_accepted(seed):
    """k-means has local minima: every fixed point reached from k random distinct rows passes, spread included."""
    cases, expected = seeded_cases("rotation_clusters", seed)
    checks, rng = all_checks()["rotation_clusters"], np.random.default_rng(seed)
    for case, want in zip(cases, expected):
        W, k = case.args()[:2]
        if not 1 < k < len(np.unique(W, axis=0)):  # one clustering only
            continue
        reached = 0
        distinct = np.unique(W, axis=0)  # BBW weights repeat rows (exact zeros): two equal seeds lose a cluster at once
        for _ in range(30):
            try:
                labels = lloyd(W, nearest_to(W, distinct[rng.choice(len(distinct), k, replace=False)]), k)
            except ValueError:  # this start lost a cluster: not a clustering the contract allows
                continue
            reached += 1
            assert all(v.passed for v in checks.verify(case, labels, want)), case.label
        assert reached, f"{case.label}: no start reached a fixed point"


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), k=st.integers(1, 6))
def test_any_lloyd_fixed_point_meets_the_structural_verdicts_even_with_ties(seed, k):
    """Integer weights on a coarse grid make many rows equidistant from two means: either choice is a fixed point."""
    rng = np.random.default_rng(seed)
    W = rng.integers(0, 3, (30, 3)).astype(float)
    distinct = np.unique(W, axis=0)
    k = min(k, len(distinct))
    start = nearest_to(W, distinct[rng.permutation(len(distinct))[:k]])
    try:
        labels = lloyd(W, start, k)
    except ValueError:  # this start lost a cluster: not a clustering the contract allows
        return
    case = Case.call("random integer weights", "rotation_clusters", W, k)
    verdicts = all_checks()["rotation_clusters"].verify(case, labels, labels)
    assert all(v.passed for v in verdicts if not v.name.startswith("within-cluster"))


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_labels_are_never_compared_any_renaming_of_the_references_clustering_passes(seed):
    cases, expected = seeded_cases("rotation_clusters")
    rng = np.random.default_rng(seed)
    for case, want in zip(cases, expected):
        renamed = rng.permutation(case.args()[1])[want]
        assert all(v.passed for v in all_checks()["rotation_clusters"].verify(case, renamed, want)), case.label


def _rotations_of_vertex_rotations(data, T):
    """Per-vertex optimal rotations, then the rotation nearest to their sum per cluster: not the cluster's summed covariance."""
    R_i = arap_rotations(data.V, lbs(data.V, data.W, T), data.F, data.C)
    R_c = np.zeros((data.k, *R_i.shape[1:]))
    np.add.at(R_c, data.clusters, R_i)
    return optimal_rotation(_swap(R_c))  # maximizes tr(R R_cᵀ)


def _rotations_without_sign_correction(data, T):
    U, _, Vt = np.linalg.svd(cluster_covariances(data, T))
    return np.swapaxes(Vt, 1, 2) @ np.swapaxes(U, 1, 2)


def _swap(R):
    return np.swapaxes(R, -1, -2)


MISTAKES = {
    "clusters: one assignment step, no iterations": ("rotation_clusters", {"rotation_clusters": one_assignment}, "Lloyd's fixed point: each row nearest to its own cluster's mean"),
    "clusters: empty clusters never refilled": ("rotation_clusters", {"rotation_clusters": empty_clusters_kept}, "every label used"),
    "clusters: a poor local minimum": ("rotation_clusters", {"rotation_clusters": bunched_start}, "within-cluster sum of squares at most 3× the reference's"),
    "clusters: labels 1..k": ("rotation_clusters", {"rotation_clusters": lambda W, k, seed=0: ref.rotation_clusters(W, k, seed) + 1}, "labels in range(k)"),
    "clusters: float labels": ("rotation_clusters", {"rotation_clusters": lambda W, k, seed=0: ref.rotation_clusters(W, k, seed).astype(float)}, "integer labels"),
    "energy: one rotation for every cell": (
        "fast_energy",
        {"fast_precompute": student_precompute, "fast_energy": lambda data, T, R: student_energy(data, T, np.broadcast_to(R[:1], np.shape(R)))},
        "energy",
    ),
    "energy: R transposed": ("fast_energy", {"fast_precompute": student_precompute, "fast_energy": lambda data, T, R: student_energy(data, T, _swap(R))}, "energy"),
    "rotations: average of per-vertex rotations": (
        "fast_rotations",
        {"fast_precompute": student_precompute, "fast_rotations": _rotations_of_vertex_rotations},
        "optimal tr(R_c S_c) for every cluster",
    ),
    "rotations: no sign correction": ("fast_rotations", {"fast_precompute": student_precompute, "fast_rotations": _rotations_without_sign_correction}, "det = +1"),
    "rotations: transposed": (
        "fast_rotations",
        {"fast_precompute": student_precompute, "fast_rotations": lambda data, T: _swap(student_rotations(data, T))},
        "optimal tr(R_c S_c) for every cluster",
    ),
    "precompute: fixed handles sorted": (
        "fast_precompute",
        {"fast_precompute": lambda V, F, W, clusters, fixed: ref.fast_precompute(V, F, W, clusters, np.sort(fixed))},
        "fixed transforms met exactly",
    ),
    "global step: fixed transforms held by a penalty": (
        "fast_global_step",
        {"fast_precompute": student_precompute, "fast_global_step": penalty_global_step},
        "fixed transforms met exactly",
    ),
    "global step: without the factor 3": (
        "fast_global_step",
        {"fast_precompute": student_precompute, "fast_global_step": lambda data, R, X: subspace_global_step(data, R, X, factor=1.0)},
        "minimal energy for the given rotations",
    ),
    "global step: R transposed": (
        "fast_global_step",
        {"fast_precompute": student_precompute, "fast_global_step": lambda data, R, X: subspace_global_step(data, R, X, transpose=True)},
        "minimal energy for the given rotations",
    ),
    "global step: translations only": (
        "fast_global_step",
        {"fast_precompute": student_precompute, "fast_global_step": lambda data, R, X: subspace_global_step(data, R, X, translations_only=True)},
        "minimal energy for the given rotations",
    ),
    "solve: energies with fresh rotations": (
        "fast_solve",
        {"fast_precompute": student_precompute, "fast_solve": student_solve(energy_of="fresh rotations")},
        "last energy is of T with the last iteration's rotations",
    ),
    "solve: energies before the global step": (
        "fast_solve",
        {"fast_precompute": student_precompute, "fast_solve": student_solve(energy_of="before")},
        "energies match the reference's from the same start",
    ),
    "solve: fixed rows of the start not replaced": (
        "fast_solve",
        {"fast_precompute": student_precompute, "fast_solve": student_solve(replace_fixed=False)},
        "T matches the reference's from the same start",
    ),
    "solve: the start's energy included": (
        "fast_solve",
        {"fast_precompute": student_precompute, "fast_solve": student_solve(extra_energy=True)},
        "len(energies) == iterations",
    ),
}


@pytest.mark.parametrize("mistake", MISTAKES)
def test_realistic_mistakes_fail(mistake):
    function, replacements, verdict = MISTAKES[mistake]
    assert verdict in failed(grade(function, **replacements))


def test_every_solve_case_separates_the_step_energy_from_fresh_rotations():
    result = grade("fast_solve", fast_precompute=student_precompute, fast_solve=student_solve(energy_of="fresh rotations"))
    assert result.fraction == 0.0


def test_nan_energies_fail_cleanly():
    cases, expected = seeded_cases("fast_solve")
    outputs = [CaseOutput((wire(value)[0], np.full(np.shape(value[1]), np.nan)), None, None) for value in expected]
    result = evaluate(all_checks()["fast_solve"], cases, outputs, expected)
    assert result.fraction == 0.0 and failed(result) == {"output shape"}


@pytest.mark.parametrize("function", ["fast_precompute", "fast_energy", "fast_rotations", "fast_global_step", "fast_solve"])
def test_a_students_multi_step_outputs_pass_through_the_kernel_wire(function, tmp_path):
    """The student's data object stays in the kernel; only the last step's raw output travels back."""
    import grader.harness.kernel_side as kernel_side
    from grader.harness.fixtures import write_fixtures
    from grader.harness.outputs import read_outputs

    namespace = {**vars(ref), **STUDENT}
    exec(compile(open(kernel_side.__file__).read(), "<kernel_side>", "exec"), namespace)
    cases, expected = seeded_cases(function)
    write_fixtures(function, cases, tmp_path / "fixtures")
    (tmp_path / "outputs").mkdir()
    namespace["__deformlab_collect__"](function, str(tmp_path / "fixtures"), str(tmp_path / "outputs"))
    collected = read_outputs(function, tmp_path / "outputs", len(cases))
    assert evaluate(all_checks()[function], cases, collected.cases, expected).fraction == 1.0
