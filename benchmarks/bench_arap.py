"""Reference ARAP against libigl on a ~50k-vertex twisted bar.

Both solvers get the same mesh, handles (the two end faces), start (the rest
pose with the handle rows moved) and number of spokes-and-rims iterations.
Runs alternate between the two in one process so that both see the same load
on a shared machine; the figures are medians over the runs, and the spread of
the per-run ratio is printed too. Wall-clock and CPU (process) times are both
reported: on a loaded machine the CPU times are the steadier ones (both solvers
run on one thread).

The local step's rotation fit is timed on its own as well: the reference's
``optimal_rotation`` (Horn's quaternion), the iteration's
``cell_rotations_transposed`` (the polar formula) and the textbook batched
``np.linalg.svd`` with the sign fix, on the ``(n, 3, 3)`` covariances of the
solved bar.

The floor: what an iteration cannot go below with this factorization and
this rotation fit, the two triangular solves with the prefactored matrix
(``data.solver`` on one global step's right-hand side) plus the 3x3
rotation fits an iteration makes (``cell_rotations_transposed`` on the cells
with a free vertex around them), each timed alone on the solved bar's
inputs; the floor's share of the iteration's CPU time says how much the
rest (two sparse products, energy, bookkeeping) adds.

Run with ``.venv/bin/python -m benchmarks.bench_arap``.
"""

from __future__ import annotations

import time

import igl
import numpy as np

from reference.arap import arap_precompute, arap_solve, cell_rotations_transposed
from reference.sign_correction import optimal_rotation
from starter.shapes import bar

# nx = 4 ny = 4 nz cells; (nx+1)(ny+1)(nz+1) - (nx-1)(ny-1)(nz-1) = 50 564 vertices
NX, NY, NZ = 212, 53, 53
TWIST = np.pi / 2
ITERATIONS = 10
RUNS = 5
PRECOMPUTE_RUNS = 3


def twisted_bar():
    """The bar, its end-face handles and their positions with the right end turned by ``TWIST``.

    Returns
    -------
    V : (n, 3) numpy.ndarray
    F : (f, 3) numpy.ndarray of int64
    handles : (h,) numpy.ndarray of int64
    handle_positions : (h, 3) numpy.ndarray
    """
    V, F = bar(length=4.0, width=1.0, height=1.0, nx=NX, ny=NY, nz=NZ)
    left = np.flatnonzero(V[:, 0] == 0.0)
    right = np.flatnonzero(V[:, 0] == 4.0)
    handles = np.concatenate([left, right])
    center = V[right].mean(axis=0)
    c, s = np.cos(TWIST), np.sin(TWIST)
    turn = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    return V, F, handles, np.vstack([V[left], (V[right] - center) @ turn.T + center])


def igl_precompute(V, F, handles, iterations):
    data = igl.ARAPData()
    data.energy = igl.ARAP_ENERGY_TYPE_SPOKES_AND_RIMS
    data.max_iter = iterations
    igl.arap_precomputation(V, F, V.shape[1], handles.astype(np.int32), data)
    return data


def timed(f, *args, **kwargs):
    """``((wall seconds, CPU seconds), f(*args, **kwargs))``."""
    wall, cpu = time.perf_counter(), time.process_time()
    result = f(*args, **kwargs)
    return (time.perf_counter() - wall, time.process_time() - cpu), result


def svd_rotations(S):
    """The textbook local step: batched SVD, flipping the last singular vector where det < 0."""
    U, _, Vt = np.linalg.svd(S)
    Vt[np.linalg.det(U @ Vt) < 0, -1, :] *= -1.0
    return np.swapaxes(U @ Vt, 1, 2)


