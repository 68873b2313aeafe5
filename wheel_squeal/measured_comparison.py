"""Measured squeal levels beside the prediction: a CSV of what the rig gave
(``acoustics.measured``) and its comparison with a sweep's predicted levels. A measured
point is compared with the sweep's curve at the same wheel speed (within 1 %), interpolated
linearly in the crabbing velocity between neighbouring limit cycles; where the sweep has no
limit cycle on both sides, there is no prediction (empty), and a speed the sweep did not run
is refused in one line.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from acoustics.measured import Measured

from .runtime.request_errors import RequestError

if TYPE_CHECKING:
    from .sweeps import VerdictGrid

__all__ = ["Measured", "check_speeds", "compare_measured", "load_measured"]

#: A measured speed matches a swept one within this fraction
SPEED_RTOL = 0.01


def load_measured(path: str | Path) -> Measured:
    """The measured points of ``path`` (``acoustics.measured.read_measured``), with
    one-line errors."""
    from acoustics.measured import MeasuredFileError, read_measured

    try:
        return read_measured(path)
    except MeasuredFileError as exc:
        raise RequestError(str(exc)) from None


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
