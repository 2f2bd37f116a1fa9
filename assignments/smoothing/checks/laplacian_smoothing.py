"""Checks of the Laplacian smoothing assignment: the uniform and cotangent Laplacians, explicit and implicit steps.

Every answer is unique, so it is compared with the reference's, to tolerances
set by roundoff (none is a fitted constant):

- ``UNIFORM_TOL``: the uniform Laplacian holds small integers, exact in float64.
- ``DIRECT_RTOL``: a cotangent entry is a sum of a few ``(a·b) / ‖a × b‖``; its
  relative roundoff is about ``1e-16 / sin θ`` (``θ`` the smallest angle, above
  ``0.002`` rad on the thinnest hidden strip), far below ``1e-9`` of the largest entry.
- ``EXPLICIT_RTOL``: ``u_i + (h / m_i) Σ_j L_ij u_j`` sums at most a few dozen
  products, each rounded to ``1e-16`` of the term ``|u_i| + (h/m_i) Σ |L_ij| |u_j|``;
  ``1e-10`` of that leaves room for any summation order (dense or sparse).
- ``RESIDUAL_RTOL``: a backward-stable solve of ``(M - h L) U' = M U`` leaves a
  residual of ``~1e-15`` of ``|M U| + h |L| |U'|`` (LU, Cholesky, dense or sparse).
- ``SOLVE_RTOL``: the solution's forward error is at most the relative residual
  times the condition number of ``M - h L``; on the hidden cases that number is at
  most 5e4 (measured: the masses spread over six orders of magnitude), so a correct
  solve lands within ~1e-11 (measured: 1.2e-14 for LU of the unsymmetric
  ``I - h M⁻¹ L``), while the wrong systems students solve miss by more than 4e-3.

Laplacians and masses are sent to the student's kernel as dense arrays (the
wire carries arrays, not sparse matrices): the contract accepts both.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from grader.checks.base import Case, FunctionChecks, Step, Verdict, as_array, as_matrix, close, max_abs, once_per_case, raises, verdict
from reference.laplacian_smoothing import cotangent_matrix, uniform_laplacian
from starter import shapes

UNIFORM_TOL = 1e-12
DIRECT_RTOL = 1e-9
EXPLICIT_RTOL = 1e-10
RESIDUAL_RTOL = 1e-9
SOLVE_RTOL = 1e-7


# --- meshes -------------------------------------------------------------------------------------


def relabel(V: np.ndarray, F: np.ndarray, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """The same mesh with vertices and triangles in random order and each triangle's corners rolled.

    Rolling keeps the orientation; nothing may depend on the order of the input.
    """
    order = rng.permutation(len(V))
    new_index = np.empty(len(V), dtype=np.int64)
    new_index[order] = np.arange(len(V))
    F = new_index[np.asarray(F)][rng.permutation(len(F))]
    F = np.stack([np.roll(f, s) for f, s in zip(F, rng.integers(0, 3, len(F)))]) if len(F) else F
    return np.ascontiguousarray(V[order], dtype=np.float64), np.ascontiguousarray(F, dtype=np.int64)


def clockwise(F: np.ndarray) -> np.ndarray:
    """Every triangle with its orientation reversed."""
    return np.ascontiguousarray(F[:, ::-1])


def mixed_orientation(F: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """About half of the triangles reversed."""
    F = F.copy()
    flip = rng.uniform(size=len(F)) < 0.5
    F[flip] = F[flip][:, ::-1]
    return F


def jittered_grid(rng: np.random.Generator, nx: int = 7, ny: int = 7, amount: float = 0.35) -> tuple[np.ndarray, np.ndarray]:
    """A planar grid with interior vertices moved by up to ``amount`` of a cell: obtuse triangles, negative cotangents."""
    V, F = shapes.grid_2d(nx, ny)
    inner = (V[:, 0] > 0) & (V[:, 0] < 1) & (V[:, 1] > 0) & (V[:, 1] < 1)
    V = V.copy()
    V[inner] += rng.uniform(-amount, amount, (int(inner.sum()), 2)) / np.array([nx, ny])
    return V, F


def disjoint_union(*meshes: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    Vs, Fs, offset = [], [], 0
    for V, F in meshes:
        Vs.append(V)
        Fs.append(F + offset)
        offset += len(V)
    return np.vstack(Vs), np.vstack(Fs)


def with_lonely_vertex(V: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The mesh plus one vertex in no triangle (its Laplacian row is zero)."""
    return np.vstack([V, V.mean(axis=0) + 0.1]), F


