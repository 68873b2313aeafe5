"""Which mode carries a multi-mode limit cycle: vibration energy per mode and the
spectrum of the contact velocity over the end of the record."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .model import TimeHistory, coordinates

__all__ = ["ModalContent", "modal_content"]

#: The end of the record analysed: this many periods of the lowest mode (at least), and
#: no more than a quarter of the record.
WINDOW_PERIODS = 200


@dataclass(frozen=True)
class ModalContent:
    """energy_share : each mode's share of the vibration energy (sum 1, about each
    coordinate's mean), time-averaged over the window, the counter-body's last where it
    moves; carrier : the mode with the
    largest share; peak_frequency_hz : the strongest frequency of the contact velocity
    there, Hz (in the frame of the contact); mode_frequency_hz : each mode's strongest
    frequency there (of its own coordinates' velocity), Hz (the tone a mode squeals at
    where several share a record that is not one periodic motion); window_s : the
    window's (start, end), s."""

    energy_share: np.ndarray
    carrier: int
    peak_frequency_hz: float
    window_s: tuple[float, float]
    mode_frequency_hz: np.ndarray = field(default_factory=lambda: np.zeros(0))


def _peak_hz(x: np.ndarray, dt: float) -> float:
    """The strongest frequency of the columns of ``x`` together (their power spectra
    summed, Hann window), interpolated between the bins on a log scale [Hz]."""
    x = np.atleast_2d(x.T).T if x.ndim == 1 else x
    x = x - x.mean(axis=0)
    spec = np.sqrt((np.abs(np.fft.rfft(x * np.hanning(len(x))[:, None], axis=0)) ** 2).sum(axis=1))
    k = int(np.argmax(spec[1:])) + 1
    if 1 <= k < len(spec) - 1:  # parabolic interpolation of the peak on a log scale
        a, b, c = np.log(spec[k - 1 : k + 2] + 1e-300)
        k = k + 0.5 * (a - c) / (a - 2 * b + c) if (a - 2 * b + c) != 0 else k
    return k / (len(x) * dt)


def modal_content(history: TimeHistory) -> ModalContent:
    """Energy shares and the contact velocity's peak frequency at the end of ``history``."""
    t, tm = history.t, history.modes_time
    f_low = min(md.frequency_hz for md in history.modes)
    span = min(WINDOW_PERIODS / f_low, 0.25 * float(t[-1]))
    sel = tm >= tm[-1] - span
    coords = history.coordinates or coordinates(history.modes, history.wheel_speed_rad_s)
    # the vibration about the mean: a static deflection (a track's under the steady creep
    # force) holds no vibration energy
    y, u = history.y_modes[sel], history.v_modes[sel]
    y = y - y.mean(axis=0)
    energy = 0.5 * (coords.m * u**2 + coords.k * y**2).mean(axis=0)
    per_mode = np.bincount(coords.mode, weights=energy, minlength=len(history.modes))
    if history.body is not None and history.body_states is not None:  # one more participant
        x = history.body_states[sel]
        x = x - x.mean(axis=0)
        body_energy = 0.5 * float((history.body.energy_weights() * x**2).mean(axis=0).sum())
        per_mode = np.append(per_mode, body_energy)
    share = per_mode / per_mode.sum() if per_mode.sum() > 0 else per_mode
    carrier = int(np.argmax(share[: len(history.modes)]))
    dt_modes = float(tm[1] - tm[0])
    own = np.array([_peak_hz(u[:, coords.mode == i], dt_modes) for i in range(len(history.modes))])
    sel = t >= t[-1] - span
    peak = _peak_hz(history.v[sel][:, None], float(t[1] - t[0]))
    return ModalContent(share, carrier, float(peak), (float(t[sel][0]), float(t[-1])), own)
