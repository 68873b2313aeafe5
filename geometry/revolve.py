"""The cyclic 3-D mesh: the profile mesh revolved in N identical sectors."""

from __future__ import annotations

import math

import numpy as np

from .mesh import ProfileMesh, SolidMesh, readonly
from .simplex import orient

__all__ = ["revolve_profile"]


def revolve_profile(profile: ProfileMesh, n_sectors: int) -> SolidMesh:
    """Tetrahedral mesh of the wheel made of ``n_sectors`` identical sectors.

    Each profile triangle swept through one sector (a prism) is split into three
    tetrahedra, with the diagonal of every quadrilateral face running from the lower
    profile node index on the sector's first face to the higher one on its second face;
    the split therefore matches across shared faces and is the same in every sector, so
    the mesh, its matrices and its clamped nodes are invariant under a rotation by
    ``2 pi / n_sectors`` about z (cyclic symmetry, exact to round-off).

    A second-order profile (``triangle6``, curved tread) gives a curved ``tetra10`` mesh:
    the mid-edge nodes are the images of (r, z, theta) points, the profile mid node (or
    vertex) at theta half-way through the sector for the edges that cross it, so every
    node lies on the revolved profile surface (bore cylinder, crowned tread). A
    first-order profile gives ``tetra`` (4 nodes).

    Numbering (used by :meth:`SolidMesh.sector_layout`): profile vertex v on face s
    (theta_s = 2 pi s / N) is node ``s * nv + v`` (the vertices come first); then per
    sector s a block of ``ne + nv + ne`` mid nodes: the profile mid nodes on face s, the
    circumferential edge mid nodes of the vertices, the diagonal mid nodes of the
    profile edges. The tetrahedra of sector s are rows ``s * 3 M .. (s + 1) * 3 M``.
    """
    if isinstance(n_sectors, bool) or not isinstance(n_sectors, (int, np.integer)) or n_sectors < 3:
        raise ValueError(f"n_sectors must be an integer >= 3, got {n_sectors!r}")
    n = int(n_sectors)
    tri = np.asarray(profile.triangles)
    pts = np.asarray(profile.points, dtype=float)
    order = 2 if tri.shape[1] == 6 else 1
    nv = int(tri[:, :3].max()) + 1
    ne = len(pts) - nv if order == 2 else 0
    q = 2 * ne + nv if order == 2 else 0
    dth = 2 * math.pi / n

    # corners sorted by profile index, with the profile mid node of each sorted pair
    perm = np.argsort(tri[:, :3], axis=1)
    abc = np.take_along_axis(tri[:, :3], perm, axis=1)
    if order == 2:
        local = np.zeros((len(tri), 3, 3), dtype=np.int64)
        for (i, j), col in (((0, 1), 3), ((1, 2), 4), ((0, 2), 5)):
            local[:, i, j] = local[:, j, i] = tri[:, col]
        rows = np.arange(len(tri))[:, None, None]
        mids = local[rows, perm[:, :, None], perm[:, None, :]]  # mids[t, i, j]: sorted i, j

    # the three tetrahedra of a prism: (corner, layer) of each vertex
    split = (
        ((0, 0), (1, 0), (2, 0), (2, 1)),
        ((0, 0), (1, 0), (1, 1), (2, 1)),
        ((0, 0), (0, 1), (1, 1), (2, 1)),
    )
    edges = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))  # meshio tetra10
    s_all = np.arange(n)[:, None]

    def vertex(c: int, layer: int) -> np.ndarray:  # (n, M)
        return ((s_all + layer) % n) * nv + abc[None, :, c]

    def mid(c1: int, l1: int, c2: int, l2: int) -> np.ndarray:
        base = n * nv
        if l1 == l2:  # in a face: the profile mid node on face s + l
            return base + ((s_all + l1) % n) * q + (mids[None, :, c1, c2] - nv)
        if c1 == c2:  # circumferential edge of a vertex
            return base + s_all * q + ne + abc[None, :, c1]
        lo, hi = (c1, c2) if l1 == 0 else (c2, c1)
        if lo > hi:
            raise AssertionError("diagonal from a higher to a lower profile index")
        return base + s_all * q + ne + nv + (mids[None, :, c1, c2] - nv)

    cells = []
    for tet in split:
        cols = [vertex(c, lay) for c, lay in tet]
        if order == 2:
            cols += [mid(*tet[a], *tet[b]) for a, b in edges]
        cells.append(np.stack(cols, axis=-1))  # (n, M, 4|10)
    tetra = np.stack(cells, axis=1).reshape(n, 3 * len(tri), -1).reshape(-1, 4 + 6 * (order == 2))

    # coordinates
    def ring(r: np.ndarray, z: np.ndarray, theta: np.ndarray) -> np.ndarray:
        out = np.empty((len(theta), len(r), 3))
        out[..., 0] = np.cos(theta)[:, None] * r
        out[..., 1] = np.sin(theta)[:, None] * r
        out[..., 2] = z
        return out.reshape(-1, 3)

    th = dth * np.arange(n)
    parts = [ring(pts[:nv, 0], pts[:nv, 1], th)]
    if order == 2:
        mp = pts[nv:]
        blocks = np.concatenate(
            [
                ring(mp[:, 0], mp[:, 1], th).reshape(n, ne, 3),
                ring(pts[:nv, 0], pts[:nv, 1], th + dth / 2).reshape(n, nv, 3),
                ring(mp[:, 0], mp[:, 1], th + dth / 2).reshape(n, ne, 3),
            ],
            axis=1,
        )
        parts.append(blocks.reshape(-1, 3))
    points = np.concatenate(parts)
    points[np.abs(points) < 1e-15 * float(np.abs(pts).max())] = 0.0
    tetra = orient(points, tetra, 3)

    def facets(prof_facets: np.ndarray) -> np.ndarray:
        f = np.asarray(prof_facets)
        if len(f) == 0:
            return np.zeros((0, 6 if order == 2 else 3), dtype=np.int64)
        p, qq = np.minimum(f[:, 0], f[:, 1]), np.maximum(f[:, 0], f[:, 1])
        s = s_all
        s1 = (s + 1) % n
        P0, Q0, P1, Q1 = s * nv + p, s * nv + qq, s1 * nv + p, s1 * nv + qq
        t1, t2 = [P0, Q0, Q1], [P0, Q1, P1]
        if order == 2:
            m = f[:, 2] - nv
            base = n * nv
            F0, F1 = base + s * q + m, base + s1 * q + m
            Cp, Cq = base + s * q + ne + p, base + s * q + ne + qq
            D = base + s * q + ne + nv + m
            t1 += [F0, Cq, D]
            t2 += [D, F1, Cp]
        out = np.stack([np.stack(t1, -1), np.stack(t2, -1)], axis=2)  # (n, K, 2, k)
        return out.reshape(-1, out.shape[-1])

    bore_f, tread_f = facets(profile.bore_facets), facets(profile.tread_facets)
    straight = np.asarray(profile.straight_mid_nodes)
    if straight.size and order == 2:
        straight = (n * nv + (np.arange(n)[:, None] * q + straight[None, :] - nv)).ravel()
    return SolidMesh(
        points=readonly(points),
        tetra=readonly(tetra),
        order=order,
        bore_nodes=readonly(np.unique(bore_f)),
        tread_nodes=readonly(np.unique(tread_f)),
        bore_facets=readonly(bore_f),
        tread_facets=readonly(tread_f),
        contact_node=int(profile.contact_node),  # vertex v on face 0 is node v
        size=profile.size,
        design_name=profile.design_name,
        straight_mid_nodes=readonly(straight.astype(np.int64)),
        n_sectors=n,
    )
