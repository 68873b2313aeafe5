"""The air around the body in the meridian half-plane: a gmsh triangle mesh of the
half-disc r >= 0, rho <= R + d (rho = sqrt(r^2 + z^2)) minus the body's outline, with
the circle rho = R meshed as a line (the physical region inside it, the perfectly
matched layer outside it)."""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from geometry.gmsh_mesh import gmsh_session

from .surface import Surface

__all__ = ["AirMesh", "air_mesh", "forget_meshes"]


@dataclass(frozen=True, eq=False)
class AirMesh:
    """points (N, 2) (r, z) [m]; triangles (M, 3) counter-clockwise; radius: R, the
    physical region's radius [m]; pml_thickness: d [m]."""

    points: np.ndarray
    triangles: np.ndarray
    radius: float
    pml_thickness: float


def _half_disc(occ, radius: float) -> list[tuple[int, int]]:
    disc = occ.addDisk(0.0, 0.0, 0.0, radius, radius)
    box = occ.addRectangle(0.0, -radius, 0.0, radius, 2 * radius)
    out, _ = occ.intersect([(2, disc)], [(2, box)])
    return out


def _body(occ, points: np.ndarray, scale: float) -> list[tuple[int, int]]:
    pts = points.copy()
    pts[np.abs(pts[:, 0]) <= 1e-12 * scale, 0] = 0.0
    tags = [occ.addPoint(float(r), float(z), 0.0) for r, z in pts]
    loop = [occ.addLine(tags[i], tags[(i + 1) % len(tags)]) for i in range(len(tags))]
    return [(2, occ.addPlaneSurface([occ.addCurveLoop(loop)]))]


def air_mesh(
    surface: Surface, radius: float, pml_thickness: float, size_far: float, size_near: float
) -> AirMesh:
    """Mesh the air: elements of ``size_near`` [m] along the body growing to
    ``size_far`` [m] a few sizes away, and ``size_far`` in the layer. The mesh depends on
    the outline and the sizes only: below about a kilohertz a wheel's modes all mesh the
    same air (the sizes are bounded by the body), and the process keeps the last
    :data:`MESHES_KEPT` meshes (their arrays read-only)."""
    if radius <= surface.scale:
        raise ValueError(f"radius {radius:g} m must exceed the body's extent {surface.scale:g} m")
    points = np.ascontiguousarray(surface.points, dtype=float)
    return _meshed(
        points.tobytes(),
        len(points),
        float(surface.scale),
        float(radius),
        float(pml_thickness),
        float(size_far),
        float(size_near),
    )


#: The air meshes a process keeps (:func:`air_mesh`)
MESHES_KEPT = 16


def forget_meshes() -> None:
    """Drop the air meshes this process keeps."""
    _meshed.cache_clear()


@functools.lru_cache(maxsize=MESHES_KEPT)
def _meshed(
    outline: bytes,
    count: int,
    scale: float,
    radius: float,
    pml_thickness: float,
    size_far: float,
    size_near: float,
) -> AirMesh:
    """:func:`air_mesh` of the outline's points (``count`` (r, z) pairs as bytes)."""
    outer = radius + pml_thickness
    with gmsh_session(False) as gmsh:
        occ = gmsh.model.occ
        body = _body(occ, np.frombuffer(outline, dtype=float).reshape(count, 2), scale)
        inner = occ.cut(_half_disc(occ, radius), body)[0]
        ring = occ.cut(_half_disc(occ, outer), _half_disc(occ, radius))[0]
        occ.fragment(inner, ring)
        occ.synchronize()
        near = []
        for _, tag in gmsh.model.getEntities(1):
            lo, hi = gmsh.model.getParametrizationBounds(1, tag)
            r, z, _ = gmsh.model.getValue(1, tag, [0.5 * (lo[0] + hi[0])])
            rho = math.hypot(r, z)
            if r > 1e-9 * outer and abs(rho - radius) > 1e-6 * outer and abs(rho - outer) > 1e-6 * outer:
                near.append(tag)
        field = gmsh.model.mesh.field
        dist = field.add("Distance")
        field.setNumbers(dist, "CurvesList", near)
        field.setNumber(dist, "Sampling", 20)
        thr = field.add("Threshold")
        field.setNumber(thr, "InField", dist)
        field.setNumber(thr, "SizeMin", size_near)
        field.setNumber(thr, "SizeMax", size_far)
        field.setNumber(thr, "DistMin", 0.0)
        field.setNumber(thr, "DistMax", 4.0 * size_far)
        field.setAsBackgroundMesh(thr)
        for name, value in (
            ("Mesh.MeshSizeFromPoints", 0),
            ("Mesh.MeshSizeFromCurvature", 0),
            ("Mesh.MeshSizeExtendFromBoundary", 0),
            ("Mesh.MeshSizeMax", size_far),
            ("Mesh.Algorithm", 6),
        ):
            gmsh.option.setNumber(name, value)
        gmsh.model.mesh.generate(2)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        points = coords.reshape(-1, 3)[:, :2]
        index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
        index[tags.astype(np.int64)] = np.arange(len(tags))
        types, _, nodes = gmsh.model.mesh.getElements(2)
        tri = np.concatenate([n for t, n in zip(types, nodes) if t == 2]).reshape(-1, 3)
    tri = index[tri.astype(np.int64)]
    used = np.unique(tri)
    remap = np.full(len(points), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    points, tri = points[used], remap[tri]
    p0, p1, p2 = points[tri[:, 0]], points[tri[:, 1]], points[tri[:, 2]]
    cw = (p1[:, 0] - p0[:, 0]) * (p2[:, 1] - p0[:, 1]) - (p1[:, 1] - p0[:, 1]) * (p2[:, 0] - p0[:, 0]) < 0
    tri[cw] = tri[cw][:, [0, 2, 1]]
    points.flags.writeable = False
    tri.flags.writeable = False
    return AirMesh(points, tri, float(radius), float(pml_thickness))
