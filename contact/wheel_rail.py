"""Where a wheelset's wheels touch their rails: the contact points, rolling radii, contact
angles and curvatures of a rigid wheelset on two inclined rails, for each lateral shift.

The wheelset is rigid: both wheels (the same profile, mirrored) on one axle, their taping
lines ``flange_back_m / 2 + 70 mm`` from its centre (the S1002 taping line is 70 mm from
the flange back). Each rail is the rail profile turned toward the track's centre by the
inclination (1:40 or 1:20) and placed so that the gauge, measured ``GAUGE_DEPTH_M`` below
the rails' crowns between their gauge faces, is ``gauge_m``. For a lateral shift y of the
wheelset (positive toward the outer rail, the one the side names ``outer``), the wheelset
settles with a roll angle at which both wheels touch: on each side the smallest vertical gap
between the rotated wheel and the rail is zero. Each local minimum of the gap within
``touch_m`` of zero and at least ``SEPARATE_M`` from the first is a further contact point:
tread and flange together is the two-point contact of a flanging wheel.

At each contact: the rolling radius r (the taping-line radius plus the profile's rise), the
contact angle gamma (the contact plane's tilt; positive when the rail's normal force pushes
the wheel toward the track's centre: the tread's few degrees and the flange's 60-70 deg), and
the transverse curvatures of the wheel and the rail (positive when convex) from which the
Hertz ellipse follows. The equivalent conicity is the harmonic linearisation of the rolling
radius difference (EN 15302): lambda_e(A) = (1 / (pi A)) int_0^2pi dr(A sin t) / 2 sin t dt.
For a cone of half-angle lambda: r = r0 -+ lambda y, gamma = lambda and lambda_e = lambda.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import Literal

import numpy as np
from scipy.optimize import brentq

from geometry.outline import MAX_CONTACT_ANGLE_DEG

from .profiles import Profile, s1002, uic60

__all__ = [
    "SHIFT_STEP_M",
    "ContactGeometry",
    "ContactPoint",
    "WheelsetPosition",
    "is_flange_angle",
]

Side = Literal["outer", "inner"]

#: The gauge is measured this far below the rails' crowns [m] (EN 13848-1)
GAUGE_DEPTH_M = 0.014
#: The taping line's distance from the flange back [m] (EN 13715)
TAPING_LINE_FROM_FLANGE_BACK_M = 0.070
#: A gap this small counts as touching [m]: about the Hertz approach of a wheel's load
TOUCH_M = 1.0e-4
#: Two contact points of one wheel lie at least this far apart across it [m]
SEPARATE_M = 0.005
#: The smallest relative transverse curvature of a contact [1/m]: a conformal contact (a
#: worn wheel's flange root on the rail's gauge corner) is a long ellipse, not an infinite one
CONFORMAL_CURVATURE_1_M = 1.0e-3
#: The step of :attr:`ContactGeometry.tabulated`'s shifts [m]
SHIFT_STEP_M = 5.0e-5
#: The largest roll of a wheelset the settling searches [rad]
MAX_ROLL_RAD = 0.05


def is_flange_angle(contact_angle_rad: float) -> bool:
    """Whether a contact at this angle [rad] is on the flange: steeper than
    :data:`MAX_CONTACT_ANGLE_DEG`, the tread's regime.

    Parameters
    ----------
    contact_angle_rad : float
        The contact angle [rad].

    Returns
    -------
    bool
        True on the flange.

    Examples
    --------
    >>> is_flange_angle(math.radians(70.0)), is_flange_angle(0.0)
    (True, False)"""
    return abs(contact_angle_rad) > math.radians(MAX_CONTACT_ANGLE_DEG)


def _vertex_offset(g: np.ndarray, i: int) -> float:
    """Where between samples i - 1 and i + 1 the parabola through them is lowest (-0.5 to 0.5)."""
    if i == 0 or i == g.size - 1 or not np.all(np.isfinite(g[i - 1 : i + 2])):
        return 0.0
    curvature = g[i - 1] - 2.0 * g[i] + g[i + 1]
    return float(np.clip(0.5 * (g[i - 1] - g[i + 1]) / curvature, -0.5, 0.5)) if curvature > 0 else 0.0


@dataclass(frozen=True)
class ContactPoint:
    """One contact of one wheel with its rail.

    Attributes
    ----------
    wheel_lateral_m : float
        Where on the wheel (s from the taping line, positive toward the field side) [m].
    lateral_position_m : float
        Its distance from the track's centre line [m].
    rolling_radius_m : float
    contact_angle_rad : float
        The contact plane's tilt (module docstring).
    wheel_curvature_1_m, rail_curvature_1_m : float
        Transverse curvatures at the contact, positive when convex [1/m].
    gap_m : float
        0 for the first contact, at most ``touch_m`` for a further one.

    Examples
    --------
    >>> c = ContactGeometry().position(0.0).outer[0]
    >>> c.on_flange, c.gap_m
    (False, 0.0)
    """

    wheel_lateral_m: float
    lateral_position_m: float
    rolling_radius_m: float
    contact_angle_rad: float
    wheel_curvature_1_m: float
    rail_curvature_1_m: float
    gap_m: float = 0.0

    @property
    def on_flange(self) -> bool:
        return is_flange_angle(self.contact_angle_rad)

    @property
    def relative_transverse_radius_m(self) -> float:
        """1 / (wheel's + rail's transverse curvature) [m]: the Hertz ellipse's relative
        radius across rolling (a conformal contact's a long, finite one)."""
        return 1.0 / max(self.wheel_curvature_1_m + self.rail_curvature_1_m, CONFORMAL_CURVATURE_1_M)


@dataclass(frozen=True)
class WheelsetPosition:
    """The wheelset at one lateral shift: its roll and each wheel's contacts, the first of
    each side the lowest (on the tread unless the flange alone carries).

    Attributes
    ----------
    lateral_shift_m : float
        The wheelset's lateral shift [m].
    roll_rad : float
        Its roll [rad].
    outer, inner : tuple of ContactPoint
        Each wheel's contacts.

    Examples
    --------
    >>> p = ContactGeometry().position(0.0)
    >>> len(p.outer) >= 1 and len(p.inner) >= 1
    True"""

    lateral_shift_m: float
    roll_rad: float
    outer: tuple[ContactPoint, ...]
    inner: tuple[ContactPoint, ...]

    @property
    def rolling_radius_difference_m(self) -> float:
        """r_outer - r_inner at the tread contacts [m]."""
        return self.outer[0].rolling_radius_m - self.inner[0].rolling_radius_m

    def side(self, side: Side) -> tuple[ContactPoint, ...]:
        return self.outer if side == "outer" else self.inner


@dataclass(frozen=True, eq=False)
class ContactGeometry:
    """A wheel profile on a rail profile (module docstring).

    Attributes
    ----------
    wheel, rail : Profile
        The wheel's and the rail's profiles.
    rolling_radius_m : float
        The wheel's radius at its taping line [m].
    inclination : float
        The rail's inclination, dimensionless (1:40).
    gauge_m, flange_back_m : float
        The track's gauge and the wheelset's back-to-back spacing [m].
    touch_m : float
        The gap within which a second point counts as touching [m].

    Examples
    --------
    >>> g = ContactGeometry()
    >>> p = g.position(0.0)
    >>> round(1e3 * p.outer[0].wheel_lateral_m, 1), round(math.degrees(p.outer[0].contact_angle_rad), 2)
    (3.1, 1.41)
    """

    wheel: Profile = field(default_factory=s1002)
    rail: Profile = field(default_factory=uic60)
    rolling_radius_m: float = 0.46
    inclination: float = 1.0 / 40.0
    gauge_m: float = 1.435
    flange_back_m: float = 1.360
    touch_m: float = TOUCH_M
    _rail_u: np.ndarray = field(init=False, repr=False)
    _rail_z: np.ndarray = field(init=False, repr=False)
    _rail_kappa: np.ndarray = field(init=False, repr=False)
    _wheel_kappa: np.ndarray = field(init=False, repr=False)
    _wheel_slope: np.ndarray = field(init=False, repr=False)
    _index: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if not 0.0 <= self.inclination <= 0.1:
            raise ValueError(f"rail inclination {self.inclination!r}: 0 to 1:10 (1:40 or 1:20 in service)")
        if not 1.3 <= self.flange_back_m < self.gauge_m <= 1.8:
            raise ValueError(
                f"gauge {self.gauge_m!r} m and flange-back spacing {self.flange_back_m!r} m: "
                "standard gauge is 1.435 m with 1.360 m between the flange backs"
            )
        if not 0.2 <= self.rolling_radius_m <= 0.8:
            raise ValueError(f"rolling radius {self.rolling_radius_m!r} m: a railway wheel's is 0.2-0.8 m")
        u, z = self._rail_curve()
        object.__setattr__(self, "_rail_u", u)
        object.__setattr__(self, "_rail_z", z)
        object.__setattr__(self, "_rail_kappa", -Profile("rail", u, z).curvature_1_m())
        object.__setattr__(self, "_wheel_kappa", -self.wheel.curvature_1_m())
        object.__setattr__(self, "_wheel_slope", self.wheel.slope())
        object.__setattr__(self, "_index", np.arange(self.wheel.lateral_m.size, dtype=float))

    @property
    def taping_line_m(self) -> float:
        """The taping line's distance from the wheelset's centre [m]."""
        return 0.5 * self.flange_back_m + TAPING_LINE_FROM_FLANGE_BACK_M

    def _rail_curve(self) -> tuple[np.ndarray, np.ndarray]:
        """The inclined rail head as height over the distance from the track centre."""
        d = math.atan(self.inclination)
        v, z = self.rail.lateral_m, self.rail.height_m
        u = v * math.cos(d) - z * math.sin(d)
        zz = v * math.sin(d) + z * math.cos(d)
        zz = zz - zz.max()
        gauge_face = np.flatnonzero((u < u[np.argmax(zz)]) & (zz >= -GAUGE_DEPTH_M))[0]
        u = u + 0.5 * self.gauge_m - u[gauge_face]
        keep = np.concatenate([[True], np.diff(u) > 0])  # a vertical flank stays single-valued
        return u[keep], zz[keep]

    def _gaps(self, shift_m: float, roll_rad: float, sign: int) -> np.ndarray:
        """Vertical gaps between one wheel (sign +1 outer, -1 inner) and its rail, at the
        wheel's profile points, with the axle's centre at height 0."""
        s = self.wheel.lateral_m
        y_w = sign * (self.taping_line_m + s)
        z_w = -(self.rolling_radius_m + self.wheel.height_m)
        c, sn = math.cos(roll_rad), math.sin(roll_rad)
        y = shift_m + y_w * c - z_w * sn
        z = y_w * sn + z_w * c
        rail = np.interp(sign * y, self._rail_u, self._rail_z, left=np.nan, right=np.nan)
        return np.where(np.isnan(rail), np.inf, z - rail)

    def _roll(self, shift_m: float) -> float:
        def unequal(phi: float) -> float:
            return float(self._gaps(shift_m, phi, 1).min() - self._gaps(shift_m, phi, -1).min())

        return float(brentq(unequal, -MAX_ROLL_RAD, MAX_ROLL_RAD, xtol=1e-12))

    def position(self, shift_m: float) -> WheelsetPosition:
        """The wheelset at lateral shift ``shift_m`` [m] (module docstring)."""
        phi = self._roll(float(shift_m))
        sides = []
        for sign in (1, -1):
            gaps = self._gaps(float(shift_m), phi, sign)
            sides.append(self._contacts(gaps, float(shift_m), phi, sign))
        return WheelsetPosition(float(shift_m), phi, sides[0], sides[1])

    def _contacts(
        self, gaps: np.ndarray, shift_m: float, roll_rad: float, sign: int
    ) -> tuple[ContactPoint, ...]:
        g = gaps - gaps.min()
        inner = (g[1:-1] <= g[:-2]) & (g[1:-1] <= g[2:])
        minima = np.flatnonzero(inner) + 1
        minima = minima[g[minima] <= self.touch_m]
        order = minima[np.argsort(g[minima])]
        s = self.wheel.lateral_m
        chosen = [int(np.argmin(g))]
        first_on_flange = self._steep(chosen[0], roll_rad, sign)
        for i in order:  # the other region's lowest: the tread beside a flange, or the flange
            if (
                self._steep(int(i), roll_rad, sign) != first_on_flange
                and abs(s[i] - s[chosen[0]]) >= SEPARATE_M
            ):
                chosen.append(int(i))
                break
        points = []
        for i in chosen:
            at = i + _vertex_offset(g, i)  # the gap's minimum between the samples
            si = float(np.interp(at, self._index, s))
            u = sign * (shift_m + sign * (self.taping_line_m + si) * math.cos(roll_rad))
            gamma = math.atan(-float(np.interp(at, self._index, self._wheel_slope))) + sign * roll_rad
            points.append(
                ContactPoint(
                    wheel_lateral_m=si,
                    lateral_position_m=float(u),
                    rolling_radius_m=float(
                        self.rolling_radius_m + np.interp(at, self._index, self.wheel.height_m)
                    ),
                    contact_angle_rad=float(gamma),
                    wheel_curvature_1_m=float(np.interp(at, self._index, self._wheel_kappa)),
                    rail_curvature_1_m=float(np.interp(u, self._rail_u, self._rail_kappa)),
                    gap_m=float(g[i]),
                )
            )
        return tuple(points)

    def _steep(self, i: int, roll_rad: float, sign: int) -> bool:
        gamma = math.atan(-self._wheel_slope[i]) + sign * roll_rad
        return abs(gamma) > math.radians(MAX_CONTACT_ANGLE_DEG)

    def flange_clearance_m(self) -> float:
        """The lateral shift at which the outer wheel's flange first touches [m] (where the
        wheelset, pushed further, would climb its flange)."""

        def flanged(y: float) -> bool:
            return any(c.on_flange for c in self.position(y).outer)

        steps = np.arange(1, 81) * 2.5e-4
        touching = [y for y in steps if flanged(float(y))]
        if not touching:
            raise ValueError("the flange does not touch within 20 mm of shift: check the gauge and profiles")
        hi = float(touching[0])
        lo = hi - 2.5e-4
        for _ in range(30):
            mid = 0.5 * (lo + hi)
            lo, hi = (lo, mid) if flanged(mid) else (mid, hi)
        return hi

    def flank_reach_m(self) -> float:
        """The shift at which the outer contact is steepest on the flank [m]: beyond it the
        wheel climbs its flange."""
        shifts = self.flange_clearance_m() + np.arange(0, 41) * SHIFT_STEP_M
        angles = [self.position(float(y)).outer[0].contact_angle_rad for y in shifts]
        return float(shifts[int(np.argmax(angles))])

    @cached_property
    def tabulated(self) -> tuple[WheelsetPosition, ...]:
        """The wheelset at every :data:`SHIFT_STEP_M` between the flanks' reaches (worked
        out once per geometry; what a curving solve interpolates)."""
        reach = self.flank_reach_m()
        return tuple(
            self.position(float(y)) for y in np.arange(-reach, reach + 0.5 * SHIFT_STEP_M, SHIFT_STEP_M)
        )

    def equivalent_conicity(self, amplitude_m: float, points: int = 64) -> float:
        """The equivalent conicity at ``amplitude_m`` (harmonic linearisation of the rolling
        radius difference, EN 15302; module docstring)."""
        t = (np.arange(points) + 0.5) * 2.0 * math.pi / points
        dr = np.array([self.position(amplitude_m * math.sin(x)).rolling_radius_difference_m for x in t])
        return float(np.sum(0.5 * dr * np.sin(t)) * (2.0 * math.pi / points) / (math.pi * amplitude_m))
