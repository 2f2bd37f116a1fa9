"""The stage 03 checks fail realistic mistakes and accept correct variations."""

from __future__ import annotations

import types
from pathlib import Path

import igl
import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import reference.arap as ref
from reference.meshes import edges
from grader.checks import check_namespace, seeded_cases, all_checks, evaluate, wire
from grader.harness.outputs import CaseOutput


REPO = Path(__file__).resolve().parents[2]


def grade(function, seed=0, **replacements):
    """The checks' result for the reference with some contract functions replaced."""
    return check_namespace(function, {**vars(ref), **replacements}, seed)


def failed(result):
    return result.failed_verdicts()


# --- a student's own precomputation and global steps, built from the contract's definitions ---


def student_precompute(V, F, handles):
    """A student's data: the mesh, its weights, and the reference's data for an exact global step."""
    return types.SimpleNamespace(V=V, F=F, handles=handles, C=ref.cotangent_weights(V, F), inner=ref.arap_precompute(V, F, handles))


def student_global_step(data, R, handle_positions):
    """The global step on ``student_precompute`` data."""
    return ref.arap_global_step(data.inner, R, handle_positions)


def linear_term(V, F, C, R):
    """``B`` of the energy ``-3 tr(Uᵀ L U) − 2 tr(Uᵀ B) + const``: rotated rest edges gathered at their ends."""
    edge = V[F[:, [2, 0, 1]]] - V[F[:, [1, 2, 0]]]  # opposite each corner, as in the contract
    rotated = np.einsum("tij,tkj->tki", R[F].sum(axis=1), edge) * C[..., None]
    B = np.zeros_like(V)
    for k in range(3):
        np.add.at(B, F[:, (k + 2) % 3], rotated[:, k])
        np.add.at(B, F[:, (k + 1) % 3], -rotated[:, k])
    return B


def penalty_global_step(data, R, handle_positions, weight=1e8):
    """Minimize the energy plus ``weight ‖U[handles] − positions‖²``: handles only approximately met."""
    L = ref.cotangent_laplacian(data.V, data.F)
    penalty = sp.coo_matrix((np.full(len(data.handles), weight), (data.handles, data.handles)), shape=L.shape)
    rhs = linear_term(data.V, data.F, data.C, R)
    rhs[data.handles] += weight * handle_positions
    return spla.spsolve(sp.csc_matrix(-3.0 * L + penalty), rhs)


def kkt_global_step(data, R, handle_positions):
    """Handles as Lagrange constraints of the full system: exact, but not by substitution like the reference."""
    n, h = len(data.V), data.handles
    L = ref.cotangent_laplacian(data.V, data.F)
    select = sp.coo_matrix((np.ones(len(h)), (np.arange(len(h)), h)), shape=(len(h), n))
    K = sp.bmat([[-3.0 * L, select.T], [select, None]]).tocsc()
    return spla.spsolve(K, np.vstack([linear_term(data.V, data.F, data.C, R), handle_positions]))[:n]


def uniform_laplacian_editing(V, F, handles, handle_positions):
    """Laplacian editing with the graph Laplacian instead of the cotangent one."""
    n = len(V)
    E = edges(F)
    A = sp.coo_matrix((np.ones(2 * len(E)), (np.r_[E[:, 0], E[:, 1]], np.r_[E[:, 1], E[:, 0]])), shape=(n, n)).tocsr()
    L = A - sp.diags(np.asarray(A.sum(axis=1)).ravel())
    free = np.setdiff1d(np.arange(n), handles)
    U = V.copy()
    U[handles] = handle_positions
    U[free] = spla.spsolve(sp.csc_matrix(L[free][:, free]), (L @ V)[free] - L[free][:, handles] @ handle_positions)
    return U


def student_solve(energy_of="after", replace_handles=True, extra_energy=False):
    """``arap_solve`` on ``student_precompute`` data, optionally with one of the usual mistakes."""

    def solve(data, handle_positions, U0=None, iterations=10):
        V, F, C = data.V, data.F, data.C
        U = (V if U0 is None else U0).copy()
        if replace_handles:
            U[data.handles] = handle_positions
        energies = [ref.arap_energy(V, U, F, C, ref.arap_rotations(V, U, F, C))] if extra_energy else []
        for _ in range(iterations):
            R = ref.arap_rotations(V, U, F, C)
            before = ref.arap_energy(V, U, F, C, R)
            U = ref.arap_global_step(data.inner, R, handle_positions)
            if energy_of == "after":
                energies.append(ref.arap_energy(V, U, F, C, R))
            elif energy_of == "fresh rotations":
                energies.append(ref.arap_energy(V, U, F, C, ref.arap_rotations(V, U, F, C)))
            else:
                energies.append(before)
        return U, energies

    return solve


def test_a_students_own_data_and_loop_pass():
    assert grade("arap_solve", arap_precompute=student_precompute, arap_solve=student_solve()).fraction == 1.0


