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

Each wheel touches its rail where :class:`contact.wheel_rail.ContactGeometry` puts it
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
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import OptimizeResult, brentq, least_squares

from contact.hertz import hertz_contact, kalker_coefficients
from contact.wheel_rail import SHIFT_STEP_M, ContactGeometry, ContactPoint, is_flange_angle

from .curving import GRAVITY_M_S2, MAX_ANGLE_OF_ATTACK_RAD, RAIL_SPACING_M, WHEELS, Axle, Rail

__all__ = [
    "BogieCurving",
    "ContactState",
    "ContactTable",
    "CurvingError",
    "Vehicle",
    "WheelContact",
    "contact_table",
    "solve_curving",
    "steady_curving",
]


#: The least share of the friction coefficient the lateral creep force keeps where the
#: longitudinal creep force saturates the contact (the creep law's sharing is smooth, never
#: a hard zero)
LEAST_LATERAL_FRICTION = 0.05
#: The conicity a first guess of the pure-rolling shift takes (a worn profile's order)
CONICITY_GUESS = 0.15
#: Where no start finds the equilibrium, it is followed from a wider curve to the one asked,
#: through these multiples of its radius
CONTINUATION_RADII = np.array([4.0, 2.5, 1.8, 1.4, 1.2, 1.1, 1.0])
#: The equilibrium is solved when every force is within this fraction of the wheel load
FORCE_TOLERANCE = 1.0e-4


class CurvingError(RuntimeError):
    """No steady equilibrium of the bogie was found in this curve, or it would climb its
    flange: a failed computation, said in one line."""


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
class ContactState:
    """One contact of a wheel with its rail in steady curving.

    Attributes
    ----------
    point : ContactPoint
        Where it touches: on the wheel (``wheel_lateral_m``), its rolling radius, contact
        angle and curvatures.
    normal_force_n : float
        Its normal force [N].
    longitudinal_force_n : float
        The rail's longitudinal creep force on the wheel there [N].
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

    point: ContactPoint
    normal_force_n: float
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
        return self.point.contact_angle_rad

    @property
    def on_flange(self) -> bool:
        return self.point.on_flange

    @property
    def longitudinal_force_share(self) -> float:
        """|F_x| / N: the adhesion the longitudinal creep force takes [-]."""
        return abs(self.longitudinal_force_n) / self.normal_force_n

    def lateral_friction_coefficient(self, friction_coefficient: float) -> float:
        """The friction left to the lateral creep force [-]: the longitudinal force takes
        its share of the adhesion both share, sqrt(mu^2 - (F_x / N)^2) (at least
        :data:`LEAST_LATERAL_FRICTION` of mu, where the longitudinal creep saturates)."""
        left = friction_coefficient**2 - self.longitudinal_force_share**2
        return max(math.sqrt(max(left, 0.0)), LEAST_LATERAL_FRICTION * friction_coefficient)

    @property
    def crabbing_velocity_fraction(self) -> float:
        """|xi_y|: the lateral sliding speed in the contact plane over the rolling speed [-]."""
        return abs(self.lateral_creepage)


@dataclass(frozen=True)
class WheelContact:
    """One wheel in a curve, at its own contacts.

    Attributes
    ----------
    axle, rail : str
    lateral_shift_m : float
        The wheelset's, positive toward the outer rail [m].
    angle_of_attack_rad : float
    contacts : tuple of ContactState
        Its contacts: one, or the tread's and the flange's in a two-point contact.
    wheel_load_n : float
        The rail's vertical force on the wheel, all its contacts [N].
    lateral_force_n : float
        The rail's lateral force on the wheel, all its contacts, positive toward the
        curve's centre [N].
    """

    axle: Axle
    rail: Rail
    lateral_shift_m: float
    angle_of_attack_rad: float
    contacts: tuple[ContactState, ...]
    wheel_load_n: float
    lateral_force_n: float

    @property
    def flange_contact(self) -> bool:
        """Whether one of its contacts is on the flange."""
        return any(c.on_flange for c in self.contacts)

    @property
    def main(self) -> ContactState:
        """The contact that describes the wheel in one row: the flange's where it touches
        (the steepest), else the tread's."""
        return max(self.contacts, key=lambda c: abs(c.contact_angle_rad))

    @property
    def contact_angle_rad(self) -> float:
        return self.main.contact_angle_rad


