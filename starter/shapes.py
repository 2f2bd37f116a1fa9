"""Procedural course meshes: bars, tubes, a torus, 2D grids and cut-outs.

Every generator is deterministic (no randomness: the same arguments give the
same arrays bit for bit) and returns ``(V, F)``: ``V`` ``(n, d)`` float64
positions and ``F`` ``(f, 3)`` int64 triangles. The meshes are edge-manifold,
consistently oriented (closed surfaces point outward, 2D triangles are
counter-clockwise), have no unreferenced vertices and no zero-area triangles.

The 2D cut-outs (:func:`character_2d`, :func:`disc_with_holes`) are
triangulated with Jonathan Shewchuk's Triangle through ``igl.triangle``.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "bar",
    "cylinder",
    "torus",
    "grid_2d",
    "disc_with_holes",
    "character_2d",
    "character_2d_skeleton",
    "character_2d_handles",
]


def _positive(x, name: str) -> float:
    try:
        v = float(x)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a positive number, got {x!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be a positive finite number, got {x!r}")
    return v


def _count(x, name: str, minimum: int) -> int:
    if isinstance(x, (bool, np.bool_)) or not isinstance(x, (int, np.integer)):
        raise ValueError(f"{name} must be an integer, got {x!r}")
    if x < minimum:
        raise ValueError(f"{name} must be at least {minimum}, got {x}")
    return int(x)


def _grid_triangles(idx: np.ndarray) -> np.ndarray:
    """Split every cell of a ``(p + 1, q + 1)`` grid of vertex indices into two triangles.

    The cell corners ``(a, b), (a + 1, b), (a + 1, b + 1), (a, b + 1)`` run
    counter-clockwise in the ``(a, b)`` parameter plane, and so do the
    triangles. Diagonals alternate like a checkerboard so that the mesh keeps
    the mirror symmetries of the grid (a bent bar stays symmetric).

    Returns
    -------
    numpy.ndarray
        ``(2 p q, 3)`` int64.
    """
    c00, c10, c11, c01 = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
    a, b = np.indices(c00.shape)
    even = ((a + b) % 2 == 0)[..., None]
    first = np.where(even, np.stack([c00, c10, c11], -1), np.stack([c00, c10, c01], -1))
    second = np.where(even, np.stack([c00, c11, c01], -1), np.stack([c10, c11, c01], -1))
    return np.stack([first, second], axis=2).reshape(-1, 3).astype(np.int64)


def bar(length=4.0, width=1.0, height=1.0, nx=40, ny=10, nz=10):
    """Closed triangulated surface of the box ``[0, length] x [0, width] x [0, height]``.

    Each of the six sides is a regular grid of ``nx x ny``, ``ny x nz`` or
    ``nx x nz`` cells, each cell split into two triangles; sides share their
    vertices along the box's edges. The vertices are the surface points of the
    ``(nx + 1) x (ny + 1) x (nz + 1)`` lattice, in lattice (x-major) order, so
    the ends ``x == 0`` and ``x == length`` hold exactly.

    Parameters
    ----------
    length, width, height : float
        Box extents along x, y and z (positive).
    nx, ny, nz : int
        Number of cells along x, y and z (at least 1).

    Returns
    -------
    V : (n, 3) numpy.ndarray of float64
        ``n = (nx+1)(ny+1)(nz+1) - (nx-1)(ny-1)(nz-1)``.
    F : (f, 3) numpy.ndarray of int64
        ``f = 4 (nx ny + ny nz + nz nx)`` triangles, normals pointing outward.
    """
    extents = [_positive(length, "length"), _positive(width, "width"), _positive(height, "height")]
    counts = [_count(nx, "nx", 1), _count(ny, "ny", 1), _count(nz, "nz", 1)]
    shape = tuple(c + 1 for c in counts)
    interior = np.zeros(shape, dtype=bool)
    interior[1:-1, 1:-1, 1:-1] = True
    on_surface = ~interior
    vid = np.full(shape, -1, dtype=np.int64)
    vid[on_surface] = np.arange(int(on_surface.sum()))
    axes = [np.linspace(0.0, e, c + 1) for e, c in zip(extents, counts)]
    ijk = np.argwhere(on_surface)
    V = np.stack([axes[k][ijk[:, k]] for k in range(3)], axis=1)

    faces = []
    for a in range(3):
        for side in (0, counts[a]):
            idx = vid.take(side, axis=a)
            # Parameter axes (b, c) must satisfy e_b x e_c = e_a; for a = 1
            # the remaining axes come out as (x, z), so swap them to (z, x).
            if a == 1:
                idx = idx.T
            tris = _grid_triangles(idx)
            faces.append(tris if side else tris[:, ::-1])
    return V, np.ascontiguousarray(np.concatenate(faces))


def cylinder(length=4.0, radius=0.5, n_around=32, n_along=64, caps=True):
    """Tube of the given radius around the x axis, from ``x = 0`` to ``x = length``.

    Rings of ``n_around`` vertices sit at ``n_along + 1`` equally spaced
    ``x``; with ``caps`` each end is closed by a fan around a centre vertex
    on the axis.

    Parameters
    ----------
    length, radius : float
        Positive.
    n_around : int
        Vertices per ring (at least 3).
    n_along : int
        Segments along the axis (at least 1).
    caps : bool
        Close both ends (a genus-0 closed surface); otherwise the tube is
        open with two boundary loops.

    Returns
    -------
    V : (n, 3) numpy.ndarray of float64
        ``(n_along + 1) * n_around`` ring vertices (ring by ring, from
        ``x = 0``), then, with ``caps``, the centres ``(0, 0, 0)`` and
        ``(length, 0, 0)``.
    F : (f, 3) numpy.ndarray of int64
        Outward-facing triangles.
    """
    length = _positive(length, "length")
    radius = _positive(radius, "radius")
    n_around = _count(n_around, "n_around", 3)
    n_along = _count(n_along, "n_along", 1)
    x = np.linspace(0.0, length, n_along + 1)
    theta = 2.0 * np.pi * np.arange(n_around) / n_around
    ring = np.stack([np.zeros(n_around), radius * np.cos(theta), radius * np.sin(theta)], axis=1)
    V = np.repeat(ring[None], n_along + 1, axis=0)
    V[:, :, 0] = x[:, None]
    V = V.reshape(-1, 3)
    idx = np.arange((n_along + 1) * n_around, dtype=np.int64).reshape(n_along + 1, n_around)
    idx = np.concatenate([idx, idx[:, :1]], axis=1)
    # In the (theta, x) parameter order counter-clockwise cells face outward.
    faces = [_grid_triangles(idx.T)]
    if caps:
        first, last = idx[0], idx[-1]
        c0, c1 = len(V), len(V) + 1
        V = np.concatenate([V, [[0.0, 0.0, 0.0], [length, 0.0, 0.0]]])
        faces.append(np.stack([np.full(n_around, c0), first[1:], first[:-1]], axis=1))
        faces.append(np.stack([np.full(n_around, c1), last[:-1], last[1:]], axis=1))
    return V, np.ascontiguousarray(np.concatenate(faces).astype(np.int64))


def torus(R=1.0, r=0.35, n_major=48, n_minor=24):
    """Torus around the z axis (genus 1, Euler characteristic 0).

    Vertex ``(i, j)`` is ``((R + r cos φ_j) cos θ_i, (R + r cos φ_j) sin θ_i, r sin φ_j)``
    with ``θ_i = 2π i / n_major`` and ``φ_j = 2π j / n_minor``.

    Parameters
    ----------
    R : float
        Distance from the centre to the tube's axis.
    r : float
        Tube radius, ``0 < r < R``.
    n_major, n_minor : int
        Vertices around the z axis and around the tube (each at least 3).

    Returns
    -------
    V : (n_major * n_minor, 3) numpy.ndarray of float64
    F : (2 * n_major * n_minor, 3) numpy.ndarray of int64
        Outward-facing triangles.
    """
    R = _positive(R, "R")
    r = _positive(r, "r")
    if r >= R:
        raise ValueError(f"r must be smaller than R (the tube would self-intersect), got r={r}, R={R}")
    n_major = _count(n_major, "n_major", 3)
    n_minor = _count(n_minor, "n_minor", 3)
    theta = 2.0 * np.pi * np.arange(n_major) / n_major
    phi = 2.0 * np.pi * np.arange(n_minor) / n_minor
    T, P = np.meshgrid(theta, phi, indexing="ij")
    rho = R + r * np.cos(P)
    V = np.stack([rho * np.cos(T), rho * np.sin(T), r * np.sin(P)], axis=-1).reshape(-1, 3)
    idx = np.arange(n_major * n_minor, dtype=np.int64).reshape(n_major, n_minor)
    idx = np.concatenate([idx, idx[:1]], axis=0)
    idx = np.concatenate([idx, idx[:, :1]], axis=1)
    # d/dθ x d/dφ points away from the tube's axis: (θ, φ) cells face outward.
    return V, np.ascontiguousarray(_grid_triangles(idx))


def grid_2d(nx=10, ny=10, width=1.0, height=1.0):
    """Regular triangulated 2D rectangle ``[0, width] x [0, height]`` (the unit square by default).

    Parameters
    ----------
    nx, ny : int
        Number of cells along x and y (at least 1).
    width, height : float
        Positive extents.

    Returns
    -------
    V : ((nx + 1) * (ny + 1), 2) numpy.ndarray of float64
        Vertex ``i * (ny + 1) + j`` is ``(width * i / nx, height * j / ny)``.
    F : (2 * nx * ny, 3) numpy.ndarray of int64
        Counter-clockwise triangles.
    """
    nx = _count(nx, "nx", 1)
    ny = _count(ny, "ny", 1)
    X, Y = np.meshgrid(
        np.linspace(0.0, _positive(width, "width"), nx + 1),
        np.linspace(0.0, _positive(height, "height"), ny + 1),
        indexing="ij",
    )
    V = np.stack([X, Y], axis=-1).reshape(-1, 2)
    idx = np.arange((nx + 1) * (ny + 1), dtype=np.int64).reshape(nx + 1, ny + 1)
    return V, _grid_triangles(idx)


def _edge_length(max_area: float) -> float:
    """Side of the equilateral triangle of area ``max_area``: the boundary spacing
    that Triangle's area bound would produce anyway, so it does not split it again."""
    return math.sqrt(4.0 * max_area / math.sqrt(3.0))


