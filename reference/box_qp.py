"""Convex quadratic programs on the unit box: ``min ½ xᵀ H x - gᵀ x`` s.t. ``0 ≤ x ≤ 1``."""

import numpy as np
import scipy
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from starter.validation import as_float_array

# ADMM's penalty ρ relative to √(λ_min λ_max) of H, its over-relaxation and
# its number of steps (see _admm_active_sets). Worst / geometric-mean CPU
# ratio to igl.bbw on the BBW benchmark family with 20, 30, 40, 60 steps:
# 0.88 / 0.47, 0.93 / 0.47, 0.79 / 0.44, 0.85 / 0.42 (the tetrahedral hand
# wants fewer, the character with bones more); penalty 0.05: 1.05 / 0.47.
# The previous start (out-of-box regions shrunk by 6 rings): 1.12 / 0.65.
ADMM_PENALTY = 0.02
ADMM_RELAXATION = 1.6
ADMM_STEPS = 40

# SymmetricMode with diagonal pivots: H is symmetric positive definite, and
# SuperLU factors it far faster this way than with partial pivoting
SYMMETRIC = {"diag_pivot_thresh": 0.0, "options": {"SymmetricMode": True}}


def box_qp(H, G, tol=1e-9):
    """Minimize ``½ xᵀ H x - gᵀ x`` subject to ``0 ≤ x ≤ 1``, for each column ``g`` of ``G``.

    Parameters
    ----------
    H : (n, n) sparse matrix or array_like of float
        Symmetric positive definite.
    G : (n,) or (n, m) array_like of float
        The linear terms: one problem per column.
    tol : float, optional
        KKT tolerance relative to ``max_i Σ_j |H_ij|``: the returned ``x`` is
        feasible and its projected gradient (``H x - g`` with the part that
        pushes against an active bound removed) is at most ``tol`` times that
        scale, in every entry.

    Returns
    -------
    X : numpy.ndarray, the shape of ``G``
        The minimizers, ``0 ≤ X ≤ 1`` exactly.

    Raises
    ------
    ValueError
        On malformed input, or if ``H`` is not positive definite.
    RuntimeError
        If the active-set solver does not converge (it should not happen: the
        problem is strictly convex, and the solver falls back to Murty's rule,
        which cannot cycle).

    Notes
    -----
    Primal-dual active sets (Hintermüller, Ito and Kunisch 2002), started from
    the bounds that the unconstrained minimizer ``H⁻¹ g`` breaks. When those
    vertices are few (a set C), ordering C last in one sparse factorization of
    ``H`` gives the Schur complement K of ``H`` onto C, and every step is a
    small dense solve on C; if the solution then leaves the box outside C, C
    grows and the solve repeats. When C is large, the iterations start from
    the bounds that a few ADMM steps touch (Boyd et al. 2011, one
    factorization of ``H + ρI`` for all columns), every step
    factors the free block of ``H`` in the fill-reducing order of ``H``,
    computed once, and the iterations stop as soon as the KKT conditions hold
    to ``tol``: the last steps of an exact active-set solver only move
    variables within 1e-7 of a bound.
    """
    if sp.issparse(H):
        H = sp.csc_matrix(H, dtype=np.float64)
        if not np.isfinite(H.data).all():
            raise ValueError("H contains NaN or inf")
    else:
        H = sp.csc_matrix(as_float_array(H, "H", ndim=2))
    if H.shape[0] != H.shape[1] or H.shape[0] == 0:
        raise ValueError(f"H must be a non-empty square matrix, got shape {H.shape}")
    G = as_float_array(G, "G")
    if G.ndim not in (1, 2) or G.shape[0] != H.shape[0]:
        raise ValueError(f"G must have shape ({H.shape[0]},) or ({H.shape[0]}, m) to match H, got {G.shape}")
    tol = float(as_float_array(tol, "tol", ndim=0))
    if not tol > 0:
        raise ValueError(f"tol must be positive, got {tol}")
    asymmetry = abs(H - H.T).max() if H.nnz else 0.0
    if asymmetry > 1e-12 * abs(H).max():
        raise ValueError(f"H must be symmetric, max |H - Hᵀ| is {asymmetry:.3g}")
    X = _solve(H, G.reshape(len(G), -1), tol)
    return X.reshape(G.shape)


