"""Convex quadratic programs on the unit box: ``min ½ xᵀ H x - gᵀ x`` s.t. ``0 ≤ x ≤ 1``."""

import functools
import threading

import cvxopt
import numpy as np
import scipy
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from cvxopt import amd, cholmod
from scipy.sparse.csgraph import connected_components, shortest_path
from threadpoolctl import ThreadpoolController

from starter.validation import as_float_array

# The constants below were chosen on the BBW benchmark family (CPU time
# against igl.bbw, worst member / geometric mean, 3 alternating runs each):
# - ADMM's penalty ρ relative to √(λ_min λ_max) of H, its over-relaxation and
#   its number of steps (see _admm_active_sets), with ADMM_NEAR_BOUND 0.3:
#   penalty 0.02 and 40 steps 0.53 / 0.35, 25 steps 0.56 / 0.36; penalty
#   0.01 and 25 steps 0.56 / 0.37, and with ADMM_NEAR_BOUND 0.1 0.50 / 0.35.
#   The tetrahedral hand wants fewer steps, the character with bones more.
# - ADMM_NEAR_BOUND: ADMM's iterate within this fraction of its last step of a
#   bound starts the active-set steps at that bound. An absolute 1e-3 cost
#   the character with regions twice the steps (0.95); 0 cost the hand 18
#   factorizations instead of 9.
# - BORDER_BUDGET: how many variables may border a factored free block
#   (_FreeBlockSolver) before the next block is factored anew, in units of
#   Σ cc² / Σ cc (cc the column counts of the block's factor, whose
#   factorization costs about Σ cc² flops and a solve 4 Σ cc). 0.5: 0.45 /
#   0.33, 0.7: 0.46 / 0.34, 1: 0.47 / 0.34 (the same within this machine's
#   noise); 2: 0.61 / 0.39 (the character with bones pays for the solves); 0
#   (always factor): the hand alone 0.82. Since RELEASE_RANGE (steps that
#   move fewer variables), 0.5 -> 1 took CPU on the family (the order of
#   WIDEN_MAX's figures) -9, -13, -15, -4, -4, 0, +3, +1, -7 %, and in a
#   second sweep the U notch -9, the comb -15, the bones +2, the regions 0,
#   the hand -12 %; 1.5 was no better.
# - WIDEN_MAX: the largest ring (a fraction of a column's free set) by which
#   the predicted free set is widened (_widened). Factorizations, BBW family
#   (square, U notch, comb, holes, bones, regions, L, hexagon, hand), 0 (never
#   widen) -> 0.3: 22 -> 14, 42 -> 34, 81 -> 72, 33 -> 24, 43 -> 30, 28 -> 22,
#   270 -> 230, 0 -> 0, 13 -> 13; CPU -27, -2, -5, -20, -13, -22, -8, 0, 0 %
#   (3 alternating runs, busy machine). The hand's rings are 0.4-1.0 of its
#   free sets: widened anyway (WIDEN_MAX 1.1) it took 29.
# - RELEASE_RANGE: a step releases a bound variable only if its multiplier
#   is wrong by at least this fraction of the worst one. Factorizations on
#   the family as above, 0 -> 0.003: 14 -> 10, 34 -> 24, 72 -> 59, 24 -> 17,
#   30 -> 23, 22 -> 16, 230 -> 172, 0 -> 0, 13 -> 13; CPU -7, -15, -9, -13,
#   0, -23, -10, 0, 0 % (3 alternating runs). 0.0003-0.03 within noise.
# - The free blocks and H + ρI are factored by CHOLMOD's supernodal
#   Cholesky (cvxopt's binding, which bundles OpenBLAS) in the order they
#   keep, with that order alone (nmethods 1: by default CHOLMOD also tries
#   AMD on every block, which tripled its analysis). On the character's
#   6167-variable block: 5.4 ms (1.7 of them the analysis) and 1.6 ms to
#   hand it over, against SuperLU's 15.8-18 ms; cholespy, whose CHOLMOD
#   always orders and runs on reference BLAS, 39.5 ms. box_qp alone against
#   SuperLU blocks: square 0.78, bones 0.81, regions 0.83, hand 0.98; and
#   H + ρI in double precision by CHOLMOD against single by SuperLU: 0.95 to
#   1.02 on the family. With CHOLMOD's cheaper factorizations BORDER_BUDGET
#   0.5 instead of 1: bones 0.98, regions 0.95, L 0.96, others within 1 %
#   (0.3: square 0.90 but comb 1.07). Factoring the hand's small blocks
#   dense (LAPACK's Cholesky, which beat SuperLU on them by 9-11 %) no
#   longer gains anything (1.00), so every block is factored by CHOLMOD.
# Tried and dropped: starting each column at the lower bound wherever an
# earlier column came out at 1 (the partition of unity) raised the
# factorizations of the L with 20 points from 270 to 323 and of the
# tetrahedral hand from 13 to 20 (cause not measured). Measured before
# WIDEN_MAX: releasing, with each wrong multiplier, its bound neighbours in
# H's graph took the factorizations from 43 to 58 (bones), 28 to 53
# (regions), 13 to 27 (hand); widening by two rings, 43 to 46 (bones);
# predicting the upper bound from ADMM's dual (U > 0) or from the trend of
# its iterate changed nothing beyond noise. Stopping ADMM once its
# predicted sets settle: they never do (2-7 % of the entries move every 5
# steps, from 15 to 45 steps). Faster factorizations: SuperLU's
# relax/panel_size change the 10k-vertex character's by under 10 %;
# cholespy (CHOLMOD, its ordering included) factors it in 76 ms against
# SuperLU's 32 ms, though it solves in half the time. With WIDEN_MAX,
# RELEASE_RANGE and BORDER_BUDGET 1, 40 ADMM steps instead of 25: U notch
# -28 %, comb -16 %, regions -7 %, but bones +11 % and the hand (the
# worst member) +12 %.
# Issue 27 (hand 0.33, bones 0.28 of igl.bbw's CPU), measured and dropped:
# on the hand (44 ms a call) the shared part is SuperLU's MMD ordering of H
# (1.8 ms), its factorization (2.4 ms), that of H + ρI (2.3 ms, float32
# barely faster) and 25 ADMM solves (0.29 ms each for 6 columns; a dense
# float32 Cholesky of the whole H costs 5.8 ms and solves in 0.65 ms, so no
# gain there); the columns take ~29 ms, 1 factorization and 2-4 bordered
# steps each. Skipping ADMM (start from the out-of-box bounds of H⁻¹ g):
# hand 6 -> 10 factorizations, +17 % time. ADMM 5, 10, 15, 20, 40 steps on
# the hand: 8, 8, 8, 7, 6 factorizations, time within noise of 25 steps
# (-5 to +18 %). Releasing, on a step that only releases, the bound
# neighbours of every released variable too (the bones' first column grows
# ~7 variables a step for 17 steps): bones 17 -> 234 factorizations (7x
# the time), hand 6 -> 42 (not traced; see the variant below). Widening also by ring variables whose ADMM
# iterate is strictly inside the box: no change (the hand's missed free
# variables sit at ADMM's bound exactly). RELEASE_RANGE 0 / 0.0003 and
# BORDER_BUDGET 0.5 / 1.5 on the bones: 24 / 16 and 24 / 13 factorizations,
# time within noise or worse. On the bones' slow column the bordered steps
# cost ~10 ms each, mostly SuperLU solves of the new bordering columns
# (0.23 ms a right-hand side on a 6000-variable block). The same ring
# release, but never to a variable already pinned from out of the box in
# that column: bones 17 -> 27 factorizations (+15 % time), hand 6 -> 11
# (+50 %): a whole ring is wider than the front's true step, and its far
# side falls out of the box. Dense blocks bordered less (their budget times
# 0, 0.1, 0.3, 0.5): hand 19, 13, 9, 7 factorizations instead of 6, +3 to
# +30 % time (2 alternating runs).
# Issue 27, second round (box_qp alone, new/old CPU, alternating runs in one
# process): a step that only releases also releases what its Jacobi move
# makes wrong (_lookahead): square 0.93, U notch 0.97, comb 0.99, holes
# 1.00, bones 0.91, regions 0.93, L 0.96, hexagon 1.01, hand 1.01 (bordered
# steps: bones 48 -> 40, square 23 -> 17). Iterating that estimate 2-3
# rings, or scaling its move by 2-8: no fewer steps, more factorizations.
# SuperLU's solve slows down past ~16 right-hand sides on 6000-variable
# blocks (0.09 ms each at 16, 0.17 at 50, 0.26 at 100): SOLVE_CHUNK.
# Measured and dropped:
# - With the exact final active sets handed in (no ADMM at all), box_qp
#   takes 22 ms on the hand (45 with ADMM) and 140 ms on the bones (610):
#   the hand's columns alone cost 14.5 ms then, 6 factorizations and their
#   checks, so with the 4 ms outside box_qp the hand cannot reach 0.25 of
#   igl.bbw's ~125 ms through a better prediction alone.
# - ADMM's misses are the fronts: variables whose final weight is 1e-6 to
#   1e-3 (median 2e-3 on the hand, 5e-4 on the bones), which its iterate
#   leaves at 0; 200 steps still miss 247 of the hand's 2636 free entries.
#   Anderson acceleration (memory 5) of ADMM: hand +5 to +45 % CPU, bones
#   -12 to +23 %. Against the lookahead alone, ADMM's steps from half the
#   graph's diameter (10-40): U notch -8 %, comb -14 %, hand -4 %, but bones
#   +10 %, holes +5 %; 40 steps: U notch -20 %, comb -17 %, regions -11 %,
#   but bones +5 %, hand +13 %. The two worst members want 25 or fewer.
# - A coarse Galerkin predictor (a maximal independent set of the mesh's
#   free vertices, averaging interpolation P, box_qp on PᵀHP): on the bones
#   it misses 22 free entries instead of ADMM's 2065 but frees 13,900 that
#   end at 0, and its own solve takes 233 ms: 46 factorizations, 2x slower.
# - A dense free block grown in place ([[L, 0], [Cᵀ, L₂₂]]) and shrunk by
#   refactoring its tail, instead of bordering: hand +6 %.
# - Releasing whole rings ahead of a front that crept 2-4 steps, or solving
#   the box problem on the bound variables within 8 rings of it (dense, at
#   most 800 / 3000 of them): more factorizations, or bones -3 % / +20 %.
# Issue 27, third round, measured and dropped:
# - Each column's first step factors the predicted block, then pins 60-1000
#   of it and factors again (5 of the bones' 16 factorizations). Pinning
#   first where 20-40 Jacobi-preconditioned CG steps from ADMM's iterate go
#   negative catches 79 of 81 such pins on one column but 90 of 1046 on
#   another: 16 -> 15 factorizations, time within noise. ADMM's unclipped
#   iterate, or the gradient at it, does not separate the free variables it
#   misses from the ones rightly at 0 (bones: 20 of 199 caught, 22 wrongly).
# - METIS nested dissection (pymetis) instead of MMD: as much fill (bones
#   1.22M against 1.24M entries, hand 153k against 133k) and a slower
#   ordering (56 against 12 ms on the bones); COLAMD, MMD on AᵀA and reverse
#   Cuthill-McKee fill more.
# - Forward solves only (S = Wᵀ D⁻¹ W, W = L⁻¹ B): SuperLU's column-wise
#   triangular solve (what spsolve_triangular calls) takes 80 % of the
#   supernodal full solve for 8-64 right-hand sides.
# - ADMM_STEPS 20 or 15 instead of 25: per member erratic (20: bones -7 %
#   but regions +19 %, square and U notch +5 %; 15: bones +19 %).
# - Widening by a second ring where it adds at most 15 % of the free set:
#   +6 to +57 % on every triangle mesh (the hand unchanged).
# Issue 27, fourth round (CHOLMOD; box_qp alone, alternating A/B runs):
# - H itself factored by CHOLMOD in AMD's order instead of SuperLU: every
#   member faster (hexagon 0.74, regions 0.90, bones 0.91, hand 0.92, comb
#   and L 0.98). Its pattern, read out once the unconstrained minimizer and
#   ρ are known (cvxopt hands L over by making the factor symbolic), bounds
#   the blocks' column counts as SuperLU's U did. The branch with C last
#   keeps SuperLU, whose factor's trailing block is K: its x0 and its final
#   solve come from that same factor (from CHOLMOD's instead, the KKT
#   residual of the exact branch grew from 1e-12 to 3e-11).
# - The tetrahedral hand's predictions: after 25 ADMM steps it misses 324
#   free entries and predicts 746 free that end at 0, after 8 steps 357 and
#   437 (after 2, 396 and 36): ADMM's iterate spreads. Hence the steps from
#   the rings across (_admm_steps: 8 on the hand, -12 %), and the first
#   step's releases at ADMM's iterate (hand 27 -> 20 steps, 14 -> 10
#   factorizations, -13 %). ADMM_PENALTY 0.03-1 on the hand: -9 to +12 %,
#   erratic; BORDER_BUDGET 0.25-0.3: hand -4 to +1 %, comb +5-7 %;
#   WIDEN_MAX 0.6 or 1.1 on the hand: +3 %, +16 %.
ADMM_PENALTY = 0.01
ADMM_RELAXATION = 1.6
ADMM_STEPS = 25
ADMM_NEAR_BOUND = 0.1
BORDER_BUDGET = 0.5
WIDEN_MAX = 0.3
RELEASE_RANGE = 0.003
SOLVE_CHUNK = 16

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
    the bounds that the unconstrained minimizer ``H⁻¹ g`` breaks (``H``
    factored by CHOLMOD in AMD's order). When those vertices are few (a set
    C), ordering C last in one sparse factorization of ``H`` gives the Schur
    complement K of ``H`` onto C, and every step is a small dense solve on C;
    if the solution then leaves the box outside C, C grows and the solve
    repeats. When C is large, the iterations start from the bounds that a few
    ADMM steps touch or nearly touch (Boyd et al. 2011, one factorization of
    ``H + ρI`` for all columns; at most half as many steps as ``H``'s graph
    is rings across), and the first step's releases are taken at ADMM's
    iterate before any factorization. The free blocks of ``H`` keep the
    fill-reducing order of ``H`` and are factored by CHOLMOD's supernodal
    Cholesky in that order; a step whose
    free block differs from the last factored one by a few variables borders
    that factorization instead of factoring anew (a Schur-complement update).
    The predicted free sets start one ring of ``H``'s graph wider where that
    ring is thin: the steps pin a free set too large in bulk, but grow one
    too small only at its border, a ring per step. Free components that
    nothing drives (a zero right-hand side: their minimizer is 0) start at
    the lower bound instead of in the block. A variable is released from its
    bound only when its multiplier is wrong by more than half of ``tol`` and
    by at least RELEASE_RANGE of the step's worst; a step that only releases
    also releases the bound variables whose multipliers the released ones'
    move (estimated by a Jacobi step) turns wrong. The iterations stop as
    soon as the KKT conditions hold to ``tol``: the last steps of an exact
    active-set solver only move variables within 1e-7 of a bound.
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
    # OpenBLAS's threads only slow the small dense products and solves here
    # down (bbw on the tetrahedral hand, 2 cores: 0.36 s wall with them, 0.10
    # s without)
    with _thread_pools().limit(limits=1, user_api="blas"):
        X = _solve(H, G.reshape(len(G), -1), tol)
    return X.reshape(G.shape)


