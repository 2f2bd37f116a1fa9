"""Regenerate the course meshes in ``data/`` bit for bit.

Run ``.venv/bin/python data/make_meshes.py`` (or ``--out DIR`` to write
elsewhere). Each mesh becomes ``<name>.npz`` holding ``V`` (float64), ``F``
(int64; triangles ``(f, 3)``, or tetrahedra ``(f, 4)`` for the volumetric
meshes ``*_tet``) and its handle sets: a set that is one index array is stored as
``handles/<set>``, a set that is a list of arrays as ``handles/<set>/<k>``.

``np.savez`` stamps every archive member with the current time, so reruns
would differ; this script writes the same ``.npy`` members itself into an
uncompressed zip with a fixed timestamp, which ``np.load`` reads as usual.
"""

from __future__ import annotations

import argparse
import io
import sys
import zipfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
# Run from a checkout without installing the package.
sys.path.insert(0, str(HERE.parent))

from starter import shapes  # noqa: E402

_ZIP_TIME = (1980, 1, 1, 0, 0, 0)

# name -> (generator, keyword arguments); the origin column of data/README.md.
GENERATED = {
    "bar": (shapes.bar, dict(length=4.0, width=1.0, height=1.0, nx=48, ny=12, nz=12)),
    "bar_coarse": (shapes.bar, dict(length=4.0, width=1.0, height=1.0, nx=20, ny=5, nz=5)),
    "bar_fine": (shapes.bar, dict(length=4.0, width=1.0, height=1.0, nx=96, ny=24, nz=24)),
    "cylinder": (shapes.cylinder, dict(length=4.0, radius=0.5, n_around=32, n_along=64, caps=True)),
    "character": (shapes.character_2d, dict(max_area=0.0009)),
    "character_fine": (shapes.character_2d, dict(max_area=0.00013)),
    "torus": (shapes.torus, dict(R=1.0, r=0.35, n_major=48, n_minor=24)),
    "disc_with_holes": (shapes.disc_with_holes, dict(n_holes=2, max_area=0.002)),
}
# name -> pyvista.examples loader; the files ship inside the pyvista wheel.
PYVISTA = {"ant": "load_ant", "nut": "load_nut", "sphere": "load_sphere"}

# Kuhn's split of the unit cube into 6 tetrahedra along its main diagonal: one
# per order in which the path from corner (0,0,0) to (1,1,1) steps along the
# axes. Neighbouring cubes split their shared square along the same diagonal,
# so the tetrahedra of any set of grid cubes form a conforming mesh.
_KUHN_ORDERS = ((0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0))
# Voxel size of the hand and its boxes in voxels: (x0, x1, y0, y1, z0, z1).
HAND_VOXEL = 0.1
HAND_BOXES = {
    "palm": (0, 11, 0, 10, 0, 4),
    "index": (0, 2, 10, 17, 0, 4),
    "middle": (3, 5, 10, 18, 0, 4),
    "ring": (6, 8, 10, 17, 0, 4),
    "little": (9, 11, 10, 15, 0, 4),
    "thumb": (-6, 0, 3, 5, 0, 4),
}
# Bones of the hand, as grid points (voxel units) on the mid-plane z = 2: the
# palm's from the wrist to the middle knuckle, then one per finger from its
# knuckle to near its tip. Handle k is every vertex on segment k.
HAND_BONES = {
    "palm": ((4, 1, 2), (4, 9, 2)),
    "index": ((1, 10, 2), (1, 16, 2)),
    "middle": ((4, 10, 2), (4, 17, 2)),
    "ring": ((7, 10, 2), (7, 16, 2)),
    "little": ((10, 10, 2), (10, 14, 2)),
    "thumb": ((-1, 4, 2), (-5, 4, 2)),
}


