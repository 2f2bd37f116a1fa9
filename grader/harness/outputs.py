"""Read what the kernel wrote back, as hostile data, into plain Python/numpy values.

Every byte of the outputs folder is the student's: the files may be links, FIFOs
or devices, the folder itself may have been swapped for a link, the JSON may be
huge or nested without end, and an ``.npz`` member may declare any shape. So:

- files are opened relative to the outputs folder's own descriptor, never
  following a link (``O_NOFOLLOW``), without blocking (``O_NONBLOCK``), and
  only regular files within a size cap are read;
- the JSON is capped in size, parsed with its recursion caught, and checked
  field by field;
- ``.npz`` members must be stored (not compressed: nothing to inflate), and
  each array's header is read first: only numeric dtypes, and no more elements
  than the reference's output for the same case allows (a few times its size),
  before a byte is allocated. Sparse matrices' declared shapes get the same
  bound, then are rebuilt here by trusted scipy from their triplets.

Nothing is unpickled or executed.
"""

from __future__ import annotations

import io
import json
import math
import os
import stat
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp

from starter.library_policy import OWN as POLICY
from starter.library_policy import forbidden

#: Largest ``.npz`` accepted from one function's collection.
MAX_OUTPUT_BYTES = 256 * 2**20
#: Largest ``.json`` record file (case records: errors, timings, output kinds).
MAX_RECORDS_BYTES = 4 * 2**20
#: An output may hold this many times the reference's elements (plus ``SLACK_ELEMENTS``)
#: and still be read: enough to show a wrong shape in feedback, never enough to exhaust memory.
SIZE_FACTOR = 4
SLACK_ELEMENTS = 4096
#: Elements allowed where the reference has no output to compare with.
DEFAULT_ELEMENTS = 2**22
#: Nesting of tuples in one output.
MAX_DEPTH = 4
MAX_ITEMS = 64
#: Recorded callee calls (``grader.checks.callees``): per case, and elements read over one function's cases.
MAX_CALLS = 200
RECORD_ELEMENTS = 2**23
#: Entries of a records file's ``policy_violations`` read (the policy lists fewer routines per function).
MAX_POLICY_VIOLATIONS = 64


class OutputError(ValueError):
    """A student's output cannot be read as the contract says it should be."""


@dataclass
class CaseOutput:
    """One case's result: ``value`` when ``error`` is None; ``calls``, what it called of the course's other functions."""

    value: Any
    error: str | None
    seconds: float | None
    calls: list = field(default_factory=list)


@dataclass
class RecordedCall:
    """One call the student's function made to another course function, as the kernel wrote it down.

    Attributes
    ----------
    name : str
        The course function called.
    args : list, kwargs : dict
        Sketches of the arguments (``__deformlab_sketch__``), validated; ``None`` for batched calls.
    items : numpy.ndarray or None
        A batched call's whole input, ``(..., *item shape)``.
    output : any
        The student's output, read like a collected output (plain arrays, CSR matrices, tuples).
    """

    name: str
    args: list | None
    kwargs: dict | None
    items: np.ndarray | None
    output: Any


@dataclass
class Collected:
    function: str
    cases: list[CaseOutput]
    peak_rss_bytes: int | None
    #: library routines the course's policy forbids in ``function`` that the kernel saw it call
    policy_violations: tuple[str, ...] = ()


def element_count(value: Any) -> int:
    """Elements a trusted value holds: array sizes, sparse matrices' dense sizes, summed over tuples.

    Parameters
    ----------
    value : any
        A reference output.

    Returns
    -------
    int
    """
    if sp.issparse(value):
        return int(math.prod(value.shape))
    if isinstance(value, np.ndarray):
        return int(value.size)
    if isinstance(value, (tuple, list)):
        return sum(element_count(v) for v in value)
    return 1