def similar_copy(V: np.ndarray, rng: np.random.Generator, scale: float, distance: float) -> np.ndarray:
    """``V`` scaled by ``scale``, rotated and moved ``distance`` away: cotangents must not change."""
    d = V.shape[1]
    Q, R = np.linalg.qr(rng.normal(size=(d, d)))
    Q = Q * np.sign(np.diag(R))
    if np.linalg.det(Q) < 0:
        Q[:, 0] *= -1
    direction = rng.normal(size=d)
    return scale * V @ Q.T + distance * direction / np.linalg.norm(direction)


GRID = "2D grid (boundary, right triangles)"
DISC = "2D disc with two holes, clockwise triangles"
JITTERED = "2D jittered grid with obtuse triangles (negative cotangents), each triangle in either orientation"
STRIP = "2D strip of thin triangles (aspect 100:1)"
TORUS = "3D torus (closed)"
BAR = "3D bar (closed, flat faces meeting at right angles)"
PLANAR_3D = "planar 3D mesh (z = 0)"
TWO = "two 2D components, one clockwise"
LONELY = "3D torus plus a vertex in no triangle (its row is zero)"
SMALL_FAR = "2D jittered grid scaled by 1/1000, turned and moved 1000 units away"
TRIANGLE = "a single 3D triangle"


def smoothing_meshes(rng: np.random.Generator) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """The hidden meshes by label, each relabelled at random."""
    grid = shapes.grid_2d(5, 3)
    V_j, F_j = jittered_grid(rng)
    V_disc, F_disc = shapes.disc_with_holes(2, 0.04)
    V_plane, F_plane = shapes.grid_2d(6, 4, width=1.5)
    raw = {
        GRID: shapes.grid_2d(6, 4),
        DISC: (V_disc, clockwise(F_disc)),
        JITTERED: (V_j, mixed_orientation(F_j, rng)),
        STRIP: shapes.grid_2d(10, 2, width=1.0, height=0.002),
        TORUS: shapes.torus(n_major=10, n_minor=6),
        BAR: shapes.bar(length=3.0, nx=6, ny=2, nz=2),
        PLANAR_3D: (np.c_[V_plane, np.zeros(len(V_plane))], F_plane),
        TWO: disjoint_union(grid, (grid[0] + [2.0, 0.0], clockwise(grid[1]))),
        LONELY: with_lonely_vertex(*shapes.torus(n_major=8, n_minor=5)),
        SMALL_FAR: (similar_copy(V_j, rng, 1e-3, 1e3), F_j),
        TRIANGLE: (rng.normal(size=(3, 3)), np.array([[0, 1, 2]])),
    }
    return {label: relabel(V, F, rng) for label, (V, F) in raw.items()}


def sparse_verdict(got) -> Verdict:
    """A Laplacian must come back sparse (the wire rebuilds any scipy.sparse matrix as CSR)."""
    return verdict("a scipy.sparse matrix", sp.issparse(got), f"returned a dense {type(got).__name__}; the contract asks for a scipy.sparse matrix")


def _matches(got, want, tol: float, scale: float) -> bool:
    return close(got, want, tol, scale)[0]


# --- the Laplacians -----------------------------------------------------------------------------


