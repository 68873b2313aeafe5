"""gmsh meshes of a wheel design: a 2-D profile mesh and a 3-D revolved solid mesh.

Both are built with the gmsh Python API and the OpenCASCADE kernel from the outline of
:func:`geometry.profile.half_profile` (straight segments and the crowned tread arc).
Every call initialises gmsh, builds one model, meshes it, copies the result into numpy
arrays and finalises gmsh again (also on errors): no gmsh state survives a call. gmsh
failures become :class:`MeshError`. Invalid designs never reach gmsh: a
:class:`~geometry.design.WheelDesign` validates on construction and raises
:class:`~geometry.design.DesignError`.

Coordinates
    2-D: ``points[:, 0] = r`` (radius), ``points[:, 1] = z`` (axial).
    3-D: ``z`` is the wheel axis; the profile is revolved about it starting from the
    half-plane ``y = 0, x > 0``, so the contact point (tread apex) is the mesh node at
    ``(x, y, z) = (rolling_radius, 0, 0)`` (index ``contact_node``).

Node ordering is meshio's (= VTK's): ``triangle6`` = 3 vertices then the mid-nodes of
edges (0,1), (1,2), (2,0); ``tetra10`` = 4 vertices then edges (0,1), (1,2), (2,0),
(0,3), (1,3), (2,3). Elements are positively oriented (counter-clockwise triangles in
the (r, z) plane; tetrahedra with positive Jacobian). Second-order meshes are curved:
mid-edge nodes on the bore and the tread lie on the true cylinder / crown surface.

Mesh size
    One characteristic length ``size`` [m] everywhere, or ``elements_through_web``
    (size = web_thickness / n). Default (neither given):
    :data:`DEFAULT_ELEMENTS_THROUGH_WEB` = ``{2: 2, 3: 1}``, i.e. web_thickness / 2 for
    the profile (7.5 mm for Table 1: about 400 P2 nodes; the axisymmetric solver gets
    every mode below 5 kHz within 0.15 % on it) and web_thickness / 1 in 3-D (15 mm:
    about 7k P2 tets, 14k nodes, 41k DOF,
    under a second to mesh). Both reproduce the exact area / volume to about 1e-6 with
    P2. For converged 3-D frequencies use ``elements_through_web=2`` (about 34k P2 tets,
    60k nodes; FE notes: two P2 layers through the web give frequencies within 0.2 %).
    Whatever the size, the bore gets at least 16 elements around, and thin curved
    features are refined locally where curved elements would otherwise invert.

This module knows nothing of finite elements: it returns plain arrays.
"""

from __future__ import annotations

import math
import os
import tempfile
import threading
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterator

import numpy as np

from .design import WheelDesign, validate
from .profile import half_profile

__all__ = [
    "DEFAULT_ELEMENTS_THROUGH_WEB",
    "MAX_ELEMENTS",
    "bore_size",
    "estimate_element_count",
    "PHYSICAL_TAGS",
    "MeshError",
    "ProfileMesh",
    "SolidMesh",
    "mesh_profile",
    "mesh_size",
    "mesh_wheel",
    "revolve_profile",
    "SectorLayout",
]

#: Default number of elements across the web thickness, by mesh dimension:
#: size = web_thickness / 2 for the (cheap) 2-D profile, web_thickness / 1 in 3-D.
DEFAULT_ELEMENTS_THROUGH_WEB: dict[int, int] = {2: 2, 3: 1}
#: Refuse sizes whose estimated element count exceeds this (a typo like ``size=1e-5``
#: would otherwise run for hours).
MAX_ELEMENTS = 3_000_000
#: gmsh physical-group tags (names are "bore", "tread", "wheel"), also in the .msh files.
PHYSICAL_TAGS: dict[str, int] = {"bore": 1, "tread": 2, "wheel": 3}

# gmsh works on the wheel scaled to a unit rolling radius (so that meshing does not
# depend on the units or the size of the wheel). Profile segments shorter than _SNAP
# (relative to the rolling radius) are merged away before gmsh sees them: OCC's
# confusion tolerance is 1e-7, and a web face 1e-9 from a rim face would otherwise make
# a degenerate edge. 1e-6 * 0.213 m = 0.2 um: far below any machining tolerance.
_SNAP = 1e-6

