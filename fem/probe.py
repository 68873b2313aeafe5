"""Point evaluation of a finite-element field, robust on (and a hair outside) a curved
boundary."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import skfem as fe
from scipy.spatial import cKDTree

__all__ = ["probe_matrix"]


def _clip_to_triangle(X: np.ndarray) -> np.ndarray:
    """Project reference coordinates (2, ...) onto the reference triangle."""
    x, y = X[0].copy(), X[1].copy()
    s = x + y
    over = s > 1
    x[over] -= (s[over] - 1) / 2
    y[over] -= (s[over] - 1) / 2
    x, y = np.clip(x, 0, 1), np.clip(y, 0, 1)
    s = x + y
    over = s > 1
    x[over] /= s[over]
    y[over] /= s[over]
    return np.array([x, y])


def probe_matrix(basis: fe.CellBasis, pts: np.ndarray, n_cand: int = 8) -> sp.csr_matrix:
    """Matrix P with ``(P @ x)[c * n + i]`` = component c of the field x at point i.

    Like ``CellBasis.probes`` but robust on the boundary: the element is the nearest
    candidate after projecting the point onto each candidate's straight-sided (corner)
    triangle, and the reference coordinates are clipped to the element. A point on a
    curved boundary, or a chord height outside it, is evaluated at the closest point
    of the mesh (scikit-fem's own finder rejects such points and has no MeshTri2
    version).
    """
    pts = np.atleast_2d(np.asarray(pts, dtype=float))
    if pts.shape[0] != 2:
        pts = pts.T
    npts = pts.shape[1]
    m = basis.mesh
    corners = m.doflocs[:, m.t[:3]]  # (2, 3, nel)
    kc = min(n_cand, m.t.shape[1])
    _, cand = cKDTree(corners.mean(axis=1).T).query(pts.T, kc)
    cand = np.asarray(cand).reshape(npts, kc)
    # affine reference coordinates in each candidate (straight-sided) triangle
    p0 = corners[:, 0, cand]  # (2, npts, kc)
    e1 = corners[:, 1, cand] - p0
    e2 = corners[:, 2, cand] - p0
    det = e1[0] * e2[1] - e1[1] * e2[0]
    d = pts[:, :, None] - p0
    X = np.array([(d[0] * e2[1] - d[1] * e2[0]) / det, (e1[0] * d[1] - e1[1] * d[0]) / det])
    Xc = _clip_to_triangle(X)
    proj = p0 + Xc[0] * e1 + Xc[1] * e2
    dist = np.linalg.norm(proj - pts[:, :, None], axis=0)
    best = np.argmin(dist, axis=1)
    ii = np.arange(npts)
    cells = cand[ii, best]
    Xb = Xc[:, ii, best]
    if not isinstance(basis.mapping, fe.MappingAffine):
        # curved elements: Newton on the isoparametric map from the affine guess
        try:
            Xn = basis.mapping.invF(pts[:, :, None], tind=cells)[:, :, 0]
            Xb = _clip_to_triangle(Xn)
        except Exception:  # noqa: BLE001 (no convergence: keep the affine estimate)
            pass
    Xb = Xb[:, :, None]
    phis = np.array(
        [np.asarray(basis.elem.gbasis(basis.mapping, Xb, k, tind=cells)[0]) for k in range(basis.Nbfun)]
    )  # (Nbfun, comp, npts, 1) or (Nbfun, npts, 1)
    comp = phis.shape[1] if phis.ndim == 4 else 1
    rows = np.tile(np.arange(comp * npts), basis.Nbfun)
    cols = basis.element_dofs[:, np.tile(cells, comp)].ravel()
    return sp.coo_matrix((phis.ravel(), (rows, cols)), shape=(comp * npts, basis.N)).tocsr()
