"""Audit: does every buggy corpus entry make its notebook's PUBLIC tests name the mistake?

For each ``tests/corpus/buggy/*.py`` entry, the notebook's cells run as a student
runs them (provided cells that need no student function, the solution cells with
the entry's bug, the public tests cells without their hidden section), and the
first failing assertion of the tests cell of every function the entry changes or
loses is compared with ``HINTS``: the words a student with that bug must read in
one of them. Each entry
runs in its own process with a time limit (some bugs make a solver crawl).

Run ``.venv/bin/python -m tests.grader.public_hints_audit [ENTRY ...]``; it prints
one line per entry (the tests cell whose message holds the hint, or the first that fails)
and exits 1 if a hint is missing.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from grader.build.authored import read_authored
from grader.build.source_notebook import with_policy_check
from tests.corpus import load_entry
from grader.course_pack import pack
from grader.pipeline.sanitize import _calls_contract_at_top_level

CONTRACT_NAMES = pack("deformation").function_names

ROOT = Path(__file__).resolve().parents[2]
NOTEBOOKS = ROOT / "notebooks" / "deformation"
BUGGY = ROOT / "tests" / "corpus" / "buggy"
TIMEOUT = 300

#: entry -> words its public tests' message must contain (one of each tuple); every buggy entry has one
#: (tests/grader/test_public_hints.py).
HINTS: dict[str, tuple[tuple[str, ...], ...]] = {
    "arap_rotations_transposed": (("you return Qᵀ",),),
    "bbw_active_set_never_releases": (("release a held value",),),
    "bbw_clip_unconstrained": (("clipping is feasible but not optimal",),),
    "bbw_no_upper_bound": (("0 ≤ w ≤ 1",),),
    "bbw_not_normalized": (("normalize",),),
    "biharmonic_without_mass": (("M⁻¹ is missing",),),
    "boundary_directed_half_edges": (("oriented alike",),),
    "boundary_edges_not_loops": (("count the loops",),),
    "cascade_centroid_in_rigid_align": (("the weights are ignored",),),
    "cascade_cot_not_halved_in_bbw": (("that is cot, not ½cot",),),
    "cascade_cot_not_halved_in_03b": (("that is cot, not ½cot",),),
    "cascade_cot_not_halved_in_fast": (("that is cot, not ½cot",),),
    "cascade_energy_unit_weights_in_03b": (("without the weights",),),
    "cascade_covariance_in_rigid_align": (("subtract the centroids",),),
    "cascade_laplacian_sign_in_03b": (("the diagonal has the wrong sign",),),
    "cascade_laplacian_sign_in_bbw": (("the diagonal has the wrong sign",),),
    "cascade_laplacian_sign_in_fast": (("the diagonal has the wrong sign",),),
    "cascade_lbs_matrix_in_fast": (("the weight enters once",),),
    "cascade_sign_from_det_in_arap": (("det(S) = 0 says nothing",),),
    "cascade_rotations_transposed_in_03b": (("you return Qᵀ",),),
    "cascade_sign_from_det_in_fast": (("det(S) = 0 says nothing",),),
    "centroid_ignores_weights": (("weights are ignored",),),
    "cot_not_halved": (("not ½cot",),),
    "cot_signed_area": (("|a × b|",),),
    "cotangents_clamped": (("negative weight",),),
    "covariance_edges_swapped": (("instead of Σ c e e'ᵀ",),),
    "covariance_not_centred": (("subtract the centroids",),),
    "covariance_spokes_only": (("all three of its edges",),),
    "deformation_gradients_transposed": (("transposed",),),
    "dqs_blends_matrices": (("linear blend skinning",),),
    "dqs_without_pivot_flip": (("flip the dual quaternions",),),
    "dual_quaternion_transforms_rotation_transposed": (("transposed",),),
    "dual_quaternions_accepts_non_rotation": (("raise a ValueError naming T[1]",),),
    "dual_quaternions_divide_by_w": (("w = 0",),),
    "edges_as_floats": (("integer",),),
    "edges_not_deduplicated": (("remove duplicates",),),
    "energy_unit_weights": (("without the weights",),),
    "euler_characteristic_signs_swapped": (("the signs are swapped",),),
    "fast_clusters_empty_never_refilled": (("refill a cluster",),),
    "fast_clusters_single_assignment": (("until no label changes",),),
    "fast_energy_without_constant": (("Q, P and constant",),),
    "fast_global_step_translations_only": (("not only their translations",),),
    "fast_precompute_without_definiteness_check": (("positive definite",),),
    "fast_precompute_without_factor_3": (("Q = 3 Aᵀ(-L)A",),),
    "fast_rotations_vertex_average": (("not the cluster's best rotation",),),
    "fast_solve_energy_before_global": (("rotations of iteration k's local step",),),
    "fast_solve_keeps_t0_fixed_rows": (("before the first local step",),),
    "fast_step_rotations_transposed": (("transposed rotations",),),
    "genus_ignores_components": (("connected component",),),
    "global_step_soft_handles": (("must equal handle_positions exactly",),),
    "global_step_spokes_rhs": (("mean rotation of each triangle",),),
    "handle_columns_reversed": (("reverse order",),),
    "idw_power_ignored": (("power 1",),),
    "laplacian_diagonal_sign": (("diagonal has the wrong sign",),),
    "laplacian_editing_uniform": (("not the uniform graph Laplacian",),),
    "lbs_ignores_translation": (("t_j = T[j, :, d]",),),
    "lbs_matrix_one_first": (("the 1 goes last",),),
    "lbs_matrix_coordinate_major": (("handle by handle",),),
    "lbs_matrix_weights_squared": (("the weight enters once",),),
    "no_sign_correction": (("correct the sign",),),
    "orthogonal_transposed": (("transpose",),),
    "precompute_handles_deduplicated": (("np.unique would also sort",),),
    "rotation_transposed_in_arap": (("transposed",),),
    "sign_flip_largest": (("smallest singular value",),),
    "sign_from_det_of_s": (("det(S) = 0 says nothing",),),
    "sign_from_det_of_s_zero_as_positive": (("det(S) = 0 says nothing",), ("which is -1 here",)),
    "solve_energy_before_global": (("rotations the global step used",),),
    "solve_keeps_u0_handles": (("before the first local step",),),
    "tet_arap_precompute_accepts_bad_handles": (("must raise ValueError",),),
    "k_harmonic_precompute_sorts_handles": (("np.unique would also sort",),),
    "k_harmonic_operator_without_mass": (("M⁻¹ is missing",),),
    "k_harmonic_operator_sign": (("the sign",),),
    "k_harmonic_operator_k_off_by_one": (("off by one",),),
    "k_harmonic_solve_rhs_sign": (("wrong sign",),),
    "k_harmonic_solve_handles_ignored": (("right-hand side",),),
    "k_harmonic_precompute_accepts_bad_handles": (("expected a ValueError",),),
    "tet_biharmonic_without_mass": (("M⁻¹ is missing",),),
    "tet_energy_unweighted": (("per unit volume",),),
    "tet_global_step_rotations_transposed": (("not its transpose",),),
    "tet_global_step_signed_volumes": (("weight B by |vol_t|",),),
    "tet_laplacian_stiffness_sign": (("signs are flipped",),),
    "tet_mass_signed_volumes": (("use |vol|",),),
    "tet_rotations_no_sign_correction": (("flip the singular vector",),),
    "tet_volumes_unsigned": (("keep the sign",),),
    "translation_between_centroids": (("q̄ - R p̄",),),
}


# a library-policy entry's hint is the policy's own message (starter.library_policy.message)
HINTS.update({path.stem: (("LIBRARY_POLICY.md",),) for path in BUGGY.glob("policy_*.py")})


def public_failures(notebook: str, solutions: dict[str, str], functions: set[str]) -> dict[str, str]:
    """First failing public assertion of each of ``functions``' tests cells ("" if it passes).

    ``solutions`` replaces those functions' solution cells; the other cells are the notebook's own.
    Every tests cell runs, in order, as the student runs them (a later one may read an earlier one's names).
    """
    os.environ["DEFORMLAB_NO_PLOTS"] = "1"
    from starter import library_policy

    library_policy.install()  # as the notebook's provided cell does, before any solution cell
    namespace: dict = {}
    found: dict[str, str] = {}
    for cell in read_authored(NOTEBOOKS / f"{notebook}.py").cells:
        if cell.kind == "provided" and not _calls_contract_at_top_level(cell.source, CONTRACT_NAMES):
            exec(compile(cell.source, notebook, "exec"), namespace)
        elif cell.kind == "solution":
            exec(compile(solutions.get(cell.function, cell.source), notebook, "exec"), namespace)
        elif cell.kind == "tests":
            try:  # as built: between the library policy's watch and verdict
                exec(compile(with_policy_check(cell.function, cell.source), notebook, "exec"), namespace)
                message = ""
            except Exception as exc:  # noqa: BLE001 - a crash is what the student sees too
                message = str(exc) if isinstance(exc, AssertionError) else f"{type(exc).__name__}: {exc}"
            if cell.function in functions:
                found[cell.function] = message
                if set(found) >= set(functions):
                    break
    return found


def hinted(name: str, messages: dict[str, str]) -> list[str]:
    """The functions whose first failing public assertion holds entry ``name``'s ``HINTS``."""
    words = HINTS.get(name)
    return [f for f, m in messages.items() if m and words and all(any(w in m for w in group) for group in words)]


def _audit_one(path: Path) -> dict:
    entry = load_entry(path)
    return public_failures(entry.notebook, entry.solutions, set(entry.solutions) | set(entry.loses))


def main(argv: list[str]) -> int:
    if argv[:1] == ["--one"]:
        print(json.dumps(_audit_one(Path(argv[1]))))
        return 0
    paths = [BUGGY / f"{name}.py" for name in argv] or sorted(BUGGY.glob("*.py"))
    missing = 0
    for path in paths:
        entry = load_entry(path)
        try:
            run = subprocess.run([sys.executable, "-m", "tests.grader.public_hints_audit", "--one", str(path)],
                                 cwd=ROOT, capture_output=True, text=True, timeout=TIMEOUT)
            messages = json.loads(run.stdout.strip().splitlines()[-1]) if run.returncode == 0 else None
        except subprocess.TimeoutExpired:
            messages, run = None, None
        if messages is None:
            why = "timed out" if run is None else f"crashed: {run.stderr.strip().splitlines()[-1:]}"
            print(f"{entry.name:<42} ?       {why}")
            missing += 1
            continue
        failed = {f: m for f, m in messages.items() if m}
        found = hinted(entry.name, messages)
        missing += not found
        status = "ok" if found else ("PASSES" if not failed else "NO HINT")
        function = found[0] if found else next(iter(failed), ", ".join(entry.solutions))
        print(f"{entry.name:<42} {status:<7} {function}: {failed.get(function, '')[:300]!r}")
    print(f"{len(paths)} entries, {missing} without a hint")
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