class UniformLaplacianChecks(FunctionChecks):
    function = "uniform_laplacian"
    description = "sparse L = A - D, each edge once, in 2D and 3D, with boundaries, several components, a lonely vertex, a non-manifold edge"

    def cases(self, rng):
        meshes = smoothing_meshes(rng)
        cases = [Case.call(label, "uniform_laplacian", V, F) for label, (V, F) in meshes.items() if label not in (SMALL_FAR, STRIP)]
        V = rng.normal(size=(5, 3))
        cases.append(Case.call("three triangles on one edge (non-manifold): the edge counts once", "uniform_laplacian", V, np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])))
        V, F = meshes[GRID]
        cases.append(raises("F indexes vertex n (one past the last)", [Step("uniform_laplacian", (V, np.vstack([F, [[0, 1, len(V)]]])))]))
        cases.append(raises("F of shape (f, 4) (tetrahedra, not triangles)", [Step("uniform_laplacian", (V, np.c_[F, F[:, :1]]))]))
        return cases

    def verify(self, case, got, expected):
        n = len(case.args()[0])
        L = as_matrix(got, (n, n), "L")
        want = as_matrix(expected, (n, n), "the reference's L")
        ok, where = close(L, want, UNIFORM_TOL)
        hint = ""
        if not ok:
            A = want - sp.diags(want.diagonal())
            degree = sp.diags(-want.diagonal())
            off = L - sp.diags(L.diagonal())
            if off.nnz and off.max() >= 2.0 and _matches(off.minimum(1.0), A, UNIFORM_TOL, 1.0):
                hint = " (an edge shared by two triangles is counted twice: it is one edge, weight 1)"
            elif _matches(L, A + degree, UNIFORM_TOL, 1.0):
                hint = " (the diagonal has the wrong sign: L[i, i] = -deg(i), so that rows sum to zero)"
            elif _matches(L, A, UNIFORM_TOL, 1.0):
                hint = " (the diagonal is missing: L = A - D)"
            elif _matches(L, -want, UNIFORM_TOL, 1.0):
                hint = " (the signs are flipped: +1 off the diagonal, -deg(i) on it)"
        return [sparse_verdict(got), verdict("L = A - D", ok, f"{where}{hint}")]


def _assemble(F: np.ndarray, C: np.ndarray, n: int) -> sp.csr_matrix:
    """The Laplacian with weight ``C[t, k]`` on the edge opposite corner ``k`` of triangle ``t``."""
    i, j = F[:, [1, 2, 0]].ravel(), F[:, [2, 0, 1]].ravel()
    W = sp.coo_matrix((np.r_[C.ravel(), C.ravel()], (np.r_[i, j], np.r_[j, i])), shape=(n, n)).tocsr()
    return (W - sp.diags(np.asarray(W.sum(axis=1)).ravel())).tocsr()


def _cotangent_variants(case: Case) -> dict[str, sp.csr_matrix]:
    """Matrices of common mistakes, computed once per case: a match names the mistake."""

    def compute():
        V, F = case.args()
        a = V[F[:, [1, 2, 0]]] - V[F]  # from each corner to the next
        b = V[F[:, [2, 0, 1]]] - V[F]  # and to the one after
        dot = np.einsum("tkd,tkd->tk", a, b)
        if V.shape[1] == 2:
            signed = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
        else:
            signed = np.linalg.norm(np.cross(a, b), axis=-1)
        half_cot = 0.5 * dot / np.abs(signed)
        n = len(V)
        right = _assemble(F, half_cot, n)
        found = {}
        if V.shape[1] == 2:  # first: on a clockwise mesh it is also "every sign flipped"
            found[" (the 2D cross product is signed: clockwise triangles flip their weights; use |a × b|)"] = _assemble(F, 0.5 * dot / signed, n)
        found |= {
            " (these are cot, the weight is ½ cot)": 2.0 * right,
            " (the signs are flipped: off the diagonal +½ cot, on it minus the row's sum)": -right,
            " (negative cotangents were clamped or made positive: an obtuse angle has a negative cotangent, keep it)": _assemble(F, np.abs(half_cot), n),
            " (negative cotangents were set to 0: an obtuse angle has a negative cotangent, keep it)": _assemble(F, np.maximum(half_cot, 0.0), n),
            " (each weight sits on the wrong edge: the angle at corner k weights the edge opposite it)": _assemble(F, np.roll(half_cot, 1, axis=1), n),
        }
        return found

    return once_per_case(case, "cotangent variants", compute)


