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
from collections.abc import Callable
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import ArrayLike

from .hertz import HertzContact, kalker_c22

__all__ = [
    "FRICTION_LAWS",
    "ConstantFriction",
    "FallingFriction",
    "FrictionLaw",
    "ContactLaw",
    "adhesion_ratio",
    "adhesion_ratio_slope",
    "falling_friction_factor",
    "friction_law_named",
]

#: Liu & Meehan's C22 (Table 1)
TABLE1_C22 = 3.14


@dataclass(frozen=True)
class FrictionLaw:
    """A friction law: the falling factor F(s) of Eq. 3 that multiplies the creep
    polynomial, as a function of the sliding speed s [m/s]::

        F(s) = 1 - w1 exp(-s1 / s) - w2 exp(-s2 / s)      (F(0+) = 1)

    The compiled integrators evaluate this family from the four numbers of
    :meth:`kernel_parameters`, the linear stability from :meth:`slope`, so one class gives
    the law everywhere. A new law is a subclass with its own :attr:`name` and defaults,
    registered in :data:`FRICTION_LAWS` (``FRICTION_LAWS["mine"] = Mine``); a law that is not
    of this family needs kernels of its own.

    Attributes
    ----------
    name : str
        The law's name in :data:`FRICTION_LAWS`.
    weight_1, weight_2 : float
        w1, w2: each term's share of the fall, dimensionless (w1 + w2 <= 1: F >= 0).
    decay_speed_1_m_s, decay_speed_2_m_s : float
        s1, s2: the sliding speeds of the two terms [m/s] (infinite: no such term).

    Examples
    --------
    >>> law = FallingFriction()
    >>> round(float(law.factor(1.0)), 4), round(float(law.slope(1.0)), 4)  # F(1 m/s), dF/ds [s/m]
    (0.5639, -0.0636)
    >>> float(ConstantFriction().factor(1.0))
    1.0
    """

    name: ClassVar[str] = "custom"
    weight_1: float
    decay_speed_1_m_s: float
    weight_2: float
    decay_speed_2_m_s: float

    def __post_init__(self) -> None:
        for w in (self.weight_1, self.weight_2):
            if not 0.0 <= w <= 1.0:
                raise ValueError(f"{type(self).__name__}: a weight must lie in [0, 1], got {w!r}")
        if self.weight_1 + self.weight_2 > 1.0:
            raise ValueError(f"{type(self).__name__}: the weights sum beyond 1 (F would turn negative)")
        for s in (self.decay_speed_1_m_s, self.decay_speed_2_m_s):
            if not s > 0.0:  # infinite is allowed: no falling term
                raise ValueError(
                    f"{type(self).__name__}: a decay speed must be positive (or infinite), got {s!r}"
                )

    def kernel_parameters(self) -> tuple[float, float, float, float]:
        """(w1, s1, w2, s2) [-, m/s, -, m/s], the numbers the compiled kernels take."""
        return (self.weight_1, self.decay_speed_1_m_s, self.weight_2, self.decay_speed_2_m_s)

    def factor(self, sliding_speed_m_s: ArrayLike) -> np.ndarray:
        """F(s) for sliding speeds s >= 0 [m/s], dimensionless.

        Finite and equal to 1 at s = 0 (the limit), without warnings: there -s1/s is -inf
        and its exponential exactly 0, as it is for an infinite decay speed (no falling
        term); for a subnormal s the quotient overflows to -inf, and below s = s1/746 the
        exponential underflows to 0.
        """
        s = np.abs(np.asarray(sliding_speed_m_s, dtype=float))
        with np.errstate(divide="ignore", over="ignore", under="ignore"):
            return (
                1.0
                - self.weight_1 * np.exp(-self.decay_speed_1_m_s / s)
                - self.weight_2 * np.exp(-self.decay_speed_2_m_s / s)
            )

    def slope(self, sliding_speed_m_s: ArrayLike) -> np.ndarray:
        """dF/ds [s/m]. Below s = s_k/700 a term's exponential underflows (e^-700) and its
        slope is exactly 0 in double precision (all derivatives of exp(-c/s) vanish at 0)."""
        s = np.abs(np.asarray(sliding_speed_m_s, dtype=float))
        d = np.zeros_like(s)
        for weight, decay in (
            (self.weight_1, self.decay_speed_1_m_s),
            (self.weight_2, self.decay_speed_2_m_s),
        ):
            if math.isinf(decay):  # no falling term
                continue
            live = s > decay / 700.0
            inv = np.divide(1.0, s, out=np.zeros_like(s), where=live)
            with np.errstate(under="ignore"):
                d = d - np.where(live, weight * decay * inv * inv * np.exp(-decay * inv), 0.0)
        return d

    def steepness_s_m(self) -> float:
        """sum_k 2 w_k / s_k [s/m]: the fall's steepness, whose 2 e^-2 multiple bounds the magnitude of dF/ds
        over all s (a term's largest slope, w 4 e^-2 / s_k, is at s = s_k / 2)."""
        return 2.0 * self.weight_1 / self.decay_speed_1_m_s + 2.0 * self.weight_2 / self.decay_speed_2_m_s


