"""The air and the decibel scales."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = [
    "AIR",
    "DENSITY_RANGE_KG_M3",
    "P_REF_PA",
    "SOUND_SPEED_RANGE_M_S",
    "W_REF_W",
    "Air",
    "implausible_air",
    "mean_square_spl_db",
    "sound_power_level_db",
    "spl_db",
]

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

#: The fluids a wheel may radiate into, from thin air at altitude (0.4 kg/m^3, 300 m/s)
#: to water (1000 kg/m^3, 1480 m/s), with room to spare; beyond them a value is a slip
#: of units.
DENSITY_RANGE_KG_M3 = (0.05, 2000.0)
SOUND_SPEED_RANGE_M_S = (100.0, 2000.0)


def implausible_air(density_kg_m3: float, sound_speed_m_s: float) -> str | None:
    """One line naming an implausible density [kg/m^3] or sound speed [m/s] (and the
    value meant, for a slip of units), or None."""
    lo, hi = DENSITY_RANGE_KG_M3
    if not (math.isfinite(density_kg_m3) and lo <= density_kg_m3 <= hi):
        hint = f" (looks like g/cm^3: write {density_kg_m3 * 1000:g})" if 5e-5 <= density_kg_m3 < lo else ""
        return f"air density {density_kg_m3:g} kg/m^3 is outside {lo:g} to {hi:g} kg/m^3{hint}"
    lo, hi = SOUND_SPEED_RANGE_M_S
    if not (math.isfinite(sound_speed_m_s) and lo <= sound_speed_m_s <= hi):
        hint = f" (looks like km/s: write {sound_speed_m_s * 1000:g})" if 0.1 <= sound_speed_m_s < 2 else ""
        return f"sound speed {sound_speed_m_s:g} m/s is outside {lo:g} to {hi:g} m/s{hint}"
    return None


def spl_db(pressure_amplitude_pa) -> np.ndarray:
    """Sound pressure level [dB re 20 uPa] of a tone of peak amplitude |p| (rms = |p|/sqrt 2)."""
    p_rms = np.abs(np.asarray(pressure_amplitude_pa)) / math.sqrt(2.0)
    with np.errstate(divide="ignore"):
        return 20.0 * np.log10(p_rms / P_REF_PA)


def mean_square_spl_db(mean_square_pa2) -> np.ndarray:
    """Sound pressure level [dB re 20 uPa] of a mean-square pressure [Pa^2] (-inf at 0)."""
    with np.errstate(divide="ignore"):
        return 10.0 * np.log10(np.asarray(mean_square_pa2, dtype=float) / P_REF_PA**2)


#: Below this sound pressure level [dB re 20 uPa] a microphone hears silence: 2 uPa, a
#: tenth of the threshold of hearing where the ear is most sensitive (a node of the
#: radiation, such as the axis of a mode with nodal diameters, gives round-off near
#: -260 dB, which is no level at all).
SILENT_SPL_DB = -20.0


def audible_spl_db(level_db: float | None) -> float | None:
    """``level_db`` [dB re 20 uPa], or None where it is silence (:data:`SILENT_SPL_DB`)."""
    if level_db is None or not level_db >= SILENT_SPL_DB:
        return None
    return float(level_db)


def sound_power_level_db(power_w) -> np.ndarray:
    """Sound power level [dB re 1 pW] of a time-averaged power [W]."""
    with np.errstate(divide="ignore"):
        return 10.0 * np.log10(np.asarray(power_w, dtype=float) / W_REF_W)
