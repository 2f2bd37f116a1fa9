NOTEBOOK = "03_arap"
DESCRIPTION = 'Student 04: exchange student, French comments and names (sommets, triangles, poids, aretes, coins), vectorized per corner with np.add.at and einsum, dict with French keys.'
SOLUTIONS = {
    "optimal_rotation": r'''import numpy as np


def optimal_rotation(S):
    """The rotation maximizing ``tr(R S)``, for one matrix or a stack of them.

    Parameters
    ----------
    S : (d, d) or (k, d, d) array_like of float
        Covariance matrix or matrices, ``S = Ũ Σ Ṽᵀ``.

    Returns
    -------
    R : numpy.ndarray, the shape of ``S``
        ``R = Ṽ diag(1, …, 1, det(Ṽ Ũᵀ)) Ũᵀ``: orthogonal with ``det R = +1``.
    """
    S = np.asarray(S, dtype=float)
    U_g, sigma, Vt_d = np.linalg.svd(S)
    # det(V U^T) = det(V) det(U) : +1 pour une rotation, -1 pour une reflexion
    signe = np.sign(np.linalg.det(Vt_d) * np.linalg.det(U_g))
    # on retourne la derniere colonne de U (direction de la plus petite valeur singuliere)
    U_g = U_g.copy()
    U_g[..., :, -1] *= signe[..., None]
    return np.swapaxes(Vt_d, -1, -2) @ np.swapaxes(U_g, -1, -2)
''',
    "cotangent_weights": r'''import numpy as np


def cotangent_weights(V, F):
    """Half the cotangent of every triangle corner.

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions, ``d`` in {2, 3}.
    F : (f, 3) array_like of int
        Triangles, none of zero area.

    Returns
    -------
    C : (f, 3) numpy.ndarray
        ``C[t, k] = ½ cot`` of the angle at corner ``k`` of triangle ``t``: the weight of
        the opposite edge ``(F[t, (k+1)%3], F[t, (k+2)%3])``.
    """
    sommets = np.asarray(V, dtype=float)
    triangles = np.asarray(F, dtype=int)
    # en 2D on ajoute une coordonnee nulle pour pouvoir utiliser le produit vectoriel
    if sommets.shape[1] == 2:
        sommets = np.hstack([sommets, np.zeros((len(sommets), 1))])
    poids = np.empty((len(triangles), 3))
    for coin in range(3):
        depart = sommets[triangles[:, coin]]
        vers_suivant = sommets[triangles[:, (coin + 1) % 3]] - depart
        vers_autre = sommets[triangles[:, (coin + 2) % 3]] - depart
        produit_scalaire = (vers_suivant * vers_autre).sum(axis=1)
        norme_vectorielle = np.linalg.norm(np.cross(vers_suivant, vers_autre), axis=1)
        # demi-cotangente de l'angle au coin
        poids[:, coin] = 0.5 * produit_scalaire / norme_vectorielle
    return poids
''',
    "cotangent_laplacian": r'''import numpy as np
import scipy.sparse as sp


def cotangent_laplacian(V, F):
    """The cotangent Laplacian (libigl's sign: negative semi-definite).

    Parameters
    ----------
    V : (n, d) array_like of float
        Vertex positions.
    F : (f, 3) array_like of int
        Triangles.

    Returns
    -------
    L : (n, n) scipy.sparse matrix
        Symmetric; ``L[i, j]`` is the sum of the cotangent weights of edge ``(i, j)``,
        ``L[i, i] = -Σ_{j≠i} L[i, j]``.
    """
    triangles = np.asarray(F, dtype=int)
    nb_sommets = len(V)
    poids = cotangent_weights(V, triangles)
    # l'arete opposee au coin k relie les coins k+1 et k+2
    debut = triangles[:, [1, 2, 0]].ravel()
    fin = triangles[:, [2, 0, 1]].ravel()
    A = sp.csr_matrix((poids.ravel(), (debut, fin)), shape=(nb_sommets, nb_sommets))
    # symetrisation (les doublons sont additionnes)
    A = A + A.T
    diagonale = np.asarray(A.sum(axis=1)).ravel()
    return (A - sp.diags(diagonale)).tocsr()
''',
    "arap_covariances": r'''import numpy as np


def arap_covariances(V, U, F, C):
    """The covariance matrix of every vertex's cell (the triangles around it).

    Parameters
    ----------
    V, U : (n, d) array_like of float
        Rest and deformed positions.
    F : (f, 3) array_like of int
        Triangles.
    C : (f, 3) array_like of float
        Cotangent weights, ``C[t, k]`` for the edge opposite corner ``k``.

    Returns
    -------
    S : (n, d, d) numpy.ndarray
        ``S_i = Σ_{t ∋ i} Σ_k C[t, k] e_tk e'_tkᵀ``, ``e_tk`` the rest edge opposite corner
        ``k`` and ``e'_tk`` the same edge in ``U``.
    """
    sommets = np.asarray(V, dtype=float)
    deformes = np.asarray(U, dtype=float)
    triangles = np.asarray(F, dtype=int)
    poids = np.asarray(C, dtype=float)
    nb_sommets, dim = sommets.shape
    # aretes opposees a chaque coin, meme orientation au repos et deformees : (f, 3, d)
    aretes_repos = sommets[triangles[:, [2, 0, 1]]] - sommets[triangles[:, [1, 2, 0]]]
    aretes_def = deformes[triangles[:, [2, 0, 1]]] - deformes[triangles[:, [1, 2, 0]]]
    # matrice de chaque triangle : somme_k c_k e_k e'_k^T
    par_triangle = np.einsum("tk,tki,tkj->tij", poids, aretes_repos, aretes_def)
    # chaque triangle donne la meme matrice a ses trois coins
    S = np.zeros((nb_sommets, dim, dim))
    for coin in range(3):
        np.add.at(S, triangles[:, coin], par_triangle)
    return S
''',
    "arap_rotations": r'''def arap_rotations(V, U, F, C):
    """The local step: the best rotation of every vertex's cell.

    Parameters
    ----------
    V, U : (n, d) array_like of float
        Rest and deformed positions.
    F : (f, 3) array_like of int
        Triangles.
    C : (f, 3) array_like of float
        Cotangent weights.

    Returns
    -------
    R : (n, d, d) numpy.ndarray
        ``R_i = optimal_rotation(S_i)`` with ``S = arap_covariances(V, U, F, C)``.
    """
    # etape locale : une rotation par cellule
    return optimal_rotation(arap_covariances(V, U, F, C))
''',
    "arap_energy": r'''import numpy as np


def arap_energy(V, U, F, C, R):
    """The ARAP energy of positions ``U`` measured against one rotation per vertex.

    Parameters
    ----------
    V, U : (n, d) array_like of float
        Rest and deformed positions.
    F : (f, 3) array_like of int
        Triangles.
    C : (f, 3) array_like of float
        Cotangent weights.
    R : (n, d, d) array_like of float
        The rotation of every vertex's cell.

    Returns
    -------
    E : float
        ``Σ_i Σ_{t ∋ i} Σ_k C[t, k] ‖e'_tk - R_i e_tk‖²``.
    """
    sommets = np.asarray(V, dtype=float)
    deformes = np.asarray(U, dtype=float)
    triangles = np.asarray(F, dtype=int)
    poids = np.asarray(C, dtype=float)
    rotations = np.asarray(R, dtype=float)
    aretes_repos = sommets[triangles[:, [2, 0, 1]]] - sommets[triangles[:, [1, 2, 0]]]
    aretes_def = deformes[triangles[:, [2, 0, 1]]] - deformes[triangles[:, [1, 2, 0]]]
    # rotations des trois coins : (f, 3, d, d)
    rot_coins = rotations[triangles]
    # tableau (triangle, coin dont la rotation, arete)
    tournees = np.einsum("tcij,tkj->tcki", rot_coins, aretes_repos)
    ecarts = aretes_def[:, None, :, :] - tournees
    carres = np.sum(ecarts ** 2, axis=-1)
    return float(np.einsum("tk,tck->", poids, carres))
''',
}
LOSES = set()