def element_budget(expected: Any) -> int:
    """How many elements a student's output for a case may hold, from the reference's output.

    Parameters
    ----------
    expected : any
        The reference's output on the same case, or ``None`` if there is none.

    Returns
    -------
    int
    """
    if expected is None:
        return DEFAULT_ELEMENTS
    return SIZE_FACTOR * element_count(expected) + SLACK_ELEMENTS


def _read_untrusted(directory_fd: int, name: str, limit: int) -> bytes:
    """The bytes of ``name`` inside an open folder: a regular file of at most ``limit`` bytes, links never followed."""
    try:
        fd = os.open(name, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC, dir_fd=directory_fd)
    except FileNotFoundError:
        raise OutputError("no outputs were written (the kernel stopped before the collection finished)") from None
    except OSError as exc:  # ELOOP: a link
        raise OutputError(f"{name} is not a plain file ({exc.strerror})") from None
    with os.fdopen(fd, "rb") as fh:
        info = os.fstat(fh.fileno())
        if not stat.S_ISREG(info.st_mode):
            raise OutputError(f"{name} is not a plain file")
        if info.st_size > limit:
            raise OutputError(f"{name} is larger than {limit // 2**20} MiB")
        data = fh.read(info.st_size + 1)  # not limit + 1: read() allocates what it is asked for
    if len(data) > limit:
        raise OutputError(f"{name} is larger than {limit // 2**20} MiB")
    return data


def _open_folder(directory: Path) -> int:
    try:
        return os.open(directory, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW | os.O_CLOEXEC)
    except FileNotFoundError:
        raise OutputError("no outputs were written (the kernel stopped before the collection finished)") from None
    except OSError as exc:
        raise OutputError(f"the outputs folder is not a plain folder ({exc.strerror})") from None


class _Arrays:
    """The members of a stored (uncompressed) ``.npz``, each loaded only after its header passed the checks."""

    def __init__(self, data: bytes):
        try:
            self._zip = zipfile.ZipFile(io.BytesIO(data))
            members = self._zip.infolist()
        except (zipfile.BadZipFile, ValueError, OSError) as exc:
            raise OutputError(f"outputs are malformed: {exc}") from None
        if len(members) > 100_000:
            raise OutputError("outputs are malformed: too many arrays")
        self._members = {}
        for m in members:
            if m.compress_type != zipfile.ZIP_STORED or m.file_size > len(data):
                raise OutputError("outputs are malformed: a compressed or oversized array")
            if m.filename.endswith(".npy"):
                self._members[m.filename[:-4]] = m

    def header(self, key: str) -> tuple[tuple[int, ...], np.dtype]:
        """Declared shape and dtype of array ``key``, read from its header alone."""
        member = self._members.get(key)
        if member is None:
            raise OutputError(f"array {key} is missing")
        with self._zip.open(member) as fh:
            version = np.lib.format.read_magic(fh)
            reader = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
            shape, _, dtype = reader(fh, max_header_size=10_000)
        if dtype.hasobject or dtype.kind not in "biuf":
            raise OutputError(f"not a numeric array (dtype {dtype})")
        return tuple(int(s) for s in shape), dtype

    def load(self, key: str, budget: int) -> np.ndarray:
        """Array ``key`` as a fresh plain ndarray, if its declared size fits ``budget`` elements."""
        shape, _ = self.header(key)
        if math.prod(shape) > budget:
            raise OutputError(f"an array of shape {shape} is far larger than this case's answer")
        with self._zip.open(self._members[key]) as fh:
            return np.array(np.lib.format.read_array(fh, allow_pickle=False), copy=True)


