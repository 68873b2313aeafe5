"""Steady-state curving of a two-axle bogie on its primary suspension: each wheel's contact
position, contact angle, load, creepages and forces (quasi-static curving: Newland 1969,
Boocock 1969, Elkins & Gostling 1977; Iwnicki (ed.), Handbook of Railway Vehicle Dynamics,
2006, the chapter on curving).

The bogie runs at a constant speed V through a curve of radius R and cant h. Unknowns: each
wheelset's lateral shift y_i (positive toward the outer rail), angle of attack psi_i
(positive: its rolling direction points outward of the curve) and rolling speed (its wheels'
angular speed over V / r0), and the frame's lateral shift and yaw. The frame carries the
unbalanced lateral force m (V^2/R - g h/s) (m the mass on the bogie's wheels, s the rails'
spacing) and passes it to the wheelsets through the primary suspension: per wheelset a
lateral stiffness k_y and a yaw stiffness k_psi to the frame (the secondary suspension's yaw
is left out: the frame is free to yaw under the car body). The same acceleration moves load
to the outer wheels: dW = m_w (V^2/R - g h/s) h_cg / s for the mass m_w on a wheelset.

Each wheel touches its rail where :class:`track.contact_geometry.ContactGeometry` puts it
for the wheelset's shift: its rolling radius r, contact angle gamma and curvatures, hence its
Hertz ellipse under its normal force N and Kalker's coefficients. Its creepages, in the
contact plane:

- longitudinal xi_x = (1 + y_c / R) - (1 + e) r / r0 (y_c the contact's lateral position
  from the track centre, outward positive; e the wheelset's rolling-speed excess): the outer
  wheel runs a longer way round, the rolling radius difference makes up for it;
- lateral xi_y = -psi / cos(gamma) (the wheel slides inward under a positive angle of attack,
  the contact plane tilted by gamma);
- spin phi = sin(gamma) / r, its lateral force toward the wheel's field side.

The creep force follows Kalker's linear theory (G a b C11 xi_x, G a b C22 xi_y and
G (ab)^(3/2) C23 phi) saturated along its own direction by the project's creep polynomial:
|F| = mu N (z - z^2/3 + z^3/27) for z = |F_linear| / (mu N) < 3, mu N beyond (the adhesion
the longitudinal and lateral creepages share). Each wheelset balances its lateral forces,
its yaw moments and its longitudinal forces; the frame its lateral force and yaw moment.
The flange is the contact itself: past the flange root the contact climbs the flank to
60-70 deg and the normal force's lateral part holds the wheelset. Where the equilibrium
would need more than the flank gives, the wheelset would climb its flange: refused.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import least_squares

from reduced.contact import hertz_contact, kalker_coefficients

from .contact_geometry import SHIFT_STEP_M, ContactGeometry, ContactPoint
from .curving import GRAVITY_M_S2, RAIL_SPACING_M, WHEELS, Axle, Rail

__all__ = ["CurvingError", "Vehicle", "WheelContact", "steady_curving"]


#: The equilibrium is solved when every force is within this fraction of the wheel load
FORCE_TOLERANCE = 1.0e-4


class CurvingError(ValueError):
    """The bogie has no steady equilibrium in this curve (it would climb its flange)."""


@dataclass(frozen=True)
class Vehicle:
    """A two-axle bogie's running gear.

    Attributes
    ----------
    wheelbase_m : float
        2a [m].
    primary_yaw_stiffness_n_m_rad : float
        k_psi per wheelset [N m/rad] (2 k_x d^2 for longitudinal stiffness k_x at each axle
        box, d half their lateral spacing).
    primary_lateral_stiffness_n_m : float
        k_y per wheelset [N/m].
    centre_of_gravity_height_m : float
        h_cg of the mass on the wheels above the rail heads [m].
    """

    wheelbase_m: float = 2.5
    primary_yaw_stiffness_n_m_rad: float = 1.0e7
    primary_lateral_stiffness_n_m: float = 5.0e6
    centre_of_gravity_height_m: float = 1.5


@dataclass(frozen=True)
class WheelContact:
    """One wheel in a curve, at its own contact.

    Attributes
    ----------
    axle, rail : str
    lateral_shift_m : float
        The wheelset's, positive toward the outer rail [m].
    angle_of_attack_rad : float
    contact : ContactPoint
        Where it touches (the first of its contacts).
    flange_contact : bool
        Whether one of its contacts is on the flange.
    wheel_load_n : float
        The rail's vertical force on the wheel [N].
    normal_force_n : float
        The contact's normal force [N].
    lateral_force_n : float
        The rail's lateral force on the wheel, positive toward the curve's centre [N].
    longitudinal_force_n : float
    longitudinal_creepage, lateral_creepage : float
        In the contact plane [-].
    spin_creepage_1_m : float
    semi_axis_a_m, semi_axis_b_m : float
        The Hertz ellipse (rolling, across) [m].
    c22 : float
        Kalker's lateral coefficient of that ellipse.
    adhesion_used : float
        |creep force| / (mu N).
    load_share : float
        The share of the wheel load on this contact (below 1 in a two-point contact).
    """

    axle: Axle
    rail: Rail
    lateral_shift_m: float
    angle_of_attack_rad: float
    contact: ContactPoint
    flange_contact: bool
    wheel_load_n: float
    normal_force_n: float
    lateral_force_n: float
    longitudinal_force_n: float
    longitudinal_creepage: float
    lateral_creepage: float
    spin_creepage_1_m: float
    semi_axis_a_m: float
    semi_axis_b_m: float
    c22: float
    adhesion_used: float
    load_share: float = 1.0

    @property
    def contact_angle_rad(self) -> float:
        return self.contact.contact_angle_rad

    @property
    def longitudinal_force_share(self) -> float:
        """|F_x| / N: the adhesion the longitudinal creep force takes [-]."""
        return abs(self.longitudinal_force_n) / self.normal_force_n


@dataclass(frozen=True)
class _Table:
    shifts_m: np.ndarray
    contacts: tuple[tuple[ContactPoint, ...], ...]  # per shift: outer's, inner's first contacts
    flanged: tuple[tuple[bool, bool], ...]
    values: np.ndarray = field(repr=False)  # shift x side x (y_c, r, gamma, kappa_w, kappa_r)


def _table(geometry: ContactGeometry) -> _Table:
    positions = geometry.tabulated
    shifts = np.array([p.lateral_shift_m for p in positions])
    contacts = tuple((p.outer[0], p.inner[0]) for p in positions)
    flanged = tuple((any(c.on_flange for c in p.outer), any(c.on_flange for c in p.inner)) for p in positions)
    values = [
        [
            [
                c.lateral_position_m,
                c.rolling_radius_m,
                c.contact_angle_rad,
                c.wheel_curvature_1_m,
                c.rail_curvature_1_m,
            ]
            for c in pair
        ]
        for pair in contacts
    ]
    return _Table(shifts, contacts, flanged, np.array(values))


@dataclass(frozen=True)
class _Scene:
    geometry: ContactGeometry
    radius_m: float
    speed_m_s: float
    unbalanced_m_s2: float
    wheel_load_n: float
    friction_coefficient: float
    youngs_modulus_pa: float
    poissons_ratio: float


def _side_forces(
    scene: _Scene, row: np.ndarray, sign: int, vertical_n: float, psi: float, excess: float
) -> tuple[float, float, float, tuple[Any, ...]]:
    """One wheel's contact forces: (lateral global, longitudinal, yaw moment, details)."""
    y_c, r, gamma, k_w, k_r = row
    r0 = scene.geometry.rolling_radius_m
    xi_x = (1.0 + sign * y_c / scene.radius_m) - (1.0 + excess) * r / r0
    xi_y = -psi / math.cos(gamma)
    spin = math.sin(gamma) / r
    g_mod = scene.youngs_modulus_pa / (2.0 * (1.0 + scene.poissons_ratio))
    transverse = max(k_w + k_r, 1e-3)  # a conformal contact's ellipse: a long, finite one
    normal = vertical_n / math.cos(gamma)
    for _ in range(4):  # the creep force's vertical part changes the normal force
        h = hertz_contact(
            r / math.cos(gamma),
            1.0 / transverse,
            math.inf,
            math.inf,
            scene.youngs_modulus_pa,
            scene.poissons_ratio,
            max(normal, 1.0),
        )
        ab = h.semi_axis_a_m * h.semi_axis_b_m
        k = kalker_coefficients(h.a_over_b, scene.poissons_ratio)
        fx = -g_mod * ab * k.c11 * xi_x
        ft = -g_mod * ab * k.c22 * xi_y + sign * g_mod * ab**1.5 * k.c23 * spin
        limit = scene.friction_coefficient * max(normal, 1.0)
        z = math.hypot(fx, ft) / limit
        scale = (1.0 - z / 3.0 + z * z / 27.0) if z < 3.0 else 1.0 / z
        fx, ft = fx * scale, ft * scale
        normal = max((vertical_n - sign * ft * math.sin(gamma)) / math.cos(gamma), 0.0)
    lateral = -sign * normal * math.sin(gamma) + ft * math.cos(gamma)
    details = (normal, fx, xi_x, xi_y, spin, h, k.c22, math.hypot(fx, ft) / limit)
    return lateral, fx, -sign * y_c * fx, details