def voxel_tetrahedra(voxels: np.ndarray, size: float) -> tuple[np.ndarray, np.ndarray]:
    """Positively oriented tetrahedra filling a set of grid cubes (Kuhn's split).

    Parameters
    ----------
    voxels : (c, 3) array_like of int
        Integer corner ``(i, j, k)`` of each cube ``[i, i+1] x [j, j+1] x [k, k+1]``.
    size : float
        Edge length of a cube.

    Returns
    -------
    V : (n, 3) numpy.ndarray of float64
        The cubes' corners, ``size`` times their grid coordinates, sorted
        lexicographically by ``(i, j, k)``.
    T : (6 c, 4) numpy.ndarray of int64
        Six tetrahedra per cube, each with positive volume ``size³ / 6``.
    """
    voxels = np.asarray(voxels, dtype=np.int64)
    paths = []
    for order in _KUHN_ORDERS:
        steps = np.eye(3, dtype=np.int64)[list(order)]
        path = np.vstack([np.zeros(3, dtype=np.int64), np.cumsum(steps, axis=0)])
        if np.linalg.det(steps) < 0:  # an odd order walks a negatively oriented tetrahedron
            path = path[[0, 2, 1, 3]]
        paths.append(path)
    corners = voxels[:, None, None, :] + np.array(paths)[None]  # (c, 6, 4, 3)
    grid, index = np.unique(corners.reshape(-1, 3), axis=0, return_inverse=True)
    T = index.reshape(-1, 4).astype(np.int64)
    return size * grid.astype(np.float64), T


def box_voxels(x0, x1, y0, y1, z0, z1) -> np.ndarray:
    """Integer corners of the cubes filling ``[x0, x1] x [y0, y1] x [z0, z1]``."""
    axes = np.meshgrid(np.arange(x0, x1), np.arange(y0, y1), np.arange(z0, z1), indexing="ij")
    return np.stack([a.ravel() for a in axes], axis=1)


def bar_tet(length=4.0, width=1.0, height=1.0, nx=24, ny=6, nz=6):
    """The volumetric bar ``[0, length] x [0, width] x [0, height]``: ``nx ny nz`` boxes, 6 tetrahedra each.

    Returns
    -------
    V : (n, 3) numpy.ndarray of float64
    T : (6 nx ny nz, 4) numpy.ndarray of int64
    """
    V, T = voxel_tetrahedra(box_voxels(0, nx, 0, ny, 0, nz), 1.0)
    scale = np.array([length / nx, width / ny, height / nz])
    return V * scale, T