def _triangle_flags(max_area: float) -> str:
    # Triangle reads the area bound as plain digits: 'e' would start another switch.
    area = f"{max_area:.12f}".rstrip("0")
    return f"pq30a{area}Q"


def _triangulate(V, E, H, max_area):
    """Quality-triangulate a planar straight-line graph; CCW triangles, float64/int64."""
    import igl.triangle

    V2, F2, _, _, _ = igl.triangle.triangulate(
        np.ascontiguousarray(V, dtype=np.float64),
        np.ascontiguousarray(E, dtype=np.int64),
        np.ascontiguousarray(H, dtype=np.float64).reshape(-1, 2),
        flags=_triangle_flags(max_area),
    )
    V2 = np.ascontiguousarray(V2, dtype=np.float64)
    F2 = np.ascontiguousarray(F2, dtype=np.int64)
    e1 = V2[F2[:, 1]] - V2[F2[:, 0]]
    e2 = V2[F2[:, 2]] - V2[F2[:, 0]]
    clockwise = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] < 0
    F2[clockwise] = F2[clockwise][:, ::-1]
    return V2, F2


def _loop_edges(start: int, count: int) -> np.ndarray:
    i = np.arange(count, dtype=np.int64)
    return np.stack([start + i, start + (i + 1) % count], axis=1)


