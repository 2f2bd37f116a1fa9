"""Regenerate the course meshes in ``data/`` bit for bit.

Run ``.venv/bin/python data/make_meshes.py`` (or ``--out DIR`` to write
elsewhere). Each mesh becomes ``<name>.npz`` holding ``V`` (float64), ``F``
(int64) and its handle sets: a set that is one index array is stored as
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
