# %% [markdown]
# # 00 · Triangle areas
#
# The area of triangle $(a, b, c)$ is half the norm of $(b - a) \times (c - a)$.

# %%
import numpy as np

# %% deformlab={"solution": "triangle_areas"}
def triangle_areas(V, F):
    """Area of every triangle, (m,), of vertices ``V`` (n, 2) or (n, 3) and triangles ``F`` (m, 3)."""
    ### BEGIN SOLUTION
    total = []
    for a, b, c in F:
        e1, e2 = V[b] - V[a], V[c] - V[a]
        if len(e1) == 2:
            total.append(abs(e1[0] * e2[1] - e1[1] * e2[0]) / 2)
        else:
            total.append(np.linalg.norm(np.cross(e1, e2)) / 2)
    return np.array(total)
    ### END SOLUTION

# %% deformlab={"tests": "triangle_areas", "points": 2}
_unit = triangle_areas(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]), np.array([[0, 1, 2]]))
assert np.allclose(_unit, [0.5]), f"the unit right triangle has area 0.5, got {_unit}"
