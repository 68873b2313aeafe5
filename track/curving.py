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

__all__ = ["BOGIES", "WHEELS", "Bogie", "WheelKinematics", "wheel_kinematics"]

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
    if not (math.isfinite(radius_m) and radius_m > 0):
        raise ValueError(f"curve radius {radius_m!r} m: positive")
    if not (math.isfinite(train_speed_km_h) and train_speed_km_h > 0):
        raise ValueError(f"train speed {train_speed_km_h!r} km/h: positive")
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
