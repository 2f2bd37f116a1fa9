"""How the deformation course's reference reaches its callees, for the engine's reruns (``grader.checks.callees``).

``BATCHED``, ``ALIASES`` and ``COMPOSITIONS`` are read by the engine from this
package's ``__init__``: which callees are matched item by item, which private
reference functions stand for a graded one, and the callers the reference
computes inline, written as their contracts define them in terms of their callees.
"""

from __future__ import annotations

from typing import Callable

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from grader.checks.callees import pure

#: Functions called on a stack of independent items (leading axes): recorded whole and matched item by item,
#: so a student who calls them once per vertex is matched as well as one who calls them on the stack.
#: name -> (the argument holding the items, the number of trailing axes of one item)
BATCHED: dict[str, tuple[str, int]] = {"optimal_rotation": ("S", 2)}

#: Private reference functions that compute a contract function on input already checked, called
#: inside the reference in its place: a substitution of the contract function applies to them too.
ALIASES: dict[str, str] = {
    "_biharmonic_matrix": "biharmonic_matrix",
    "tet_volumes_unchecked": "tet_volumes",
    "_tet_cotangent_laplacian": "tet_cotangent_laplacian",
    "_tet_mass_matrix": "tet_mass_matrix",
}


def _arap_solve(f, data, handle_positions, U0=None, iterations=10):
    """``arap_solve`` as its contract defines it: local step, global step, energy, ``iterations`` times."""
    V, F, C = data.V, data.F, data.C
    U = np.array(V if U0 is None else U0, dtype=float)
    U[data.handles] = handle_positions
    energies = []
    for _ in range(int(iterations)):
        R = f.arap_rotations(V, U, F, C)
        U = f.arap_global_step(data, R, handle_positions)
        energies.append(f.arap_energy(V, U, F, C, R))
    return U, np.array(energies, dtype=float)


class _LU:
    """The LU factors of a square sparse matrix, with the ``solve`` and ``solve_into`` of the reference's Cholesky factor.

    A student's Laplacian may be indefinite (a sign error), which Cholesky refuses; the student's
    own code factored it, so the rerun does too.
    """

    def __init__(self, A):
        self._lu = spla.splu(sp.csc_matrix(A))

    def solve(self, b):
        return self._lu.solve(np.asarray(b, dtype=float))

    def solve_into(self, b, x):
        x[...] = self.solve(b)


def _arap_precompute(f, V, F, handles):
    """``arap_precompute`` from the course's weights and Laplacian (the student's, in a rerun)."""
    from reference import arap

    checked = pure(arap.arap_precompute, (V, F, handles), {})  # the reference's own checks of the input
    C = np.asarray(f.cotangent_weights(V, F), dtype=float)
    L = sp.csr_matrix(f.cotangent_laplacian(V, F), dtype=float)
    return arap._precomputed(checked.V, checked.F, checked.handles, C, L, factor=_LU)


def _dqs(f, V, W, T):
    """``dqs``: blend the handles' dual quaternions (handle 0 the pivot), one rigid motion per vertex."""
    V, W = np.asarray(V, dtype=float), np.asarray(W, dtype=float)
    Q = np.array(f.dual_quaternions(T), dtype=float)
    Q[Q[:, 0] @ Q[0, 0] < 0] *= -1.0
    blends = (W @ Q.reshape(len(Q), 8)).reshape(len(V), 2, 4)
    motions = np.asarray(f.dual_quaternion_transforms(blends), dtype=float)
    return np.einsum("iab,ib->ia", motions[:, :, :3], V) + motions[:, :, 3]


def _tet_biharmonic_matrix(f, V, T):
    """``tet_biharmonic_matrix``: ``L M⁻¹ L`` from the course's Laplacian and mass matrix."""
    L = sp.csr_matrix(f.tet_cotangent_laplacian(V, T), dtype=float)
    M = sp.csr_matrix(f.tet_mass_matrix(V, T), dtype=float)
    return (L @ sp.diags(1.0 / M.diagonal()) @ L).tocsr()


def _tet_arap_precompute(f, V, T, handles):
    """``tet_arap_precompute`` with the course's Laplacian and volumes in place of the reference's own."""
    from reference import tetrahedra

    data = pure(tetrahedra.tet_arap_precompute, (V, T, handles), {})
    L = sp.csr_matrix(f.tet_cotangent_laplacian(V, T), dtype=float)
    data.volumes = np.abs(np.asarray(f.tet_volumes(V, T), dtype=float))
    data.L = L
    L_free = L[data.free]
    data.L_free_handles = L_free[:, data.handles].tocsr()
    if data.free.size:
        data.solver = _LU(-L_free[:, data.free])
    return data


#: caller -> (its definition in terms of the course functions it calls, those functions)
COMPOSITIONS: dict[str, tuple[Callable, tuple[str, ...]]] = {
    "arap_precompute": (_arap_precompute, ("cotangent_weights", "cotangent_laplacian")),
    "arap_solve": (_arap_solve, ("arap_rotations", "arap_global_step", "arap_energy")),
    "dqs": (_dqs, ("dual_quaternions", "dual_quaternion_transforms")),
    "tet_biharmonic_matrix": (_tet_biharmonic_matrix, ("tet_cotangent_laplacian", "tet_mass_matrix")),
    "tet_arap_precompute": (_tet_arap_precompute, ("tet_cotangent_laplacian", "tet_volumes")),
}