@dataclass(frozen=True)
class ContactTable:
    """A wheel's contacts on its rail at every tabulated lateral shift, with each contact's
    Hertz ellipse at 1 N and Kalker's coefficients: what the curving interpolates (made
    once per wheel and rail by :func:`contact_table`)."""

    shifts_m: np.ndarray
    contacts: tuple[tuple[ContactPoint, ...], ...]  # per shift: outer's, inner's first contacts
    # shift x side x (y_c, r, gamma, a and b at 1 N, C11, C22, C23): a Hertz ellipse keeps
    # its shape under any load and its semi-axes grow as N^(1/3)
    values: np.ndarray = field(repr=False)
    youngs_modulus_pa: float = 210e9
    poissons_ratio: float = 0.3


def contact_table(
    geometry: ContactGeometry, youngs_modulus_pa: float = 210e9, poissons_ratio: float = 0.3
) -> ContactTable:
    """The :class:`ContactTable` of ``geometry`` for wheel and rail of Young's modulus
    ``youngs_modulus_pa`` [Pa] and Poisson's ratio ``poissons_ratio``."""
    positions = geometry.tabulated
    shifts = np.array([p.lateral_shift_m for p in positions])
    contacts = tuple((p.outer[0], p.inner[0]) for p in positions)
    values = []
    for pair in contacts:
        sides = []
        for c in pair:
            h = hertz_contact(
                c.rolling_radius_m / math.cos(c.contact_angle_rad),
                c.relative_transverse_radius_m,
                math.inf,
                math.inf,
                youngs_modulus_pa,
                poissons_ratio,
                1.0,
            )
            k = kalker_coefficients(h.a_over_b, poissons_ratio)
            sides.append(
                [
                    c.lateral_position_m,
                    c.rolling_radius_m,
                    c.contact_angle_rad,
                    h.semi_axis_a_m,
                    h.semi_axis_b_m,
                    k.c11,
                    k.c22,
                    k.c23,
                ]
            )
        values.append(sides)
    return ContactTable(shifts, contacts, np.array(values), float(youngs_modulus_pa), float(poissons_ratio))


@dataclass(frozen=True)
class _Scene:
    geometry: ContactGeometry
    radius_m: float
    speed_m_s: float
    unbalanced_m_s2: float
    wheel_load_n: float
    friction_coefficient: float
    flange_friction_coefficient: float
    youngs_modulus_pa: float
    poissons_ratio: float

    def friction_at(self, contact_angle_rad: float) -> float:
        """The friction coefficient of a contact: the flange's on the flange
        (``contact_geometry.is_flange_angle``), else the rail head's."""
        if is_flange_angle(contact_angle_rad):
            return self.flange_friction_coefficient
        return self.friction_coefficient


#: A normal force's guess (the same contact's last) is refined by one secant step over this
#: relative width; kept where it balances to the bracketing's tolerance (the Jacobian's
#: differences and Newton's last steps move the force far less than the width)
GUESS_STEP = 1.0e-7


def _side_forces(
    scene: _Scene,
    row: np.ndarray,
    sign: int,
    vertical_n: float,
    psi: float,
    excess: float,
    guess_n: float | None = None,
) -> tuple[float, float, float, tuple[Any, ...]]:
    """One wheel's contact forces: (lateral global, longitudinal, yaw moment, details).

    The normal force N carries the vertical load with the creep force's vertical part,
    N cos(gamma) + sign F_t(N) sin(gamma) = W, where F_t grows with N (the ellipse's area
    as N^(2/3), the saturation's limit as mu N): solved by bracketing, since on a flank
    (mu tan(gamma) near 1) a fixed-point iteration converges slowly or not at all; first
    by a secant step from ``guess_n`` (:data:`GUESS_STEP`), kept where it balances."""
    y_c, r, gamma, a1, b1, c11, c22, c23 = row
    r0 = scene.geometry.rolling_radius_m
    xi_x = (1.0 + sign * y_c / scene.radius_m) - (1.0 + excess) * r / r0
    xi_y = -psi / math.cos(gamma)
    spin = math.sin(gamma) / r
    g_mod = scene.youngs_modulus_pa / (2.0 * (1.0 + scene.poissons_ratio))
    cos_g, sin_g = math.cos(gamma), math.sin(gamma)
    mu = scene.friction_at(gamma)

    def forces(normal: float) -> tuple[float, float, float]:
        grow = max(normal, 1.0) ** (1.0 / 3.0)
        ab = a1 * b1 * grow * grow
        fx = -g_mod * ab * c11 * xi_x
        ft = -g_mod * ab * c22 * xi_y + sign * g_mod * ab**1.5 * c23 * spin
        limit = mu * max(normal, 1.0)
        z = math.hypot(fx, ft) / limit
        scale = (1.0 - z / 3.0 + z * z / 27.0) if z < 3.0 else 1.0 / z
        return fx * scale, ft * scale, z * scale

    def imbalance(normal: float) -> float:
        return normal * cos_g + sign * forces(normal)[1] * sin_g - vertical_n

    xtol = 1e-9 * max(vertical_n, 1.0)
    normal = math.nan
    if guess_n is not None and guess_n > 0.0:
        f0, step = imbalance(guess_n), GUESS_STEP * guess_n
        slope = (imbalance(guess_n + step) - f0) / step
        if slope > 0.0:
            trial = guess_n - f0 / slope
            if trial > 0.0 and abs(imbalance(trial)) <= slope * xtol:
                normal = trial
    if math.isnan(normal):
        high = max(vertical_n, 1.0) / cos_g
        while imbalance(high) < 0.0 and high < 1e3 * max(vertical_n, 1.0) / cos_g:
            high *= 2.0
        if imbalance(0.0) >= 0.0:  # no load on this contact (a wheel lifting, a vanishing share)
            normal = 0.0
        elif imbalance(high) > 0.0:
            normal = brentq(imbalance, 0.0, high, xtol=xtol)
        else:
            normal = high
    fx, ft, used = forces(normal)
    lateral = -sign * normal * sin_g + ft * cos_g
    grow = max(normal, 1.0) ** (1.0 / 3.0)
    details = (normal, fx, xi_x, xi_y, spin, (a1 * grow, b1 * grow), c22, used)
    return lateral, fx, -sign * y_c * fx, details


