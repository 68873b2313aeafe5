"""From a vibration record to what a microphone records: the harmonics of a periodic
velocity, the pressure signal through a transfer function known at those harmonics,
resampling, and a WAV file.

A limit cycle is periodic but not sinusoidal: its velocity holds harmonics at k f0, and
each radiates at its own frequency. The pressure signal of a whole run (its growth
and its limit cycle) is built in the frequency domain: the velocity record's spectrum
is split into bands around the harmonics, ((k - 1/2) f0, (k + 1/2) f0], and each band is
multiplied by the transfer (pressure per unit velocity, complex) at k f0. The growth
spreads each harmonic over a few Hz, a band is f0 wide: the transfer is taken constant
across it (the radiation varies over hundreds of Hz).
"""

from __future__ import annotations

import math
import struct
from dataclasses import dataclass

import numpy as np

__all__ = [
    "MAX_WAV_SECONDS",
    "WAV_FADE_S",
    "WAV_RATE_HZ",
    "MicrophoneSignal",
    "faded",
    "periodic_samples",
    "whole_periods",
    "harmonic_amplitudes",
    "harmonics_holding",
    "line_spectrum",
    "pressure_signal",
    "resample",
    "wav_file_bytes",
]

#: The WAV files' sample rate [Hz] (CD audio)
WAV_RATE_HZ = 44_100

#: The longest squeal WAV [s] (0.9 MB at 44.1 kHz and 16 bit)
MAX_WAV_SECONDS = 10.0
#: squeal WAV fades in and out over this time [s] (raised cosine: no click)
WAV_FADE_S = 0.02


