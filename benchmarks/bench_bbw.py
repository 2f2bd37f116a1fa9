"""Reference ``bbw`` against ``igl.bbw``: the ~10k-vertex 2D character, then a family of shapes.

The mesh is ``starter.shapes.character_2d`` (Triangle, through
``igl.triangle``) with its area bound set for about 10,000 vertices, and four
point handles (head, both hands, left foot), each a mesh vertex. Both solvers
get the same ``(b, bc)``; ``igl.bbw``'s weights are normalized as the
reference's are. Runs alternate between the two in one process so that both
see the same load on a shared machine; the figures are medians over the runs,
with the spread of the per-run ratio. Wall-clock and CPU (process) times are
both reported: on a loaded machine the CPU times are the steadier ones.

BLAS runs on one thread during the timings (``threadpoolctl``, which also
reaches the OpenBLAS that cvxopt's CHOLMOD uses): the reference's small dense
steps gain nothing from OpenBLAS threads, and on a loaded machine the threads'
busy waiting makes some steps 100x slower (a 200x200 ``cho_factor`` measured
0.3 s instead of 0.2 ms), which would time the machine's load rather than the
code.
``igl.bbw`` does not use BLAS; its own threads are left alone (its CPU time
exceeds its wall time).

The **family** (``family()``) times both solvers the same way on nine more
problems (each at least twice, and again until ``igl.bbw`` has taken a second
of CPU: the tetrahedral hand's runs are short and noisy), so that a speed-up
tuned on the character cannot hide a slow shape:
convex, notched, with holes, with thin parts, 2D and tetrahedra, few and many
(20) handles, point handles, bones and regions. Its figure is the worst CPU
ratio over the family (target ≤ 0.5, aim ≤ 0.25) and the largest weight
difference (≤ 1e-4). A member is one entry of ``FAMILY``: a label and a function
returning ``(V, F, handles)``, ``F`` triangles or ``(f, 4)`` tetrahedra.

Run with ``.venv/bin/python -m benchmarks bbw``.
"""

from __future__ import annotations

import time

import igl
import numpy as np
from threadpoolctl import threadpool_limits

from reference.bounded_biharmonic_weights import bbw, handle_constraints
from starter.meshes import load_handles, load_mesh
from starter.shapes import _edge_length, _loop_edges, _triangulate, character_2d, character_2d_handles, disc_with_holes

# character_2d's docstring: 1.3e-4 gives about 10,000 vertices
MAX_AREA = 1.3e-4
POINT_HANDLES = 4  # head, left hand, right hand, left foot
RUNS = 5
FAMILY_RUNS = 2
# a member runs until igl.bbw has taken this much CPU too: the tetrahedral
# hand's 0.15 s runs would otherwise give a median of two noisy ratios
FAMILY_SECONDS = 1.0
FAMILY_MAX_RUNS = 15


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


def _polygon(outline, max_area):
    """Quality triangulation of a simple polygon ``outline`` ``(k, 2)``, its sides split at the mesh spacing."""
    spacing = _edge_length(max_area)
    points = []
    for a, b in zip(outline, np.roll(outline, -1, axis=0)):
        pieces = max(1, int(np.ceil(np.linalg.norm(b - a) / spacing)))
        points.append(a + np.arange(pieces)[:, None] / pieces * (b - a))
    P = np.vstack(points)
    return _triangulate(P, _loop_edges(0, len(P)), np.zeros((0, 2)), max_area)


def _nearest(V, points):
    """One point handle per position: the nearest vertex."""
    return [[int(np.argmin(np.linalg.norm(V - p, axis=1)))] for p in np.asarray(points, float)]


def _convex_square():
    V, F = _polygon(np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float), 6e-4)
    return V, F, _nearest(V, [[0.3, 0.3], [1.7, 0.5], [1.0, 1.7]])


def _u_with_a_deep_notch():
    V, F = _polygon(np.array([[0, 0], [3, 0], [3, 3], [0, 3], [0, 2], [2, 2], [2, 1], [0, 1]], float), 8e-4)
    return V, F, _nearest(V, [[0.2, 0.5], [0.2, 2.5], [2.8, 1.5], [1.5, 0.5]])


def _comb(teeth=6):
    outline = [[0, 0], [teeth, 0]] + [
        p for k in range(teeth - 1, -1, -1) for p in ([k + 0.75, 1], [k + 0.75, 4], [k + 0.25, 4], [k + 0.25, 1])
    ]
    V, F = _polygon(np.array(outline, float), 1.5e-3)
    return V, F, _nearest(V, [[k + 0.5, 3.9] for k in range(teeth)] + [[teeth / 2, 0.1]])


def _disc_with_holes():
    V, F = disc_with_holes(3, 4e-4)
    return V, F, _nearest(V, [[0.9, 0], [-0.9, 0], [0, 0.9], [0, -0.9], [0, 0]])


def _character_bones():
    V, F = character_2d(max_area=MAX_AREA)
    return V, F, [np.asarray(bone) for bone in character_2d_handles(V)["bones"]]