def _factor(A, permc_spec):
    try:
        return spla.splu(A, permc_spec=permc_spec, **SYMMETRIC)
    except RuntimeError as error:  # SuperLU: "Factor is exactly singular"
        raise ValueError(f"H must be positive definite: its factorization failed ({error})") from None


def _solve(H, G, tol):
    n, m = G.shape
    tol_x = 1e-11
    lu = _factor(H, "MMD_AT_PLUS_A")
    # without pivoting SuperLU factors any nonsingular symmetric matrix:
    # an indefinite H shows as a negative pivot
    if (lu.U.diagonal() <= 0).any():
        raise ValueError("H must be positive definite: its factorization has a non-positive pivot")
    scale = float(abs(H).sum(axis=1).max())
    # about the flops of one sparse factorization of H (Σ column count²)
    sparse_flops = float((np.diff(lu.L.indptr).astype(np.float64) ** 2).sum())
    X_unconstrained = lu.solve(G)
    X = X_unconstrained
    # at_lower[i, j]: x_i = 0 in problem j; at_upper[i, j]: x_i = 1
    at_lower = np.zeros_like(X, dtype=bool)
    at_upper = np.zeros_like(X, dtype=bool)
    C = np.zeros(n, dtype=bool)
    while True:
        at_lower |= X < -tol_x
        at_upper |= X > 1 + tol_x
        grown = C | at_lower.any(axis=1) | at_upper.any(axis=1)
        if np.array_equal(grown, C):
            return np.clip(X, 0.0, 1.0)
        # a dense step costs up to |C|³/3 flops but runs them ~30x faster
        # than SuperLU: go dense when that beats a sparse factorization
        if float(grown.sum()) ** 3 >= 100 * sparse_flops:
            at_lower, at_upper = _admm_active_sets(H, G, X_unconstrained, lu, scale)
            # every free block keeps lu's fill-reducing order (lu.perm_c[i] is
            # the position of variable i): a good order for the block too, so
            # SuperLU skips its own ordering; H is permuted once
            order = np.argsort(lu.perm_c)
            H_ordered = H[order][:, order].tocsc()
            H_ordered.sort_indices()
            columns = np.repeat(np.arange(n), np.diff(H_ordered.indptr))
            X = np.empty((n, m))
            for j in range(m):
                X[order, j] = _sparse_active_set(
                    H_ordered, columns, G[order, j], at_lower[order, j], at_upper[order, j], tol * scale,
                )
            return X
        # Order C last, the rest in lu's fill-reducing order (lu.perm_c[i] is
        # the position of variable i): the trailing block of the factor is
        # then the Schur complement K of H onto C.
        order = np.argsort(lu.perm_c + n * grown, kind="stable")
        lu_c = _factor(H[order][:, order].tocsc(), "NATURAL")
        # SuperLU postorders its elimination tree, which can move a few other
        # variables behind C: take the whole trailing block
        tail = n - int(lu_c.perm_c[np.argsort(order)[grown]].min())
        trailing = order[np.argsort(lu_c.perm_c)[-tail:]]
        K = lu_c.L[-tail:, -tail:].toarray() @ lu_c.U[-tail:, -tail:].toarray()
        K = 0.5 * (K + K.T)
        K_inverse = scipy.linalg.cho_solve(
            scipy.linalg.cho_factor(K, check_finite=False), np.eye(len(K)), check_finite=False,
        )
        C[trailing] = True
        # with the other variables eliminated, the energy on C is
        # ½ (y - x0)ᵀ K (y - x0), x0 the unconstrained minimizer there; its
        # multipliers are the gradient of the full energy
        multipliers = np.zeros((n, m))
        for j in range(m):
            nu, lower, upper = _dense_active_set(
                K, K_inverse, X_unconstrained[trailing, j], at_lower[trailing, j], at_upper[trailing, j],
            )
            multipliers[trailing, j] = nu
            at_lower[:, j] = False
            at_upper[:, j] = False
            at_lower[trailing[lower], j] = True
            at_upper[trailing[upper], j] = True
        X = lu.solve(G + multipliers)
        X[at_lower] = 0.0
        X[at_upper] = 1.0


