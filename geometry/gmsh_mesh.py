"""gmsh meshes of a wheel design: the 2-D profile and the 3-D revolved solid.

Both are built with the gmsh Python API and the OpenCASCADE kernel from the outline of
:func:`geometry.profile.half_profile` (straight segments and circular arcs: the tread,
fillets, any outline's arcs; arcs over 90 degrees are split, and the segment holding the
contact point is split there so that the contact is a mesh node).
Every call initialises gmsh, builds one model, meshes it, copies the result into numpy
arrays and finalises gmsh again (also on errors): no gmsh state survives a call. gmsh
failures become :class:`~geometry.mesh.MeshError`. Invalid designs never reach gmsh: a
:class:`~geometry.wheel_design.WheelDesign` validates on construction and raises
:class:`~geometry.wheel_design.DesignError`. Sizes: :func:`geometry.mesh.mesh_size`.
"""

from __future__ import annotations

import math
import os
import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np

from .mesh import (
    MAX_ELEMENTS,
    PHYSICAL_TAGS,
    MeshError,
    ProfileMesh,
    SolidMesh,
    bore_size,
    estimate_element_count,
    mesh_size,
    readonly,
)
from .profile import half_profile
from .simplex import inverted, jacobians, orient, straighten
from .wheel_design import WheelDesign, validate

__all__ = ["gmsh_session", "mesh_profile", "mesh_wheel"]

_SNAP = 1e-6

_LOCK = threading.RLock()  # gmsh is a process-wide singleton and not thread-safe

#: Straightened mid-nodes are accepted only if the mesh volume (area) stays this close
#: to the exact one; otherwise the mesh is refined locally instead.
_STRAIGHT_TOL = 2e-3


def _measure_error(points, cells, dim, order, design) -> float:
    det, _, w = jacobians(points, cells, dim, order)
    prof = half_profile(design)
    exact = prof.area() if dim == 2 else prof.revolved_volume()
    return abs(float((det @ w).sum()) / exact - 1.0)


def _check_order(order: int) -> int:
    if isinstance(order, bool) or order not in (1, 2):
        raise ValueError(f"order must be 1 or 2, got {order!r}")
    return int(order)


def _check_count(design: WheelDesign, h: float, dim: int) -> None:
    est = estimate_element_count(design, h, dim)
    if est > MAX_ELEMENTS:
        raise ValueError(
            f"size {h:.3g} m would give about {est:.3g} elements (limit {MAX_ELEMENTS:.0e}); "
            "use a larger size or fewer elements through the web"
        )


def _python_handlers() -> dict[int, Any]:
    """The signal dispositions Python keeps that gmsh changes at the C level: SIGINT (set
    to its default: the process would die at once), SIGTERM (its own handler, which exits
    at once) and SIGPIPE (Python ignores it; at its default a write to a closed pipe,
    such as a dead worker's, would kill the process). Main thread only."""
    if threading.current_thread() is not threading.main_thread():
        return {}
    return {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM, signal.SIGPIPE)}


def _restore(handlers: dict[int, Any]) -> None:
    """Give the process its own signal dispositions back, so that a stopped run cleans
    up and a broken pipe is an error, not a death."""
    for signum, handler in handlers.items():
        if handler is not None:
            signal.signal(signum, handler)


@contextmanager
def _held(handlers: dict[int, Any]) -> Iterator[None]:
    """Block the stop signals while gmsh sets its own dispositions and ours are put back
    (a signal in between would meet gmsh's, or the default, and kill the process without
    its clean-up); one that came meanwhile is delivered to ours on leaving."""
    stops = {signal.SIGINT, signal.SIGTERM} & set(handlers)
    old = signal.pthread_sigmask(signal.SIG_BLOCK, stops) if stops else None
    try:
        yield
    finally:
        if old is not None:
            signal.pthread_sigmask(signal.SIG_SETMASK, old)


#: A home folder that cannot exist (``/dev/null`` is not a folder), and the user "nobody"
_NO_HOME, _NOBODY_UID = "/dev/null/no-home", 65534


@contextmanager
def _no_preference_files() -> Iterator[None]:
    """gmsh's initialisation without the preference files its FLTK writes: FLTK creates
    ``$HOME/.fltk/fltk.org/fltk.prefs`` and, for a process that may, the system-wide
    ``/etc/fltk/fltk.org/fltk.prefs``. Neither is the tool's to write (it writes only its
    result and its cache), so both writes are made to fail: HOME names no folder, and a
    root process is the user "nobody" for the call. gmsh reads no preference it needs
    from them (its own options are set by the session)."""
    home = os.environ.get("HOME")
    os.environ["HOME"] = _NO_HOME
    dropped = False
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        try:
            os.seteuid(_NOBODY_UID)
            dropped = True
        except OSError:  # a container without the capability: the system file is written
            pass
    try:
        yield
    finally:
        if dropped:
            os.seteuid(0)
        if home is None:
            os.environ.pop("HOME", None)
        else:
            os.environ["HOME"] = home


