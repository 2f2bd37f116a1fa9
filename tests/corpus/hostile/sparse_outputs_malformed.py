NOTEBOOK = "07_tetrahedra"
DESCRIPTION = (
    "sparse outputs the grader compares without densifying: tet_cotangent_laplacian stores a NaN among its "
    "entries, tet_biharmonic_matrix is one row and column too large, and tet_mass_matrix is a COO matrix with "
    "every tetrahedron's quarter stored as its own duplicate entry, explicit zeros off the diagonal and rows out "
    "of order (a correct matrix: it keeps its marks); the ARAP precomputation and global step build on the "
    "NaN Laplacian and lose too, as a buggy Laplacian's do"
)
SOLUTIONS = {
    "tet_cotangent_laplacian": '''import scipy.sparse as sp


def tet_cotangent_laplacian(V, T):
    V, T = np.asarray(V, dtype=float), np.asarray(T)
    D = np.stack([V[T[:, k]] - V[T[:, 0]] for k in (1, 2, 3)], axis=2)
    B = np.linalg.inv(D)
    G = np.concatenate([-B.sum(axis=1, keepdims=True), B], axis=1)  # (f, 4, 3) hat gradients
    volume = np.abs(np.linalg.det(D)) / 6
    K = volume[:, None, None] * np.einsum("tia,tja->tij", G, G)
    rows, cols = np.repeat(T, 4, axis=1), np.tile(T, (1, 4))
    L = -sp.csr_matrix((K.ravel(), (rows.ravel(), cols.ravel())), shape=(len(V), len(V)))
    L.data[len(L.data) // 2] = np.nan
    return L
''',
    "tet_mass_matrix": '''import scipy.sparse as sp


def tet_mass_matrix(V, T):
    V, T = np.asarray(V, dtype=float), np.asarray(T)
    D = np.stack([V[T[:, k]] - V[T[:, 0]] for k in (1, 2, 3)], axis=2)
    quarter = np.abs(np.linalg.det(D)) / 24
    n = len(V)
    off = np.arange(n - 1, 0, -1)  # explicit zeros below the diagonal, last row first
    rows = np.concatenate([T.ravel()[::-1], off])
    cols = np.concatenate([T.ravel()[::-1], off - 1])
    values = np.concatenate([np.repeat(quarter, 4)[::-1], np.zeros(n - 1)])
    return sp.coo_matrix((values, (rows, cols)), shape=(n, n))
''',
    "tet_biharmonic_matrix": '''import scipy.sparse as sp


def tet_biharmonic_matrix(V, T):
    n = len(V)
    return sp.identity(n + 1, format="csr")
''',
}
LOSES = {"tet_cotangent_laplacian", "tet_biharmonic_matrix", "tet_arap_precompute", "tet_arap_global_step"}


def CHECK(result, autograded, params):
    """Each malformed matrix is refused with a message naming what is wrong with it."""
    failed = {t["function"]: [f for c in t["cases"] for f in c["failed"] + [c["error"] or ""]] for t in result["tests"]}
    problems = []
    if not any("NaN or inf" in f for f in failed.get("tet_cotangent_laplacian", [])):
        problems.append(f"tet_cotangent_laplacian's NaN is not named: {failed.get('tet_cotangent_laplacian')}")
    if not any("should have shape" in f for f in failed.get("tet_biharmonic_matrix", [])):
        problems.append(f"tet_biharmonic_matrix's shape is not named: {failed.get('tet_biharmonic_matrix')}")
    return problems