@functools.cache
def _thread_pools():
    # finding the loaded BLAS libraries takes 0.3 ms: once, not per call
    return ThreadpoolController()


def _factor(A, permc_spec):
    try:
        return spla.splu(A, permc_spec=permc_spec, **SYMMETRIC)
    except RuntimeError as error:  # SuperLU: "Factor is exactly singular"
        raise ValueError(f"H must be positive definite: its factorization failed ({error})") from None


class _SparseCholesky:
    """CHOLMOD's supernodal Cholesky factor of a sparse SPD matrix ``A`` ``(k, k)``; ``solve`` as SuperLU's.

    ``A`` is CSC (only its lower triangle is read), factored in its own order,
    or with ``fill_reducing`` in AMD's. CHOLMOD comes through cvxopt, whose
    wheel bundles it with OpenBLAS; cvxopt's AMD orders.
    """

    # cvxopt keeps CHOLMOD's settings in one module-level dict; these hold
    # only while a factor is made, under a lock (two threads swapping them
    # could leave them set). nmethods 1: the order given and no other
    # (CHOLMOD's default also tries AMD, which tripled the analysis of the
    # character's blocks)
    OPTIONS = {"nmethods": 1, "supernodal": 2, "postorder": True}
    LOCK = threading.Lock()

    def __init__(self, A, fill_reducing=False):
        k = self.size = A.shape[0]
        columns = np.repeat(np.arange(k, dtype=np.int64), np.diff(A.indptr))
        lower = np.flatnonzero(A.indices >= columns)
        matrix = cvxopt.spmatrix(
            cvxopt.matrix(A.data.take(lower)), cvxopt.matrix(A.indices.take(lower).astype(np.int64)),
            cvxopt.matrix(columns.take(lower)), (k, k),
        )
        # AMD instead of SuperLU's MMD: a little less fill (bones 1.22M
        # against 1.24M entries, comb -14 %) in a fraction of the time (hand
        # 0.75 against ~3 ms, bones 7 against ~12 ms)
        order = amd.order(matrix, uplo="L") if fill_reducing else cvxopt.matrix(np.arange(k, dtype=np.int64))
        with self.LOCK:
            saved = dict(cholmod.options)
            cholmod.options.update(self.OPTIONS)
            try:
                self.factor = cholmod.symbolic(matrix, p=order, uplo="L")
                cholmod.numeric(matrix, self.factor)
            except ArithmeticError as error:  # CHOLMOD: "not positive definite"
                raise ValueError(f"H must be positive definite: its factorization failed ({error})") from None
            finally:
                cholmod.options.clear()
                cholmod.options.update(saved)

    def solve(self, b):
        """``A⁻¹ b`` for ``b`` ``(k,)`` or ``(k, q)``."""
        x = cvxopt.matrix(np.asfortranarray(b, dtype=np.float64).reshape(len(b), -1))
        cholmod.solve(self.factor, x)
        return np.array(x).reshape(b.shape)

    def read_out(self):
        """``(order, L)``: the factor's order (``order[p]`` is the row of ``A`` at position ``p``: the
        order asked for, then CHOLMOD's postorder) and ``L`` ``(k, k)`` CSC, ``A[order][:, order] = L Lᵀ``.

        cvxopt hands ``L`` over by turning the factor symbolic: no ``solve``
        after this.
        """
        x = cvxopt.matrix(np.arange(self.size, dtype=np.float64))
        cholmod.solve(self.factor, x, sys=7)  # x := P x, so x[p] is the row at position p
        order = np.array(x).ravel().astype(np.int64)
        colptr, rowind, values = cholmod.getfactor(self.factor).CCS
        L = sp.csc_matrix(
            (np.array(values).ravel(), np.array(rowind).ravel(), np.array(colptr).ravel()), shape=(self.size, self.size),
        )
        return order, L


