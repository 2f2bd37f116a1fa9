# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3 (ipykernel)
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 00 · Meshes: vertices, edges, faces and the Euler–Poincaré formula
#
# *Workload: about 2.5 hours for 4 graded functions (11 points) and 1 written answer (an estimate for a student who attended the lecture).*
#
# Every shape you will deform in this assignment is a **triangle mesh**: an array
# `V` of shape `(n, d)` holding one vertex position per row ($d = 2$ for planar
# meshes, $d = 3$ for surfaces), and an integer array `F` of shape `(f, 3)` whose
# rows are triangles, each given by three row indices into `V`.
#
# A deformation moves the vertices and never touches `F`. The connectivity, and
# with it the *topology* of the shape, stays what it is: no deformation can tear
# a hole into a disc or close the hole of a ring. This warm-up counts that
# connectivity. The counts are tied together by the **Euler–Poincaré formula**
#
# $$\chi \;=\; V - E + F \;=\; 2(c - g) - b,$$
#
# where, in this formula only, $V$, $E$ and $F$ are the *numbers* of vertices,
# edges and triangles, $c$ is the number of connected components, $g$ the genus
# (the number of handles: holes you could put a finger through) and $b$ the
# number of boundary loops.
#
# **How to work.** Write each function in the cell below its explanation,
# replacing `raise NotImplementedError()`, then run the tests cell under it.
# Those tests are there to help you; your functions are graded on more inputs
# than they show. Later cells use your earlier functions.

# %%
import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from starter import load_mesh, plotting, shapes

rng = np.random.default_rng(0)

# %% [markdown]
# These are the meshes of the course. Before computing anything, guess for each
# one how many boundary loops $b$ and how many handles $g$ it has.

# %%
gallery = ["torus", "disc_with_holes", "bar", "character", "sphere", "ant", "nut"]
plotting.show_meshes([load_mesh(name) for name in gallery], titles=gallery, link_views=False)

# %% [markdown]
# We also test on three meshes small enough to check by hand: a tetrahedron (a
# closed surface), a square made of two triangles (one boundary loop) and a
# square ring made of eight triangles (two boundary loops: the outer and the
# inner square). The two planar ones are drawn below.

# %%
V_tet = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
F_tet = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])

V_square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
F_square = np.array([[0, 1, 2], [0, 2, 3]])

V_ring = np.array(
    [[-2.0, -2.0], [2.0, -2.0], [2.0, 2.0], [-2.0, 2.0], [-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
)
F_ring = np.array([[0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]])

plotting.show_meshes([(V_square, F_square), (V_ring, F_ring)], titles=["square", "ring"], link_views=False)

# %% [markdown]
# ## 1. Edges
#
# The triangle $(i, j, k)$ has the three edges $\{i, j\}$, $\{j, k\}$ and
# $\{k, i\}$. An edge between two triangles therefore shows up twice when you go
# through `F` triangle by triangle (in opposite directions, if the triangles are
# consistently oriented), and an edge on the boundary shows up once.
#
# `edges(F)` returns every **undirected** edge exactly once, as a row `[i, j]`
# with `i < j`, the rows sorted lexicographically (by `i`, then by `j`). Sorting
# makes the answer unique, so that it can be compared.
#
# *Hint:* every triangle contributes three directed edges, and `F[:, [0, 1]]`
# is the first of them for all triangles at once. Look up what
# `np.sort(..., axis=1)` and `np.unique(..., axis=0)` do to the rows of an array:
# which one forgets an edge's direction, which one removes repeated rows? No
# Python loop over triangles is needed.
#
# A check you can do in your head: on a *closed* mesh every edge lies in exactly
# two triangles and every triangle has three edges, so $2E = 3F$.

# %% deformlab={"solution": "edges"}
import numpy as np


def edges(F):
    """Every undirected edge of a triangle mesh, once.

    Parameters
    ----------
    F : (f, 3) array_like of int
        Triangles.

    Returns
    -------
    E : (e, 2) numpy.ndarray of int
        One row ``[i, j]`` per edge with ``i < j``, rows sorted lexicographically.
    """
    ### BEGIN SOLUTION
    F = np.asarray(F, dtype=np.int64).reshape(-1, 3)
    directed = np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])  # the 3f half-edges
    # Sorting each row forgets the direction; np.unique drops the repeats and sorts the rows.
    return np.unique(np.sort(directed, axis=1), axis=0)
    ### END SOLUTION

