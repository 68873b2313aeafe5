"""From the squeal mode to sound: the mode's surface velocity scaled to the contact's
velocity amplitude, its radiation (``acoustics``), and the levels a user is judged on.

The radiation of one mode per unit contact velocity (peak, 1 m/s) is a property of the
mode alone; a limit cycle of amplitude v scales the pressure by v and the power by v^2.
The wheel is alone in free field (no roller, shaft or floor). Levels: SPL in dB re
20 uPa of the rms pressure (a pure tone, rms = peak / sqrt 2), sound power level in dB
re 1 pW.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from geometry import WheelDesign

from .cache import CacheMiss, StageCache, code_version
from .errors import RequestError

__all__ = [
    "MICROPHONE_DISTANCE_M",
    "Radiation",
    "Sound",
    "default_microphone",
    "mode_radiation",
    "mode_surface",
    "parse_microphone",
    "ring_points",
    "sound_of",
]

#: The paper's microphone distance from the wheel [m]; its position on the wheel is not
#: given: it is taken axially off the rim face, at the rolling radius, at angle 0 (the
#: contact's, an antinode of the squeal mode's cos member).
MICROPHONE_DISTANCE_M = 0.05


def default_microphone(design: WheelDesign) -> tuple[float, float, float]:
    """(r, z, theta) [m, m, rad]: 0.05 m off the rim face at the rolling radius."""
    return (design.rolling_radius, design.rim_width / 2 + MICROPHONE_DISTANCE_M, 0.0)


def parse_microphone(text: str) -> tuple[float, float, float]:
    """``R,Z,THETA`` (m, m, rad) as a tuple; RequestError otherwise."""
    try:
        r, z, theta = (float(v) for v in text.split(","))
    except ValueError:
        raise RequestError(f"--microphone takes R,Z,THETA (m, m, rad), got {text!r}") from None
    if not all(math.isfinite(v) for v in (r, z, theta)) or r < 0:
        raise RequestError(f"--microphone R,Z,THETA needs finite values and R >= 0, got {text!r}")
    return (r, z, theta)


def mode_surface(modeset, mode, frequency_hz: float, contact_velocity_m_s: float = 1.0):
    """The mode's outline and surface velocity (``acoustics.Surface``), scaled so that
    the axial velocity amplitude at the contact is ``contact_velocity_m_s`` [m/s]."""
    from acoustics import Surface
    from fem.shapes import meridian_outline

    points, displacement = meridian_outline(modeset, mode.index)
    v_c = abs(float(mode.contact_axial[0]))
    if not v_c > 0:
        raise RequestError(f"mode {mode.index} ({mode.label()}) does not move the contact: it cannot squeal")
    omega = 2 * math.pi * frequency_hz
    velocity = 1j * omega * displacement * (contact_velocity_m_s / (omega * v_c))
    return Surface(points, velocity, int(mode.nodal_diameters))


#: The circle on which the sound plot draws the SPL: this fraction of the air region's
#: radius, at this many angles from the +z axis (0) to the -z axis (pi).
RING_FRACTION, RING_ANGLES = 0.9, 181


def ring_points(radius_m: float) -> np.ndarray:
    """(r, z) [m] of the SPL circle (:data:`RING_FRACTION`, :data:`RING_ANGLES`) in an air
    region of radius ``radius_m``, shape (RING_ANGLES, 2)."""
    angle = np.linspace(0.0, np.pi, RING_ANGLES)
    return RING_FRACTION * radius_m * np.stack([np.sin(angle), np.cos(angle)], axis=1)


@dataclass(frozen=True)
class Radiation:
    """A mode's sound field at 1 m/s contact velocity (``acoustics.SoundField``) and its
    pressure [Pa] (complex amplitude of cos(n theta)) where the outputs look: at the
    microphone's (r, z) and on :func:`ring_points` (evaluated once, with the field)."""

    field: object
    microphone_pressure_pa: complex
    ring_pressure_pa: np.ndarray

    @classmethod
    def of(cls, field, microphone) -> Radiation:
        """The radiation of ``field`` (``acoustics.SoundField`` at 1 m/s) seen from a
        microphone (r, z[, theta])."""
        at_microphone = complex(field.pressure_at(np.array([microphone[:2]]))[0])
        return cls(field, at_microphone, field.pressure_at(ring_points(field.mesh.radius)))


#: The arrays a cached radiation holds (part of its key: another layout is another entry).
STORED = ("scalars", "points", "triangles", "dof_points", "pressure", "microphone_pressure", "ring_pressure")


def _field_arrays(field) -> dict[str, np.ndarray]:
    scalars = np.array(
        [
            field.frequency_hz,
            field.harmonic,
            field.sound_power_w,
            field.radiation_efficiency,
            field.surface_power_w,
            field.flux_power_w,
            field.mesh.radius,
            field.mesh.pml_thickness,
            field.air.density_kg_m3,
            field.air.sound_speed_m_s,
        ]
    )
    return {
        "scalars": scalars,
        "points": field.mesh.points,
        "triangles": field.mesh.triangles,
        "dof_points": field.dof_points,
        "pressure": field.pressure,
    }


