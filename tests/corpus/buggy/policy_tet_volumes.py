NOTEBOOK = "07_tetrahedra"
DESCRIPTION = "tet_volumes() is the bindings' extension module's volume (igl.pyigl_core.volume)"
SOLUTIONS = {
    "tet_volumes": '''import igl.pyigl_core
import numpy as np


def tet_volumes(V, T):
    return igl.pyigl_core.volume(np.asarray(V, dtype=float), np.asarray(T, dtype=np.int64)).ravel()
''',
}
LOSES = {"tet_volumes"}


def CHECK(result, autograded, params):
    """The function scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "tet_volumes")
    problems = [] if "igl.volume" in test["summary"] and test["score"] == 0 else [f"tet_volumes: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["igl.volume"] else [f"policy_violations {test.get('policy_violations')!r}"])
