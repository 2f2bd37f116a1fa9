import runpy
from pathlib import Path

# the same student's 03 submission: its functions are copied into 03b, as the notebook asks
_STAGE_03 = runpy.run_path(str(Path(__file__).parents[1] / "03_arap" / Path(__file__).name))

NOTEBOOK = "03b_arap_global"
DESCRIPTION = _STAGE_03["DESCRIPTION"]
SOLUTIONS = {
    **_STAGE_03["SOLUTIONS"],
    "arap_precompute": r'''import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def arap_precompute(V, F, handles):
    """What the ARAP iterations reuse: the rest mesh, the weights and the factorized system.

    Parameters
    ----------
    V : (n, d) array_like of float
        Rest positions.
    F : (f, 3) array_like of int
        Triangles.
    handles : (h,) array_like of int
        Distinct vertex indices whose positions are prescribed; at least one.

    Returns
    -------
    data : object of your design
        Everything ``arap_global_step`` and ``arap_solve`` need.

    Raises
    ------
    ValueError
        If ``handles`` is empty, repeats a vertex or is out of range.
    """
    sommets = np.asarray(V, dtype=float)
    triangles = np.asarray(F, dtype=int)
    fixes = np.asarray(handles, dtype=int).ravel()
    nb_sommets = len(sommets)
    # verifications des poignees
    if fixes.size == 0:
        raise ValueError("il faut au moins une poignee")
    if len(np.unique(fixes)) != len(fixes):
        raise ValueError("poignee repetee")
    if np.any(fixes < 0) or np.any(fixes >= nb_sommets):
        raise ValueError("indice de poignee hors limites")
    libres = np.setdiff1d(np.arange(nb_sommets), fixes)
    poids = cotangent_weights(sommets, triangles)
    laplacien = sp.csr_matrix(cotangent_laplacian(sommets, triangles))
    # matrice du systeme, factorisee une seule fois
    systeme = -laplacien[libres][:, libres]
    return {
        "sommets": sommets,
        "triangles": triangles,
        "poids": poids,
        "laplacien": laplacien,
        "fixes": fixes,
        "libres": libres,
        "couplage": laplacien[libres][:, fixes],
        "resoudre": spla.factorized(systeme.tocsc()),
    }
''',
    "arap_global_step": r'''import numpy as np


def arap_global_step(data, R, handle_positions):
    """The global step: the positions minimizing the ARAP energy for fixed rotations.

    Parameters
    ----------
    data : object
        From ``arap_precompute``.
    R : (n, d, d) array_like of float
        The rotation of every vertex's cell.
    handle_positions : (h, d) array_like of float
        Where the handles go.

    Returns
    -------
    U : (n, d) numpy.ndarray
        ``U[handles] = handle_positions``; the free rows solve ``(-L)_ff U_f = B_f - (-L)_fh U_h``.
    """
    sommets = data["sommets"]
    triangles = data["triangles"]
    poids = data["poids"]
    rotations = np.asarray(R, dtype=float)
    positions = np.asarray(handle_positions, dtype=float)
    # rotation moyenne de chaque triangle
    moyenne = rotations[triangles].mean(axis=1)
    second_membre = np.zeros_like(sommets)
    for coin in range(3):
        a = triangles[:, (coin + 1) % 3]
        b = triangles[:, (coin + 2) % 3]
        terme = poids[:, coin, None] * np.einsum("tij,tj->ti", moyenne, sommets[a] - sommets[b])
        np.add.at(second_membre, a, terme)
        np.add.at(second_membre, b, -terme)
    libres = data["libres"]
    droite = second_membre[libres] + data["couplage"] @ positions
    resultat = np.empty_like(sommets)
    resultat[data["fixes"]] = positions
    for axe in range(sommets.shape[1]):
        resultat[libres, axe] = data["resoudre"](droite[:, axe])
    return resultat
''',
    "arap_solve": r'''import numpy as np


def arap_solve(data, handle_positions, U0=None, iterations=10):
    """ARAP deformation: alternate the local and the global step.

    Parameters
    ----------
    data : object
        From ``arap_precompute``.
    handle_positions : (h, d) array_like of float
        Where the handles go.
    U0 : (n, d) array_like of float, optional
        The start; the rest positions by default. Its handle rows are replaced by
        ``handle_positions`` first.
    iterations : int
        Local–global iterations.

    Returns
    -------
    U : (n, d) numpy.ndarray
        The positions after the last iteration.
    energies : (iterations,) numpy.ndarray
        ``energies[k]``: the energy after iteration ``k``'s global step, with the rotations it used.
    """
    sommets = data["sommets"]
    if U0 is None:
        courant = sommets.copy()
    else:
        courant = np.array(U0, dtype=float)
    # on place les poignees avant la premiere etape locale
    courant[data["fixes"]] = handle_positions
    energies = []
    for _ in range(iterations):
        rotations = arap_rotations(sommets, courant, data["triangles"], data["poids"])
        courant = arap_global_step(data, rotations, handle_positions)
        energies.append(arap_energy(sommets, courant, data["triangles"], data["poids"], rotations))
    return courant, np.array(energies)
''',
    "laplacian_editing": r'''import numpy as np


def laplacian_editing(V, F, handles, handle_positions):
    """Naive Laplacian editing: the global step with every rotation the identity.

    Parameters
    ----------
    V : (n, d) array_like of float
        Rest positions.
    F : (f, 3) array_like of int
        Triangles.
    handles : (h,) array_like of int
        Vertex indices.
    handle_positions : (h, d) array_like of float
        Where the handles go.

    Returns
    -------
    U : (n, d) numpy.ndarray
    """
    donnees = arap_precompute(V, F, handles)
    nb_sommets, dim = donnees["sommets"].shape
    # toutes les rotations sont l'identite
    identites = np.broadcast_to(np.eye(dim), (nb_sommets, dim, dim))
    return arap_global_step(donnees, identites, handle_positions)
''',
}
LOSES = set()
