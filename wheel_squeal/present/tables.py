"""The CSV files: one row per record (compare.csv, sweep.csv, stability.csv,
measured.csv), their columns from :mod:`wheel_squeal.fields`."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..output_files import columns_of
from ..outputs import write_csv
from ..sweeps import VerdictGrid

if TYPE_CHECKING:
    from ..analysis import Analysis
    from ..envelope import Envelope

__all__ = ["by_loudness", "write_envelope_csv", "write_measured_csv", "write_sweep_csv", "write_sweep_spl"]


def by_loudness(analyses: Sequence[Analysis]) -> list[Analysis]:
    """compare's order: the loudest sound power level first, then designs that squeal
    without a level (a modal model's), then the quiet ones; by name within each."""

    def rank(a: Analysis) -> tuple[float, str]:
        level = a.verdict.get("sound_power_level_db") if a.verdict.squeals else None
        if level is not None:
            return -float(level), a.design.name
        return (math.inf if not a.verdict.squeals else 1e9), a.design.name

    return sorted(analyses, key=rank)


def write_envelope_csv(path: Path, env: Envelope) -> Path:
    """stability.csv: one row per (crabbing velocity, speed) with the fastest mode."""
    rows = []
    for i, vc in enumerate(env.crabbing_velocities_m_s):
        for j, rpm in enumerate(env.rpm):
            m = env.modes[env.winner[i, j]]
            rows.append(
                {
                    "crabbing_velocity_m_s": float(vc),
                    "rpm": float(rpm),
                    "growth_rate_1_s": float(env.growth_rate_1_s[i, j]),
                    "unstable": bool(env.growth_rate_1_s[i, j] > 0),
                    "fastest_mode_index": m.index,
                    "fastest_mode": m.label(),
                    "fastest_mode_frequency_hz": m.frequency_hz,
                }
            )
    return write_csv(path, rows, columns_of("stability.csv"))


def _cell(x: float) -> float | None:
    return float(x) if np.isfinite(x) else None


def _rows(grid: VerdictGrid, fields: dict[str, np.ndarray]) -> list[dict]:
    return [
        {
            "crabbing_velocity_m_s": float(vc),
            "rpm": float(rpm),
            "rolling_speed_m_s": float(grid.rolling_speeds_m_s[j]),
            "verdict_mode": str(grid.mode[i, j]),
            "squeals": bool(grid.squeals[i, j]),
            "saturated": bool(grid.saturated[i, j]),
            **{k: _cell(v[i, j]) for k, v in fields.items()},
        }
        for i, vc in enumerate(grid.crabbing_velocities_m_s)
        for j, rpm in enumerate(grid.rpm)
    ]


def write_sweep_csv(path: Path, grid: VerdictGrid) -> Path:
    """sweep.csv: per point the verdict's mode, whether it squeals and saturates, the
    contact velocity amplitude [m/s], tone [Hz], linear growth rate [1/s] and time to
    saturation [s] (empty where they do not apply)."""
    fields = {
        "amplitude_m_s": grid.amplitude_m_s,
        "tone_hz": grid.tone_hz,
        "growth_rate_1_s": grid.growth_rate_1_s,
        "time_to_saturation_s": grid.time_to_saturation_s,
    }
    return write_csv(path, _rows(grid, fields), columns_of("sweep.csv"))


def write_sweep_spl(path: Path, grid: VerdictGrid) -> Path:
    """sweep_spl.csv: per point the verdict's mode, squeal and saturation, the amplitude
    [m/s], the SPL at the microphone [dB re 20 uPa] and the sound power level [dB re 1 pW]."""
    fields = {
        "amplitude_m_s": grid.amplitude_m_s,
        "spl_db": grid.spl_db,
        "sound_power_level_db": grid.sound_power_level_db,
    }
    return write_csv(path, _rows(grid, fields), columns_of("sweep_spl.csv"))


def write_measured_csv(path: Path, comparison: list[dict]) -> Path:
    """measured.csv: per measured point its values, the prediction there and the
    prediction minus the measurement (``wheel_squeal.measured_comparison.compare_measured``)."""
    return write_csv(path, comparison, columns_of("measured.csv"))