def _admm_active_sets(H, G, X_unconstrained, lu, scale):
    """Predict the active sets of every column with a few ADMM steps.

    ADMM on the splitting ``x = z``, ``z`` in the box: each step is one solve
    with ``H + ρI``, factored once for all columns, then a clip. Its iterate
    is not accurate, but the bounds it touches are close to the final active
    sets, which PDAS started from the unconstrained minimizer's out-of-box
    regions reaches only a stencil ring per step. ``G`` and
    ``X_unconstrained`` are ``(n, m)``, ``lu`` factors ``H`` and ``scale``
    bounds its largest eigenvalue; returns ``(at_lower, at_upper)``, ``(n,
    m)`` bool.
    """
    n = H.shape[0]
    # √(λ_min λ_max) is ADMM's optimal penalty on strongly convex quadratics
    # (Ghadimi et al. 2015), and scaling by it suits triangles and tetrahedra
    # alike. Only the bounds matter here, and a fraction of it finds them in
    # fewer steps: on the family's square after 50 unrelaxed steps, ρ ≈ 0.6
    # √(λ_min λ_max) left 42 active-set factorizations, ρ ≈ 0.06 √(λ_min
    # λ_max) 26 (and see ADMM_PENALTY).
    # A few inverse iterations estimate λ_min.
    v = np.linspace(1.0, 2.0, n)
    for _ in range(6):
        v = lu.solve(v)
        v /= np.linalg.norm(v)
    rho = ADMM_PENALTY * float(np.sqrt(max(v @ (H @ v), 0.0) * scale))
    lu = _factor((H + rho * sp.identity(n, format="csc")).tocsc(), "MMD_AT_PLUS_A")
    Z = np.clip(X_unconstrained, 0.0, 1.0)
    U = X_unconstrained - Z
    for _ in range(ADMM_STEPS):
        X = ADMM_RELAXATION * lu.solve(G + rho * (Z - U)) + (1.0 - ADMM_RELAXATION) * Z
        Z = np.clip(X + U, 0.0, 1.0)
        U += X - Z
    return Z <= 0.0, Z >= 1.0


def _next_active_sets(lower, upper, below, above, release, seen, murty):
    """One pivoting step: move every infeasible variable across, or only the last one (Murty's rule).

    Block moves usually converge in a few dozen steps but can cycle: once an
    active set repeats, only the last infeasible variable moves, which cannot
    cycle. Returns ``(lower, upper, murty)``.
    """
    infeasible = below | above | release
    state = (lower.tobytes(), upper.tobytes())
    murty = murty or state in seen
    seen.add(state)
    if murty:
        infeasible = np.zeros_like(infeasible)
        infeasible[np.flatnonzero(below | above | release)[-1]] = True
    lower = (lower & ~(infeasible & release)) | (infeasible & below)
    upper = (upper & ~(infeasible & release)) | (infeasible & above)
    return lower, upper, murty