@dataclass(frozen=True)
class FallingFriction(FrictionLaw):
    """The paper's falling friction (Liu & Meehan, CM2015, Eq. 3): w1 = w2 = 0.5, s1 = 0.138
    and s2 = 6.9 m/s.

    Attributes
    ----------
    weight_1, decay_speed_1_m_s, weight_2, decay_speed_2_m_s : float
        As :class:`FrictionLaw`'s, with the paper's values [-, m/s, -, m/s].

    Examples
    --------
    >>> FallingFriction().kernel_parameters()
    (0.5, 0.138, 0.5, 6.9)
    """

    name: ClassVar[str] = "falling"
    weight_1: float = 0.5
    decay_speed_1_m_s: float = 0.138
    weight_2: float = 0.5
    decay_speed_2_m_s: float = 6.9


@dataclass(frozen=True)
class ConstantFriction(FallingFriction):
    """Eq. 3 without the falling factor (F = 1: infinite decay speeds), the creep
    polynomial saturating at mu_s: its slope is never negative, so falling friction cannot
    drive squeal and only the other mechanism, mode coupling through the normal contact,
    can.

    Attributes
    ----------
    decay_speed_1_m_s, decay_speed_2_m_s : float
        Infinite [m/s]: no falling term (the weights as :class:`FallingFriction`'s).

    Examples
    --------
    >>> float(ConstantFriction().slope(0.5))
    0.0
    """

    name: ClassVar[str] = "constant"
    decay_speed_1_m_s: float = math.inf
    decay_speed_2_m_s: float = math.inf


#: The friction laws by name: name -> class (SciPy's ``METHODS``), each instantiated with
#: its own defaults by :meth:`ContactLaw.from_hertz`.
FRICTION_LAWS: dict[str, Callable[[], FrictionLaw]] = {
    law.name: law for law in (FallingFriction, ConstantFriction)
}


