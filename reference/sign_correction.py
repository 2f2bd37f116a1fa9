"""Stage 02, sign correction: the best rotation (``det R = +1``), not just the best orthogonal map."""

import numpy as np

from reference.shape_matching import centroid, covariance_matrix
from starter.validation import as_square_matrices


def optimal_rotation(S):
    """Rotation maximizing ``tr(R S)``, for one matrix or a stack.

    Parameters
    ----------
    S : (d, d) or (k, d, d) array_like of float
        ``d`` in {2, 3}, typically covariance matrices.

    Returns
    -------
    R : numpy.ndarray, same shape as ``S``
        Rotations (orthonormal, ``det R = +1``) with ``tr(R S)`` maximal over
        all rotations: ``R = Ũ D Uᵀ`` for the SVD ``S = U Σ Ũᵀ`` with
        ``D = diag(1, ..., 1, det(Ũ Uᵀ))``, which flips the singular vector
        of the smallest singular value when the best orthogonal map is a
        reflection. Any maximizer is returned when ``S`` is rank-deficient.

    Notes
    -----
    2D: ``tr(R S) = cos θ (S₀₀ + S₁₁) + sin θ (S₀₁ - S₁₀)`` is maximal at
    ``θ = atan2(S₀₁ - S₁₀, S₀₀ + S₁₁)``.

    3D (Horn's quaternion method): ``tr(R(q) S) = qᵀ N q`` for the rotation
    ``R(q)`` of a unit quaternion ``q`` and a symmetric 4x4 ``N`` built from
    ``S``, so the best ``q`` is the eigenvector of ``N``'s largest eigenvalue
    ``λ``. ``λ`` is the largest root of ``(λ² - a)² - 8 c λ - 4 b`` with
    ``a = ‖S‖²``, ``b = ‖cof S‖²``, ``c = det S``; Newton's method reaches it
    from above, ``q`` is a column of ``adj(N - λ I)``, and ``R(q)`` is a
    rotation whatever the rounding. This is elementwise numpy code, about ten
    times faster than a batched ``np.linalg.svd`` on the ARAP local step's
    large stacks (see ``benchmarks/bench_arap.py``). Where ``λ`` is (nearly)
    a multiple eigenvalue (rank ≤ 1, or a reflection with two equal small
    singular values) the eigenvector is ill-determined, and those matrices
    use the SVD formula above.
    """
    S = as_square_matrices(S, "S")
    d = S.shape[-1]
    A = S.reshape(-1, d, d)
    k = len(A)
    if d == 2:
        theta = np.arctan2(A[:, 0, 1] - A[:, 1, 0], A[:, 0, 0] + A[:, 1, 1])
        c, s = np.cos(theta), np.sin(theta)
        return np.stack([c, -s, s, c], axis=-1).reshape(S.shape)

    def horn_rotations(X, R):
        """Rotations of the ``(9, m)`` rows of entries of ``S`` into the rows of ``R``; returns the trust mask."""
        # Scale to ‖S‖ = 1 so that the tolerances below are absolute; entries
        # beyond 1e±100 are divided by their largest first to avoid overflow.
        norm2 = np.einsum("im,im->m", X, X)
        if not ((norm2 > 1e-200) & (norm2 < 1e200)).all():
            big = np.abs(X).max(axis=0)
            X = X / np.where(big > 0, big, 1.0)
            norm2 = np.einsum("im,im->m", X, X)
        # zero matrices stay zero and are left to the SVD below
        X = X / np.sqrt(np.where(norm2 > 0, norm2, 1.0))
        s00, s01, s02, s10, s11, s12, s20, s21, s22 = X
        c0 = s11 * s22 - s12 * s21
        c1 = s12 * s20 - s10 * s22
        c2 = s10 * s21 - s11 * s20
        c3 = s02 * s21 - s01 * s22
        c4 = s00 * s22 - s02 * s20
        c5 = s01 * s20 - s00 * s21
        c6 = s01 * s12 - s02 * s11
        c7 = s02 * s10 - s00 * s12
        c8 = s00 * s11 - s01 * s10
        det = s00 * c0 + s01 * c1 + s02 * c2
        b = c0 * c0 + c1 * c1 + c2 * c2 + c3 * c3 + c4 * c4 + c5 * c5 + c6 * c6 + c7 * c7 + c8 * c8
        # With a = ‖S‖² = 1: λ² = 1 + 2u and u² = b + 2 det λ (u = σ₁σ₂ ± σ₁σ₃ ± σ₂σ₃).
        # Cauchy-Schwarz gives u ≤ √(3b); substituting that bound once more gives
        # an upper bound of λ that is exact when det S = 0 (flat one-rings).
        lam = np.sqrt(1.0 + 2.0 * np.sqrt(3.0 * b))
        lam = np.sqrt(1.0 + 2.0 * np.sqrt(b + 2.0 * np.abs(det) * lam))
        b4, det8 = 4.0 * b, 8.0 * det
        for step in range(12):
            l2a = lam * lam - 1.0
            p = l2a * l2a - b4 - det8 * lam
            dp = 4.0 * lam * l2a - det8
            if step >= 2:
                # Above the largest root of a real-rooted quartic 0 ≤ λ - λ₁ ≤ 4 p / p',
                # and q's error is below 192 p / p'²; 1e-13 covers the rounding of b
                # and det. Trusted: q's error < 1e-8, so tr(R S) is within 1e-15.
                trusted = np.abs(p) + 1e-13 < (1e-8 / 192.0) * (dp * dp)
                if trusted.all() or step == 11:
                    break
            # p' is small only near a multiple root: those matrices go to the SVD anyway
            lam -= p / np.where(dp > 0.01, dp, np.inf)
        # N - λ I, with Horn's symmetric N: tr(R(q) S) = qᵀ N q for q = (w, x, y, z)
        n00 = s00 + s11 + s22 - lam
        n11 = s00 - s11 - s22 - lam
        n22 = s11 - s00 - s22 - lam
        n33 = s22 - s00 - s11 - lam
        n01, n02, n03 = s12 - s21, s20 - s02, s01 - s10
        n12, n13, n23 = s01 + s10, s02 + s20, s12 + s21
        # adj(N - λ I) = -Π(λ - λ_j) q qᵀ, from the 2x2 minors of rows (0, 1) and (2, 3)
        m0 = n00 * n11 - n01 * n01
        m1 = n00 * n12 - n01 * n02
        m2 = n00 * n13 - n01 * n03
        m3 = n01 * n12 - n11 * n02
        m4 = n01 * n13 - n11 * n03
        m5 = n02 * n13 - n12 * n03
        r1 = n02 * n23 - n03 * n22
        r2 = n02 * n33 - n03 * n23
        r3 = n12 * n23 - n13 * n22
        r4 = n12 * n33 - n13 * n23
        r5 = n22 * n33 - n23 * n23
        j00 = n11 * r5 - n12 * r4 + n13 * r3
        j01 = n02 * r4 - n01 * r5 - n03 * r3
        j02 = n13 * m5 - n23 * m4 + n33 * m3
        j03 = n22 * m4 - n12 * m5 - n23 * m3
        j11 = n00 * r5 - n02 * r2 + n03 * r1
        j12 = n23 * m2 - n03 * m5 - n33 * m1
        j13 = n02 * m5 - n22 * m2 + n23 * m1
        j22 = n03 * m4 - n13 * m2 + n33 * m0
        j23 = n12 * m2 - n02 * m4 - n23 * m0
        j33 = n02 * m3 - n12 * m1 + n22 * m0
        # the column with the largest diagonal entry is the most accurate multiple of q
        d0, d1, d2, d3 = np.abs(j00), np.abs(j11), np.abs(j22), np.abs(j33)
        first = (d0 >= d1) & (d0 >= d2) & (d0 >= d3)
        second = (d1 >= d2) & (d1 >= d3)
        third = d2 >= d3

        def column_entry(e0, e1, e2, e3):
            return np.where(first, e0, np.where(second, e1, np.where(third, e2, e3)))

        w = column_entry(j00, j01, j02, j03)
        x = column_entry(j01, j11, j12, j13)
        y = column_entry(j02, j12, j22, j23)
        z = column_entry(j03, j13, j23, j33)
        # rotation of the unit quaternion q / |q|
        scale = 2.0 / np.where(trusted, w * w + x * x + y * y + z * z, 1.0)
        sx, sy, sz = scale * x, scale * y, scale * z
        wx, wy, wz = w * sx, w * sy, w * sz
        xx, xy, xz = x * sx, x * sy, x * sz
        yy, yz, zz = y * sy, y * sz, z * sz
        np.subtract(1.0, yy + zz, out=R[0])
        np.subtract(xy, wz, out=R[1])
        np.add(xz, wy, out=R[2])
        np.add(xy, wz, out=R[3])
        np.subtract(1.0, xx + zz, out=R[4])
        np.subtract(yz, wx, out=R[5])
        np.subtract(xz, wy, out=R[6])
        np.add(yz, wx, out=R[7])
        np.subtract(1.0, xx + yy, out=R[8])
        return trusted

    def svd_rotations(B):
        U, _, Vt = np.linalg.svd(B)
        Vt[np.linalg.det(U @ Vt) < 0, -1, :] *= -1.0
        return np.swapaxes(U @ Vt, 1, 2)

    # Blocks that fit in the CPU cache: the method makes ~300 elementwise passes.
    block = 4096
    R = np.empty((k, 9))
    trusted = np.empty(k, dtype=bool)
    for start in range(0, k, block):
        stop = min(start + block, k)
        # one contiguous row per matrix entry
        X = A[start:stop].reshape(-1, 9).T.copy()
        trusted[start:stop] = horn_rotations(X, R[start:stop].T)
    R = R.reshape(k, 3, 3)
    if not trusted.all():
        R[~trusted] = svd_rotations(A[~trusted])
    return R.reshape(S.shape)


def rigid_align(P, Q, w=None):
    """Rotation and translation best aligning ``P`` to ``Q``.

    Parameters
    ----------
    P : (k, d) array_like of float
        Source points, ``d`` in {2, 3}.
    Q : (k, d) array_like of float
        Target points, ``Q[i]`` corresponds to ``P[i]``.
    w : (k,) array_like of float, optional
        Non-negative weights with a positive sum; default all ones.

    Returns
    -------
    R : (d, d) numpy.ndarray
        Rotation (``det R = +1``).
    t : (d,) numpy.ndarray
        Translation; ``(R, t)`` minimizes ``Σ w_i ‖R p_i + t - q_i‖²`` over
        rotations and translations.
    """
    S = covariance_matrix(P, Q, w)
    R = optimal_rotation(S)
    t = centroid(Q, w) - R @ centroid(P, w)
    return R, t