def _dense_active_set(K, K_inverse, x0, lower, upper):
    """Minimize ``½ (y - x0)ᵀ K (y - x0)`` over ``0 ≤ y ≤ 1`` exactly; ``K`` dense SPD ``(k, k)``.

    ``x0`` is ``(k,)``; ``lower`` and ``upper`` are ``(k,)`` bool, the initial
    active sets (``y = 0``, ``y = 1``). Each step solves the equality problem
    on the smaller side: the free block of ``K`` or the active block of ``K⁻¹``.

    Returns ``(nu, lower, upper)``: the multipliers ``K (y - x0)`` (zero on
    the free variables) and the final active sets.
    """
    tol_x = 1e-11
    tol_nu = 1e-12 * abs(K).max()
    max_iter = 100 + 5 * len(x0)
    seen, murty = set(), False
    for _ in range(max_iter):
        active = np.flatnonzero(lower | upper)
        inactive = np.flatnonzero(~(lower | upper))
        y = upper.astype(np.float64)
        nu = np.zeros_like(y)
        if active.size < inactive.size:
            # y = x0 + K⁻¹[:, A] nu_A with y_A fixed
            factor = scipy.linalg.cho_factor(K_inverse[np.ix_(active, active)], check_finite=False)
            nu[active] = scipy.linalg.cho_solve(factor, y[active] - x0[active], check_finite=False)
            y[inactive] = x0[inactive] + K_inverse[np.ix_(inactive, active)] @ nu[active]
        else:
            if inactive.size:
                coupling = K[np.ix_(inactive, active)] @ (y[active] - x0[active])
                factor = scipy.linalg.cho_factor(K[np.ix_(inactive, inactive)], check_finite=False)
                y[inactive] = x0[inactive] - scipy.linalg.cho_solve(factor, coupling, check_finite=False)
            nu[active] = K[active] @ (y - x0)
        below = ~(lower | upper) & (y < -tol_x)
        above = ~(lower | upper) & (y > 1 + tol_x)
        release = (lower & (nu < -tol_nu)) | (upper & (nu > tol_nu))
        if not (below | above | release).any():
            return nu, lower, upper
        lower, upper, murty = _next_active_sets(lower, upper, below, above, release, seen, murty)
    raise RuntimeError(
        f"box_qp: the active-set solver did not converge in {max_iter} iterations "
        f"({int((below | above | release).sum())} of {len(x0)} variables still infeasible)"
    )


def _principal_submatrix(A, columns, keep):
    """``A[keep][:, keep]`` for ``A`` CSC with sorted indices, its indices sorted too (no sort needed).

    ``columns`` ``(nnz,)`` is the column of each stored entry of ``A``;
    ``keep`` is ``(n,)`` bool.
    """
    entries = keep[A.indices] & keep[columns]
    renumber = np.cumsum(keep) - 1
    k = int(renumber[-1]) + 1
    indptr = np.zeros(k + 1, dtype=np.int64)
    np.cumsum(np.bincount(renumber[columns[entries]], minlength=k), out=indptr[1:])
    return sp.csc_matrix((A.data[entries], renumber[A.indices[entries]], indptr), shape=(k, k))


def _sparse_active_set(H, columns, g, lower, upper, tol_kkt):
    """Minimize ``½ xᵀ H x - gᵀ x`` over ``0 ≤ x ≤ 1`` to KKT residual ``tol_kkt``; ``H`` sparse SPD.

    ``H`` is CSC with sorted indices, its variables in a fill-reducing order
    that every free block keeps, and ``columns`` the column of each of its
    stored entries (see ``_principal_submatrix``); ``lower`` and ``upper``
    are ``(n,)`` bool, the initial active sets.

    Returns ``x`` ``(n,)``, in the box exactly.
    """
    n = len(g)
    max_iter = 100 + 5 * n
    seen, murty = set(), False
    for _ in range(max_iter):
        free = ~(lower | upper)
        x = upper.astype(np.float64)
        if free.any():
            # H[free, upper] 1 is (H 1_upper)[free]
            rhs = (g - H @ x)[free]
            x[free] = _factor(_principal_submatrix(H, columns, free), "NATURAL").solve(rhs)
        gradient = H @ x - g
        below = free & (x < 0)
        above = free & (x > 1)
        release = (lower & (gradient < 0)) | (upper & (gradient > 0))
        if not (below | above | release).any():
            return x  # the exact minimizer
        clipped = np.clip(x, 0.0, 1.0)
        if below.any() or above.any():
            gradient = H @ clipped - g
        # the projected gradient: what remains after the bounds push back
        residual = np.where(clipped <= 0, np.minimum(gradient, 0.0), np.where(clipped >= 1, np.maximum(gradient, 0.0), gradient))
        if np.abs(residual).max() <= tol_kkt:
            return clipped
        lower, upper, murty = _next_active_sets(lower, upper, below, above, release, seen, murty)
    raise RuntimeError(
        f"box_qp: the active-set solver did not converge in {max_iter} iterations "
        f"(KKT residual {np.abs(residual).max():.3g}, tolerance {tol_kkt:.3g})"
    )
