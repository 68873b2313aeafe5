"""scikit-fem meshes from the geometry package's meshes (plain arrays).

Triangles of the (r, z) profile: a second-order ``ProfileMesh`` becomes a curved
``MeshTri2`` (mid-edge nodes on the true tread arc), or a straight-sided ``MeshTri1`` on
its corner nodes (for P2 elements on straight triangles). Tetrahedra: a ``tetra10``
mesh becomes a curved ``MeshTet2`` for P2, otherwise a ``MeshTet1`` on the corners.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import skfem as fe

__all__ = ["corner_mesh", "to_skfem_mesh", "to_skfem_tet", "to_skfem_tri"]


def to_skfem_mesh(mesh: Any, curved: bool = False) -> fe.Mesh:
    """A scikit-fem triangle mesh of the (r, z) profile from a ``ProfileMesh`` (or
    anything with ``points`` and ``triangles``), or a scikit-fem ``MeshTri1`` /
    ``MeshTri2`` (returned as is); see :func:`to_skfem_tri`."""
    if isinstance(mesh, fe.Mesh):
        return mesh
    return to_skfem_tri(mesh.points, mesh.triangles, curved)


def to_skfem_tri(points: np.ndarray, triangles: np.ndarray, curved: bool = False) -> fe.Mesh:
    """Triangles (M, 3) or (M, 6) in meshio order on points (N, 2+) as a scikit-fem mesh.

    Second-order triangles become a curved ``MeshTri2`` (mid-edge nodes on the true
    tread arc) with ``curved=True``, otherwise a straight-sided ``MeshTri1`` on their
    corner nodes (renumbered), on which ElementTriP2 is used.
    """
    pts = np.asarray(points, dtype=float)[:, :2]
    tri = np.asarray(triangles, dtype=np.int64)
    if tri.shape[1] == 6 and curved:
        return fe.MeshTri2(np.ascontiguousarray(pts.T), np.ascontiguousarray(tri.T))
    corners = tri[:, :3]
    used, inv = np.unique(corners, return_inverse=True)
    t = inv.reshape(corners.shape)
    p = pts[used]
    # scikit-fem expects counter-clockwise triangles for a positive Jacobian sign only
    # in some places; orient them consistently anyway.
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    t[cross < 0] = t[cross < 0][:, [0, 2, 1]]
    return fe.MeshTri1(np.ascontiguousarray(p.T), np.ascontiguousarray(t.T))


def corner_mesh(m: fe.Mesh) -> tuple[np.ndarray, np.ndarray]:
    """Corner points (Np, 2) and triangles (M, 3) of a scikit-fem triangle mesh."""
    nv = m.nvertices
    p = np.asarray(m.doflocs[:, :nv].T)
    t = np.array(m.t[:3].T)  # scikit-fem sorts t: orientation is lost, restore CCW
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
    cw = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]) < 0
    t[cw] = t[cw][:, [0, 2, 1]]
    return p, t


def to_skfem_tet(points: np.ndarray, tetra: np.ndarray, order: int):
    """scikit-fem mesh for the requested element order; returns (mesh, curved)."""
    points = np.asarray(points, dtype=float)
    tetra = np.asarray(tetra)
    if tetra.shape[1] == 10 and order == 2:
        # meshio tetra10 edge order (01, 12, 20, 03, 13, 23) is scikit-fem's P2 order.
        return fe.MeshTet2(np.ascontiguousarray(points.T), np.ascontiguousarray(tetra.T)), True
    corners = tetra[:, :4]
    used, inv = np.unique(corners, return_inverse=True)
    t = inv.reshape(corners.shape)
    return fe.MeshTet1(np.ascontiguousarray(points[used].T), np.ascontiguousarray(t.T)), False
