"""data/make_meshes.py: reruns reproduce the committed data/ bit for bit; README and size match."""

import importlib.util
import re
import sys
from pathlib import Path

import numpy as np
import pytest

from starter import meshes

DATA = Path(meshes.__file__).resolve().parent.parent / "data"


@pytest.fixture(scope="module")
def make_meshes():
    spec = importlib.util.spec_from_file_location("make_meshes", DATA / "make_meshes.py")
    module = importlib.util.module_from_spec(spec)
    path = list(sys.path)
    spec.loader.exec_module(module)
    sys.path[:] = path  # the script puts the repository first, for running it from a checkout
    return module


def test_two_runs_write_the_committed_files_byte_for_byte(make_meshes, tmp_path):
    first = make_meshes.write_meshes(tmp_path / "first")
    second = make_meshes.write_meshes(tmp_path / "second")
    committed = sorted(p.name for p in DATA.glob("*.npz"))
    assert sorted(p.name for p in first) == sorted(p.name for p in second) == committed
    for name in committed:
        expected = (DATA / name).read_bytes()
        assert (tmp_path / "first" / name).read_bytes() == expected, f"{name} differs from data/"
        assert (tmp_path / "second" / name).read_bytes() == expected, f"{name} differs between runs"


def test_archives_hold_only_plain_arrays_under_the_documented_keys(make_meshes):
    for path in sorted(DATA.glob("*.npz")):
        with np.load(path, allow_pickle=False) as z:
            assert z["V"].dtype == np.float64 and z["F"].dtype == np.int64
            for key in z.files:
                assert key in ("V", "F") or re.fullmatch(r"handles/[a-z_]+(/\d+)?", key), key
                if key.startswith("handles/"):
                    assert z[key].dtype == np.int64 and z[key].ndim == 1 and len(z[key]) > 0


def test_readme_table_lists_every_file_with_its_counts_and_size():
    rows = re.findall(r"^\| (\S+\.npz) \| (\d+) \| (\d+) \| (\d+) \|", (DATA / "README.md").read_text(), re.M)
    assert sorted(r[0] for r in rows) == sorted(p.name for p in DATA.glob("*.npz"))
    for name, n, f, size in rows:
        with np.load(DATA / name, allow_pickle=False) as z:
            assert (len(z["V"]), len(z["F"])) == (int(n), int(f)), name
        assert (DATA / name).stat().st_size == int(size), name


def test_data_folder_stays_under_three_megabytes():
    assert sum(p.stat().st_size for p in DATA.iterdir() if p.is_file()) < 3_000_000


def test_clean_triangles_merges_points_and_drops_bad_triangles(make_meshes):
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [9, 9, 9], [1, 0, 0], [0, 0, 1], [2, 0, 0]], dtype=np.float32)
    F = np.array([
        [0, 1, 2],  # kept
        [0, 2, 5],  # kept
        [4, 0, 5],  # vertex 4 duplicates vertex 1: kept as (1, 0, 5)
        [1, 4, 2],  # repeated vertex once 4 -> 1
        [0, 1, 6],  # collinear: zero area
        [2, 1, 0],  # the first triangle again (reversed)
    ])
    V2, F2 = make_meshes.clean_triangles(V, F)
    assert V2.dtype == np.float64 and F2.dtype == np.int64
    # Vertex 3 is unused, 4 merges into 1, 6 is only in the dropped triangle.
    assert np.array_equal(V2, [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    assert np.array_equal(F2, [[0, 1, 2], [0, 2, 3], [1, 0, 3]])