_LOCK = threading.RLock()  # gmsh is a process-wide singleton and not thread-safe


class MeshError(RuntimeError):
    """gmsh failed, or produced an unusable mesh, for a valid design."""


# --------------------------------------------------------------------------------------
# quadrature and P1/P2 shape functions (reference simplex, VTK node ordering)
# --------------------------------------------------------------------------------------
def _gauss_jacobi01(n: int, alpha: int) -> tuple[np.ndarray, np.ndarray]:
    """n-point rule on [0, 1] for the weight (1 - t)^alpha."""
    from scipy.special import roots_jacobi

    x, w = roots_jacobi(n, alpha, 0.0)
    return (1.0 + x) / 2.0, w / 2.0 ** (alpha + 1)


def _simplex_rule(dim: int, n: int = 3) -> tuple[np.ndarray, np.ndarray]:
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


_EDGES = {2: ((0, 1), (1, 2), (2, 0)), 3: ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))}


def _shape(dim: int, order: int, xi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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
    for i, j in _EDGES[dim]:
        vals.append(4 * lam[:, i] * lam[:, j])
        grads.append(4 * (lam[:, i, None] * dlam[j] + lam[:, j, None] * dlam[i]))
    return np.stack(vals, axis=1), np.stack(grads, axis=1)


def _jacobians(points: np.ndarray, cells: np.ndarray, dim: int, order: int, n: int = 3):
    """detJ (M, nq), physical quadrature points (M, nq, dim) and weights (nq,)."""
    xi, w = _simplex_rule(dim, n)
    N, dN = _shape(dim, order, xi)
    X = points[cells]  # (M, nn, dim)
    J = np.einsum("eak,qal->eqkl", X, dN)
    return np.linalg.det(J), np.einsum("qa,eak->eqk", N, X), w


# Node permutations that reverse an element's orientation (swap vertices 1 and 2).
_FLIP = {
    (2, 1): [0, 2, 1],
    (2, 2): [0, 2, 1, 5, 4, 3],
    (3, 1): [0, 2, 1, 3],
    (3, 2): [0, 2, 1, 3, 6, 5, 4, 7, 9, 8],
}


def _orient(points: np.ndarray, cells: np.ndarray, dim: int) -> np.ndarray:
    """Flip the elements whose straight-sided (vertex) Jacobian is negative."""
    det, _, _ = _jacobians(points, cells[:, : dim + 1], dim, 1, n=1)
    neg = det[:, 0] < 0
    if neg.any():
        order = 1 if cells.shape[1] == dim + 1 else 2
        cells = cells.copy()
        cells[neg] = cells[neg][:, _FLIP[(dim, order)]]
    return cells


def _inverted(points: np.ndarray, cells: np.ndarray, dim: int, order: int) -> np.ndarray:
    """Mask of the elements with a non-positive Jacobian at some quadrature point."""
    det, _, _ = _jacobians(points, cells, dim, order)
    return (det <= 1e-12 * np.abs(det).max()).any(axis=1)


def _straighten(points, cells, bad, keep, dim) -> tuple[np.ndarray, np.ndarray]:
    """Move the mid-edge nodes of the ``bad`` elements to the middle of their edge,
    except the nodes in ``keep`` (bore and tread). Curving a mid-node onto a concave
    surface (the rim's inner cylinder) inverts an element thinner than the edge's
    sagitta; a straight edge there changes the volume by at most the sagitta times the
    element's face area. Returns the new points and the moved node indices."""
    points = points.copy()
    moved = []
    for k, (i, j) in enumerate(_EDGES[dim]):
        mid = cells[bad, dim + 1 + k]
        move = ~np.isin(mid, keep)
        e = cells[bad][move]
        points[mid[move]] = 0.5 * (points[e[:, i]] + points[e[:, j]])
        moved.append(mid[move])
    return points, np.unique(np.concatenate(moved))


#: Straightened mid-nodes are accepted only if the mesh volume (area) stays this close
#: to the exact one; otherwise the mesh is refined locally instead.
_STRAIGHT_TOL = 2e-3


def _measure_error(points, cells, dim, order, design) -> float:
    from .profile import profile_area, revolved_volume

    det, _, w = _jacobians(points, cells, dim, order)
    exact = profile_area(design) if dim == 2 else revolved_volume(design)
    return abs(float((det @ w).sum()) / exact - 1.0)


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a)
    a.setflags(write=False)
    return a


