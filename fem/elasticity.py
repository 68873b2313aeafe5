"""3-D isotropic linear elasticity on tetrahedra, vectorised over the elements."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from skfem import Basis

__all__ = ["assemble_elasticity"]


def assemble_elasticity(mesh, basis, elem, lam: float, mu: float, rho: float):
    """K and M of isotropic linear elasticity, vectorised over the elements.

    Equal to scikit-fem's ``asm(linear_elasticity(lam, mu), basis)`` and
    ``asm(rho u.v)`` (same quadrature, same DOF numbering; tested to 1e-10, measured
    ~4e-16 relative) but 3-4x faster: the element matrices come from the scalar
    basis' gradients ``G[e, q, i, a] = d phi_i / d x_a`` (isoparametric, per
    quadrature point) as one batched product ``B = G^T diag(w) G`` of the pairs
    ``int dphi_i/dx_a dphi_j/dx_b``, combined as
    ``K_(ia)(jb) = lam B_iajb + mu B_ibja + mu delta_ab sum_c B_icjc``; the mass is the
    scalar mass on the diagonal component blocks. ElementVector's local DOF ``3 i + a``
    is component ``a`` of scalar function ``i``.
    """
    sb = Basis(mesh, elem.elem, quadrature=basis.quadrature)
    nb = sb.Nbfun
    ne = mesh.t.shape[1]
    dx = sb.dx  # (ne, nq)
    G = np.stack([sb.basis[i][0].grad for i in range(nb)])  # (nb, 3, ne, nq)
    G = np.ascontiguousarray(G.transpose(2, 3, 0, 1)).reshape(ne, dx.shape[1], 3 * nb)
    B = np.matmul((G * dx[:, :, None]).transpose(0, 2, 1), G).reshape(ne, nb, 3, nb, 3)
    Kl = lam * B
    Kl += mu * B.transpose(0, 1, 4, 3, 2)
    tr = mu * np.einsum("eiaja->eij", B)
    for a in range(3):
        Kl[:, :, a, :, a] += tr
    P = np.stack([np.asarray(sb.basis[i][0]) for i in range(nb)], axis=2)  # (ne, nq, nb)
    Ml = rho * np.matmul((P * dx[:, :, None]).transpose(0, 2, 1), P)  # (ne, nb, nb)
    dofs = basis.element_dofs.T  # (ne, 3 nb), local index 3 i + a
    N = basis.N
    rows = np.repeat(dofs, 3 * nb, axis=1).ravel()
    cols = np.tile(dofs, (1, 3 * nb)).ravel()
    K = sp.coo_matrix((Kl.ravel(), (rows, cols)), shape=(N, N)).tocsr()
    d3 = dofs.reshape(ne, nb, 3)
    M = sp.csr_matrix((N, N))
    for a in range(3):
        da = d3[:, :, a]
        M = (
            M
            + sp.coo_matrix(
                (Ml.ravel(), (np.repeat(da, nb, axis=1).ravel(), np.tile(da, (1, nb)).ravel())), shape=(N, N)
            ).tocsr()
        )
    return K, M