# %% deformlab={"tests": "edges", "points": 3}
_E = edges(F_square)
_expected = np.array([[0, 1], [0, 2], [0, 3], [1, 2], [2, 3]])
assert isinstance(_E, np.ndarray), f"edges must return a numpy array, got {type(_E).__name__}"
assert np.issubdtype(_E.dtype, np.integer), f"edges are pairs of vertex indices: expected an integer array, got dtype {_E.dtype}"
assert _E.shape == (5, 2), (
    f"the square [[0, 1, 2], [0, 2, 3]] has 5 edges, so edges(F) must have shape (5, 2); got {_E.shape}"
    + (": the shared edge (0, 2) is listed twice, remove duplicates" if _E.shape == (6, 2) else "")
)
assert np.array_equal(_E, _expected), (
    f"edges of the square: expected {_expected.tolist()}, got {_E.tolist()} "
    "(each row sorted ascending, rows sorted lexicographically)"
)

_E = edges(np.array([[2, 1, 0]]))
assert np.array_equal(_E, [[0, 1], [0, 2], [1, 2]]), (
    f"edges of the single triangle [2, 1, 0]: expected [[0, 1], [0, 2], [1, 2]], got {np.asarray(_E).tolist()}: "
    "sort each row so that the direction of an edge does not matter"
)

_F_copy = F_tet.copy()
_E = edges(F_tet)
assert np.array_equal(F_tet, _F_copy), "edges must not modify its input F"
assert len(_E) == 6, f"a tetrahedron has 6 edges, got {len(_E)}"

_V, _F = load_mesh("torus")
_E = edges(_F)
assert np.all(_E[:, 0] < _E[:, 1]), f"row {int(np.argmax(_E[:, 0] >= _E[:, 1]))} of edges(F) is not sorted ascending"
assert np.array_equal(np.lexsort((_E[:, 1], _E[:, 0])), np.arange(len(_E))), "the rows of edges(F) are not sorted lexicographically"
assert 2 * len(_E) == 3 * len(_F), (
    f"the torus is closed: each of its edges lies in exactly two of its {len(_F)} triangles, "
    f"so it has 3F/2 = {3 * len(_F) // 2} edges; got {len(_E)}"
)

# %% [markdown]
# Because of the sorting, the answer depends only on the mesh, not on the order
# in which `F` lists the triangles or the corners of each triangle:

# %%
_, F = load_mesh("torus")
F_shuffled = np.roll(F[rng.permutation(len(F))], 1, axis=1)
print("same edges after shuffling the triangles and turning their corners:", np.array_equal(edges(F), edges(F_shuffled)))

# %% [markdown]
# ## 2. The Euler characteristic
#
# $$\chi = V - E + F.$$
#
# For the tetrahedron, $\chi = 4 - 6 + 4 = 2$; for a single triangle,
# $\chi = 3 - 3 + 1 = 1$.
#
# The point of this number is that it does **not** depend on how a shape is
# triangulated, only on its topology. Refining a mesh never changes it:
#
# - a new vertex inside a triangle, joined to its three corners, adds
#   $1$ vertex, $3$ edges and $2$ triangles: $\Delta\chi = 1 - 3 + 2 = 0$;
# - a new vertex in the middle of an interior edge, joined to the two opposite
#   corners, adds $1$ vertex, $3$ edges and $2$ triangles: again $\Delta\chi = 0$
#   (on a boundary edge: $1$ vertex, $2$ edges, $1$ triangle).
#
# Any two triangulations of the same surface have a common refinement, so they
# have the same $\chi$.
#
# `euler_characteristic(V, F)` returns $\chi$ as a Python `int` (use your `edges`).