def main(iterations=ITERATIONS, runs=RUNS, precompute_runs=PRECOMPUTE_RUNS):
    """Time both solvers side by side and print the figures.

    Parameters
    ----------
    iterations : int
        Local-global iterations per solve.
    runs : int
        Solves per solver (alternating).
    precompute_runs : int
        Precomputations per solver (alternating).

    Returns
    -------
    dict
        ``vertices``, ``faces``, ``handles``, ``iterations``, ``runs``;
        ``precompute_s`` and ``igl_precompute_s`` (wall, medians);
        ``per_iteration_s`` and ``igl_per_iteration_s`` (wall, medians);
        ``ratio`` (median over runs of ours / igl per iteration, wall),
        ``ratio_min``, ``ratio_max``; the same with CPU time
        (``per_iteration_cpu_s``, ``igl_per_iteration_cpu_s``, ``ratio_cpu``,
        ``ratio_cpu_min``, ``ratio_cpu_max``); ``rotations_cpu_s``,
        ``polar_rotations_cpu_s`` and ``svd_rotations_cpu_s``, one local
        step's rotation fit by ``optimal_rotation``, ``cell_rotations_transposed``
        and the batched SVD (medians);
        ``moving_cells``, the cells with a free vertex in their one-ring
        (the others are fitted once per solve) and ``moving_rotations_cpu_s``,
        their rotation fit (median); ``triangular_solves_cpu_s``, one
        prefactored solve (median); ``floor_cpu_s``, the last two summed, and ``floor_cpu_s_range``, the spread
        of the per-run sums; ``iteration_over_floor`` (the iteration's median
        CPU time over the floor), ``floor_share`` (its inverse: the fraction
        of the floor the iteration reaches) and ``floor_over_igl``;
        ``max_diff_rel_diag``, the largest ``|U - U_igl|`` over the bounding
        box diagonal.
    """
    V, F, handles, target = twisted_bar()
    start = V.copy()
    start[handles] = target

    pre, pre_igl = [], []
    for _ in range(precompute_runs):
        t, data = timed(arap_precompute, V, F, handles)
        pre.append(t)
        t, data_igl = timed(igl_precompute, V, F, handles, iterations)
        pre_igl.append(t)

    ours, theirs = [], []
    for _ in range(runs):
        t, (U, _) = timed(arap_solve, data, target, iterations=iterations)
        ours.append(np.array(t) / iterations)
        t, U_igl = timed(igl.arap_solve, target, data_igl, start)
        theirs.append(np.array(t) / iterations)
    ours, theirs = np.array(ours), np.array(theirs)
    ratios = ours / theirs

    n, d = V.shape
    S = (data.covariance_operator @ U).reshape(n, d, d)
    # an iteration fits the cells with a free vertex around them (the others once per solve)
    S_moving = S[data.moving_cells]
    rhs = data.rhs_operator @ cell_rotations_transposed(S).reshape(n * d, d)
    rhs += data.L_free_handles @ target
    x = np.empty_like(rhs)
    fit, fit_svd, solves, fit_all, fit_polar = [], [], [], [], []
    for _ in range(max(runs, 3) * 4):
        fit.append(timed(cell_rotations_transposed, S_moving)[0])
        solves.append(timed(data.solver.solve_into, rhs, x)[0])
        if len(fit_svd) < runs:
            fit_all.append(timed(optimal_rotation, S)[0])
            fit_polar.append(timed(cell_rotations_transposed, S)[0])
            fit_svd.append(timed(svd_rotations, S)[0])
    spread = np.array(fit)[:, 1] + np.array(solves)[:, 1]
    fit, fit_svd, solves = np.median(fit, axis=0), np.median(fit_svd, axis=0), np.median(solves, axis=0)
    fit_all, fit_polar = np.median(fit_all, axis=0), np.median(fit_polar, axis=0)
    floor = fit[1] + solves[1]

    diag = float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))
    median = np.median
    figures = {
        "vertices": n,
        "faces": len(F),
        "handles": len(handles),
        "iterations": iterations,
        "runs": runs,
        "precompute_s": float(median([t[0] for t in pre])),
        "igl_precompute_s": float(median([t[0] for t in pre_igl])),
        "per_iteration_s": float(median(ours[:, 0])),
        "igl_per_iteration_s": float(median(theirs[:, 0])),
        "ratio": float(median(ratios[:, 0])),
        "ratio_min": float(ratios[:, 0].min()),
        "ratio_max": float(ratios[:, 0].max()),
        "per_iteration_cpu_s": float(median(ours[:, 1])),
        "igl_per_iteration_cpu_s": float(median(theirs[:, 1])),
        "ratio_cpu": float(median(ratios[:, 1])),
        "ratio_cpu_min": float(ratios[:, 1].min()),
        "ratio_cpu_max": float(ratios[:, 1].max()),
        "rotations_cpu_s": float(fit_all[1]),
        "polar_rotations_cpu_s": float(fit_polar[1]),
        "svd_rotations_cpu_s": float(fit_svd[1]),
        "moving_cells": int(data.moving_cells.size),
        "moving_rotations_cpu_s": float(fit[1]),
        "triangular_solves_cpu_s": float(solves[1]),
        "floor_cpu_s": float(floor),
        "floor_cpu_s_range": f"{spread.min():.4f}-{spread.max():.4f}",
        "iteration_over_floor": float(np.median(ours[:, 1]) / floor),
        "floor_share": float(floor / np.median(ours[:, 1])),
        "floor_over_igl": float(floor / np.median(theirs[:, 1])),
        "max_diff_rel_diag": float(np.abs(U - U_igl).max() / diag),
    }
    print(f"ARAP, spokes and rims, bar twisted by {np.degrees(TWIST):.0f} degrees")
    print(f"mesh: {n} vertices, {len(F)} faces, {len(handles)} handles; "
          f"{iterations} iterations x {runs} runs, alternating")
    print(f"{'':28s}{'reference':>12s}{'libigl':>12s}")
    print(f"{'precompute, wall (s)':28s}{figures['precompute_s']:12.3f}{figures['igl_precompute_s']:12.3f}")
    for label, key in (("wall", ""), ("CPU", "_cpu")):
        print(f"{'per iteration, ' + label + ' (ms)':28s}{1e3 * figures['per_iteration' + key + '_s']:12.1f}"
              f"{1e3 * figures['igl_per_iteration' + key + '_s']:12.1f}")
        print(f"  ratio reference / libigl, {label}: median {figures['ratio' + key]:.2f}, "
              f"range {figures['ratio' + key + '_min']:.2f}-{figures['ratio' + key + '_max']:.2f}")
    print(f"local step, {n} rotations, CPU (ms): optimal_rotation {1e3 * figures['rotations_cpu_s']:.1f}, "
          f"cell_rotations_transposed {1e3 * figures['polar_rotations_cpu_s']:.1f}, "
          f"batched np.linalg.svd {1e3 * figures['svd_rotations_cpu_s']:.1f}")
    print(f"floor on this machine, CPU (ms): the two triangular solves {1e3 * figures['triangular_solves_cpu_s']:.1f} + the rotation fits "
          f"of the {figures['moving_cells']} cells with a free vertex {1e3 * figures['moving_rotations_cpu_s']:.1f} = {1e3 * floor:.1f} (range {figures['floor_cpu_s_range']} s); "
          f"the iteration ({1e3 * figures['per_iteration_cpu_s']:.1f}) takes {figures['iteration_over_floor']:.2f}x the floor, "
          f"so the floor is {100 * figures['floor_share']:.0f}% of it (and {figures['floor_over_igl']:.2f} of libigl's iteration)")
    print(f"max |U - U_igl| / bbox diagonal: {figures['max_diff_rel_diag']:.1e}")
    return figures


if __name__ == "__main__":
    main()