@contextmanager
def gmsh_session(verbose: bool) -> Iterator[Any]:
    """An initialised gmsh with one fresh model; finalised (or, if someone else had
    initialised gmsh, the model removed and the options restored) on exit."""
    import gmsh

    with _LOCK:
        owner = not gmsh.isInitialized()
        saved: dict[str, float] = {}
        current = None
        handlers: dict[int, Any] = {}
        if owner:
            interruptible = threading.current_thread() is threading.main_thread()
            handlers = _python_handlers() if interruptible else {}
            with _held(handlers), _no_preference_files():
                gmsh.initialize(readConfigFiles=False, interruptible=interruptible)
                _restore(handlers)
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
                with _held(handlers):
                    gmsh.finalize()
                    _restore(handlers)
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


def _outline(design: WheelDesign) -> tuple[list[tuple[float, float]], list[str], list[float]]:
    """Profile vertices, segment kinds ('bore', 'line', 'arc') and bulges, with straight
    segments shorter than _SNAP merged into a neighbour (never moving an arc's end
    points)."""
    prof = half_profile(design)
    verts = [(float(r), float(z)) for r, z in prof.points]
    bulges = [float(b) for b in prof.bulges]
    kinds = ["line" if b == 0.0 else "arc" for b in bulges]
    for i in prof.clamp:
        kinds[i] = "bore"
    while True:
        n = len(verts)
        snap = _SNAP * design.rolling_radius
        short = [i for i in range(n) if math.dist(verts[i], verts[(i + 1) % n]) < snap]
        if not short:
            return verts, kinds, bulges
        i = short[0]
        if kinds[i] != "line":
            raise MeshError(
                f"design {design.name!r}: the {kinds[i]} segment is shorter than {snap:.3g} m "
                f"({_SNAP:g} x rolling_radius); "
                "cannot mesh a feature that small"
            )
        j = (i + 1) % n
        if kinds[j] == "line":  # drop vertex j: segment i absorbs segment j
            del verts[j], kinds[j], bulges[j]
        elif kinds[(i - 1) % n] == "line":  # drop vertex i: segment i-1 absorbs segment i
            del verts[i], kinds[i], bulges[i]
        else:
            raise MeshError(f"design {design.name!r}: degenerate profile near {verts[i]}")


def _pieces(p, q, bulge: float, contact) -> list[tuple[np.ndarray, np.ndarray, np.ndarray | None]]:
    """Segment p -> q as gmsh pieces (start, end, arc centre or None): split at the
    contact point if it lies inside, and arcs into pieces of at most 90 degrees."""
    p, q, c = (np.asarray(x, float) for x in (p, q, contact))
    tol = 1e-12 * np.linalg.norm(c)
    if bulge == 0.0:
        d = q - p
        t = float((c - p) @ d / (d @ d))
        if 0 < t < 1 and np.linalg.norm(p + t * d - c) <= tol:
            return [(p, c, None), (c, q, None)]
        return [(p, q, None)]
    d = q - p
    centre = (p + q) / 2 + (1 - bulge * bulge) / (4 * bulge) * np.array([-d[1], d[0]])
    radius = float(np.linalg.norm(p - centre))
    phi0, theta = math.atan2(p[1] - centre[1], p[0] - centre[0]), 4 * math.atan(bulge)
    cuts = {0.0: p, 1.0: q}  # position along the arc (0..1) -> point
    rel = c - centre
    if abs(np.linalg.norm(rel) - radius) <= tol:
        s = ((math.atan2(rel[1], rel[0]) - phi0) * math.copysign(1, theta)) % (2 * math.pi) / abs(theta)
        if 1e-9 < s < 1 - 1e-9:
            cuts[s] = c
    n = int(math.ceil(abs(theta) / (math.pi / 2) - 1e-9))
    for k in range(1, n):
        s = k / n
        if all(abs(s - t) > 0.05 for t in cuts):  # no sliver next to the contact point
            phi = phi0 + s * theta
            cuts[s] = centre + radius * np.array([math.cos(phi), math.sin(phi)])
    order = sorted(cuts)
    return [(cuts[a], cuts[b], centre) for a, b in zip(order[:-1], order[1:])]