def hand_tet():
    """A blocky hand (palm, four fingers, thumb) of ``HAND_VOXEL`` cubes, 6 tetrahedra each.

    Returns
    -------
    V : (n, 3) numpy.ndarray of float64
    T : (f, 4) numpy.ndarray of int64
    bones : list of numpy.ndarray of int64
        One handle per bone of ``HAND_BONES``: the vertices on the segment,
        ordered from its first end to its second.
    """
    voxels = np.unique(np.vstack([box_voxels(*box) for box in HAND_BOXES.values()]), axis=0)
    V, T = voxel_tetrahedra(voxels, HAND_VOXEL)
    grid = np.rint(V / HAND_VOXEL).astype(np.int64)
    lookup = {tuple(p): i for i, p in enumerate(grid.tolist())}
    bones = []
    for start, end in HAND_BONES.values():
        start, end = np.array(start), np.array(end)
        count = int(np.abs(end - start).max())
        points = start + np.outer(np.arange(count + 1), (end - start) // count)
        bones.append(np.array([lookup[tuple(p)] for p in points.tolist()], dtype=np.int64))
    return V, T, bones


def end_handles(V: np.ndarray, length: float) -> dict[str, np.ndarray]:
    """Vertices on the planes ``x = 0`` ("left") and ``x = length`` ("right").

    The generators place these ends exactly (``np.linspace`` end points), so
    the comparison is exact.
    """
    return {
        "left": np.flatnonzero(V[:, 0] == 0.0).astype(np.int64),
        "right": np.flatnonzero(V[:, 0] == length).astype(np.int64),
    }


def clean_triangles(V: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Merge coincident points, drop degenerate and repeated triangles, drop unused points.

    Vertices keep their first-occurrence order and triangles their order, so
    the result depends only on the input.

    Parameters
    ----------
    V : (n, 3) array_like of float
    F : (f, 3) array_like of int

    Returns
    -------
    V : (n', 3) numpy.ndarray of float64
    F : (f', 3) numpy.ndarray of int64
    """
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    _, first, inverse = np.unique(V, axis=0, return_index=True, return_inverse=True)
    # Renumber the unique points by first occurrence, not by sorted position.
    rank = np.empty(len(first), dtype=np.int64)
    rank[np.argsort(first, kind="stable")] = np.arange(len(first))
    F = rank[inverse.reshape(-1)][F]
    V = V[np.sort(first)]
    repeated = (F[:, 0] == F[:, 1]) | (F[:, 1] == F[:, 2]) | (F[:, 2] == F[:, 0])
    area2 = np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    F = F[~repeated & (area2 > 0.0)]
    _, keep = np.unique(np.sort(F, axis=1), axis=0, return_index=True)
    F = F[np.sort(keep)]
    used = np.zeros(len(V), dtype=bool)
    used[F.ravel()] = True
    new_index = np.cumsum(used) - 1
    return np.ascontiguousarray(V[used]), np.ascontiguousarray(new_index[F])


def pyvista_mesh(loader: str) -> tuple[np.ndarray, np.ndarray]:
    """Load a pyvista example mesh (no network), as cleaned triangles."""
    from pyvista import examples

    mesh = getattr(examples, loader)().triangulate()
    return clean_triangles(mesh.points, mesh.regular_faces)


def build_meshes() -> dict[str, dict[str, np.ndarray]]:
    """Every course mesh as the arrays of its ``.npz``, in a fixed order."""
    out = {}
    for name, (generator, kwargs) in GENERATED.items():
        V, F = generator(**kwargs)
        arrays = {"V": V, "F": F}
        if generator in (shapes.bar, shapes.cylinder):
            sets = end_handles(V, kwargs["length"])
        elif generator is shapes.character_2d:
            sets = shapes.character_2d_handles(V)
        else:
            sets = {}
        for key, value in sets.items():
            if isinstance(value, list):
                arrays.update({f"handles/{key}/{k}": a for k, a in enumerate(value)})
            else:
                arrays[f"handles/{key}"] = value
        out[name] = arrays
    for name, loader in PYVISTA.items():
        V, F = pyvista_mesh(loader)
        out[name] = {"V": V, "F": F}
    V, T = bar_tet()
    out["bar_tet"] = {"V": V, "F": T, **{f"handles/{k}": a for k, a in end_handles(V, 4.0).items()}}
    V, T, bones = hand_tet()
    out["hand_tet"] = {"V": V, "F": T, **{f"handles/bones/{k}": a for k, a in enumerate(bones)}}
    return out


def write_npz(path: Path, arrays: dict[str, np.ndarray]) -> None:
    """Write ``arrays`` as an ``.npz`` whose bytes depend only on the arrays."""
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_STORED) as zf:
        for key, value in arrays.items():
            buffer = io.BytesIO()
            np.lib.format.write_array(buffer, np.ascontiguousarray(value), allow_pickle=False)
            info = zipfile.ZipInfo(f"{key}.npy", date_time=_ZIP_TIME)
            info.external_attr = 0o644 << 16
            zf.writestr(info, buffer.getvalue())


def write_meshes(out_dir: Path) -> list[Path]:
    """Write every course mesh to ``out_dir/<name>.npz``; return the paths."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = []
    for name, arrays in build_meshes().items():
        path = out_dir / f"{name}.npz"
        write_npz(path, arrays)
        paths.append(path)
    return paths


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=HERE, help="output folder (default: data/)")
    args = parser.parse_args(argv)
    print("| name | vertices | faces | bytes |")
    print("|---|---:|---:|---:|")
    for path in write_meshes(args.out):
        with np.load(path, allow_pickle=False) as z:
            print(f"| {path.name} | {len(z['V'])} | {len(z['F'])} | {path.stat().st_size} |")


if __name__ == "__main__":
    main()
