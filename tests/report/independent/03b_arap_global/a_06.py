import runpy
from pathlib import Path

# the same student's 03 submission: its functions are copied into 03b, as the notebook asks
_STAGE_03 = runpy.run_path(str(Path(__file__).parents[1] / "03_arap" / Path(__file__).name))

NOTEBOOK = '03b_arap_global'
DESCRIPTION = _STAGE_03["DESCRIPTION"]
SOLUTIONS = {
    **_STAGE_03["SOLUTIONS"],
    'arap_precompute': r'''import numpy as np
from scipy.sparse.linalg import factorized


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
    V=np.asarray(V,float);F=np.asarray(F);h=np.asarray(handles,dtype=np.int64).ravel();n=len(V)
    if not h.size or len(set(h.tolist()))<h.size or h.min()<0 or h.max()>=n:raise ValueError(f"bad handles {h}")
    f=np.setdiff1d(np.arange(n),h);K=-cotangent_laplacian(V,F).tocsr()
    return V,F,cotangent_weights(V,F),h,f,K[f][:,h],factorized(K[f][:,f].tocsc())
''',
    'arap_global_step': r'''import numpy as np


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
    V,F,C,h,f,K,sol=data;P=np.asarray(handle_positions,float);i,j=F[:,[1,2,0]],F[:,[2,0,1]];d=V.shape[1]
    y=(C[...,None]*((V[j]-V[i])@np.asarray(R,float)[F].mean(1).transpose(0,2,1))).reshape(-1,d)
    B=np.zeros_like(V);np.add.at(B,j.ravel(),y);np.add.at(B,i.ravel(),-y)
    U=np.empty_like(V);U[h]=P;r=B[f]-K@P;U[f]=np.stack([sol(r[:,c]) for c in range(d)],1);return U
''',
    'arap_solve': r'''import numpy as np


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
    V,F,C,h=data[:4];U=np.array(V if U0 is None else U0,float);U[h]=handle_positions;E=[]
    for _ in range(iterations):R=arap_rotations(V,U,F,C);U=arap_global_step(data,R,handle_positions);E+=[arap_energy(V,U,F,C,R)]
    return U,E
''',
    'laplacian_editing': r'''import numpy as np


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
    return arap_global_step(arap_precompute(V,F,handles),np.tile(np.eye(np.shape(V)[1]),(len(V),1,1)),handle_positions)
''',
}
LOSES = set()