# %% deformlab={"solution": "euler_characteristic"}
def euler_characteristic(V, F):
    """The Euler characteristic ``χ = V - E + F`` of a triangle mesh.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions.
    F : (f, 3) array_like of int
        Triangles.

    Returns
    -------
    chi : int
    """
    ### BEGIN SOLUTION
    return int(len(V) - len(edges(F)) + len(F))
    ### END SOLUTION

# %% deformlab={"tests": "euler_characteristic", "points": 2}
_chi = euler_characteristic(V_tet, F_tet)
assert isinstance(_chi, (int, np.integer)), f"euler_characteristic must return an int, got {type(_chi).__name__}"
assert _chi == 2, (
    f"tetrahedron: expected chi = 4 - 6 + 4 = 2, got {_chi}"
    + (": that is V + E - F; the signs are swapped, chi = V - E + F" if _chi == 6 else "")
)
_chi = euler_characteristic(V_square, F_square)
assert _chi == 1, f"square of two triangles: expected chi = 4 - 5 + 2 = 1, got {_chi}"
_chi = euler_characteristic(V_ring, F_ring)
assert _chi == 0, f"square ring: expected chi = 8 - 16 + 8 = 0, got {_chi}"
for _name, _expected in [("sphere", 2), ("torus", 0)]:
    _chi = euler_characteristic(*load_mesh(_name))
    assert _chi == _expected, f"the {_name} mesh: expected chi = {_expected}, got {_chi}"

# %% [markdown]
# Refinement in action: the coarse and the fine bar differ in every count, but not in $\chi$.

# %%
for name in ["bar_coarse", "bar", "bar_fine"]:
    V, F = load_mesh(name)
    print(f"{name:>10}:  V = {len(V):5d}  E = {len(edges(F)):5d}  F = {len(F):5d}  chi = {euler_characteristic(V, F)}")

# %% [markdown]
# ## 3. Boundary loops
#
# A **boundary edge** lies in exactly one triangle. On the meshes of this course
# (edge-manifold: no edge lies in more than two triangles) the boundary edges
# close up into loops: the rim of a disc is one loop, a ring has two, the closed
# tetrahedron none.
#
# `boundary_loop_count(F)` returns the number $b$ of these loops, that is, the
# number of connected components of the graph whose edges are the boundary edges.
#
# *Hints:*
#
# - how many triangles use each edge? `np.unique` can count repeated rows for
#   you (see its `return_counts`);
# - `scipy.sparse.csgraph.connected_components` counts the components of a
#   graph given by its (sparse) adjacency matrix;
# - careful: in such a graph a vertex with no edge is a component of its own,
#   so the interior vertices must not be in it, or they get counted as loops.
#
# Counting boundary *edges* instead of loops is the classic mistake: the square
# has four boundary edges but one boundary loop.

# %% deformlab={"solution": "boundary_loop_count"}
import numpy as np
import scipy.sparse
import scipy.sparse.csgraph