def _field_from(arrays: dict[str, np.ndarray]):
    from acoustics import Air, AirMesh, SoundField

    s = arrays["scalars"]
    mesh = AirMesh(arrays["points"], arrays["triangles"], float(s[6]), float(s[7]))
    return SoundField(
        mesh,
        arrays["dof_points"],
        arrays["pressure"],
        float(s[0]),
        int(s[1]),
        float(s[2]),
        float(s[3]),
        float(s[4]),
        float(s[5]),
        Air(float(s[8]), float(s[9])),
    )


def mode_radiation(
    design: WheelDesign,
    modeset,
    mode,
    frequency_hz: float,
    microphone: tuple[float, float, float],
    cache: StageCache | None = None,
    modes_key: dict | None = None,
    air=None,
) -> Radiation:
    """The :class:`Radiation` of ``mode`` at 1 m/s contact velocity, its air region made
    large enough to hold the microphone; cached beside the modes when ``modes_key``
    (:func:`wheel_squeal.api.modes_cache_key`) is given; ``air``: ``acoustics.Air``
    (default: 1.21 kg/m^3, 343 m/s)."""
    from acoustics import AIR, RadiationSettings, radiate

    settings, air = RadiationSettings(), air or AIR
    key = None
    if cache is not None and modes_key is not None:
        key = {
            **modes_key,
            "stage": "sound",
            "mode": mode.index,
            "frequency_hz": round(float(frequency_hz), 6),
            "microphone_rz": [round(microphone[0], 9), round(microphone[1], 9)],
            "settings": repr(settings),
            "air": repr(air),
            "code": code_version("acoustics"),
            "stored": list(STORED),
        }
        try:
            arrays = cache.load("sound", key)
            return Radiation(
                _field_from(arrays), complex(arrays["microphone_pressure"][0]), arrays["ring_pressure"]
            )
        except CacheMiss:
            pass
    surface = mode_surface(modeset, mode, frequency_hz)
    field = radiate(surface, frequency_hz, air, settings, field_points=np.array([microphone[:2]]))
    rad = Radiation.of(field, microphone)
    if key is not None:
        at = {
            "microphone_pressure": np.array([rad.microphone_pressure_pa]),
            "ring_pressure": rad.ring_pressure_pa,
        }
        cache.store("sound", key, {**_field_arrays(field), **at})
    return rad


@dataclass(frozen=True)
class Sound:
    """What a microphone and a sound power measurement would give for a tone of contact
    velocity amplitude ``velocity_amplitude_m_s``, from the :class:`Radiation` at 1 m/s
    (made for the microphone's (r, z); theta only sets the angular factor)."""

    radiation: Radiation
    velocity_amplitude_m_s: float
    microphone: tuple[float, float, float]
    travelling: bool = False

    @property
    def field(self):
        """The sound field at 1 m/s (``acoustics.SoundField``)."""
        return self.radiation.field

    @property
    def microphone_pressure_pa(self) -> float:
        """Peak pressure amplitude at the microphone [Pa] (a travelling wave passes every
        angle with the antinode's amplitude)."""
        n, theta = self.field.harmonic, self.microphone[2]
        angular = 1.0 if self.travelling else abs(math.cos(n * theta))
        return abs(self.radiation.microphone_pressure_pa) * angular * self.velocity_amplitude_m_s

    @property
    def sound_power_w(self) -> float:
        """Time-averaged radiated power [W]; a travelling wave (a rotating pair) is the
        cos and sin members together, twice the standing wave's."""
        twice = self.travelling and self.field.harmonic >= 1
        return self.field.sound_power_w * self.velocity_amplitude_m_s**2 * (2.0 if twice else 1.0)

    def summary(self) -> dict:
        """JSON-ready levels (None where the amplitude is zero: no sound, no level)."""
        from acoustics import sound_power_level_db, spl_db

        def level(fn, value):
            return float(fn(value)) if value > 0 else None

        unit = Sound(self.radiation, 1.0, self.microphone, self.travelling)
        return {
            "sound_power_level_db": level(sound_power_level_db, self.sound_power_w),
            "spl_db": level(spl_db, self.microphone_pressure_pa),
            "microphone_m": list(self.microphone),
            "radiation_efficiency": self.field.radiation_efficiency,
            "frequency_hz": self.field.frequency_hz,
            "velocity_amplitude_m_s": self.velocity_amplitude_m_s,
            "per_unit_velocity": {
                "sound_power_level_db": level(sound_power_level_db, unit.sound_power_w),
                "spl_db": level(spl_db, unit.microphone_pressure_pa),
            },
            "checks": {
                "surface_power_w": self.field.surface_power_w * self.velocity_amplitude_m_s**2,
                "flux_power_w": self.field.flux_power_w * self.velocity_amplitude_m_s**2,
            },
        }


def sound_of(
    radiation: Radiation, velocity_amplitude_m_s: float, microphone, travelling: bool = False
) -> Sound:
    """The levels of ``radiation`` (at 1 m/s) for a contact velocity amplitude [m/s] at a
    microphone (r, z, theta)."""
    if not (math.isfinite(velocity_amplitude_m_s) and velocity_amplitude_m_s >= 0):
        raise RequestError(f"velocity amplitude must be zero or positive, got {velocity_amplitude_m_s!r}")
    return Sound(radiation, float(velocity_amplitude_m_s), tuple(microphone), travelling)
