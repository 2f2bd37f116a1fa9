"""The hidden inputs' generators every stage's checks share: random rotations and meshes drawn by the run's generator.

Every stage draws its hidden meshes the same way: a small mesh from
``starter.shapes`` with its vertices, triangles and corners shuffled by the run's
generator, so that no output can be memorized from the handout. The contract
fixes no orientation, labelling or placement, so the hidden meshes use that
freedom: clockwise as well as counter-clockwise 2D triangles (whole meshes,
single components, or triangle by triangle), and copies of a whole problem
scaled and moved far from the origin.
"""

from __future__ import annotations

import numpy as np

from starter import shapes


def random_rotation(rng: np.random.Generator, d: int, angle: float | None = None) -> np.ndarray:
    """A ``(d, d)`` rotation: uniformly random, or by ``angle`` about a random axis.

    Parameters
    ----------
    rng : numpy.random.Generator
    d : int
        2 or 3.
    angle : float, optional
        Rotation angle in radians.

    Returns
    -------
    R : (d, d) numpy.ndarray
        ``RᵀR = I``, ``det R = +1``.
    """
    if angle is None:
        A, upper = np.linalg.qr(rng.standard_normal((d, d)))
        A = A * np.sign(np.diag(upper))
        if np.linalg.det(A) < 0:
            A[:, 0] = -A[:, 0]
        return A
    c, s = np.cos(angle), np.sin(angle)
    if d == 2:
        return np.array([[c, -s], [s, c]])
    k = rng.standard_normal(3)
    k /= np.linalg.norm(k)
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + s * K + (1.0 - c) * K @ K



