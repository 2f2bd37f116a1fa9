import json
import math

NOTEBOOK = "01_shape_matching"
DESCRIPTION = (
    "centroid's cell overwrites fixtures/kernel_side.py, the collector the grader's collection cells run, with one "
    "that reports every case passed with zeros, in NaN, infinite and negative seconds, and an absurd peak memory: "
    "every function is graded on those outputs, and no forged number reaches the unit's record"
)
SOLUTIONS = {
    "centroid": '''import os

import numpy as np

_FORGED = """
def __deformlab_collect__(function, fixture_dir, out_dir):
    import json, os
    import numpy as np
    with open(os.path.join(fixture_dir, function + ".json")) as fh:
        n = len(json.load(fh)["cases"])
    np.savez(os.path.join(out_dir, function + ".npz"), **{f"c{i}": np.zeros(3) for i in range(n)})
    forged = [float("nan"), float("inf"), -1e300, 1e300]
    records = [{"ok": True, "output": {"kind": "array"}, "seconds": forged[i % 4]} for i in range(n)]
    with open(os.path.join(out_dir, function + ".json"), "w") as fh:
        json.dump({"function": function, "records": records, "peak_rss_bytes": float("inf")}, fh)
"""
with open(os.path.join("fixtures", "kernel_side.py"), "w") as fh:
    fh.write(_FORGED)


def centroid(P, w=None):
    P = np.asarray(P, dtype=float)
    w = np.ones(len(P)) if w is None else np.asarray(w, dtype=float)
    return (w / w.sum()) @ P
''',
}
LOSES = {"centroid", "covariance_matrix", "optimal_orthogonal", "orthogonal_align"}


def CHECK(result, autograded, params):
    problems = []
    for test in result["tests"]:
        for case in test["cases"]:
            seconds = case.get("seconds")
            if seconds is not None and not (isinstance(seconds, float) and math.isfinite(seconds) and seconds >= 0):
                problems.append(f"{test['function']} {case['label']!r}: the forged time {seconds!r} was recorded")
    try:
        json.dumps({k: v for k, v in result.items() if k != "autograded_notebook"}, allow_nan=False)
    except ValueError as exc:
        problems.append(f"the unit's record is not strict JSON: {exc}")
    return problems
