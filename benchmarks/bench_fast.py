"""FAST (``reference.fast``) against full ARAP (``reference.arap``) on the ~50k-vertex twisted bar.

The bar is ``bench_arap``'s. FAST gets 8 region handles: the two end faces,
fixed (the left at rest, the right turned by ``TWIST`` about the bar's axis),
and 6 free cross-section rings at equal spacing along the bar; bounded
biharmonic weights (``reference.bbw``, a few seconds here) and
``CLUSTERS`` rotation clusters. Full ARAP gets the end-face vertices placed
by the same fixed transforms.

Per-iteration times alternate between the two solvers in one process, so that
both see the same load on a shared machine; figures are medians over the
runs, wall-clock and CPU.

Quality is the ARAP energy with fresh optimal per-vertex rotations,
``arap_energy(V, U, F, C, arap_rotations(V, U, F, C))``, of the FAST result
and of full ARAP after each of ``ENERGY_ITERATIONS``, on this bar and on the
course mesh ``bar`` (2,594 vertices, same handles). The energy of the smooth
uniform twist (every cross-section turned by ``TWIST x / length``) is given
too: the finer the surface, the further below it full ARAP goes by caving the
walls in (the energy has no bending term; on the 10k-vertex ``bar_fine`` the
mid-length cross-section shrinks to 20-76 % of its rest radius), which the
affine ring handles cannot follow; the largest distances of both results
from the smooth twist show it.

The fair test of FAST's energy target (at most twice full ARAP's energy
after 1000 iterations) is a volume, whose walls cannot cave in: on the
tetrahedral course mesh ``bar_tet`` (1,225 vertices, 5,184 tetrahedra, same
handles, same twist) FAST runs on tetrahedral cells (``fast_precompute`` with
``(f, 4)`` cells) and full ARAP is ``reference.tetrahedra`` (one rotation per
tetrahedron); both results are measured with the tetrahedral ARAP energy and
fresh per-tetrahedron rotations, ``tet_arap_energy(V, U, T,
tet_arap_rotations(V, U, T))``, and by their volume change.

Run with ``.venv/bin/python -m benchmarks.bench_fast``.
"""

from __future__ import annotations

import numpy as np

from benchmarks.bench_arap import TWIST, timed, twisted_bar
from reference.arap import arap_energy, arap_precompute, arap_rotations, arap_solve, cotangent_weights
from reference.bounded_biharmonic_weights import bbw, handle_constraints
from reference.fast import fast_precompute, fast_solve, rotation_clusters
from reference.linear_blend_skinning import lbs
from reference.tetrahedra import tet_arap_energy, tet_arap_precompute, tet_arap_rotations, tet_arap_solve, tet_volumes
from starter.meshes import load_mesh

FREE_RINGS = 6
CLUSTERS = 50
FAST_ITERATIONS = 100
ARAP_ITERATIONS = 10
RUNS = 5
PRECOMPUTE_RUNS = 3
ENERGY_ITERATIONS = (10, 100, 1000)


def skinned_bar(V):
    """Handles and fixed transforms of a bar ``[0, length] x [0, 1] x [0, 1]``.

    Returns
    -------
    sets : list of numpy.ndarray of int64
        Vertices of each handle: left end, right end, then the free rings.
    fixed_transforms : (2, 3, 4) numpy.ndarray
        The left end at rest, the right end turned by ``TWIST`` about its centre.
    """
    length = V[:, 0].max()
    xs = np.unique(V[:, 0])
    # grid columns nearest to equal spacing: whole rings of vertices
    rings = xs[np.round((len(xs) - 1) * np.arange(1, FREE_RINGS + 1) / (FREE_RINGS + 1)).astype(int)]
    sets = [np.flatnonzero(V[:, 0] == 0.0), np.flatnonzero(V[:, 0] == length)]
    sets += [np.flatnonzero(V[:, 0] == x) for x in rings]
    centre = V[sets[1]].mean(axis=0)
    c, s = np.cos(TWIST), np.sin(TWIST)
    turn = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    return sets, np.stack([np.eye(3, 4), np.c_[turn, centre - turn @ centre]])