def test_an_exact_global_step_by_another_method_passes():
    assert grade("arap_global_step", arap_precompute=student_precompute, arap_global_step=kkt_global_step).fraction == 1.0


def rotations_without_sign_correction(V, U, F, C):
    Us, _, Vt = np.linalg.svd(ref.arap_covariances(V, U, F, C))
    return np.swapaxes(Vt, 1, 2) @ np.swapaxes(Us, 1, 2)


def _swap(R):
    return np.swapaxes(R, -1, -2)


def cotangent_weights_of_signed_area(V, F):
    """½ dot / cross with the signed 2D cross product: right on counter-clockwise triangles only."""
    V, F = np.asarray(V, float), np.asarray(F)
    a, b, c = V[F], V[np.roll(F, -1, axis=1)], V[np.roll(F, -2, axis=1)]
    u, v = b - a, c - a
    if V.shape[1] == 2:
        cross = u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]
    else:
        cross = np.linalg.norm(np.cross(u, v), axis=-1)
    return 0.5 * np.sum(u * v, axis=-1) / cross


MISTAKES = {
    "weights: cot instead of ½ cot": ("cotangent_weights", {"cotangent_weights": lambda V, F: 2.0 * ref.cotangent_weights(V, F)}, "C matches ½ cot of each corner's angle"),
    "weights: signed 2D area (clockwise triangles flip sign)": ("cotangent_weights", {"cotangent_weights": cotangent_weights_of_signed_area}, "C matches ½ cot of each corner's angle"),
    "weights: columns shifted": ("cotangent_weights", {"cotangent_weights": lambda V, F: np.roll(ref.cotangent_weights(V, F), 1, axis=1)}, "C matches ½ cot of each corner's angle"),
    "laplacian: signs flipped": ("cotangent_laplacian", {"cotangent_laplacian": lambda V, F: -ref.cotangent_laplacian(V, F)}, "L matches"),
    "laplacian: dense": ("cotangent_laplacian", {"cotangent_laplacian": lambda V, F: ref.cotangent_laplacian(V, F).toarray()}, "a scipy.sparse matrix"),
    "covariances: transposed": ("arap_covariances", {"arap_covariances": lambda V, U, F, C: _swap(ref.arap_covariances(V, U, F, C))}, "S matches"),
    "covariances: own weights instead of C": (
        "arap_covariances",
        {"arap_covariances": lambda V, U, F, C: ref.arap_covariances(V, U, F, ref.cotangent_weights(V, F))},
        "S matches",
    ),
    "rotations: no sign correction": ("arap_rotations", {"arap_rotations": rotations_without_sign_correction}, "det = +1"),
    "rotations: transposed": ("arap_rotations", {"arap_rotations": lambda V, U, F, C: _swap(ref.arap_rotations(V, U, F, C))}, "optimal tr(R_i S_i) at every vertex"),
    "energy: fresh rotations instead of R": (
        "arap_energy",
        {"arap_energy": lambda V, U, F, C, R: ref.arap_energy(V, U, F, C, ref.arap_rotations(V, U, F, C))},
        "energy",
    ),
    "energy: R transposed": ("arap_energy", {"arap_energy": lambda V, U, F, C, R: ref.arap_energy(V, U, F, C, _swap(R))}, "energy"),
    "precompute: handles sorted": (
        "arap_precompute",
        {"arap_precompute": lambda V, F, handles: ref.arap_precompute(V, F, np.sort(handles))},
        "handles met exactly",
    ),
    "global step: handles held by a penalty": (
        "arap_global_step",
        {"arap_precompute": student_precompute, "arap_global_step": penalty_global_step},
        "handles met exactly",
    ),
    "global step: R transposed": (
        "arap_global_step",
        {"arap_global_step": lambda data, R, P: ref.arap_global_step(data, _swap(R), P)},
        "minimal energy for the given rotations",
    ),
    "global step: rotations ignored": (
        "arap_global_step",
        {"arap_global_step": lambda data, R, P: ref.arap_global_step(data, np.broadcast_to(np.eye(R.shape[-1]), R.shape).copy(), P)},
        "U is the unique minimizer",
    ),
    "solve: energies with fresh rotations": (
        "arap_solve",
        {"arap_precompute": student_precompute, "arap_solve": student_solve(energy_of="fresh rotations")},
        "last energy is of U with the last iteration's rotations",
    ),
    "solve: energies before the global step": (
        "arap_solve",
        {"arap_precompute": student_precompute, "arap_solve": student_solve(energy_of="before")},
        "energies match the reference's from the same start",
    ),
    "solve: handle rows of the start not replaced": (
        "arap_solve",
        {"arap_precompute": student_precompute, "arap_solve": student_solve(replace_handles=False)},
        "U matches the reference's from the same start",
    ),
    "solve: the start's energy included": (
        "arap_solve",
        {"arap_precompute": student_precompute, "arap_solve": student_solve(extra_energy=True)},
        "len(energies) == iterations",
    ),
    "editing: handles held by a penalty": (
        "laplacian_editing",
        {"laplacian_editing": lambda V, F, h, P: penalty_global_step(student_precompute(V, F, h), np.tile(np.eye(V.shape[1]), (len(V), 1, 1)), P)},
        "handles met exactly",
    ),
    "editing: uniform Laplacian": ("laplacian_editing", {"laplacian_editing": uniform_laplacian_editing}, "U is the unique minimizer"),
}