#: Neighbouring table shifts whose contacts lie further apart than this across the wheel
#: straddle a jump of the contact (to the flank, or across a hollow of the tread) [m]
JUMP_M = 1.0e-3


def _rows(table: ContactTable, y: float, side: int) -> list[tuple[float, int, np.ndarray]]:
    """The contacts of one side at shift ``y`` as (share of the load, table index, values):
    one contact interpolated between its neighbours, or, where the contact jumps between
    them (onto the flange, or from one part of the tread to another), both, the load shared
    in proportion to the way across (two-point contact)."""
    yy = float(np.clip(y, table.shifts_m[0], table.shifts_m[-1]))
    k = min(int((yy - table.shifts_m[0]) / SHIFT_STEP_M), table.shifts_m.size - 2)
    w = (yy - table.shifts_m[k]) / SHIFT_STEP_M
    lo, hi = table.contacts[k][side], table.contacts[k + 1][side]
    if abs(lo.wheel_lateral_m - hi.wheel_lateral_m) > JUMP_M:
        return [(1.0 - w, k, table.values[k, side]), (w, k + 1, table.values[k + 1, side])]
    return [(1.0, k if w < 0.5 else k + 1, (1.0 - w) * table.values[k, side] + w * table.values[k + 1, side])]


def _wheelset(
    scene: _Scene,
    table: ContactTable,
    y: float,
    psi: float,
    excess: float,
    transfer_n: float,
    guesses: dict[tuple[int, int], float],
) -> tuple[float, float, float, list[list[tuple[float, int, np.ndarray, float, tuple[Any, ...]]]]]:
    """A wheelset's contact forces: (lateral, yaw moment, longitudinal, per side its
    contacts' (share, table index, values, forces)); ``guesses``: each contact's last normal
    force [N] by (side, table index), its next solve's start, updated here."""
    lat = mom = lon = 0.0
    sides = []
    for side, sign in ((0, 1), (1, -1)):
        vertical = scene.wheel_load_n + sign * transfer_n
        contacts = []
        for share, k, row in _rows(table, y, side):
            if share <= 0.0:
                continue
            guess = guesses.get((side, k))
            f_lat, f_x, m_z, d = _side_forces(scene, row, sign, share * vertical, psi, excess, guess)
            guesses[(side, k)] = d[0]
            lat, mom, lon = lat + f_lat, mom + m_z, lon + f_x
            contacts.append((share, k, row, f_lat, d))
        sides.append(contacts)
    # beyond the flank's reach the wheelset would climb: a steep wall that the solver sees
    over = abs(y) - table.shifts_m[-1]
    if over > 0:
        lat -= math.copysign(1e10 * over, y)
    return lat, mom, lon, sides