def _circle(center, radius: float, spacing: float, minimum: int) -> np.ndarray:
    n = max(minimum, math.ceil(2.0 * math.pi * radius / spacing))
    t = 2.0 * np.pi * np.arange(n) / n
    return np.stack([center[0] + radius * np.cos(t), center[1] + radius * np.sin(t)], axis=1)


def disc_with_holes(n_holes=2, max_area=0.002):
    """Unit disc with ``n_holes`` circular holes, quality-triangulated.

    The holes are centred on the circle of radius 0.5, hole ``k`` at angle
    ``2π k / n_holes``, with radius ``min(0.25, 0.3 * chord)`` where
    ``chord = sin(π / n_holes)`` is the distance between neighbouring centres.

    Parameters
    ----------
    n_holes : int
        Number of holes, 0 to 12.
    max_area : float
        Largest triangle area (Triangle's ``a`` switch); boundary circles are
        sampled at the matching edge length.

    Returns
    -------
    V : (n, 2) numpy.ndarray of float64
    F : (f, 3) numpy.ndarray of int64
        Counter-clockwise triangles; ``1 + n_holes`` boundary loops, Euler
        characteristic ``1 - n_holes``.
    """
    n_holes = _count(n_holes, "n_holes", 0)
    if n_holes > 12:
        raise ValueError(f"n_holes must be at most 12 (the holes would be too small to mesh), got {n_holes}")
    max_area = _positive(max_area, "max_area")
    if max_area < 1e-6:
        raise ValueError(f"max_area must be at least 1e-6 (millions of triangles otherwise), got {max_area}")
    h = min(_edge_length(max_area), 0.1)
    loops = [_circle((0.0, 0.0), 1.0, h, 32)]
    centres = np.zeros((n_holes, 2))
    if n_holes:
        rho = 0.25 if n_holes == 1 else min(0.25, 0.3 * math.sin(math.pi / n_holes))
        angles = 2.0 * np.pi * np.arange(n_holes) / n_holes
        centres = 0.5 * np.stack([np.cos(angles), np.sin(angles)], axis=1)
        loops += [_circle(c, rho, h, 12) for c in centres]
    starts = np.cumsum([0] + [len(p) for p in loops])
    E = np.concatenate([_loop_edges(s, len(p)) for s, p in zip(starts, loops)])
    return _triangulate(np.concatenate(loops), E, centres, max_area)


