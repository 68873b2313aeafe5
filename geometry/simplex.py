"""Reference-simplex mathematics of P1/P2 triangles and tetrahedra (meshio / VTK node
order): quadrature, shape functions, Jacobians, and the checks and repairs of curved
elements the meshers need (orientation, inversion, straightened mid-edge nodes)."""

from __future__ import annotations

import numpy as np

__all__ = ["EDGES", "inverted", "jacobians", "orient", "shape_functions", "simplex_rule", "straighten"]


def _gauss_jacobi01(n: int, alpha: int) -> tuple[np.ndarray, np.ndarray]:
    """n-point rule on [0, 1] for the weight (1 - t)^alpha."""
    from scipy.special import roots_jacobi

    x, w = roots_jacobi(n, alpha, 0.0)
    return (1.0 + x) / 2.0, w / 2.0 ** (alpha + 1)


def simplex_rule(dim: int, n: int = 3) -> tuple[np.ndarray, np.ndarray]:
    """Collapsed (Duffy / Stroud conical product) rule on the reference simplex, exact
    for polynomials of degree 2n - 1; positive weights summing to 1/dim!."""
    if dim == 2:
        u, wu = _gauss_jacobi01(n, 1)
        v, wv = _gauss_jacobi01(n, 0)
        U, V = np.meshgrid(u, v, indexing="ij")
        W = np.outer(wu, wv)
        pts = np.stack([U, V * (1 - U)], axis=-1).reshape(-1, 2)
        return pts, W.ravel()
    u, wu = _gauss_jacobi01(n, 2)
    v, wv = _gauss_jacobi01(n, 1)
    w, ww = _gauss_jacobi01(n, 0)
    U, V, Wc = np.meshgrid(u, v, w, indexing="ij")
    W = wu[:, None, None] * wv[None, :, None] * ww[None, None, :]
    pts = np.stack([U, V * (1 - U), Wc * (1 - U) * (1 - V)], axis=-1).reshape(-1, 3)
    return pts, W.ravel()


EDGES = {2: ((0, 1), (1, 2), (2, 0)), 3: ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))}


def shape_functions(dim: int, order: int, xi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Values (nq, nn) and reference gradients (nq, nn, dim) of the Lagrange basis."""
    nq = xi.shape[0]
    lam = np.concatenate([1.0 - xi.sum(axis=1, keepdims=True), xi], axis=1)  # (nq, dim+1)
    dlam = np.concatenate([-np.ones((1, dim)), np.eye(dim)], axis=0)  # (dim+1, dim)
    if order == 1:
        return lam, np.broadcast_to(dlam, (nq, dim + 1, dim)).copy()
    vals, grads = [], []
    for i in range(dim + 1):
        vals.append(lam[:, i] * (2 * lam[:, i] - 1))
        grads.append((4 * lam[:, i] - 1)[:, None] * dlam[i])
    for i, j in EDGES[dim]:
        vals.append(4 * lam[:, i] * lam[:, j])
        grads.append(4 * (lam[:, i, None] * dlam[j] + lam[:, j, None] * dlam[i]))
    return np.stack(vals, axis=1), np.stack(grads, axis=1)


def jacobians(points: np.ndarray, cells: np.ndarray, dim: int, order: int, n: int = 3):
    """detJ (M, nq), physical quadrature points (M, nq, dim) and weights (nq,)."""
    xi, w = simplex_rule(dim, n)
    N, dN = shape_functions(dim, order, xi)
    X = points[cells]  # (M, nn, dim)
    J = np.einsum("eak,qal->eqkl", X, dN)
    return np.linalg.det(J), np.einsum("qa,eak->eqk", N, X), w


_FLIP = {
    (2, 1): [0, 2, 1],
    (2, 2): [0, 2, 1, 5, 4, 3],
    (3, 1): [0, 2, 1, 3],
    (3, 2): [0, 2, 1, 3, 6, 5, 4, 7, 9, 8],
}


def orient(points: np.ndarray, cells: np.ndarray, dim: int) -> np.ndarray:
    """Flip the elements whose straight-sided (vertex) Jacobian is negative."""
    det, _, _ = jacobians(points, cells[:, : dim + 1], dim, 1, n=1)
    neg = det[:, 0] < 0
    if neg.any():
        order = 1 if cells.shape[1] == dim + 1 else 2
        cells = cells.copy()
        cells[neg] = cells[neg][:, _FLIP[(dim, order)]]
    return cells


def inverted(points: np.ndarray, cells: np.ndarray, dim: int, order: int) -> np.ndarray:
    """Mask of the elements with a non-positive Jacobian at some quadrature point."""
    det, _, _ = jacobians(points, cells, dim, order)
    return (det <= 1e-12 * np.abs(det).max()).any(axis=1)


def straighten(points, cells, bad, keep, dim) -> tuple[np.ndarray, np.ndarray]:
    """Move the mid-edge nodes of the ``bad`` elements to the middle of their edge,
    except the nodes in ``keep`` (bore and tread). Curving a mid-node onto a concave
    surface (the rim's inner cylinder) inverts an element thinner than the edge's
    sagitta; a straight edge there changes the volume by at most the sagitta times the
    element's face area. Returns the new points and the moved node indices."""
    points = points.copy()
    moved = []
    for k, (i, j) in enumerate(EDGES[dim]):
        mid = cells[bad, dim + 1 + k]
        move = ~np.isin(mid, keep)
        e = cells[bad][move]
        points[mid[move]] = 0.5 * (points[e[:, i]] + points[e[:, j]])
        moved.append(mid[move])
    return points, np.unique(np.concatenate(moved))
