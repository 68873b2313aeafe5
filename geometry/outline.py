"""A wheel's half-profile: a closed loop of straight segments and circular arcs in (r, z).

Any axisymmetric wheel is its half cross-section revolved about the z axis. The loop
is given by its vertices and, for each segment (vertex i to vertex i + 1, the last one
closing the loop), a *bulge* ``tan(theta / 4)``: 0 for a straight segment, otherwise
theta is the arc's included angle, positive counter-clockwise in the (r, z) plane drawn
with r to the right and z up (the DXF polyline convention). The loop may run either
way round. Two boundary parts are named: the *clamp* (the bore, segments at r equal to
the smallest radius of the loop) and the *contact point*, a point of the tread, which
lies at z = 0 (designs given in other coordinates are shifted axially when loaded, see
:func:`outline_from_mapping`).

Area and revolved volume are exact (Green's theorem on every segment, closed form on
arcs; volume by Pappus, ``2 pi * integral of r dA``); the checks of :func:`check`
raise :class:`OutlineError` naming the first problem.
"""

from __future__ import annotations

import csv
import functools
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ._polyline import crossing_pairs, ray_hits, segment_distances
from .files import read_text

__all__ = [
    "ARC_CHORDS",
    "Outline",
    "OutlineError",
    "fillet",
    "outline_from_mapping",
]


class OutlineError(ValueError):
    """An invalid outline; the message names the problem (and the segment or point)."""


#: Bulges below this are straight segments.
STRAIGHT_BULGE = 2e-9
#: Chords per arc where a curve is approximated by a polygon (self-intersection check,
#: thickness and mid-surface sampling): sagitta below 1.2e-4 of the radius for a half
#: circle, far below any mesh size.
ARC_CHORDS = 64
#: Shortest segment, relative to the loop's largest radius.
MIN_SEGMENT_REL = 1e-4
#: Distance within which a point counts as on the boundary, relative to the largest radius.
ON_BOUNDARY_REL = 1e-6
#: A wall is measured across it: a ray counts where it meets the far face within
#: 60 degrees of head-on (not grazing past an acute corner next to its start).
WALL_FACING = 0.5
#: Beyond this many polygon edges the wall thickness casts fewer rays per edge.
MANY_EDGES = 2000
#: Largest contact angle [deg]: the angle between the outward normal at the contact
#: point and the radial direction. Up to it the contact is one Hertz ellipse on a tread
#: or a flange root, whose spin creepage (sin(angle) / r) stays small beside the lateral
#: creepage of the model; beyond it lies flange contact, a different regime (two-point
#: contact, spin-dominated creep) that the lateral creep law does not describe.
MAX_CONTACT_ANGLE_DEG = 45.0


