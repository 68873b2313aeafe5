"""The sound's files for other tools: pressure.vtu (ParaView) and squeal.wav."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ..squeal_sound import SquealSound

__all__ = ["write_pressure_vtu", "write_squeal_wav", "write_wav"]


def write_squeal_wav(path: Path, sound: SquealSound) -> float:
    """squeal.wav: the microphone pressure over the run at 44.1 kHz, 16 bit, faded in and
    out, the limit cycle's peak at full scale; returns that peak [Pa] (summary.json has
    the levels)."""
    assert sound.signal is not None  # a squeal's sound keeps its record
    return write_wav(path, sound.signal.wav_samples(), sound.signal.wav_full_scale_pa())


def write_wav(path: Path, signal: np.ndarray, full_scale: float | None = None) -> float:
    """A WAV file of ``signal`` [Pa] at 44.1 kHz, 16 bit, written in one call
    (``acoustics.signal.wav_file_bytes``); returns the pressure at full scale [Pa]."""
    from acoustics.signal import WAV_RATE_HZ, wav_file_bytes

    data, peak = wav_file_bytes(signal, WAV_RATE_HZ, full_scale)
    path.write_bytes(data)
    return peak


def write_pressure_vtu(path: Path, sound: SquealSound) -> Path:
    """pressure.vtu: the pressure field on the (r, z) plane (x = r, y = z) for ParaView:
    real and imaginary parts, amplitude [Pa] and SPL [dB]."""
    import meshio

    from acoustics import spl_db

    field = sound.fundamental.field
    p = field.vertex_pressure() * sound.fundamental.velocity_amplitude_m_s
    pts = np.column_stack([field.mesh.points, np.zeros(len(field.mesh.points))])
    mesh = meshio.Mesh(
        pts,
        [("triangle", field.mesh.triangles)],
        point_data={
            "pressure_real_pa": p.real,
            "pressure_imag_pa": p.imag,
            "pressure_amplitude_pa": np.abs(p),
            "spl_db": np.nan_to_num(spl_db(p), neginf=-100.0),
        },
    )
    mesh.write(path)
    return Path(path)
