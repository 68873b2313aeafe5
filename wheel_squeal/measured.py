"""Measured squeal levels beside the prediction: a CSV of what the rig gave, read with
one-line errors, and its comparison with a sweep's predicted levels.

The file has a header and the columns ``crab_velocity`` [m/s], ``rpm``, ``spl_db``
[dB re 20 uPa at the microphone], optionally ``frequency_hz`` [Hz], in any order; other
columns are refused by name. A measured point is compared with the sweep's curve at the
same wheel speed (within 1 %), interpolated linearly in the crabbing velocity between
neighbouring limit cycles; where the sweep has no limit cycle on both sides, there is no
prediction (empty), and a speed the sweep did not run is refused in one line.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from geometry.files import read_text

from .errors import RequestError

if TYPE_CHECKING:
    from .sweeps import VerdictGrid

__all__ = ["Measured", "compare_measured", "load_measured"]

_REQUIRED = ("crab_velocity", "rpm", "spl_db")
_OPTIONAL = ("frequency_hz",)
#: A measured speed matches a swept one within this fraction
SPEED_RTOL = 0.01


@dataclass(frozen=True)
class Measured:
    """Measured points: crab_velocity [m/s], rpm, spl_db [dB re 20 uPa], frequency_hz
    [Hz] (NaN where not given), one entry per row."""

    crab_velocity: np.ndarray
    rpm: np.ndarray
    spl_db: np.ndarray
    frequency_hz: np.ndarray


def load_measured(path: str | Path) -> Measured:
    """The measured points of ``path`` (module docstring); a bad file raises
    :class:`~wheel_squeal.errors.RequestError` in one line naming the problem."""
    text = read_text(path, "measured data", RequestError)
    rows = list(csv.reader(io.StringIO(text)))
    rows = [r for r in rows if r and not r[0].lstrip().startswith("#")]
    if not rows:
        raise RequestError(f"{path}: no header: give the columns {', '.join(_REQUIRED)}[, frequency_hz]")
    header = [h.strip() for h in rows[0]]
    unknown = [h for h in header if h not in _REQUIRED + _OPTIONAL]
    missing = [h for h in _REQUIRED if h not in header]
    if unknown or missing:
        what = f"unknown column {unknown[0]!r}" if unknown else f"no column {missing[0]!r}"
        raise RequestError(
            f"{path}: {what}; the columns are {', '.join(_REQUIRED)} and optionally frequency_hz"
        )
    if len(rows) < 2:
        raise RequestError(f"{path}: no measured point below the header")
    values: dict[str, list[float]] = {h: [] for h in header}
    for line, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise RequestError(f"{path}: line {line} has {len(row)} values for {len(header)} columns")
        for h, cell in zip(header, row):
            try:
                x = float(cell) if cell.strip() else math.nan
            except ValueError:
                raise RequestError(f"{path}: line {line}, {h}: {cell.strip()!r} is not a number") from None
            if h in _REQUIRED and not math.isfinite(x):
                raise RequestError(f"{path}: line {line}, {h}: a finite number is needed")
            values[h].append(x)
    rpm = np.array(values["rpm"])
    if np.any(rpm <= 0):
        raise RequestError(f"{path}: rpm must be positive")
    n = len(rpm)
    return Measured(
        np.array(values["crab_velocity"]),
        rpm,
        np.array(values["spl_db"]),
        np.array(values.get("frequency_hz", [math.nan] * n)),
    )


def compare_measured(grid: VerdictGrid, measured: Measured) -> list[dict]:
    """Per measured point: its values, the sweep's predicted SPL and tone there, and the
    prediction minus the measurement [dB, Hz] (None where the sweep has no limit cycle
    on both sides of the point)."""
    vcs = grid.crabbing_velocities_m_s
    out = []
    for vc, rpm, spl, f in zip(measured.crab_velocity, measured.rpm, measured.spl_db, measured.frequency_hz):
        j = int(np.argmin(np.abs(grid.rpm - rpm)))
        if abs(grid.rpm[j] - rpm) > SPEED_RTOL * rpm:
            swept = ", ".join(f"{r:g}" for r in grid.rpm)
            raise RequestError(
                f"measured speed {rpm:g} RPM is not among the sweep's ({swept}): give it with --rpm"
            )
        cycle = grid.squeals[:, j] & grid.saturated[:, j] & np.isfinite(grid.spl_db[:, j])
        predicted_spl = _between(vcs, grid.spl_db[:, j], cycle, vc)
        predicted_tone = _between(vcs, grid.tone_hz[:, j], cycle, vc)
        out.append(
            {
                "crabbing_velocity_m_s": float(vc),
                "rpm": float(rpm),
                "measured_spl_db": float(spl),
                "predicted_spl_db": predicted_spl,
                "spl_difference_db": None if predicted_spl is None else predicted_spl - float(spl),
                "measured_frequency_hz": float(f) if math.isfinite(f) else None,
                "predicted_tone_hz": predicted_tone,
                "tone_difference_hz": (
                    None if predicted_tone is None or not math.isfinite(f) else predicted_tone - float(f)
                ),
            }
        )
    return out


def _between(x: np.ndarray, y: np.ndarray, valid: np.ndarray, at: float) -> float | None:
    """y at ``at``, linear between the neighbouring valid points (exact on one); None
    outside them or where a neighbour is not valid."""
    exact = np.flatnonzero(np.isclose(x, at, rtol=0, atol=1e-12))
    if len(exact):
        k = int(exact[0])
        return float(y[k]) if valid[k] else None
    hi = int(np.searchsorted(x, at))
    if hi == 0 or hi == len(x) or not (valid[hi - 1] and valid[hi]):
        return None
    w = (at - x[hi - 1]) / (x[hi] - x[hi - 1])
    return float((1 - w) * y[hi - 1] + w * y[hi])