@dataclass(frozen=True)
class Outline:
    """Closed half-profile loop (see the module docstring). Lengths in m.

    ``points``: the K vertices (r, z); ``bulges``: K bulges, segment i runs from vertex
    i to vertex (i + 1) % K; ``clamp``: indices of the clamped segments (the bore);
    ``contact``: the contact point (r, 0) on the tread. Construction checks everything
    (:func:`check`).
    """

    points: tuple[tuple[float, float], ...]
    bulges: tuple[float, ...]
    clamp: tuple[int, ...]
    contact: tuple[float, float]
    #: shortest segment accepted, relative to the largest radius (a parametric wheel's
    #: own outline may have shorter ones, e.g. a web a micrometre from a rim face: the
    #: mesher merges them)
    min_segment_rel: float = field(default=MIN_SEGMENT_REL, compare=False, repr=False)

    def __post_init__(self) -> None:
        # a sagitta below 1e-9 of the chord is a straight segment (and a centre at
        # 1e9 chords is round-off)
        flat = tuple(0.0 if abs(b) < STRAIGHT_BULGE else float(b) for b in self.bulges)
        object.__setattr__(self, "bulges", flat)
        # tuples whatever sequences were given: an outline is hashed (its polygon and
        # frames are kept per outline)
        try:
            object.__setattr__(self, "points", tuple((float(r), float(z)) for r, z in self.points))
            object.__setattr__(self, "clamp", tuple(int(i) for i in self.clamp))
            r, z = self.contact
            object.__setattr__(self, "contact", (float(r), float(z)))
        except (TypeError, ValueError) as exc:
            raise OutlineError(f"an outline's points and contact: (r, z) pairs of numbers ({exc})") from None
        check(self)

    # -- segments ---------------------------------------------------------------------
    @property
    def n_segments(self) -> int:
        return len(self.points)

    def ends(self, i: int) -> tuple[np.ndarray, np.ndarray]:
        """Start and end point of segment i."""
        k = self.n_segments
        return np.asarray(self.points[i], float), np.asarray(self.points[(i + 1) % k], float)

    def arc(self, i: int) -> tuple[np.ndarray, float, float, float] | None:
        """(centre, radius, start angle, included angle) of segment i, None if straight."""
        b = self.bulges[i]
        if b == 0.0:
            return None
        p, q = self.ends(i)
        d = q - p
        centre = (p + q) / 2 + (1 - b * b) / (4 * b) * np.array([-d[1], d[0]])
        radius = float(np.hypot(*d)) * (1 + b * b) / (4 * abs(b))
        start = math.atan2(p[1] - centre[1], p[0] - centre[0])
        return centre, radius, start, 4 * math.atan(b)

    def segment_points(self, i: int, n: int) -> np.ndarray:
        """n + 1 points (n + 1, 2) evenly along segment i, both ends included."""
        t = np.linspace(0.0, 1.0, n + 1)
        a = self.arc(i)
        if a is None:
            p, q = self.ends(i)
            return p + t[:, None] * (q - p)
        c, R, phi0, theta = a
        phi = phi0 + t * theta
        pts = c + R * np.column_stack([np.cos(phi), np.sin(phi)])
        pts[0], pts[-1] = self.ends(i)  # exact end points
        return pts

    def segment_length(self, i: int) -> float:
        a = self.arc(i)
        if a is None:
            p, q = self.ends(i)
            return float(np.hypot(*(q - p)))
        return a[1] * abs(a[3])

    def polygon(self, chords: int = ARC_CHORDS) -> tuple[np.ndarray, np.ndarray]:
        """The loop as a polygon: vertices (P, 2), arcs cut in ``chords`` chords, and
        the segment each polygon edge belongs to (P,) (read-only arrays)."""
        return _polygon(self, chords)

    # -- measures ---------------------------------------------------------------------
    def _green(self) -> tuple[float, float]:
        """Signed loop integrals of r dz (area) and r^2/2 dz (first moment about z)."""
        area = moment = 0.0
        for i in range(self.n_segments):
            a = self.arc(i)
            (r0, z0), (r1, z1) = self.ends(i)
            if a is None:
                area += 0.5 * (r0 + r1) * (z1 - z0)
                moment += (z1 - z0) * (r0 * r0 + r0 * r1 + r1 * r1) / 6
                continue
            (cr, _), R, p0, th = a
            p1 = p0 + th
            ds = math.sin(p1) - math.sin(p0)
            dc2 = (p1 - p0) / 2 + (math.sin(2 * p1) - math.sin(2 * p0)) / 4  # int cos^2
            dc3 = ds - (math.sin(p1) ** 3 - math.sin(p0) ** 3) / 3  # int cos^3
            area += cr * R * ds + R * R * dc2
            moment += 0.5 * R * (cr * cr * ds + 2 * cr * R * dc2 + R * R * dc3)
        return area, moment

    @property
    def orientation(self) -> int:
        """+1 for a counter-clockwise loop in (r, z), -1 for clockwise."""
        return 1 if self._green()[0] > 0 else -1

    def area(self) -> float:
        """Exact area of the half-profile [m^2]."""
        return abs(self._green()[0])

    def revolved_volume(self) -> float:
        """Exact volume of the revolved profile [m^3] (Pappus)."""
        return 2 * math.pi * abs(self._green()[1])

    def perimeter(self) -> float:
        return float(sum(self.segment_length(i) for i in range(self.n_segments)))

    @property
    def scale(self) -> float:
        """The largest radius of the loop [m], the length scale of the tolerances."""
        return float(max(p[0] for p in self.points))

    @property
    def bore_radius(self) -> float:
        """Radius of the clamped bore [m]."""
        return float(min(self.points[i][0] for i in self.clamp))

    def axial_extent(self, r: float) -> tuple[float, float]:
        """Smallest and largest z of the material on the circle of radius r [m]."""
        poly, _ = self.polygon()
        zs = _vertical_crossings(poly, r)
        if len(zs) == 0:
            raise OutlineError(f"no material at r = {r:.6g} m")
        return float(zs.min()), float(zs.max())

    def outer_radius(self, z: np.ndarray) -> np.ndarray:
        """The largest radius of the outline at each axial position ``z`` [m] (nan where no
        segment crosses it): the running surface, tread and flange, across the rim."""
        z = np.atleast_1d(np.asarray(z, dtype=float))
        best = np.full(z.shape, -np.inf)
        for i in range(self.n_segments):
            p, q = self.ends(i)
            a = self.arc(i)
            if a is None:
                if q[1] == p[1]:
                    continue  # a face across the axis: its radii belong to the segments beside it
                t = (z - p[1]) / (q[1] - p[1])
                best = np.where((t >= 0) & (t <= 1), np.maximum(best, p[0] + t * (q[0] - p[0])), best)
                continue
            (cr, cz), radius, start, sweep = a
            dz = z - cz
            across = np.sqrt(np.clip(radius * radius - dz * dz, 0.0, None))
            for r in (cr + across, cr - across):
                phi = np.arctan2(dz, r - cr)
                turned = np.mod((phi - start) * math.copysign(1.0, sweep), 2 * math.pi)
                on = (np.abs(dz) <= radius) & (turned <= abs(sweep) + 1e-12)
                best = np.where(on, np.maximum(best, r), best)
        return np.where(np.isfinite(best), best, np.nan)

    # -- where things are -------------------------------------------------------------
    def contains(self, xy: np.ndarray) -> np.ndarray:
        """Whether each (r, z) point [m] lies inside the material (even-odd rule on the
        polygon of :meth:`polygon`), shape (N,)."""
        xy = np.atleast_2d(np.asarray(xy, dtype=float))
        poly, _ = self.polygon()
        (r0, z0), (r1, z1) = poly.T, np.roll(poly, -1, axis=0).T
        inside = np.zeros(len(xy), dtype=bool)
        for k, (r, z) in enumerate(xy):
            crosses = (z0 > z) != (z1 > z)
            with np.errstate(divide="ignore", invalid="ignore"):
                r_at = r0 + (z - z0) * (r1 - r0) / (z1 - z0)
            inside[k] = bool(np.count_nonzero(crosses & (r < r_at)) % 2)
        return inside

    def distance(self, xy: np.ndarray, segments: tuple[int, ...] | None = None) -> np.ndarray:
        """Distance [m] of points (N, 2) from the loop (or from the given segments)."""
        xy = np.atleast_2d(np.asarray(xy, float))
        chosen = np.arange(self.n_segments) if segments is None else np.asarray(segments, dtype=np.int64)
        bulges = np.asarray(self.bulges)[chosen]
        straight = chosen[bulges == 0.0]
        pts = np.asarray(self.points, float)
        best = segment_distances(xy, pts[straight], pts[(straight + 1) % self.n_segments])
        for i in chosen[bulges != 0.0]:
            best = np.minimum(best, _segment_distance(self, int(i), xy))
        return best

    def contact_segment(self) -> int:
        """The segment the contact point lies on (the first, at a vertex)."""
        return _contact_segment(self)

    def contact_normal(self) -> tuple[float, float]:
        """The outward unit normal (n_r, n_z) of the outline at the contact point."""
        n = -_inward_normals(self, self.contact_segment(), np.array([self.contact]))[0]
        return float(n[0]), float(n[1])

    def contact_crown_radius(self) -> float:
        """Transverse radius of the tread at the contact point [m], inf on a straight one."""
        a = self.arc(self.contact_segment())
        return math.inf if a is None else a[1]

    def is_mirror_symmetric(self, rtol: float = 1e-9) -> bool:
        """True when the profile is its own mirror image about z = 0."""
        pts, _ = self.polygon()
        mirrored = pts * np.array([1.0, -1.0])
        return bool(self.distance(mirrored).max() <= rtol * self.scale)

    def thinnest_wall(self) -> tuple[float, tuple[float, float]]:
        """The thinnest wall [m]: the shortest distance across the material along the
        inward normal to a face it meets within 60 degrees of head-on
        (:data:`WALL_FACING`), from the middle 90 % of every straight segment and the
        chord midpoints of every arc (the elements-through-the-web rule sizes meshes by it).
        For the parametric wheel it is the web's thickness. Returns the thickness [m]
        and the (r, z) [m] the thinnest ray starts from."""
        poly, seg = self.polygon()
        nxt = np.roll(poly, -1, axis=0)
        e = nxt - poly
        n = np.stack([-e[:, 1], e[:, 0]], axis=1) / np.hypot(*e.T)[:, None] * self.orientation  # inward
        straight = np.asarray(self.bulges)[seg] == 0.0
        # 19 rays from each straight edge, one from each arc chord's middle; of
        # thousands of edges (a dense polyline) every so many, 3 rays each
        edges = np.arange(len(poly))
        if len(poly) > MANY_EDGES:
            length = np.hypot(*e.T)
            long_ = length > 8.0 * float(np.median(length))
            edges = np.union1d(np.linspace(0, len(poly) - 1, MANY_EDGES).astype(np.int64), edges[long_])
        many = np.linspace(0.05, 0.95, 19 if len(poly) <= MANY_EDGES else 3)
        t = [many if straight[i] else np.array([0.5]) for i in edges]
        k = np.repeat(edges, [len(x) for x in t])
        s = poly[k] + np.concatenate(t)[:, None] * e[k]
        lift = 1e-9 * self.scale  # start just inside, off the segment itself
        hits = ray_hits(s + lift * n[k], n[k], poly, nxt, facing=WALL_FACING)
        j = int(np.argmin(hits))
        best = float(hits[j] + lift)
        # the same value for the same wall, however computed
        return float(f"{best:.12g}"), (float(s[j, 0]), float(s[j, 1]))

    def wall_thickness(self) -> float:
        """The thinnest wall [m] (:meth:`thinnest_wall`)."""
        return self.thinnest_wall()[0]

    def mid_surface(self, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The profile's mid-surface line from the bore to the contact radius: at each of
        n radii, the middle of the material's axial extent there (the stretch of the line
        r = const nearest the previous middle). Returns r, z and the half-thickness
        there [m]. For a web that is a graph over r (flat, conical, curved) this is the
        web's mid-surface; across the rim it is the middle of the rim."""
        return _mid_surface(self, n)

    # -- copies -----------------------------------------------------------------------
    def scaled(self, factor: float) -> Outline:
        return Outline(
            tuple((r * factor, z * factor) for r, z in self.points),
            self.bulges,
            self.clamp,
            (self.contact[0] * factor, self.contact[1] * factor),
            self.min_segment_rel,
        )

    def to_mapping(self) -> dict[str, Any]:
        """The outline as a TOML-shaped mapping ([profile]); :func:`outline_from_mapping`
        reads it back exactly."""
        return {
            "points": [[r, z] for r, z in self.points + self.points[:1]],  # closed
            "bulges": list(self.bulges),
            "clamp": list(self.clamp),
            "contact": list(self.contact),
        }