# --------------------------------------------------------------------------------------
# data objects
# --------------------------------------------------------------------------------------
def _atomic_meshio_write(path: str | Path, mesh, binary: bool | None) -> Path:
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
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    try:
        meshio.write(tmp, mesh, **kwargs)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


@dataclass(frozen=True, eq=False)
class _MeshBase:
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

    def write(
        self, path: str | Path, include_boundaries: bool = True, binary: bool | None = None
    ) -> Path:
        """Write ``.msh`` (MSH 2.2, physical groups "wheel", "bore", "tread" with the tags
        of :data:`PHYSICAL_TAGS`) or ``.vtu`` through meshio, chosen by the extension,
        atomically (temporary file in the same folder, then rename). ``binary``: default
        ASCII for .msh, binary (compressed) for .vtu."""
        return _atomic_meshio_write(path, self.to_meshio(include_boundaries), binary)


@dataclass(frozen=True, eq=False)
class ProfileMesh(_MeshBase):
    """Triangle mesh of the half-profile in the (r, z) plane.

    ``points`` (N, 2) [r, z] in m; ``triangles`` (M, 3) or (M, 6), meshio ordering,
    counter-clockwise; ``bore_nodes`` / ``tread_nodes``: sorted node indices on the bore
    (r = bore_radius) and on the crowned tread, mid-edge nodes included;
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
        det, _, w = _jacobians(self.points, self.triangles, 2, self.order)
        return float((det @ w).sum())

    def revolved_volume(self) -> float:
        """Volume of the mesh revolved about the axis, 2 pi * integral of r dA [m^3]."""
        det, x, w = _jacobians(self.points, self.triangles, 2, self.order)
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
    cylinder and on the crowned tread, mid-edge nodes included; ``bore_facets`` /
    ``tread_facets``: boundary triangles (K, 3) or (K, 6), meshio ordering;
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
            det, _, w = _jacobians(self.points, self.tetra[start : start + 100_000], 3, self.order)
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


# --------------------------------------------------------------------------------------
# size control
# --------------------------------------------------------------------------------------
def mesh_size(
    design: WheelDesign,
    size: float | None = None,
    elements_through_web: int | None = None,
    dim: int = 3,
) -> float:
    """The characteristic length [m] from ``size`` or ``elements_through_web`` (not both);
    default ``web_thickness / DEFAULT_ELEMENTS_THROUGH_WEB[dim]``."""
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
    return design.web_thickness / int(n)


def _check_order(order: int) -> int:
    if isinstance(order, bool) or order not in (1, 2):
        raise ValueError(f"order must be 1 or 2, got {order!r}")
    return int(order)


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

    t = design.web_thickness
    hb = bore_size(design, h)
    if dim == 2:
        verts = half_profile(design).vertices
        perimeter = float(np.sum(np.linalg.norm(np.roll(verts, -1, axis=0) - verts, axis=1)))
        est = 2.3 * profile_area(design) / h**2 + perimeter / h
        if hb < h:
            est += 6.0 * t / hb
    else:
        est = 7.5 * revolved_volume(design) / h**3
        if hb < h:
            est += 2600.0 * (t / hb) ** 0.62 * (t / h) ** 1.6
    return int(math.ceil(est))


def _check_count(design: WheelDesign, h: float, dim: int) -> None:
    est = estimate_element_count(design, h, dim)
    if est > MAX_ELEMENTS:
        raise ValueError(
            f"size {h:.3g} m would give about {est:.3g} elements (limit {MAX_ELEMENTS:.0e}); "
            "use a larger size or fewer elements through the web"
        )


# --------------------------------------------------------------------------------------
# gmsh session and geometry
# --------------------------------------------------------------------------------------
@contextmanager
def _gmsh_session(verbose: bool) -> Iterator[object]:
    """An initialised gmsh with one fresh model; finalised (or, if someone else had
    initialised gmsh, the model removed and the options restored) on exit."""
    import gmsh

    with _LOCK:
        owner = not gmsh.isInitialized()
        saved: dict[str, float] = {}
        current = None
        if owner:
            interruptible = threading.current_thread() is threading.main_thread()
            gmsh.initialize(readConfigFiles=False, interruptible=interruptible)
        else:
            current = gmsh.model.getCurrent()
            for name in _OPTIONS_TOUCHED:
                saved[name] = gmsh.option.getNumber(name)
        try:
            gmsh.option.setNumber("General.Terminal", 1 if verbose else 0)
            gmsh.model.add(f"wheel-{os.getpid()}-{threading.get_ident()}")
            yield gmsh
        finally:
            if owner:
                gmsh.finalize()
            else:
                try:
                    gmsh.model.remove()
                    gmsh.model.setCurrent(current)
                finally:
                    for name, value in saved.items():
                        gmsh.option.setNumber(name, value)


_OPTIONS_TOUCHED = (
    "General.Terminal",
    "General.NumThreads",
    "Geometry.OCCBoundsUseStl",
    "Mesh.Algorithm",
    "Mesh.Algorithm3D",
    "Mesh.ElementOrder",
    "Mesh.SecondOrderLinear",
    "Mesh.HighOrderOptimize",
    "Mesh.MeshSizeMin",
    "Mesh.MeshSizeMax",
    "Mesh.MeshSizeFromPoints",
    "Mesh.MeshSizeFromCurvature",
    "Mesh.MeshSizeExtendFromBoundary",
    "Mesh.Optimize",
)


def _outline(design: WheelDesign) -> tuple[list[tuple[float, float]], list[str]]:
    """Profile vertices and segment kinds ('bore', 'line', 'arc'), with segments shorter
    than _SNAP merged into a neighbour (never moving the arc's end points)."""
    prof = half_profile(design)
    verts = [tuple(map(float, v)) for v in prof.vertices]
    kinds = ["line"] * len(verts)
    kinds[prof.arc[0]] = "arc"
    for i in prof.bore:
        kinds[i] = "bore"
    while True:
        n = len(verts)
        snap = _SNAP * design.rolling_radius
        short = [i for i in range(n) if math.dist(verts[i], verts[(i + 1) % n]) < snap]
        if not short:
            return verts, kinds
        i = short[0]
        if kinds[i] != "line":
            raise MeshError(
                f"design {design.name!r}: the {kinds[i]} segment is shorter than {snap:.3g} m "
                f"({_SNAP:g} x rolling_radius); "
                "cannot mesh a feature that small"
            )
        j = (i + 1) % n
        if kinds[j] == "line":  # drop vertex j: segment i absorbs segment j
            del verts[j]
            del kinds[j]
        elif kinds[(i - 1) % n] == "line":  # drop vertex i: segment i-1 absorbs segment i
            del verts[i]
            del kinds[i]
        else:
            raise MeshError(f"design {design.name!r}: degenerate profile near {verts[i]}")


def _build_profile_surface(gmsh, design: WheelDesign, h: float, dim: int):
    """Add the profile as an OCC plane surface. For dim 2 it lies in the (x=r, y=z)
    plane, for dim 3 in the (x=r, z=z) half-plane y = 0. The tread arc is split at its
    apex so that the contact point is a geometric vertex. Returns the surface tag and the
    curve tags of the bore and of the tread."""
    occ = gmsh.model.occ
    verts, kinds = _outline(design)

    L = design.rolling_radius  # unit of length inside gmsh

    def point(r: float, z: float) -> int:
        r, z = r / L, z / L
        return occ.addPoint(r, z, 0.0, h / L) if dim == 2 else occ.addPoint(r, 0.0, z, h / L)

    tags = [point(r, z) for r, z in verts]
    centre = point(design.rolling_radius - design.crown_radius, 0.0)
    apex = point(design.rolling_radius, 0.0)
    curves, bore, tread = [], [], []
    n = len(verts)
    for i, kind in enumerate(kinds):
        a, b = tags[i], tags[(i + 1) % n]
        if kind == "arc":
            c1 = occ.addCircleArc(a, centre, apex)
            c2 = occ.addCircleArc(apex, centre, b)
            curves += [c1, c2]
            tread += [c1, c2]
        else:
            c = occ.addLine(a, b)
            curves.append(c)
            if kind == "bore":
                bore.append(c)
    loop = occ.addCurveLoop(curves)
    surface = occ.addPlaneSurface([loop])
    occ.remove([(0, centre)])
    return surface, bore, tread


def _classify_surfaces(gmsh, design: WheelDesign, volume: int):
    """Bore and tread surfaces of the revolved solid, found by sampling each boundary
    surface: all samples at r = bore_radius, or all on the crown circle."""
    L = design.rolling_radius  # gmsh works in units of the rolling radius
    rb, R = design.bore_radius / L, design.crown_radius / L
    c = 1.0 - R
    tol = 1e-9 * (1.0 + R)
    s = np.linspace(0.1, 0.9, 5)
    bore, tread = [], []
    for _, tag in gmsh.model.getBoundary([(3, volume)], oriented=False):
        (umin, vmin), (umax, vmax) = np.asarray(gmsh.model.getParametrizationBounds(2, tag))
        U, V = np.meshgrid(umin + s * (umax - umin), vmin + s * (vmax - vmin))
        uv = np.column_stack([U.ravel(), V.ravel()]).ravel()
        xyz = np.asarray(gmsh.model.getValue(2, tag, uv)).reshape(-1, 3)
        r, z = np.hypot(xyz[:, 0], xyz[:, 1]), xyz[:, 2]
        if np.all(np.abs(r - rb) < tol):
            bore.append(tag)
        elif np.all(np.abs(np.hypot(r - c, z) - R) < tol):
            tread.append(tag)
    if not bore or not tread:
        raise MeshError(
            f"design {design.name!r}: could not identify the bore/tread surfaces of the "
            f"revolved solid (found {len(bore)} bore, {len(tread)} tread)"
        )
    return bore, tread


def _set_options(gmsh, h: float, order: int, dim: int) -> None:
    opt = gmsh.option.setNumber
    opt("General.NumThreads", 1)  # deterministic meshes
    opt("Mesh.Algorithm", 6)  # Frontal-Delaunay
    opt("Mesh.Algorithm3D", 1)  # Delaunay
    opt("Mesh.MeshSizeMin", 0.0)
    opt("Mesh.MeshSizeMax", h)
    opt("Mesh.MeshSizeFromPoints", 1)
    # 2-D: at least 16 elements around a full circle (a strongly crowned tread); not in
    # 3-D, where curvature sizing of a small crown is costly (_Sizer refines the bore)
    opt("Mesh.MeshSizeFromCurvature", 16 if dim == 2 else 0)
    opt("Mesh.MeshSizeExtendFromBoundary", 1)
    opt("Mesh.Optimize", 1)
    opt("Mesh.ElementOrder", 1)  # raised with setOrder after generation
    opt("Mesh.SecondOrderLinear", 0)  # mid-edge nodes on the true geometry
    opt("Mesh.HighOrderOptimize", 0)


def _attempts(dim: int, order: int) -> list[int]:
    """The 3-D algorithm of each meshing attempt, tried until no curved element has a
    non-positive Jacobian. Delaunay (1) sometimes leaves a flat tet with all four
    vertices on the bore, which curving its mid-nodes inverts: HXT (10) avoids it. A
    rim overhang thinner than an edge's sagitta inverts too: the offending mid-nodes off
    the bore and tread are put back on their straight edge if that keeps the volume
    within _STRAIGHT_TOL, else the size is halved locally (:class:`_Sizer`) and the
    mesh redone."""
    if order == 1:
        return [1]
    return [1, 10] + [1] * _REFINEMENTS


_REFINEMENTS = 4  # local halvings of the size around inverted curved elements


class _Sizer:
    """gmsh size callback (gmsh units = rolling radius): the uniform size h, at least 16
    elements around the bore, and axisymmetric rings of finer size around the (r, z)
    positions where curved elements inverted in an earlier attempt."""

    def __init__(self, design: WheelDesign, h: float, dim: int):
        L = design.rolling_radius
        self.h = h / L
        self.dim = dim
        self.rb = design.bore_radius / L
        self.h_bore = bore_size(design, h) / L
        self.rings = np.zeros((0, 4))  # r, z, radius, size (gmsh units)
        self.L = L

    def __call__(self, dim, tag, x, y, z, lc):
        r, zz = (x, y) if self.dim == 2 else (math.hypot(x, y), z)
        size = min(lc, self.h)
        if r < self.rb + 2 * self.h_bore:
            size = min(size, self.h_bore)
        if len(self.rings):
            R = self.rings
            inside = np.hypot(R[:, 0] - r, R[:, 1] - zz) < R[:, 2]
            if inside.any():
                size = min(size, float(R[inside, 3].min()))
        return size

    def refine(self, points: np.ndarray, bad_cells: np.ndarray, dim: int) -> None:
        p = points / self.L
        v = p[bad_cells[:, : dim + 1]]  # (k, dim+1, dim)
        rz = v if dim == 2 else np.stack([np.hypot(v[..., 0], v[..., 1]), v[..., 2]], -1)
        centre = rz.mean(axis=1)
        edge = np.max(np.linalg.norm(v[:, :, None, :] - v[:, None, :, :], axis=-1), axis=(1, 2))
        new = np.column_stack([centre, 1.5 * edge, 0.5 * edge])
        # one ring per cluster is enough: round (r, z) to half the new size
        key = np.round(new[:, :2] / np.maximum(new[:, 3:4], 1e-12)).astype(np.int64)
        _, first = np.unique(key, axis=0, return_index=True)
        self.rings = np.concatenate([self.rings, new[first]])


def _extract(gmsh, dim: int, order: int, bore: list[int], tread: list[int]):
    """Nodes, elements and boundary facets as compact numpy arrays (meshio ordering)."""
    cell_type = {(2, 1): 2, (2, 2): 9, (3, 1): 4, (3, 2): 11}[(dim, order)]
    facet_type = {(2, 1): 1, (2, 2): 8, (3, 1): 2, (3, 2): 9}[(dim, order)]
    node_tags, coords, _ = gmsh.model.mesh.getNodes()
    node_tags = np.asarray(node_tags, dtype=np.int64)
    coords = np.asarray(coords).reshape(-1, 3)
    _, enodes = gmsh.model.mesh.getElementsByType(cell_type)
    nn = {2: 3, 3: 4}[dim] if order == 1 else {2: 6, 3: 10}[dim]
    cells = np.asarray(enodes, dtype=np.int64).reshape(-1, nn)
    if len(cells) == 0:
        raise MeshError("gmsh produced no elements")
    if (dim, order) == (3, 2):  # gmsh tetra10 -> VTK: swap the last two edge nodes
        cells = cells[:, [0, 1, 2, 3, 4, 5, 6, 7, 9, 8]]

    def facets_of(entities: list[int]) -> np.ndarray:
        blocks = [
            np.asarray(gmsh.model.mesh.getElementsByType(facet_type, e)[1], dtype=np.int64)
            for e in entities
        ]
        return np.concatenate(blocks).reshape(-1, nn_f)

    nn_f = {1: dim, 2: {2: 3, 3: 6}[dim]}[order]
    bore_f, tread_f = facets_of(bore), facets_of(tread)
    # compact numbering: only the nodes of the elements; the element vertices first,
    # then the mid-edge nodes (so points[:n_vertices] with cells[:, :dim+1] is the P1 mesh)
    vertices = np.unique(cells[:, : dim + 1])
    used = np.concatenate([vertices, np.setdiff1d(np.unique(cells), vertices)])
    lookup = np.full(node_tags.max() + 1, -1, dtype=np.int64)
    lookup[node_tags] = np.arange(len(node_tags))
    points = coords[lookup[used]]
    index = np.full(node_tags.max() + 1, -1, dtype=np.int64)
    index[used] = np.arange(len(used))
    cells, bore_f, tread_f = index[cells], index[bore_f], index[tread_f]
    if (bore_f < 0).any() or (tread_f < 0).any():
        raise MeshError("boundary facets refer to nodes outside the mesh")
    return points, cells, bore_f, tread_f


def _contact_node(points: np.ndarray, design: WheelDesign) -> int:
    target = np.zeros(points.shape[1])
    target[0] = design.rolling_radius
    dist = np.linalg.norm(points - target, axis=1)
    k = int(np.argmin(dist))
    if dist[k] > 1e-9 * design.rolling_radius:
        raise MeshError(f"no mesh node at the contact point (nearest {dist[k]:.3g} m away)")
    return k


def _run(design: WheelDesign, size, elements_through_web, order, verbose, dim):
    if not isinstance(design, WheelDesign):
        raise TypeError(f"design must be a WheelDesign, got {type(design).__name__}")
    validate(design)  # again: a frozen dataclass can still be forced; DesignError before gmsh
    order = _check_order(order)
    h = mesh_size(design, size, elements_through_web, dim)
    _check_count(design, h, dim)
    # Snapping errors (MeshError) surface before gmsh is started.
    _outline(design)
    try:
        with _gmsh_session(verbose) as gmsh:
            _set_options(gmsh, h / design.rolling_radius, order, dim)
            surface, bore, tread = _build_profile_surface(gmsh, design, h, dim)
            occ = gmsh.model.occ
            if dim == 3:
                out = occ.revolve([(2, surface)], 0, 0, 0, 0, 0, 1, 2 * math.pi)
                volumes = [t for d, t in out if d == 3]
                if len(volumes) != 1:
                    raise MeshError(f"revolve gave {len(volumes)} volumes, expected 1")
                occ.synchronize()
                bore, tread = _classify_surfaces(gmsh, design, volumes[0])
                domain = volumes
            else:
                occ.synchronize()
                domain = [surface]
            model = gmsh.model
            model.addPhysicalGroup(dim - 1, bore, PHYSICAL_TAGS["bore"], "bore")
            model.addPhysicalGroup(dim - 1, tread, PHYSICAL_TAGS["tread"], "tread")
            model.addPhysicalGroup(dim, domain, PHYSICAL_TAGS["wheel"], "wheel")
            sizer = _Sizer(design, h, dim)
            model.mesh.setSizeCallback(sizer)
            failures = []
            for attempt, algorithm in enumerate(_attempts(dim, order)):
                gmsh.option.setNumber("Mesh.Algorithm3D", algorithm)
                model.mesh.clear()
                model.mesh.generate(dim)
                if order == 2:
                    model.mesh.setOrder(2)
                try:
                    points, cells, bore_f, tread_f = _extract(gmsh, dim, order, bore, tread)
                except MeshError as exc:  # e.g. the 3-D mesher gave up
                    failures.append(f"attempt {attempt}: {exc}")
                    continue
                points *= design.rolling_radius
                if dim == 2:
                    points = points[:, :2]
                else:
                    # the seam of the revolution is the half-plane y = 0: clean round-off
                    points[np.abs(points[:, 1]) < 1e-14 * design.rolling_radius, 1] = 0.0
                cells = _orient(points, cells, dim)
                bad = _inverted(points, cells, dim, order)
                straight = np.zeros(0, dtype=np.int64)
                if bad.any():
                    keep = np.union1d(bore_f, tread_f)
                    fixed, moved = _straighten(points, cells, bad, keep, dim)
                    if (not _inverted(fixed, cells, dim, order).any()
                            and _measure_error(fixed, cells, dim, order, design) <= _STRAIGHT_TOL):
                        points, straight, bad = fixed, moved, bad & False
                if not bad.any():
                    break
                failures.append(f"attempt {attempt}: {np.count_nonzero(bad)} inverted curved "
                                "element(s)")
                sizer.refine(points, cells[bad], dim)
            else:
                raise MeshError("; ".join(failures))
    except (MeshError, ValueError, TypeError) as exc:
        if isinstance(exc, MeshError) and not str(exc).startswith("design"):
            raise MeshError(f"design {design.name!r} ({dim}-D, size {h:.4g} m, order {order}): "
                            f"{exc}") from exc
        raise
    except Exception as exc:  # gmsh raises plain Exception with its last error message
        raise MeshError(f"gmsh failed to mesh design {design.name!r} ({dim}-D, size {h:.4g} m, "
                        f"order {order}): {exc}") from exc
    contact = _contact_node(points, design)
    common = dict(
        points=_readonly(points),
        order=order,
        bore_nodes=_readonly(np.unique(bore_f)),
        tread_nodes=_readonly(np.unique(tread_f)),
        bore_facets=_readonly(bore_f),
        tread_facets=_readonly(tread_f),
        contact_node=contact,
        straight_mid_nodes=_readonly(straight),
        size=h,
        design_name=design.name,
    )
    if dim == 2:
        return ProfileMesh(triangles=_readonly(cells), **common)
    return SolidMesh(tetra=_readonly(cells), **common)


# --------------------------------------------------------------------------------------
# public entry points
# --------------------------------------------------------------------------------------
def mesh_profile(
    design: WheelDesign,
    size: float | None = None,
    elements_through_web: int | None = None,
    order: int = 2,
    verbose: bool = False,
) -> ProfileMesh:
    """2-D triangle mesh of the half-profile in the (r, z) plane (for an axisymmetric /
    Fourier-harmonic solver). ``order`` 1 or 2 (curved: mid-nodes on the tread arc).

    Raises ValueError for a bad size/order, MeshError if gmsh fails.
    """
    return _run(design, size, elements_through_web, order, verbose, dim=2)


def mesh_wheel(
    design: WheelDesign,
    size: float | None = None,
    elements_through_web: int | None = None,
    order: int = 2,
    verbose: bool = False,
) -> SolidMesh:
    """3-D tetrahedral mesh of the whole wheel: the profile revolved 2 pi about z (OCC
    revolve). ``order`` 1 or 2 (curved: mid-nodes on the bore cylinder and the tread).

    Raises ValueError for a bad size/order, MeshError if gmsh fails.
    """
    return _run(design, size, elements_through_web, order, verbose, dim=3)


# --------------------------------------------------------------------------------------
# cyclic mesh: the profile mesh revolved in N identical sectors
# --------------------------------------------------------------------------------------
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


def _sector_layout(m: "SolidMesh") -> SectorLayout:
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
    split = (((0, 0), (1, 0), (2, 0), (2, 1)),
             ((0, 0), (1, 0), (1, 1), (2, 1)),
             ((0, 0), (0, 1), (1, 1), (2, 1)))
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
        blocks = np.concatenate([
            ring(mp[:, 0], mp[:, 1], th).reshape(n, ne, 3),
            ring(pts[:nv, 0], pts[:nv, 1], th + dth / 2).reshape(n, nv, 3),
            ring(mp[:, 0], mp[:, 1], th + dth / 2).reshape(n, ne, 3),
        ], axis=1)
        parts.append(blocks.reshape(-1, 3))
    points = np.concatenate(parts)
    points[np.abs(points) < 1e-15 * float(np.abs(pts).max())] = 0.0
    tetra = _orient(points, tetra, 3)

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
        points=_readonly(points),
        tetra=_readonly(tetra),
        order=order,
        bore_nodes=_readonly(np.unique(bore_f)),
        tread_nodes=_readonly(np.unique(tread_f)),
        bore_facets=_readonly(bore_f),
        tread_facets=_readonly(tread_f),
        contact_node=int(profile.contact_node),  # vertex v on face 0 is node v
        size=profile.size,
        design_name=profile.design_name,
        straight_mid_nodes=_readonly(straight.astype(np.int64)),
        n_sectors=n,
    )