class CotangentMatrixChecks(FunctionChecks):
    function = "cotangent_matrix"
    description = "sparse symmetric L with ½ (cot α + cot β) per edge and zero row sums, equal to igl.cotmatrix: thin, obtuse, clockwise, tiny and far-away meshes"

    def cases(self, rng):
        meshes = smoothing_meshes(rng)
        cases = [Case.call(label, "cotangent_matrix", V, F) for label, (V, F) in meshes.items()]
        V, F = meshes[TORUS]
        # a separate triangle with its corners exactly on a line (the cross product is exactly 0)
        flat = np.vstack([V, [[3.0, 0.0, 0.0], [4.0, 0.0, 0.0], [5.0, 0.0, 0.0]]])
        segment = np.array([[len(V), len(V) + 2, len(V) + 1]])
        cases.append(raises("a zero-area triangle (three corners on a line)", [Step("cotangent_matrix", (flat, np.vstack([F, segment])))]))
        cases.append(raises("F has a negative index", [Step("cotangent_matrix", (V, np.vstack([F, [[0, 1, -1]]])))]))
        return cases

    def verify(self, case, got, expected):
        V, F = case.args()
        n = len(V)
        L = as_matrix(got, (n, n), "L")
        want = as_matrix(expected, (n, n), "the reference's L")
        scale = max_abs(want)
        ok, where = close(L, want, DIRECT_RTOL, scale)
        hint = ""
        if not ok:
            hint = next((why for why, wrong in _cotangent_variants(case).items() if _matches(L, wrong, DIRECT_RTOL, scale)), "")
        return [sparse_verdict(got), verdict("L matches ½ (cot α + cot β)", ok, f"{where}{hint}")]


# --- the steps ----------------------------------------------------------------------------------


def _barycentric_masses(V: np.ndarray, F: np.ndarray) -> np.ndarray:
    e1, e2 = V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]
    if V.shape[1] == 2:
        area = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    else:
        area = 0.5 * np.linalg.norm(np.cross(e1, e2), axis=1)
    return np.bincount(F.ravel(), weights=np.repeat(area / 3.0, 3), minlength=len(V))


def critical_step(L: sp.spmatrix, m: np.ndarray) -> float:
    """``2 / λ_max`` of ``-M⁻¹ L``: the largest stable explicit step."""
    s = 1.0 / np.sqrt(m)
    S = sp.diags(s) @ (-sp.csr_matrix(L)) @ sp.diags(s)  # symmetric, same eigenvalues as -M⁻¹ L
    v0 = np.linspace(1.0, 2.0, len(m))  # a fixed start: ARPACK's random one would make h differ between runs in its last bits
    return 2.0 / float(spla.eigsh(S, k=1, which="LA", v0=v0, return_eigenvectors=False)[0])


