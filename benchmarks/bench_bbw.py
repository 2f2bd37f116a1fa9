"""Reference ``bbw`` against ``igl.bbw`` on the ~10k-vertex 2D character.

The mesh is ``starter.shapes.character_2d`` (Triangle, through
``igl.triangle``) with its area bound set for about 10,000 vertices, and four
point handles (head, both hands, left foot), each a mesh vertex. Both solvers
get the same ``(b, bc)``; ``igl.bbw``'s weights are normalized as the
reference's are. Runs alternate between the two in one process so that both
see the same load on a shared machine; the figures are medians over the runs,
with the spread of the per-run ratio. Wall-clock and CPU (process) times are
both reported: on a loaded machine the CPU times are the steadier ones.

BLAS runs on one thread during the timings (``threadpoolctl``): the
reference's dense Cholesky steps (a few hundred unknowns each) gain nothing
from OpenBLAS threads, and on a loaded machine the threads' busy waiting makes
some steps 100x slower (a 200x200 ``cho_factor`` measured 0.3 s instead of
0.2 ms), which would time the machine's load rather than the code.
``igl.bbw`` does not use BLAS; its own threads are left alone (its CPU time
exceeds its wall time).

Run with ``.venv/bin/python -m benchmarks.bench_bbw``.
"""

from __future__ import annotations

import time

import igl
import numpy as np
from threadpoolctl import threadpool_limits

from reference.bounded_biharmonic_weights import bbw, handle_constraints
from starter.shapes import character_2d, character_2d_handles

# character_2d's docstring: 1.3e-4 gives about 10,000 vertices
MAX_AREA = 1.3e-4
POINT_HANDLES = 4  # head, left hand, right hand, left foot
RUNS = 5


def character_problem():
    """The character mesh and the boundary conditions of its first four point handles.

    Returns
    -------
    V : (n, 2) numpy.ndarray
    F : (f, 3) numpy.ndarray of int64
    b : (4,) numpy.ndarray of int64
    bc : (4, 4) numpy.ndarray
    """
    V, F = character_2d(max_area=MAX_AREA)
    points = character_2d_handles(V)["points"][:POINT_HANDLES]
    b, bc = handle_constraints([[int(i)] for i in points])
    return V, F, b, bc


def _timed(run):
    wall, cpu = time.perf_counter(), time.process_time()
    result = run()
    return result, time.perf_counter() - wall, time.process_time() - cpu


def main(runs=RUNS):
    """Time reference ``bbw`` and ``igl.bbw`` side by side and print the figures.

    Parameters
    ----------
    runs : int
        Timed runs of each solver, alternating, after one untimed run each.

    Returns
    -------
    dict
        Sizes; median wall and CPU seconds of each solver; the median ratio
        ours/igl (wall and CPU) with its range over the runs; and the largest
        ``|W - W_igl|`` with igl's weights normalized.
    """
    V, F, b, bc = character_problem()

    def ours():
        return bbw(V, F, b, bc)

    def libigl():
        W = igl.bbw(V, F, b, bc)
        return W / W.sum(axis=1, keepdims=True)

    wall = {"ours": [], "igl": []}
    cpu = {"ours": [], "igl": []}
    with threadpool_limits(limits=1, user_api="blas"):
        W, W_igl = ours(), libigl()
        for _ in range(runs):
            for name, run in (("ours", ours), ("igl", libigl)):
                _, t_wall, t_cpu = _timed(run)
                wall[name].append(t_wall)
                cpu[name].append(t_cpu)
    wall = {k: np.array(v) for k, v in wall.items()}
    cpu = {k: np.array(v) for k, v in cpu.items()}
    wall_ratio = wall["ours"] / wall["igl"]
    cpu_ratio = cpu["ours"] / cpu["igl"]
    figures = {
        "vertices": len(V),
        "faces": len(F),
        "point handles": len(b),
        "runs": runs,
        "ours wall (s)": float(np.median(wall["ours"])),
        "igl wall (s)": float(np.median(wall["igl"])),
        "ratio wall ours/igl": float(np.median(wall_ratio)),
        "ratio wall range": f"{wall_ratio.min():.3f}-{wall_ratio.max():.3f}",
        "ours cpu (s)": float(np.median(cpu["ours"])),
        "igl cpu (s)": float(np.median(cpu["igl"])),
        "ratio cpu ours/igl": float(np.median(cpu_ratio)),
        "ratio cpu range": f"{cpu_ratio.min():.3f}-{cpu_ratio.max():.3f}",
        "max abs(W - W_igl normalized)": float(np.abs(W - W_igl).max()),
    }
    print(f"mesh: {len(V)} vertices, {len(F)} faces; {len(b)} point handles; {runs} alternating runs, BLAS limited to 1 thread")
    for name, label in (("ours", "reference bbw"), ("igl", "igl.bbw")):
        print(
            f"{label:>14}: wall median {np.median(wall[name]):.3f} s "
            f"(runs {', '.join(f'{t:.3f}' for t in wall[name])}), "
            f"cpu median {np.median(cpu[name]):.3f} s"
        )
    print(
        f"ratio ours/igl: wall {figures['ratio wall ours/igl']:.3f} (range {figures['ratio wall range']}), "
        f"cpu {figures['ratio cpu ours/igl']:.3f} (range {figures['ratio cpu range']}); "
        f"required <= 0.5, aim <= 0.25"
    )
    print(f"max |W - W_igl normalized|: {figures['max abs(W - W_igl normalized)']:.2e} (required <= 1e-4)")
    return figures


if __name__ == "__main__":
    main()
