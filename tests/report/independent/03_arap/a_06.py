NOTEBOOK = '03_arap'
DESCRIPTION = '06 competitive programmer: terse one-liners, index permutations [1,2,0]/[2,0,1], tuple as precomputed data'
SOLUTIONS = {
    'optimal_rotation': r'''import numpy as np


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
    u,s,v=np.linalg.svd(np.asarray(S,float));v[...,-1,:]*=np.sign(np.linalg.det(u@v))[...,None]
    return np.swapaxes(u@v,-1,-2)
''',
    'cotangent_weights': r'''import numpy as np


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
    V=np.asarray(V,float);F=np.asarray(F);a=V[F[:,[1,2,0]]]-V[F];b=V[F[:,[2,0,1]]]-V[F]
    x=a[...,0]*b[...,1]-a[...,1]*b[...,0] if V.shape[1]==2 else np.linalg.norm(np.cross(a,b),axis=-1)
    return .5*(a*b).sum(-1)/abs(x)
''',
    'cotangent_laplacian': r'''import numpy as np
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
    n=len(V);F=np.asarray(F);i,j,c=F[:,[1,2,0]].ravel(),F[:,[2,0,1]].ravel(),cotangent_weights(V,F).ravel()
    A=sp.coo_matrix((np.r_[c,c],(np.r_[i,j],np.r_[j,i])),(n,n)).tocsr();return A-sp.diags(A.sum(1).A1)
''',
    'arap_covariances': r'''import numpy as np


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
    V,U,F,C=np.asarray(V,float),np.asarray(U,float),np.asarray(F),np.asarray(C,float);n,d=V.shape
    i,j=F[:,[1,2,0]],F[:,[2,0,1]];T=(C[...,None]*(V[j]-V[i])).transpose(0,2,1)@(U[j]-U[i])
    S=np.zeros((n,d*d))
    for k in range(3):np.add.at(S,F[:,k],T.reshape(-1,d*d))
    return S.reshape(n,d,d)
''',
    'arap_rotations': r'''def arap_rotations(V, U, F, C):
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
    return optimal_rotation(arap_covariances(V,U,F,C))
''',
    'arap_energy': r'''import numpy as np


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
    V,U,F,R,C=(np.asarray(x) for x in (V,U,F,R,C));i,j=F[:,[1,2,0]],F[:,[2,0,1]];e,g=V[j]-V[i],U[j]-U[i]
    return float(sum((C*((g-e@R[F[:,c]].transpose(0,2,1))**2).sum(-1)).sum() for c in range(3)))
''',
}
LOSES = set()
