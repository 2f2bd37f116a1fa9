"""Reference ``bbw`` against ``igl.bbw`` on a ~10k-vertex 2D character.

Run with ``.venv/bin/python -m benchmarks.bench_bbw``. Both solvers run in this
process, alternating, so that the machine's load affects them alike; the
figures are medians over the runs, with the spread of the per-pair ratios.
"""

import time

import igl
import igl.triangle
import numpy as np

from reference.bbw import bbw, handle_constraints

# ~10k vertices: the outline encloses an area of ~2.85, Triangle's 'a' bounds each triangle's area
MAX_TRIANGLE_AREA = 2.85e-4
# head, both hands and the left foot of the figure
HANDLE_TIPS = np.array([[0.0, 1.4], [-1.2, 0.5], [1.2, 0.5], [-0.8, -1.1]])


def gingerbread_outline(k=400):
    """Closed ``(k, 2)`` polygon of a five-lobed figure (head, arms, legs) and its ``(k, 2)`` edges."""
    t = np.linspace(0.0, 2.0 * np.pi, k, endpoint=False)
    r = 1.0 + 0.45 * np.cos(5 * t) + 0.1 * np.cos(10 * t)
    P = np.c_[r * np.cos(t + np.pi / 2), r * np.sin(t + np.pi / 2)]
    E = np.c_[np.arange(k), (np.arange(k) + 1) % k]
    return P, E


def benchmark_mesh():
    """The figure triangulated with quality (min angle 30°) and area bounds: ``(V, F)``."""
    P, E = gingerbread_outline()
    V, F, *_ = igl.triangle.triangulate(P, E, flags=f"pq30a{MAX_TRIANGLE_AREA:.8f}Q")
    return V, F


def main(runs=5):
    """Time reference ``bbw`` and ``igl.bbw`` side by side and print the figures.

    Parameters
    ----------
    runs : int
        Timed runs of each solver (after one untimed warm-up run each).

    Returns
    -------
    dict
        Sizes, median times in seconds, the median ratio ours/igl and its
        range over the runs, and the largest ``|W - W_igl|`` (igl normalized).
    """
    V, F = benchmark_mesh()
    handles = [[int(np.argmin(np.linalg.norm(V - tip, axis=1)))] for tip in HANDLE_TIPS]
    b, bc = handle_constraints(handles)

    def run_ours():
        return bbw(V, F, b, bc)

    def run_igl():
        W = igl.bbw(V, F, b, bc)
        return W / W.sum(axis=1, keepdims=True)

    W, W_igl = run_ours(), run_igl()
    times = {"ours": [], "igl": []}
    for _ in range(runs):
        for name, run in (("ours", run_ours), ("igl", run_igl)):
            start = time.perf_counter()
            run()
            times[name].append(time.perf_counter() - start)
    ours, igl_s = np.array(times["ours"]), np.array(times["igl"])
    ratios = ours / igl_s
    figures = {
        "vertices": len(V),
        "faces": len(F),
        "handles": len(handles),
        "ours_s": float(np.median(ours)),
        "igl_s": float(np.median(igl_s)),
        "ratio": float(np.median(ratios)),
        "ratio_min": float(ratios.min()),
        "ratio_max": float(ratios.max()),
        "max_abs_diff": float(np.abs(W - W_igl).max()),
    }
    print(f"mesh: {figures['vertices']} vertices, {figures['faces']} faces, {figures['handles']} point handles")
    print(f"reference bbw: median {figures['ours_s']:.3f} s  (runs {', '.join(f'{t:.3f}' for t in ours)})")
    print(f"igl.bbw:       median {figures['igl_s']:.3f} s  (runs {', '.join(f'{t:.3f}' for t in igl_s)})")
    print(
        f"ratio ours/igl: median {figures['ratio']:.3f}, range {figures['ratio_min']:.3f}-{figures['ratio_max']:.3f}"
        f"  (required <= 0.5, aim <= 0.25)"
    )
    print(f"max |W - W_igl normalized|: {figures['max_abs_diff']:.2e}  (required <= 1e-4)")
    return figures


if __name__ == "__main__":
    main()
