"""Wheel and rail cross-section profiles: the S1002 wheel (EN 13715), the UIC60 (60E1) rail
head (EN 13674-1), a cone for checks, and any profile given as points.

Both are curves in a plane through the axle, lengths in m:

- a wheel profile gives, for the lateral coordinate ``s`` from the taping line (positive
  toward the field side, negative toward the flange), the increase of the wheel's radius
  over its taping-line radius, ``rise(s)`` (the flange tip of S1002 rises 28 mm);
- a rail profile gives, for the lateral coordinate ``v`` from the rail head's centre line
  (positive toward the field side), the head's height ``z(v)`` below its crown (0 at the
  crown, negative below), before the rail is inclined.

S1002 is the standard's piecewise definition: a 1:15 cone, two polynomials, a circular
flange root, the 70 deg straight flank and three circular arcs to the flange back (UIC
510-2 Annex C, EN 13715). UIC60 E1's head is three tangent arcs of 300, 80 and 13 mm
radius and a 1:20 flank (EN 13674-1); the arcs' ends below follow from their tangency,
the head 72 mm wide at the flank.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from geometry.outline import Outline

__all__ = [
    "STANDARD_WHEELS",
    "Profile",
    "cone_wheel",
    "profile_from_points",
    "running_surface",
    "s1002",
    "standard_wheel",
    "uic60",
]

#: Points a built-in profile is sampled at (0.05 mm apart on S1002's 130 mm)
SAMPLES = 2601


@dataclass(frozen=True, eq=False)
class Profile:
    """A profile as a curve ``height(lateral)`` sampled at increasing lateral points [m].

    Attributes
    ----------
    name : str
    lateral_m, height_m : ndarray
        For a wheel: ``s`` and the radius' rise over the taping line; for a rail: ``v`` and
        the head's height (module docstring).

    Examples
    --------
    >>> p = s1002()
    >>> p.name, len(p.lateral_m) == len(p.height_m)
    ('S1002', True)
    """

    name: str
    lateral_m: np.ndarray
    height_m: np.ndarray

    def __post_init__(self) -> None:
        y, z = np.asarray(self.lateral_m, float), np.asarray(self.height_m, float)
        if y.ndim != 1 or y.shape != z.shape or y.size < 5:
            raise ValueError(f"profile {self.name!r}: at least 5 (lateral, height) points")
        if not (np.all(np.isfinite(y)) and np.all(np.isfinite(z))):
            raise ValueError(f"profile {self.name!r}: every point must be finite")
        if np.any(np.diff(y) <= 0):
            raise ValueError(f"profile {self.name!r}: the lateral coordinates must increase")
        object.__setattr__(self, "lateral_m", y)
        object.__setattr__(self, "height_m", z)

    def __repr__(self) -> str:
        lo, hi = 1e3 * self.lateral_m[0], 1e3 * self.lateral_m[-1]
        return f"Profile({self.name!r}, {self.lateral_m.size} points, {lo:.1f} to {hi:.1f} mm)"

    def at(self, lateral_m: np.ndarray) -> np.ndarray:
        """The height at ``lateral_m`` (linear between the points; nan outside)."""
        return np.interp(lateral_m, self.lateral_m, self.height_m, left=np.nan, right=np.nan)

    def slope(self) -> np.ndarray:
        """d height / d lateral at the points (second-order differences)."""
        return np.gradient(self.height_m, self.lateral_m)

    def curvature_1_m(self) -> np.ndarray:
        """The curve's signed curvature h'' / (1 + h'^2)^(3/2) at the points [1/m]."""
        d1 = self.slope()
        d2 = np.gradient(d1, self.lateral_m)
        return d2 / (1.0 + d1 * d1) ** 1.5


def profile_from_points(name: str, lateral_m: np.ndarray, height_m: np.ndarray) -> Profile:
    """A profile from measured or drawn points, resampled at :data:`SAMPLES` even points
    (points in any order along the lateral coordinate; duplicates refused).

    Parameters
    ----------
    name : str
        The profile's name.
    lateral_m, height_m : numpy.ndarray
        The points' lateral coordinate and height [m].

    Returns
    -------
    Profile
        The profile on its even grid.

    Examples
    --------
    >>> p = profile_from_points("flat", np.array([-0.05, 0.05]), np.array([0.0, 0.0]))
    >>> float(p.height_m.max())
    0.0"""
    y, z = np.asarray(lateral_m, float), np.asarray(height_m, float)
    order = np.argsort(y)
    y, z = y[order], z[order]
    if np.any(np.diff(y) <= 0):
        raise ValueError(f"profile {name!r}: two points at the same lateral coordinate")
    even = np.linspace(y[0], y[-1], SAMPLES)
    return Profile(name, even, np.interp(even, y, z))


# S1002 (UIC 510-2 Annex C; EN 13715): s in mm from the taping line (positive to the field
# side), F(s) in mm the rise of the radius. The standard's sections and coefficients.
_S1002_BOUNDS_MM = (
    -70.0,
    -62.764705882,
    -49.662510381,
    -39.764473993,
    -38.426669071,
    -35.0,
    -26.0,
    32.15796,
    60.0,
)
_S1002_B = (
    0.0,
    -3.358537058e-02,
    1.565681624e-03,
    -2.810427944e-05,
    5.844240864e-08,
    -1.562379023e-08,
    5.309217349e-15,
    -5.957839843e-12,
    2.646656573e-13,
)
_S1002_C = (
    -4.320221063e03,
    -1.038384026e03,
    -1.065501873e02,
    -6.051367875,
    -2.054332446e-01,
    -4.169739389e-03,
    -4.687195829e-05,
    -2.252755540e-07,
)


def _circle(s: np.ndarray, base: float, radius: float, shift: float, sign: float) -> np.ndarray:
    return base + sign * np.sqrt(np.maximum(radius**2 - (s + shift) ** 2, 0.0))


def _s1002_rise_mm(s: np.ndarray) -> np.ndarray:
    b = _S1002_BOUNDS_MM
    sections = [
        _circle(s, 9.519259302, 20.5, 49.5, 1.0),  # H: the flange back
        _circle(s, 16.0, 12.0, 55.0, 1.0),  # G: the flange tip
        _circle(s, 8.834924130, 20.0, 58.558326413, 1.0),  # F
        -93.576667419 - 2.747477419 * s,  # E: the flank, 70 deg
        _circle(s, 16.446, 13.0, 26.210665, -1.0),  # D: the flange root
        np.polynomial.polynomial.polyval(s, _S1002_C),  # C
        np.polynomial.polynomial.polyval(s, _S1002_B),  # B: the tread
        1.364323640 - 0.066666667 * s,  # A: the 1:15 field-side cone
    ]
    where = [(b[i] <= s) & (s <= b[i + 1]) for i in range(8)]
    return np.select(where, sections, default=np.nan)


def s1002(samples: int = SAMPLES) -> Profile:
    """The S1002 wheel profile (EN 13715), from the flange back (-70 mm) to 60 mm.

    Parameters
    ----------
    samples : int
        The profile's points.

    Returns
    -------
    Profile
        Height [m] over the lateral coordinate [m].

    Examples
    --------
    >>> p = s1002()
    >>> round(1e3 * float(p.height_m.max()), 2)  # the flange, 28 mm above the taping line
    28.0
    >>> round(math.degrees(math.atan(float(-p.slope()[np.searchsorted(p.lateral_m, -0.039)]))), 1)
    70.0
    """
    s_mm = np.linspace(_S1002_BOUNDS_MM[0], _S1002_BOUNDS_MM[-1], samples)
    return Profile("S1002", 1e-3 * s_mm, 1e-3 * _s1002_rise_mm(s_mm))


#: The standard wheel profiles a design's contact may take, by name
_STANDARD_WHEEL_PROFILES = {"S1002": s1002}
STANDARD_WHEELS = tuple(_STANDARD_WHEEL_PROFILES)


def standard_wheel(name: str) -> Profile:
    """The standard wheel profile called ``name`` (one of :data:`STANDARD_WHEELS`).

    Parameters
    ----------
    name : str
        The profile's name.

    Returns
    -------
    Profile
        Height [m] over the lateral coordinate [m].

    Examples
    --------
    >>> standard_wheel("S1002").name
    'S1002'
    """
    if name not in _STANDARD_WHEEL_PROFILES:
        raise ValueError(f"wheel profile {name!r}: one of {', '.join(STANDARD_WHEELS)}")
    return _STANDARD_WHEEL_PROFILES[name]()


#: UIC60 E1's head (EN 13674-1): arc radii [m] from the crown outwards, the lateral
#: coordinates [m] where the 300 and 80 mm arcs end, and the flank's slope (1:20)
UIC60_RADII_M = (0.300, 0.080, 0.013)
UIC60_ARC_ENDS_M = (0.010228, 0.026027)
UIC60_FLANK_SLOPE = 1.0 / 20.0


def _arc_heads(
    radii: tuple[float, float, float], ends: tuple[float, float]
) -> list[tuple[float, float, float]]:
    """Each arc's (centre lateral, centre height, radius), each tangent to the one before."""
    centres = [(0.0, -radii[0], radii[0])]
    for end, r_next in zip(ends, radii[1:]):
        cy, cz, r = centres[-1]
        sin_t = (end - cy) / r
        cos_t = math.sqrt(1.0 - sin_t * sin_t)
        centres.append((cy + (r - r_next) * sin_t, cz + (r - r_next) * cos_t, r_next))
    return centres


