"""A squeal model's record for other tools and for the eye: timeseries.csv (the contact's
quantities, every k-th sample to stay within its size) and the figures of Liu & Meehan
(CM2015): the creep curve (Fig. 4), the velocity from rest (Fig. 6), the velocity and
force (Fig. 7, 9) and the power input (Fig. 8, 10) over a few cycles. Each figure holds
no more points than its pixels show (``canvas.decimate``)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from reduced import TimeHistory, adhesion_ratio
from reduced.summaries import TIMESERIES_COLUMNS, timeseries_table

from .canvas import decimate, figure, save

__all__ = [
    "TIMESERIES_BYTES",
    "TIME_HISTORY_FIGURES",
    "TIMESERIES_ROW_BYTES",
    "timeseries_stride",
    "write_time_history_plots",
    "write_timeseries_csv",
]

#: What timeseries.csv may hold unless the whole record is asked for (``--full-record``,
#: up to the size any file may take) [bytes]: every k-th sample beyond it
TIMESERIES_BYTES = 20e6
#: The longest row of timeseries.csv [bytes]: nine numbers of at most 15 characters
#: (``-1.23456789e-05``), their separators and the line end.
TIMESERIES_ROW_BYTES = 9 * 16


def timeseries_stride(history: TimeHistory, max_bytes: float = math.inf) -> int:
    """k: timeseries.csv holds every k-th sample, so that it stays within ``max_bytes``."""
    return max(1, math.ceil(len(history.t) * TIMESERIES_ROW_BYTES / max_bytes))


def write_timeseries_csv(
    history: TimeHistory, directory: Path, name: str = "timeseries.csv", max_bytes: float = math.inf
) -> Path:
    """Write ``reduced.summaries.TIMESERIES_COLUMNS`` (contact-point totals) as a plain CSV
    (one header line, then numbers: any CSV reader takes it as it is), every sample, or
    every k-th where all of them would exceed ``max_bytes`` (:func:`timeseries_stride`;
    summary.json says k)."""
    path = Path(directory) / name
    data = timeseries_table(history)[:: timeseries_stride(history, max_bytes)]
    header = ",".join(TIMESERIES_COLUMNS)
    row = ",".join(["%.9g"] * data.shape[1]) + "\n"
    # one format operation for the whole table: the text of np.savetxt, 2.5x faster
    path.write_text(header + "\n" + (row * len(data)) % tuple(data.ravel().tolist()))
    return path


def _window(history: TimeHistory, centre_s: float, n_cycles: float = 6.0) -> tuple[np.ndarray, float]:
    """Samples of ``n_cycles`` periods of the highest mode around ``centre_s``, kept
    inside the record (a record shorter than the window is shown whole)."""
    f = max(md.frequency_hz for md in history.modes)
    t_end = float(history.t[-1])
    half = min(0.5 * n_cycles / f, 0.5 * t_end)
    centre = min(max(centre_s, half), t_end - half)
    sel = (history.t >= centre - half) & (history.t <= centre + half)
    return sel, centre


#: The figures of a time history (:func:`write_time_history_plots`), by name.
TIME_HISTORY_FIGURES = ("creep_curve", "velocity_history", "force_velocity", "power")


def write_time_history_plots(
    history: TimeHistory, directory: Path, times_s: tuple = (0.2, 0.4), figures: tuple = TIME_HISTORY_FIGURES
) -> list:
    """PNG plots: creep_curve.png (Fig. 4), velocity_history.png (Fig. 6),
    force_velocity_<t>s.png (Fig. 7, 9) and power_<t>s.png (Fig. 8, 10) for each
    time in ``times_s`` (clamped to the record); ``figures`` chooses which of
    :data:`TIME_HISTORY_FIGURES` to draw. Returns the written paths."""
    directory = Path(directory)
    paths = []
    if "creep_curve" in figures:
        paths.append(_creep_curve(history, directory))
    if "velocity_history" in figures:
        paths.append(_velocity_history(history, directory))
    for t0 in times_s:
        if "force_velocity" in figures:
            paths.append(_force_velocity(history, directory, t0))
        if "power" in figures:
            paths.append(_power(history, directory, t0))
    return paths


def _creep_curve(history: TimeHistory, directory: Path) -> Path:
    """Fig. 4: the creep curve at the operating point."""
    op, law = history.operating_point, history.contact
    sat = law.saturation_creepage
    zeta = np.linspace(-6 * max(sat, abs(op.creepage)), 6 * max(sat, abs(op.creepage)), 2001)
    fig, ax = figure(6, 4)
    ax.plot(zeta, adhesion_ratio(zeta, law, op.rolling_speed_m_s), lw=1.5)
    ax.axvline(op.creepage, color="C3", ls="--", lw=1, label=f"quasi-static creepage {op.creepage:.4f}")
    for s in (-sat, sat):
        ax.axvline(s, color="0.5", ls=":", lw=1)
    ax.set_xlabel("lateral creepage zeta (-)")
    ax.set_ylabel("adhesion ratio mu = -Q/W (-)")
    ax.set_title(f"Creep curve (Eq. 3), V0 = {op.rolling_speed_m_s:.2f} m/s; saturation at {sat:.4f}")
    ax.legend(loc="lower right")
    ax.grid(alpha=0.3)
    return save(fig, directory / "creep_curve.png")


def _velocity_history(history: TimeHistory, directory: Path) -> Path:
    """Fig. 6: the contact velocity from rest."""
    op = history.operating_point
    fig, ax = figure(7, 4)
    ax.plot(*decimate(history.t, history.v), lw=0.4)
    for s in (1, -1):
        ax.axhline(s * op.crabbing_velocity_m_s, color="C3", ls="--", lw=1)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("lateral vibration velocity y' (m/s)")
    ax.set_title(f"Velocity from rest; Vc = {op.crabbing_velocity_m_s:.3f} m/s (dashed: +/- Vc)")
    ax.grid(alpha=0.3)
    return save(fig, directory / "velocity_history.png")


def _force_velocity(history: TimeHistory, directory: Path, t0: float) -> Path:
    """Fig. 7 / 9: velocity and lateral force over a few cycles around ``t0``."""
    sel, centre = _window(history, t0)
    t = history.t[sel]
    fig, (a1, a2) = figure(7, 5, 2, 1, sharex=True)
    a1.plot(t, history.v[sel], lw=1)
    a1.set_ylabel("y' (m/s)")
    a1.set_title(f"Velocity and lateral force around {centre:.3f} s (Fig. 7/9)")
    a2.plot(t, history.Q[sel], color="C1", lw=1)
    a2.set_ylabel("Q (N)")
    a2.set_xlabel("time (s)")
    for a in (a1, a2):
        a.grid(alpha=0.3)
    return save(fig, directory / f"force_velocity_{centre:.2f}s.png")


def _power(history: TimeHistory, directory: Path, t0: float) -> Path:
    """Fig. 8 / 10: the power input over a few cycles around ``t0``."""
    sel, centre = _window(history, t0)
    fig, ax = figure(7, 3.5)
    ax.plot(history.t[sel], history.P[sel], color="C2", lw=1)
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("P = Q y' - c y'^2 (W)")
    ax.set_title(f"Power input around {centre:.3f} s (Fig. 8/10); window mean {history.P[sel].mean():.3g} W")
    ax.grid(alpha=0.3)
    return save(fig, directory / f"power_{centre:.2f}s.png")
