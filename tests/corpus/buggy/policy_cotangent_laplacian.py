NOTEBOOK = "03_arap"
DESCRIPTION = "cotangent_laplacian = igl.cotmatrix, the routine itself under the contract name (arap_precompute calls it: only cotangent_laplacian loses)"
SOLUTIONS = {
    "cotangent_laplacian": '''import igl

cotangent_laplacian = igl.cotmatrix
''',
}
LOSES = {"cotangent_laplacian"}


def CHECK(result, autograded, params):
    """The function scores 0 with a message naming the routine."""
    test = next(t for t in result["tests"] if t["function"] == "cotangent_laplacian")
    problems = [] if "igl.cotmatrix" in test["summary"] and test["score"] == 0 else [f"cotangent_laplacian: {test['score']} points, {test['summary']!r}"]
    return problems + ([] if test.get("policy_violations") == ["igl.cotmatrix"] else [f"policy_violations {test.get('policy_violations')!r}"])