# The character is the zero level set of a signed distance: a head disc and
# capsules (segment, radius) for the body and the right limbs, mirrored to the
# left and blended with a smooth minimum so the armpits, neck and crotch are
# rounded. Units: the character is about 2 tall, feet near y = 0.
_HEAD = ((0.0, 1.62), 0.34)
_CAPSULES = (
    ((0.0, 0.80), (0.0, 1.10), 0.36),  # body
    ((0.25, 1.10), (0.92, 0.92), 0.13),  # right arm, hand at the far end
    ((0.17, 0.70), (0.40, 0.14), 0.155),  # right leg, foot at the far end
)
_BLEND = 0.07
_SDF_STEP = 0.004


def character_2d_skeleton():
    """Skeleton and handle anchors of :func:`character_2d` (independent of the mesh).

    "Left" means negative x (the viewer's left).

    Returns
    -------
    dict
        ``"points"``: ``(5, 2)`` float64 point-handle positions (head top,
        left hand, right hand, left foot, right foot), each a mesh vertex;
        ``"point_names"``: their names;
        ``"bones"``: ``(5, 2, 2)`` float64 bone segments ``[start, end]``
        (spine from the pelvis to the head centre, left arm, right arm, left
        leg, right leg; arms and legs start at the body), pairwise disjoint
        and strictly inside the outline;
        ``"bone_names"``: their names;
        ``"regions"``: ``(3, 3)`` float64 discs ``(cx, cy, radius)`` (head,
        left foot, right foot);
        ``"region_names"``: their names.
    """
    (arm_a, arm_b), (leg_a, leg_b) = (np.array(_CAPSULES[k][:2]) for k in (1, 2))
    head_c = np.array(_HEAD[0])
    mirror = np.array([-1.0, 1.0])
    right_arm = np.stack([arm_a + 0.15 * (arm_b - arm_a), arm_a + 0.88 * (arm_b - arm_a)])
    right_leg = np.stack([leg_a + 0.10 * (leg_b - leg_a), leg_a + 0.85 * (leg_b - leg_a)])
    bones = np.stack([
        np.array([[0.0, 0.62], head_c]),
        right_arm * mirror,
        right_arm,
        right_leg * mirror,
        right_leg,
    ])
    points = np.array([
        head_c + [0.0, 0.22],
        arm_b * mirror,
        arm_b,
        leg_b * mirror,
        leg_b,
    ])
    regions = np.array([
        [head_c[0], head_c[1], 0.22],
        [-leg_b[0], leg_b[1], 0.12],
        [leg_b[0], leg_b[1], 0.12],
    ])
    return {
        "points": points,
        "point_names": ("head", "left hand", "right hand", "left foot", "right foot"),
        "bones": bones,
        "bone_names": ("spine", "left arm", "right arm", "left leg", "right leg"),
        "regions": regions,
        "region_names": ("head", "left foot", "right foot"),
    }