def uic60(samples: int = SAMPLES, depth_m: float = 0.03) -> Profile:
    """The UIC60 (60E1) rail head (EN 13674-1), symmetric, from its crown down ``depth_m``
    on the flanks.

    Parameters
    ----------
    samples : int
        The profile's points.
    depth_m : float
        How far down the flanks it reaches [m].

    Returns
    -------
    Profile
        Height [m] over the lateral coordinate [m].

    Examples
    --------
    >>> p = uic60()
    >>> round(2e3 * float(p.lateral_m[-1]), 1)  # the head's width at 30 mm depth [mm]
    73.6
    """
    arcs = _arc_heads(UIC60_RADII_M, UIC60_ARC_ENDS_M)
    cy, cz, r = arcs[-1]
    flank = math.atan(UIC60_FLANK_SLOPE)  # the flank's angle from the vertical
    flank_v, flank_z = cy + r * math.cos(flank), cz + r * math.sin(flank)
    ends = (*UIC60_ARC_ENDS_M, flank_v)
    bottom_v = flank_v + (depth_m + flank_z) * UIC60_FLANK_SLOPE
    v = np.linspace(0.0, bottom_v, samples // 2 + 1)
    z = flank_z - (v - flank_v) / UIC60_FLANK_SLOPE
    start = 0.0
    for (ay, az, ar), end in zip(arcs, ends):
        on = (v >= start) & (v <= end)
        z[on] = az + np.sqrt(np.maximum(ar * ar - (v[on] - ay) ** 2, 0.0))
        start = end
    both_v = np.concatenate([-v[:0:-1], v])
    both_z = np.concatenate([z[:0:-1], z])
    return Profile("UIC60", both_v, both_z)


def cone_wheel(half_angle_rad: float, half_width_m: float = 0.06, samples: int = SAMPLES) -> Profile:
    """A cone of ``half_angle_rad`` (its radius falling toward the field side) without a
    flange: the closed forms' check (rolling radius r0 - s tan(lambda), contact angle
    lambda).

    Parameters
    ----------
    half_angle_rad : float
        lambda, the cone's angle [rad].
    half_width_m : float
        How far it reaches each side of the taping line [m].
    samples : int
        Its points.

    Returns
    -------
    Profile
        Its height [m] over the lateral coordinate [m].

    Examples
    --------
    >>> p = cone_wheel(0.05)
    >>> round(float(-p.slope()[0]), 4)  # tan(lambda)
    0.05"""
    s = np.linspace(-half_width_m, half_width_m, samples)
    return Profile(f"cone {half_angle_rad:g} rad", s, -s * math.tan(half_angle_rad))


#: A wheel's running surface is read across the rim this far below the taping line's radius
#: [m]: deeper than a flange's back reaches above its rim, shallower than the web
RIM_DEPTH_M = 0.02
#: The running surface stops this far inside the rim's faces [m] (a face has no single height)
FACE_INSET_M = 1.0e-4


def running_surface(outline: Outline, rolling_radius_m: float, samples: int = SAMPLES) -> Profile:
    """A wheel profile from a design's outline: its largest radius across the rim
    (``Outline.outer_radius``) over the taping line's, with z (the outline's axial
    coordinate, 0 at the taping line, the flange toward -z) as the lateral coordinate s.

    Parameters
    ----------
    outline : geometry.outline.Outline
        The wheel's outline.
    rolling_radius_m : float
        The radius at the taping line [m].
    samples : int
        The profile's points.

    Returns
    -------
    Profile
        Height [m] over the lateral coordinate [m].

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> p = running_surface(ws.load_design("railway_920_track").wheel.profile, 0.46)
    >>> round(1e3 * float(p.height_m.max()), 1)  # the flange's height [mm]
    28.0
    """
    low, high = outline.axial_extent(rolling_radius_m - RIM_DEPTH_M)
    s = np.linspace(low + FACE_INSET_M, high - FACE_INSET_M, samples)
    return Profile("running surface", s, outline.outer_radius(s) - rolling_radius_m)
