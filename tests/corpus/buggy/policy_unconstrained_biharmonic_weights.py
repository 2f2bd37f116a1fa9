NOTEBOOK = "04_bbw"
DESCRIPTION = "unconstrained_biharmonic_weights() is igl.harmonic(..., 2) (bbw calls it: only unconstrained_biharmonic_weights loses)"
SOLUTIONS = {
    "unconstrained_biharmonic_weights": '''import igl
import numpy as np


def unconstrained_biharmonic_weights(V, F, b, bc):
    V, F = np.asarray(V, dtype=float), np.asarray(F, dtype=np.int64)
    return igl.harmonic(V, F, np.asarray(b, dtype=np.int64), np.asarray(bc, dtype=float), 2)
''',
}
LOSES = {"unconstrained_biharmonic_weights"}


def CHECK(result, autograded, params):
    """The function scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "unconstrained_biharmonic_weights")
    problems = [] if "igl.harmonic" in test["summary"] and test["score"] == 0 else [f"unconstrained_biharmonic_weights: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["igl.harmonic"] else [f"policy_violations {test.get('policy_violations')!r}"])
