"""What the kernel wrote is read as hostile data: no links, FIFOs or devices, no size the case does not need."""

from __future__ import annotations

import io
import json
import os
import time
import tracemalloc
import zipfile

import numpy as np
import pytest
import scipy.sparse as sp

from grader.harness.outputs import OutputError, element_budget, read_outputs

GOOD = {"records": [{"ok": True, "output": {"kind": "array"}, "seconds": 0.1}]}


def write(folder, records=GOOD, arrays=None):
    folder.mkdir(exist_ok=True)
    (folder / "f.json").write_text(json.dumps(records))
    np.savez(folder / "f.npz", **(arrays if arrays is not None else {"c0": np.eye(3)}))
    return folder


def test_a_plain_output_within_its_budget_is_read(tmp_path):
    out = read_outputs("f", write(tmp_path / "out"), 1, [np.eye(3)]).cases[0]
    np.testing.assert_array_equal(out.value, np.eye(3))


@pytest.mark.parametrize("name", ["f.json", "f.npz"])
def test_a_link_to_a_host_file_is_refused_and_never_read(tmp_path, name):
    secret = tmp_path / "secret.txt"
    secret.write_text("root:$6$hash")
    folder = write(tmp_path / "out")
    (folder / name).unlink()
    (folder / name).symlink_to(secret)
    with pytest.raises(OutputError, match="not a plain file") as caught:
        read_outputs("f", folder, 1)
    assert "root" not in str(caught.value)


def test_a_fifo_is_refused_at_once_instead_of_blocking(tmp_path):
    folder = write(tmp_path / "out")
    (folder / "f.json").unlink()
    os.mkfifo(folder / "f.json")
    started = time.monotonic()
    with pytest.raises(OutputError, match="not a plain file"):
        read_outputs("f", folder, 1)
    assert time.monotonic() - started < 1


def test_an_outputs_folder_swapped_for_a_link_is_refused(tmp_path):
    real = write(tmp_path / "elsewhere")
    (tmp_path / "out").symlink_to(real)
    with pytest.raises(OutputError, match="not a plain folder"):
        read_outputs("f", tmp_path / "out", 1)


def test_a_huge_declared_array_shape_fails_its_case_without_allocating(tmp_path):
    folder = write(tmp_path / "out")
    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(header, {"descr": "<f8", "fortran_order": False, "shape": (10**6, 10**6)})
    with zipfile.ZipFile(folder / "f.npz", "w") as archive:
        archive.writestr("c0.npy", header.getvalue())
    tracemalloc.start()
    try:
        out = read_outputs("f", folder, 1, [np.eye(3)]).cases[0]
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert out.value is None and "far larger than this case's answer" in out.error
    assert peak < 2**20


def test_a_sparse_matrix_of_huge_declared_shape_fails_its_case(tmp_path):
    arrays = {"c0.data": np.zeros(0), "c0.row": np.zeros(0, np.int64), "c0.col": np.zeros(0, np.int64)}
    records = {"records": [{"ok": True, "output": {"kind": "sparse", "shape": [2**31 - 1, 2**31 - 1]}}]}
    out = read_outputs("f", write(tmp_path / "out", records, arrays), 1, [sp.eye(50, format="csr")]).cases[0]
    assert out.value is None and "far larger" in out.error


def test_a_correct_sparse_matrix_is_rebuilt_by_scipy(tmp_path):
    coo = sp.coo_matrix(sp.eye(4))
    arrays = {"c0.data": coo.data, "c0.row": coo.row.astype(np.int64), "c0.col": coo.col.astype(np.int64)}
    records = {"records": [{"ok": True, "output": {"kind": "sparse", "shape": [4, 4]}}]}
    out = read_outputs("f", write(tmp_path / "out", records, arrays), 1, [sp.eye(4)]).cases[0]
    assert (out.value != sp.eye(4)).nnz == 0


def test_a_long_sequence_of_energies_fails_its_case(tmp_path):
    records = {"records": [{"ok": True, "output": {"kind": "seq", "items": [{"kind": "array"}, {"kind": "array"}]}}]}
    arrays = {"c0.0": np.zeros((10, 2)), "c0.1": np.zeros(3 * 10**6)}
    expected = [(np.zeros((10, 2)), np.zeros(10))]
    out = read_outputs("f", write(tmp_path / "out", records, arrays), 1, expected).cases[0]
    assert out.value is None and "far larger" in out.error
    assert element_budget(expected[0]) < 3 * 10**6


def test_records_nested_beyond_recursion_are_malformed_not_a_crash(tmp_path):
    folder = write(tmp_path / "out")
    (folder / "f.json").write_text("[" * 200_000 + "]" * 200_000)
    with pytest.raises(OutputError, match="malformed"):
        read_outputs("f", folder, 1)


def test_a_compressed_archive_is_refused_so_nothing_is_inflated(tmp_path):
    folder = write(tmp_path / "out")
    np.savez_compressed(folder / "f.npz", c0=np.zeros(10))
    with pytest.raises(OutputError, match="compressed"):
        read_outputs("f", folder, 1)


def test_object_and_string_dtypes_are_refused(tmp_path):
    out = read_outputs("f", write(tmp_path / "out", arrays={"c0": np.array(["a", "b"])}), 1).cases[0]
    assert out.value is None and "not a numeric array" in out.error
