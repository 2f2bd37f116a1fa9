"""A common mistake makes the public tests fail with a message that names it."""

import pytest

from grader.corpus import load_entry
from tests.grader.public_hints_audit import BUGGY, public_failures

TRANSPOSED_ROTATION = '''
import numpy as np


def optimal_rotation(S):
    U_tilde, _, V_tilde_T = np.linalg.svd(np.asarray(S, dtype=float))
    D = np.ones(U_tilde.shape[:-1])
    D[..., -1] = np.linalg.det(U_tilde @ V_tilde_T)
    return (U_tilde * D[..., None, :]) @ V_tilde_T  # Ũ D Ṽᵀ: the transpose of the answer
'''

TRANSPOSED_ORTHOGONAL = '''
import numpy as np


def optimal_orthogonal(S):
    U_tilde, _, V_tilde_T = np.linalg.svd(np.asarray(S, dtype=float))
    return U_tilde @ V_tilde_T
'''

LARGEST_FLIPPED = '''
import numpy as np


def optimal_rotation(S):
    U_tilde, _, V_tilde_T = np.linalg.svd(np.asarray(S, dtype=float))
    V_tilde = np.swapaxes(V_tilde_T, -1, -2).copy()
    sign = np.sign(np.linalg.det(V_tilde @ np.swapaxes(U_tilde, -1, -2)))
    V_tilde[..., 0] *= sign[..., None]  # the largest singular value's vector
    return V_tilde @ np.swapaxes(U_tilde, -1, -2)
'''


def public_test_failure(notebook: str, function: str, source: str) -> str:
    """The message of the first failing public test of ``function`` with ``source`` as its solution."""
    found = public_failures(notebook, {function: source}, {function})
    if function not in found:
        raise AssertionError(f"{notebook} has no tests cell for {function}")
    return found[function]


@pytest.mark.parametrize(
    "notebook, function, source, words",
    [
        ("02_sign_correction", "optimal_rotation", TRANSPOSED_ROTATION, ("transpose",)),
        ("01_shape_matching", "optimal_orthogonal", TRANSPOSED_ORTHOGONAL, ("transpose",)),
        ("02_sign_correction", "optimal_rotation", LARGEST_FLIPPED, ("smallest singular value",)),
    ],
    ids=["02 transposed rotation", "01 transposed orthogonal map", "02 flipped the largest singular value"],
)
def test_a_common_mistake_gets_a_hint_that_names_it(notebook, function, source, words):
    message = public_test_failure(notebook, function, source)
    assert message, f"the public tests of {function} pass with the mistake"
    for word in words:
        assert word in message, f"the hint does not say {word!r}: {message}"


@pytest.mark.parametrize(
    "entry, function, words",
    [
        ("boundary_directed_half_edges", "boundary_loop_count", ("oriented alike",)),
        ("biharmonic_without_mass", "biharmonic_matrix", ("M⁻¹ is missing",)),
        ("dqs_without_pivot_flip", "dqs", ("the long way", "flip the dual quaternions")),
        ("energy_unit_weights", "arap_energy", ("without the weights",)),
        ("fast_clusters_empty_never_refilled", "rotation_clusters", ("refill a cluster that ends up empty",)),
        ("fast_clusters_single_assignment", "rotation_clusters", ("until no label changes",)),
        # the bug is in fast_precompute, whose data only fast_energy's tests can read
        ("fast_precompute_without_factor_3", "fast_energy", ("Q = 3 Aᵀ(-L)A",)),
        ("fast_rotations_vertex_average", "fast_rotations", ("not the cluster's best rotation",)),
        ("fast_solve_keeps_t0_fixed_rows", "fast_solve", ("before the first local step",)),
        ("fast_global_step_translations_only", "fast_global_step", ("not only their translations",)),
        ("fast_step_rotations_transposed", "fast_global_step", ("transposed rotations",)),
        ("global_step_soft_handles", "arap_global_step", ("must equal handle_positions exactly",)),
        ("tet_mass_signed_volumes", "tet_mass_matrix", ("use |vol|",)),
        ("tet_biharmonic_without_mass", "tet_biharmonic_matrix", ("M⁻¹ is missing",)),
        ("tet_global_step_rotations_transposed", "tet_arap_global_step", ("not its transpose",)),
        # the bug is in the precomputation, whose data the global step's tests use
        ("tet_global_step_signed_volumes", "tet_arap_global_step", ("weight B by |vol_t|",)),
        ("sign_from_det_of_s", "optimal_rotation", ("det(S) = 0 says nothing",)),
        ("handle_columns_reversed", "handle_constraints", ("reverse order",)),
        ("idw_power_ignored", "inverse_distance_weights", ("power 1",)),
        ("laplacian_diagonal_sign", "cotangent_laplacian", ("diagonal has the wrong sign",)),
        ("laplacian_editing_uniform", "laplacian_editing", ("not the uniform graph Laplacian",)),
        ("lbs_matrix_one_first", "lbs_matrix", ("the 1 goes last",)),
        ("precompute_handles_deduplicated", "arap_precompute", ("np.unique would also sort",)),
    ],
)
def test_a_buggy_corpus_entry_gets_a_hint_that_names_its_mistake(entry, function, words):
    bug = load_entry(BUGGY / f"{entry}.py")
    message = public_failures(bug.notebook, bug.solutions, {function})[function]
    assert message, f"{entry}: the public tests of {function} pass with the mistake"
    for word in words:
        assert word in message, f"{entry}: the hint of {function} does not say {word!r}: {message}"
