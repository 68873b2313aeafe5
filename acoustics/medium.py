"""The air and the decibel scales."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["AIR", "P_REF_PA", "W_REF_W", "Air", "sound_power_level_db", "spl_db"]

#: Reference sound pressure (rms) [Pa] and sound power [W].
P_REF_PA = 20e-6
W_REF_W = 1e-12


@dataclass(frozen=True)
class Air:
    """The fluid around the wheel: density [kg/m^3] and speed of sound [m/s]."""

    density_kg_m3: float = 1.21
    sound_speed_m_s: float = 343.0

    def __post_init__(self) -> None:
        for name in ("density_kg_m3", "sound_speed_m_s"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 0):
                raise ValueError(f"Air.{name} must be positive, got {v!r}")

    def wavenumber(self, frequency_hz: float) -> float:
        """k = 2 pi f / c [1/m]."""
        return 2 * math.pi * frequency_hz / self.sound_speed_m_s

    def wavelength(self, frequency_hz: float) -> float:
        """c / f [m]."""
        return self.sound_speed_m_s / frequency_hz

    @property
    def impedance(self) -> float:
        """rho c [Pa s/m]."""
        return self.density_kg_m3 * self.sound_speed_m_s


#: Air at 20 degC (the defaults).
AIR = Air()


def spl_db(pressure_amplitude_pa) -> np.ndarray:
    """Sound pressure level [dB re 20 uPa] of a tone of peak amplitude |p| (rms = |p|/sqrt 2)."""
    p_rms = np.abs(np.asarray(pressure_amplitude_pa)) / math.sqrt(2.0)
    with np.errstate(divide="ignore"):
        return 20.0 * np.log10(p_rms / P_REF_PA)


def sound_power_level_db(power_w) -> np.ndarray:
    """Sound power level [dB re 1 pW] of a time-averaged power [W]."""
    with np.errstate(divide="ignore"):
        return 10.0 * np.log10(np.asarray(power_w, dtype=float) / W_REF_W)