def smooth_twist(V, sets):
    """Every cross-section turned by ``TWIST x / length`` about the bar's axis."""
    length = V[:, 0].max()
    centre = V[sets[1]].mean(axis=0)
    angle = TWIST * V[:, 0] / length
    y, z = V[:, 1] - centre[1], V[:, 2] - centre[2]
    c, s = np.cos(angle), np.sin(angle)
    return np.c_[V[:, 0], centre[1] + c * y - s * z, centre[2] + s * y + c * z]


def end_targets(V, sets, fixed_transforms):
    """Positions of the end-face vertices under the fixed transforms, in the order of ``sets[0]``, ``sets[1]``."""
    return np.vstack([V[part] @ T[:, :3].T + T[:, 3] for part, T in zip(sets[:2], fixed_transforms)])


def energies(V, F, W, clusters, sets, fixed_transforms):
    """ARAP energies (fresh rotations) of FAST, of full ARAP after each of ``ENERGY_ITERATIONS``, of the smooth twist.

    Returns
    -------
    dict
        ``fast_energy``, ``fast_last_half_drop`` (relative drop of FAST's own
        energy over its last half of ``FAST_ITERATIONS``),
        ``arap_energy_after_<k>``, ``energy_ratio`` (FAST over full ARAP's
        last), ``smooth_twist_energy``, ``fast_from_smooth_twist`` and
        ``arap_from_smooth_twist`` (largest distance of a vertex from the
        smooth twist, over the bar's width).
    """
    C = cotangent_weights(V, F)

    def fresh(U):
        return float(arap_energy(V, U, F, C, arap_rotations(V, U, F, C)))

    data_fast = fast_precompute(V, F, W, clusters, np.array([0, 1]))
    T, own = fast_solve(data_fast, fixed_transforms, iterations=FAST_ITERATIONS)
    U_fast = lbs(V, W, T)
    data_arap = arap_precompute(V, F, np.concatenate(sets[:2]))
    targets = end_targets(V, sets, fixed_transforms)
    U, done, full = None, 0, {}
    for k in ENERGY_ITERATIONS:
        U, _ = arap_solve(data_arap, targets, U0=U, iterations=k - done)
        done = k
        full[f"arap_energy_after_{k}"] = fresh(U)
    twist = smooth_twist(V, sets)
    width = V[:, 1].max() - V[:, 1].min()
    half = FAST_ITERATIONS // 2
    return {
        "fast_energy": fresh(U_fast),
        "fast_last_half_drop": float((own[half - 1] - own[-1]) / own[-1]),
        **full,
        "energy_ratio": fresh(U_fast) / fresh(U),
        "smooth_twist_energy": fresh(twist),
        "fast_from_smooth_twist": float(np.linalg.norm(U_fast - twist, axis=1).max() / width),
        "arap_from_smooth_twist": float(np.linalg.norm(U - twist, axis=1).max() / width),
    }


def volumetric():
    """FAST on tetrahedral cells against full tetrahedral ARAP on ``bar_tet``, twisted as the surface bars.

    Returns
    -------
    dict
        ``volumetric_vertices``, ``volumetric_tets``; ``volumetric_fast_energy``
        (after ``FAST_ITERATIONS``) and ``volumetric_fast_last_half_drop``;
        ``volumetric_arap_energy_after_<k>`` for ``ENERGY_ITERATIONS``;
        ``volumetric_energy_ratio`` (FAST over full ARAP after the last),
        ``volumetric_smooth_twist_energy``; ``volumetric_fast_volume_change``,
        ``volumetric_arap_volume_change`` (relative); ``volumetric_arap_1000_cpu_s``.
    """
    V, T = load_mesh("bar_tet")
    sets, fixed_transforms = skinned_bar(V)
    W = bbw(V, T, *handle_constraints(sets))

    def fresh(U):
        return float(tet_arap_energy(V, U, T, tet_arap_rotations(V, U, T)))

    data_fast = fast_precompute(V, T, W, rotation_clusters(W, CLUSTERS), np.array([0, 1]))
    transforms, own = fast_solve(data_fast, fixed_transforms, iterations=FAST_ITERATIONS)
    U_fast = lbs(V, W, transforms)
    data_arap = tet_arap_precompute(V, T, np.concatenate(sets[:2]))
    targets = end_targets(V, sets, fixed_transforms)
    U, done, full, cpu = None, 0, {}, 0.0
    for k in ENERGY_ITERATIONS:
        (_, seconds), (U, _) = timed(tet_arap_solve, data_arap, targets, U0=U, iterations=k - done)
        cpu += seconds
        done = k
        full[f"volumetric_arap_energy_after_{k}"] = fresh(U)
    volume = tet_volumes(V, T).sum()
    half = FAST_ITERATIONS // 2
    return {
        "volumetric_vertices": len(V),
        "volumetric_tets": len(T),
        "volumetric_fast_energy": fresh(U_fast),
        "volumetric_fast_last_half_drop": float((own[half - 1] - own[-1]) / own[-1]),
        **full,
        "volumetric_energy_ratio": fresh(U_fast) / fresh(U),
        "volumetric_smooth_twist_energy": fresh(smooth_twist(V, sets)),
        "volumetric_fast_volume_change": float(tet_volumes(U_fast, T).sum() / volume - 1.0),
        "volumetric_arap_volume_change": float(tet_volumes(U, T).sum() / volume - 1.0),
        "volumetric_arap_1000_cpu_s": cpu,
    }


