NOTEBOOK = "00_meshes"
DESCRIPTION = "edges() is igl.edges, sorted"
SOLUTIONS = {
    "edges": '''import igl
import numpy as np


def edges(F):
    E = np.sort(igl.edges(np.asarray(F, dtype=np.int64)), axis=1)
    return E[np.lexsort((E[:, 1], E[:, 0]))]
''',
}
LOSES = {"edges"}


def CHECK(result, autograded, params):
    """The function scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "edges")
    problems = [] if "igl.edges" in test["summary"] and test["score"] == 0 else [f"edges: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["igl.edges"] else [f"policy_violations {test.get('policy_violations')!r}"])
