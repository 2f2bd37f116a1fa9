"""The tetrahedra checks (stage 07) fail realistic mistakes, with hints, and accept correct variations."""

from __future__ import annotations

import importlib
import types
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

from grader.checks import check_namespace
from tests.corpus import load_entry

# The package re-exports tet_volumes(), which hides the module attribute ``reference.tetrahedra``.
ref = importlib.import_module("reference.tetrahedra")
# correct variants: the corpus entry's loops over dihedral angles (dense L) and polar decomposition
CORRECT = load_entry(Path(__file__).resolve().parents[1] / "corpus" / "correct" / "tetrahedra_dihedral_loops_and_polar.py")


def corpus_solution(function):
    """``function`` as the correct corpus entry writes it, calling the reference for the rest."""
    namespace = dict(vars(ref))
    exec(CORRECT.solutions[function], namespace)
    return namespace[function]


def grade(function, implementation, seed=0):
    """The checks' result for the reference with ``function`` replaced by ``implementation``."""
    return check_namespace(function, {**vars(ref), function: implementation}, seed)


def details(result):
    return " ".join(v.detail for c in result.cases for v in c.verdicts if not v.passed)


def edges(V, T):
    V, T = np.asarray(V, float), np.asarray(T)
    return np.stack([V[T[:, k]] - V[T[:, 0]] for k in (1, 2, 3)], axis=2)


def volumes_unsigned(V, T):
    return np.abs(ref.tet_volumes(V, T))


def volumes_of_the_parallelepiped(V, T):
    return np.linalg.det(edges(V, T))


def laplacian_signs_flipped(V, T):
    return -ref.tet_cotangent_laplacian(V, T)


def laplacian_times_det(V, T):
    return 6 * ref.tet_cotangent_laplacian(V, T)


def mass_signed(V, T):
    T = np.asarray(T)
    return sp.diags(np.bincount(T.ravel(), np.repeat(ref.tet_volumes(V, T) / 4, 4), minlength=len(V)))


def mass_whole_volume(V, T):
    return 4 * ref.tet_mass_matrix(V, T)


def gradients_transposed(V, U, T):
    return ref.deformation_gradients(V, U, T).transpose(0, 2, 1)


def gradients_inverted(V, U, T):
    return edges(V, T) @ np.linalg.inv(edges(U, T))


def rotations_without_sign_correction(V, U, T):
    X, _, Yt = np.linalg.svd(ref.deformation_gradients(V, U, T))
    return X @ Yt


def rotations_transposed(V, U, T):
    return ref.tet_arap_rotations(V, U, T).transpose(0, 2, 1)


def energy_signed_volumes(V, U, T, R):
    J = ref.deformation_gradients(V, U, T)
    return float(ref.tet_volumes(V, T) @ np.sum((J - R) ** 2, axis=(1, 2)))


def energy_unweighted(V, U, T, R):
    J = ref.deformation_gradients(V, U, T)
    return float(np.sum((J - R) ** 2))


def biharmonic_without_mass(V, T):
    L = ref.tet_cotangent_laplacian(V, T)
    return L @ L


def biharmonic_times_mass(V, T):
    L = ref.tet_cotangent_laplacian(V, T)
    return L @ ref.tet_mass_matrix(V, T) @ L


def global_step_transposed(data, R, handle_positions):
    return ref.tet_arap_global_step(data, np.transpose(R, (0, 2, 1)), handle_positions)


def global_step_signed_volumes(data, R, handle_positions):
    signed = types.SimpleNamespace(**{**vars(data), "volumes": ref.tet_volumes(data.V, data.T)})
    return ref.tet_arap_global_step(signed, R, handle_positions)


def global_step_without_handle_columns(data, R, handle_positions):
    dropped = types.SimpleNamespace(**{**vars(data), "L_free_handles": 0 * data.L_free_handles})
    return ref.tet_arap_global_step(dropped, R, handle_positions)


def global_step_handles_not_copied(data, R, handle_positions):
    U = ref.tet_arap_global_step(data, R, handle_positions)
    U[data.handles] = data.V[data.handles]  # solved with the targets, but the rest positions returned
    return U