def _rebuild(meta: Any, key: str, arrays: _Arrays, budget: int, depth: int = 0) -> Any:
    if not isinstance(meta, dict):
        raise OutputError("unreadable output record")
    kind = meta.get("kind")
    if kind == "array":
        return arrays.load(key, budget)
    if kind == "sparse":
        shape = meta.get("shape")
        if not (isinstance(shape, list) and len(shape) == 2 and all(isinstance(s, int) and not isinstance(s, bool) and s >= 0 for s in shape)):
            raise OutputError("a sparse matrix with an unreadable shape")
        if math.prod(shape) > budget:
            raise OutputError(f"a sparse matrix of shape {tuple(shape)} is far larger than this case's answer")
        data, row, col = (arrays.load(f"{key}.{part}", budget) for part in ("data", "row", "col"))
        if not (data.ndim == row.ndim == col.ndim == 1 and len(data) == len(row) == len(col)):
            raise OutputError("a sparse matrix whose triplets do not match")
        return sp.coo_matrix((data.astype(float), (row.astype(np.int64), col.astype(np.int64))), shape=tuple(shape)).tocsr()
    if kind == "seq":
        items = meta.get("items")
        if not isinstance(items, list) or len(items) > MAX_ITEMS or depth >= MAX_DEPTH:
            raise OutputError("a sequence nested too deeply or too long")
        return tuple(_rebuild(m, f"{key}.{i}", arrays, budget, depth + 1) for i, m in enumerate(items))
    if kind == "invalid":
        return_type = str(meta.get("type"))[:80]
        raise OutputError(f"returned a {return_type}, which is not a numeric array ({str(meta.get('error'))[:300]})")
    raise OutputError(f"unreadable output record {str(kind)[:40]!r}")


def policy_violations(function: str, reported: Any) -> tuple[str, ...]:
    """The routines of the library-call policy the kernel says ``function`` called, as the grader's own strings.

    ``reported`` is hostile: only a list is read, only its first entries, and only names the
    policy forbids in ``function`` are kept (the policy table's own strings, never the kernel's text).
    """
    if not isinstance(reported, list):
        return ()
    allowed = {r: r for r in forbidden(function)} if function in POLICY else {}
    kept = []
    for item in reported[:MAX_POLICY_VIOLATIONS]:
        routine = allowed.get(item) if isinstance(item, str) else None
        if routine is not None and routine not in kept:
            kept.append(routine)
    return tuple(kept)


def _parse_records(data: bytes, n_cases: int) -> tuple[list, Any, Any]:
    """The case records, the peak memory and the policy violations the kernel reports: hostile, checked by the callers."""
    try:
        meta = json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise OutputError(f"outputs are malformed: {type(exc).__name__}") from None
    records = meta.get("records") if isinstance(meta, dict) else None
    if not isinstance(records, list) or len(records) != n_cases:
        raise OutputError(f"expected {n_cases} case records, found {len(records) if isinstance(records, list) else 'none'}")
    if not all(isinstance(r, dict) for r in records):
        raise OutputError("outputs are malformed: a case record is not a record")
    return records, meta.get("peak_rss_bytes"), meta.get("policy_violations")


def read_outputs(function: str, directory: Path, n_cases: int, expected: list | None = None) -> Collected:
    """Read ``directory/<function>.{json,npz}`` written by the kernel.

    Parameters
    ----------
    function : str
        The contract function collected.
    directory : Path
        The outputs folder inside the student's workdir (its parents are the grader's).
    n_cases : int
        Number of hidden cases.
    expected : list, optional
        ``(n_cases,)`` reference outputs, bounding each case's size; without
        them every case gets ``DEFAULT_ELEMENTS``.

    Returns
    -------
    Collected

    Raises
    ------
    OutputError
        If the files are missing, not plain files, too large or malformed (as a whole).
    """
    folder = _open_folder(Path(directory))
    try:
        records_bytes = _read_untrusted(folder, f"{function}.json", MAX_RECORDS_BYTES)
        arrays_bytes = _read_untrusted(folder, f"{function}.npz", MAX_OUTPUT_BYTES)
    finally:
        os.close(folder)
    records, peak, reported = _parse_records(records_bytes, n_cases)
    violations = policy_violations(function, reported)
    arrays = _Arrays(arrays_bytes)
    cases = []
    room = [RECORD_ELEMENTS]
    for i, rec in enumerate(records):
        seconds = _non_negative(rec.get("seconds"))
        if rec.get("ok") is not True:
            calls = _recorded_calls(rec.get("calls"), i, arrays, room)
            cases.append(CaseOutput(None, str(rec.get("error", "failed"))[:2000], seconds, calls))
            continue
        budget = element_budget(expected[i]) if expected is not None else DEFAULT_ELEMENTS
        try:
            value = _rebuild(rec.get("output"), f"c{i}", arrays, budget)
        except (OutputError, KeyError, ValueError, TypeError, OSError, zipfile.BadZipFile) as exc:
            cases.append(CaseOutput(None, f"output could not be read: {exc}", seconds))
            continue
        cases.append(CaseOutput(value, None, seconds, _recorded_calls(rec.get("calls"), i, arrays, room)))
    peak = _non_negative(peak)
    return Collected(function, cases, None if peak is None else int(peak), violations)