def _solve_in_chunks(lu, B):
    """SuperLU's ``lu.solve(B)`` for ``B`` ``(k, q)``, in runs of ``SOLVE_CHUNK`` columns."""
    if B.ndim == 1 or B.shape[1] <= SOLVE_CHUNK:
        return lu.solve(B)
    X = np.empty_like(B, order="F")
    for start in range(0, B.shape[1], SOLVE_CHUNK):
        X[:, start:start + SOLVE_CHUNK] = lu.solve(np.asfortranarray(B[:, start:start + SOLVE_CHUNK]))
    return X


def _solve(H, G, tol):
    n, m = G.shape
    tol_x = 1e-11
    factor = _SparseCholesky(H, fill_reducing=True)
    scale = float(abs(H).sum(axis=1).max())
    X_unconstrained = factor.solve(G)
    rho = _admm_penalty(H, factor, scale)
    # what is read out of the factor ends its solves: the order every free
    # block keeps (position p holds variable order[p]) and the pattern of L,
    # whose columns' counts bound those of every block's factor. fill holds
    # it transposed with unit entries (see _FreeBlockSolver).
    order, L = factor.read_out()
    position = np.argsort(order)
    fill = sp.csr_matrix((np.ones(L.nnz), L.indices, L.indptr), shape=(n, n))
    # about the flops of one sparse factorization of H (Σ column count²)
    sparse_flops = float((np.diff(L.indptr).astype(np.float64) ** 2).sum())
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
        # than SuperLU (the factor 100 was set against SuperLU's blocks, ~3x
        # slower than CHOLMOD's): go dense when that beats a sparse one
        if float(grown.sum()) ** 3 >= 100 * sparse_flops:
            # every free block keeps the factor's fill-reducing order: a good
            # order for the block too, so CHOLMOD skips its own ordering; H is
            # permuted once, and ADMM works in that order too
            H_ordered = H[order][:, order].tocsc()
            H_ordered.sort_indices()
            # column-major: CHOLMOD (through cvxopt) takes that layout as is
            G_ordered = np.asfortranarray(G[order])
            at_lower, at_upper, Z = _admm_active_sets(
                H_ordered, G_ordered, np.asfortranarray(X_unconstrained[order]), rho, _admm_steps(H_ordered),
            )
            at_lower, at_upper = _widened(H_ordered, at_lower, at_upper)
            columns = np.repeat(np.arange(n), np.diff(H_ordered.indptr))
            # fill is in that order too: the pattern of every block's factor
            # lies within it (see _FreeBlockSolver)
            X = np.empty((n, m))
            for j in range(m):
                X[order, j] = _sparse_active_set(
                    H_ordered, columns, fill, G_ordered[:, j], at_lower[:, j], at_upper[:, j], tol * scale,
                    Z[:, j],
                )
            return X
        # Order C last, the rest in the fill-reducing order: the trailing
        # block of the factor is then the Schur complement K of H onto C.
        order_c = np.argsort(position + n * grown, kind="stable")
        lu_c = _factor(H[order_c][:, order_c].tocsc(), "NATURAL")
        # SuperLU postorders its elimination tree, which can move a few other
        # variables behind C: take the whole trailing block
        tail = n - int(lu_c.perm_c[np.argsort(order_c)[grown]].min())
        trailing = order_c[np.argsort(lu_c.perm_c)[-tail:]]
        K = lu_c.L[-tail:, -tail:].toarray() @ lu_c.U[-tail:, -tail:].toarray()
        K = 0.5 * (K + K.T)
        K_inverse = scipy.linalg.cho_solve(
            scipy.linalg.cho_factor(K, check_finite=False), np.eye(len(K)), check_finite=False,
        )
        C[trailing] = True
        # with the other variables eliminated, the energy on C is
        # ½ (y - x0)ᵀ K (y - x0), x0 the unconstrained minimizer there; its
        # multipliers are the gradient of the full energy. x0 and the final
        # solve come from lu_c, as K does: from CHOLMOD's factor instead, the
        # two factorizations' roundoff left KKT residuals of 3e-11 (1e-11
        # from one)
        x0 = np.empty((n, m))
        x0[order_c] = _solve_in_chunks(lu_c, np.asfortranarray(G[order_c]))
        multipliers = np.zeros((n, m))
        for j in range(m):
            nu, lower, upper = _dense_active_set(
                K, K_inverse, x0[trailing, j], at_lower[trailing, j], at_upper[trailing, j],
            )
            multipliers[trailing, j] = nu
            at_lower[:, j] = False
            at_upper[:, j] = False
            at_lower[trailing[lower], j] = True
            at_upper[trailing[upper], j] = True
        X = np.empty((n, m))
        X[order_c] = _solve_in_chunks(lu_c, np.asfortranarray((G + multipliers)[order_c]))
        X[at_lower] = 0.0
        X[at_upper] = 1.0


