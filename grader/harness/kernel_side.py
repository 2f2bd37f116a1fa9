"""Runs inside the student's kernel: call student functions on fixtures, save raw outputs.

This file's source is sent to the kernel as one cell, so it imports only the
standard library, numpy and scipy, and defines a single entry point,
``__deformlab_collect__`` (with ``__deformlab_policy__``, its recorder of library calls the
course's policy forbids). Everything it writes is treated as untrusted by the
grader; it computes no verdicts.
"""


def __deformlab_collect__(function, fixture_dir, out_dir):
    import json as _json
    import os as _os
    import time as _time
    import traceback as _tb

    import numpy as _np

    with open(_os.path.join(fixture_dir, function + ".json")) as fh:
        manifest = _json.load(fh)
    arrays = dict(_np.load(_os.path.join(fixture_dir, function + ".npz"), allow_pickle=False))
    namespace = globals()
    saved, records = {}, []
    policy = __deformlab_policy__(namespace, function)

    def decode(value, results):
        if "a" in value:
            return arrays[value["a"]].copy()  # a copy: student code must not alter the fixtures
        if "ref" in value:
            return results[value["ref"]]
        if "list" in value:
            return [decode(v, results) for v in value["list"]]
        if "tuple" in value:
            return tuple(decode(v, results) for v in value["tuple"])
        return value["v"]

    def encode(value, key):
        try:
            import scipy.sparse as _sp

            if _sp.issparse(value):
                coo = _sp.coo_matrix(value)
                saved[key + ".data"] = _np.asarray(coo.data, dtype=float)
                saved[key + ".row"] = _np.asarray(coo.row, dtype=_np.int64)
                saved[key + ".col"] = _np.asarray(coo.col, dtype=_np.int64)
                return {"kind": "sparse", "shape": [int(s) for s in coo.shape]}
        except ImportError:
            pass
        if isinstance(value, (tuple, list)) and not all(isinstance(v, (int, float)) for v in value):
            return {"kind": "seq", "items": [encode(v, f"{key}.{i}") for i, v in enumerate(value)]}
        try:
            arr = _np.array(value)
        except Exception as exc:  # noqa: BLE001 - any failure is the student's output's fault
            return {"kind": "invalid", "type": type(value).__name__, "error": repr(exc)[:300]}
        if arr.dtype == object:
            return {"kind": "invalid", "type": type(value).__name__, "error": "not a numeric array"}
        saved[key] = _np.array(arr, order="C")  # not ascontiguousarray: it makes 0-d arrays 1-d
        return {"kind": "array"}

    for index, case in enumerate(manifest["cases"]):
        start = _time.perf_counter()
        results = []
        try:
            for step in case["steps"]:
                fn = namespace.get(step["function"])
                if fn is None or not callable(fn):
                    raise NameError(f"{step['function']} is not defined in the notebook")
                args = [decode(a, results) for a in step["args"]]
                kwargs = {k: decode(v, results) for k, v in step["kwargs"].items()}
                results.append(fn(*args, **kwargs))
            record = {"ok": True, "output": encode(results[-1], f"c{index}")}
        except BaseException as exc:  # SystemExit and KeyboardInterrupt too: the case fails, collection goes on
            frames = [f for f in _tb.extract_tb(exc.__traceback__) if f.filename.startswith("<") or "ipykernel" in f.filename]
            where = f" (line {frames[-1].lineno})" if frames else ""
            record = {"ok": False, "error": f"{type(exc).__name__}: {str(exc)[:1500]}{where}"}
        record["seconds"] = _time.perf_counter() - start
        records.append(record)

    tmp = _os.path.join(out_dir, function + ".tmp.npz")
    _np.savez(tmp, **saved)
    _os.replace(tmp, _os.path.join(out_dir, function + ".npz"))
    try:
        import resource as _resource

        peak = _resource.getrusage(_resource.RUSAGE_SELF).ru_maxrss * 1024
    except Exception:  # noqa: BLE001
        peak = None
    with open(_os.path.join(out_dir, function + ".json"), "w") as fh:
        _json.dump({"function": function, "records": records, "peak_rss_bytes": peak,
                    "policy_violations": policy()}, fh)


def __deformlab_policy__(namespace, function):
    """Start recording the library-call policy's violations for ``function``; returns what reads them.

    The recorder is ``starter.library_policy``, installed before the notebook's first cell
    (the kernel template and an IPython extension). What it reports is the kernel's word,
    read by the grader as untrusted data.
    """
    import sys as _sys

    recorder = _sys.modules.get("starter.library_policy")
    try:
        recorder.reset(namespace, function)
    except Exception:  # noqa: BLE001 - no recorder: nothing is charged
        return lambda: None

    def violations():
        try:
            return [str(r)[:200] for r in recorder.violations(function)[:64]]
        except Exception:  # noqa: BLE001
            return None

    return violations