def relabel(V: np.ndarray, F: np.ndarray, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """The same mesh with vertices and triangles in random order and each triangle's corners rotated.

    Parameters
    ----------
    V : (n, d) numpy.ndarray
    F : (f, 3) numpy.ndarray of int
    rng : numpy.random.Generator

    Returns
    -------
    V : (n, d) numpy.ndarray of float64
    F : (f, 3) numpy.ndarray of int64
        Same orientation as the input (corners are rotated cyclically, never swapped).
    """
    order = rng.permutation(len(V))
    new_index = np.empty_like(order)
    new_index[order] = np.arange(len(V))
    F = new_index[np.asarray(F)][rng.permutation(len(F))]
    shift = rng.integers(0, 3, len(F))
    F = F[np.arange(len(F))[:, None], (np.arange(3) + shift[:, None]) % 3]
    return np.ascontiguousarray(V[order], dtype=np.float64), np.ascontiguousarray(F, dtype=np.int64)



def clockwise(F: np.ndarray) -> np.ndarray:
    """Every triangle with its corners in reverse order: a counter-clockwise 2D mesh becomes clockwise.

    Parameters
    ----------
    F : (f, 3) numpy.ndarray of int

    Returns
    -------
    (f, 3) numpy.ndarray of int64
        Same triangles, same corner positions, opposite orientation.
    """
    return np.ascontiguousarray(np.asarray(F)[:, ::-1], dtype=np.int64)



def mixed_orientation(F: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """About half of the triangles, drawn at random, with their corners in reverse order.

    The contract does not ask for consistently oriented triangles; a mesh read from
    some exporters has them in either order, and none of its quantities (edges,
    boundary loops, cotangents, energies) may depend on it.

    Returns
    -------
    (f, 3) numpy.ndarray of int64
    """
    F = np.array(F, dtype=np.int64)
    flip = rng.uniform(size=len(F)) < 0.5
    F[flip] = F[flip][:, ::-1]
    return F



def bad_handle_sets(handles: np.ndarray, n: int) -> list[tuple[str, np.ndarray]]:
    """``(what, handles)`` that a precomputation's contract refuses with a ``ValueError``: none, one repeated, one out of range.

    Parameters
    ----------
    handles : (h,) int, h >= 3
        Valid handles of a mesh of ``n`` vertices.
    """
    return [
        ("no handle", np.zeros(0, dtype=np.int64)),
        ("a handle repeated", np.r_[handles[:3], handles[:1]]),
        ("a handle out of range", np.r_[handles[:3], n]),
    ]


def unsorted_order(rng: np.random.Generator, items) -> np.ndarray:
    """``items`` (a 1-D array, or a count ``k`` for ``range(k)``) in random order, never ascending when there are two or more.

    Handles in ascending order would hide an implementation that sorts them,
    e.g. by ``np.unique``.
    """
    order = rng.permutation(items)
    if len(order) > 1 and np.all(np.diff(order) > 0):
        order = order[::-1]
    return order



def similar_copy(rng: np.random.Generator, d: int, scale: float, distance: float):
    """A map ``x -> scale · R x + t`` of ``(k, d)`` points: ``R`` a random rotation, ``‖t‖ = distance``.

    Applied to every position of a problem (rest mesh, handle targets) it gives
    the same problem at another size and place; a rotation, never a
    reflection, so triangles keep their orientation.
    """
    R = random_rotation(rng, d)
    t = rng.normal(size=d)
    t *= distance / np.linalg.norm(t)
    return lambda X: scale * np.asarray(X, dtype=np.float64) @ R.T + t



def disjoint_union(*meshes: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Several meshes of the same dimension as one mesh with several connected components.

    Parameters
    ----------
    *meshes : (V, F) pairs
        ``V`` ``(n_k, d)``, ``F`` ``(f_k, 3)``.

    Returns
    -------
    V : (Σ n_k, d) numpy.ndarray of float64
    F : (Σ f_k, 3) numpy.ndarray of int64
    """
    offsets = np.cumsum([0] + [len(V) for V, _ in meshes])
    V = np.concatenate([V for V, _ in meshes]).astype(np.float64)
    F = np.concatenate([np.asarray(F) + o for (_, F), o in zip(meshes, offsets)]).astype(np.int64)
    return V, F



def perforated_slab(n_holes: int, max_area: float = 0.03) -> tuple[np.ndarray, np.ndarray]:
    """Closed surface of genus ``n_holes``: ``starter.shapes.disc_with_holes`` extruded to thickness 0.2.

    Returns
    -------
    V : (2 n, 3) numpy.ndarray of float64
        The disc's ``n`` vertices at ``z = 0``, then again at ``z = 0.2``.
    F : (f, 3) numpy.ndarray of int64
        Bottom (flipped), top and a wall of two triangles per boundary edge,
        consistently oriented.
    """
    V2, F2 = shapes.disc_with_holes(n_holes, max_area)
    n = len(V2)
    half_edges = F2[:, [[1, 2], [2, 0], [0, 1]]].reshape(-1, 2)
    key = np.sort(half_edges, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    a, b = half_edges[counts[inverse.ravel()] == 1].T  # boundary edges as the top triangles run them
    # Quad a, b, b', a' runs each edge against the bottom's and the top's triangles.
    walls = np.concatenate([np.stack([a, b, b + n], 1), np.stack([a, b + n, a + n], 1)])
    V = np.concatenate([np.c_[V2, np.zeros(n)], np.c_[V2, np.full(n, 0.2)]])
    return V, np.concatenate([F2[:, ::-1], F2 + n, walls]).astype(np.int64)



def jittered_grid(rng: np.random.Generator, nx: int, ny: int, width: float = 1.0, height: float = 1.0, amount: float = 0.3) -> tuple[np.ndarray, np.ndarray]:
    """``starter.shapes.grid_2d`` with interior vertices moved by up to ``amount`` cells: obtuse triangles, negative cotangents.

    Returns
    -------
    V : ((nx + 1)(ny + 1), 2) numpy.ndarray of float64
    F : (2 nx ny, 3) numpy.ndarray of int64
        Still counter-clockwise for ``amount < 0.5``.
    """
    V, F = shapes.grid_2d(nx, ny, width=width, height=height)
    interior = np.all((V > 0.0) & (V < [width, height]), axis=1)
    V[interior] += rng.uniform(-amount, amount, (int(interior.sum()), 2)) * [width / nx, height / ny]
    return V, F



def closed_mesh_with_hole(V: np.ndarray, F: np.ndarray, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A closed mesh with one random triangle removed: one boundary loop, same genus.

    Returns
    -------
    V : (n, d) numpy.ndarray
        ``V`` itself (every vertex of a closed mesh keeps other triangles).
    F : (f - 1, 3) numpy.ndarray
    """
    return V, np.delete(F, rng.integers(len(F)), axis=0)
