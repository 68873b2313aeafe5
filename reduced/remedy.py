"""What stops a squeal at one operating point, for the whole wheel: the levers that make
every eigenvalue of the linear model (:mod:`reduced.stability`) decay, each found on the
coupled eigenvalues and each checked by solving them again with it applied.

- **Damping** (:func:`damping_to_stop`): round by round, the fastest-growing eigenvalue's
  modes (those holding at least ``PARTNER_SHARE`` of its energy) have their damping
  ratios raised together by the least amount with which no eigenvalue they take part in
  grows; then the next growing eigenvalue, until none grows. A falling-friction mode far
  from the others gets its critical damping ratio; a coalesced pair both partners'
  raised alike (one partner's damping hardly moves a coalesced pair). The ratios are
  rounded up to two significant digits, as a user writes them, and checked.
- **Friction coefficient** (:func:`friction_coefficient_to_stop`): mu_s (and mu_0 in
  proportion) lowered until nothing grows: the friction modifier's target.
- **Creep-curve slope** (:func:`friction_slope_to_stop`): dmu/dzeta at the quasi-static
  creepage above which nothing grows.
- **Frequency separation** (:func:`separation_to_stop`): for a coupled pair, the
  frequency the higher partner must reach for the pair to separate and decay.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np

from contact.creep import ContactLaw

from .counter_body import BodyModel
from .model import ModalDOF, Modes, OperatingPoint, as_modes
from .stability import MAX_DAMPING_RATIO, PARTNER_SHARE, LinearContact, eigen_shares, largest_growth_rate

__all__ = [
    "DECAY_RATE_1_S",
    "DampingRemedy",
    "damping_to_stop",
    "friction_coefficient_to_stop",
    "friction_slope_to_stop",
    "held_growth_rates",
    "remedy_solves",
    "round_up",
    "separation_to_stop",
]

#: The damping remedy aims at eigenvalues decaying at least this fast [1/s], not merely
#: at zero: damping on the stability boundary would leave an oscillation that dies over
#: minutes, which a time-domain check (and a rig) cannot tell from a squeal; it costs a
#: damping ratio of 1 / (2 pi f) more (1.4e-4 at 1.1 kHz). The friction levers are
#: bounds (nothing grows below them) rounded to two digits on the safe side.
DECAY_RATE_1_S = 1.0

#: Relative width to which each lever is bisected (its value is then rounded outwards)
_RTOL = 1e-3


def round_up(x: float, digits: int = 2) -> float:
    """``x`` > 0 rounded up to ``digits`` significant digits (0.001648 -> 0.0017): a
    value a user writes that is never below the one found."""
    if not (x > 0.0 and math.isfinite(x)):
        return x
    step = 10.0 ** (math.floor(math.log10(x)) - digits + 1)
    return float(round(math.ceil(x / step * (1 - 1e-12)) * step, 12))


def _round_down(x: float, digits: int = 2) -> float:
    step = 10.0 ** (math.floor(math.log10(x)) - digits + 1)
    return float(round(math.floor(x / step * (1 + 1e-12)) * step, 12))


def _with_ratios(modes: Sequence[ModalDOF], zeta: np.ndarray) -> list[ModalDOF]:
    return [md.with_damping_ratio(float(z)) for md, z in zip(modes, zeta)]


def _bisect_to_stable(grows: Callable[[float], float], lo: float, hi: float, limit: float) -> float | None:
    """The least x in [lo, limit] at which ``grows(x)`` <= 0 (``grows(lo)`` > 0), to
    :data:`_RTOL`: ``hi`` doubled until it is stable (None if not by ``limit``), then bisected."""
    while grows(hi) > 0.0:
        lo, hi = hi, 2.0 * hi
        if hi > limit:
            if grows(limit) > 0.0:
                return None
            hi = limit
            break
    while hi - lo > _RTOL * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if grows(mid) > 0.0 else (lo, mid)
    return hi


@dataclass(frozen=True)
class DampingRemedy:
    """Damping ratios with which no eigenvalue grows (:func:`damping_to_stop`).

    Attributes
    ----------
    damping_ratio : numpy.ndarray
        Per degree of freedom, the ratio [-]: raised where it had to be (rounded up to
        two significant digits), the present one elsewhere.
    raised : tuple of int
        The degrees of freedom whose ratio was raised.
    growth_rate_1_s : float
        The largest growth rate with these ratios [1/s] of the eigenvalues a wheel mode
        takes part in.
    settled : bool
        Whether every eigenvalue, the counter-body's own included, decays at least at
        :data:`DECAY_RATE_1_S` with them (False: ``reason`` says what is left).
    reason : str
    counter_body_growth_rate_1_s : float
        The largest growth rate [1/s] of the eigenvalues no adjustable mode takes part in
        (a counter-body's own, which no damping of the wheel moves; -inf: none).
    """

    damping_ratio: np.ndarray
    raised: tuple[int, ...]
    growth_rate_1_s: float
    settled: bool
    reason: str = ""
    counter_body_growth_rate_1_s: float = -math.inf


def damping_to_stop(
    modes: Modes,
    contact: ContactLaw,
    op: OperatingPoint,
    wheel_speed_rad_s: float = 0.0,
    adjustable: Sequence[int] | None = None,
    max_rounds: int | None = None,
    body: BodyModel | None = None,
) -> DampingRemedy:
    """The damping ratios with which no eigenvalue grows at ``op`` (module docstring).

    Parameters
    ----------
    modes : ModalDOF or sequence of them
    contact : ContactLaw
    op : OperatingPoint
    wheel_speed_rad_s : float
        Omega [rad/s] (0: no rotation).
    adjustable : sequence of int, optional
        The modes whose damping a remedy may raise (default all).
    max_rounds : int, optional
        Most rounds (default twice the number of modes, plus 4).
    body : BodyModel, optional
        The counter-body (its own eigenvalues no damping of the wheel moves).

    Returns
    -------
    DampingRemedy

    Examples
    --------
    >>> from reduced import ModalDOF, ContactLaw, OperatingPoint
    >>> m = ModalDOF.from_damping_ratio(3.1, 3.1 * (2 * 3.1416 * 1143.4) ** 2, 0.001)
    >>> law = ContactLaw(1000.0, 0.3, 0.3, 6.8e10, 8.5e-4, 5.9e-4)
    >>> r = damping_to_stop([m], law, OperatingPoint(17.84, 0.39))
    >>> r.settled, bool(r.damping_ratio[0] > 0.001)
    (True, True)
    """
    modes = as_modes(modes)
    n = len(modes)
    linear = LinearContact.at(contact, op)
    allowed = set(range(n) if adjustable is None else adjustable)
    zeta = np.array([md.damping_ratio for md in modes])
    raised: set[int] = set()
    rounds = 2 * n + 4 if max_rounds is None else max_rounds

    def solve(z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return eigen_shares(_with_ratios(modes, z), linear, wheel_speed_rad_s, body)

    reason = ""

    def wheel_held(lam: np.ndarray, share: np.ndarray) -> np.ndarray:
        """Which eigenvalues an adjustable mode takes part in (the others are the
        counter-body's own: no damping of the wheel moves them)."""
        rows = sorted(allowed)
        return share[rows].max(axis=0) >= PARTNER_SHARE if rows else np.zeros(len(lam), bool)

    for _ in range(rounds):
        lam, share = solve(zeta)
        held = wheel_held(lam, share)
        candidates = np.flatnonzero(held & (lam.real + DECAY_RATE_1_S > 0.0))
        if len(candidates) == 0:
            break
        j = int(candidates[np.argmax(lam.real[candidates])])
        group = [k for k in np.argsort(-share[:n, j]) if share[k, j] >= PARTNER_SHARE and k in allowed]

        def grows(delta: float, group: list[int] = group) -> float:
            z = zeta.copy()
            z[group] += delta
            lam_z, share_z = solve(z)
            involved = share_z[group].max(axis=0) >= PARTNER_SHARE
            return float(np.max(lam_z.real[involved], initial=-math.inf)) + DECAY_RATE_1_S

        start = max(float(zeta[group].max()), 1e-5)
        delta = _bisect_to_stable(grows, 0.0, start, MAX_DAMPING_RATIO)
        if delta is None:
            reason = (
                f"damping below {MAX_DAMPING_RATIO:g} does not stop the eigenvalue at {lam[j].real:.3g} 1/s"
            )
            break
        zeta[group] += delta
        raised.update(int(k) for k in group)
    for k in raised:
        zeta[k] = round_up(float(zeta[k]))
    lam, share = solve(zeta)
    held = wheel_held(lam, share)
    rate = float(np.max(lam.real[held], initial=-math.inf))
    own = float(np.max(lam.real[~held], initial=-math.inf))
    # settled means nothing grows: a counter-body's own growing eigenvalue unsettles it too
    settled = max(rate, own) + DECAY_RATE_1_S <= 0.0
    if not settled and not reason:
        reason = (
            f"the counter-body's own eigenvalue grows at {own:.3g} 1/s, which no damping of the wheel moves"
            if own + DECAY_RATE_1_S > 0.0
            else f"an eigenvalue still grows at {rate:.3g} 1/s after {rounds} rounds"
        )
    return DampingRemedy(zeta, tuple(sorted(raised)), rate, settled, "" if settled else reason, own)


def held_growth_rates(
    modes: Modes,
    contact: ContactLaw,
    op: OperatingPoint,
    wheel_speed_rad_s: float = 0.0,
    adjustable: Sequence[int] | None = None,
    body: BodyModel | None = None,
) -> tuple[float, float]:
    """(the largest growth rate of the eigenvalues an ``adjustable`` mode takes part in,
    that of the others: the counter-body's own) [1/s]; -inf where there are none."""
    modes = as_modes(modes)
    rows = list(range(len(modes)) if adjustable is None else adjustable)
    lam, share = eigen_shares(modes, LinearContact.at(contact, op), wheel_speed_rad_s, body)
    held = share[rows].max(axis=0) >= PARTNER_SHARE if rows else np.zeros(len(lam), bool)
    return (
        float(np.max(lam.real[held], initial=-math.inf)),
        float(np.max(lam.real[~held], initial=-math.inf)),
    )


def friction_coefficient_to_stop(
    modes: Modes,
    contact: ContactLaw,
    op: OperatingPoint,
    wheel_speed_rad_s: float = 0.0,
    body: BodyModel | None = None,
) -> float | None:
    """The friction coefficient mu_s (mu_0 lowered in proportion) below which nothing
    grows at ``op``, rounded down to two significant digits; None when nothing grows now
    or no coefficient down to a hundredth of the present one stops it."""
    modes = as_modes(modes)
    mu = contact.friction_coefficient

    def grows_at(scale: float) -> float:
        c = replace(
            contact,
            friction_coefficient=mu * scale,
            stationary_friction_coefficient=contact.stationary_friction_coefficient * scale,
        )
        return largest_growth_rate(modes, c, op, wheel_speed_rad_s, body)

    if grows_at(1.0) <= 0.0:
        return None
    # bisect on the reduction 1 - scale, growing with it, from none to 99 %
    reduction = _bisect_to_stable(lambda r: grows_at(1.0 - r), 0.0, 0.05, 0.99)
    if reduction is None:
        return None
    value = _round_down(mu * (1.0 - reduction))
    return value if grows_at(value / mu) <= 0.0 else None


def friction_slope_to_stop(
    modes: Modes,
    contact: ContactLaw,
    op: OperatingPoint,
    wheel_speed_rad_s: float = 0.0,
    body: BodyModel | None = None,
) -> float | None:
    """The creep-curve slope dmu/dzeta at the quasi-static creepage above which nothing
    grows at ``op`` (None: nothing grows now, or no slope up to +1 stops it)."""
    modes = as_modes(modes)
    linear = LinearContact.at(contact, op)
    scale = contact.normal_load_n / op.rolling_speed_m_s  # g per unit of dmu/dzeta
    now = linear.friction_damping_ns_m / scale

    def grows_by(rise: float) -> float:
        lin = replace(linear, friction_damping_ns_m=scale * (now + rise))
        lam, _ = eigen_shares(modes, lin, wheel_speed_rad_s, body)
        return float(lam.real.max())

    if grows_by(0.0) <= 0.0:
        return None
    rise = _bisect_to_stable(grows_by, 0.0, max(abs(now), 1e-3) * 0.1, abs(now) + 1.0)
    return None if rise is None else now + rise


def separation_to_stop(
    modes: Modes,
    contact: ContactLaw,
    op: OperatingPoint,
    pair: tuple[int, int],
    wheel_speed_rad_s: float = 0.0,
    body: BodyModel | None = None,
) -> float | None:
    """For a coupled pair (indices into ``modes``), the natural frequency [Hz] the
    higher partner must reach (its stiffness raised, its mass and damping ratio kept) for
    no eigenvalue the pair takes part in to grow; None when no shift up to an octave
    does it."""
    modes = list(as_modes(modes))
    linear = LinearContact.at(contact, op)
    hi = max(pair, key=lambda k: modes[k].angular_frequency_rad_s)
    f0 = modes[hi].angular_frequency_rad_s / (2 * math.pi)
    zeta = modes[hi].damping_ratio

    def grows_with(shift_hz: float) -> float:
        md = modes[hi]
        k = md.mass_kg * (2 * math.pi * (f0 + shift_hz)) ** 2
        moved = modes.copy()
        moved[hi] = ModalDOF.from_damping_ratio(
            md.mass_kg, k, zeta, md.nodal_diameters, md.lateral, md.normal
        )
        lam, share = eigen_shares(moved, linear, wheel_speed_rad_s, body)
        involved = share[list(pair)].max(axis=0) >= PARTNER_SHARE
        return float(np.max(lam.real[involved], initial=-math.inf))

    if grows_with(0.0) <= 0.0:
        return None
    shift = _bisect_to_stable(grows_with, 0.0, max(1e-3 * f0, 0.1), f0)
    return None if shift is None else round_up(f0 + shift, 4)


def remedy_solves(n_modes: int, n_growing: int) -> float:
    """Eigen-solves the remedy takes (damping rounds of about 20 solves per growing
    eigenvalue, the friction coefficient and slope some 20 each, a separation 20)."""
    return 20.0 * max(n_growing, 1) + 60.0 + 0.2 * n_modes