def friction_law_named(name: str) -> FrictionLaw:
    """The law registered as ``name`` in :data:`FRICTION_LAWS`, with its own parameters
    (the one check of a law's name: the design file and the API report its ValueError).

    Parameters
    ----------
    name : str
        A key of :data:`FRICTION_LAWS`.

    Returns
    -------
    FrictionLaw
        The law with its class's parameters.

    Raises
    ------
    ValueError
        For a name no law is registered under (the message lists the names).

    Examples
    --------
    >>> friction_law_named("constant").name
    'constant'
    """
    try:
        return FRICTION_LAWS[name]()
    except KeyError:
        raise ValueError(
            f"friction_law must be one of {', '.join(map(repr, FRICTION_LAWS))}, got {name!r}"
        ) from None


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
    friction : the friction law, whose falling factor F(s) multiplies Eq. 3's polynomial
        (:class:`FrictionLaw`; default the paper's, :class:`FallingFriction`).
    hertz_approach_m : delta0, the static Hertz approach under W, m: the normal force
        follows N = W (1 + d / delta0)^(3/2) for an extra approach d (linearised: the
        spring k_H = 3 W / (2 delta0)). Infinite: the paper's constant normal load (no
        normal spring: the contact's normal direction is switched off).
    relaxation_length_m : L, the rolling distance over which the creep force builds up
        (transient creep: a first-order lag of time constant L / V0), m; 0: the paper's
        steady creep law.

    Examples
    --------
    >>> from contact.hertz import hertz_contact
    >>> h = hertz_contact(0.213, 0.3, 0.085, 0.04, 175e9, 0.28, 1000.0)  # Table 1's rig
    >>> law = ContactLaw.from_hertz(h, friction_coefficient=0.3)
    >>> round(law.saturation_creepage, 4), law.friction_law
    (0.0083, 'falling')
    """

    normal_load_n: float
    friction_coefficient: float
    stationary_friction_coefficient: float
    shear_modulus_pa: float
    semi_axis_a_m: float
    semi_axis_b_m: float
    c22: float = TABLE1_C22
    friction: FrictionLaw = FallingFriction()
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
        if not isinstance(self.friction, FrictionLaw):
            raise TypeError(f"ContactLaw.friction must be a FrictionLaw, got {self.friction!r}")
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
        friction = friction_law_named(friction_law)
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
            friction=friction,
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
        """The name of the law in :data:`FRICTION_LAWS` ("custom" for a bare :class:`FrictionLaw`)."""
        return self.friction.name

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
    """F(s) of the contact's friction law at sliding speeds s >= 0 [m/s] (:meth:`FrictionLaw.factor`).

    Parameters
    ----------
    sliding_speed_m_s : array_like
        Sliding speeds s [m/s].
    law : ContactLaw
        The contact whose friction law is read.

    Returns
    -------
    numpy.ndarray
        F(s), dimensionless, 1 at s = 0.

    Examples
    --------
    >>> from contact.hertz import hertz_contact
    >>> law = ContactLaw.from_hertz(hertz_contact(0.213, 0.3, 0.085, 0.04, 175e9, 0.28, 1000.0))
    >>> float(falling_friction_factor(0.0, law))
    1.0
    """
    return law.friction.factor(sliding_speed_m_s)


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

    Returns
    -------
    numpy.ndarray
        mu, |mu| <= mu_s (0-d for a scalar creepage).

    Examples
    --------
    >>> from contact.hertz import hertz_contact
    >>> h = hertz_contact(0.213, 0.3, 0.085, 0.04, 175e9, 0.28, 1000.0)  # Table 1's rig
    >>> law = ContactLaw.from_hertz(h, friction_coefficient=0.3)
    >>> float(adhesion_ratio(0.1, law, 17.84)) < 0.3  # saturated, and falling with the sliding speed
    True
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

    Parameters
    ----------
    creepage : array_like
        Lateral creepage zeta, dimensionless.
    law : ContactLaw
        The creep law.
    rolling_speed_m_s : float
        V0 [m/s].

    Returns
    -------
    numpy.ndarray
        d mu / d zeta, dimensionless (negative on the falling branch).

    Examples
    --------
    >>> from contact.hertz import hertz_contact
    >>> law = ContactLaw.from_hertz(hertz_contact(0.213, 0.3, 0.085, 0.04, 175e9, 0.28, 1000.0))
    >>> round(float(adhesion_ratio_slope(0.02186, law, 17.84)), 2)  # Fig. 6: falling
    -1.7
    """
    zeta = np.asarray(creepage, dtype=float)
    a = np.abs(zeta)
    K = law.normalised_creepage_per_creepage
    poly, dpoly = _creep_polynomial(a * K)
    s = a * rolling_speed_m_s
    f = falling_friction_factor(s, law)
    df = law.friction.slope(s)
    return law.friction_coefficient * (dpoly * K * f + poly * df * rolling_speed_m_s)