def _build_profile_surface(gmsh, design: WheelDesign, h: float, dim: int):
    """Add the profile as an OCC plane surface. For dim 2 it lies in the (x=r, y=z)
    plane, for dim 3 in the (x=r, z=z) half-plane y = 0. The segment holding the contact
    point is split there, so that the contact point is a geometric vertex. Returns the
    surface tag and the curve tags of the bore and of the tread (the segment holding the
    contact point)."""
    occ = gmsh.model.occ
    verts, kinds, bulges = _outline(design)
    contact = (design.rolling_radius, 0.0)

    L = design.rolling_radius  # unit of length inside gmsh
    tags: dict[tuple[float, float], int] = {}

    def point(xy) -> int:
        key = (float(xy[0]), float(xy[1]))
        if key not in tags:
            r, z = key[0] / L, key[1] / L
            tags[key] = occ.addPoint(r, z, 0.0, h / L) if dim == 2 else occ.addPoint(r, 0.0, z, h / L)
        return tags[key]

    prof = half_profile(design)
    tread_segment = (prof.contact_segment(),)
    curves, bore, tread, centres = [], [], [], []
    n = len(verts)
    for i, kind in enumerate(kinds):
        for a, b, centre in _pieces(verts[i], verts[(i + 1) % n], bulges[i], contact):
            mid = (a + b) / 2
            if centre is not None:
                mid = centre + np.linalg.norm(a - centre) * (mid - centre) / np.linalg.norm(mid - centre)
            on_tread = kind != "bore" and prof.distance(mid[None], tread_segment)[0] <= 1e-9 * L
            if centre is None:
                c = occ.addLine(point(a), point(b))
            else:
                pc = (
                    occ.addPoint(centre[0] / L, centre[1] / L, 0.0)
                    if dim == 2
                    else occ.addPoint(centre[0] / L, 0.0, centre[1] / L)
                )
                centres.append(pc)
                c = occ.addCircleArc(point(a), pc, point(b))
            curves.append(c)
            if kind == "bore":
                bore.append(c)
            if on_tread:
                tread.append(c)
    if not tread:
        raise MeshError(f"design {design.name!r}: the contact point's segment was lost in meshing")
    loop = occ.addCurveLoop(curves)
    surface = occ.addPlaneSurface([loop])
    occ.remove([(0, c) for c in centres])
    return surface, bore, tread


def _classify_surfaces(gmsh, design: WheelDesign, volume: int):
    """Bore and tread surfaces of the revolved solid, found by sampling each boundary
    surface: all samples on a clamped segment, or all on the contact point's segment."""
    L = design.rolling_radius  # gmsh works in units of the rolling radius
    prof = half_profile(design)
    tol = 1e-9 * L
    tread_segment = (prof.contact_segment(),)
    s = np.linspace(0.1, 0.9, 5)
    bore, tread = [], []
    for _, tag in gmsh.model.getBoundary([(3, volume)], oriented=False):
        (umin, vmin), (umax, vmax) = np.asarray(gmsh.model.getParametrizationBounds(2, tag))
        U, V = np.meshgrid(umin + s * (umax - umin), vmin + s * (vmax - vmin))
        uv = np.column_stack([U.ravel(), V.ravel()]).ravel()
        xyz = np.asarray(gmsh.model.getValue(2, tag, uv)).reshape(-1, 3) * L
        rz = np.column_stack([np.hypot(xyz[:, 0], xyz[:, 1]), xyz[:, 2]])
        if np.all(prof.distance(rz, prof.clamp) < tol):
            bore.append(tag)
        elif np.all(prof.distance(rz, tread_segment) < tol):
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
        self.L = L
        self.rings = np.zeros((0, 4))  # r, z, radius, size (gmsh units)

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
            np.asarray(gmsh.model.mesh.getElementsByType(facet_type, e)[1], dtype=np.int64) for e in entities
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
        with gmsh_session(verbose) as gmsh:
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
                cells = orient(points, cells, dim)
                bad = inverted(points, cells, dim, order)
                straight = np.zeros(0, dtype=np.int64)
                if bad.any():
                    keep = np.union1d(bore_f, tread_f)
                    fixed, moved = straighten(points, cells, bad, keep, dim)
                    if (
                        not inverted(fixed, cells, dim, order).any()
                        and _measure_error(fixed, cells, dim, order, design) <= _STRAIGHT_TOL
                    ):
                        points, straight, bad = fixed, moved, bad & False
                if not bad.any():
                    break
                failures.append(f"attempt {attempt}: {np.count_nonzero(bad)} inverted curved element(s)")
                sizer.refine(points, cells[bad], dim)
            else:
                raise MeshError("; ".join(failures))
    except (MeshError, ValueError, TypeError) as exc:
        if isinstance(exc, MeshError) and not str(exc).startswith("design"):
            raise MeshError(
                f"design {design.name!r} ({dim}-D, size {h:.4g} m, order {order}): {exc}"
            ) from exc
        raise
    except Exception as exc:  # gmsh raises plain Exception with its last error message
        raise MeshError(
            f"gmsh failed to mesh design {design.name!r} ({dim}-D, size {h:.4g} m, order {order}): {exc}"
        ) from exc
    contact = _contact_node(points, design)
    common = dict(
        points=readonly(points),
        order=order,
        bore_nodes=readonly(np.unique(bore_f)),
        tread_nodes=readonly(np.unique(tread_f)),
        bore_facets=readonly(bore_f),
        tread_facets=readonly(tread_f),
        contact_node=contact,
        straight_mid_nodes=readonly(straight),
        size=h,
        design_name=design.name,
    )
    if dim == 2:
        return ProfileMesh(triangles=readonly(cells), **common)
    return SolidMesh(tetra=readonly(cells), **common)


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
