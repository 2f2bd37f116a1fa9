"""Runs inside the student's kernel: call student functions on fixtures, save raw outputs.

This file's source is sent to the kernel as one cell, so it imports only the
standard library, numpy and scipy, and defines a single entry point,
``__deformlab_collect__``, with ``__deformlab_policy__`` (its recorder of library
calls the course's policy forbids) and the argument sketch the grader computes
too (``__deformlab_sketch__``). Everything it writes is treated as untrusted by
the grader; it computes no verdicts.

While a function's cases run, the other course functions the manifest names
under ``"record"`` are wrapped, so that every call the student's function makes
to them is written down: a sketch of its arguments and its output (for a
``batched`` function, the whole first argument, matched item by item). The
grader then reruns the reference with the student's own outputs of those
functions (``grader.checks.callees``): a mistake in a callee costs the
callee's points only.
"""

def __deformlab_sketch__(value, seed):
    """A few numbers that tell two arguments apart: shape, Frobenius norm and two random bilinear projections.

    A ``(r, ...)`` array (dense or sparse) is read as an ``r x c`` matrix ``A``;
    its projections are ``f_k ᵀ A g_k`` with standard normal ``f_k``, ``g_k``
    drawn from ``seed``, so the grader recomputes them for the reference's
    arguments. Non-numeric arguments (a precomputation object) are opaque.
    """
    import numpy as _np

    if isinstance(value, str):
        return {"v": value[:100]}
    if value is None:
        return {"v": None}
    try:
        import scipy.sparse as _sp

        sparse = _sp.issparse(value)
    except ImportError:
        sparse = False
    if sparse:
        A = _sp.csr_matrix(value, dtype=float)
        A.sum_duplicates()
        shape = [int(s) for s in A.shape]
        coo = A.tocoo()
        rows, cols = shape
        norm = float(_np.sqrt(_np.sum(coo.data * coo.data)))
    else:
        try:
            arr = _np.asarray(value, dtype=float)
        except Exception:  # noqa: BLE001 - a ragged list, an object: nothing to compare
            return {"opaque": True}
        shape = [int(s) for s in arr.shape]
        rows = shape[0] if arr.ndim else 1
        cols = int(arr.size // rows) if rows else 0
        A = arr.reshape(rows, cols)
        norm = float(_np.linalg.norm(A))
    projections = []
    for k in range(2):
        f = _np.random.default_rng([seed, 2 * k]).standard_normal(rows)
        g = _np.random.default_rng([seed, 2 * k + 1]).standard_normal(cols)
        if sparse:
            projections.append(float(_np.sum(coo.data * f[coo.row] * g[coo.col])))
        else:
            projections.append(float(f @ A @ g))
    return {"shape": shape, "norm": norm, "p": projections}



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
    # a snapshot: the policy finds the student's own functions on the stack, not the recorders below
    policy = __deformlab_policy__(dict(namespace), function)
    plan = manifest.get("record") or {}
    room = [int(plan.get("budget", 0))]  # elements the recordings may still hold
    max_calls = int(plan.get("max_calls", 0))  # per case

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

    def recorder(name, fn, batched):
        def recorded(*args, **kwargs):
            out = fn(*args, **kwargs)
            if len(calls) >= max_calls or room[0] <= 0:
                return out
            try:
                key = f"r{index}.{len(calls)}"
                entry = {"name": name}
                if batched:
                    items = _np.array(args[0] if args else kwargs.get(plan["batched"][name]), dtype=float)
                    room[0] -= items.size
                    saved[key + ".in"] = items
                else:
                    entry["args"] = [__deformlab_sketch__(a, plan["seed"]) for a in args]
                    entry["kwargs"] = {str(k): __deformlab_sketch__(v, plan["seed"]) for k, v in kwargs.items()}
                before = len(saved)
                entry["output"] = encode(out, key + ".out")
                room[0] -= sum(saved[k].size for k in list(saved)[before:])
                calls.append(entry)
            except Exception:  # noqa: BLE001 - what cannot be recorded is judged without it
                pass
            return out

        return recorded

    wrapped = {}
    for name in plan.get("names", ()):
        fn = namespace.get(name)
        if name != function and callable(fn):
            wrapped[name] = fn
            namespace[name] = recorder(name, fn, name in plan.get("batched", {}))

    index = 0
    try:
        for index, case in enumerate(manifest["cases"]):
            start = _time.perf_counter()
            results = []
            calls = []  # the case's recorded calls (the recorders read this name)
            try:
                for step in case["steps"]:
                    # a case's own steps are not calls of the student's function: never recorded
                    fn = wrapped.get(step["function"], namespace.get(step["function"]))
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
            if calls:
                record["calls"] = calls
            records.append(record)
    finally:
        namespace.update(wrapped)  # the student's own functions again, for the next collection

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
