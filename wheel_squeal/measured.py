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
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from geometry.files import read_text

from .errors import RequestError

if TYPE_CHECKING:
    from .sweeps import VerdictGrid

__all__ = ["MAX_POINTS", "RANGES", "Measured", "check_speeds", "compare_measured", "load_measured"]

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


#: Plausible ranges of the measured values (low, high, unit): outside them a value is a
#: typing error or another unit.
RANGES = {
    "crab_velocity": (-10.0, 10.0, "m/s"),
    "rpm": (1e-3, 1e5, "rev/min"),
    "spl_db": (-20.0, 200.0, "dB re 20 uPa"),
    "frequency_hz": (1.0, 1e6, "Hz"),
}
#: The most measured points a file may hold (a rig's campaign is hundreds).
MAX_POINTS = 100_000


def load_measured(path: str | Path) -> Measured:
    """The measured points of ``path`` (module docstring); a bad file raises
    :class:`~wheel_squeal.errors.RequestError` in one line naming the problem (with the
    line of the file, comments counted)."""
    text = read_text(path, "measured data", RequestError).removeprefix("\ufeff")  # a spreadsheet's BOM
    try:
        numbered = [
            (line, row)
            for line, row in enumerate(csv.reader(io.StringIO(text)), start=1)
            if row and not row[0].lstrip().startswith("#")
        ]
    except csv.Error as exc:
        raise RequestError(f"{path}: not a readable CSV file ({exc})") from None
    if not numbered:
        raise RequestError(f"{path}: no header: give the columns {', '.join(_REQUIRED)}[, frequency_hz]")
    header_line, header_row = numbered[0]
    header = [h.strip() for h in header_row]
    unknown = [h for h in header if h not in _REQUIRED + _OPTIONAL]
    missing = [h for h in _REQUIRED if h not in header]
    if unknown or missing:
        what = f"unknown column {unknown[0][:40]!r}" if unknown else f"no column {missing[0]!r}"
        raise RequestError(
            f"{path}: {what}; the columns are {', '.join(_REQUIRED)} and optionally frequency_hz"
        )
    twice = sorted({h for h in header if header.count(h) > 1})
    if twice:
        raise RequestError(f"{path}: line {header_line}: the column {twice[0]!r} is given twice")
    if len(numbered) < 2:
        raise RequestError(f"{path}: no measured point below the header")
    if len(numbered) - 1 > MAX_POINTS:
        raise RequestError(f"{path}: {len(numbered) - 1:,} measured points, more than {MAX_POINTS:,}")
    values: dict[str, list[float]] = {h: [] for h in header}
    for line, row in numbered[1:]:
        if len(row) != len(header):
            raise RequestError(f"{path}: line {line} has {len(row)} values for {len(header)} columns")
        for h, cell in zip(header, row):
            values[h].append(_value(path, line, h, cell))
    n = len(values["rpm"])
    return Measured(
        np.array(values["crab_velocity"]),
        np.array(values["rpm"]),
        np.array(values["spl_db"]),
        np.array(values.get("frequency_hz", [math.nan] * n)),
    )


def _value(path: str | Path, line: int, column: str, cell: str) -> float:
    """One cell's number, checked against :data:`RANGES` (empty: NaN, for frequency_hz)."""
    where = f"{path}: line {line}, {column}"
    text = cell.strip()
    if not text and column in _OPTIONAL:
        return math.nan
    try:
        x = float(text)
    except ValueError:
        shown = text if len(text) <= 40 else text[:37] + "..."
        raise RequestError(f"{where}: {shown!r} is not a number") from None
    low, high, unit = RANGES[column]
    if not (math.isfinite(x) and low <= x <= high):
        raise RequestError(f"{where}: {x:g} {unit} is outside {low:g} to {high:g} {unit}")
    return x


def check_speeds(measured: Measured, rpms: Sequence[float]) -> None:
    """Refuse (one line, before any work) measured speeds the sweep will not run."""
    swept = np.asarray(rpms, float)
    for rpm in np.unique(measured.rpm):
        if not np.any(np.abs(swept - rpm) <= SPEED_RTOL * rpm):
            listed = ", ".join(f"{r:g}" for r in swept)
            raise RequestError(
                f"measured speed {rpm:g} RPM is not among the sweep's ({listed}): "
                "add it to the sweep's speeds"
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
                f"measured speed {rpm:g} RPM is not among the sweep's ({swept}): add it to the sweep's speeds"
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