#: A Jacobian of the equilibrium's residuals at the (scaled) unknowns
Jacobian = Callable[[np.ndarray], np.ndarray]
#: The step of the contact forces' differences, in the scaled unknowns (mm, mrad, per mille):
#: far above the normal force's bracketing tolerance, far below the contact table's step
JACOBIAN_STEP = 1.0e-6
#: Newton's iteration has converged when its step is below this, in the scaled unknowns
#: (1e-12 m), with the forces balanced to :data:`FORCE_TOLERANCE`
NEWTON_STEP = 1.0e-9
#: Newton's iteration keeps its Jacobian for the next step while a step leaves at most this
#: share of the forces' norm (a new Jacobian is six evaluations of the contact forces)
KEPT_JACOBIAN_CONTRACTION = 0.25


def _suspension(vehicle: Vehicle, radius_m: float, unbalanced_n: float) -> tuple[np.ndarray, np.ndarray]:
    """The equilibrium's suspension and inertia terms, linear in the unknowns u (shift,
    attack, rolling-speed excess of each wheelset, then the frame's shift and yaw): the
    matrix and the constant of ``springs @ u + preload`` [N, N m]. Wheelset i at x_i = +-a
    from the frame's centre takes k_y (y_f + x_i psi_f + a^2 / 2R - y_i) laterally and
    k_psi (psi_f + x_i / R - psi_i) in yaw (the frame sits on the curve's chord); the frame
    carries the unbalanced force less both springs, and its yaw moment over a."""
    a = 0.5 * vehicle.wheelbase_m
    k_y, k_psi = vehicle.primary_lateral_stiffness_n_m, vehicle.primary_yaw_stiffness_n_m_rad
    springs, preload = np.zeros((8, 8)), np.zeros(8)
    preload[6] = unbalanced_n
    for axle, x_i in enumerate((a, -a)):
        lateral, lateral_0 = np.zeros(8), k_y * a * a / (2.0 * radius_m)
        lateral[[6, 7, 3 * axle]] = k_y, k_y * x_i, -k_y
        yaw, yaw_0 = np.zeros(8), k_psi * x_i / radius_m
        yaw[[7, 3 * axle + 1]] = k_psi, -k_psi
        springs[3 * axle] += lateral
        springs[3 * axle + 1] += yaw
        springs[6] -= lateral
        springs[7] -= (yaw + x_i * lateral) / a
        preload[3 * axle] += lateral_0
        preload[3 * axle + 1] += yaw_0
        preload[6] -= lateral_0
        preload[7] -= (yaw_0 + x_i * lateral_0) / a
    return springs, preload


def _newton(
    residuals: Callable[[np.ndarray], np.ndarray],
    jacobian: Jacobian,
    start: np.ndarray,
    iterations: int = 20,
    kept: np.ndarray | None = None,
) -> OptimizeResult | None:
    """The equilibrium by Newton's iteration with a halved step where the forces would not
    fall, its Jacobian kept for the next step (with Broyden's update) while a step cuts the
    forces to :data:`KEPT_JACOBIAN_CONTRACTION` of theirs (a kept one's step costs one
    evaluation of the forces, a new Jacobian six more) and made anew where a kept one's
    step would not lower them; None where it does not converge (a kink of the
    interpolated contact table, a singular Jacobian), for the trust region to take over.
    ``kept``: a Jacobian to start with (a neighbouring curve's); the result's ``jac`` the
    latest one (a start for the next curve)."""
    x, f = np.array(start, float), residuals(start)
    jac = last = kept
    for _ in range(2 * iterations):  # a pass takes a step or lets a kept Jacobian go
        fresh = jac is None
        if jac is None:
            jac = last = jacobian(x)
        try:
            step = np.linalg.solve(jac, -f)
        except np.linalg.LinAlgError:
            if fresh:
                return None
            jac = None
            continue
        t = 1.0
        while True:
            trial = residuals(x + t * step)
            downhill = np.linalg.norm(trial) < np.linalg.norm(f) or t * np.max(np.abs(step)) <= NEWTON_STEP
            if downhill or not fresh:
                break
            t *= 0.5
            if t < 1.0 / 64.0:
                return None
        if not downhill:
            jac = None  # a kept Jacobian that no longer leads downhill: a new one from here
            continue
        moved = t * step
        if np.linalg.norm(trial) > KEPT_JACOBIAN_CONTRACTION * np.linalg.norm(f):
            jac = None
        elif moved @ moved > 0.0:  # Broyden's update: the kept Jacobian true along the step
            jac = last = jac + np.outer(trial - f - jac @ moved, moved) / (moved @ moved)
        x, f = x + moved, trial
        if t * np.max(np.abs(step)) <= NEWTON_STEP and np.max(np.abs(f)) <= FORCE_TOLERANCE:
            return OptimizeResult(x=x, fun=f, cost=0.5 * float(f @ f), jac=last)
    return None