def step_inputs(rng: np.random.Generator) -> list[tuple[str, np.ndarray, np.ndarray, np.ndarray, float]]:
    """``(label, U, L, m, h)`` for the step checks; ``L`` dense (the wire carries arrays)."""
    meshes = smoothing_meshes(rng)
    out = []

    def noisy(V, amount=0.02):
        return V + amount * rng.normal(size=V.shape)

    V, F = meshes[TORUS]
    L, m = cotangent_matrix(V, F), _barycentric_masses(V, F)
    h = critical_step(L, m)
    out.append(("noisy 3D torus, cotangent L, barycentric masses, h = half the critical step", noisy(V), L, m, 0.5 * h))
    out.append(("noisy 3D torus, cotangent L, barycentric masses, h = 3 x the critical step (unstable, the formula still)", noisy(V), L, m, 3.0 * h))
    out.append(("noisy 3D torus, cotangent L, h = 1000 x the critical step", noisy(V), L, m, 1000.0 * h))
    V, F = meshes[DISC]
    Lu = uniform_laplacian(V, F)
    out.append(("2D disc with holes, uniform L, unit masses, h = 0.1", noisy(V), Lu, np.ones(len(V)), 0.1))
    out.append(("2D disc with holes, uniform L, masses = degrees (umbrella step), h = 1", noisy(V), Lu, -Lu.diagonal(), 1.0))
    V, F = meshes[JITTERED]
    L = cotangent_matrix(V, F)
    out.append(("a scalar function U (n, 1) on the jittered grid, cotangent L, masses from 1e-3 to 1e3, h = 0.01", rng.normal(size=(len(V), 1)), L,
                10.0 ** rng.uniform(-3, 3, len(V)), 0.01))
    V, F = meshes[TWO]
    L, m = cotangent_matrix(V, F), _barycentric_masses(V, F)
    out.append(("two 2D components far from the origin, cotangent L, h = 0.05", noisy(V) + [50.0, -30.0], L, m, 0.05))
    V, F = meshes[LONELY]
    L, m = cotangent_matrix(V, F), np.maximum(_barycentric_masses(V, F), 0.01)
    out.append(("3D torus with a lonely vertex (zero row of L), h = 0.02", noisy(V), L, m, 0.02))
    V, F = meshes[BAR]
    L, m = cotangent_matrix(V, F), _barycentric_masses(V, F)
    out.append(("3D bar, U with 5 columns, h = 0", rng.normal(size=(len(V), 5)), L, m, 0.0))
    return [(label, U, np.asarray(sp.csr_matrix(L).toarray()), np.asarray(m, float), float(h)) for label, U, L, m, h in out]


def bad_step_inputs(function: str, rng: np.random.Generator) -> list[Case]:
    """The contract's ``ValueError`` cases of a step."""
    V, F = smoothing_meshes(rng)[GRID]
    L, m = cotangent_matrix(V, F).toarray(), _barycentric_masses(V, F)
    zero_mass = m.copy()
    zero_mass[rng.integers(len(m))] = 0.0
    bad = [
        ("h = -0.1 < 0", (V, L, m, -0.1)),
        ("a zero mass", (V, L, zero_mass, 0.1)),
        ("negative masses", (V, L, -m, 0.1)),
        ("L of shape (n - 1, n - 1)", (V, L[:-1, :-1], m, 0.1)),
        ("m of shape (n - 1,)", (V, L, m[:-1], 0.1)),
        ("U of shape (n,), not (n, d)", (V[:, 0].copy(), L, m, 0.1)),
    ]
    return [raises(label, [Step(function, args)]) for label, args in bad]


def _abs_product(L: np.ndarray, U: np.ndarray) -> np.ndarray:
    return np.abs(L) @ np.abs(U)


class ExplicitSmoothingStepChecks(FunctionChecks):
    function = "explicit_smoothing_step"
    description = "U + h M⁻¹ L U for cotangent and uniform L, any masses and step sizes (stable or not), columns of any number"

    def cases(self, rng):
        return [Case.call(label, self.function, U, L, m, h) for label, U, L, m, h in step_inputs(rng)] + bad_step_inputs(self.function, rng)

    def verify(self, case, got, expected):
        U, L, m, h = case.args()
        out = as_array(got, U.shape, "U'")
        want = as_array(expected, U.shape, "the reference's U'")
        scale = float(np.max(np.abs(U) + (h / m)[:, None] * _abs_product(L, U)))
        ok, where = close(out, want, EXPLICIT_RTOL, scale)
        hint = ""
        if not ok:
            update = L @ U
            variants = {
                " (the update is subtracted: L is negative semidefinite, the step adds h M⁻¹ L U)": U - (h / m)[:, None] * update,
                " (the masses are ignored: divide each row's update by m_i)": U + h * update,
                " (the update is multiplied by the masses: divide by them)": U + h * m[:, None] * update,
                " (that is the update alone: return U + h M⁻¹ L U)": (h / m)[:, None] * update,
            }
            hint = next((why for why, wrong in variants.items() if _matches(out, wrong, EXPLICIT_RTOL, scale)), "")
        # Σ_i m_i u'_i - Σ_i m_i u_i = h 1ᵀ L U = 0: each term rounds to 1e-16 of m_i times its row's scale
        moved = np.abs(m @ out - m @ U)
        allowed = EXPLICIT_RTOL * (m @ (np.abs(U) + (h / m)[:, None] * _abs_product(L, U)))
        return [
            verdict("U' = U + h M⁻¹ L U", ok, f"{where} (vertex, coordinate){hint}"),
            verdict("mass-weighted centroid kept", bool(np.all(moved <= allowed)), f"Σ m_i u'_i moved by {moved.max():.3g} from Σ m_i u_i"),
        ]


