"""Checks of stage 05, linear blend skinning: the LBS matrix layout and the deformed positions."""

from __future__ import annotations

import numpy as np

from grader.checks.base import Case, FunctionChecks, as_array, close, verdict
from .generators import relabel
from .generators import random_rotation
from starter import shapes

#: Relative tolerance of LBS outputs: products and sums of the inputs, no solve.
LBS_RTOL = 1e-12


def _weights(rng: np.random.Generator, n: int, m: int, normalized: bool = True) -> np.ndarray:
    """``(n, m)`` non-negative weights with some zeros (local support); rows sum to 1 when ``normalized``."""
    W = rng.uniform(0.0, 1.0, (n, m)) * (rng.uniform(size=(n, m)) < 0.7)
    W[np.arange(n), rng.integers(0, m, n)] += 0.1  # no zero rows
    return W / W.sum(axis=1, keepdims=True) if normalized else W


def _meshes(rng: np.random.Generator) -> list[tuple[str, np.ndarray]]:
    """Small 2D and 3D meshes in random vertex order (only ``V`` matters for LBS)."""
    meshes = [
        ("2D grid", shapes.grid_2d(int(rng.integers(4, 8)), 4, width=2.0)),
        ("3D bar", shapes.bar(nx=int(rng.integers(5, 9)), ny=2, nz=2)),
        ("2D disc with a hole", shapes.disc_with_holes(1, 0.05)),
        ("3D capped cylinder", shapes.cylinder(n_around=7, n_along=4)),
    ]
    return [(label, relabel(V, F, rng)[0] + rng.normal(0.0, 2.0, V.shape[1])) for label, (V, F) in meshes]


def _affine(rng: np.random.Generator, m: int, d: int) -> np.ndarray:
    """``(m, d, d+1)`` random affine transforms ``[A | t]``."""
    return np.concatenate([rng.normal(size=(m, d, d)), rng.normal(0.0, 2.0, (m, d, 1))], axis=2)


class LbsMatrixChecks(FunctionChecks):
    function = "lbs_matrix"
    description = "M[i, j(d+1)+c] = W[i, j]·[v_i; 1][c] in 2D and 3D, one or several handles, dense or sparse"

    def cases(self, rng):
        (l2, V2), (l3, V3), (ld, Vd), (lc, Vc) = _meshes(rng)
        picks = [
            (f"{l2}, 3 handles", V2, _weights(rng, len(V2), 3)),
            (f"{l3}, 4 handles", V3, _weights(rng, len(V3), 4)),
            (f"{ld}, one handle", Vd, np.ones((len(Vd), 1))),
            (f"{lc}, 5 handles, unnormalized weights", Vc, _weights(rng, len(Vc), 5, normalized=False)),
            (f"{l2}, 2 handles, unnormalized weights", V2, _weights(rng, len(V2), 2, normalized=False)),
        ]
        return [Case.call(label, "lbs_matrix", V, W) for label, V, W in picks]

    def verify(self, case, got, expected):
        V, W = case.args()
        (n, d), m = V.shape, W.shape[1]
        M = as_array(got, (n, m * (d + 1)), "M")
        want = as_array(expected, (n, m * (d + 1)), "the reference's M")
        ok, where = close(M, want, LBS_RTOL, scale=float(np.abs(want).max()))
        hint = ""
        if not ok and m > 1:
            by_coordinate = want.reshape(n, m, d + 1).transpose(0, 2, 1).reshape(n, -1)
            if close(M, by_coordinate, LBS_RTOL, float(np.abs(want).max()))[0]:
                hint = " (columns are ordered coordinate-major, c·m + j; the contract orders them handle-major, j(d+1) + c)"
        return [verdict("M matches the layout M[i, j(d+1)+c] = W[i, j]·[v_i; 1][c]", ok, where + hint)]


class LbsChecks(FunctionChecks):
    function = "lbs"
    description = "identity transforms give V, one rigid transform for all handles moves the mesh rigidly, random affine transforms"

    def cases(self, rng):
        (l2, V2), (l3, V3), (ld, Vd), (lc, Vc) = _meshes(rng)
        cases = []

        def add(label, kind, V, W, T):
            case = Case.call(label, "lbs", V, W, T)
            case.context["kind"] = kind
            cases.append(case)

        for label, V, m in ((l2, V2, 3), (l3, V3, 4)):
            d = V.shape[1]
            add(f"{label}, identity transforms", "identity", V, _weights(rng, len(V), m), np.tile(np.eye(d, d + 1), (m, 1, 1)))
        for label, V, m in ((ld, Vd, 2), (lc, Vc, 5)):
            d = V.shape[1]
            rigid = np.c_[random_rotation(rng, d), rng.normal(0.0, 2.0, d)]
            add(f"{label}, the same rigid transform for every handle", "rigid", V, _weights(rng, len(V), m), np.tile(rigid, (m, 1, 1)))
        add(f"{l2}, random affine transforms", "affine", V2, _weights(rng, len(V2), 4), _affine(rng, 4, 2))
        add(f"{l3}, random affine transforms", "affine", V3, _weights(rng, len(V3), 3), _affine(rng, 3, 3))
        add(f"{lc}, affine transforms, unnormalized weights", "affine", Vc, _weights(rng, len(Vc), 2, normalized=False), _affine(rng, 2, 3))
        return cases

    def verify(self, case, got, expected):
        V, W, T = case.args()
        U = as_array(got, V.shape, "U")
        want = as_array(expected, V.shape, "the reference's U")
        scale = float(np.abs(want).max())
        verdicts = []
        kind = case.context["kind"]
        if kind == "identity":
            ok, where = close(U, V, LBS_RTOL, scale)
            verdicts.append(verdict("identity transforms return V", ok, where))
        elif kind == "rigid":
            ok, where = close(U, V @ T[0, :, :-1].T + T[0, :, -1], LBS_RTOL, scale)
            verdicts.append(verdict("one rigid transform for every handle moves the mesh rigidly", ok, where))
        ok, where = close(U, want, LBS_RTOL, scale)
        return verdicts + [verdict("U = Σ_j W[i, j] T_j [v_i; 1]", ok, where)]