def main(runs=RUNS, precompute_runs=PRECOMPUTE_RUNS):
    """Time FAST and full ARAP side by side, compare their energies, print the figures.

    Parameters
    ----------
    runs : int
        Solves per solver for the per-iteration times (alternating).
    precompute_runs : int
        Precomputations per solver (alternating).

    Returns
    -------
    dict
        ``vertices``, ``faces``, ``handles``, ``fixed handle vertices``,
        ``clusters``, ``runs``; ``weights_s`` (``bbw``), ``clusters_s``
        (``rotation_clusters``); ``fast_precompute_s`` and
        ``arap_precompute_s`` (wall, medians); ``fast_per_iteration_s`` and
        ``arap_per_iteration_s`` (wall, medians, over ``FAST_ITERATIONS`` and
        ``ARAP_ITERATIONS`` iterations per run) and their ``*_cpu_s``;
        ``speedup`` (median over runs of ARAP / FAST per iteration, wall),
        ``speedup_min``, ``speedup_max``, ``speedup_cpu``; the figures of
        ``energies`` on this bar, and with the prefix ``coarse_`` on the
        course mesh ``bar`` (same handles, weights and clusters count); the
        figures of ``volumetric`` (tetrahedral ``bar_tet``).
    """
    V, F, _, _ = twisted_bar()
    sets, fixed_transforms = skinned_bar(V)
    ends = np.concatenate(sets[:2])
    targets = end_targets(V, sets, fixed_transforms)

    weights_s, W = timed(bbw, V, F, *handle_constraints(sets))
    clusters_s, clusters = timed(rotation_clusters, W, CLUSTERS)

    pre_fast, pre_arap = [], []
    for _ in range(precompute_runs):
        t, data = timed(fast_precompute, V, F, W, clusters, np.array([0, 1]))
        pre_fast.append(t[0])
        t, data_arap = timed(arap_precompute, V, F, ends)
        pre_arap.append(t[0])

    fast, full = [], []
    for _ in range(runs):
        t, _ = timed(fast_solve, data, fixed_transforms, iterations=FAST_ITERATIONS)
        fast.append(np.array(t) / FAST_ITERATIONS)
        t, _ = timed(arap_solve, data_arap, targets, iterations=ARAP_ITERATIONS)
        full.append(np.array(t) / ARAP_ITERATIONS)
    fast, full = np.array(fast), np.array(full)
    speedups = full / fast

    V_coarse, F_coarse = load_mesh("bar")
    sets_coarse, fixed_coarse = skinned_bar(V_coarse)
    W_coarse = bbw(V_coarse, F_coarse, *handle_constraints(sets_coarse))

    median = np.median
    figures = {
        "vertices": len(V),
        "faces": len(F),
        "handles": len(sets),
        "fixed handle vertices": len(ends),
        "clusters": CLUSTERS,
        "runs": runs,
        "weights_s": weights_s[0],
        "clusters_s": clusters_s[0],
        "fast_precompute_s": float(median(pre_fast)),
        "arap_precompute_s": float(median(pre_arap)),
        "fast_per_iteration_s": float(median(fast[:, 0])),
        "arap_per_iteration_s": float(median(full[:, 0])),
        "speedup": float(median(speedups[:, 0])),
        "speedup_min": float(speedups[:, 0].min()),
        "speedup_max": float(speedups[:, 0].max()),
        "fast_per_iteration_cpu_s": float(median(fast[:, 1])),
        "arap_per_iteration_cpu_s": float(median(full[:, 1])),
        "speedup_cpu": float(median(speedups[:, 1])),
        **energies(V, F, W, clusters, sets, fixed_transforms),
        "coarse_vertices": len(V_coarse),
        **{
            f"coarse_{key}": value
            for key, value in energies(
                V_coarse, F_coarse, W_coarse, rotation_clusters(W_coarse, CLUSTERS), sets_coarse, fixed_coarse
            ).items()
        },
        **volumetric(),
    }

    print(f"FAST vs full ARAP, spokes and rims, bar twisted by {np.degrees(TWIST):.0f} degrees")
    print(f"mesh: {len(V)} vertices, {len(F)} faces; {len(sets)} handles (2 fixed end faces, {len(ends)} vertices, "
          f"{len(sets) - 2} free rings), {CLUSTERS} rotation clusters")
    print(f"weights (bbw) {figures['weights_s']:.2f} s, clusters {figures['clusters_s']:.2f} s")
    print(f"{'':28s}{'FAST':>12s}{'full ARAP':>12s}")
    print(f"{'precompute, wall (s)':28s}{figures['fast_precompute_s']:12.3f}{figures['arap_precompute_s']:12.3f}")
    print(f"{'per iteration, wall (ms)':28s}{1e3 * figures['fast_per_iteration_s']:12.3f}"
          f"{1e3 * figures['arap_per_iteration_s']:12.3f}")
    print(f"{'per iteration, CPU (ms)':28s}{1e3 * figures['fast_per_iteration_cpu_s']:12.3f}"
          f"{1e3 * figures['arap_per_iteration_cpu_s']:12.3f}")
    print(f"  FAST faster per iteration by: median {figures['speedup']:.0f}x "
          f"(range {figures['speedup_min']:.0f}-{figures['speedup_max']:.0f}), CPU {figures['speedup_cpu']:.0f}x")
    half = FAST_ITERATIONS // 2
    for prefix, n in (("", len(V)), ("coarse_", len(V_coarse))):
        print(f"ARAP energy with fresh per-vertex rotations, {n} vertices:")
        print(f"  FAST after {FAST_ITERATIONS} iterations: {figures[prefix + 'fast_energy']:.4f} "
              f"(its own energy dropped {figures[prefix + 'fast_last_half_drop']:.1e} over the last "
              f"{FAST_ITERATIONS // 2})")
        for k in ENERGY_ITERATIONS:
            print(f"  full ARAP after {k} iterations: {figures[f'{prefix}arap_energy_after_{k}']:.4f}")
        print(f"  smooth uniform twist: {figures[prefix + 'smooth_twist_energy']:.4f}")
        print(f"  FAST / full ARAP: {figures[prefix + 'energy_ratio']:.2f}")
        print(f"  largest distance from the smooth twist / bar width: FAST "
              f"{figures[prefix + 'fast_from_smooth_twist']:.3f}, "
              f"full ARAP {figures[prefix + 'arap_from_smooth_twist']:.3f}")
    print(f"Volumetric bar ({figures['volumetric_vertices']} vertices, {figures['volumetric_tets']} tetrahedra), "
          f"ARAP energy with fresh per-tetrahedron rotations:")
    print(f"  FAST on tetrahedra after {FAST_ITERATIONS} iterations: {figures['volumetric_fast_energy']:.4f} "
          f"(its own energy dropped {figures['volumetric_fast_last_half_drop']:.1e} over the last {half})")
    for k in ENERGY_ITERATIONS:
        print(f"  full tetrahedral ARAP after {k} iterations: {figures[f'volumetric_arap_energy_after_{k}']:.4f}")
    print(f"  smooth uniform twist: {figures['volumetric_smooth_twist_energy']:.4f}")
    print(f"  FAST volumetric energy / full tet-ARAP energy after {ENERGY_ITERATIONS[-1]} iterations: "
          f"{figures['volumetric_energy_ratio']:.2f} (target <= 2)")
    print(f"  volume change: FAST {100 * figures['volumetric_fast_volume_change']:+.2f} %, "
          f"full ARAP {100 * figures['volumetric_arap_volume_change']:+.2f} %")
    return figures


if __name__ == "__main__":
    main()
