"""Levels as acousticians report them: A-weighting (IEC 61672-1), one-third-octave bands
(IEC 61260-1, base 10) and the band levels of a pressure signal.

A-weighting is the standard's analytic response,

    R_A(f) = 12194^2 f^4 / ((f^2 + 20.6^2) sqrt((f^2 + 107.7^2)(f^2 + 737.9^2)) (f^2 + 12194^2)),
    A(f) = 20 log10 R_A(f) + 2.00 dB,

0 dB at 1 kHz (to 0.001 dB), -8.3 dB at 261 Hz, +0.35 dB at 1136 Hz. The one-third-octave
bands have exact centres f_m = 1000 * 10^(k/10) Hz and edges f_m * 10^(-+1/20), and carry
the nominal labels of the standard (250, 315, ... 5000 Hz). Band levels of a signal are
its mean-square pressure split by frequency (Parseval), so they add up, in energy, to the
signal's overall level.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .medium import mean_square_spl_db

__all__ = [
    "NOMINAL_THIRD_OCTAVES_HZ",
    "ThirdOctaveBand",
    "a_weighting_db",
    "band_levels_db",
    "energy_sum_db",
    "third_octave_bands",
]

#: The nominal one-third-octave centre frequencies [Hz] (IEC 61260-1, ISO 266), k = -20..13
NOMINAL_THIRD_OCTAVES_HZ = (
    10,
    12.5,
    16,
    20,
    25,
    31.5,
    40,
    50,
    63,
    80,
    100,
    125,
    160,
    200,
    250,
    315,
    400,
    500,
    630,
    800,
    1000,
    1250,
    1600,
    2000,
    2500,
    3150,
    4000,
    5000,
    6300,
    8000,
    10000,
    12500,
    16000,
    20000,
)
#: The band index k of the first nominal frequency (10 Hz: f_m = 1000 * 10^(k/10))
_FIRST_K = -20


def a_weighting_db(frequency_hz):
    """The A-weighting [dB] at ``frequency_hz`` (IEC 61672-1's analytic form); -inf at 0."""
    f2 = np.asarray(frequency_hz, float) ** 2
    with np.errstate(divide="ignore"):
        r = (12194.0**2 * f2**2) / (
            (f2 + 20.6**2) * np.sqrt((f2 + 107.7**2) * (f2 + 737.9**2)) * (f2 + 12194.0**2)
        )
        return 20.0 * np.log10(r) + 2.00


@dataclass(frozen=True)
class ThirdOctaveBand:
    """A one-third-octave band: its exact centre [Hz], its nominal label [Hz] and its
    edges [Hz]."""

    centre_hz: float
    label_hz: float
    lower_hz: float
    upper_hz: float


def third_octave_bands(f_low_hz: float = 10.0, f_high_hz: float = 20000.0) -> list[ThirdOctaveBand]:
    """The bands whose centres lie in [f_low_hz, f_high_hz] (within the nominal 10 Hz to
    20 kHz)."""
    out = []
    for i, label in enumerate(NOMINAL_THIRD_OCTAVES_HZ):
        centre = 1000.0 * 10.0 ** ((_FIRST_K + i) / 10.0)
        if f_low_hz / 1.001 <= centre <= f_high_hz * 1.001:
            out.append(ThirdOctaveBand(centre, float(label), centre * 10 ** (-0.05), centre * 10**0.05))
    return out


def energy_sum_db(levels_db) -> float:
    """The level [dB] of the energy sum of ``levels_db`` (-inf for none)."""
    levels = np.asarray(levels_db, float)
    levels = levels[np.isfinite(levels)]
    if not len(levels):
        return -math.inf
    return float(10.0 * np.log10(np.sum(10.0 ** (levels / 10.0))))


def band_levels_db(
    pressure_pa: np.ndarray, sample_rate_hz: float, bands: list[ThirdOctaveBand]
) -> tuple[np.ndarray, float]:
    """The one-third-octave band levels [dB re 20 uPa] of a pressure signal [Pa] sampled
    at ``sample_rate_hz``, and its overall level [dB re 20 uPa] (its rms, time domain).
    The mean square is split by frequency from the signal's spectrum (Parseval, a
    rectangular window over the whole signal): the bands hold all of it that lies
    between the lowest band's lower edge and the highest band's upper edge."""
    p = np.asarray(pressure_pa, float)
    n = len(p)
    spec = np.fft.rfft(p)
    power = np.abs(spec) ** 2 / n**2  # two-sided |X_k|^2 / N^2 per bin
    power[1 : (n + 1) // 2] *= 2.0  # fold the negative frequencies (not DC or Nyquist)
    f = np.fft.rfftfreq(n, 1.0 / sample_rate_hz)
    levels = np.empty(len(bands))
    for i, b in enumerate(bands):
        sel = (f >= b.lower_hz) & (f < b.upper_hz)
        levels[i] = float(mean_square_spl_db(power[sel].sum()))
    return levels, float(mean_square_spl_db(np.mean(p**2)))
