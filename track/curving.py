"""Steady curving kinematics of a two-axle bogie: from the curve radius, the train speed
and the wheelbase, each wheel's angle of attack, lateral creepage and crabbing velocity
(the physics layer: nothing here knows a wheel's modes).

A wheelset running through a curve of radius R at an angle of attack psi to the rail
slides laterally at V sin(psi) ~ V psi while it rolls at V: the lateral creepage is
psi and the crabbing velocity V psi (Rudd 1976; Remington 1987; Thompson 2009, ch. 14).
The angle of attack follows from how the bogie sits in the curve (wheelbase 2a):

- ``rigid`` bogie, its leading axle against the outer rail's flange and its trailing
  axle radial (the usual position in tight curves): psi = 2a / R at the leading axle,
  0 at the trailing one;
- ``symmetric`` bogie (both axles equally yawed, free-rolling in the middle): psi = a / R
  at the leading axle and -a / R at the trailing one.

Both wheels of an axle share its angle of attack. The leading outer wheel also touches
the rail at its flange root; the squeal model takes the tread contact of every wheel
(the flange contact adds spin and longitudinal creep, which it leaves out). Cant
deficiency, which moves load from the inner to the outer rail, is not modelled: every
wheel carries the design's load.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

__all__ = [
    "BOGIES",
    "MAX_ANGLE_OF_ATTACK_RAD",
    "MAX_TRAIN_SPEED_KM_H",
    "MAX_UNBALANCED_ACCELERATION_M_S2",
    "WHEELS",
    "Bogie",
    "WheelKinematics",
    "check_curve",
    "wheel_kinematics",
]

Axle = Literal["leading", "trailing"]
Rail = Literal["inner", "outer"]
BogieKind = Literal["rigid", "symmetric"]

#: The four wheels of a bogie, in the order every output lists them
WHEELS: tuple[tuple[Axle, Rail], ...] = (
    ("leading", "inner"),
    ("leading", "outer"),
    ("trailing", "inner"),
    ("trailing", "outer"),
)
#: The bogie positions :func:`wheel_kinematics` knows
BOGIES: tuple[BogieKind, ...] = ("rigid", "symmetric")
#: The largest angle of attack the curving holds for [rad]: about 50 mrad (3 deg), what a
#: bogie's leading axle reaches in the tightest curves bogie vehicles run (depot curves of
#: about 50 m radius for a 2.5 m wheelbase); beyond it the kinematics' small angles and a
#: wheelset guided by its flange no longer hold
MAX_ANGLE_OF_ATTACK_RAD = 0.05
#: The fastest a train runs [km/h] (the fastest in service run at 320-350 km/h)
MAX_TRAIN_SPEED_KM_H = 400.0
#: The largest unbalanced lateral acceleration in a curve [m/s^2]: tilting trains run at
#: up to about 2 m/s^2 (a cant deficiency near 300 mm), 3 m/s^2 is beyond any service
#: and near where a vehicle overturns
MAX_UNBALANCED_ACCELERATION_M_S2 = 3.0
#: Standard gravity [m/s^2] and the distance between the rails' centres [m] (standard gauge)
GRAVITY_M_S2, RAIL_SPACING_M = 9.81, 1.5


def check_curve(radius_m: float, train_speed_km_h: float, bogie: Bogie, cant_mm: float = 0.0) -> None:
    """Refuse (ValueError, one line) a curve the curving cannot mean: a radius at which
    ``bogie`` would run beyond :data:`MAX_ANGLE_OF_ATTACK_RAD`, a speed beyond
    :data:`MAX_TRAIN_SPEED_KM_H`, or one whose unbalanced lateral acceleration
    V^2/R - g h/s exceeds :data:`MAX_UNBALANCED_ACCELERATION_M_S2`.

    Examples
    --------
    >>> check_curve(150.0, 40.0, Bogie(2.5))
    >>> check_curve(5.0, 40.0, Bogie(2.5))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: curve radius 5 m: ... angle of attack of 500 mrad; the curving holds up to 50 mrad, ...
    """
    if not (math.isfinite(radius_m) and radius_m > 0):
        raise ValueError(f"curve radius {radius_m!r} m: positive")
    if not (math.isfinite(train_speed_km_h) and train_speed_km_h > 0):
        raise ValueError(f"train speed {train_speed_km_h!r} km/h: positive")
    psi = bogie.wheelbase_m / radius_m
    if psi > MAX_ANGLE_OF_ATTACK_RAD:
        tightest = bogie.wheelbase_m / MAX_ANGLE_OF_ATTACK_RAD
        raise ValueError(
            f"curve radius {radius_m:g} m: a bogie of wheelbase {bogie.wheelbase_m:g} m would run at an "
            f"angle of attack of {psi * 1e3:.0f} mrad; the curving holds up to "
            f"{MAX_ANGLE_OF_ATTACK_RAD * 1e3:.0f} mrad, R >= {tightest:.0f} m for this wheelbase (the "
            "tightest curves bogie vehicles run)"
        )
    if train_speed_km_h > MAX_TRAIN_SPEED_KM_H:
        raise ValueError(
            f"train speed {train_speed_km_h:g} km/h: faster than any train runs (at most "
            f"{MAX_TRAIN_SPEED_KM_H:g} km/h)"
        )
    speed = train_speed_km_h / 3.6
    unbalanced = speed * speed / radius_m - GRAVITY_M_S2 * cant_mm * 1e-3 / RAIL_SPACING_M
    if abs(unbalanced) > MAX_UNBALANCED_ACCELERATION_M_S2:
        fastest = 3.6 * math.sqrt(
            max(MAX_UNBALANCED_ACCELERATION_M_S2 + GRAVITY_M_S2 * cant_mm * 1e-3 / RAIL_SPACING_M, 0.0)
            * radius_m
        )
        raise ValueError(
            f"{train_speed_km_h:g} km/h in a curve of {radius_m:g} m (cant {cant_mm:g} mm): an unbalanced "
            f"lateral acceleration of {unbalanced:.3g} m/s^2, beyond any train's "
            f"({MAX_UNBALANCED_ACCELERATION_M_S2:g} m/s^2, {fastest:.0f} km/h there)"
        )


@dataclass(frozen=True)
class Bogie:
    """A two-axle bogie: its wheelbase 2a [m] and how it sits in a curve."""

    wheelbase_m: float
    kind: BogieKind = "rigid"

    def __post_init__(self) -> None:
        if not (math.isfinite(self.wheelbase_m) and 0.5 <= self.wheelbase_m <= 20.0):
            raise ValueError(
                f"wheelbase {self.wheelbase_m!r} m: a bogie's is 1.5 to 3 m (0.5 to 20 accepted)"
            )
        if self.kind not in BOGIES:
            raise ValueError(f"bogie {self.kind!r}: one of {', '.join(BOGIES)}")


@dataclass(frozen=True)
class WheelKinematics:
    """One wheel in a curve.

    Attributes
    ----------
    axle : {"leading", "trailing"}
    rail : {"inner", "outer"}
    angle_of_attack_rad : float
        psi [rad] (positive: the wheel's rolling direction points outwards of the curve).
    lateral_creepage : float
        tan(psi) [-]: the crabbing velocity over the rolling speed.
    crabbing_velocity_m_s : float
        V psi [m/s].
    rolling_speed_m_s : float
        V [m/s].
    """

    axle: Axle
    rail: Rail
    angle_of_attack_rad: float
    lateral_creepage: float
    crabbing_velocity_m_s: float
    rolling_speed_m_s: float


def wheel_kinematics(radius_m: float, train_speed_km_h: float, bogie: Bogie) -> tuple[WheelKinematics, ...]:
    """The four wheels of ``bogie`` in a curve of ``radius_m`` at ``train_speed_km_h``, in
    :data:`WHEELS` order (module docstring).

    Examples
    --------
    >>> w = wheel_kinematics(200.0, 40.0, Bogie(2.5))
    >>> round(w[0].angle_of_attack_rad, 4), round(w[0].crabbing_velocity_m_s, 4), w[2].angle_of_attack_rad
    (0.0125, 0.1389, 0.0)
    """
    check_curve(radius_m, train_speed_km_h, bogie)
    speed = train_speed_km_h / 3.6
    half = 0.5 * bogie.wheelbase_m
    psi = {"leading": 2 * half / radius_m, "trailing": 0.0}
    if bogie.kind == "symmetric":
        psi = {"leading": half / radius_m, "trailing": -half / radius_m}
    return tuple(
        WheelKinematics(
            axle,
            rail,
            psi[axle],
            math.tan(psi[axle]),
            speed * math.sin(psi[axle]),
            speed * math.cos(psi[axle]),
        )
        for axle, rail in WHEELS
    )
