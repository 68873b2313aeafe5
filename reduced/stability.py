"""Linear stability of every mode at an operating point: which mode squeals.

Linearised about steady sliding at the quasi-static creepage zeta0 = Vc/V0, the contact
force is ``Q = Q0 - g v`` with the friction damping ``g = (W/V0) dmu/dzeta(zeta0)`` [N s/m]
(the full slope of Eq. 3, the falling factor included; g < 0 on the falling branch)
and ``v`` the contact velocity. The N modes seen at the contact then obey

    M q'' + (D + g b a^T) q' + (S + g b e^T) q = 0,

a rank-one coupling through the contact. Without rotation ``q`` are the modal
coordinates, ``D = C``, ``S = K``, ``a = b = 1`` and ``e = 0`` (MODEL.md section 7). With
the wheel turning at Omega, a mode with n >= 1 nodal diameters is a pair whose
coordinates in the frame of the (fixed) contact, ``x`` and ``w``, see Coriolis-like
terms (MODEL.md section 8, written for p = (a + i b) e^{i n Omega t}):

    m x'' + c x' + 2 m n Omega w' + (k - m n^2 Omega^2) x + c n Omega w = Q
    m w'' + c w' - 2 m n Omega x' + (k - m n^2 Omega^2) w - c n Omega x = 0

with the contact velocity ``v = x' + n Omega w``. Gyroscopic and centrifugal terms of
the wheel itself are neglected (of order Omega / w0, about 1 %). Its 2N (or 2N + 2 per
pair) eigenvalues ``sigma + i omega_d`` are those of a real matrix; each is assigned to
the mode that holds most of its vibration energy.

Per mode (:class:`ModeStability`): the growth rate sigma [1/s] (the largest of the
mode's eigenvalues: a pair under rotation has two travelling waves at f0 -/+ n Omega /
2 pi), the damped frequency [Hz], the critical damping ratio (the modal damping ratio
above which the mode is stable at this point, the others as given) and the critical
friction slope (the dmu/dzeta at zeta0 above which it is stable). For a mode far from
the others in frequency these tend to ``sigma = -(c + g) / (2 m)`` (``-(c + g/2) / (2 m)``
for a rotating pair when n Omega >> |sigma|), ``zeta_crit = -g / (2 m w)`` and
``dmu/dzeta_crit = -c V0 / W``; near another mode the coupling moves them, and the
exact values are found by root finding on the coupled eigenvalues.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ._numerics import find_root
from .creep import ContactLaw, adhesion_ratio_slope
from .model import ModalDOF, OperatingPoint, as_modes

__all__ = [
    "ModeStability",
    "StabilityResult",
    "friction_damping_ns_m",
    "growth_rates",
    "linear_stability",
]


def friction_damping_ns_m(contact: ContactLaw, op: OperatingPoint) -> float:
    """g = (W / V0) dmu/dzeta at the quasi-static creepage [N s/m] (< 0: destabilising)."""
    slope = float(adhesion_ratio_slope(op.creepage, contact, op.rolling_speed_m_s))
    return contact.normal_load_n / op.rolling_speed_m_s * slope


@dataclass(frozen=True)
class ModeStability:
    """One mode's linear stability at an operating point (see the module docstring).

    growth_rate_1_s : sigma, 1/s (> 0: the mode grows, it can squeal).
    damped_frequency_hz : the frequency of its fastest-growing eigenvalue, Hz (in the
        frame of the contact: f0 -/+ n Omega / 2 pi for a rotating pair).
    critical_damping_ratio : modal damping ratio above which it is stable here (0 if it
        is stable without damping).
    critical_friction_slope : dmu/dzeta at zeta0 above which it is stable here.
    """

    growth_rate_1_s: float
    damped_frequency_hz: float
    critical_damping_ratio: float
    critical_friction_slope: float

    @property
    def unstable(self) -> bool:
        return self.growth_rate_1_s > 0.0


@dataclass(frozen=True)
class StabilityResult:
    """The linear stability of every mode at one operating point.

    modes : one :class:`ModeStability` per input mode, in input order.
    eigenvalues : every eigenvalue of the coupled system with Im >= 0, 1/s.
    friction_damping_ns_m : g, N s/m.
    wheel_speed_rad_s : Omega (0: rotation off), rad/s.
    """

    modes: tuple[ModeStability, ...]
    eigenvalues: np.ndarray
    friction_damping_ns_m: float
    wheel_speed_rad_s: float

    @property
    def winner(self) -> int:
        """Index of the fastest-growing mode."""
        return int(np.argmax([m.growth_rate_1_s for m in self.modes]))

    @property
    def growth_rate_1_s(self) -> float:
        """The largest growth rate of the system, 1/s."""
        return max(m.growth_rate_1_s for m in self.modes)


# --------------------------------------------------------------------------------------
# the coupled linear system
# --------------------------------------------------------------------------------------
def _blocks(modes: Sequence[ModalDOF], wheel_speed_rad_s: float) -> list[tuple[int, int]]:
    """(first coordinate, number of coordinates) of each mode: 2 for a rotating pair."""
    out, at = [], 0
    for md in modes:
        size = 2 if (wheel_speed_rad_s != 0.0 and md.nodal_diameters >= 1) else 1
        out.append((at, size))
        at += size
    return out


def _state_matrix(
    modes: Sequence[ModalDOF],
    damping: np.ndarray,
    g: float,
    wheel_speed_rad_s: float,
    blocks: list[tuple[int, int]],
) -> np.ndarray:
    """A of z' = A z, z = (q, q'), for the modes with dampings ``damping`` [N s/m]."""
    nq = sum(size for _, size in blocks)
    M, D, S = np.zeros(nq), np.zeros((nq, nq)), np.zeros((nq, nq))
    a, b, e = np.zeros(nq), np.zeros(nq), np.zeros(nq)
    for md, c, (i, size) in zip(modes, damping, blocks):
        m, k = md.mass_kg, md.stiffness_n_m
        M[i : i + size] = m
        a[i] = b[i] = 1.0
        if size == 1:
            D[i, i], S[i, i] = c, k
            continue
        w = md.nodal_diameters * wheel_speed_rad_s  # n Omega
        D[i : i + 2, i : i + 2] = [[c, 2 * m * w], [-2 * m * w, c]]
        S[i : i + 2, i : i + 2] = [[k - m * w * w, c * w], [-c * w, k - m * w * w]]
        e[i + 1] = w
    D += g * np.outer(b, a)
    S += g * np.outer(b, e)
    A = np.zeros((2 * nq, 2 * nq))
    A[:nq, nq:] = np.eye(nq)
    A[nq:, :nq] = -S / M[:, None]
    A[nq:, nq:] = -D / M[:, None]
    return A


def _mode_eigenvalues(modes, damping, g, wheel_speed_rad_s, blocks):
    """Eigenvalues with Im >= 0, and for each mode the ones assigned to it."""
    A = _state_matrix(modes, damping, g, wheel_speed_rad_s, blocks)
    lam, vec = np.linalg.eig(A)
    keep = lam.imag >= 0.0
    lam, vec = lam[keep], vec[:, keep]
    nq = A.shape[0] // 2
    q = vec[:nq]
    k = np.concatenate([[md.stiffness_n_m] * size for md, (_, size) in zip(modes, blocks)])
    m = np.concatenate([[md.mass_kg] * size for md, (_, size) in zip(modes, blocks)])
    energy = (k[:, None] + m[:, None] * np.abs(lam[None, :]) ** 2) * np.abs(q) ** 2  # (nq, n_lambda)
    per_mode = np.array([energy[i : i + size].sum(axis=0) for i, size in blocks])  # (modes, n_lambda)
    share = per_mode / np.maximum(per_mode.sum(axis=0, keepdims=True), 1e-300)
    capacity = [size for _, size in blocks]
    assigned: list[list[int]] = [[] for _ in modes]
    taken = np.zeros(len(lam), dtype=bool)
    for flat in np.argsort(-share, axis=None):
        i, j = np.unravel_index(flat, share.shape)
        if not taken[j] and len(assigned[i]) < capacity[i]:
            assigned[i].append(int(j))
            taken[j] = True
    return lam, assigned


def growth_rates(modes, damping, g: float, wheel_speed_rad_s: float = 0.0) -> np.ndarray:
    """sigma [1/s] of each mode for dampings ``damping`` [N s/m] and friction damping g."""
    modes = as_modes(modes)
    blocks = _blocks(modes, wheel_speed_rad_s)
    lam, assigned = _mode_eigenvalues(modes, np.asarray(damping, float), g, wheel_speed_rad_s, blocks)
    return np.array([max((lam[j].real for j in js), default=-math.inf) for js in assigned])


def _decreasing_root(fn, lo: float, hi: float, floor: float = -math.inf) -> float:
    """The root of a decreasing ``fn``: the bracket [lo, hi] is widened (never below
    ``floor``) until fn(lo) > 0 > fn(hi), then refined by Brent's method; ``floor`` if
    fn is already <= 0 there."""
    for _ in range(80):
        f_lo = fn(lo)
        if f_lo > 0.0:
            break
        if lo <= floor:
            return floor
        lo = max(floor, lo - 2.0 * (hi - lo))
    else:
        return -math.inf
    for _ in range(80):
        if fn(hi) < 0.0:
            return find_root(fn, lo, hi, xtol=1e-15, rtol=1e-10)
        lo, hi = hi, hi + 2.0 * (hi - lo)
    return math.inf


def linear_stability(
    modes, contact: ContactLaw, op: OperatingPoint, wheel_speed_rad_s: float = 0.0
) -> StabilityResult:
    """The linear stability of every mode at ``op`` (see the module docstring).

    ``modes``: a ModalDOF or a sequence of them (all seen at the same contact point);
    ``wheel_speed_rad_s``: Omega, rotation of the wheel [rad/s] (0: the paper's model,
    no rotation; a rotating wheel needs the modes' ``nodal_diameters``).
    """
    modes = as_modes(modes)
    g = friction_damping_ns_m(contact, op)
    damping = np.array([md.damping_ns_m for md in modes])
    blocks = _blocks(modes, wheel_speed_rad_s)
    lam, assigned = _mode_eigenvalues(modes, damping, g, wheel_speed_rad_s, blocks)
    scale = contact.normal_load_n / op.rolling_speed_m_s  # g per unit of dmu/dzeta
    result = []
    for i, md in enumerate(modes):
        js = assigned[i]
        j = max(js, key=lambda jj: lam[jj].real)
        sigma, fd = float(lam[j].real), float(abs(lam[j].imag)) / (2 * math.pi)
        crit_c = math.sqrt(md.stiffness_n_m * md.mass_kg)  # c = 2 zeta crit_c

        def sigma_at_zeta(zeta: float, i=i, crit_c=crit_c) -> float:
            d = damping.copy()
            d[i] = 2.0 * zeta * crit_c
            return float(growth_rates(modes, d, g, wheel_speed_rad_s)[i])

        def sigma_at_slope(slope: float, i=i) -> float:
            return float(growth_rates(modes, damping, scale * slope, wheel_speed_rad_s)[i])

        zeta_sep = -g / (2.0 * crit_c)  # the separated-mode values: the first bracket
        zeta_crit = _decreasing_root(sigma_at_zeta, 0.0, max(2.0 * zeta_sep, 1e-6), floor=0.0)
        slope_sep = -md.damping_ns_m / scale
        width = abs(slope_sep) + 1e-3
        slope_crit = _decreasing_root(sigma_at_slope, slope_sep - width, slope_sep + width)
        result.append(ModeStability(sigma, fd, zeta_crit, slope_crit))
    return StabilityResult(tuple(result), lam, g, float(wheel_speed_rad_s))
