"""Hidden cases of triangle_areas: random 2D and 3D triangles, clockwise ones too."""

import numpy as np

from grader.checks.base import Case, FunctionChecks, as_array, close, verdict


class TriangleAreasChecks(FunctionChecks):
    function = "triangle_areas"
    description = "areas of random 2D and 3D triangles, in both orientations"

    def cases(self, rng):
        cases = []
        for d in (2, 3):
            V = rng.normal(size=(12, d))
            F = np.array([rng.permutation(12)[:3] for _ in range(8)])
            cases.append(Case.call(f"{d}D triangles", "triangle_areas", V, F))
            cases.append(Case.call(f"{d}D clockwise", "triangle_areas", V, F[:, ::-1].copy()))
        return cases

    def verify(self, case, got, expected):
        F = case.args()[1]
        A = as_array(got, (len(F),), "areas")
        ok, where = close(A, np.asarray(expected), 1e-9, float(np.abs(expected).max()))
        return [verdict("areas", ok, f"triangle {where}")]
