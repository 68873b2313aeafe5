"""The curve's limits and the bogie's wheels: the names every curve output lists the four
wheels by, and the refusal of a curve the steady curving (``track.bogie_curving``) cannot
mean: a radius tighter than a bogie's wheelbase runs, a speed beyond any train's, or an
unbalanced lateral acceleration beyond any service.

A wheelset running through a curve of radius R at an angle of attack psi to the rail
slides laterally at V sin(psi) ~ V psi while it rolls at V (Rudd 1976; Remington 1987;
Thompson 2009, ch. 14). A bogie of wheelbase 2a held rigidly against the outer rail puts its
leading axle at psi = 2a / R, the most any bogie's axle reaches in that curve: the bound
the refusal uses. Where each axle actually runs, and each wheel's contact, load and
creepages, is the steady curving's.
"""

from __future__ import annotations

import math
from typing import Literal

__all__ = [
    "MAX_ANGLE_OF_ATTACK_RAD",
    "MAX_TRAIN_SPEED_KM_H",
    "MAX_UNBALANCED_ACCELERATION_M_S2",
    "WHEELS",
    "check_curve",
]

Axle = Literal["leading", "trailing"]
Rail = Literal["inner", "outer"]

#: The four wheels of a bogie, in the order every output lists them
WHEELS: tuple[tuple[Axle, Rail], ...] = (
    ("leading", "inner"),
    ("leading", "outer"),
    ("trailing", "inner"),
    ("trailing", "outer"),
)
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


#: The slowest train speed a curve is computed for [km/h]: below it a wheel creeps rather
#: than rolls through the curve, and squeal's time scales (a growth over many wheel turns)
#: have no meaning
MIN_TRAIN_SPEED_KM_H = 1.0
#: The largest installed cant [mm] in magnitude: main lines apply at most about 180 mm
#: (EN 13803-1 sets the limits); 200 mm is taken as the bound beyond which a cant is a slip
MAX_CANT_MM = 200.0


def check_curve(radius_m: float, train_speed_km_h: float, wheelbase_m: float, cant_mm: float = 0.0) -> None:
    """Refuse (ValueError, one line) a curve the curving cannot mean: a radius at which
    a bogie of wheelbase ``wheelbase_m`` [m] would run beyond :data:`MAX_ANGLE_OF_ATTACK_RAD`, a speed beyond
    :data:`MAX_TRAIN_SPEED_KM_H` or below :data:`MIN_TRAIN_SPEED_KM_H`, a cant beyond
    :data:`MAX_CANT_MM`, or one whose unbalanced lateral acceleration
    V^2/R - g h/s exceeds :data:`MAX_UNBALANCED_ACCELERATION_M_S2`.

    Examples
    --------
    >>> check_curve(150.0, 40.0, 2.5)
    >>> check_curve(5.0, 40.0, 2.5)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: curve radius 5 m: ... angle of attack of 500 mrad; the curving holds up to 50 mrad, ...
    """
    if not (math.isfinite(radius_m) and radius_m > 0):
        raise ValueError(f"curve radius {radius_m!r} m: positive")
    if not (math.isfinite(train_speed_km_h) and train_speed_km_h >= MIN_TRAIN_SPEED_KM_H):
        raise ValueError(
            f"train speed {train_speed_km_h!r} km/h: a running train's, {MIN_TRAIN_SPEED_KM_H:g} km/h or more"
        )
    if not (math.isfinite(cant_mm) and abs(cant_mm) <= MAX_CANT_MM):
        raise ValueError(f"cant {cant_mm!r} mm: an installed cant, at most {MAX_CANT_MM:g} mm either way")
    if not (math.isfinite(wheelbase_m) and 0.5 <= wheelbase_m <= 20.0):
        raise ValueError(f"wheelbase {wheelbase_m!r} m: a bogie's is 1.5 to 3 m (0.5 to 20 accepted)")
    psi = wheelbase_m / radius_m
    if psi > MAX_ANGLE_OF_ATTACK_RAD:
        tightest = wheelbase_m / MAX_ANGLE_OF_ATTACK_RAD
        raise ValueError(
            f"curve radius {radius_m:g} m: a bogie of wheelbase {wheelbase_m:g} m would run at an "
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
