"""Modal squeal model of Liu & Meehan (CM2015), Eq. 1, 2, 4, 5, 7, and its time integration.

Each mode i of the wheel, seen at the contact point, obeys (Eq. 1, 2)::

    m_i y_i'' + c_i y_i' + k_i y_i = Q,   Q = -mu(zeta) W,   zeta = (Vc + v)/V0  (Eq. 4)

with the contact velocity v = sum_i y_i' (modal superposition at the contact point).
With a single mode this is exactly the paper's 1-DOF model. Power input (Eq. 7):
P = Q v - sum_i c_i y_i'^2.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from contact.creep import ContactLaw, adhesion_ratio

from . import _engine, _kernels

__all__ = [
    "ModalDOF",
    "OperatingPoint",
    "rpm_to_speed",
    "TimeHistory",
    "IntegrationError",
    "Integration",
    "simulate_rk4",
    "simulate_reference",
    "Coordinates",
    "as_modes",
    "choose_time_step",
    "coordinates",
    "highest_frequency_hz",
    "law_vector",
    "mode_arrays",
]


def _finite_positive(owner: str, name: str, value: float, allow_zero: bool = False) -> float:
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"{owner}.{name} must be finite, got {value!r}")
    if value < 0.0 or (value == 0.0 and not allow_zero):
        kind = "non-negative" if allow_zero else "positive"
        raise ValueError(f"{owner}.{name} must be {kind}, got {value!r}")
    return value


@dataclass(frozen=True)
class ModalDOF:
    """One degree of freedom seen at the contact point: a wheel mode, or a mode of the
    counter-body.

    Attributes
    ----------
    mass_kg : modal mass m at the contact point along the coordinate's reference
        direction, kg (for a degenerate pair the pair-combined contact modal mass; for
        the paper's lateral mode, the lateral modal mass 1/phi_t^2).
    stiffness_n_m : modal stiffness k = omega^2 m, N/m.
    damping_ns_m : viscous modal damping c, N s/m.
    nodal_diameters : n; a mode with n >= 1 is a cos/sin pair, which wheel rotation
        turns into two travelling waves (:mod:`reduced.stability`); 0 for a standing mode.
    lateral, normal : the displacement of the contact along the lateral tangent t and
        the normal n (out of the wheel, towards the counter-body) per unit of the
        coordinate, dimensionless: (1, 0) is the paper's lateral mode, (1, phi_n/phi_t)
        a wheel mode that also moves the contact normally, (phi_t/phi_n, 1) one that moves
        it mostly normally, and -1 a counter-body's own motion (the contact sees the
        wheel's motion relative to it).
    """

    mass_kg: float
    stiffness_n_m: float
    damping_ns_m: float
    nodal_diameters: int = 0
    lateral: float = 1.0
    normal: float = 0.0

    def __post_init__(self) -> None:
        _finite_positive("ModalDOF", "mass_kg", self.mass_kg)
        _finite_positive("ModalDOF", "stiffness_n_m", self.stiffness_n_m)
        _finite_positive("ModalDOF", "damping_ns_m", self.damping_ns_m, allow_zero=True)
        n = self.nodal_diameters
        if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 0:
            raise ValueError(f"ModalDOF.nodal_diameters must be a non-negative integer, got {n!r}")
        for name in ("lateral", "normal"):
            if not math.isfinite(float(getattr(self, name))):
                raise ValueError(f"ModalDOF.{name} must be finite, got {getattr(self, name)!r}")
        if self.lateral == 0.0 and self.normal == 0.0:
            raise ValueError("ModalDOF: lateral and normal are both 0: the contact does not see the mode")

    @classmethod
    def from_damping_ratio(
        cls,
        mass_kg: float,
        stiffness_n_m: float,
        damping_ratio: float,
        nodal_diameters: int = 0,
        lateral: float = 1.0,
        normal: float = 0.0,
    ) -> ModalDOF:
        """c = 2 zeta_d sqrt(k m); damping_ratio dimensionless (Table 1: 9.4e-4 -> 42 N s/m)."""
        _finite_positive("ModalDOF", "damping_ratio", damping_ratio, allow_zero=True)
        c = 2.0 * damping_ratio * math.sqrt(stiffness_n_m * mass_kg)
        return cls(mass_kg, stiffness_n_m, c, int(nodal_diameters), lateral, normal)

    @classmethod
    def from_frequency(
        cls,
        mass_kg: float,
        frequency_hz: float,
        damping_ratio: float,
        nodal_diameters: int = 0,
        lateral: float = 1.0,
        normal: float = 0.0,
    ) -> ModalDOF:
        """k = (2 pi f)^2 m, c = 2 zeta_d sqrt(k m); f in Hz."""
        k = (2.0 * math.pi * frequency_hz) ** 2 * mass_kg
        return cls.from_damping_ratio(mass_kg, k, damping_ratio, nodal_diameters, lateral, normal)

    @classmethod
    def from_components(
        cls,
        frequency_hz: float,
        damping_ratio: float,
        phi_t: float,
        phi_n: float,
        nodal_diameters: int = 0,
        lateral_modal_mass_kg: float | None = None,
    ) -> ModalDOF:
        """A mode from its mass-normalised components at the contact, ``phi_t`` (lateral)
        and ``phi_n`` (normal) [1/sqrt(kg)]: the coordinate is the contact's motion along
        the larger one (modal mass 1/phi^2), the other a ratio. ``lateral_modal_mass_kg``:
        1/phi_t^2 as the caller computed it (a pair's, from both members), kept exactly."""
        if phi_t == 0.0 and phi_n == 0.0:
            raise ValueError(
                "ModalDOF.from_components: the contact is a node of the mode (phi_t = phi_n = 0)"
            )
        if abs(phi_t) >= abs(phi_n):
            mass = 1.0 / (phi_t * phi_t) if lateral_modal_mass_kg is None else lateral_modal_mass_kg
            return cls.from_frequency(mass, frequency_hz, damping_ratio, nodal_diameters, 1.0, phi_n / phi_t)
        mass = 1.0 / (phi_n * phi_n)
        return cls.from_frequency(mass, frequency_hz, damping_ratio, nodal_diameters, phi_t / phi_n, 1.0)

    def with_damping_ratio(self, damping_ratio: float) -> ModalDOF:
        """The same mode with another modal damping ratio."""
        return ModalDOF.from_damping_ratio(
            self.mass_kg, self.stiffness_n_m, damping_ratio, self.nodal_diameters, self.lateral, self.normal
        )

    @property
    def angular_frequency_rad_s(self) -> float:
        """Undamped natural angular frequency sqrt(k/m), rad/s."""
        return math.sqrt(self.stiffness_n_m / self.mass_kg)

    @property
    def frequency_hz(self) -> float:
        """Undamped natural frequency, Hz (Table 1: 1143 Hz)."""
        return self.angular_frequency_rad_s / (2.0 * math.pi)

    @property
    def damping_ratio(self) -> float:
        """c / (2 sqrt(k m)), dimensionless."""
        return self.damping_ns_m / (2.0 * math.sqrt(self.stiffness_n_m * self.mass_kg))

    @property
    def components(self) -> tuple[float, float]:
        """(phi_t, phi_n): the contact's mass-normalised displacement along t and n
        [1/sqrt(kg)] (the counter-body's, with the sign of its relative motion)."""
        unit = 1.0 / math.sqrt(self.mass_kg)
        return self.lateral * unit, self.normal * unit

    @property
    def lateral_only(self) -> bool:
        """The paper's lateral mode: lateral 1, normal 0."""
        return self.lateral == 1.0 and self.normal == 0.0


def rpm_to_speed(rpm: float, rolling_radius_m: float) -> float:
    """Rolling speed at the contact [m/s] of a wheel of ``rolling_radius_m`` [m] at
    ``rpm`` [rev/min]: V0 = rpm 2 pi / 60 R."""
    return rpm * 2.0 * math.pi / 60.0 * rolling_radius_m


#: One mode or several seen at the same contact point (the modal model's input).
Modes = ModalDOF | Sequence[ModalDOF]


@dataclass(frozen=True)
class OperatingPoint:
    """Rolling speed V0 and crabbing (lateral sliding) velocity Vc.

    Attributes
    ----------
    rolling_speed_m_s : V0 at the contact, m/s (> 0).
    crabbing_velocity_m_s : Vc, m/s (any sign; Vc = theta V0, Eq. 5).
    """

    rolling_speed_m_s: float
    crabbing_velocity_m_s: float

    def __post_init__(self) -> None:
        v0 = float(self.rolling_speed_m_s)
        if not math.isfinite(v0):
            raise ValueError(f"rolling_speed_m_s must be finite, got {v0!r}")
        if v0 <= 0.0:
            raise ValueError(f"rolling_speed_m_s must be > 0 (the creepage divides by it), got {v0!r}")
        if not math.isfinite(float(self.crabbing_velocity_m_s)):
            raise ValueError(f"crabbing_velocity_m_s must be finite, got {self.crabbing_velocity_m_s!r}")

    @classmethod
    def from_rpm(cls, rpm: float, wheel_radius_m: float, crabbing_velocity_m_s: float) -> OperatingPoint:
        """V0 = rpm 2 pi / 60 * R (R: rolling radius in m). 800 RPM on R = 0.213 m -> 17.84 m/s."""
        if not math.isfinite(float(rpm)) or rpm <= 0.0:
            raise ValueError(f"rpm must be > 0 and finite, got {rpm!r}")
        _finite_positive("OperatingPoint", "wheel_radius_m", wheel_radius_m)
        return cls(rpm_to_speed(rpm, wheel_radius_m), crabbing_velocity_m_s)

    @classmethod
    def from_angle_of_attack(cls, rolling_speed_m_s: float, angle_of_attack_rad: float) -> OperatingPoint:
        """Vc = theta V0 (Eq. 5, small angle), theta in rad."""
        if not math.isfinite(float(angle_of_attack_rad)):
            raise ValueError(f"angle_of_attack_rad must be finite, got {angle_of_attack_rad!r}")
        return cls(rolling_speed_m_s, angle_of_attack_rad * rolling_speed_m_s)

    @property
    def creepage(self) -> float:
        """Quasi-static lateral creepage Vc/V0 (= angle of attack), dimensionless."""
        return self.crabbing_velocity_m_s / self.rolling_speed_m_s

    def wheel_speed_rad_s(self, rolling_radius_m: float) -> float:
        """Omega = V0 / R, the angular speed of a wheel of rolling radius R [m] rolling at
        V0 [rad/s] (the speed at which a turning wheel's modes pass the contact)."""
        _finite_positive("OperatingPoint", "rolling_radius_m", rolling_radius_m)
        return self.rolling_speed_m_s / rolling_radius_m

    def rpm(self, rolling_radius_m: float) -> float:
        """The wheel speed [rev/min] of a wheel of rolling radius R [m] rolling at V0."""
        return self.wheel_speed_rad_s(rolling_radius_m) * 60.0 / (2.0 * math.pi)


class IntegrationError(RuntimeError):
    """The time integration became unstable or inaccurate and could not be refined."""


#: largest number of stored samples simulate() accepts (the TimeHistory holds about
#: 2 N + 6 float64 arrays of that length, plus temporaries: ~1.5 GB for one mode)
MAX_STORED_SAMPLES = 10_000_000
#: RK4 steps per period of the highest mode (with rotation: of its faster wave); the
#: convergence study measures the amplitude error of this rung (about 1e-4)
STEPS_PER_PERIOD = 48


def _check_storage(
    n_out: int,
    n_modes: int,
    n_steps: int,
    h: float,
    duration: float,
    store_every: int,
    f_max: float,
    error: type[Exception] = ValueError,
) -> None:
    if n_out <= MAX_STORED_SAMPLES:
        return
    need = int(math.ceil(n_steps / (MAX_STORED_SAMPLES - 1)))
    per_period = 1.0 / (f_max * h * need)
    gb = n_out * (2 * n_modes + 12) * 8 / 1e9
    # limit-cycle metrics need >= 16 samples per period of the highest mode
    fix = (
        f"pass store_every >= {need} (keeps {per_period:.0f} samples per period)"
        if per_period >= 16
        else f"shorten the duration to at most {MAX_STORED_SAMPLES / (16 * f_max):.3g} s (16 samples "
        f"per period, store_every = {max(1, int(1 / (16 * f_max * h)))})"
    )
    raise error(
        f"simulate would store {n_out:,} samples (~{gb:.1f} GB): {n_steps:,} RK4 steps of "
        f"{h:.3g} s over {duration:g} s with store_every={store_every} (highest mode "
        f"{f_max:.4g} Hz); {fix} (limit MAX_STORED_SAMPLES = {MAX_STORED_SAMPLES:,})"
    )


@dataclass(frozen=True, eq=False)
class TimeHistory:
    """Result of a time integration (all arrays share the time axis).

    Attributes
    ----------
    t : time, s, shape (n,).
    y : contact-point lateral displacement sum_i p_i a_i y_i, m, shape (n,).
    v : contact-point lateral velocity sum_i p_i a_i y_i' (the material velocity at the
        contact, relative to the counter-body's), m/s, shape (n,); p_i = 1 without
        rotation, a_i the coordinate's lateral gain (1 for the paper's mode).
    y_modes, v_modes : displacement (m) and velocity (m/s) of each modal coordinate,
        shape (n, N): one per mode, two (the pair's a, b) per rotating pair.
    creepage : zeta = (Vc + v)/V0, dimensionless.
    Q : lateral contact force on the wheel, N (Eq. 2; with transient creep the lagged
        force the modes feel).
    P : power input to the modes Q v - sum c_i y_i'^2, W (Eq. 7).
    u_n : the normal approach at the contact sum_i p_i b_i y_i, m (0 when no
        coordinate moves the contact normally; the Hertz spring is measured from its
        static value, :func:`static_normal_approach_m`).
    N : the normal contact force, N (W with a constant normal load; 0 where the
        surfaces have separated, :attr:`separated`).
    modes, contact, operating_point : the inputs.
    step_s : integration step, s (for the reference: the output spacing).
    method : "rk4" (fixed step, :func:`simulate`) or the solve_ivp method name.
    energy_mismatch_j : |Delta E - int P dt| at the end, J (RK4 only; NaN otherwise).
    wheel_speed_rad_s : Omega, the wheel's rotation (0: off), rad/s.
    coordinates : the modal coordinates (:class:`Coordinates`) of the columns of
        y_modes and v_modes.
    t_modes : the times of y_modes and v_modes, s (None: t; the exponential
        integrator keeps the coordinates over the record's tail only).
    v_body : the counter-body's own lateral velocity at the contact, m/s (None: rigid).
    body : the counter-body (``reduced.counter_body.BodyModel``; None: rigid).
    body_states : its states over t_modes, shape (len(t_modes), its states).
    """

    t: np.ndarray
    y: np.ndarray
    v: np.ndarray
    y_modes: np.ndarray
    v_modes: np.ndarray
    creepage: np.ndarray
    Q: np.ndarray
    P: np.ndarray
    modes: tuple
    contact: ContactLaw
    operating_point: OperatingPoint
    step_s: float
    method: str
    energy_mismatch_j: float = field(default=float("nan"))
    wheel_speed_rad_s: float = 0.0
    coordinates: Coordinates | None = None
    u_n: np.ndarray | None = None
    N: np.ndarray | None = None
    t_modes: np.ndarray | None = None
    v_body: np.ndarray | None = None
    body: Any = None
    body_states: np.ndarray | None = None

    @property
    def modes_time(self) -> np.ndarray:
        """The times of y_modes and v_modes [s]."""
        return self.t if self.t_modes is None else self.t_modes

    def tail(self, seconds: float, modes_seconds: float | None = None) -> TimeHistory:
        """The record's last ``seconds`` (every series over time cut, the rest as it is),
        the modal coordinates' and the counter-body's states over their last
        ``modes_seconds`` (default ``seconds``; 0: the final state): what a caller keeping
        many records needs of each once its metrics are taken."""
        keep = self.t >= self.t[-1] - seconds
        tm = self.modes_time
        keep_modes = tm >= tm[-1] - (seconds if modes_seconds is None else modes_seconds)

        def cut(x: np.ndarray | None, k: np.ndarray) -> np.ndarray | None:
            return None if x is None else np.array(x[k])

        return replace(
            self,
            t=self.t[keep].copy(),
            y=self.y[keep].copy(),
            v=self.v[keep].copy(),
            creepage=self.creepage[keep].copy(),
            Q=self.Q[keep].copy(),
            P=self.P[keep].copy(),
            u_n=cut(self.u_n, keep),
            N=cut(self.N, keep),
            v_body=cut(self.v_body, keep),
            y_modes=self.y_modes[keep_modes].copy(),
            v_modes=self.v_modes[keep_modes].copy(),
            t_modes=None if self.t_modes is None else self.t_modes[keep_modes].copy(),
            body_states=cut(self.body_states, keep_modes),
        )

    @property
    def separated(self) -> np.ndarray:
        """Where the wheel and the counter-body have lost contact (N = 0), shape (n,)."""
        return np.zeros(len(self.t), dtype=bool) if self.N is None else self.N == 0.0


@dataclass(frozen=True, eq=False)
class Coordinates:
    """The modal coordinates the integrator advances, and how the contact sees them.

    mode : index into ``modes`` of each coordinate; m, c, k : its mass, damping,
    stiffness (SI); w, phase : its participation at the contact is
    ``cos(w t + phase)`` (w in rad/s; 0 and 0 without rotation: exactly 1); a, b : the
    contact's lateral and normal motion per unit coordinate (``ModalDOF.lateral``,
    ``ModalDOF.normal``).
    """

    mode: np.ndarray
    m: np.ndarray
    c: np.ndarray
    k: np.ndarray
    w: np.ndarray
    phase: np.ndarray
    a: np.ndarray
    b: np.ndarray

    def participation(self, t: np.ndarray) -> np.ndarray:
        """cos(w t + phase) at times t, shape (len(t), N)."""
        return np.cos(np.outer(t, self.w) + self.phase[None, :])


def coordinates(modes: Modes, wheel_speed_rad_s: float = 0.0) -> Coordinates:
    """The modal coordinates of ``modes``: one per mode, two (a and b, docs/theory.md,
    rotation) per pair with nodal diameters when the wheel turns at ``wheel_speed_rad_s``."""
    modes = as_modes(modes)
    rows = []
    for i, md in enumerate(modes):
        row = (i, md.mass_kg, md.damping_ns_m, md.stiffness_n_m)
        gains = (md.lateral, md.normal)
        if wheel_speed_rad_s != 0.0 and md.nodal_diameters >= 1:
            w = md.nodal_diameters * wheel_speed_rad_s
            rows += [(*row, w, 0.0, *gains), (*row, w, 0.5 * math.pi, *gains)]
        else:
            rows.append((*row, 0.0, 0.0, *gains))
    cols = list(zip(*rows))
    return Coordinates(np.array(cols[0], dtype=np.int64), *(np.array(col, dtype=float) for col in cols[1:]))


def static_normal_approach_m(modes: Modes, contact: ContactLaw, op: OperatingPoint) -> float:
    """The normal approach [m] by which the steady creep force Q0 = -mu0 W deflects the
    modes statically, sum_i b_i a_i Q0 / k_i (0 when no mode moves the contact
    normally). The rig's load (a dead weight or a soft spring) keeps the mean normal
    force at W, so the Hertz spring is measured from this state: N = W at steady
    sliding, as the linear model assumes (on a turning wheel the steady deflection of a
    pair differs by (n Omega / omega)^2, under 1e-3 here)."""
    modes = as_modes(modes)
    if all(md.normal == 0.0 for md in modes):
        return 0.0
    q0 = -float(adhesion_ratio(op.creepage, contact, op.rolling_speed_m_s)) * contact.normal_load_n
    return float(sum(md.normal * md.lateral * q0 / md.stiffness_n_m for md in modes))


def preloaded_state(
    modes: Modes,
    contact: ContactLaw,
    op: OperatingPoint,
    preloaded: Sequence[int],
    wheel_speed_rad_s: float = 0.0,
) -> tuple[np.ndarray, np.ndarray]:
    """An initial state (y0, v0) per coordinate (:func:`coordinates`) with the modes
    ``preloaded`` (indices into ``modes``) at rest in their static deflection under the
    steady creep force, a_i Q0 / k_i (Q0 = -mu0 W), the others at rest at zero: a track
    has carried the steady force long before the squeal starts, so its slow terms do not
    ring from a step."""
    modes = as_modes(modes)
    coords = coordinates(modes, wheel_speed_rad_s)
    q0 = -float(adhesion_ratio(op.creepage, contact, op.rolling_speed_m_s)) * contact.normal_load_n
    y0 = np.zeros(len(coords.m))
    for c, i in enumerate(coords.mode):
        if int(i) in set(preloaded) and coords.w[c] == 0.0:
            y0[c] = modes[int(i)].lateral * q0 / modes[int(i)].stiffness_n_m
    return y0, np.zeros(len(coords.m))


def law_vector(contact: ContactLaw, op: OperatingPoint, modes: Modes | None = None) -> np.ndarray:
    """Pack the contact and operating point for the RK4 kernels (:mod:`reduced._kernels`);
    with ``modes``, the static normal approach they take (:func:`static_normal_approach_m`),
    and where none of them moves the contact normally no Hertz spring at all (the normal
    force is W either way: the kernels then skip its energy at every step)."""
    lateral_only = modes is not None and all(md.normal == 0.0 for md in as_modes(modes))
    return np.array(
        [
            contact.normal_load_n,
            contact.friction_coefficient,
            contact.normalised_creepage_per_creepage,
            contact.friction.decay_speed_1_m_s,
            contact.friction.decay_speed_2_m_s,
            op.rolling_speed_m_s,
            op.crabbing_velocity_m_s,
            math.inf if lateral_only else contact.hertz_approach_m,
            contact.relaxation_time_s(op.rolling_speed_m_s),
            0.0 if modes is None else static_normal_approach_m(modes, contact, op),
            contact.friction.weight_1,
            contact.friction.weight_2,
        ],
        dtype=float,
    )


def as_modes(modes: Modes) -> tuple[ModalDOF, ...]:
    """A ModalDOF or a sequence of them as a non-empty tuple (TypeError otherwise)."""
    if isinstance(modes, ModalDOF):
        return (modes,)
    modes = tuple(modes)
    if not modes or not all(isinstance(md, ModalDOF) for md in modes):
        raise TypeError("modes must be a ModalDOF or a non-empty sequence of ModalDOF")
    return modes


def mode_arrays(modes: tuple[ModalDOF, ...]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(m, c, k) of the modes as float arrays [kg, N s/m, N/m]."""
    m = np.array([md.mass_kg for md in modes], dtype=float)
    c = np.array([md.damping_ns_m for md in modes], dtype=float)
    k = np.array([md.stiffness_n_m for md in modes], dtype=float)
    return m, c, k


def max_contact_damping_ns_m(contact: ContactLaw, op: OperatingPoint) -> float:
    """Upper bound of W/V0 |dmu/dzeta|, N s/m: the largest viscous-like coefficient
    the friction law can add (slope at zeta = 0 plus the falling factor's largest slope,
    :meth:`FrictionLaw.steepness_s_m`)."""
    dmu = contact.friction_coefficient * (
        contact.normalised_creepage_per_creepage
        + op.rolling_speed_m_s * 2.0 * math.exp(-2.0) * contact.friction.steepness_s_m()
    )
    return contact.normal_load_n / op.rolling_speed_m_s * dmu


def highest_frequency_hz(
    modes: Modes, wheel_speed_rad_s: float = 0.0, normal_stiffness_n_m: float = 0.0
) -> float:
    """The highest frequency [Hz] the contact sees: a mode's natural frequency, plus
    n Omega / 2 pi for a rotating pair (its forward travelling wave), raised by the
    normal contact spring ``normal_stiffness_n_m`` [N/m] where modes move the contact
    normally (a bound: the largest omega^2 plus k_H (|phi_n|^2 + |phi_t| |phi_n|), the
    second for the friction's coupling with mu <= 1)."""
    modes = as_modes(modes)
    f = max(md.frequency_hz + md.nodal_diameters * abs(wheel_speed_rad_s) / (2.0 * math.pi) for md in modes)
    if normal_stiffness_n_m == 0.0 or all(md.normal == 0.0 for md in modes):
        return f
    pn = math.sqrt(sum(md.normal**2 / md.mass_kg for md in modes))
    pt = math.sqrt(sum(md.lateral**2 / md.mass_kg for md in modes))
    return math.sqrt(f * f + normal_stiffness_n_m * (pn * pn + pt * pn) / (2.0 * math.pi) ** 2)


def choose_time_step(
    modes: Modes,
    contact: ContactLaw,
    op: OperatingPoint,
    steps_per_period: int = STEPS_PER_PERIOD,
    wheel_speed_rad_s: float = 0.0,
) -> float:
    """RK4 step, s: the smallest of (i) the period of the highest frequency the contact
    sees divided by ``steps_per_period`` (accuracy; RK4's amplitude error per cycle ~
    (omega h)^6), (ii) 0.5 / lambda with lambda = max contact damping * sum(a_i^2/m_i) +
    max c_i/m_i, which keeps the stiff, strongly damped direction of the creep region
    far inside RK4's stability interval (|lambda h| < 2.78), and (iii) with transient
    creep the lag's time constant (RK4 is stable on it below 2.78 tau)."""
    modes = as_modes(modes)
    if steps_per_period < 8:
        raise ValueError(f"steps_per_period must be >= 8, got {steps_per_period}")
    f_max = highest_frequency_hz(modes, wheel_speed_rad_s, contact.normal_stiffness_n_m)
    h_acc = 1.0 / (f_max * steps_per_period)
    lam = max_contact_damping_ns_m(contact, op) * sum(md.lateral * md.lateral / md.mass_kg for md in modes)
    lam += max(md.damping_ns_m / md.mass_kg for md in modes)
    h_stab = 0.5 / lam if lam > 0 else math.inf
    tau = contact.relaxation_time_s(op.rolling_speed_m_s)
    return min(h_acc, h_stab, tau if tau > 0.0 else math.inf)


def _initial_state(
    initial_state: tuple[ArrayLike, ArrayLike] | None, n_modes: int
) -> tuple[np.ndarray, np.ndarray]:
    if initial_state is None:
        return np.zeros(n_modes), np.zeros(n_modes)
    y0, v0 = initial_state
    y0 = np.broadcast_to(np.asarray(y0, dtype=float), (n_modes,)).copy()
    v0 = np.broadcast_to(np.asarray(v0, dtype=float), (n_modes,)).copy()
    if not (np.all(np.isfinite(y0)) and np.all(np.isfinite(v0))):
        raise ValueError("initial_state must be finite")
    return y0, v0


def _history(
    t: np.ndarray,
    y_modes: np.ndarray,
    v_modes: np.ndarray,
    modes: tuple[ModalDOF, ...],
    contact: ContactLaw,
    op: OperatingPoint,
    step: float,
    method: str,
    coords: Coordinates,
    wheel_speed_rad_s: float,
    mismatch: float = float("nan"),
    lagged_force: np.ndarray | None = None,
) -> TimeHistory:
    p = coords.participation(t)
    pa = p * coords.a[None, :]
    y = (pa * y_modes).sum(axis=1)
    v = (pa * v_modes).sum(axis=1)
    u_n = (p * coords.b[None, :] * y_modes).sum(axis=1)
    x = 1.0 + (u_n - static_normal_approach_m(modes, contact, op)) / contact.hertz_approach_m
    N = contact.normal_load_n * np.where(x > 0.0, x * np.sqrt(np.maximum(x, 0.0)), 0.0)
    zeta = (op.crabbing_velocity_m_s + v) / op.rolling_speed_m_s
    Q = -adhesion_ratio(zeta, contact, op.rolling_speed_m_s) * N if lagged_force is None else lagged_force
    P = Q * v - (coords.c[None, :] * v_modes**2).sum(axis=1)
    return TimeHistory(
        t=t,
        y=y,
        v=v,
        y_modes=y_modes,
        v_modes=v_modes,
        creepage=zeta,
        Q=Q,
        P=P,
        modes=modes,
        contact=contact,
        operating_point=op,
        step_s=float(step),
        method=method,
        energy_mismatch_j=float(mismatch),
        wheel_speed_rad_s=float(wheel_speed_rad_s),
        coordinates=coords,
        u_n=u_n,
        N=N,
    )


def _check_duration(duration: float) -> float:
    duration = float(duration)
    if not math.isfinite(duration) or duration <= 0.0:
        raise ValueError(f"duration must be positive and finite (s), got {duration!r}")
    return duration


@dataclass(frozen=True)
class Integration:
    """How :func:`simulate` integrates and what it keeps.

    Attributes
    ----------
    steps_per_period
        RK4 steps per period of the highest mode (measured: the limit-cycle amplitude
        within 1e-4 of solve_ivp DOP853 at rtol 1e-8 for the Fig. 6 case, within 3e-4
        of a 128-step run over the whole Vc x speed grid).
    step_s
        Force a step [s] instead of :func:`choose_time_step`.
    store_every
        Keep every n-th step in the output (1 = all).
    samples_per_period
        Instead of ``store_every``, keep at least this many samples per period of the
        highest mode (every step when the step is longer; the choice is made again after
        a refinement, so halving the step does not double the record).
    refine, max_refinements
        On detected instability, halve the step up to ``max_refinements`` times; with
        ``refine=False`` raise at once.
    energy_tolerance
        Accepted ``|dE - integral of P dt|`` relative to the largest modal energy
        reached; a larger mismatch (or a non-finite state) means the step is too large
        for the dynamics.
    method
        "rk4", "exponential" (:mod:`reduced.stepping`) or None: the one rule
        (:func:`reduced.integrate.choose_method`).
    """

    steps_per_period: int = STEPS_PER_PERIOD
    step_s: float | None = None
    store_every: int = 1
    samples_per_period: int | None = None
    refine: bool = True
    max_refinements: int = 4
    energy_tolerance: float = 1e-2
    method: str | None = None


def _integrate(
    coords: Coordinates,
    law: np.ndarray,
    y0: np.ndarray,
    u0: np.ndarray,
    h: float,
    n_steps: int,
    store_every: int,
    n_out: int,
) -> tuple[int, float, float, np.ndarray, np.ndarray, np.ndarray]:
    """One RK4 run of ``n_steps`` steps of ``h`` [s]: (status, energy mismatch [J], the
    largest modal energy [J], stored y, stored y', stored lagged force). The paper's
    one-mode model takes the scalar kernel."""
    m, c, k, w, phase, a, b = coords.m, coords.c, coords.k, coords.w, coords.phase, coords.a, coords.b
    n_coord = len(m)
    out_y = np.empty((n_out, n_coord))
    out_u = np.empty((n_out, n_coord))
    out_q = np.full(n_out, np.nan)
    lag = law[_kernels.LAW_TAU] > 0.0
    if n_coord == 1 and w[0] == 0.0 and a[0] == 1.0 and b[0] == 0.0 and not lag:
        kernels = _engine.integration_kernels(n_steps)
        status, mismatch, emax, _work, _done = kernels.integrate_store_1(
            *(float(x[0]) for x in (y0, u0, m, c, k)),
            tuple(law.tolist()),
            h,
            n_steps,
            store_every,
            out_y[:, 0],
            out_u[:, 0],
        )
    else:
        kernels = _engine.integration_kernels(n_steps, scalar=False)
        status, mismatch, emax, _work, _done = kernels.integrate_store(
            y0, u0, m, c, k, a, b, w, phase, law, h, n_steps, store_every, out_y, out_u, out_q
        )
    return status, mismatch, emax, out_y, out_u, out_q


def simulate_rk4(
    modes: Modes,
    contact: ContactLaw,
    operating_point: OperatingPoint,
    duration: float,
    initial_state: tuple[ArrayLike, ArrayLike] | None = None,
    *,
    wheel_speed_rad_s: float = 0.0,
    integration: Integration | None = None,
    body: Any = None,
    **changes: Any,
) -> TimeHistory:
    """Integrate the modal squeal model with fixed-step RK4, the paper's explicit scheme
    (:func:`reduced.simulate` chooses between it and the exponential integrator; see
    :mod:`reduced._engine` for when it runs compiled).

    Parameters
    ----------
    modes : a ModalDOF or a sequence of them, all driven by the same contact force.
    contact : creep-law parameters.
    operating_point : rolling speed and crabbing velocity.
    duration : simulated time, s.
    initial_state : None (rest: y = 0, y' = 0) or (y0, v0) per coordinate
        (:func:`coordinates`) in m and m/s.
    wheel_speed_rad_s : Omega, rad/s: with a turning wheel each pair (n of 1 or more
        nodal diameters) is two coordinates seen at the contact through cos(n Omega t)
        and -sin(n Omega t); 0, the paper's model, leaves them out.
    integration : the step and the record (:class:`Integration`); ``changes`` replace
        its fields, as in ``simulate(..., store_every=4)``.
    body : must be None or without terms (RK4 integrates no counter-body).

    Returns
    -------
    TimeHistory

    Raises
    ------
    IntegrationError
        If the integration cannot be made stable and consistent.
    ValueError
        Before integrating, if the output would exceed ``MAX_STORED_SAMPLES`` samples
        (very stiff or light modes over long durations: raise ``store_every``).
    """
    opts = replace(integration or Integration(), **changes)
    if body is not None and body.terms:
        raise ValueError("RK4 integrates no counter-body: the exponential integrator does (reduced.stepping)")
    steps_per_period, step_s, store_every = opts.steps_per_period, opts.step_s, opts.store_every
    samples_per_period, refine, max_refinements = opts.samples_per_period, opts.refine, opts.max_refinements
    energy_tolerance = opts.energy_tolerance
    modes = as_modes(modes)
    duration = _check_duration(duration)
    if store_every < 1:
        raise ValueError(f"store_every must be >= 1, got {store_every}")
    if samples_per_period is not None and samples_per_period < 2:
        raise ValueError(f"samples_per_period must be >= 2, got {samples_per_period}")
    coords = coordinates(modes, wheel_speed_rad_s)
    n_coord = len(coords.m)
    law = law_vector(contact, operating_point, modes)
    y0, u0 = _initial_state(initial_state, n_coord)
    h = (
        choose_time_step(modes, contact, operating_point, steps_per_period, wheel_speed_rad_s)
        if step_s is None
        else float(step_s)
    )
    if not (math.isfinite(h) and h > 0.0):
        raise ValueError(f"step_s must be positive and finite, got {step_s!r}")
    attempts = 1 + (max_refinements if refine else 0)
    f_max = highest_frequency_hz(modes, wheel_speed_rad_s, contact.normal_stiffness_n_m)
    for attempt in range(attempts):
        n_steps = int(math.ceil(duration / h - 1e-9))
        h_eff = duration / n_steps
        if samples_per_period is not None:
            store_every = max(1, int(1.0 / (f_max * h_eff * samples_per_period)))
        n_out = n_steps // store_every + 1
        _check_storage(
            n_out,
            n_coord,
            n_steps,
            h_eff,
            duration,
            store_every,
            f_max,
            ValueError if attempt == 0 else IntegrationError,
        )
        status, mismatch, emax, out_y, out_u, out_q = _integrate(
            coords, law, y0, u0, h_eff, n_steps, store_every, n_out
        )
        ok = status == 0 and mismatch <= energy_tolerance * emax + 1e-300
        if ok:
            t = np.arange(n_out) * (h_eff * store_every)
            return _history(
                t,
                out_y,
                out_u,
                modes,
                contact,
                operating_point,
                h_eff,
                "rk4",
                coords,
                wheel_speed_rad_s,
                mismatch,
                out_q if contact.relaxation_length_m > 0.0 else None,
            )
        reason = (
            "non-finite state"
            if status != 0
            else f"energy balance violated (|dE - int P dt| = {mismatch:.3g} J vs max energy {emax:.3g} J)"
        )
        h = 0.5 * h_eff
    raise IntegrationError(
        f"RK4 integration unstable with step {h_eff:.3g} s ({reason}) after {attempts} attempt(s); "
        f"reduce step_s / raise steps_per_period, or check the parameters "
        f"(contact damping up to {max_contact_damping_ns_m(contact, operating_point):.3g} N s/m)"
    )


def simulate_reference(
    modes: Modes,
    contact: ContactLaw,
    operating_point: OperatingPoint,
    duration: float,
    initial_state: tuple[ArrayLike, ArrayLike] | None = None,
    *,
    method: str = "DOP853",
    rtol: float = 1e-8,
    samples_per_period: int = 64,
    wheel_speed_rad_s: float = 0.0,
) -> TimeHistory:
    """Reference integration with scipy.integrate.solve_ivp (adaptive, tight tolerance),
    the same model as :func:`simulate` (rotation, the normal contact and transient
    creep included) on a Python right-hand side.

    Output on a uniform grid of ``samples_per_period`` points per period of the
    highest mode (dense output). atol is 1e-14 m on displacements, 1e-10 m/s on
    velocities. Slow (pure-Python right-hand side): for validation and benchmarks.
    """
    from scipy.integrate import solve_ivp

    modes = as_modes(modes)
    duration = _check_duration(duration)
    coords = coordinates(modes, wheel_speed_rad_s)
    m, c, k, w, phase, a, b = coords.m, coords.c, coords.k, coords.w, coords.phase, coords.a, coords.b
    n = len(m)
    load, approach = contact.normal_load_n, contact.hertz_approach_m
    static = static_normal_approach_m(modes, contact, operating_point)
    tau = contact.relaxation_time_s(operating_point.rolling_speed_m_s)
    law = tuple(law_vector(contact, operating_point, modes).tolist())
    mu = _kernels.adhesion  # the production path's creep law, interpreted

    def forces(t: float, y: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, float, float]:
        p = np.cos(w * t + phase)
        x = 1.0 + (float((p * b) @ y) - static) / approach
        normal = load * x**1.5 if x > 0.0 else 0.0
        return p, normal, -mu(float((p * a) @ u), law) * normal

    def rhs(t: float, s: np.ndarray) -> np.ndarray:
        y, u = s[:n], s[n : 2 * n]
        p, normal, q = forces(t, y, u)
        lag = [] if tau == 0.0 else [(q - s[2 * n]) / tau]
        q = q if tau == 0.0 else s[2 * n]
        return np.concatenate([u, (p * (a * q - b * (normal - load)) - c * u - k * y) / m, lag])

    y0, u0 = _initial_state(initial_state, n)
    f_max = highest_frequency_hz(modes, wheel_speed_rad_s, contact.normal_stiffness_n_m)
    n_out = int(math.ceil(duration * f_max * samples_per_period)) + 1
    t_eval = np.linspace(0.0, duration, n_out)
    q0 = [] if tau == 0.0 else [forces(0.0, y0, u0)[2]]
    atol = np.concatenate([np.full(n, 1e-14), np.full(n, 1e-10), np.full(len(q0), 1e-8)])
    sol = solve_ivp(
        rhs, (0.0, duration), np.concatenate([y0, u0, q0]), method=method, t_eval=t_eval, rtol=rtol, atol=atol
    )
    if not sol.success:
        raise IntegrationError(f"solve_ivp({method}) failed: {sol.message}")
    return _history(
        sol.t,
        sol.y[:n].T.copy(),
        sol.y[n : 2 * n].T.copy(),
        modes,
        contact,
        operating_point,
        duration / (n_out - 1),
        method,
        coords,
        wheel_speed_rad_s,
        lagged_force=sol.y[2 * n].copy() if tau > 0.0 else None,
    )
