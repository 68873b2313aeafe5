"""A mode's tone as a microphone and a sound power measurement give it: its sound field at
1 m/s contact velocity seen from a microphone (:class:`Radiation`: the pressure there, on
the plot's circle and the far-field directivity) and its levels at a contact velocity
amplitude (:class:`Sound`). A limit cycle of amplitude v scales the pressure by v and the
power by v^2. Levels: SPL in dB re 20 uPa of the rms pressure (a pure tone, rms = peak /
sqrt 2), sound power level in dB re 1 pW.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .medium import audible_spl_db, sound_power_level_db, spl_db
from .waves import pressure_amplitude, radiated_power

if TYPE_CHECKING:
    from .helmholtz import SoundField

__all__ = ["RING_ANGLES", "RING_FRACTION", "Radiation", "Sound", "ring_points"]


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
    """A mode's sound field at 1 m/s contact velocity (``acoustics.SoundField``) and what
    the outputs look at, evaluated once with the field: its pressure [Pa] (complex
    amplitude of cos(n theta)) at the microphone's (r, z) and on :func:`ring_points`,
    and its far-field directivity |D| [Pa m] on ``acoustics.farfield.DIRECTIVITY_ANGLES``."""

    field: SoundField
    microphone_pressure_pa: complex
    ring_pressure_pa: np.ndarray
    directivity_pa_m: np.ndarray

    @classmethod
    def of(cls, field: SoundField, microphone: tuple[float, float, float]) -> Radiation:
        """The radiation of ``field`` (``acoustics.SoundField`` at 1 m/s) seen from a
        microphone (r, z[, theta])."""
        from .farfield import directivity

        # one evaluation for both (each builds the air mesh's basis)
        pressures = field.pressure_at(np.vstack([np.array([microphone[:2]]), ring_points(field.mesh.radius)]))
        return cls(field, complex(pressures[0]), pressures[1:], directivity(field))

    def scaled(self, factor: float) -> Radiation:
        """The radiation of the same surface vibrating ``factor`` times as fast (factor >
        0; ``SoundField.scaled``)."""
        return Radiation(
            self.field.scaled(factor),
            factor * self.microphone_pressure_pa,
            factor * self.ring_pressure_pa,
            factor * self.directivity_pa_m,
        )


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
    def field(self) -> SoundField:
        """The sound field at 1 m/s (``acoustics.SoundField``)."""
        return self.radiation.field

    @property
    def microphone_pressure_pa(self) -> float:
        """Peak pressure amplitude at the microphone [Pa] (``acoustics.waves``)."""
        p = pressure_amplitude(
            self.radiation.microphone_pressure_pa, self.field.harmonic, self.microphone[2], self.travelling
        )
        return p * self.velocity_amplitude_m_s

    def microphone_transfer(self) -> complex:
        """The complex pressure [Pa] at the microphone per unit contact velocity amplitude
        of the surface's phase (j sign(phi_c) against the contact's): P cos(n theta) for a
        standing wave; a travelling wave passes with the antinode's |P|."""
        n, theta = self.field.harmonic, self.microphone[2]
        factor = 1.0 if self.travelling else math.cos(n * theta)
        return self.radiation.microphone_pressure_pa * factor

    @property
    def sound_power_w(self) -> float:
        """Time-averaged radiated power [W] (a travelling wave: both members)."""
        w = radiated_power(self.field.sound_power_w, self.field.harmonic, self.travelling)
        return w * self.velocity_amplitude_m_s**2

    def summary(self) -> dict:
        """JSON-ready levels (None where the amplitude is zero: no sound, no level)."""

        def level(fn: Callable[[float], Any], value: float) -> float | None:
            return float(fn(value)) if value > 0 else None

        unit = Sound(self.radiation, 1.0, self.microphone, self.travelling)
        return {
            "sound_power_level_db": level(sound_power_level_db, self.sound_power_w),
            "spl_db": audible_spl_db(level(spl_db, self.microphone_pressure_pa)),
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
