"""The student contract as data: which function belongs to which stage.

The names and their stage are the interface shared by students, ``reference/`` and the
grader. Stages 00–05 are ``shared/CONTRACT.md``; the bonus stage 06 is
``BONUS_CONTRACT.md``; ``LECTURE_CONTRACT.md`` adds the project's own functions to
stages. ``tests/grader/test_contract.py`` checks these tables against the three files.
"""

from __future__ import annotations

ASSIGNMENT = "deformation"

#: stage -> (reference module, contract functions in the order the notebook teaches them)
STAGES: dict[str, tuple[str, tuple[str, ...]]] = {
    "00_meshes": ("meshes", ("edges", "euler_characteristic", "boundary_loop_count", "genus")),
    "01_shape_matching": (
        "shape_matching",
        ("centroid", "covariance_matrix", "optimal_orthogonal", "orthogonal_align"),
    ),
    "02_sign_correction": ("sign_correction", ("optimal_rotation", "rigid_align")),
    "03_arap": (
        "arap",
        (
            "cotangent_weights",
            "cotangent_laplacian",
            "arap_covariances",
            "arap_rotations",
            "arap_energy",
            "arap_precompute",
            "arap_global_step",
            "arap_solve",
            "laplacian_editing",
        ),
    ),
    "04_bbw": (
        "bounded_biharmonic_weights",
        (
            "biharmonic_matrix",
            "handle_constraints",
            "inverse_distance_weights",
            "unconstrained_biharmonic_weights",
            "bbw",
        ),
    ),
    "05_lbs": ("linear_blend_skinning", ("lbs_matrix", "lbs")),
    "06_fast": (
        "fast",
        ("rotation_clusters", "fast_precompute", "fast_energy", "fast_rotations", "fast_global_step", "fast_solve"),
    ),
    # a stage of LECTURE_CONTRACT.md only: its functions are in LECTURE_STAGES
    "07_tetrahedra": ("tetrahedra", ()),
}

#: the functions of ``LECTURE_CONTRACT.md``, taught in a stage after that stage's own:
#: stage -> (reference module, functions in the order the notebook teaches them)
LECTURE_STAGES: dict[str, tuple[str, tuple[str, ...]]] = {
    "05_lbs": ("dual_quaternion_skinning", ("dual_quaternions", "dual_quaternion_transforms", "dqs")),
    "07_tetrahedra": (
        "tetrahedra",
        (
            "tet_volumes",
            "tet_cotangent_laplacian",
            "tet_mass_matrix",
            "deformation_gradients",
            "tet_arap_rotations",
            "tet_arap_energy",
            "tet_arap_precompute",
            "tet_arap_global_step",
            "tet_biharmonic_matrix",
        ),
    ),
}

#: stages whose points are bonus: flagged in grades.csv and Gradescope, outside the regular maximum
BONUS_STAGES: frozenset[str] = frozenset({"06_fast"})

#: every contract function -> its reference module (``reference.<module>``)
MODULE_OF: dict[str, str] = {
    name: module for module, names in (*STAGES.values(), *LECTURE_STAGES.values()) for name in names
}

CONTRACT_NAMES: frozenset[str] = frozenset(MODULE_OF)

#: the functions of ``BONUS_CONTRACT.md`` (the rest are ``shared/CONTRACT.md``'s)
BONUS_NAMES: frozenset[str] = frozenset(n for stage in BONUS_STAGES for n in STAGES[stage][1])

#: the functions of ``LECTURE_CONTRACT.md``
LECTURE_NAMES: frozenset[str] = frozenset(n for _, names in LECTURE_STAGES.values() for n in names)


def stage_functions(notebook: str) -> tuple[str, ...]:
    """The functions ``notebook`` teaches and grades: its ``shared/CONTRACT.md`` (or bonus) ones, then its lecture ones."""
    return STAGES[notebook][1] + LECTURE_STAGES.get(notebook, ("", ()))[1]


def stage_of(function: str) -> str:
    """The stage that teaches and grades ``function``."""
    return next(stage for stage in STAGES if function in stage_functions(stage))


def is_bonus(notebook: str) -> bool:
    """Whether the points of ``notebook`` (a stage name such as ``06_fast``) are bonus points."""
    return notebook in BONUS_STAGES


def reference_function(name: str):
    """Return the reference implementation of contract function ``name``."""
    import importlib

    if name not in MODULE_OF:
        raise ValueError(f"{name!r} is not a contract function")
    return getattr(importlib.import_module(f"reference.{MODULE_OF[name]}"), name)