def _solve(A: sp.spmatrix, B: np.ndarray) -> np.ndarray:
    return np.asarray(spla.splu(sp.csc_matrix(A)).solve(B)).reshape(B.shape)


class ImplicitSmoothingStepChecks(FunctionChecks):
    function = "implicit_smoothing_step"
    description = "the solution of (M - h L) U' = M U: small to huge steps, uniform and cotangent L, masses over six orders of magnitude, one or several columns"

    def cases(self, rng):
        return [Case.call(label, self.function, U, L, m, h) for label, U, L, m, h in step_inputs(rng)] + bad_step_inputs(self.function, rng)

    def verify(self, case, got, expected):
        U, L, m, h = case.args()
        out = as_array(got, U.shape, "U'")
        want = as_array(expected, U.shape, "the reference's U'")
        residual = m[:, None] * out - h * (L @ out) - m[:, None] * U
        size = np.max(np.abs(m[:, None] * U) + h * _abs_product(L, out), axis=0)  # per column
        worst = np.unravel_index(int(np.argmax(np.abs(residual) / np.maximum(size, 1e-300))), residual.shape)
        solves = bool(np.all(np.abs(residual) <= RESIDUAL_RTOL * np.maximum(size, np.finfo(float).tiny)))
        scale = float(np.max(np.abs(want)))
        ok, where = close(out, want, SOLVE_RTOL, scale)
        hint = ""
        if not (ok and solves):
            hint = next((why for why, wrong in self._variants(case).items() if wrong is not None and _matches(out, wrong, 1e-6, scale)), "")
        # Σ m_i u'_i - Σ m_i u_i = 1ᵀ residual + h 1ᵀ L U', and 1ᵀ L = 0 up to roundoff
        moved = np.abs(m @ out - m @ U)
        allowed = RESIDUAL_RTOL * (m @ np.abs(U) + h * np.sum(_abs_product(L, out), axis=0))
        return [
            verdict("solves (M - h L) U' = M U", solves, f"residual {float(residual[worst]):.3g} at {tuple(int(i) for i in worst)} (vertex, coordinate){hint}"),
            verdict("mass-weighted centroid kept", bool(np.all(moved <= allowed)), f"Σ m_i u'_i moved by {moved.max():.3g} from Σ m_i u_i"),
            verdict("U' is the unique solution", ok, f"{where} (vertex, coordinate){hint}"),
        ]

    @staticmethod
    def _variants(case: Case) -> dict[str, np.ndarray | None]:
        """Wrong systems students solve, computed once per case: a match names the mistake."""

        def compute():
            U, L, m, h = case.args()
            L = sp.csr_matrix(L)
            M = sp.diags(m)
            n = len(U)
            found = {
                " (the right-hand side is M U, not U)": _solve(M - h * L, U),
                " (the masses are missing: (I - h L) U' = U is another equation)": _solve(sp.identity(n) - h * L, U),
                " (that is the explicit step U + h M⁻¹ L U)": U + (h / m)[:, None] * (L @ U),
            }
            try:
                with np.errstate(all="ignore"):
                    plus = _solve(M + h * L, m[:, None] * U)
                found[" (the sign of h L is flipped: the system is (M - h L) U' = M U)"] = plus if np.all(np.isfinite(plus)) else None
            except RuntimeError:  # M + h L is singular
                pass
            return found

        return once_per_case(case, "implicit variants", compute)