def boundary_loop_count(F):
    """The number of boundary loops of an edge-manifold triangle mesh.

    Parameters
    ----------
    F : (f, 3) array_like of int
        Triangles.

    Returns
    -------
    b : int
        Connected components of the graph of boundary edges (edges of one triangle only).
    """
    ### BEGIN SOLUTION
    F = np.asarray(F, dtype=np.int64).reshape(-1, 3)
    half = np.sort(np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    edge, count = np.unique(half, axis=0, return_counts=True)
    boundary = edge[count == 1]
    if len(boundary) == 0:
        return 0
    # Number the boundary vertices 0..k-1: an interior vertex in the graph would be a "loop" of its own.
    vertices, local = np.unique(boundary, return_inverse=True)
    local = local.reshape(boundary.shape)
    k = len(vertices)
    A = scipy.sparse.coo_matrix((np.ones(len(local)), (local[:, 0], local[:, 1])), shape=(k, k))
    loops, _ = scipy.sparse.csgraph.connected_components(A, directed=False)
    return int(loops)
    ### END SOLUTION

# %% deformlab={"tests": "boundary_loop_count", "points": 3}
_b = boundary_loop_count(F_square)
assert isinstance(_b, (int, np.integer)), f"boundary_loop_count must return an int, got {type(_b).__name__}"
assert _b == 1, (
    f"square of two triangles: expected 1 boundary loop, got {_b}"
    + (": that is the number of boundary edges, count the loops they form" if _b == 4 else "")
)
# The same square with its second triangle listed clockwise: orientations need not agree.
_b = boundary_loop_count(np.array([[0, 1, 2], [0, 3, 2]]))
assert _b == 1, (
    f"square of two triangles, the second listed clockwise: expected 1 boundary loop, got {_b}: the diagonal "
    "is shared, so it is no boundary edge; triangles need not be oriented alike, so compare edges "
    "whichever direction a triangle lists them in"
)
_b = boundary_loop_count(F_tet)
assert _b == 0, f"the tetrahedron is closed: expected 0 boundary loops, got {_b}"
_b = boundary_loop_count(F_ring)
assert _b == 2, f"square ring: expected 2 boundary loops (outer and inner square), got {_b}"
_b = boundary_loop_count(np.array([[0, 1, 2], [3, 4, 5]]))
assert _b == 2, f"two separate triangles: expected 2 boundary loops, got {_b}"
_b = boundary_loop_count(load_mesh("sphere")[1])
assert _b == 0, f"the sphere mesh is closed: expected 0 boundary loops, got {_b}"
_V, _F = shapes.disc_with_holes(n_holes=3, max_area=0.01)
_b = boundary_loop_count(_F)
assert _b == 4, (
    f"a disc with 3 holes: expected 4 boundary loops (the outer rim and 3 holes), got {_b}"
    + (": are the interior vertices counted as components of their own?" if _b > 4 else "")
)

# %% [markdown]
# ## 4. Genus
#
# Why $\chi = 2(c - g) - b$? A sphere has $\chi = 2$ (the tetrahedron). Cutting a
# disc out of a surface removes one face and leaves the vertices and edges of its
# rim: one boundary loop costs $1$. A handle is made by cutting two discs and
# gluing a tube (a ring, $\chi = 0$) between the two rims: it costs $2$. And
# $\chi$ adds up over separate components. So a surface with $c$ components,
# $g$ handles in total and $b$ boundary loops has $\chi = 2c - 2g - b$.
#
# `genus(V, F)` solves that for the total genus:
#
# $$g = \frac{2c - b - \chi}{2}.$$
#
# You have $\chi$ and $b$. For $c$, count the connected components of the graph of
# **all** edges on all `len(V)` vertices (every vertex is used by a triangle, and
# two triangles sharing a vertex are connected). Return an `int`: $2c - b - \chi$
# is even on every orientable surface, so integer division is exact.

# %% deformlab={"solution": "genus"}
import numpy as np
import scipy.sparse
import scipy.sparse.csgraph


def genus(V, F):
    """The total genus ``g`` of an orientable manifold triangle mesh, from ``χ = 2(c - g) - b``.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions (every vertex is used by a triangle).
    F : (f, 3) array_like of int
        Triangles.

    Returns
    -------
    g : int
    """
    ### BEGIN SOLUTION
    n = len(V)
    E = edges(F)
    A = scipy.sparse.coo_matrix((np.ones(len(E)), (E[:, 0], E[:, 1])), shape=(n, n))
    c, _ = scipy.sparse.csgraph.connected_components(A, directed=False)  # connected components
    return int((2 * c - boundary_loop_count(F) - euler_characteristic(V, F)) // 2)
    ### END SOLUTION

# %% deformlab={"tests": "genus", "points": 3}
_g = genus(V_tet, F_tet)
assert isinstance(_g, (int, np.integer)), (
    f"genus must return an int, got {type(_g).__name__} {_g}: use integer division // or int()"
)
assert _g == 0, f"tetrahedron (a sphere): expected genus 0, got {_g}"
_g = genus(V_ring, F_ring)
assert _g == 0, f"square ring (chi = 0, b = 2, c = 1): expected genus 0, got {_g}"
_V, _F = load_mesh("torus")
_g = genus(_V, _F)
assert _g == 1, f"torus (chi = 0, b = 0, c = 1): expected genus 1, got {_g}"

_V2 = np.vstack([V_tet, V_tet + 3.0])
_F2 = np.vstack([F_tet, F_tet + len(V_tet)])
_g = genus(_V2, _F2)
assert _g == 0, (
    f"two separate tetrahedra (chi = 4, b = 0, c = 2): expected genus 0, got {_g}"
    + (": did you assume one connected component?" if _g == -1 else "")
)
_V2 = np.vstack([_V, V_tet + 10.0])
_F2 = np.vstack([_F, F_tet + len(_V)])
_g = genus(_V2, _F2)
assert _g == 1, f"a torus and a separate tetrahedron (chi = 2, b = 0, c = 2): expected genus 1, got {_g}"
_g = genus(*load_mesh("ant"))
assert _g == 0, (
    f"the ant mesh: expected genus 0, got {_g}"
    + (": a negative genus means c is too small; count the connected components c of the whole mesh" if _g < 0 else "")
)

# %% [markdown]
# ## 5. The course meshes, counted
#
# **Question, before you count.** The nut is one closed surface with $\chi = 0$,
# and the ant is closed too, with $\chi = 30$. What do these numbers tell you
# about the nut, and what can they not tell you? How can a closed mesh have
# $\chi = 30$, so far from the $2$ of a sphere, and what do you expect $c$ and $g$
# of the ant to be? Answer in a few sentences in the cell below; the table after
# it then counts everything for the gallery.

# %% [markdown] deformlab={"answer": "nut", "points": 2}
# The nut is one closed surface ($c = 1$, $b = 0$) with $\chi = 0$, so
# $g = (2c - b - \chi)/2 = 1$: topologically it is a torus, a doughnut. The hole
# for the bolt is its one handle; the outer shape, the sharp edges and the size are
# invisible to $\chi$, which is unchanged by any deformation or remeshing that does
# not tear or glue. So $\chi$ cannot tell the nut from a washer, a ring or a
# coffee mug; it only says that no deformation of this mesh can close the hole
# or make a second one. The ant is not one surface but <span class="measured">15</span> separate closed
# pieces (body parts and limbs, each modelled on its own), each a topological sphere with
# $\chi = 2$: $\chi = 2(c - g) - b = 2 \cdot 15 = 30$. $\chi$ adds up over
# components, which is why $c$ belongs in the formula (the table below
# counts $g$ = <span class="measured">0</span> for the ant and $g$ = <span class="measured">1</span> for the nut).

# %% [markdown]
# Your functions, on the gallery from the top. Compare with your guesses and
# your answer.

# %%
print(f"{'mesh':>16} {'V':>6} {'E':>6} {'F':>6} {'chi':>4} {'b':>3} {'c':>3} {'g':>3}")
for name in gallery:
    V, F = load_mesh(name)
    E = edges(F)
    graph = sp.coo_matrix((np.ones(len(E)), (E[:, 0], E[:, 1])), shape=(len(V), len(V)))
    components = connected_components(graph, directed=False)[0]
    print(
        f"{name:>16} {len(V):6d} {len(E):6d} {len(F):6d} {euler_characteristic(V, F):4d} "
        f"{boundary_loop_count(F):3d} {components:3d} {genus(V, F):3d}"
    )
