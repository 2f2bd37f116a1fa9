"""Read what the kernel wrote back, as untrusted data, into plain Python/numpy values.

Nothing from the kernel is unpickled or executed: arrays are loaded with
``allow_pickle=False``, converted to fresh plain ``numpy.ndarray`` objects, and
sparse matrices are rebuilt here by trusted scipy from their triplets.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp

#: Largest output file accepted from one function's collection.
MAX_OUTPUT_BYTES = 256 * 2**20


class OutputError(ValueError):
    """A student's output cannot be read as the contract says it should be."""


@dataclass
class CaseOutput:
    """One case's result: ``value`` when ``error`` is None."""

    value: Any
    error: str | None
    seconds: float | None


@dataclass
class Collected:
    function: str
    cases: list[CaseOutput]
    peak_rss_bytes: int | None


def _rebuild(meta: dict, key: str, arrays) -> Any:
    kind = meta.get("kind")
    if kind == "array":
        return np.array(arrays[key], copy=True)
    if kind == "sparse":
        shape = tuple(int(s) for s in meta["shape"])
        return sp.coo_matrix(
            (np.asarray(arrays[key + ".data"], float), (np.asarray(arrays[key + ".row"]), np.asarray(arrays[key + ".col"]))),
            shape=shape,
        ).tocsr()
    if kind == "seq":
        return tuple(_rebuild(m, f"{key}.{i}", arrays) for i, m in enumerate(meta["items"]))
    if kind == "invalid":
        raise OutputError(f"returned a {meta.get('type')}, which is not a numeric array ({meta.get('error')})")
    raise OutputError(f"unreadable output record {kind!r}")


def read_outputs(function: str, directory: Path, n_cases: int) -> Collected:
    """Read ``directory/<function>.{json,npz}`` written by the kernel.

    Raises
    ------
    OutputError
        If the files are missing, too large or malformed (as a whole).
    """
    directory = Path(directory)
    meta_path, npz_path = directory / f"{function}.json", directory / f"{function}.npz"
    if not meta_path.is_file() or not npz_path.is_file():
        raise OutputError("no outputs were written (the kernel stopped before the collection finished)")
    if npz_path.stat().st_size > MAX_OUTPUT_BYTES:
        raise OutputError(f"outputs are larger than {MAX_OUTPUT_BYTES // 2**20} MiB")
    try:
        meta = json.loads(meta_path.read_text())
        records = meta["records"]
        arrays = np.load(npz_path, allow_pickle=False)
    except Exception as exc:  # noqa: BLE001 - any malformed file is the same failure
        raise OutputError(f"outputs are malformed: {exc}") from None
    if not isinstance(records, list) or len(records) != n_cases:
        raise OutputError(f"expected {n_cases} case records, found {len(records) if isinstance(records, list) else 'none'}")
    cases = []
    with arrays:
        for i, rec in enumerate(records):
            seconds = rec.get("seconds") if isinstance(rec.get("seconds"), (int, float)) else None
            if not rec.get("ok"):
                cases.append(CaseOutput(None, str(rec.get("error", "failed"))[:2000], seconds))
                continue
            try:
                cases.append(CaseOutput(_rebuild(rec["output"], f"c{i}", arrays), None, seconds))
            except (OutputError, KeyError, ValueError, TypeError) as exc:
                cases.append(CaseOutput(None, f"output could not be read: {exc}", seconds))
    peak = meta.get("peak_rss_bytes")
    return Collected(function, cases, int(peak) if isinstance(peak, (int, float)) else None)
