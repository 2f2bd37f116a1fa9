"""Checks of stage 05's dual-quaternion skinning (``LECTURE_CONTRACT.md``).

A dual quaternion and its negative are the same transform, so ``dual_quaternions``
is compared with the reference up to one sign per handle; transforms and skinned
positions are compared directly.
"""

from __future__ import annotations

import numpy as np

from grader.checks.base import Case, FunctionChecks, Step, as_array, close, raises, verdict
from .linear_blend_skinning import _weights as lbs_weights
from .generators import relabel
from .generators import random_rotation
from . import reference as reference_function
from starter import shapes

#: Relative tolerance of quaternion conversions and blends: a few products and one square root.
DQ_RTOL = 1e-10


def _turn(axis, degrees: float) -> np.ndarray:
    """``(3, 3)`` rotation by ``degrees`` about the unit vector ``axis`` (Rodrigues)."""
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
    theta = np.radians(degrees)
    return np.eye(3) + np.sin(theta) * K + (1.0 - np.cos(theta)) * K @ K


def _rigid(rng: np.random.Generator, m: int, half_turns: bool = False) -> np.ndarray:
    """``(m, 3, 4)`` random rigid transforms; with ``half_turns`` the first ones turn by 180° (w = 0) or nearly."""
    R = np.stack([random_rotation(rng, 3) for _ in range(m)])
    if half_turns:
        for j, (axis, degrees) in enumerate([((1, 0, 0), 180.0), ((0, 1, 0), 180.0), ((0, 0, 1), 180.0), ((1, 2, -2), 179.9)][:m]):
            R[j] = _turn(axis, degrees)
    return np.concatenate([R, rng.normal(0.0, 2.0, (m, 3, 1))], axis=2)