@functools.lru_cache(maxsize=64)
def _contact_segment(o: Outline) -> int:
    """:meth:`Outline.contact_segment`, cached (meshing asks for it per surface)."""
    xy = np.array([o.contact])
    pts = np.asarray(o.points, float)
    k = np.arange(o.n_segments)
    d = _point_segment_each(xy[0], pts[k], pts[(k + 1) % o.n_segments])
    for i in np.flatnonzero(np.asarray(o.bulges) != 0.0):
        d[i] = float(_segment_distance(o, int(i), xy)[0])
    return int(np.argmin(d))


def _point_segment_each(x: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The distance of the point x to each straight edge a -> b, shape (E,)."""
    d = b - a
    t = np.clip(((x - a) * d).sum(axis=1) / np.maximum((d * d).sum(axis=1), 1e-300), 0.0, 1.0)
    return np.hypot(*(x - (a + t[:, None] * d)).T)


@functools.lru_cache(maxsize=64)
def _polygon(o: Outline, chords: int) -> tuple[np.ndarray, np.ndarray]:
    """:meth:`Outline.polygon`, cached: checks, measures and meshing all walk it."""
    pts, seg = [], []
    for i in range(o.n_segments):
        n = 1 if o.bulges[i] == 0.0 else chords
        pts.append(o.segment_points(i, n)[:-1])
        seg.append(np.full(n, i))
    poly, index = np.concatenate(pts), np.concatenate(seg)
    for a in (poly, index):
        a.setflags(write=False)
    return poly, index


@functools.lru_cache(maxsize=64)
def _mid_surface(o: Outline, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:meth:`Outline.mid_surface`, cached: every solve of a design labels along it."""
    poly, _ = o.polygon()
    r0, r1 = o.bore_radius, o.contact[0]
    eps = 1e-9 * o.scale
    rs = np.linspace(r0 + eps, r1 - eps, n)
    z_mid, half = np.empty(n), np.empty(n)
    prev = None
    for k, r in enumerate(rs):
        zs = np.sort(_vertical_crossings(poly, r))
        lo, hi = zs[0::2], zs[1::2]
        if len(hi) == 0:
            raise OutlineError(f"no material at r = {r:.6g} m between the bore and the contact")
        mids = (lo + hi) / 2
        # the stretch nearest the previous middle (at the bore: the clamp's middle)
        ref = np.mean([o.points[i][1] for i in o.clamp]) if prev is None else prev
        j = int(np.argmin(np.abs(mids - ref)))
        z_mid[k], half[k] = mids[j], (hi[j] - lo[j]) / 2
        prev = mids[j]
    rs[0], rs[-1] = r0, r1
    z_mid[-1] = o.contact[1]
    for a in (rs, z_mid, half):
        a.setflags(write=False)  # shared by every caller through the cache
    return rs, z_mid, half


def _segment_distance(o: Outline, i: int, xy: np.ndarray) -> np.ndarray:
    p, q = o.ends(i)
    a = o.arc(i)
    if a is None:
        d = q - p
        t = np.clip(((xy - p) @ d) / max(d @ d, 1e-300), 0.0, 1.0)
        return np.linalg.norm(xy - (p + t[:, None] * d), axis=1)
    c, R, phi0, th = a
    rel = xy - c
    phi = np.arctan2(rel[:, 1], rel[:, 0])
    # position along the arc in units of its angle: inside when 0 <= s <= 1
    s = np.mod((phi - phi0) * np.sign(th), 2 * math.pi) / abs(th)
    on = np.abs(np.hypot(rel[:, 0], rel[:, 1]) - R)
    ends = np.minimum(np.linalg.norm(xy - p, axis=1), np.linalg.norm(xy - q, axis=1))
    return np.where(s <= 1.0, on, ends)


def _inward_normals(o: Outline, i: int, pts: np.ndarray) -> np.ndarray:
    """Unit normals pointing into the material at points of segment i."""
    a = o.arc(i)
    if a is None:
        p, q = o.ends(i)
        d = (q - p) / np.hypot(*(q - p))
        n = np.array([-d[1], d[0]]) * o.orientation  # left of travel on a CCW loop
        return np.tile(n, (len(pts), 1))
    c, R, _, th = a
    radial = (pts - c) / R
    # travelling counter-clockwise about the centre (th > 0) the centre is on the left
    return -radial * np.sign(th) * o.orientation


def _vertical_crossings(poly: np.ndarray, r: float) -> np.ndarray:
    """z where the line r = const crosses the polygon (half-open rule at vertices)."""
    a, b = poly, np.roll(poly, -1, axis=0)
    cross = (a[:, 0] <= r) != (b[:, 0] <= r)
    a, b = a[cross], b[cross]
    t = (r - a[:, 0]) / (b[:, 0] - a[:, 0])
    return a[:, 1] + t * (b[:, 1] - a[:, 1])


# -- checks -------------------------------------------------------------------------------
def check(o: Outline) -> None:
    """Raise :class:`OutlineError` naming the first problem of the outline."""
    k = len(o.points)
    if k < 3:
        raise OutlineError(f"an outline needs at least 3 points, got {k}")
    if len(o.bulges) != k:
        raise OutlineError(f"{k} points need {k} bulges (one per segment, the last closes the loop)")
    for i, (r, z) in enumerate(o.points):
        if not (math.isfinite(r) and math.isfinite(z)):
            raise OutlineError(f"point {i} ({r}, {z}) is not finite")
    for i, b in enumerate(o.bulges):
        if not math.isfinite(b) or abs(b) > 1.0:
            raise OutlineError(
                f"segment {i}: bulge {b} must be finite and within +-1 (at most a half circle)"
            )
    scale = o.scale
    if not scale > 0:
        raise OutlineError("the outline must lie at r > 0 (every radius is <= 0)")
    min_len = o.min_segment_rel * scale
    for i in range(k):
        if o.segment_length(i) < min_len or o.segment_length(i) == 0.0:
            raise OutlineError(
                f"segment {i} from {_pt(o.points[i])} is {o.segment_length(i):.3g} m long, "
                f"shorter than {min_len:.3g} m ({o.min_segment_rel:g} x the largest radius): merge it"
            )
    poly, seg = o.polygon()
    if poly[:, 0].min() <= 0:
        j = int(np.argmin(poly[:, 0]))
        raise OutlineError(
            f"the outline reaches r = {poly[j, 0]:.6g} m <= 0 on segment {seg[j]}: "
            "a wheel's profile lies at r > 0 (it has a bore)"
        )
    _check_simple(poly, seg, k)
    # the clamp
    if not o.clamp:
        raise OutlineError("no clamped boundary: name the bore's segments (clamp = [...])")
    r_min = float(poly[:, 0].min())
    tol = ON_BOUNDARY_REL * scale
    for i in o.clamp:
        if not (isinstance(i, int) and 0 <= i < k):
            raise OutlineError(f"clamp: segment {i!r} does not exist (0 to {k - 1})")
        (r0, _), (r1, _) = o.ends(i)
        if o.bulges[i] != 0.0 or abs(r0 - r_min) > tol or abs(r1 - r_min) > tol:
            raise OutlineError(
                f"clamp: segment {i} is not on the bore; a clamped segment is straight at the "
                f"smallest radius of the outline (r = {r_min:.6g} m)"
            )
    # the contact
    rc, zc = o.contact
    if not (math.isfinite(rc) and math.isfinite(zc)):
        raise OutlineError(f"contact point {o.contact} is not finite")
    d = float(o.distance(np.array([o.contact]))[0])
    if d > tol:
        raise OutlineError(
            f"contact point {_pt(o.contact)} is not on the outline (nearest boundary {d:.3g} m away)"
        )
    if abs(zc) > tol:
        raise OutlineError(f"contact point {_pt(o.contact)}: it must lie at z = 0")
    i = o.contact_segment()
    if i in o.clamp:
        raise OutlineError(f"contact point {_pt(o.contact)} is on the clamped bore")
    a = o.arc(i)
    pt = np.array([o.contact])
    normal = -_inward_normals(o, i, pt)[0]
    tilt = math.degrees(math.acos(max(-1.0, min(1.0, float(normal[0])))))
    if tilt > MAX_CONTACT_ANGLE_DEG:
        raise OutlineError(
            f"contact point {_pt(o.contact)}: the outward normal there is {tilt:.3g} deg from radial "
            f"(at most {MAX_CONTACT_ANGLE_DEG:g}: beyond it is flange contact, which the lateral "
            "creep model does not describe); the contact must be on the tread or the flange root"
        )
    if a is not None and float(np.dot(a[0] - pt[0], normal)) > 0:
        raise OutlineError(
            f"contact point {_pt(o.contact)} lies on a concave arc (radius {a[1]:.4g} m): "
            "Hertz contact needs a convex tread"
        )


def _check_simple(poly: np.ndarray, seg: np.ndarray, k: int) -> None:
    """No two polygon edges of the loop cross or touch, except neighbours at their
    shared vertex (and neighbours must not fold back onto each other)."""
    a, b = poly, np.roll(poly, -1, axis=0)
    pair = crossing_pairs(a, b)
    if pair is not None:
        i, j = pair
        raise OutlineError(
            f"the outline intersects itself: segment {seg[i]} crosses segment {seg[j]} "
            f"near {_pt(tuple((a[i] + b[i]) / 2))}"
        )
    # neighbours folding back: the turn at a vertex of (nearly) 180 degrees
    e = b - a
    e = e / np.linalg.norm(e, axis=1)[:, None]
    prev = np.roll(e, 1, axis=0)
    back = np.einsum("ij,ij->i", e, prev) < -1 + 1e-9
    if back.any():
        v = int(np.flatnonzero(back)[0])
        raise OutlineError(f"the outline folds back on itself at {_pt(tuple(poly[v]))} (segment {seg[v]})")


def _pt(p) -> str:
    return f"({float(p[0]):.6g}, {float(p[1]):.6g})"


# -- construction ---------------------------------------------------------------------------
def fillet(
    points: list[tuple[float, float]], bulges: list[float], vertex: int, radius: float
) -> tuple[list[tuple[float, float]], list[float]]:
    """Round the corner at ``vertex`` between two straight segments with an arc of
    ``radius`` [m] tangent to both: the new points and bulges (the vertex becomes the
    arc's two tangent points, so later vertices move up by one)."""
    k = len(points)
    i_in, i_out = (vertex - 1) % k, vertex
    if bulges[i_in] != 0.0 or bulges[i_out] != 0.0:
        raise OutlineError(f"fillet at {_pt(points[vertex])}: both segments must be straight")
    v = np.asarray(points[vertex], float)
    a, b = np.asarray(points[i_in], float), np.asarray(points[(vertex + 1) % k], float)
    d_in, d_out = (v - a) / np.linalg.norm(v - a), (b - v) / np.linalg.norm(b - v)
    turn = math.atan2(d_in[0] * d_out[1] - d_in[1] * d_out[0], float(d_in @ d_out))
    if abs(turn) < 1e-9:
        raise OutlineError(f"fillet at {_pt(points[vertex])}: the segments are in line")
    t = radius * math.tan(abs(turn) / 2)  # tangent length
    if t >= np.linalg.norm(v - a) or t >= np.linalg.norm(b - v):
        raise OutlineError(
            f"fillet radius {radius:g} m at {_pt(points[vertex])} does not fit: it needs "
            f"{t:.4g} m of each adjoining segment"
        )
    p1, p2 = v - t * d_in, v + t * d_out
    new_pts = list(points[:vertex]) + [tuple(p1), tuple(p2)] + list(points[vertex + 1 :])
    new_b = list(bulges[:vertex]) + [math.tan(turn / 4), 0.0] + list(bulges[vertex + 1 :])
    return [(float(x), float(y)) for x, y in new_pts], new_b


def _number(value: Any, what: str, source: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise OutlineError(f"{source}: {what} must be a number, got {value!r}")
    return float(value)


def _pair(value: Any, what: str, source: str) -> tuple[float, float]:
    if not (isinstance(value, list | tuple) and len(value) == 2):
        raise OutlineError(f"{source}: {what} must be a pair [r, z] in m, got {value!r}")
    return _number(value[0], what, source), _number(value[1], what, source)


def _bulge_from_centre(p, q, centre, i: int, source: str) -> float:
    p, q, c = (np.asarray(x, float) for x in (p, q, centre))
    rp, rq = np.linalg.norm(p - c), np.linalg.norm(q - c)
    if abs(rp - rq) > 1e-6 * max(rp, rq):
        raise OutlineError(
            f"{source}: arc on segment {i}: its end points are {rp:.6g} m and {rq:.6g} m from the "
            "centre; an arc's centre is equally far from both"
        )
    a, b = p - c, q - c
    theta = math.atan2(a[0] * b[1] - a[1] * b[0], float(a @ b))  # the shorter way round
    return math.tan(theta / 4)


def _read_csv(path: Path, source: str) -> tuple[list[tuple[float, float]], list[float]]:
    try:
        text = read_text(path, "profile file", OutlineError)
    except OutlineError as exc:
        raise OutlineError(f"{source}: {exc}") from None
    rows = [row for row in csv.reader(text.splitlines()) if row and not row[0].lstrip().startswith("#")]
    header = [c.strip() for c in rows[0]] if rows else []
    if header not in (["r", "z"], ["r", "z", "bulge"]):
        raise OutlineError(
            f"{path}: the first line must be the header r,z or r,z,bulge (metres), got {','.join(header)!r}"
        )
    pts, bulges = [], []
    for n, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise OutlineError(f"{path}, line {n}: {len(row)} values for {len(header)} columns")
        try:
            values = [float(c) for c in row]
        except ValueError:
            raise OutlineError(f"{path}, line {n}: not a number in {row}") from None
        pts.append((values[0], values[1]))
        bulges.append(values[2] if len(values) > 2 else 0.0)
    return pts, bulges


def outline_from_mapping(data: Any, source: str = "design", base: Path | None = None) -> Outline:
    """An outline from the ``[profile]`` table of a design file.

    Keys: ``points`` (list of [r, z] in m, a closed loop: the last point repeats the
    first) or ``file`` (a CSV file next to the design, header ``r,z`` or ``r,z,bulge``,
    the bulge of a row being that of the segment it starts; the last row repeats the
    first); ``bulges`` (one per segment, default 0) and/or
    ``arcs`` (a list of tables ``{segment = i, centre = [r, z]}``: the shorter arc about
    that centre); ``contact`` ([r, z], a point of the tread); ``clamp`` (segment
    indices; default the segments at the smallest radius). The outline is shifted
    axially so that the contact point lies at z = 0.
    """
    if not isinstance(data, dict):
        raise OutlineError(f"{source}: [profile] must be a table")
    allowed = {"points", "file", "bulges", "arcs", "contact", "clamp"}
    for key in data:
        if key not in allowed:
            raise OutlineError(
                f"{source}: unknown key '{key}' in [profile]; allowed: " + ", ".join(sorted(allowed))
            )
    if ("points" in data) == ("file" in data):
        raise OutlineError(f'{source}: [profile] needs either points = [[r, z], ...] or file = "NAME.csv"')
    if "points" in data:
        raw = data["points"]
        if not isinstance(raw, list):
            raise OutlineError(f"{source}: [profile] points must be a list of [r, z] pairs")
        pts = [_pair(p, f"point {i}", source) for i, p in enumerate(raw)]
        bulges = [0.0] * len(pts)
    else:
        if not isinstance(data["file"], str):
            raise OutlineError(f"{source}: [profile] file must be a file name")
        path = Path(data["file"])
        if base is not None and not path.is_absolute():
            path = base / path
        pts, bulges = _read_csv(path, source)
    pts, bulges = _closed(pts, bulges, source)
    if "bulges" in data:
        raw = data["bulges"]
        if not isinstance(raw, list) or len(raw) != len(pts):
            raise OutlineError(
                f"{source}: [profile] bulges must be a list of {len(pts)} numbers (one per segment)"
            )
        bulges = [_number(b, f"bulge {i}", source) for i, b in enumerate(raw)]
    arcs = data.get("arcs", [])
    if not isinstance(arcs, list):
        raise OutlineError(
            f"{source}: [profile] arcs is a list of {{segment = i, centre = [r, z]}}, got {arcs!r}"
        )
    for arc in arcs:
        if not (isinstance(arc, dict) and set(arc) == {"segment", "centre"}):
            raise OutlineError(f"{source}: each [profile] arcs entry is {{segment = i, centre = [r, z]}}")
        i = arc["segment"]
        if isinstance(i, bool) or not isinstance(i, int) or not 0 <= i < len(pts):
            raise OutlineError(f"{source}: arcs: segment {i!r} does not exist (0 to {len(pts) - 1})")
        centre = _pair(arc["centre"], f"the centre of arc {i}", source)
        bulges[i] = _bulge_from_centre(pts[i], pts[(i + 1) % len(pts)], centre, i, source)
    if "contact" not in data:
        raise OutlineError(f"{source}: [profile] needs contact = [r, z], the contact point on the tread")
    rc, zc = _pair(data["contact"], "contact", source)
    if "clamp" in data:
        raw = data["clamp"]
        if not isinstance(raw, list) or not all(isinstance(i, int) and not isinstance(i, bool) for i in raw):
            raise OutlineError(f"{source}: [profile] clamp must be a list of segment indices")
        clamp = tuple(raw)
    else:
        clamp = _bore_segments(pts, bulges)
    pts, bulges, clamp = _merge_collinear(pts, bulges, clamp)
    shifted = tuple((r, z - zc) for r, z in pts)
    try:
        return Outline(shifted, tuple(bulges), clamp, (rc, 0.0))
    except OutlineError as exc:
        raise OutlineError(f"{source}: {exc}") from None


def _closed(
    pts: list[tuple[float, float]], bulges: list[float], source: str
) -> tuple[list[tuple[float, float]], list[float]]:
    """The loop without its closing point (which must repeat the first point)."""
    if len(pts) < 2:
        raise OutlineError(f"{source}: [profile] needs a closed loop of points, got {len(pts)}")
    first, last = pts[0], pts[-1]
    tol = ON_BOUNDARY_REL * max(max(abs(r), abs(z)) for r, z in pts)
    if math.dist(first, last) > tol:
        raise OutlineError(
            f"{source}: the outline is open: its last point {_pt(last)} is not its first {_pt(first)}; "
            "repeat the first point at the end to close the loop"
        )
    return pts[:-1], bulges[:-1]


#: Two consecutive straight segments run on as one when their directions differ by
#: less than this (radians): a face a CAD export split into many pieces.
COLLINEAR_RAD = 1e-9


def _merge_collinear(
    pts: list[tuple[float, float]], bulges: list[float], clamp: tuple[int, ...]
) -> tuple[list[tuple[float, float]], list[float], tuple[int, ...]]:
    """The loop with every run of consecutive straight, collinear segments (same
    direction within :data:`COLLINEAR_RAD`) as one segment, and the clamp's indices
    renumbered (a run is never half clamped: its clamped and free parts stay apart)."""
    k = len(pts)
    if k < 4:
        return pts, bulges, clamp
    p = np.asarray(pts, float)
    d = np.roll(p, -1, axis=0) - p  # segment i runs from vertex i to i + 1
    unit = d / np.maximum(np.hypot(*d.T), 1e-300)[:, None]
    prev = np.roll(unit, 1, axis=0)  # the segment ending at vertex i
    straight = np.asarray(bulges) == 0.0
    clamped = np.zeros(k, dtype=bool)
    clamped[[i for i in clamp if isinstance(i, int) and 0 <= i < k]] = True
    cross = unit[:, 0] * prev[:, 1] - unit[:, 1] * prev[:, 0]
    removable = (
        straight
        & np.roll(straight, 1)
        & (clamped == np.roll(clamped, 1))
        & (np.abs(cross) < COLLINEAR_RAD)
        & (np.einsum("ij,ij->i", unit, prev) > 0)
    )
    if not removable.any() or removable.all():
        return pts, bulges, clamp
    kept = np.flatnonzero(~removable)
    new_index = np.cumsum(~removable) - 1  # the merged segment each original one joins
    new_index[: kept[0]] = len(kept) - 1  # the run wrapping past vertex 0
    merged_clamp = tuple(sorted({int(new_index[i]) for i in clamp if isinstance(i, int) and 0 <= i < k}))
    bad = tuple(i for i in clamp if not (isinstance(i, int) and 0 <= i < k))
    return [pts[i] for i in kept], [bulges[i] for i in kept], merged_clamp + bad


def _bore_segments(pts: list[tuple[float, float]], bulges: list[float]) -> tuple[int, ...]:
    """The straight segments at the smallest radius (the default clamp)."""
    if not pts:
        return ()
    r_min = min(r for r, _ in pts)
    tol = ON_BOUNDARY_REL * max(abs(r) for r, _ in pts)
    k = len(pts)
    return tuple(
        i
        for i in range(k)
        if bulges[i] == 0.0 and abs(pts[i][0] - r_min) <= tol and abs(pts[(i + 1) % k][0] - r_min) <= tol
    )
