"""Lateral creep law of Liu & Meehan (CM2015), Eq. 3 and Eq. 6.

``mu(zeta)`` is the lateral adhesion ratio Q/W as a function of the lateral
creepage zeta (dimensionless) at rolling speed V0 (m/s)::

    z' = |zeta| G a b C22 / (mu_0 W)                                   (Eq. 6)
    s  = |zeta| V0      (lateral sliding speed, m/s)
    F(s) = 1 - 0.5 exp(-0.138/s) - 0.5 exp(-6.9/s)   (falling friction; F(0+) = 1)
    mu = sign(zeta) mu_s (z' - z'^2/3 + z'^3/27) F(s)   for z' <= 3        (Eq. 3)
    mu = sign(zeta) mu_s F(s)                            for z' >  3

mu is odd in zeta (friction opposes sliding). The cubic reaches 1 with zero slope at
z' = 3, so the law is continuous and C1 there. F is evaluated without dividing by
zero: exp(-0.138/s) -> 0 as s -> 0+.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .contact import HertzContact, kalker_c22

__all__ = [
    "FRICTION_LAWS",
    "ContactLaw",
    "adhesion_ratio",
    "adhesion_ratio_slope",
    "falling_friction_factor",
]

#: Liu & Meehan's C22 (Table 1)
TABLE1_C22 = 3.14

#: The friction laws by name, as the decay speeds (s1, s2) [m/s] of the falling factor
#: F(s) of Eq. 3. "falling" is the paper's law. "constant" is Eq. 3 without the falling
#: factor (F = 1: infinite decay speeds), the creep polynomial saturating at mu_s: its
#: slope is never negative, so falling friction cannot drive squeal and only the other
#: mechanism, mode coupling through the normal contact, can.
FRICTION_LAWS: dict[str, tuple[float, float]] = {
    "falling": (0.138, 6.9),
    "constant": (math.inf, math.inf),
}


@dataclass(frozen=True)
class ContactLaw:
    """Parameters of the creep law (Eq. 2, 3, 6).

    Attributes
    ----------
    normal_load_n : W, N.
    friction_coefficient : mu_s, saturation adhesion ratio, dimensionless.
    stationary_friction_coefficient : mu_0 in Eq. 6, dimensionless.
    shear_modulus_pa : G = E / 2(1 + nu), Pa.
    semi_axis_a_m, semi_axis_b_m : Hertz semi-axes (rolling, lateral), m.
    c22 : Kalker's lateral creep coefficient, dimensionless.
    decay_speed_1_m_s, decay_speed_2_m_s : the sliding speeds 0.138 and 6.9 m/s of
        the falling-friction factor F(s) of Eq. 3 (infinite: no falling friction, the
        "constant" law of :data:`FRICTION_LAWS`).
    hertz_approach_m : delta0, the static Hertz approach under W, m: the normal force
        follows N = W (1 + d / delta0)^(3/2) for an extra approach d (linearised: the
        spring k_H = 3 W / (2 delta0)). Infinite: the paper's constant normal load (no
        normal spring: the contact's normal direction is switched off).
    relaxation_length_m : L, the rolling distance over which the creep force builds up
        (transient creep: a first-order lag of time constant L / V0), m; 0: the paper's
        steady creep law.
    """

    normal_load_n: float
    friction_coefficient: float
    stationary_friction_coefficient: float
    shear_modulus_pa: float
    semi_axis_a_m: float
    semi_axis_b_m: float
    c22: float = TABLE1_C22
    decay_speed_1_m_s: float = 0.138
    decay_speed_2_m_s: float = 6.9
    hertz_approach_m: float = math.inf
    relaxation_length_m: float = 0.0

    def __post_init__(self) -> None:
        for name in (
            "normal_load_n",
            "friction_coefficient",
            "stationary_friction_coefficient",
            "shear_modulus_pa",
            "semi_axis_a_m",
            "semi_axis_b_m",
            "c22",
        ):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"ContactLaw.{name} must be positive and finite, got {value!r}")
        for name in ("decay_speed_1_m_s", "decay_speed_2_m_s"):
            value = getattr(self, name)
            if not value > 0.0:  # infinite is allowed: no falling friction
                raise ValueError(f"ContactLaw.{name} must be positive (or infinite), got {value!r}")
        if not self.hertz_approach_m > 0.0:
            raise ValueError(
                f"ContactLaw.hertz_approach_m must be positive (or infinite), got {self.hertz_approach_m!r}"
            )
        if not (math.isfinite(self.relaxation_length_m) and self.relaxation_length_m >= 0.0):
            raise ValueError(
                f"ContactLaw.relaxation_length_m must be 0 or positive, got {self.relaxation_length_m!r}"
            )

    @classmethod
    def from_hertz(
        cls,
        hertz: HertzContact,
        friction_coefficient: float = 0.3,
        stationary_friction_coefficient: float | None = None,
        c22: float | str = TABLE1_C22,
        friction_law: str = "falling",
        normal: bool = True,
        relaxation_length_m: float = 0.0,
    ) -> ContactLaw:
        """Build from a Hertz contact (which carries W, E, nu, a, b).

        ``c22`` is a number (Table 1: 3.14) or ``"kalker"`` for Kalker's table
        value at the contact's a/b and nu (4.28 for Table 1). mu_0 defaults to mu_s.
        ``friction_law``: a name of :data:`FRICTION_LAWS`. ``normal``: the Hertz spring
        in the normal direction (its approach ``hertz.approach_m``); False keeps the
        normal load constant (the paper's model). ``relaxation_length_m``: transient
        creep (0: steady).
        """
        try:
            s1, s2 = FRICTION_LAWS[friction_law]
        except KeyError:
            raise ValueError(
                f"unknown friction law {friction_law!r}; choose {', '.join(FRICTION_LAWS)}"
            ) from None
        if isinstance(c22, str):
            if c22.lower() != "kalker":
                raise ValueError(f"c22 must be a number or 'kalker', got {c22!r}")
            c22 = kalker_c22(hertz.a_over_b, hertz.poissons_ratio)
        mu0 = (
            friction_coefficient
            if stationary_friction_coefficient is None
            else stationary_friction_coefficient
        )
        return cls(
            normal_load_n=hertz.normal_load_n,
            friction_coefficient=float(friction_coefficient),
            stationary_friction_coefficient=float(mu0),
            shear_modulus_pa=hertz.shear_modulus_pa,
            semi_axis_a_m=hertz.semi_axis_a_m,
            semi_axis_b_m=hertz.semi_axis_b_m,
            c22=float(c22),
            decay_speed_1_m_s=s1,
            decay_speed_2_m_s=s2,
            hertz_approach_m=hertz.approach_m if normal else math.inf,
            relaxation_length_m=float(relaxation_length_m),
        )

    @property
    def normal_stiffness_n_m(self) -> float:
        """k_H = 3 W / (2 delta0) [N/m]; 0 with the normal direction switched off."""
        return 1.5 * self.normal_load_n / self.hertz_approach_m

    def relaxation_time_s(self, rolling_speed_m_s: float) -> float:
        """tau = L / V0 [s], the lag of the creep force (0: steady creep)."""
        return self.relaxation_length_m / rolling_speed_m_s

    @property
    def friction_law(self) -> str:
        """The name of the law in :data:`FRICTION_LAWS` (or "custom")."""
        speeds = (self.decay_speed_1_m_s, self.decay_speed_2_m_s)
        return next((k for k, v in FRICTION_LAWS.items() if v == speeds), "custom")

    @property
    def normalised_creepage_per_creepage(self) -> float:
        """dz'/d|zeta| = G a b C22 / (mu_0 W) of Eq. 6, dimensionless."""
        return (
            self.shear_modulus_pa
            * self.semi_axis_a_m
            * self.semi_axis_b_m
            * self.c22
            / (self.stationary_friction_coefficient * self.normal_load_n)
        )

    @property
    def saturation_creepage(self) -> float:
        """Creepage at which z' = 3 (full sliding), dimensionless: 0.0083 for Table 1."""
        return 3.0 / self.normalised_creepage_per_creepage


def falling_friction_factor(sliding_speed_m_s: ArrayLike, law: ContactLaw) -> np.ndarray:
    """F(s) = 1 - 0.5 exp(-s1/s) - 0.5 exp(-s2/s) for sliding speed s >= 0 (m/s).

    Finite and equal to 1 at s = 0 (the limit), without warnings: there -s1/s is -inf and
    its exponential exactly 0, as it is for an infinite decay speed (no falling term);
    for a subnormal s the quotient overflows to -inf, and below s = s1/746 the exponential
    underflows to 0.
    """
    s = np.abs(np.asarray(sliding_speed_m_s, dtype=float))
    with np.errstate(divide="ignore", over="ignore", under="ignore"):
        return 1.0 - 0.5 * np.exp(-law.decay_speed_1_m_s / s) - 0.5 * np.exp(-law.decay_speed_2_m_s / s)


def _falling_friction_slope(s: np.ndarray, law: ContactLaw) -> np.ndarray:
    """dF/ds, 1/(m/s). Below s = s1/700 the exponentials underflow (e^-700) and the
    slope is exactly 0 in double precision (all derivatives of exp(-c/s) vanish at 0)."""
    d = np.zeros_like(s)
    for decay in (law.decay_speed_1_m_s, law.decay_speed_2_m_s):
        if math.isinf(decay):  # no falling term
            continue
        live = s > decay / 700.0
        inv = np.divide(1.0, s, out=np.zeros_like(s), where=live)
        with np.errstate(under="ignore"):
            d = d - np.where(live, 0.5 * decay * inv * inv * np.exp(-decay * inv), 0.0)
    return d


def _creep_cubic(zp: np.ndarray) -> np.ndarray:
    """The cubic of Eq. 3 in the normalised creepage z' >= 0: P = z'(1 - z'/3 + z'^2/27)
    below z' = 3, 1 beyond."""
    return np.where(zp < 3.0, zp * (1.0 - zp / 3.0 + zp * zp / 27.0), 1.0)


def _creep_polynomial(zp: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The cubic of Eq. 3 (:func:`_creep_cubic`) and its derivative P' = (1 - z'/3)^2
    below z' = 3, 0 beyond."""
    dpoly = np.where(zp < 3.0, 1.0 - 2.0 * zp / 3.0 + zp * zp / 9.0, 0.0)
    return _creep_cubic(zp), dpoly


def adhesion_ratio(creepage: ArrayLike, law: ContactLaw, rolling_speed_m_s: float) -> np.ndarray:
    """Lateral adhesion ratio mu(zeta) of Eq. 3 (dimensionless, odd in zeta).

    Parameters
    ----------
    creepage : lateral creepage zeta = (Vc + y')/V0, dimensionless; scalar or array.
    law : creep-law parameters.
    rolling_speed_m_s : V0, m/s (> 0).

    Returns an array (or 0-d array for scalar input) of mu, |mu| <= mu_s.
    """
    zeta = np.asarray(creepage, dtype=float)
    a = np.abs(zeta)
    poly = _creep_cubic(a * law.normalised_creepage_per_creepage)
    f = falling_friction_factor(a * rolling_speed_m_s, law)
    return np.sign(zeta) * law.friction_coefficient * poly * f


def adhesion_ratio_slope(creepage: ArrayLike, law: ContactLaw, rolling_speed_m_s: float) -> np.ndarray:
    """Analytic derivative d mu / d zeta of Eq. 3 (dimensionless), even in zeta.

    d mu/d zeta = mu_s [ P'(z') K F(s) + P(z') F'(s) V0 ] with K = dz'/d|zeta|,
    P the cubic (P = 1, P' = 0 beyond z' = 3). Used for the linear growth rate
    sigma = -(c + W/V0 dmu/dzeta) / (2 m).
    """
    zeta = np.asarray(creepage, dtype=float)
    a = np.abs(zeta)
    K = law.normalised_creepage_per_creepage
    poly, dpoly = _creep_polynomial(a * K)
    s = a * rolling_speed_m_s
    f = falling_friction_factor(s, law)
    df = _falling_friction_slope(s, law)
    return law.friction_coefficient * (dpoly * K * f + poly * df * rolling_speed_m_s)