def _quaternion_product(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    w1, v1, w2, v2 = p[:, 0], p[:, 1:], q[:, 0], q[:, 1:]
    return np.c_[w1 * w2 - np.einsum("ij,ij->i", v1, v2), w1[:, None] * v2 + w2[:, None] * v1 + np.cross(v1, v2)]


def _skin(V: np.ndarray, W: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Blend the dual quaternions ``Q`` with the weights as given (no sign choice) and move ``V``."""
    T = reference_function("dual_quaternion_transforms")((W @ Q.reshape(len(Q), 8)).reshape(len(V), 2, 4))
    return np.einsum("iab,ib->ia", T[:, :, :3], V) + T[:, :, 3]


class DualQuaternionsChecks(FunctionChecks):
    function = "dual_quaternions"
    description = (
        "unit dual quaternions of random rigid transforms, half turns (w = 0), pure rotations and translations; "
        "a ValueError for a transform that is not rigid"
    )

    def cases(self, rng):
        rotations_only = _rigid(rng, 3)
        rotations_only[:, :, 3] = 0.0
        translations_only = np.concatenate([np.tile(np.eye(3), (3, 1, 1)), rng.normal(0.0, 3.0, (3, 3, 1))], axis=2)
        picks = [
            ("one random rigid transform", _rigid(rng, 1)),
            ("6 random rigid transforms", _rigid(rng, 6)),
            ("half turns about x, y, z and a 179.9° turn, with translations", _rigid(rng, 4, half_turns=True)),
            ("rotations without translation", rotations_only),
            ("translations without rotation", translations_only),
        ]
        scaled, mirrored = _rigid(rng, 3), _rigid(rng, 2)
        scaled[1, :, :3] *= 1.5
        mirrored[0, :, :3] = mirrored[0, :, :3] @ np.diag([1.0, 1.0, -1.0])
        return [Case.call(label, "dual_quaternions", T) for label, T in picks] + [
            # the contract's promise: a ValueError naming T[j] when R_j is not a rotation to 1e-6
            raises("T[1]'s 3x3 part is a rotation scaled by 1.5 (not rigid)", [Step("dual_quaternions", (scaled,))]),
            raises("T[0]'s 3x3 part is a reflection (det -1)", [Step("dual_quaternions", (mirrored,))]),
        ]

    def verify(self, case, got, expected):
        T = case.args()[0]
        m = len(T)
        Q = as_array(got, (m, 2, 4), "Q")
        want = as_array(expected, (m, 2, 4), "the reference's Q")
        sign = np.where(np.einsum("jk,jk->j", Q[:, 0], want[:, 0]) < 0, -1.0, 1.0)  # the real part fixes the sign
        scale = float(np.abs(want).max())
        ok_real, where_real = close(sign[:, None] * Q[:, 0], want[:, 0], DQ_RTOL)
        hint = ""
        if not ok_real:
            if close(np.abs(Q[:, 0][:, [3, 0, 1, 2]]), np.abs(want[:, 0]), DQ_RTOL)[0]:
                hint = " (the scalar part w is last; the contract stores (w, x, y, z), scalar first)"
            elif close(np.abs(Q[:, 0] * [1, -1, -1, -1]), np.abs(want[:, 0]), DQ_RTOL)[0]:
                hint = " (this is the quaternion of Rᵀ, the inverse rotation: check the signs of R[k, j] - R[j, k])"
        verdicts = [verdict("Q[j, 0] is the unit quaternion (w, x, y, z) of R_j, up to sign", ok_real, where_real + hint)]
        ok_dual, where_dual = close(sign[:, None] * Q[:, 1], want[:, 1], DQ_RTOL, scale)
        hint = ""
        if not ok_dual and ok_real:
            t = np.c_[np.zeros(m), T[:, :, 3]]
            if close(Q[:, 1], 0.5 * _quaternion_product(Q[:, 0], t), DQ_RTOL, scale)[0]:
                hint = " (this is ½ q_0 (0, t); the contract's dual part is ½ (0, t) q_0: quaternion products do not commute)"
            elif close(Q[:, 1], _quaternion_product(t, Q[:, 0]), DQ_RTOL, scale)[0]:
                hint = " (missing the factor ½)"
        verdicts.append(verdict("Q[j, 1] = ½ (0, t_j) Q[j, 0], with the same sign as Q[j, 0]", ok_dual, where_dual + hint))
        return verdicts


class DualQuaternionTransformsChecks(FunctionChecks):
    function = "dual_quaternion_transforms"
    description = "rigid transforms of unit, scaled, negated and blended (non-unit) dual quaternions"

    def cases(self, rng):
        ref = reference_function("dual_quaternions")
        Q = ref(_rigid(rng, 5))
        blended = rng.uniform(0.1, 1.0, (4, 5)) @ Q.reshape(5, 8)
        picks = [
            ("unit dual quaternions of 5 rigid transforms", Q),
            ("the same, scaled by 3 and by -0.5", np.concatenate([3.0 * Q[:3], -0.5 * Q[3:]])),
            ("half turns (w = 0)", ref(_rigid(rng, 4, half_turns=True))),
            ("weighted sums of 5 unit dual quaternions (q_0 · q_e != 0)", blended.reshape(4, 2, 4)),
            ("random non-zero dual quaternions", rng.normal(size=(6, 2, 4))),
        ]
        return [Case.call(label, "dual_quaternion_transforms", Q) for label, Q in picks]

    def verify(self, case, got, expected):
        Q = case.args()[0]
        k = len(Q)
        T = as_array(got, (k, 3, 4), "T")
        want = as_array(expected, (k, 3, 4), "the reference's T")
        ok_R, where_R = close(T[:, :, :3], want[:, :, :3], DQ_RTOL)
        hint = ""
        if not ok_R and close(T[:, :, :3].transpose(0, 2, 1), want[:, :, :3], DQ_RTOL)[0]:
            hint = " (R is transposed: it is the rotation of the conjugate quaternion)"
        elif not ok_R and not close(np.einsum("kji,kjl->kil", T[:, :, :3], T[:, :, :3]), np.tile(np.eye(3), (k, 1, 1)), 1e-6)[0]:
            hint = " (R is not a rotation: divide q_0 by its norm first)"
        ok_t, where_t = close(T[:, :, 3], want[:, :, 3], DQ_RTOL, float(np.abs(want[:, :, 3]).max()))
        if not ok_t and ok_R:
            norm = np.linalg.norm(Q[:, 0], axis=1)[:, None]
            if any(close(T[:, :, 3] / norm**p, want[:, :, 3], DQ_RTOL, float(np.abs(want).max()))[0] for p in (1, 2)):
                where_t += " (both q_0 and q_e must be divided by ‖q_0‖ before t = 2 vec(c_e c̄_0))"
        return [
            verdict("R is the rotation of q_0 / ‖q_0‖", ok_R, where_R + hint),
            verdict("t = 2 vec(c_e c̄_0) with c = q / ‖q_0‖", ok_t, where_t),
        ]


class DqsChecks(FunctionChecks):
    function = "dqs"
    description = (
        "one rigid transform for all handles, one-hot rows, a twisted cylinder (no collapse), random rigid poses, "
        "handles across the half turn (antipodal quaternions), unnormalized weights"
    )

    def cases(self, rng):
        cylinder = relabel(*shapes.cylinder(length=3.0, radius=0.4, n_around=10, n_along=8), rng)[0]
        bar = relabel(*shapes.bar(length=2.0, nx=int(rng.integers(5, 9)), ny=3, nz=3), rng)[0] + rng.normal(0.0, 1.0, 3)
        s = (cylinder[:, 0] - cylinder[:, 0].min()) / np.ptp(cylinder[:, 0])
        ramp = np.c_[1.0 - (3 * s**2 - 2 * s**3), 3 * s**2 - 2 * s**3]

        def weights(n, m, normalized=True):
            return lbs_weights(rng, n, m, normalized)

        twist = np.stack([np.eye(3, 4), np.c_[_turn((1, 0, 0), 150.0), [0.5, 0.0, 0.0]]])
        across = np.stack([np.c_[_turn((0, 0, 1), 170.0), np.zeros(3)], np.c_[_turn((0, 0, 1), -170.0), [0.0, 0.3, 0.0]]])
        across = np.concatenate([across, _rigid(rng, 1)])
        one = _rigid(rng, 1)
        cases = []

        def add(label, kind, V, W, T):
            case = Case.call(label, "dqs", V, W, T)
            case.context["kind"] = kind
            cases.append(case)

        add("3D bar, the same rigid transform for all 4 handles", "rigid", bar, weights(len(bar), 4), np.tile(one, (4, 1, 1)))
        add("3D bar, one-hot weight rows, 3 handles", "one-hot", bar, np.eye(3)[rng.integers(0, 3, len(bar))], _rigid(rng, 3))
        add("cylinder twisted by 150° between its ends", "twist", cylinder, ramp, twist)
        add("3D bar, 5 random rigid transforms", "general", bar, weights(len(bar), 5), _rigid(rng, 5))
        add("cylinder, handles at +170° and -170° (antipodal quaternions)", "general", cylinder, weights(len(cylinder), 3), across)
        add("3D bar, unnormalized weights, 3 handles", "general", bar, weights(len(bar), 3, normalized=False), _rigid(rng, 3))
        return cases

    def verify(self, case, got, expected):
        V, W, T = case.args()
        U = as_array(got, V.shape, "U")
        want = as_array(expected, V.shape, "the reference's U")
        scale = float(np.abs(want).max())
        verdicts = []
        kind = case.context["kind"]
        if kind == "rigid":
            ok, where = close(U, V @ T[0, :, :3].T + T[0, :, 3], DQ_RTOL, scale)
            verdicts.append(verdict("one rigid transform for every handle moves the mesh rigidly", ok, where))
        elif kind == "one-hot":
            owner = W.argmax(axis=1)
            ok, where = close(U, np.einsum("iab,ib->ia", T[owner, :, :3], V) + T[owner, :, 3], DQ_RTOL, scale)
            verdicts.append(verdict("a vertex with a one-hot weight row follows its handle exactly", ok, where))
        elif kind == "twist":
            ok, where = close(np.linalg.norm(U[:, 1:], axis=1), np.linalg.norm(V[:, 1:], axis=1), DQ_RTOL, scale)
            verdicts.append(verdict("every cross-section of the twisted cylinder keeps its radius", ok, "radius: " + where))
        ok, where = close(U, want, DQ_RTOL, scale)
        if not ok:
            Q = reference_function("dual_quaternions")(T)
            lbs = np.einsum("ij,jab,ib->ia", W, T[:, :, :3], V) + W @ T[:, :, 3]
            if close(U, lbs, DQ_RTOL, scale)[0]:
                where += " (this is linear blend skinning: blend the dual quaternions, not the matrices)"
            elif close(U, _skin(V, W, Q), DQ_RTOL, scale)[0]:
                where += (
                    " (q̂ and -q̂ are the same transform but blend differently: flip every handle whose q_0 has a "
                    "negative dot product with handle 0's before blending)"
                )
        return verdicts + [verdict("U matches dual-quaternion skinning", ok, where)]
