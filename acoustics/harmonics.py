"""A squeal's harmonics: which of the contact velocity's harmonics over a limit cycle are
radiated, and at which frequency a tone is radiated.

The harmonics over the last :data:`LIMIT_CYCLE_PERIODS` periods of a record are radiated up
to the fewest that hold :data:`HARMONIC_ENERGY_SHARE` of its energy (at most
:data:`MAX_HARMONICS`, none above :data:`MAX_HARMONIC_HZ`: the air mesh grows as the
frequency squared; the share they hold is reported). Each harmonic k of the tone f0 is the
mode's shape vibrating at k f0 (the radiation at k times the mode's frequency).
"""

from __future__ import annotations

import math

import numpy as np

from .signal import harmonic_amplitudes, harmonics_holding, periodic_samples, whole_periods

__all__ = [
    "HARMONIC_ENERGY_SHARE",
    "LIMIT_CYCLE_PERIODS",
    "MAX_HARMONICS",
    "MAX_HARMONIC_HZ",
    "RADIATION_STEP",
    "kept_harmonics",
    "limit_cycle_harmonics",
    "max_harmonic_order",
    "radiation_frequency_hz",
]

#: The contact velocity's harmonics radiated hold this share of its energy
HARMONIC_ENERGY_SHARE = 0.99
#: ... and are at most this many, none above this frequency [Hz]
MAX_HARMONICS, MAX_HARMONIC_HZ = 8, 10_000.0
#: ... and none whose energy is below this fraction of the fundamental's (-20 dB): a
#: record of several modes never holds the share in one mode's harmonics, and a
#: harmonic that small adds next to nothing to a level (railway_920_track at 300 m /
#: 40 km/h: the (7,1) mode's second harmonic, 26 dB below its fundamental's band, adds
#: 0.01 dB to L_pAmax), while its radiation at twice the frequency is a solve of four
#: times the unknowns (there 39 s and 2.3 GB of the run's 51 s)
HARMONIC_FLOOR = 1e-2
#: A record whose zero crossings give a frequency this far (relative) from the verdict's
#: tone is analysed over whole periods of the tone instead
TONE_MISMATCH = 0.1
#: The limit cycle's harmonics and band levels are taken over its last this many periods
LIMIT_CYCLE_PERIODS = 50
#: Samples per period the limit cycle is resampled to for its spectrum (its harmonics
#: up to the 16th, far above :data:`MAX_HARMONICS`)
SAMPLES_PER_PERIOD = 32


def limit_cycle_harmonics(
    t: np.ndarray, v: np.ndarray, f0_hz: float, mode_frequency_hz: float
) -> tuple[tuple[int, ...], np.ndarray, float, tuple[float, float, int], np.ndarray]:
    """(orders, complex amplitudes [m/s], the share of the velocity's energy they hold,
    the window (start, end [s], whole periods), the velocity's samples over it, at
    :data:`SAMPLES_PER_PERIOD` per period): the contact velocity's harmonics over the
    limit cycle of the record ``t`` [s], ``v`` [m/s] at the tone ``f0_hz`` [Hz], the fewest
    holding :data:`HARMONIC_ENERGY_SHARE` (module docstring)."""
    periods = max(1, min(LIMIT_CYCLE_PERIODS, int(0.25 * (t[-1] - t[0]) * f0_hz)))
    start, end, count = whole_periods(t, v, periods)
    if abs(count / (end - start) / f0_hz - 1.0) > TONE_MISMATCH:
        # the record is not periodic at the tone (several frequencies, not settled): its
        # zero crossings count another frequency; take whole periods of the tone itself
        count = periods
        end = float(t[-1])
        start = end - count / f0_hz
    samples = periodic_samples(t, v, start, end, count * SAMPLES_PER_PERIOD)
    amps = harmonic_amplitudes(samples, count, max_harmonic_order(mode_frequency_hz))
    orders, share = kept_harmonics(amps, float(np.var(samples)))
    return orders, amps[: len(orders)], share, (start, end, count), samples


def max_harmonic_order(mode_frequency_hz: float) -> int:
    """The highest harmonic a squeal of a mode at ``mode_frequency_hz`` may radiate
    (:data:`MAX_HARMONICS`, none above :data:`MAX_HARMONIC_HZ`)."""
    return max(1, min(MAX_HARMONICS, int(MAX_HARMONIC_HZ / mode_frequency_hz)))


def kept_harmonics(amplitudes: np.ndarray, mean_square: float) -> tuple[tuple[int, ...], float]:
    """The orders of the contact velocity's harmonics (complex ``amplitudes`` [m/s], the
    fundamental first) that are radiated, and the share of the velocity's ``mean_square``
    [m^2/s^2] they hold (module docstring)."""
    amps = np.abs(np.asarray(amplitudes))
    k, share = harmonics_holding(amps, mean_square, HARMONIC_ENERGY_SHARE)
    while k > 1 and amps[k - 1] ** 2 < HARMONIC_FLOOR * amps[0] ** 2:
        k -= 1
    share = min(share, 0.5 * float(np.sum(amps[:k] ** 2)) / max(mean_square, 1e-300))
    return tuple(range(1, k + 1)), share


#: A squeal is radiated at the frequency nearest its tone on a grid of this relative step
#: through its radiating mode's natural frequency: one solve per mode, harmonic and grid
#: point, cached, whatever tone each operating point squeals at (within half a step of
#: the tone: 0.0003 dB on the Table 1 mode, whose tone is 0.001 % from the grid point)
RADIATION_STEP = 0.01


def radiation_frequency_hz(tone_hz: float, natural_hz: float) -> float:
    """The frequency [Hz] a squeal at ``tone_hz`` is radiated at (:data:`RADIATION_STEP`):
    ``natural_hz`` (1 + step)^k, the k nearest the tone."""
    ratio = math.log1p(RADIATION_STEP)
    return natural_hz * math.exp(ratio * round(math.log(tone_hz / natural_hz) / ratio))