@dataclass(frozen=True)
class BogieCurving:
    """A bogie's steady curving (:func:`solve_curving`): its four wheels, and the solved
    unknowns (scaled) and the equilibrium's Jacobian (None: not kept), a start for the
    same bogie in a neighbouring curve."""

    wheels: tuple[WheelContact, ...]
    unknowns: np.ndarray = field(repr=False)
    jacobian: np.ndarray | None = field(default=None, repr=False)


def steady_curving(
    geometry: ContactGeometry,
    vehicle: Vehicle,
    radius_m: float,
    train_speed_km_h: float,
    *,
    wheel_load_n: float,
    friction_coefficient: float,
    flange_friction_coefficient: float | None = None,
    cant_mm: float = 0.0,
    youngs_modulus_pa: float = 210e9,
    poissons_ratio: float = 0.3,
) -> tuple[WheelContact, ...]:
    """The four wheels of a bogie in steady curving, in ``track.curving.WHEELS`` order
    (module docstring). ``wheel_load_n`` is each wheel's static load [N];
    ``flange_friction_coefficient`` that of a contact on the flange (a lubricated gauge
    face's; None: the rail head's ``friction_coefficient``).

    Raises
    ------
    CurvingError
        Where the wheelset would climb its flange or no equilibrium is found.
    """
    return solve_curving(
        geometry,
        vehicle,
        radius_m,
        train_speed_km_h,
        wheel_load_n=wheel_load_n,
        friction_coefficient=friction_coefficient,
        flange_friction_coefficient=flange_friction_coefficient,
        cant_mm=cant_mm,
        table=contact_table(geometry, youngs_modulus_pa, poissons_ratio),
    ).wheels