def whole_periods(t: np.ndarray, x: np.ndarray, periods: int) -> tuple[float, float, int]:
    """(start, end [s], count): the last ``periods`` whole periods of an oscillating
    record, between upward zero crossings (interpolated between samples; fewer periods
    where the record holds fewer). A window of whole periods keeps a periodic signal's
    spectrum free of leakage."""
    t, x = np.asarray(t, float), np.asarray(x, float)
    x = x - np.mean(x[len(x) // 2 :])
    up = np.flatnonzero((x[:-1] < 0.0) & (x[1:] >= 0.0))
    if len(up) < 2:
        return float(t[0]), float(t[-1]), 1
    cross = t[up] - x[up] * (t[up + 1] - t[up]) / (x[up + 1] - x[up])
    count = min(periods, len(cross) - 1)
    return float(cross[-1 - count]), float(cross[-1]), int(count)


def periodic_samples(t: np.ndarray, x: np.ndarray, start: float, end: float, samples: int) -> np.ndarray:
    """``samples`` equally spaced samples of ``x`` (uniformly sampled at ``t``) over
    [start, end), by four-point cubic (Lagrange) interpolation: on a record of 48 samples
    per period its amplitude error is 2e-5 (linear interpolation would lose 0.15 %). For
    whole periods, the samples of one period of a periodic sequence, whose DFT bins fall
    on the harmonics."""
    t, x = np.asarray(t, float), np.asarray(x, float)
    dt = float(t[1] - t[0])
    s = (start + (end - start) * np.arange(samples) / samples - t[0]) / dt
    k = np.clip(np.floor(s).astype(np.int64), 1, len(x) - 3)
    u = s - k
    weights = (
        -u * (u - 1) * (u - 2) / 6,
        (u + 1) * (u - 1) * (u - 2) / 2,
        -(u + 1) * u * (u - 2) / 2,
        (u + 1) * u * (u - 1) / 6,
    )
    return sum(w * x[k + j] for w, j in zip(weights, (-1, 0, 1, 2)))


def harmonic_amplitudes(samples: np.ndarray, periods: int, k_max: int) -> np.ndarray:
    """The complex amplitudes X_k (x ~ sum Re(X_k e^{j 2 pi k f0 t})) of k = 1..k_max of
    ``samples`` spanning ``periods`` whole periods (:func:`periodic_samples`): the DFT
    bins k * periods."""
    spec = np.fft.rfft(np.asarray(samples, float)) * 2.0 / len(samples)
    bins = np.arange(1, k_max + 1) * periods
    return np.where(bins < len(spec), spec[np.minimum(bins, len(spec) - 1)], 0.0)


def line_spectrum(samples: np.ndarray, periods: int) -> tuple[np.ndarray, np.ndarray]:
    """(orders k, amplitudes |X_k|) of every harmonic of ``samples`` spanning ``periods``
    whole periods, up to the highest the sampling resolves."""
    spec = np.abs(np.fft.rfft(np.asarray(samples, float))) * 2.0 / len(samples)
    bins = np.arange(periods, len(spec), periods)
    return bins // periods, spec[bins]


def harmonics_holding(amplitudes: np.ndarray, mean_square: float, share: float) -> tuple[int, float]:
    """(k, held): the fewest leading harmonics (at least one, at most all given) whose
    energy |X_k|^2 / 2 holds ``share`` of a signal's ``mean_square`` (its variance), and
    the share they hold."""
    if mean_square <= 0:
        return 1, 1.0
    held = 0.5 * np.cumsum(np.abs(np.asarray(amplitudes)) ** 2) / mean_square
    k = min(len(held), int(np.searchsorted(held, share * (1 - 1e-12))) + 1)
    return k, min(1.0, float(held[k - 1]))


def pressure_signal(
    t: np.ndarray, x: np.ndarray, f0_hz: float, transfer: dict[int, complex], periodic: bool = False
) -> np.ndarray:
    """The pressure record [Pa] of a velocity record ``x`` [m/s] (uniform ``t`` [s]) with
    the transfer ``transfer[k]`` [Pa per m/s] at the harmonic k f0 applied to the band
    around it (module docstring); bands without a transfer are left out. ``periodic``:
    the record is whole periods of a periodic signal (its spectrum is then exact); else
    it is padded with as many zeros, so that its end does not wrap onto its start."""
    from scipy.fft import next_fast_len

    x = np.asarray(x, float)
    n = len(x)
    dt = float(t[1] - t[0])
    # padded to a length of small prime factors: a record's own length may hold a large
    # prime, which makes its transform many times slower
    size = n if periodic else next_fast_len(2 * n, real=True)
    spec = np.fft.rfft(x, size)
    f = np.fft.rfftfreq(size, dt)
    out = np.zeros_like(spec)
    for k, h in transfer.items():
        band = (f > (k - 0.5) * f0_hz) & (f <= (k + 0.5) * f0_hz)
        out[band] = spec[band] * h
    return np.fft.irfft(out, size)[:n]


def resample(t: np.ndarray, x: np.ndarray, rate_hz: float) -> np.ndarray:
    """``x`` on a uniform grid of ``rate_hz`` over the record's span (linear
    interpolation: the record is sampled much finer than its content)."""
    n = int(math.floor((t[-1] - t[0]) * rate_hz)) + 1
    return np.interp(t[0] + np.arange(n) / rate_hz, t, x)


def faded(signal: np.ndarray, rate_hz: float, fade_s: float) -> np.ndarray:
    """``signal`` faded in and out over ``fade_s`` [s] each end (raised cosine)."""
    s = np.array(signal, float)
    n = min(int(round(fade_s * rate_hz)), len(s) // 2)
    if n > 0:
        ramp = 0.5 - 0.5 * np.cos(np.pi * np.arange(n) / n)
        s[:n] *= ramp
        s[len(s) - n :] *= ramp[::-1]
    return s


def wav_file_bytes(
    signal: np.ndarray, rate_hz: int = WAV_RATE_HZ, full_scale: float | None = None
) -> tuple[bytes, float]:
    """``signal`` as a mono 16-bit PCM WAV file's bytes, ``full_scale`` at full scale
    (default its largest |sample|; louder samples are clipped), and the value it was
    divided by (0: a silent file)."""
    s = np.asarray(signal, float)
    peak = float(np.max(np.abs(s))) if len(s) else 0.0
    if full_scale is not None and full_scale > 0:
        peak = float(full_scale)
    pcm = (
        np.zeros(len(s), dtype="<i2")
        if peak == 0
        else np.round(np.clip(s / peak, -1.0, 1.0) * 32767).astype("<i2")
    )
    return wav_bytes(pcm, int(rate_hz)), peak


def wav_bytes(pcm: np.ndarray, rate_hz: int) -> bytes:
    """A mono 16-bit PCM WAV file's bytes (RIFF header and samples), made in memory and
    written in one call: an interrupted write leaves no half-made writer object behind
    (the standard library's ``wave`` fails in its finaliser when stopped mid-open)."""
    data = np.asarray(pcm, dtype="<i2").tobytes()
    fmt = struct.pack("<HHIIHH", 1, 1, rate_hz, 2 * rate_hz, 2, 16)  # PCM, mono, 16 bit
    body = (
        b"WAVE" + b"fmt " + struct.pack("<I", len(fmt)) + fmt + b"data" + struct.pack("<I", len(data)) + data
    )
    return b"RIFF" + struct.pack("<I", len(body)) + body


def spectrogram_db(
    pressure_pa: np.ndarray, sample_rate_hz: float, segment: int = 4096
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The spectrogram of a pressure signal [Pa]: (frequencies [Hz], segment centres [s]
    from the signal's middle, power spectral density level [dB re (20 uPa)^2/Hz]) of
    Hann-windowed segments of ``segment`` samples overlapping by half."""
    from scipy.signal import spectrogram

    f, t, sxx = spectrogram(pressure_pa, fs=sample_rate_hz, nperseg=segment, noverlap=segment // 2)
    return f, t - 0.5 * len(pressure_pa) / sample_rate_hz, 10 * np.log10(np.maximum(sxx, 1e-30) / 4e-10)


@dataclass(frozen=True, eq=False)
class MicrophoneSignal:
    """The pressure at the microphone: over the simulated run, t [s] (uniform) and p
    [Pa]; over whole periods of the limit cycle, ``cycle_pa`` [Pa] at ``cycle_rate_hz``
    (from the contact velocity's periodic samples there, exact for a periodic signal:
    its levels and bands are taken from it)."""

    t: np.ndarray
    p: np.ndarray
    cycle_pa: np.ndarray
    cycle_rate_hz: float
    window: tuple[float, float, int]

    def tail(self, seconds: float) -> MicrophoneSignal:
        """The signal over the run's last ``seconds`` (the limit cycle's periods kept)."""
        keep = self.t >= self.t[-1] - seconds
        return MicrophoneSignal(
            self.t[keep].copy(), self.p[keep].copy(), self.cycle_pa, self.cycle_rate_hz, self.window
        )

    def wav_samples(self) -> np.ndarray:
        """The pressure over the run at the WAV file's sample rate [Pa], its last
        :data:`MAX_WAV_SECONDS` at most (a very low tone's run is long), faded in and
        out over :data:`WAV_FADE_S` (the band filter's edges would click)."""
        keep = self.t >= self.t[-1] - MAX_WAV_SECONDS
        return faded(resample(self.t[keep], self.p[keep], WAV_RATE_HZ), WAV_RATE_HZ, WAV_FADE_S)

    def wav_full_scale_pa(self) -> float:
        """The pressure [Pa] the WAV's full scale stands for: the peak of its steady part
        (the limit cycle's window), not of an edge or of the growth's overshoot."""
        samples = self.wav_samples()
        start = max(self.t[-1] - MAX_WAV_SECONDS, self.t[0])
        first = max(0, int((self.window[0] - start) * WAV_RATE_HZ))
        steady = samples[first:] if first < len(samples) else samples
        return float(np.max(np.abs(steady))) if len(steady) else 0.0