def _admm_penalty(H, factor, scale):
    """ADMM's penalty ρ for ``H`` ``(n, n)``, factored by ``factor``, its largest eigenvalue at most ``scale``."""
    # √(λ_min λ_max) is ADMM's optimal penalty on strongly convex quadratics
    # (Ghadimi et al. 2015), and scaling by it suits triangles and tetrahedra
    # alike. Only the bounds matter here, and a fraction of it finds them in
    # fewer steps: on the family's square after 50 unrelaxed steps, ρ ≈ 0.6
    # √(λ_min λ_max) left 42 active-set factorizations, ρ ≈ 0.06 √(λ_min
    # λ_max) 26 (and see ADMM_PENALTY).
    # A few inverse iterations estimate λ_min.
    v = np.linspace(1.0, 2.0, H.shape[0])
    for _ in range(6):
        v = factor.solve(v)
        v /= np.linalg.norm(v)
    return ADMM_PENALTY * float(np.sqrt(max(v @ (H @ v), 0.0) * scale))


def _admm_active_sets(H, G, X_unconstrained, rho, steps):
    """Predict the active sets of every column with a few ADMM steps.

    ADMM on the splitting ``x = z``, ``z`` in the box: each step is one solve
    with ``H + ρI``, factored once for all columns, then a clip. Its iterate
    is not accurate, but the bounds it touches are close to the final active
    sets, which PDAS started from the unconstrained minimizer's out-of-box
    regions reaches only a stencil ring per step. ``H`` is CSC in a
    fill-reducing order, ``G`` and ``X_unconstrained`` are ``(n, m)``,
    ``rho`` the penalty and ``steps`` how many to take (see ``_admm_steps``);
    returns ``(at_lower, at_upper, Z)``: the predicted active sets, ``(n, m)``
    bool, and ADMM's iterate, ``(n, m)``.
    """
    factor = _SparseCholesky((H + rho * sp.identity(H.shape[0], format="csc")).tocsc())
    Z = np.clip(X_unconstrained, 0.0, 1.0)
    Z_last = Z
    U = X_unconstrained - Z
    for _ in range(steps):
        X = ADMM_RELAXATION * factor.solve(G + rho * (Z - U)) + (1.0 - ADMM_RELAXATION) * Z
        Z, Z_last = np.clip(X + U, 0.0, 1.0), Z
        U += X - Z
    # Skinning weights vanish on whole regions, where ADMM's iterate is still
    # slightly positive: started free, those variables would enter every free
    # block. Started at the bound, the few that belong inside are released.
    # "Slightly" is relative to how far ADMM still moves (its last step).
    near = ADMM_NEAR_BOUND * np.abs(Z - Z_last).max(axis=0)
    return Z <= near, Z >= 1.0 - near, Z