def solve_curving(
    geometry: ContactGeometry,
    vehicle: Vehicle,
    radius_m: float,
    train_speed_km_h: float,
    *,
    wheel_load_n: float,
    friction_coefficient: float,
    table: ContactTable,
    flange_friction_coefficient: float | None = None,
    cant_mm: float = 0.0,
    start: BogieCurving | None = None,
) -> BogieCurving:
    """:func:`steady_curving` with the wheel's :func:`contact_table` made once (its
    elastic constants are the table's) and, for a run of curves, the solution of a
    neighbouring one as the first ``start`` (the same equilibrium, found in a few steps)."""
    reach = table.shifts_m[-1]
    flange_mu = friction_coefficient if flange_friction_coefficient is None else flange_friction_coefficient

    def problem(radius: float) -> tuple[_Scene, float, Callable[[np.ndarray], np.ndarray], Jacobian]:
        speed = train_speed_km_h / 3.6
        unbalanced = speed * speed / radius - GRAVITY_M_S2 * cant_mm * 1e-3 / RAIL_SPACING_M
        scene = _Scene(
            geometry,
            float(radius),
            speed,
            unbalanced,
            float(wheel_load_n),
            float(friction_coefficient),
            float(flange_mu),
            table.youngs_modulus_pa,
            table.poissons_ratio,
        )
        transfer = mass_per_wheelset * unbalanced * vehicle.centre_of_gravity_height_m / RAIL_SPACING_M
        springs, preload = _suspension(vehicle, radius, 2.0 * mass_per_wheelset * unbalanced)
        guesses: dict[tuple[int, int], float] = {}  # the normal forces of this radius's last evaluation

        def contact_forces(u: np.ndarray, axle: int) -> np.ndarray:
            """Wheelset ``axle``'s (lateral force, yaw moment, longitudinal force) [N, N m]."""
            y, p, e = u[3 * axle : 3 * axle + 3]
            return np.array(_wheelset(scene, table, y, p, e, transfer, guesses)[:3])

        def residuals(x: np.ndarray) -> np.ndarray:
            u = x * scale
            forces = np.concatenate([contact_forces(u, 0), contact_forces(u, 1), [0.0, 0.0]])
            return (forces + springs @ u + preload) / wheel_load_n

        def jacobian(x: np.ndarray) -> np.ndarray:
            # the contact forces of a wheelset depend on its own unknowns alone, the
            # suspension's are linear: six differences instead of the whole system's eight
            u = x * scale
            jac = springs.copy()
            for axle in (0, 1):
                base = contact_forces(u, axle)
                for j in range(3 * axle, 3 * axle + 3):
                    moved = u.copy()
                    moved[j] += JACOBIAN_STEP * scale
                    jac[3 * axle : 3 * axle + 3, j] += (contact_forces(moved, axle) - base) / (
                        JACOBIAN_STEP * scale
                    )
            return jac * scale / wheel_load_n

        return scene, transfer, residuals, jacobian

    def equilibrium(radius: float, first: tuple[np.ndarray, ...] = (), kept: np.ndarray | None = None) -> Any:
        """The first equilibrium found from ``first`` (with the Jacobian ``kept``) and the
        usual starts (a steady curving has one), else the closest; None where every start
        ran off to a huge yaw."""
        psi = a / radius
        pure = min(reach, geometry.rolling_radius_m * 0.5 * RAIL_SPACING_M / (radius * CONICITY_GUESS))
        starts = (
            *first,
            np.array([0.0, psi, 0.0, 0.0, -psi, 0.0, 0.0, 0.0]) / scale,  # both axles equally yawed
            np.array([reach, 2 * psi, 0.0, 0.0, 0.0, 0.0, 0.0, psi]) / scale,  # the leading one flanging
            np.array([pure, psi, 0.0, pure, -psi, 0.0, pure, 0.0]) / scale,  # both near pure rolling
        )
        _, _, residuals, jacobian = problem(radius)
        best = None
        for i, start in enumerate(starts):
            sol = _newton(residuals, jacobian, start, kept=kept if i == 0 and first else None)
            if sol is None:  # a kink of the contact table in the way: the trust region's care
                sol = least_squares(
                    residuals, start, jac=jacobian, xtol=1e-12, ftol=1e-14, gtol=1e-14, max_nfev=2000
                )
            if max(abs(sol.x[1]), abs(sol.x[4])) * scale > MAX_ANGLE_OF_ATTACK_RAD:
                continue  # saturated creep forces balance at any huge yaw too: not a curving
            if best is None or sol.cost < best.cost:
                best = sol
            if np.max(np.abs(sol.fun)) <= FORCE_TOLERANCE:
                break
        return best

    a = 0.5 * vehicle.wheelbase_m
    mass_per_wheelset = 2.0 * wheel_load_n / GRAVITY_M_S2
    scale = 1e-3  # the unknowns in mm, mrad and per mille
    best = equilibrium(
        float(radius_m), () if start is None else (start.unknowns,), None if start is None else start.jacobian
    )
    if best is None or np.max(np.abs(best.fun)) > FORCE_TOLERANCE:
        # continuation: from a wider curve, where the equilibrium is easy, to this one
        best = None
        for radius in float(radius_m) * CONTINUATION_RADII:
            best = equilibrium(radius, () if best is None else (best.x,))
    if best is None:
        raise CurvingError(f"no steady curving found at R = {radius_m:g} m, {train_speed_km_h:g} km/h")
    scene, transfer, _, _ = problem(float(radius_m))
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
    guesses: dict[tuple[int, int], float] = {}
    for (axle, rail), (y, p, e) in zip(WHEELS, ((y1, p1, e1), (y1, p1, e1), (y2, p2, e2), (y2, p2, e2))):
        _, _, _, sides = _wheelset(scene, table, y, p, e, transfer, guesses)
        side, sign = (0, 1) if rail == "outer" else (1, -1)
        contacts = sides[side]
        states = []
        for share, k, _, _, d in contacts:
            normal, fx, xi_x, xi_y, spin, (semi_a, semi_b), c22, used = d
            states.append(
                ContactState(
                    point=table.contacts[k][side],
                    normal_force_n=float(normal),
                    longitudinal_force_n=float(fx),
                    longitudinal_creepage=float(xi_x),
                    lateral_creepage=float(xi_y),
                    spin_creepage_1_m=float(spin),
                    semi_axis_a_m=float(semi_a),
                    semi_axis_b_m=float(semi_b),
                    c22=float(c22),
                    adhesion_used=float(used),
                    load_share=float(share),
                )
            )
        wheels.append(
            WheelContact(
                axle=axle,
                rail=rail,
                lateral_shift_m=float(y),
                angle_of_attack_rad=float(p),
                contacts=tuple(states),
                wheel_load_n=float(scene.wheel_load_n + sign * transfer),
                lateral_force_n=float(-sum(c[3] for c in contacts)),
            )
        )
    return BogieCurving(tuple(wheels), np.array(best.x), best.jac)