#: Neighbouring table shifts whose contacts lie further apart than this across the wheel,
#: one on the flange and one not, straddle a jump of the contact to the flank [m]
JUMP_M = 1.0e-3


def _rows(table: _Table, y: float, side: int) -> list[tuple[float, int, np.ndarray]]:
    """The contacts of one side at shift ``y`` as (share of the load, table index, values):
    one contact interpolated between its neighbours, or, where the contact jumps between
    them onto the flange, both, the load shared in proportion to the way across (two-point contact)."""
    yy = float(np.clip(y, table.shifts_m[0], table.shifts_m[-1]))
    k = min(int((yy - table.shifts_m[0]) / SHIFT_STEP_M), table.shifts_m.size - 2)
    w = (yy - table.shifts_m[k]) / SHIFT_STEP_M
    lo, hi = table.contacts[k][side], table.contacts[k + 1][side]
    if lo.on_flange != hi.on_flange and abs(lo.wheel_lateral_m - hi.wheel_lateral_m) > JUMP_M:
        return [(1.0 - w, k, table.values[k, side]), (w, k + 1, table.values[k + 1, side])]
    return [(1.0, k if w < 0.5 else k + 1, (1.0 - w) * table.values[k, side] + w * table.values[k + 1, side])]


def _wheelset(
    scene: _Scene, table: _Table, y: float, psi: float, excess: float, transfer_n: float
) -> tuple[float, float, float, list[list[tuple[float, int, np.ndarray, float, tuple[Any, ...]]]]]:
    """A wheelset's contact forces: (lateral, yaw moment, longitudinal, per side its
    contacts' (share, table index, values, forces))."""
    lat = mom = lon = 0.0
    sides = []
    for side, sign in ((0, 1), (1, -1)):
        vertical = scene.wheel_load_n + sign * transfer_n
        contacts = []
        for share, k, row in _rows(table, y, side):
            if share <= 0.0:
                continue
            f_lat, f_x, m_z, d = _side_forces(scene, row, sign, share * vertical, psi, excess)
            lat, mom, lon = lat + f_lat, mom + m_z, lon + f_x
            contacts.append((share, k, row, f_lat, d))
        sides.append(contacts)
    # beyond the flank's reach the wheelset would climb: a steep wall that the solver sees
    over = abs(y) - table.shifts_m[-1]
    if over > 0:
        lat -= math.copysign(1e10 * over, y)
    return lat, mom, lon, sides


