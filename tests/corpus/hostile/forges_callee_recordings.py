NOTEBOOK = "03_arap"
DESCRIPTION = (
    "cotangent_weights' cell overwrites fixtures/kernel_side.py with a collector that answers every case with zeros "
    "and, for each case, 5,000 forged recordings of calls to other course functions: malformed entries, sketches of "
    "absurd shapes and non-finite norms, thousands of keyword arguments, an .npy header declaring 9e9 elements, "
    "outputs nested past the cap; the grader reads what it may within its caps, no rerun makes zeros pass, and "
    "every function loses"
)
SOLUTIONS = {
    "cotangent_weights": '''import os

import numpy as np

_FORGED = """
def __deformlab_collect__(function, fixture_dir, out_dir):
    import io, json, os, zipfile
    import numpy as np
    with open(os.path.join(fixture_dir, function + ".json")) as fh:
        n = len(json.load(fh)["cases"])
    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(header, {"descr": "<f8", "fortran_order": False, "shape": (10**9, 3, 3)})
    huge = np.lib.format.magic(1, 0) + header.getvalue() + bytes(72)
    nested = {"kind": "array"}
    for _ in range(200):
        nested = {"kind": "seq", "items": [nested]}
    junk = [
        {"name": "optimal_rotation", "output": {"kind": "array"}},
        {"name": "arap_covariances", "args": [{"shape": [2**39] * 8, "norm": 1.0, "p": [0.0, 0.0]}], "output": nested},
        {"name": "arap_rotations", "args": [{"shape": [3], "norm": float("nan"), "p": [0.0, 0.0]}]},
        {"name": "arap_energy", "args": [], "kwargs": {str(k): {"opaque": True} for k in range(5000)}},
        {"name": "x" * 10**5, "args": [{"v": "y" * 10**5}]},
        "not a record",
    ]
    with zipfile.ZipFile(os.path.join(out_dir, function + ".npz"), "w", zipfile.ZIP_STORED) as z:
        for i in range(n):
            buffer = io.BytesIO()
            np.save(buffer, np.zeros(3))
            z.writestr(f"c{i}.npy", buffer.getvalue())
            z.writestr(f"r{i}.0.in.npy", huge)
    records = [{"ok": True, "output": {"kind": "array"}, "seconds": 0.0, "calls": (junk * 834)[:5000]} for i in range(n)]
    with open(os.path.join(out_dir, function + ".json"), "w") as fh:
        json.dump({"function": function, "records": records, "peak_rss_bytes": 0}, fh)
"""
with open(os.path.join("fixtures", "kernel_side.py"), "w") as fh:
    fh.write(_FORGED)


def cotangent_weights(V, F):
    V, F = np.asarray(V, dtype=float), np.asarray(F)
    C = np.empty(F.shape)
    for k in range(3):
        a, b, c = V[F[:, k]], V[F[:, (k + 1) % 3]], V[F[:, (k + 2) % 3]]
        u, v = b - a, c - a
        dot = np.sum(u * v, axis=1)
        if V.shape[1] == 2:
            cross = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
        else:
            cross = np.linalg.norm(np.cross(u, v), axis=1)
        C[:, k] = 0.5 * dot / cross
    return C
''',
}
# the forged collector answers every function's collection after cotangent_weights' cell has run
LOSES = {"cotangent_weights", "cotangent_laplacian", "arap_covariances", "arap_rotations", "arap_energy"}


def CHECK(result, autograded, params):
    """The unit is graded, no case passed on forged recordings, and every summary is the grader's own text."""
    problems = [] if result["status"] in ("graded", "graded-with-incidents") else [f"status {result['status']!r}"]
    for test in result["tests"]:
        if "judged with your own" in test["summary"]:
            problems.append(f"{test['function']} passed a case on forged recordings: {test['summary']!r}")
        if "x" * 200 in test["summary"] or "y" * 200 in test["summary"]:
            problems.append(f"{test['function']}: a forged name reached the summary")
    return problems