def _non_negative(value: Any) -> float | None:
    """A time or size the kernel reports, if it is a finite number ≥ 0 (JSON also carries NaN and infinities)."""
    if isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value) and value >= 0:
        return float(value)
    return None


def _sketch(value: Any) -> dict | None:
    """A kernel-written argument sketch (``kernel_side.__deformlab_sketch__``), checked field by field; None if malformed."""
    if not isinstance(value, dict):
        return None
    if value.keys() == {"opaque"}:
        return {"opaque": True}
    if value.keys() == {"v"}:
        v = value["v"]
        if v is None or (isinstance(v, str) and len(v) <= 100):
            return {"v": v}
        return None
    if value.keys() != {"shape", "norm", "p"}:
        return None
    shape, norm, p = value["shape"], value["norm"], value["p"]
    if not (isinstance(shape, list) and len(shape) <= 8
            and all(isinstance(s, int) and not isinstance(s, bool) and 0 <= s < 2**40 for s in shape)):
        return None
    if _non_negative(norm) is None or not (isinstance(p, list) and len(p) == 2 and all(_finite(x) for x in p)):
        return None
    return {"shape": list(shape), "norm": float(norm), "p": [float(x) for x in p]}


def _finite(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def _recorded_calls(raw: Any, case: int, arrays: _Arrays, room: list[int]) -> list:
    """The calls a case recorded, each read like an output; a malformed call is left out, never trusted.

    ``room`` holds the elements still allowed over the function's cases (``RECORD_ELEMENTS``).
    """
    calls = []
    if not isinstance(raw, list):
        return calls
    for j, entry in enumerate(raw[:MAX_CALLS]):
        if room[0] <= 0:
            break
        if not isinstance(entry, dict) or not isinstance(entry.get("name"), str):
            continue
        key = f"r{case}.{j}"
        try:
            items = None
            args = kwargs = None
            if "args" in entry:
                args = [_sketch(a) for a in entry["args"]] if isinstance(entry["args"], list) else [None]
                kwargs = entry.get("kwargs") if isinstance(entry.get("kwargs"), dict) else {}
                kwargs = {str(k)[:100]: _sketch(v) for k, v in list(kwargs.items())[:MAX_ITEMS]}
                if len(args) > MAX_ITEMS or None in args or None in kwargs.values():
                    continue
            else:
                items = arrays.load(key + ".in", min(room[0], DEFAULT_ELEMENTS))
                room[0] -= items.size
            output = _rebuild(entry.get("output"), key + ".out", arrays, min(room[0], DEFAULT_ELEMENTS))
            room[0] -= element_count(output)
        except (OutputError, KeyError, ValueError, TypeError, OSError, zipfile.BadZipFile):
            continue
        calls.append(RecordedCall(entry["name"][:100], args, kwargs, items, output))
    return calls