def precompute_forgets_the_first_handle(V, T, handles):
    """Factorizes for all handles but the first, which the global step then solves for as a free vertex."""
    data = ref.tet_arap_precompute(V, T, handles)
    kept = ref.tet_arap_precompute(V, T, np.asarray(handles)[1:])
    return types.SimpleNamespace(**{**vars(kept), "handles": np.asarray(handles), "L_free_handles": data.L_free_handles})


@pytest.mark.parametrize(
    "function, implementation, hint",
    [
        ("tet_volumes", volumes_unsigned, "the volume is signed"),
        ("tet_volumes", volumes_of_the_parallelepiped, "six times too large"),
        ("tet_cotangent_laplacian", laplacian_signs_flipped, "the signs are flipped"),
        ("tet_cotangent_laplacian", laplacian_times_det, "six times too large"),
        ("tet_mass_matrix", mass_signed, "use |vol|"),
        ("tet_mass_matrix", mass_whole_volume, "a quarter of each tetrahedron's volume"),
        ("deformation_gradients", gradients_transposed, "each J_t is transposed"),
        ("deformation_gradients", gradients_inverted, "this is J⁻¹"),
        ("tet_arap_rotations", rotations_without_sign_correction, "det R = -1: a reflection"),
        ("tet_arap_rotations", rotations_transposed, "R_t is transposed"),
        ("tet_arap_energy", energy_signed_volumes, "use |vol|"),
        ("tet_arap_energy", energy_unweighted, "weighted by its volume"),
        ("tet_biharmonic_matrix", biharmonic_without_mass, "M⁻¹ is missing"),
        ("tet_biharmonic_matrix", biharmonic_times_mass, "not by M"),
        ("tet_arap_global_step", global_step_transposed, "not its transpose"),
        ("tet_arap_global_step", global_step_signed_volumes, "weight B by |vol_t|"),
        ("tet_arap_global_step", global_step_without_handle_columns, "the handles' columns belong on the right-hand side"),
        ("tet_arap_global_step", global_step_handles_not_copied, "its handle position is"),
    ],
)
def test_a_common_mistake_fails_with_a_hint_that_names_it(function, implementation, hint):
    result = grade(function, implementation)
    assert result.fraction < 1.0
    assert hint in details(result)


@pytest.mark.parametrize("function", ["tet_volumes", "tet_cotangent_laplacian", "tet_arap_rotations"])
def test_a_correct_variant_passes_every_case(function):
    assert grade(function, corpus_solution(function)).fraction == 1.0


def test_every_tet_function_sees_both_orientations_and_more_than_one_mesh():
    from grader.checks import seeded_cases

    for function in ("tet_volumes", "tet_cotangent_laplacian", "tet_mass_matrix", "deformation_gradients",
                     "tet_arap_rotations", "tet_arap_energy", "tet_arap_precompute", "tet_arap_global_step", "tet_biharmonic_matrix"):
        cases, _ = seeded_cases(function, 0)
        # the mesh is in the first step's arguments (the precomputation's, for the global step)
        Ts = [next(a for a in c.args(0) if np.ndim(a) == 2 and np.shape(a)[1] == 4 and a.dtype.kind == "i") for c in cases]
        Vs = [c.args(0)[0] for c in cases]
        signs = np.concatenate([np.sign(ref.tet_volumes(V, T)) for V, T in zip(Vs, Ts)])
        assert (signs > 0).any() and (signs < 0).any(), function
        assert len({len(T) for T in Ts}) >= 3, function


def test_the_global_step_checks_pass_the_reference_and_fail_a_precompute_that_drops_a_handle():
    assert grade("tet_arap_global_step", ref.tet_arap_global_step).fraction == 1.0
    assert grade("tet_arap_precompute", ref.tet_arap_precompute).fraction == 1.0
    result = grade("tet_arap_precompute", precompute_forgets_the_first_handle)
    assert result.fraction < 1.0


def test_a_global_step_with_a_design_of_its_own_passes_every_case():
    # the correct entry's data is a dict: its precomputation and global step go together
    namespace = dict(vars(ref))
    for function in ("tet_arap_precompute", "tet_arap_global_step"):
        exec(CORRECT.solutions[function], namespace)
    for function in ("tet_arap_precompute", "tet_arap_global_step"):
        assert check_namespace(function, namespace, 0).fraction == 1.0, function