def _admm_steps(H):
    """``ADMM_STEPS``, or half as many steps as ``H``'s graph is rings across if that is fewer.

    PDAS grows a free set by about a ring a step, so on a graph a few dozen
    rings across it reaches the fronts in a few steps and a long ADMM run
    saves it nothing: the tetrahedral hand, 17 rings across, takes 8 steps
    instead of 25 and 12 % less CPU; the triangle meshes of the BBW family
    are 41-100 rings across (the square, 46, takes 23 steps: +2 %).
    """
    return min(ADMM_STEPS, max(1, _rings_across(H) // 2))


def _rings_across(H):
    """How many rings of ``H``'s graph ``(n, n)`` separate its farthest vertices, estimated by two breadth-first sweeps."""
    pattern = _graph(H)
    rings = 0
    start = 0
    for _ in range(2):
        depth = shortest_path(pattern, unweighted=True, indices=start)
        reached = np.isfinite(depth)
        start = int(np.argmax(np.where(reached, depth, -1.0)))
        rings = max(rings, int(depth[start]))
    return rings


def _graph(H):
    """``H``'s graph: its pattern with unit entries, CSR ``(n, n)`` (``H`` CSC and symmetric: Hᵀ's pattern is H's)."""
    return sp.csr_matrix((np.ones_like(H.data), H.indices, H.indptr), shape=H.shape)


def _widened(H, at_lower, at_upper):
    """Free every bound variable that ``H`` couples to a free one, in each column where that ring is thin.

    The active-set steps release a bound variable only once its multiplier
    has the wrong sign, which happens next to the free set alone: a free set
    predicted too small grows by about one ring of ``H``'s graph per step,
    each step a new factorization. A free set predicted too large shrinks in
    bulk instead (every free variable out of the box is pinned in the same
    step). So each column starts one ring wider, unless that ring adds more
    than ``WIDEN_MAX`` of its free set (a ring of a coarse mesh, where the
    wider start costs more steps than it saves).

    ``H`` ``(n, n)`` sparse; ``at_lower`` and ``at_upper`` ``(n, m)`` bool.
    Returns the narrowed ``(at_lower, at_upper)``.
    """
    coupled = _graph(H)
    free = ~(at_lower | at_upper)
    ring = ((coupled @ free.astype(np.float64)) > 0) & ~free
    ring &= ring.sum(axis=0) <= WIDEN_MAX * free.sum(axis=0)
    return at_lower & ~ring, at_upper & ~ring


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
    entries = keep[A.indices]
    entries &= keep[columns]
    # positions, then integer takes: numpy's boolean-mask gathers were 3x
    # slower (2.0 against 0.6 ms for 60 % of the character's H)
    entries = np.flatnonzero(entries)
    renumber = np.cumsum(keep, dtype=np.int32) - 1
    k = int(renumber[-1]) + 1
    indptr = np.zeros(k + 1, dtype=np.int32)
    np.cumsum(np.bincount(renumber.take(columns.take(entries)), minlength=k), out=indptr[1:])
    return sp.csc_matrix((A.data.take(entries), renumber.take(A.indices.take(entries)), indptr), shape=(k, k))


class _FreeBlockSolver:
    """Solve ``H[F, F] x = r`` for a free set ``F`` that changes a little from one step to the next.

    One sparse factorization of a base block ``H[F0, F0]`` serves every
    later ``F`` close to ``F0``: the variables added to it (``A = F \\ F0``)
    and removed from it (``R = F0 \\ F``) border that block,

        [ H00   H0A  E_R ] [x0]   [r0]
        [ HA0   HAA   0  ] [xA] = [rA]
        [ E_Rᵀ   0    0  ] [λ ]   [0 ]

    (``E_R`` the columns of the identity at ``R``, so ``x0`` is zero there),
    and eliminating ``x0`` leaves a dense system of ``|A| + |R|`` unknowns
    (the Schur-complement update of Gill, Murray, Saunders and Wright). Each
    bordering variable costs one solve with the base factor, once. When
    ``|A| + |R|`` passes the cost of a new factorization in such solves, ``F``
    becomes the new base.

    A block is factored by CHOLMOD (``_SparseCholesky``). Its bordering
    budget comes from bounds on its factor's column counts: the pattern of
    ``H``'s own factor in the same order, restricted to the block (which
    contains the block factor's pattern: eliminating fewer variables fills in
    no more).

    ``H`` is CSC with sorted indices in the order every block keeps,
    ``columns`` the column of each stored entry (see ``_principal_submatrix``)
    and ``fill`` ``(n, n)`` sparse, the pattern of an upper triangular factor
    of ``H`` in that order, with unit entries: its product with a block's 0/1
    indicator counts the entries of each column of the lower factor (each row
    of ``fill``) within the block.
    """

    def __init__(self, H, columns, fill):
        self.H = H
        self.columns = columns
        self.fill = fill
        self.base = None

    def solve(self, free, r):
        """``x[free]`` for ``H[free, free] x[free] = r[free]``; ``free`` ``(n,)`` bool, ``r`` ``(n,)``."""
        if self.base is not None:
            added = np.flatnonzero(free & ~self.base)
            removed = np.flatnonzero(self.base & ~free)
            if added.size + removed.size <= self.budget:
                return self._bordered(free, r, added, removed)
        return self.solve_factored(free, r)

    def solve_factored(self, free, r):
        """As ``solve``, with ``H[free, free]`` factored itself (the new base)."""
        self._refactor(free)
        return self._base_solve(r)

    def _refactor(self, free):
        block = _principal_submatrix(self.H, self.columns, free)
        k = block.shape[0]
        self.factor = _SparseCholesky(block)
        # bounds, not the factor's own counts: those are not read cheaply
        # (SuperLU's lu.L, a copy of its factor, took 1.3 ms of a 10 ms
        # factorization on the character)
        column_counts = self._column_counts(free)
        self.base = free.copy()
        self.position = np.cumsum(free) - 1  # of each base variable in the block
        # a factorization costs about Σ (column count)² flops, a solve about
        # 4 Σ column count (see BORDER_BUDGET)
        self.budget = BORDER_BUDGET * float((column_counts**2).sum()) / float(column_counts.sum())
        # every variable that has bordered this block has a slot: its column
        # b of [H0A E_R] in B, H00⁻¹ b in Y, and the products bᵢᵀ yⱼ in BY.
        # B has a few entries per column: it keeps only the rows some column
        # touches (row[i] is the base position of its row i, compact[p] the
        # row of base position p or -1); against a dense (k, slots) B, the
        # bones -4 % and the regions -6 % CPU (8 alternating runs)
        self.slot = np.full(len(free), -1)
        self.used = 0
        self.r_solved = None
        self.compact = np.full(k, -1)
        self.row = np.empty(0, dtype=np.int64)
        # slots grow as variables border: allocating the whole budget at once
        # would hold 8 bytes x budget per base variable
        self.Y = np.empty((k, 16), order="F")
        self.B = np.zeros((64, 16))
        self.BY = np.empty((16, 16))

    def _column_counts(self, free):
        """Upper bounds on the column counts of a sparse factor of ``H[free, free]``, ``(k,)``."""
        return (self.fill @ free.astype(np.float64))[free]

    def _border(self, variables):
        """Give ``variables`` (``(q,)`` int, none with a slot yet) their slots."""
        q, used = len(variables), self.used
        # the new columns of B: e_i for a base variable i (a removed one), H's
        # column restricted to the base for an added one
        on_base = self.base[variables]
        rows, k, values = _stored_entries(self.H, variables[~on_base])
        inside = self.base[rows]
        rows = np.concatenate([self.position[variables[on_base]], self.position[rows[inside]]])
        columns = np.concatenate([np.flatnonzero(on_base), np.flatnonzero(~on_base)[k[inside]]])
        values = np.concatenate([np.ones(int(on_base.sum())), values[inside]])
        unseen = np.unique(rows[self.compact[rows] < 0])
        self.compact[unseen] = len(self.row) + np.arange(len(unseen))
        self.row = np.concatenate([self.row, unseen])
        self._reserve(len(self.row), used + q)
        self.B[self.compact[rows], used + columns] = values
        B = np.zeros((self.Y.shape[0], q), order="F")
        B[rows, columns] = values
        self.Y[:, used:used + q] = self.factor.solve(B)
        touched = len(self.row)
        self.BY[:used + q, used:used + q] = self.B[:touched, :used + q].T @ self.Y[self.row, used:used + q]
        self.BY[used:used + q, :used] = self.BY[:used, used:used + q].T
        self.slot[variables] = used + np.arange(q)
        self.used = used + q

    def _reserve(self, rows, slots):
        """Room in ``B`` for ``rows`` touched rows and in ``B``, ``Y``, ``BY`` for ``slots`` slots."""
        used = self.used
        if slots > self.Y.shape[1]:
            grown = 2 * slots
            # column-major, so that a run of Y's columns is one GEMM operand
            Y, BY = np.empty((self.Y.shape[0], grown), order="F"), np.empty((grown, grown))
            Y[:, :used], BY[:used, :used] = self.Y[:, :used], self.BY[:used, :used]
            self.Y, self.BY = Y, BY
        if rows > self.B.shape[0] or slots > self.B.shape[1]:
            B = np.zeros((max(rows, 2 * self.B.shape[0]), max(self.Y.shape[1], self.B.shape[1])))
            B[:self.B.shape[0], :used] = self.B[:, :used]
            self.B = B

    def _base_solve(self, r):
        """``H00⁻¹ r[base]``, kept: ``r`` on the base changes only with the upper set, seldom."""
        r = r[self.base]
        if not np.array_equal(r, self.r_solved):
            self.r_solved, self.z_solved = r, self.factor.solve(r)
        return self.z_solved.copy()

    def _bordered(self, free, r, added, removed):
        z = self._base_solve(r)
        x = np.zeros(len(free))
        if added.size + removed.size:
            both = np.concatenate([added, removed])
            new = both[self.slot[both] < 0]
            if new.size:
                self._border(new)
            slots = self.slot[both]
            k = added.size
            S = -self.BY[np.ix_(slots, slots)]
            # H[added][:, added]: the stored entries of those columns in those rows
            rows, column, values = _stored_entries(self.H, added)
            among = np.full(len(free), -1)
            among[added] = np.arange(k)
            inside = among[rows] >= 0
            np.add.at(S, (among[rows[inside]], column[inside]), values[inside])
            used = self.used
            right = -(z[self.row] @ self.B[:len(self.row), slots])
            right[:k] += r[added]
            u = np.zeros(used)
            # S is symmetric but indefinite (the removed variables' rows):
            # LAPACK's LDLᵀ, without scipy.linalg.solve's checks (a few µs
            # instead of ~20)
            _, _, u[slots], info = scipy.linalg.lapack.dsysv(S, right)
            if info != 0:
                raise ValueError("H must be positive definite: a bordered free block is singular")
            z -= self.Y[:, :used] @ u
            x[added] = u[slots[:k]]
        x[self.base] = z
        return x[free]


def _stored_entries(H, variables):
    """The stored entries of ``H``'s columns ``variables`` (CSC): ``(rows, k, values)``, ``k`` the position in ``variables``."""
    starts, stops = H.indptr[variables], H.indptr[variables + 1]
    counts = stops - starts
    k = np.repeat(np.arange(len(variables)), counts)
    entries = np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts) + np.repeat(starts, counts)
    return H.indices[entries], k, H.data[entries]


def _idle(H, columns, free, r):
    """The free variables whose connected component of ``H[free, free]`` has a zero right-hand side ``r``.

    Their minimizer is exactly 0 with a zero multiplier, so they may as well
    lie at the lower bound. A skinning weight's ADMM prediction leaves such
    islands free around the other handles: 40-50 % of some free blocks on
    the character with bones and on the tetrahedral hand, which would
    otherwise be factored at every step. A free set of one component is
    left whole (undriven, it is the trivial problem, solved in one step).
    ``free`` ``(n,)`` bool, ``r`` ``(n,)``; returns ``(n,)`` bool.
    """
    if not free.any():
        return np.zeros_like(free)
    count, labels = connected_components(_principal_submatrix(H, columns, free), directed=False)
    if count == 1:
        return np.zeros_like(free)
    driven = np.bincount(labels, weights=r[free] != 0, minlength=count) > 0
    idle = np.zeros_like(free)
    idle[np.flatnonzero(free)[~driven[labels]]] = True
    return idle


def _wrong_multipliers(gradient, lower, upper, tol_release):
    """The bound variables whose multiplier (``gradient`` ``H x - g``) has the wrong sign by more than ``tol_release``."""
    return (lower & (gradient < -tol_release)) | (upper & (gradient > tol_release))


def _released(H, diagonal, gradient, lower, upper, wrong, tol_release, lookahead):
    """Of the ``wrong`` multipliers (not none), those a step releases, with its look-ahead if ``lookahead``.

    The clearly wrong multipliers first: fewer variables move per step, and
    more steps border the last factorization instead of factoring anew (on a
    2D square: 25 steps instead of 20, 8 factorizations instead of 11).
    """
    release = wrong & (np.abs(gradient) >= RELEASE_RANGE * np.abs(gradient[wrong]).max())
    return _lookahead(H, diagonal, gradient, lower, upper, release, tol_release) if lookahead else release


def _lookahead(H, diagonal, gradient, lower, upper, release, tol_release):
    """``release`` and the bound variables whose multipliers the released ones' move makes wrong.

    A variable released from its bound moves about to where its own
    gradient vanishes, ``-gradient_i / H_ii`` (a Jacobi step, the others held),
    and that move changes its neighbours' gradients by ``H`` times it: where a
    neighbour's multiplier then has the wrong sign, the next step would
    release it anyway, one ring later. ``H`` ``(n, n)`` sparse, ``diagonal``
    its diagonal (CSC), ``gradient`` ``H x - g``; masks ``(n,)`` bool.
    """
    moved = np.flatnonzero(release)
    # only the released columns of H: a few dozen, not a product with all of H
    rows, k, values = _stored_entries(H, moved)
    step = -gradient[moved] / diagonal[moved]
    predicted = gradient + np.bincount(rows, weights=values * step[k], minlength=len(gradient))
    return release | (lower & (predicted < -tol_release)) | (upper & (predicted > tol_release))


def _sparse_active_set(H, columns, fill, g, lower, upper, tol_kkt, start=None):
    """Minimize ``½ xᵀ H x - gᵀ x`` over ``0 ≤ x ≤ 1`` to KKT residual ``tol_kkt``; ``H`` sparse SPD.

    ``H`` is CSC with sorted indices, its variables in a fill-reducing order
    that every free block keeps, and ``columns`` the column of each of its
    stored entries (see ``_principal_submatrix``), and ``fill`` the pattern
    of ``H``'s factor in that order (see ``_FreeBlockSolver``); ``lower`` and
    ``upper`` are ``(n,)`` bool, the initial active sets, and ``start``
    ``(n,)`` (optional) the predictor's iterate they came from.

    Returns ``x`` ``(n,)``, in the box exactly.
    """
    n = len(g)
    max_iter = 100 + 5 * n
    seen, murty = set(), False
    blocks = _FreeBlockSolver(H, columns, fill)
    # the free block's right-hand side, g - H[free, upper] 1, on every
    # variable; it changes only when the upper set does
    r = g - H @ upper.astype(np.float64)
    lower = lower | _idle(H, columns, ~(lower | upper), r)
    # A multiplier within this of zero is left alone: such a variable costs at
    # most half the tolerance where it is, and releasing it on the sign of
    # roundoff (a weight's zero region is degenerate: its gradient there is 0)
    # makes the free set chatter.
    tol_release = 0.5 * tol_kkt
    diagonal = H.diagonal()
    if start is not None:
        # the first step's releases, taken at the predictor's iterate before
        # any factorization: the first block then holds most of the front
        # that the prediction missed (hand -9 %, bones -3 %; with the look-
        # ahead the hand another -4 %, the regions +4 %)
        gradient = H @ np.where(lower, 0.0, np.where(upper, 1.0, start)) - g
        release = _wrong_multipliers(gradient, lower, upper, tol_release)
        if release.any():
            release = _released(H, diagonal, gradient, lower, upper, release, tol_release, lookahead=True)
            lower, upper = lower & ~release, upper & ~release
            r = g - H @ upper.astype(np.float64)
    for _ in range(max_iter):
        free = ~(lower | upper)
        x = upper.astype(np.float64)
        if free.any():
            x[free] = blocks.solve(free, r)
            gradient = H @ x - g
            if not np.array_equal(blocks.base, free) and np.abs(gradient[free]).max() > 0.1 * tol_kkt:
                # the bordered solve lost accuracy (a direct solve leaves the free
                # gradient far below a tenth of the tolerance): factor the block
                x[free] = blocks.solve_factored(free, r)
                gradient = H @ x - g
        else:
            gradient = H @ x - g
        below = free & (x < 0)
        above = free & (x > 1)
        release = _wrong_multipliers(gradient, lower, upper, tol_release)
        if not (below | above | release).any():
            return np.clip(x, 0.0, 1.0)  # the minimizer, to the tolerance
        clipped = np.clip(x, 0.0, 1.0)
        if below.any() or above.any():
            gradient = H @ clipped - g
        # the projected gradient: what remains after the bounds push back
        residual = np.where(clipped <= 0, np.minimum(gradient, 0.0), np.where(clipped >= 1, np.maximum(gradient, 0.0), gradient))
        if np.abs(residual).max() <= tol_kkt:
            return clipped
        if release.any():
            # a step that only releases: release one ring ahead too
            lookahead = not (below.any() or above.any() or murty)
            release = _released(H, diagonal, gradient, lower, upper, release, tol_release, lookahead)
        lower, upper_next, murty = _next_active_sets(lower, upper, below, above, release, seen, murty)
        if not np.array_equal(upper_next, upper):
            r = g - H @ upper_next.astype(np.float64)
        upper = upper_next
    raise RuntimeError(
        f"box_qp: the active-set solver did not converge in {max_iter} iterations "
        f"(KKT residual {np.abs(residual).max():.3g}, tolerance {tol_kkt:.3g})"
    )
