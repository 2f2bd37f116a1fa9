NOTEBOOK = "00_meshes"
DESCRIPTION = "boundary_loop_count() counts igl.boundary_loop_all's loops (after igl.bfs_orient, allowed)"
SOLUTIONS = {
    "boundary_loop_count": '''import igl
import numpy as np


def boundary_loop_count(F):
    oriented, _ = igl.bfs_orient(np.asarray(F, dtype=np.int64))  # boundary_loop_all wants consistent orientation
    return len(igl.boundary_loop_all(oriented))
''',
}
LOSES = {"boundary_loop_count"}


def CHECK(result, autograded, params):
    """The function scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "boundary_loop_count")
    problems = [] if "igl.boundary_loop_all" in test["summary"] and test["score"] == 0 else [f"boundary_loop_count: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["igl.boundary_loop_all"] else [f"policy_violations {test.get('policy_violations')!r}"])