def steady_curving(
    geometry: ContactGeometry,
    vehicle: Vehicle,
    radius_m: float,
    train_speed_km_h: float,
    *,
    wheel_load_n: float,
    friction_coefficient: float,
    cant_mm: float = 0.0,
    youngs_modulus_pa: float = 210e9,
    poissons_ratio: float = 0.3,
) -> tuple[WheelContact, ...]:
    """The four wheels of a bogie in steady curving, in ``track.curving.WHEELS`` order
    (module docstring). ``wheel_load_n`` is each wheel's static load [N].

    Raises
    ------
    CurvingError
        Where the wheelset would climb its flange or no equilibrium is found.
    """
    speed = train_speed_km_h / 3.6
    unbalanced = speed * speed / radius_m - GRAVITY_M_S2 * cant_mm * 1e-3 / RAIL_SPACING_M
    scene = _Scene(
        geometry,
        float(radius_m),
        speed,
        unbalanced,
        float(wheel_load_n),
        float(friction_coefficient),
        float(youngs_modulus_pa),
        float(poissons_ratio),
    )
    table = _table(geometry)
    a = 0.5 * vehicle.wheelbase_m
    x_axle = (a, -a)
    mass_per_wheelset = 2.0 * wheel_load_n / GRAVITY_M_S2
    transfer = mass_per_wheelset * unbalanced * vehicle.centre_of_gravity_height_m / RAIL_SPACING_M
    k_y, k_psi = vehicle.primary_lateral_stiffness_n_m, vehicle.primary_yaw_stiffness_n_m_rad
    scale = 1e-3  # the unknowns in mm, mrad and per mille

    def residuals(x: np.ndarray) -> np.ndarray:
        y1, p1, e1, y2, p2, e2, yf, pf = x * scale
        out = []
        frame_lat, frame_yaw = 2.0 * mass_per_wheelset * unbalanced, 0.0
        for (y, p, e), xi in zip(((y1, p1, e1), (y2, p2, e2)), x_axle):
            spring = k_y * (yf + xi * pf + a * a / (2.0 * radius_m) - y)
            moment = k_psi * (pf + xi / radius_m - p)
            lat, mom, lon, _ = _wheelset(scene, table, y, p, e, transfer)
            out += [lat + spring, mom + moment, lon]
            frame_lat -= spring
            frame_yaw -= moment + xi * spring
        out += [frame_lat, frame_yaw / a]
        return np.array(out) / wheel_load_n

    psi = a / radius_m
    symmetric = np.array([0.0, psi, 0.0, 0.0, -psi, 0.0, 0.0, 0.0])  # both axles equally yawed
    flanging = np.array(
        [table.shifts_m[-1], 2 * psi, 0.0, 0.0, 0.0, 0.0, 0.0, psi]
    )  # the leading one flanging
    best = min(
        (
            least_squares(residuals, start / scale, xtol=1e-12, ftol=1e-14, gtol=1e-14, max_nfev=2000)
            for start in (symmetric, flanging)
        ),
        key=lambda sol: sol.cost,
    )
    if np.max(np.abs(best.fun)) > FORCE_TOLERANCE:
        raise CurvingError(
            f"no steady curving found at R = {radius_m:g} m, {train_speed_km_h:g} km/h "
            f"(largest force imbalance {np.max(np.abs(best.fun)):.2g} of the wheel load)"
        )
    y1, p1, e1, y2, p2, e2, _, _ = best.x * scale
    if max(abs(y1), abs(y2)) > table.shifts_m[-1] + 1e-6:
        raise CurvingError(
            f"R = {radius_m:g} m at {train_speed_km_h:g} km/h: the leading wheelset would climb its flange"
        )
    wheels = []
    for (axle, rail), (y, p, e) in zip(WHEELS, ((y1, p1, e1), (y1, p1, e1), (y2, p2, e2), (y2, p2, e2))):
        _, _, _, sides = _wheelset(scene, table, y, p, e, transfer)
        side, sign = (0, 1) if rail == "outer" else (1, -1)
        contacts = sides[side]
        # the wheel's contact: the flange's where it touches, else the tread's
        share, k, row, _, d = max(contacts, key=lambda c: (table.flanged[c[1]][side], c[0]))
        normal, _, xi_x, xi_y, spin, h, c22, used = d
        wheels.append(
            WheelContact(
                axle=axle,
                rail=rail,
                lateral_shift_m=float(y),
                angle_of_attack_rad=float(p),
                contact=table.contacts[k][side],
                flange_contact=any(table.flanged[c[1]][side] for c in contacts),
                wheel_load_n=float(scene.wheel_load_n + sign * transfer),
                normal_force_n=float(normal),
                lateral_force_n=float(-sum(c[3] for c in contacts)),
                longitudinal_force_n=float(d[1]),
                longitudinal_creepage=float(xi_x),
                lateral_creepage=float(xi_y),
                spin_creepage_1_m=float(spin),
                semi_axis_a_m=h.semi_axis_a_m,
                semi_axis_b_m=h.semi_axis_b_m,
                c22=float(c22),
                adhesion_used=float(used),
                load_share=float(share),
            )
        )
    return tuple(wheels)
