"""The hidden reference solution: every function of the student contract (and of the bonus and lecture ones).

One module per stage; every contract function is importable from the package
itself, e.g. ``from reference import arap_solve``. Never shipped to students,
never visible inside the grading sandbox.
"""

from reference.meshes import boundary_loop_count, edges, euler_characteristic, genus
from reference.shape_matching import centroid, covariance_matrix, optimal_orthogonal, orthogonal_align
from reference.sign_correction import optimal_rotation, rigid_align
from reference.k_harmonic import k_harmonic_operator, k_harmonic_precompute, k_harmonic_solve
from reference.arap import (
    arap_covariances,
    arap_energy,
    arap_global_step,
    arap_precompute,
    arap_rotations,
    arap_solve,
    cotangent_laplacian,
    cotangent_weights,
    laplacian_editing,
)
from reference.bounded_biharmonic_weights import (
    bbw,
    biharmonic_matrix,
    handle_constraints,
    inverse_distance_weights,
    unconstrained_biharmonic_weights,
)
from reference.linear_blend_skinning import lbs, lbs_matrix
from reference.dual_quaternion_skinning import dqs, dual_quaternion_transforms, dual_quaternions
from reference.tetrahedra import (
    deformation_gradients,
    tet_cotangent_laplacian,
    tet_cotangent_weights,
    tet_mass_matrix,
    tet_biharmonic_matrix,
    tet_volumes,
    tet_arap_energy,
    tet_arap_global_step,
    tet_arap_precompute,
    tet_arap_rotations,
    tet_arap_solve,
)
from reference.fast import (
    fast_energy,
    fast_global_step,
    fast_precompute,
    fast_rotations,
    fast_solve,
    rotation_clusters,
)

__all__ = [
    "edges", "euler_characteristic", "boundary_loop_count", "genus",
    "centroid", "covariance_matrix", "optimal_orthogonal", "orthogonal_align",
    "optimal_rotation", "rigid_align",
    "cotangent_weights", "cotangent_laplacian", "arap_covariances", "arap_rotations", "arap_energy",
    "arap_precompute", "arap_global_step", "arap_solve", "laplacian_editing",
    "biharmonic_matrix", "handle_constraints", "inverse_distance_weights",
    "unconstrained_biharmonic_weights", "bbw",
    "lbs_matrix", "lbs",
    "dual_quaternions", "dual_quaternion_transforms", "dqs",
    "tet_volumes", "tet_cotangent_weights", "tet_cotangent_laplacian", "tet_mass_matrix",
    "tet_biharmonic_matrix",
    "deformation_gradients", "tet_arap_rotations", "tet_arap_energy", "tet_arap_precompute",
    "tet_arap_global_step", "tet_arap_solve",
    "rotation_clusters", "fast_precompute", "fast_energy", "fast_rotations", "fast_global_step", "fast_solve",
]