def _character_sdf(P: np.ndarray) -> np.ndarray:
    """Signed distance-like field of the character outline at points ``(..., 2)``."""

    def capsule(a, b, r):
        a, b = np.asarray(a), np.asarray(b)
        ab = b - a
        t = np.clip((P - a) @ ab / (ab @ ab), 0.0, 1.0)
        return np.linalg.norm(P - a - t[..., None] * ab, axis=-1) - r

    def smooth_min(d1, d2):
        h = np.clip(0.5 + 0.5 * (d2 - d1) / _BLEND, 0.0, 1.0)
        return d2 + (d1 - d2) * h - _BLEND * h * (1.0 - h)

    d = np.linalg.norm(P - np.asarray(_HEAD[0]), axis=-1) - _HEAD[1]
    for a, b, r in _CAPSULES:
        for s in (1.0, -1.0):
            d = smooth_min(d, capsule((s * a[0], a[1]), (s * b[0], b[1]), r))
    return d


def _character_outline(spacing: float) -> np.ndarray:
    """Outline polygon ``(k, 2)``, mirror-symmetric, with edges of about ``spacing``.

    The right half (``x >= 0``) of the zero contour runs from the head top to
    the crotch; it is resampled at equal arc length and mirrored, so the
    polygon is exactly symmetric and its only points on ``x = 0`` are those two.
    """
    from contourpy import contour_generator

    # x = 0 must be a grid column (exactly), so the half contour ends on it.
    xs = _SDF_STEP * np.arange(0, 331)
    ys = _SDF_STEP * np.arange(-50, 551)
    X, Y = np.meshgrid(xs, ys)
    lines = contour_generator(xs, ys, _character_sdf(np.stack([X, Y], axis=-1))).lines(0.0)
    if len(lines) != 1:
        raise RuntimeError(f"the character outline should be one curve, got {len(lines)}")
    half = lines[0]
    if half[0, 1] < half[-1, 1]:
        half = half[::-1]  # from the head top down to the crotch
    seg = np.linalg.norm(np.diff(half, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    n = max(64, math.ceil(s[-1] / spacing))
    t = s[-1] * np.arange(n + 1) / n
    right = np.stack([np.interp(t, s, half[:, 0]), np.interp(t, s, half[:, 1])], axis=1)
    right[[0, -1], 0] = 0.0
    left = right[-2:0:-1] * [-1.0, 1.0]
    return np.concatenate([right, left])


def character_2d(max_area=0.0009):
    """A 2D gingerbread character (head, arms, legs, body), quality-triangulated.

    The outline is the smooth union of a head disc and capsules for the body
    and limbs (about 2 units tall, feet near ``y = 0``). The bones of
    :func:`character_2d_skeleton` are constrained segments of the
    triangulation, so every bone is a chain of mesh edges; its point handles
    are input vertices. Find the handle vertices with
    :func:`character_2d_handles`.

    Parameters
    ----------
    max_area : float
        Largest triangle area (at least 1e-6); the outline is sampled at the
        matching edge length (at most 0.05). The default gives about 1,500
        vertices, ``1.3e-4`` about 10,000.

    Returns
    -------
    V : (n, 2) numpy.ndarray of float64
        First the outline points (clockwise from the head top), then the
        bone end points, then the point handles, then the vertices Triangle
        added.
    F : (f, 3) numpy.ndarray of int64
        Counter-clockwise triangles of a disc (one boundary loop).
    """
    max_area = _positive(max_area, "max_area")
    if max_area < 1e-6:
        raise ValueError(f"max_area must be at least 1e-6 (millions of triangles otherwise), got {max_area}")
    outline = _character_outline(min(_edge_length(max_area), 0.05))
    skeleton = character_2d_skeleton()
    bones = skeleton["bones"].reshape(-1, 2)
    nb, nj = len(outline), len(bones)
    V = np.concatenate([outline, bones, skeleton["points"]])
    E = np.concatenate([
        _loop_edges(0, nb),
        nb + np.arange(nj, dtype=np.int64).reshape(-1, 2),
    ])
    return _triangulate(V, E, np.zeros((0, 2)), max_area)


def character_2d_handles(V, tol=1e-9):
    """Handle vertex sets of a :func:`character_2d` mesh, found from the positions.

    Parameters
    ----------
    V : (n, 2) array_like of float
        Vertices returned by :func:`character_2d` (any ``max_area``).
    tol : float
        Distance below which a vertex counts as on a bone or at a point.

    Returns
    -------
    dict
        ``"points"``: ``(5,)`` int64, one vertex per point handle (head top,
        left hand, right hand, left foot, right foot);
        ``"bones"``: list of 5 int64 arrays (spine, left arm, right arm,
        left leg, right leg), every vertex on that bone segment, ordered from
        its start to its end;
        ``"regions"``: list of 3 int64 arrays (head, left foot, right foot),
        the vertices inside each disc of :func:`character_2d_skeleton`, sorted.
        All sets within a kind are disjoint.

    Raises
    ------
    ValueError
        If ``V`` is not 2D, or a point handle or a bone end point is not a
        vertex of ``V`` (``V`` is not a character mesh).
    """
    from starter.validation import as_points

    V = as_points(V, "V", dims=(2,))
    tol = _positive(tol, "tol")
    skeleton = character_2d_skeleton()

    def nearest(p, what):
        d = np.linalg.norm(V - p, axis=1)
        i = int(np.argmin(d))
        if d[i] > tol:
            raise ValueError(f"V has no vertex at the {what} {p.tolist()} (nearest is {d[i]:.3g} away): not a character_2d mesh")
        return i

    points = np.array([nearest(p, f"{name} handle") for p, name in zip(skeleton["points"], skeleton["point_names"])], dtype=np.int64)
    bones = []
    for (a, b), name in zip(skeleton["bones"], skeleton["bone_names"]):
        nearest(a, f"start of the {name} bone")
        nearest(b, f"end of the {name} bone")
        ab = b - a
        t = (V - a) @ ab / (ab @ ab)
        dist = np.linalg.norm(V - a - np.clip(t, 0.0, 1.0)[:, None] * ab, axis=1)
        on = np.flatnonzero(dist <= tol)
        bones.append(on[np.argsort(t[on], kind="stable")].astype(np.int64))
    regions = [
        np.flatnonzero(np.linalg.norm(V - c[:2], axis=1) <= c[2]).astype(np.int64)
        for c in skeleton["regions"]
    ]
    return {"points": points, "bones": bones, "regions": regions}