@pytest.mark.parametrize("mistake", MISTAKES)
def test_realistic_mistakes_fail(mistake):
    function, replacements, verdict = MISTAKES[mistake]
    assert verdict in failed(grade(function, **replacements))


def test_every_solve_case_separates_the_step_energy_from_fresh_rotations():
    result = grade("arap_solve", arap_precompute=student_precompute, arap_solve=student_solve(energy_of="fresh rotations"))
    assert result.fraction == 0.0


def test_nan_energies_fail_cleanly():
    cases, expected = seeded_cases("arap_solve")
    outputs = []
    for value in expected:
        U, energies = wire(value)
        outputs.append(CaseOutput((U, np.full(np.shape(energies), np.nan)), None, None))
    result = evaluate(all_checks()["arap_solve"], cases, outputs, expected)
    assert result.fraction == 0.0 and failed(result) == {"output shape"}


@pytest.mark.parametrize("function", ["arap_precompute", "arap_global_step", "arap_solve"])
def test_a_students_multi_step_outputs_pass_through_the_kernel_wire(function, tmp_path):
    """The student's data object stays in the kernel; only the last step's raw output travels back."""
    import grader.harness.kernel_side as kernel_side
    from grader.harness.fixtures import write_fixtures
    from grader.harness.outputs import read_outputs

    namespace = {**vars(ref), "arap_precompute": student_precompute, "arap_global_step": student_global_step, "arap_solve": student_solve()}
    exec(compile(open(kernel_side.__file__).read(), "<kernel_side>", "exec"), namespace)
    cases, expected = seeded_cases(function)
    write_fixtures(function, cases, tmp_path / "fixtures")
    (tmp_path / "outputs").mkdir()
    namespace["__deformlab_collect__"](function, str(tmp_path / "fixtures"), str(tmp_path / "outputs"))
    collected = read_outputs(function, tmp_path / "outputs", len(cases))
    assert evaluate(all_checks()[function], cases, collected.cases, expected).fraction == 1.0


def test_scenes_have_clockwise_mixed_and_scaled_copies_the_reference_solves_alike():
    """The orientation, size and place of a hidden problem never change its answer (up to the same similarity)."""
    from deformlab_packs.deformation.checks.arap import DISC, JITTERED, SCALED, TWO_COMPONENTS, deformation_scenes

    scenes = deformation_scenes(np.random.default_rng(9))

    assert (igl.doublearea(*scenes[DISC][:2]) < 0).all()  # signed for 2D input
    for label in (JITTERED, TWO_COMPONENTS):
        area = igl.doublearea(*scenes[label][:2])
        assert (area < 0).any() and (area > 0).any()
    V, F, handles, P = scenes["2D strip, right end turned by 90°"]
    Vs, Fs, hs, Ps = scenes[SCALED]
    assert np.array_equal(F, Fs) and np.array_equal(handles, hs)
    U = ref.laplacian_editing(V, F, handles, P)
    Us = ref.laplacian_editing(Vs, Fs, hs, Ps)
    # the copy's answer is the same similarity of the original's answer: fit it on the rest positions
    fit = np.linalg.lstsq(np.c_[V, np.ones(len(V))], Vs, rcond=None)[0]
    assert np.allclose(np.c_[U, np.ones(len(U))] @ fit, Us, atol=1e-9)
    assert np.allclose(ref.cotangent_weights(V, F), ref.cotangent_weights(Vs, Fs))


def test_a_laplacian_of_signed_area_cotangents_is_told_about_clockwise_triangles():
    from grader.build.authored import read_authored

    # the notebook's own Laplacian cell calls the student's cotangent_weights
    cells = read_authored(REPO / "notebooks" / "deformation" / "03_arap.py").cells
    laplacian = next(c.source for c in cells if c.kind == "solution" and c.function == "cotangent_laplacian")
    notebook = {"cotangent_weights": cotangent_weights_of_signed_area}
    exec(laplacian, notebook)
    result = grade("cotangent_laplacian", cotangent_laplacian=notebook["cotangent_laplacian"])
    details = [v.detail for c in result.cases for v in c.verdicts if not v.passed]
    assert any("clockwise mesh" in d and "signed area" in d for d in details)
    assert not any("clockwise" in d for d in details if "signs are flipped:" in d)
