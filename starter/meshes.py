"""Load the course meshes shipped in ``data/`` (written by ``data/make_meshes.py``).

The data folder is ``$DEFORMLAB_DATA`` if that variable is set, else the
``data/`` folder next to the ``starter`` package, else ``./data``.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

__all__ = ["data_dir", "mesh_names", "load_mesh", "load_handles"]


def _candidates() -> list[Path]:
    env = os.environ.get("DEFORMLAB_DATA")
    if env:
        return [Path(env)]
    return [Path(__file__).resolve().parent.parent / "data", Path.cwd() / "data"]


def data_dir() -> Path:
    """The folder the course meshes are read from.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    FileNotFoundError
        If no candidate folder exists; the message lists where it looked.
    """
    candidates = _candidates()
    for folder in candidates:
        if folder.is_dir():
            return folder
    looked = ", ".join(str(c) for c in candidates)
    hint = "" if os.environ.get("DEFORMLAB_DATA") else " (set DEFORMLAB_DATA to the folder holding the .npz files)"
    raise FileNotFoundError(f"no DeformLab data folder found; looked in: {looked}{hint}")


def mesh_names() -> list[str]:
    """Names of the available meshes, sorted.

    Returns
    -------
    list of str
        One per ``<name>.npz`` in :func:`data_dir`.
    """
    return sorted(p.stem for p in data_dir().glob("*.npz"))


def _archive(name) -> Path:
    names = mesh_names()
    if not isinstance(name, str) or name not in names:
        raise ValueError(f"name must be one of the course meshes {names}, got {name!r}")
    return data_dir() / f"{name}.npz"


def load_mesh(name):
    """Vertices and triangles of a course mesh.

    Parameters
    ----------
    name : str
        One of :func:`mesh_names`.

    Returns
    -------
    V : (n, d) numpy.ndarray of float64
        ``d`` is 2 for the planar meshes, 3 for surfaces and volumes.
    F : (f, 3) or (f, 4) numpy.ndarray of int64
        Triangles; tetrahedra for the volumetric meshes (``bar_tet``, ``hand_tet``).

    Raises
    ------
    ValueError
        If ``name`` is not an available mesh (the message lists them).
    FileNotFoundError
        If there is no data folder.
    """
    with np.load(_archive(name), allow_pickle=False) as z:
        return z["V"], z["F"]


def load_handles(name):
    """Handle vertex sets of a course mesh.

    Parameters
    ----------
    name : str
        One of :func:`mesh_names`.

    Returns
    -------
    dict of str to numpy.ndarray or list of numpy.ndarray
        Each value is an int64 index array (e.g. ``"left"``, ``"right"`` of the
        bars; ``"points"`` of the characters, one vertex per point handle) or a
        list of them, one per handle (``"bones"``, ``"regions"``). Empty for a
        mesh without handles.

    Raises
    ------
    ValueError
        If ``name`` is not an available mesh (the message lists them).
    """
    sets: dict = {}
    lists: dict[str, dict[int, np.ndarray]] = {}
    with np.load(_archive(name), allow_pickle=False) as z:
        for key in z.files:
            parts = key.split("/")
            if parts[0] != "handles":
                continue
            if len(parts) == 2:
                sets[parts[1]] = z[key]
            else:
                lists.setdefault(parts[1], {})[int(parts[2])] = z[key]
    for key, members in lists.items():
        sets[key] = [members[k] for k in sorted(members)]
    return {key: sets[key] for key in sorted(sets)}
