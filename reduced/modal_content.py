"""Which mode carries a multi-mode limit cycle: vibration energy per mode and the
spectrum of the contact velocity over the end of the record."""

from __future__ import annotations

from dataclasses import dataclass

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
    there, Hz (in the frame of the contact); window_s : the window's (start, end), s."""

    energy_share: np.ndarray
    carrier: int
    peak_frequency_hz: float
    window_s: tuple[float, float]


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
    sel = t >= t[-1] - span
    v = history.v[sel] - history.v[sel].mean()
    spec = np.abs(np.fft.rfft(v * np.hanning(len(v))))
    dt = float(t[1] - t[0])
    k = int(np.argmax(spec[1:])) + 1
    if 1 <= k < len(spec) - 1:  # parabolic interpolation of the peak on a log scale
        a, b, c = np.log(spec[k - 1 : k + 2] + 1e-300)
        k = k + 0.5 * (a - c) / (a - 2 * b + c) if (a - 2 * b + c) != 0 else k
    peak = k / (len(v) * dt)
    carrier = int(np.argmax(share[: len(history.modes)]))
    return ModalContent(share, carrier, float(peak), (float(t[sel][0]), float(t[-1])))
