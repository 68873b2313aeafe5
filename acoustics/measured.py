"""Squeal levels measured on a rig: a CSV of the points (``crab_velocity`` [m/s], ``rpm``,
``spl_db`` [dB re 20 uPa at the microphone], optionally ``frequency_hz`` [Hz], in any order;
other columns are refused by name; ``#`` starts a comment line), read with one-line errors
(:class:`MeasuredFileError`) naming the file, the line and the value."""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from geometry.files import read_text

__all__ = ["MAX_POINTS", "RANGES", "Measured", "MeasuredFileError", "read_measured"]


class MeasuredFileError(ValueError):
    """A measured-data file that cannot be read (one line: the file, the line, why)."""


_REQUIRED = ("crab_velocity", "rpm", "spl_db")
_OPTIONAL = ("frequency_hz",)


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


def read_measured(path: str | Path) -> Measured:
    """The measured points of ``path`` (module docstring); a bad file raises
    :class:`MeasuredFileError` in one line naming the problem (with the line of the file,
    comments counted)."""
    text = read_text(path, "measured data", MeasuredFileError).removeprefix("\ufeff")  # a spreadsheet's BOM
    try:
        numbered = [
            (line, row)
            for line, row in enumerate(csv.reader(io.StringIO(text)), start=1)
            if row and not row[0].lstrip().startswith("#")
        ]
    except csv.Error as exc:
        raise MeasuredFileError(f"{path}: not a readable CSV file ({exc})") from None
    if not numbered:
        raise MeasuredFileError(f"{path}: no header: give the columns {', '.join(_REQUIRED)}[, frequency_hz]")
    header_line, header_row = numbered[0]
    header = [h.strip() for h in header_row]
    unknown = [h for h in header if h not in _REQUIRED + _OPTIONAL]
    missing = [h for h in _REQUIRED if h not in header]
    if unknown or missing:
        what = f"unknown column {unknown[0][:40]!r}" if unknown else f"no column {missing[0]!r}"
        raise MeasuredFileError(
            f"{path}: {what}; the columns are {', '.join(_REQUIRED)} and optionally frequency_hz"
        )
    twice = sorted({h for h in header if header.count(h) > 1})
    if twice:
        raise MeasuredFileError(f"{path}: line {header_line}: the column {twice[0]!r} is given twice")
    if len(numbered) < 2:
        raise MeasuredFileError(f"{path}: no measured point below the header")
    if len(numbered) - 1 > MAX_POINTS:
        raise MeasuredFileError(f"{path}: {len(numbered) - 1:,} measured points, more than {MAX_POINTS:,}")
    values: dict[str, list[float]] = {h: [] for h in header}
    for line, row in numbered[1:]:
        if len(row) != len(header):
            raise MeasuredFileError(f"{path}: line {line} has {len(row)} values for {len(header)} columns")
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
        raise MeasuredFileError(f"{where}: {shown!r} is not a number") from None
    low, high, unit = RANGES[column]
    if not (math.isfinite(x) and low <= x <= high):
        raise MeasuredFileError(f"{where}: {x:g} {unit} is outside {low:g} to {high:g} {unit}")
    return x
