"""Where the sound is heard: the microphone (the paper's, or one a user places) and the
air it is heard through, each checked before any work."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .design import Design
from .runtime.request_errors import RequestError

if TYPE_CHECKING:
    from acoustics import Air

__all__ = [
    "MAX_MICROPHONE_DISTANCE_M",
    "MICROPHONE_DISTANCE_M",
    "Listener",
    "air_for",
    "default_microphone",
    "microphone_for",
]

#: The paper's microphone distance from the wheel [m]; its position on the wheel is not
#: given: it is taken axially off the rim face, at the rolling radius, at angle 0 (the
#: contact's, an antinode of the squeal mode's cos member).
MICROPHONE_DISTANCE_M = 0.05


def default_microphone(design: Design) -> tuple[float, float, float]:
    """(r, z, theta) [m, m, rad]: 0.05 m off the rim face at the rolling radius."""
    return (design.wheel.rolling_radius, design.wheel.rim_width / 2 + MICROPHONE_DISTANCE_M, 0.0)


#: The farthest microphone [m]: beyond it a position is a slip of units (mm for m).
MAX_MICROPHONE_DISTANCE_M = 1000.0


def microphone_for(
    design: Design, microphone: tuple[float, float, float] | None = None
) -> tuple[float, float, float]:
    """The microphone (r, z, theta) [m, m, rad] (None: the default,
    :func:`default_microphone`), checked against the wheel: a position inside its
    cross-section, absurdly far or not finite is refused (:class:`RequestError`)."""
    from geometry.profile import half_profile

    mic = default_microphone(design) if microphone is None else microphone
    if not all(math.isfinite(v) for v in mic) or mic[0] < 0:
        raise RequestError(f"microphone (r, z, theta) = {mic}: finite values and r >= 0")
    r, z, _ = mic
    if math.hypot(r, z) > MAX_MICROPHONE_DISTANCE_M:
        raise RequestError(
            f"microphone at r {r:g} m, z {z:g} m is more than {MAX_MICROPHONE_DISTANCE_M:g} m from the "
            "wheel (positions are in metres)"
        )
    if bool(half_profile(design.wheel).contains(np.array([[r, z]]))[0]):
        raise RequestError(
            f"microphone at r {r:g} m, z {z:g} m is inside the wheel's cross-section: place it in the air"
        )
    return mic


@dataclass(frozen=True)
class Listener:
    """Where the sound is heard and through what: the microphone (r, z, theta) [m, m,
    rad] and the air (``acoustics.Air``)."""

    microphone: tuple[float, float, float]
    air: Air


def air_for(density_kg_m3: float, sound_speed_m_s: float) -> Air:
    """``acoustics.Air`` of the given density and sound speed, refused
    (:class:`RequestError`) outside the plausible ranges (``acoustics.implausible_air``)."""
    from acoustics import Air
    from acoustics.medium import implausible_air

    problem = implausible_air(density_kg_m3, sound_speed_m_s)
    if problem:
        raise RequestError(problem)
    return Air(density_kg_m3, sound_speed_m_s)
