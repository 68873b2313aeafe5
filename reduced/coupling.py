"""The contact in two directions: the linear stability of modes that move the contact
point both laterally (t) and normally (n), and which mechanism makes an eigenvalue grow.

With mass-normalised modal coordinates q and each mode's components at the contact,
``phi_t`` (lateral tangent) and ``phi_n`` (normal, towards the counter-body), the normal
force follows the Hertz spring, ``N = W + k_H u_n`` with ``u_n = phi_n . q`` (a rigid,
fixed counter-body), and the lateral creep force ``Q = -mu(zeta) N``. Linearised about
steady sliding at ``zeta0 = Vc / V0`` (``mu0 = mu(zeta0)``, ``g = (W / V0) dmu/dzeta``):

    q'' + (C + g phi_t phi_t^T) q' + (K + k_H phi_n phi_n^T + mu0 k_H phi_t phi_n^T) q = 0

The velocity term with ``g < 0`` is falling friction; the last stiffness term is not
symmetric: it is mode coupling (two modes whose contact-stiffened frequencies merge
into a growing pair). The eigenvalues hold both; :func:`coupled_stability` also solves
the system with either term alone, so that each growing eigenvalue is given the
mechanism that makes it grow. With ``phi_n = 0`` the model is the paper's lateral one
(:func:`reduced.linear_stability`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np

from .creep import ContactLaw, adhesion_ratio
from .model import OperatingPoint
from .stability import friction_damping_ns_m

__all__ = [
    "ContactMode",
    "CoupledStability",
    "TwoDirectionHistory",
    "coupled_stability",
    "coupling_matrices",
    "simulate_two_directions",
    "two_mode_coalesces",
]

Mechanism = Literal["falling friction", "mode coupling", "both"]


@dataclass(frozen=True)
class ContactMode:
    """A mode as the contact sees it: natural frequency [Hz], damping ratio [-], and its
    mass-normalised displacement components at the contact point [1/sqrt(kg)] along the
    lateral tangent (``phi_t``: 1/sqrt(m) of the lateral modal mass m) and the normal."""

    frequency_hz: float
    damping_ratio: float
    phi_t: float
    phi_n: float = 0.0

    @property
    def omega_rad_s(self) -> float:
        return 2.0 * math.pi * self.frequency_hz


def coupling_matrices(
    modes: Sequence[ContactMode],
    friction_damping_ns_m: float,
    adhesion_ratio_now: float,
    normal_stiffness_n_m: float,
    falling: bool = True,
    coupling: bool = True,
) -> tuple[np.ndarray, np.ndarray]:
    """(D, S) of ``q'' + D q' + S q = 0``: ``falling`` keeps the friction damping term,
    ``coupling`` the non-symmetric friction stiffness term (see the module docstring)."""
    w = np.array([m.omega_rad_s for m in modes])
    zeta = np.array([m.damping_ratio for m in modes])
    pt = np.array([m.phi_t for m in modes])
    pn = np.array([m.phi_n for m in modes])
    damping = np.diag(2.0 * zeta * w)
    if falling:
        damping = damping + friction_damping_ns_m * np.outer(pt, pt)
    stiffness = np.diag(w**2) + normal_stiffness_n_m * np.outer(pn, pn)
    if coupling:
        stiffness = stiffness + adhesion_ratio_now * normal_stiffness_n_m * np.outer(pt, pn)
    return damping, stiffness


def _eigenvalues(damping: np.ndarray, stiffness: np.ndarray) -> np.ndarray:
    n = len(damping)
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-stiffness, -damping]])
    lam = np.linalg.eigvals(a)
    return lam[lam.imag >= 0.0]


@dataclass(frozen=True)
class CoupledStability:
    """The eigenvalues of the two-direction model with Im >= 0 [1/s], fastest-growing
    first, and for each: ``frequency_hz``, ``growth_rate_1_s`` and the ``mechanism`` that
    makes it grow ("falling friction" if it grows with the friction damping alone,
    "mode coupling" if with the coupling stiffness alone, "both" if only together; None
    where it decays)."""

    eigenvalues: np.ndarray
    mechanisms: tuple[Mechanism | None, ...]
    friction_damping_ns_m: float
    adhesion_ratio: float
    normal_stiffness_n_m: float

    @property
    def growth_rate_1_s(self) -> np.ndarray:
        return self.eigenvalues.real

    @property
    def frequency_hz(self) -> np.ndarray:
        return self.eigenvalues.imag / (2.0 * math.pi)

    @property
    def unstable(self) -> bool:
        return bool(np.any(self.growth_rate_1_s > 0.0))


def coupled_stability(
    modes: Sequence[ContactMode],
    contact: ContactLaw,
    op: OperatingPoint,
    normal_stiffness_n_m: float,
) -> CoupledStability:
    """The linear stability of ``modes`` on a rigid, fixed counter-body through a Hertz
    spring of ``normal_stiffness_n_m`` [N/m] (``reduced.HertzContact.normal_stiffness_n_m``)."""
    g = friction_damping_ns_m(contact, op)
    mu0 = float(adhesion_ratio(op.creepage, contact, op.rolling_speed_m_s))
    args = (modes, g, mu0, normal_stiffness_n_m)
    lam = _eigenvalues(*coupling_matrices(*args))
    order = np.argsort(-lam.real)
    lam = lam[order]
    alone: list[tuple[Mechanism, np.ndarray]] = [
        ("falling friction", _eigenvalues(*coupling_matrices(*args, coupling=False))),
        ("mode coupling", _eigenvalues(*coupling_matrices(*args, falling=False))),
    ]
    mechanisms: list[Mechanism | None] = []
    for x in lam:
        if x.real <= 0.0:
            mechanisms.append(None)
            continue
        # the same eigenvalue in each one-term system: the one nearest in frequency
        grows = [k for k, ev in alone if ev[np.argmin(np.abs(ev.imag - x.imag))].real > 0.0]
        mechanisms.append(grows[0] if len(grows) == 1 else "both")
    return CoupledStability(lam, tuple(mechanisms), g, mu0, normal_stiffness_n_m)


def two_mode_coalesces(stiffness: np.ndarray) -> bool:
    """Whether two undamped modes with the (non-symmetric) stiffness matrix ``stiffness``
    form a growing pair: the eigenvalues of S are complex, ``(S11 - S22)^2 + 4 S12 S21 <
    0`` (which needs S12 S21 < 0)."""
    s = np.asarray(stiffness, float)
    return bool((s[0, 0] - s[1, 1]) ** 2 + 4.0 * s[0, 1] * s[1, 0] < 0.0)


@dataclass(frozen=True)
class TwoDirectionHistory:
    """A time history of the two-direction model (:func:`simulate_two_directions`).

    t [s]; q, qd (n, N): the mass-normalised modal coordinates and their rates; v_t,
    u_n [m/s, m]: the lateral velocity and the normal approach at the contact;
    normal_force_n, lateral_force_n [N]: N and Q; separated: where N = 0 (the surfaces
    apart); energy_j: the modes' energy plus the Hertz spring's stored energy [J];
    power_w: Q v_t minus the modal damping losses [W] (its integral is the change of
    energy_j)."""

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    v_t: np.ndarray
    u_n: np.ndarray
    normal_force_n: np.ndarray
    lateral_force_n: np.ndarray
    separated: np.ndarray
    energy_j: np.ndarray
    power_w: np.ndarray


def simulate_two_directions(
    modes: Sequence[ContactMode],
    contact: ContactLaw,
    op: OperatingPoint,
    approach_m: float,
    duration_s: float,
    steps_per_period: int = 64,
    kick: float | None = None,
) -> TwoDirectionHistory:
    """Integrate the modes from rest with the contact in both directions (RK4).

    The normal force follows Hertz about the static approach ``approach_m`` (delta0,
    ``reduced.HertzContact.approach_m``): N = W (1 + u_n/delta0)^(3/2), 0 once the
    surfaces separate (u_n < -delta0); the static preload W is balanced by that
    approach, so the modes carry N - W. The lateral force is the creep law's
    Q = -mu(zeta) N with zeta = (Vc + v_t)/V0, applied from t = 0 as in the paper's
    model (its step starts the oscillation). With phi_n = 0 these are the paper's
    N-mode equations. ``kick``: None starts from rest (the paper's start: the creep
    force's step excites the modes); a number starts at the linearised static
    equilibrium with every modal rate equal to ``kick`` [sqrt(kg) m/s], small enough to
    stay linear while an instability grows. Plain NumPy: for the checks of the linear
    model, not for sweeps.
    """
    w = np.array([m.omega_rad_s for m in modes])
    c = 2.0 * np.array([m.damping_ratio for m in modes]) * w
    pt = np.array([m.phi_t for m in modes])
    pn = np.array([m.phi_n for m in modes])
    load = contact.normal_load_n
    v0, vc = op.rolling_speed_m_s, op.crabbing_velocity_m_s

    def forces(q: np.ndarray, qd: np.ndarray) -> tuple[float, float]:
        u = float(pn @ q)
        normal = load * (1.0 + u / approach_m) ** 1.5 if u > -approach_m else 0.0
        zeta = (vc + float(pt @ qd)) / v0
        return normal, -float(adhesion_ratio(zeta, contact, v0)) * normal

    def accel(q: np.ndarray, qd: np.ndarray, normal: float, lateral: float) -> np.ndarray:
        return -c * qd - w**2 * q - (normal - load) * pn + lateral * pt

    def rhs(q: np.ndarray, qd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return qd, accel(q, qd, *forces(q, qd))

    h = 2.0 * math.pi / (w.max() * steps_per_period)
    n = int(math.ceil(duration_s / h))
    h = duration_s / n
    q: np.ndarray = np.zeros(len(modes))
    qd: np.ndarray = np.zeros(len(modes))
    if kick is not None:
        mu0 = float(adhesion_ratio(op.creepage, contact, v0))
        k_h = 1.5 * load / approach_m
        stiffness = np.diag(w**2) + k_h * np.outer(pn, pn) + mu0 * k_h * np.outer(pt, pn)
        q = np.linalg.solve(stiffness, -mu0 * load * pt)
        qd = np.full(len(modes), float(kick))
    qs, qds = np.empty((n + 1, len(modes))), np.empty((n + 1, len(modes)))
    f = np.empty((n + 1, 2))  # (N, Q) at each stored state
    qs[0], qds[0] = q, qd
    for k in range(n):
        f[k] = forces(q, qd)  # the first stage's forces: kept, not evaluated twice
        a1, b1 = qd, accel(q, qd, f[k, 0], f[k, 1])
        a2, b2 = rhs(q + 0.5 * h * a1, qd + 0.5 * h * b1)
        a3, b3 = rhs(q + 0.5 * h * a2, qd + 0.5 * h * b2)
        a4, b4 = rhs(q + h * a3, qd + h * b3)
        q = q + h / 6.0 * (a1 + 2 * a2 + 2 * a3 + a4)
        qd = qd + h / 6.0 * (b1 + 2 * b2 + 2 * b3 + b4)
        qs[k + 1], qds[k + 1] = q, qd
    f[n] = forces(q, qd)
    u_n, v_t = qs @ pn, qds @ pt
    x = np.maximum(1.0 + u_n / approach_m, 0.0)
    # the Hertz spring's energy above the static state: integral of (N - W) du_n
    hertz = load * approach_m * (0.4 * x**2.5 - 0.4) - load * u_n
    energy = 0.5 * np.sum(qds**2 + (w * qs) ** 2, axis=1) + hertz
    power = f[:, 1] * v_t - np.sum(c * qds**2, axis=1)
    t = np.arange(n + 1) * h
    return TwoDirectionHistory(t, qs, qds, v_t, u_n, f[:, 0], f[:, 1], f[:, 0] == 0.0, energy, power)
