"""The loudest pass-by of a curve map as heard and seen at the ISO 3095 microphone: its
sound file (passby.wav), its A-weighted level over time and its spectrogram (passby.png),
its one-third-octave band maxima."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from ..curve_case import CurveCase, PassbySound

__all__ = ["PASSBY_PNG", "PASSBY_WAV", "band_rows", "write_passby_files"]

#: The loudest pass-by's sound
PASSBY_WAV = "passby.wav"
#: Its level-time history and spectrogram
PASSBY_PNG = "passby.png"


def band_rows(case: CurveCase) -> list[dict]:
    """The bogie's largest level over the pass-by in each one-third-octave band that
    holds a tone, in dB and dB(A) (free field)."""
    from acoustics.levels import third_octave_bands

    assert case.passby is not None
    bands = third_octave_bands(20.0, 20000.0)
    centres = [b.centre_hz for b in bands]
    levels = case.passby.free.band_maxima_db(centres)
    weighted = case.passby.free.band_maxima_db(centres, a_weighted=True)
    return [
        {"band_hz": b.label_hz, "lpmax_db": float(lv), "lpamax_dba": float(la)}
        for b, lv, la in zip(bands, levels, weighted)
        if np.isfinite(lv)
    ]


def write_passby_files(folder: Path, heard: PassbySound) -> dict[str, Any]:
    """The loudest pass-by as heard at the microphone: passby.wav (16-bit, normalised to
    its peak pressure [Pa], which is returned with the duration) and passby.png (its
    A-weighted level over time, fast, and the spectrogram of the sound)."""
    from acoustics.signal import faded

    from .vtu_and_wav import write_wav

    rate = heard.sample_rate_hz
    peak = write_wav(folder / PASSBY_WAV, faded(heard.pressure_pa, rate, 0.5))
    _passby_figure(folder / PASSBY_PNG, heard.cases, heard.pressure_pa, rate)
    return {
        "file": PASSBY_WAV,
        "figure": PASSBY_PNG,
        "radius_m": heard.radius_m,
        "train_speed_km_h": heard.train_speed_km_h,
        "duration_s": heard.duration_s,
        "peak_pa": peak,
        "sample_rate_hz": rate,
    }


def _passby_figure(path: Path, group: Sequence[CurveCase], p: np.ndarray, rate_hz: float) -> None:
    """passby.png: L_A(t), fast, of the bogie's pass-by (its sources' mean squares with their
    A-weighting, from ``acoustics.passby``) over the spectrogram of the sound ``p``."""
    from matplotlib.figure import Figure

    from acoustics.signal import spectrogram_db

    from .canvas import PLOT_DPI

    passby = group[0].passby
    assert passby is not None  # the loudest group has a pass-by
    level = passby.free.fast_level_dba()
    fig = Figure(figsize=(8, 6))
    top, bottom = fig.subplots(2, 1, sharex=False)
    top.plot(passby.free.t, level)
    top.set_ylim(max(level.max() - 40, 0), level.max() + 3)
    top.set_ylabel("L_A, fast [dB(A)]")
    top.set_xlabel("time from the bogie's centre passing [s]")
    top.grid(True, alpha=0.3)
    f, t, db = spectrogram_db(p, rate_hz)
    keep = f <= 10000.0
    mesh = bottom.pcolormesh(t, f[keep], db[keep], shading="auto", vmin=db.max() - 60, vmax=db.max())
    fig.colorbar(mesh, ax=bottom, label="PSD [dB re (20 uPa)^2/Hz]")
    half = 0.5 * len(p) / rate_hz  # the sound file's span, the level's too
    top.set_xlim(-half, half)
    bottom.set_ylabel("frequency [Hz]")
    bottom.set_xlabel("time at the microphone [s]")
    radius, speed = group[0].radius_m, group[0].train_speed_km_h
    fig.suptitle(f"the loudest pass-by: R = {radius:g} m, {speed:g} km/h, 7.5 m from the track")
    fig.tight_layout()
    fig.savefig(path, dpi=PLOT_DPI)