def _character_regions_and_points():
    V, F = character_2d(max_area=MAX_AREA)
    handles = character_2d_handles(V)
    return V, F, [np.asarray(r) for r in handles["regions"]] + [[int(i)] for i in handles["points"][1:3]]


def _l_shape_20_points():
    V, F = _polygon(np.array([[0, 0], [4, 0], [4, 1], [1, 1], [1, 4], [0, 4]], float), 6e-4)
    spread = np.random.default_rng(0).choice(len(V), 20, replace=False)
    return V, F, [[int(i)] for i in spread]


def _flat_hexagon():
    V, F = _polygon(np.array([[np.cos(t), np.sin(t)] for t in np.linspace(0, 2 * np.pi, 7)[:-1]]) * [3.0, 1.0], 5e-4)
    return V, F, _nearest(V, [[-2.8, 0], [2.8, 0]])


def _hand_tet_bones():
    V, T = load_mesh("hand_tet")
    return V, T, list(load_handles("hand_tet")["bones"])


# (label, build): build() -> (V, F, handles), handles a list of vertex index lists
FAMILY = [
    ("convex square, 3 points", _convex_square),
    ("U with a deep notch, 4 points", _u_with_a_deep_notch),
    ("comb of 6 thin teeth, 7 points", _comb),
    ("disc with 3 holes, 5 points", _disc_with_holes),
    ("character, 5 bones", _character_bones),
    ("character, 3 regions and 2 points", _character_regions_and_points),
    ("L shape, 20 points", _l_shape_20_points),
    ("flat hexagon (3 x 1), 2 points", _flat_hexagon),
    ("hand of tetrahedra, 6 bones", _hand_tet_bones),
]


def family():
    """The BBW benchmark family: ``[(label, V, F, handles)]``, ``handles`` a list of vertex index lists.

    Triangle meshes of 5k–12.5k vertices (``FAMILY``): a convex square; a U
    with a deep notch; a comb of thin teeth; a disc with holes; the character
    with bones, and with regions and points; an L with 20 point handles; a flat
    hexagon. And the hand of tetrahedra (1.2k vertices, ``data/hand_tet.npz``)
    with its six bones.
    """
    return [(label, *build()) for label, build in FAMILY]


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
    figures.update(family_figures())
    return figures


def family_figures(runs=FAMILY_RUNS, seconds=FAMILY_SECONDS):
    """Time both solvers on every problem of ``family()``; CPU ratios per problem and the worst.

    Each member runs both solvers alternately at least ``runs`` times, and
    more (up to ``FAMILY_MAX_RUNS``) until ``igl.bbw`` has taken ``seconds``
    of CPU; its ratio is the median of the per-run ratios.
    """
    ratios, errors, spreads = {}, {}, {}
    print(f"family: at least {runs} alternating runs each (more until igl.bbw took {seconds:g} s), "
          f"CPU seconds, BLAS limited to 1 thread")
    for label, V, F, handles in family():
        b, bc = handle_constraints(handles)
        cpu = {"ours": [], "igl": []}
        with threadpool_limits(limits=1, user_api="blas"):
            while len(cpu["igl"]) < runs or (sum(cpu["igl"]) < seconds and len(cpu["igl"]) < FAMILY_MAX_RUNS):
                W, _, cpu_ours = _timed(lambda: bbw(V, F, b, bc))
                W_igl, _, cpu_igl = _timed(lambda: igl.bbw(V, F, b, bc))
                cpu["ours"].append(cpu_ours)
                cpu["igl"].append(cpu_igl)
        per_run = np.array(cpu["ours"]) / np.array(cpu["igl"])
        ratios[label] = float(np.median(per_run))
        spreads[label] = f"{per_run.min():.3f}-{per_run.max():.3f} over {len(per_run)} runs"
        errors[label] = float(np.abs(W - W_igl / W_igl.sum(axis=1, keepdims=True)).max())
        print(
            f"  {label:<36} {len(V):6d} vertices, {len(handles):2d} handles: ours {np.median(cpu['ours']):6.3f} s, "
            f"igl {np.median(cpu['igl']):6.3f} s, ratio {ratios[label]:.3f} ({spreads[label]}), "
            f"max |W - W_igl| {errors[label]:.1e}",
            flush=True,
        )
    worst = max(ratios, key=ratios.get)
    # the typical shape, beside the worst: one slow member cannot hide the others' speed-up or slow-down
    geometric_mean = float(np.exp(np.mean(np.log(list(ratios.values())))))
    print(f"family worst ratio ours/igl (cpu): {ratios[worst]:.3f} ({worst}); required <= 0.5, aim <= 0.25; "
          f"geometric mean {geometric_mean:.3f}; largest |W - W_igl| {max(errors.values()):.1e} (required <= 1e-4)")
    return {
        "family problems": len(ratios),
        "family worst ratio cpu ours/igl": ratios[worst],
        "family worst problem": worst,
        "family geometric mean ratio cpu ours/igl": geometric_mean,
        "family ratios cpu": {k: round(v, 3) for k, v in ratios.items()},
        "family worst problem's runs": spreads[worst],
        "family max abs(W - W_igl normalized)": max(errors.values()),
    }


if __name__ == "__main__":
    main()
