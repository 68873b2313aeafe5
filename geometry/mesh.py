"""Meshes of a wheel design as plain arrays: the profile (2-D) and the solid (3-D).

Coordinates
    2-D: ``points[:, 0] = r`` (radius), ``points[:, 1] = z`` (axial).
    3-D: ``z`` is the wheel axis; the profile is revolved about it starting from the
    half-plane ``y = 0, x > 0``, so the contact point (tread apex) is the mesh node at
    ``(x, y, z) = (rolling_radius, 0, 0)`` (index ``contact_node``).

Node ordering is meshio's (= VTK's): ``triangle6`` = 3 vertices then the mid-nodes of
edges (0,1), (1,2), (2,0); ``tetra10`` = 4 vertices then edges (0,1), (1,2), (2,0),
(0,3), (1,3), (2,3). Elements are positively oriented (counter-clockwise triangles in
the (r, z) plane; tetrahedra with positive Jacobian). Second-order meshes are curved:
mid-edge nodes on the boundary lie on the true bore cylinder, tread and arcs.
Mesh size
    One characteristic length ``size`` [m] everywhere, or ``elements_through_web``
    (size = wall_thickness / n: the web's thickness, its thinner end if it tapers, an
    outline's thinnest wall). Default (neither given):
    :data:`DEFAULT_ELEMENTS_THROUGH_WEB` = ``{2: 2, 3: 1}``, i.e. web_thickness / 2 for
    the profile (7.5 mm for Table 1: about 400 P2 nodes; the axisymmetric solver gets
    every mode below 5 kHz within 0.15 % on it) and web_thickness / 1 in 3-D (15 mm:
    about 7k P2 tets, 14k nodes, 41k DOF,
    under a second to mesh). Both reproduce the exact area / volume to about 1e-6 with
    P2. For converged 3-D frequencies use ``elements_through_web=2`` (about 34k P2 tets,
    60k nodes; FE notes: two P2 layers through the web give frequencies within 0.2 %).
    Whatever the size, the bore gets at least 16 elements around, and thin curved
    features are refined locally where curved elements would otherwise invert.

Meshes are made by :mod:`geometry.gmsh_mesh` (gmsh) and :mod:`geometry.revolve`
(the cyclic 3-D mesh); this module knows nothing of finite elements.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from .files import stored_array
from .profile import half_profile
from .simplex import jacobians
from .wheel_design import WheelDesign

__all__ = [
    "DEFAULT_ELEMENTS_THROUGH_WEB",
    "MAX_ELEMENTS",
    "PHYSICAL_TAGS",
    "MeshError",
    "ProfileMesh",
    "SectorLayout",
    "SolidMesh",
    "bore_size",
    "estimate_element_count",
    "mesh_size",
    "short_segment_lengths",
]

#: Default number of elements across the web thickness, by mesh dimension:
#: size = web_thickness / 2 for the (cheap) 2-D profile, web_thickness / 1 in 3-D.
DEFAULT_ELEMENTS_THROUGH_WEB: dict[int, int] = {2: 2, 3: 1}
#: Refuse sizes whose estimated element count exceeds this (a typo like ``size=1e-5``
#: would otherwise run for hours).
MAX_ELEMENTS = 3_000_000
#: gmsh physical-group tags (names are "bore", "tread", "wheel"), also in the .msh files.
PHYSICAL_TAGS: dict[str, int] = {"bore": 1, "tread": 2, "wheel": 3}


class MeshError(RuntimeError):
    """gmsh failed, or produced an unusable mesh, for a valid design."""


def readonly(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a)
    a.setflags(write=False)
    return a


#: the nodes per cell a stored mesh's connectivity may have (linear, quadratic), by dimension
_STORED_COLUMNS = {
    2: {"triangles": (3, 6), "bore_facets": (2, 3), "tread_facets": (2, 3)},
    3: {"tetra": (4, 10), "bore_facets": (3, 6), "tread_facets": (3, 6)},
}


class _MeshBase:
    if TYPE_CHECKING:  # the subclasses' fields (not fields of this base)
        points: np.ndarray
        dim: int

        @property
        def cells(self) -> np.ndarray: ...

        def to_meshio(self, include_boundaries: bool = True) -> Any: ...

    def _meshio(self, cell_type: str, facet_type: str, include_boundaries: bool):
        import meshio

        pts = self.points
        if pts.shape[1] == 2:
            pts = np.column_stack([pts, np.zeros(len(pts))])
        dim = self.dim
        cells = [(cell_type, np.asarray(self.cells))]
        phys = [np.full(len(self.cells), PHYSICAL_TAGS["wheel"])]
        field_data = {"wheel": np.array([PHYSICAL_TAGS["wheel"], dim])}
        if include_boundaries:
            for name in ("bore", "tread"):
                facets = np.asarray(getattr(self, f"{name}_facets"))
                cells.append((facet_type, facets))
                phys.append(np.full(len(facets), PHYSICAL_TAGS[name]))
                field_data[name] = np.array([PHYSICAL_TAGS[name], dim - 1])
        return meshio.Mesh(
            pts,
            cells,
            cell_data={"gmsh:physical": phys, "gmsh:geometrical": [p.copy() for p in phys]},
            field_data=field_data,
        )

    @property
    def n_nodes(self) -> int:
        return int(len(self.points))

    @property
    def n_elements(self) -> int:
        return int(len(self.cells))

    @property
    def n_vertices(self) -> int:
        """Number of element vertices; they come first: ``points[:n_vertices]`` with
        ``cells[:, :dim + 1]`` is the straight-sided first-order mesh."""
        return int(self.cells[:, : self.dim + 1].max()) + 1

    def write(self, path: str | Path, include_boundaries: bool = True, binary: bool | None = None) -> Path:
        """Write ``.msh`` (MSH 2.2, physical groups "wheel", "bore", "tread" with the tags
        of :data:`PHYSICAL_TAGS`) or ``.vtu`` through meshio, chosen by the extension.
        ``binary``: default ASCII for .msh, binary (compressed) for .vtu."""
        import meshio

        path = Path(path)
        suffix = path.suffix.lower()
        if suffix == ".msh":
            # MSH 2.2: meshio's 4.1 writer needs per-node entity data for mixed cells
            kwargs = {"file_format": "gmsh22", "binary": bool(binary)}
        elif suffix == ".vtu":
            kwargs = {"file_format": "vtu", "binary": binary is None or binary}
        else:
            raise ValueError(f"mesh file must end in .msh or .vtu, got {path.name!r}")
        meshio.write(path, self.to_meshio(include_boundaries), **kwargs)
        return path

    def to_arrays(self) -> dict[str, np.ndarray]:
        """The mesh as plain arrays (for ``.npz`` files); :meth:`from_arrays` reverses it."""
        return {f.name: np.asarray(getattr(self, f.name)) for f in fields(cast(Any, self)) if f.init}

    @classmethod
    def from_arrays(cls, arrays: dict[str, np.ndarray]):
        """The mesh :meth:`to_arrays` wrote, checked before use (a stored mesh is read
        back from a cache: ``ValueError`` where it is not a mesh of this kind)."""
        dim = 2 if cls is ProfileMesh else 3
        points = stored_array(arrays, "points", "f", ndim=2, columns=dim)
        kwargs: dict[str, Any] = {"points": points}
        for f in fields(cast(Any, cls)):
            if not f.init or f.name == "points":
                continue
            if f.name == "design_name":
                kwargs[f.name] = str(stored_array(arrays, f.name, "U", ndim=0))
            elif f.name == "size":
                kwargs[f.name] = float(stored_array(arrays, f.name, "f", ndim=0))
            elif f.name in ("order", "n_sectors"):
                kwargs[f.name] = int(stored_array(arrays, f.name, "iu", ndim=0))
            else:  # connectivity and node sets: indices of the points
                columns = _STORED_COLUMNS[dim].get(f.name)
                ndim = 2 if columns else (0 if f.name == "contact_node" else 1)
                v = stored_array(arrays, f.name, "iu", ndim=ndim, columns=columns, index_below=len(points))
                kwargs[f.name] = v.item() if v.ndim == 0 else v
        if kwargs["order"] not in (1, 2):
            raise ValueError(f"stored mesh of order {kwargs['order']}")
        return cls(**kwargs)


@dataclass(frozen=True, eq=False)
class ProfileMesh(_MeshBase):
    """Triangle mesh of the half-profile in the (r, z) plane.

    ``points`` (N, 2) [r, z] in m; ``triangles`` (M, 3) or (M, 6), meshio ordering,
    counter-clockwise; ``bore_nodes`` / ``tread_nodes``: sorted node indices on the bore
    (r = bore_radius) and on the tread (the segment holding the contact point), mid-edge
    nodes included;
    ``bore_facets`` / ``tread_facets``: boundary edges (K, 2) or (K, 3) (meshio
    ``line``/``line3``: end nodes, then the mid node); ``contact_node``: the node at the
    tread apex (rolling_radius, 0); ``size``: the characteristic length used [m];
    ``straight_mid_nodes``: as for :class:`SolidMesh` (normally empty).
    """

    points: np.ndarray
    triangles: np.ndarray
    order: int
    bore_nodes: np.ndarray
    tread_nodes: np.ndarray
    bore_facets: np.ndarray
    tread_facets: np.ndarray
    contact_node: int
    size: float
    design_name: str
    straight_mid_nodes: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    dim: int = field(default=2, init=False)

    @property
    def cells(self) -> np.ndarray:
        return self.triangles

    def area(self) -> float:
        """Area of the (curved, isoparametric) mesh [m^2], exact quadrature."""
        det, _, w = jacobians(self.points, self.triangles, 2, self.order)
        return float((det @ w).sum())

    def revolved_volume(self) -> float:
        """Volume of the mesh revolved about the axis, 2 pi * integral of r dA [m^3]."""
        det, x, w = jacobians(self.points, self.triangles, 2, self.order)
        return float(2 * math.pi * ((det * x[..., 0]) @ w).sum())

    def to_meshio(self, include_boundaries: bool = True):
        """meshio.Mesh with points (r, z, 0), the triangles and, with
        ``include_boundaries``, the bore / tread edges, tagged by ``gmsh:physical``."""
        if self.order == 1:
            return self._meshio("triangle", "line", include_boundaries)
        return self._meshio("triangle6", "line3", include_boundaries)


@dataclass(frozen=True, eq=False)
class SolidMesh(_MeshBase):
    """Tetrahedral mesh of the wheel (profile revolved 2 pi about the z axis).

    ``points`` (N, 3) [x, y, z] in m; ``tetra`` (M, 4) or (M, 10), meshio ordering,
    positive Jacobian; ``bore_nodes`` / ``tread_nodes``: sorted node indices on the bore
    cylinder and on the tread (the contact point's segment revolved), mid-edge nodes
    included; ``bore_facets`` / ``tread_facets``: boundary triangles (K, 3) or (K, 6), meshio ordering;
    ``contact_node``: the node at (rolling_radius, 0, 0); ``size``: the characteristic
    length used [m]; ``straight_mid_nodes``: mid-edge nodes left on their straight edge
    because curving them would invert a thin element (normally empty; never on the bore
    or tread; the volume then stays within 0.2 % of exact).
    """

    points: np.ndarray
    tetra: np.ndarray
    order: int
    bore_nodes: np.ndarray
    tread_nodes: np.ndarray
    bore_facets: np.ndarray
    tread_facets: np.ndarray
    contact_node: int
    size: float
    design_name: str
    straight_mid_nodes: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    #: 0 for a gmsh (unstructured) mesh; N for a cyclic mesh from :func:`revolve_profile`
    #: (N identical sectors, numbered as described there; :meth:`sector_layout`).
    n_sectors: int = 0
    dim: int = field(default=3, init=False)

    @property
    def cells(self) -> np.ndarray:
        return self.tetra

    def volume(self) -> float:
        """Volume of the (curved, isoparametric) mesh [m^3], exact quadrature."""
        total = 0.0
        for start in range(0, len(self.tetra), 100_000):  # bound the memory
            det, _, w = jacobians(self.points, self.tetra[start : start + 100_000], 3, self.order)
            total += float((det @ w).sum())
        return total

    def sector_layout(self) -> SectorLayout:
        """Node bookkeeping of a cyclic mesh (``n_sectors > 0``); see :class:`SectorLayout`."""
        if self.n_sectors <= 0:
            raise ValueError("not a cyclic mesh (n_sectors == 0): build it with revolve_profile")
        return _sector_layout(self)

    def to_meshio(self, include_boundaries: bool = True):
        """meshio.Mesh with the tetrahedra and, with ``include_boundaries``, the bore /
        tread triangles, tagged by ``gmsh:physical``."""
        if self.order == 1:
            return self._meshio("tetra", "triangle", include_boundaries)
        return self._meshio("tetra10", "triangle6", include_boundaries)


@dataclass(frozen=True)
class SectorLayout:
    """Which nodes of a cyclic :class:`SolidMesh` belong to sector 0.

    ``owned``: the nodes sector 0 owns (its face at theta = 0 and everything strictly
    between theta = 0 and theta = 2 pi / N), in a fixed local order; sector s owns the
    same nodes rotated by ``s * 2 pi / N``. ``next_face``: the nodes on the face
    theta = 2 pi / N (owned by sector 1) that sector 0's tetrahedra use;
    ``next_face_local``: for each, the local index (into ``owned``) of the same profile
    node on face 0. ``tetra``: the rows of ``tetra`` that make up sector 0.
    ``face_triangles``: the profile triangles on face 0 (``triangle6`` or ``triangle``,
    meshio order) as local indices; local indices below ``nv + ne`` are the profile's
    own node numbers (vertices, then mid nodes), so ``points[owned[:nv + ne]]`` with
    ``face_triangles`` is the profile mesh at theta = 0 (r = x, z = z).
    """

    n_sectors: int
    owned: np.ndarray
    next_face: np.ndarray
    next_face_local: np.ndarray
    tetra: np.ndarray
    face_triangles: np.ndarray


def _sector_layout(m: SolidMesh) -> SectorLayout:
    n = m.n_sectors
    nv = m.n_vertices // n
    q = (m.n_nodes - n * nv) // n  # mid nodes per sector: ne (face) + nv (C) + ne (D)
    ne = (q - nv) // 2
    owned = np.concatenate([np.arange(nv), n * nv + np.arange(q)])
    next_face = np.concatenate([nv + np.arange(nv), n * nv + q + np.arange(ne)])
    next_face_local = np.concatenate([np.arange(nv), nv + np.arange(ne)])
    per = len(m.tetra) // n
    local = np.full(m.n_nodes, -1, dtype=np.int64)
    local[owned] = np.arange(len(owned))
    # the first third of sector 0's tetrahedra have their first three vertices (and the
    # mid nodes of edges 01, 12, 20) on face 0: revolve_profile's split, kept by _orient
    first = np.asarray(m.tetra[: per // 3])
    cols = [0, 1, 2, 4, 5, 6] if m.order == 2 else [0, 1, 2]
    face = local[first[:, cols]]
    if (face < 0).any():
        raise ValueError("mesh does not follow revolve_profile's numbering")
    return SectorLayout(n, owned, next_face, next_face_local, np.arange(per), face)


def mesh_size(
    design: WheelDesign,
    size: float | None = None,
    elements_through_web: int | None = None,
    dim: int = 3,
) -> float:
    """The characteristic length [m] from ``size`` or ``elements_through_web`` (not both);
    default ``wall_thickness / DEFAULT_ELEMENTS_THROUGH_WEB[dim]`` (the thinnest wall:
    :attr:`WheelDesign.wall_thickness`)."""
    if dim not in DEFAULT_ELEMENTS_THROUGH_WEB:
        raise ValueError(f"dim must be 2 or 3, got {dim!r}")
    if size is not None and elements_through_web is not None:
        raise ValueError("give either size or elements_through_web, not both")
    if size is not None:
        if isinstance(size, bool) or not isinstance(size, (int, float, np.floating, np.integer)):
            raise ValueError(f"size must be a number, got {type(size).__name__} {size!r}")
        if not math.isfinite(size) or size <= 0:
            raise ValueError(f"size must be a positive finite length in m, got {size}")
        return float(size)
    n = DEFAULT_ELEMENTS_THROUGH_WEB[dim] if elements_through_web is None else elements_through_web
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"elements_through_web must be a positive integer, got {n!r}")
    return design.wall_thickness / int(n)


def bore_size(design: WheelDesign, h: float) -> float:
    """Element size [m] along the bore: at most ``h``, and at least 16 elements around
    the bore circle (see :class:`_Sizer`)."""
    return min(h, 2 * math.pi * design.bore_radius / 16)


def estimate_element_count(design: WheelDesign, h: float, dim: int) -> int:
    """Elements gmsh will make for characteristic length ``h`` [m], without meshing.

    Measured on these wheels (Frontal-Delaunay in 2-D, Delaunay in 3-D): about
    2.3 / h^2 triangles per unit area plus one per boundary length h; 7.5 / h^3
    tetrahedra per unit volume. A bore finer than ``h`` (:func:`bore_size`) adds a band
    of small elements along it: about 6 web_thickness / h_bore triangles in 2-D, and
    2600 (t / h_bore)^0.62 (t / h)^1.6 tetrahedra in 3-D (t the web thickness; fitted to
    bore radii of 0.3-3 mm). Within a factor 2 of gmsh on the designs and presets
    (tests/test_safety.py), which is what a budget needs.
    """
    from .profile import profile_area, revolved_volume

    t = design.wall_thickness
    hb = bore_size(design, h)
    short = short_segment_lengths(design, h)
    if dim == 2:
        est = 2.3 * profile_area(design) / h**2 + half_profile(design).perimeter() / h
        if hb < h:
            est += 6.0 * t / hb
        est += DENSE_BOUNDARY_2D * t * float(np.sum(1.0 / short))
    else:
        est = 7.5 * revolved_volume(design) / h**3
        if hb < h:
            est += 2600.0 * (t / hb) ** 0.62 * (t / h) ** 1.6
        est += 7.5 * math.pi * design.rolling_radius * t * float(np.sum(1.0 / short**2))
    return int(math.ceil(est))


#: Triangles a dense stretch of boundary adds: gmsh meshes the material next to a
#: segment shorter than the element size at that segment's length, across the wall;
#: about DENSE_BOUNDARY_2D t / l per segment of length l (t the thinnest wall; fitted
#: within 10 % to webs of 600 to 6,000 segments, 20k to 1.9M triangles).
DENSE_BOUNDARY_2D = 1.1


def short_segment_lengths(design: WheelDesign, h: float) -> np.ndarray:
    """The lengths [m] of an outline's segments shorter than half the element size (a
    polyline gmsh must follow point by point); none for a parametric design."""
    if design.profile is None:
        return np.zeros(0)
    o = design.profile
    lengths = np.array([o.segment_length(i) for i in range(o.n_segments)])
    return lengths[lengths < 0.5 * h]
