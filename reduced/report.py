"""Files and JSON-ready summaries for a squeal simulation.

Writers take a directory Path and write plain files into it (the caller handles
atomic renames). Figure numbers refer to Liu & Meehan (CM2015). Plots use matplotlib's
object API on the Agg canvas (no pyplot, no display, no global figure state), and long
records are drawn as their per-pixel minimum and maximum (:func:`decimate`): the same
picture from a few thousand points instead of hundreds of thousands.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from .creep import ContactLaw, adhesion_ratio
from .limit_cycle import LimitCycle
from .model import OperatingPoint, TimeHistory

__all__ = [
    "counter_body_motion",
    "counter_body_velocity",
    "summary_dicts",
    "write_timeseries_csv",
    "write_time_history_plots",
    "PLOT_DPI",
    "VELOCITY_REFERENCE_M_S",
]

#: resolution of every figure the tool writes [dots per inch]
PLOT_DPI = 110

#: reference velocity for velocity levels, m/s (dB re 5e-8 m/s)
VELOCITY_REFERENCE_M_S = 5e-8


def summary_dicts(lc: LimitCycle, op: OperatingPoint, contact: ContactLaw) -> dict:
    """Dicts {'limit_cycle', 'operating_point', 'contact'} (SI units; NaN where a quantity
    is undefined, such as the frequency of no squeal: a JSON writer makes it null)."""
    return {
        "limit_cycle": {
            "squeal": bool(lc.squeal),
            "state": lc.state,
            "velocity_amplitude_m_s": float(lc.velocity_amplitude_m_s),
            "frequency_hz": float(lc.frequency_hz),
            "time_to_saturation_s": float(lc.time_to_saturation_s),
            "envelope_growth_rate_1_s": float(lc.envelope_growth_rate_1_s),
        },
        "operating_point": {
            "rolling_speed_m_s": float(op.rolling_speed_m_s),
            "crabbing_velocity_m_s": float(op.crabbing_velocity_m_s),
            "creepage": float(op.creepage),
        },
        "contact": {
            "semi_axis_a_m": float(contact.semi_axis_a_m),
            "semi_axis_b_m": float(contact.semi_axis_b_m),
            "c22": float(contact.c22),
            "friction_coefficient": float(contact.friction_coefficient),
            "friction_law": contact.friction_law,
        },
    }


#: The longest row of timeseries.csv [bytes]: eight numbers of at most 15 characters
#: (``-1.23456789e-05``), their separators and the line end.
TIMESERIES_ROW_BYTES = 9 * 16


#: timeseries.csv's columns (SI units: the suffix names the unit)
TIMESERIES_COLUMNS = ("t_s", "y_m", "v_m_s", "creepage", "Q_N", "P_W", "u_n_m", "N_N", "v_counter_body_m_s")


def counter_body_velocity(history: TimeHistory) -> np.ndarray:
    """The counter-body's own lateral velocity at the contact [m/s] (a rail's, a roller's
    mode's; the contact sees the wheel's velocity minus it); 0 where it is rigid."""
    return np.zeros(len(history.t)) if history.v_body is None else history.v_body


def timeseries_stride(history: TimeHistory, max_bytes: float = math.inf) -> int:
    """k: timeseries.csv holds every k-th sample, so that it stays within ``max_bytes``."""
    return max(1, math.ceil(len(history.t) * TIMESERIES_ROW_BYTES / max_bytes))


def counter_body_motion(history: TimeHistory) -> dict[str, float]:
    """The counter-body's part at the end of the record (its last quarter): the rms of
    the contact's slip velocity and of the counter-body's own velocity there [m/s], their
    ratio, and the mean power the contact force puts into the counter-body [W] (its
    fluctuating part: the steady creep force does no work on a body at rest)."""
    sel = history.t >= 0.75 * float(history.t[-1])
    v_cb = counter_body_velocity(history)[sel]
    v = history.v[sel] - history.v[sel].mean()
    q = history.Q[sel] - history.Q[sel].mean()
    rms_v, rms_cb = float(np.sqrt(np.mean(v**2))), float(np.sqrt(np.mean((v_cb - v_cb.mean()) ** 2)))
    return {
        "contact_velocity_rms_m_s": rms_v,
        "counter_body_velocity_rms_m_s": rms_cb,
        "counter_body_velocity_share": rms_cb / rms_v if rms_v > 0 else 0.0,
        "counter_body_power_w": float(np.mean(-q * (v_cb - v_cb.mean()))),
    }


def write_timeseries_csv(
    history: TimeHistory, directory: Path, name: str = "timeseries.csv", max_bytes: float = math.inf
) -> Path:
    """Write :data:`TIMESERIES_COLUMNS` (contact-point totals) as a plain CSV (one header
    line, then numbers: any CSV reader takes it as it is), every sample, or every k-th
    where all of them would exceed ``max_bytes`` (:func:`timeseries_stride`; summary.json
    says k)."""
    path = Path(directory) / name
    stride = timeseries_stride(history, max_bytes)
    zero = np.zeros(len(history.t))
    u_n = zero if history.u_n is None else history.u_n
    normal = zero + history.contact.normal_load_n if history.N is None else history.N
    data = np.column_stack(
        [
            history.t,
            history.y,
            history.v,
            history.creepage,
            history.Q,
            history.P,
            u_n,
            normal,
            counter_body_velocity(history),
        ]
    )[::stride]
    header = ",".join(TIMESERIES_COLUMNS)
    row = ",".join(["%.9g"] * data.shape[1]) + "\n"
    # one format operation for the whole table: the text of np.savetxt, 2.5x faster
    path.write_text(header + "\n" + (row * len(data)) % tuple(data.ravel().tolist()))
    return path


def _figure(width_in: float, height_in: float, rows: int = 1, cols: int = 1, **kwargs: Any) -> Any:
    """A new Agg figure and its axes (object API: nothing global), with fixed margins
    for tick labels, axis labels and a title (tight_layout would draw every figure twice)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width_in, height_in))
    axes = fig.subplots(rows, cols, **kwargs)
    fig.subplots_adjust(
        left=0.85 / width_in,
        right=1 - 0.2 / width_in,
        bottom=0.55 / height_in,
        top=1 - 0.4 / height_in,
        hspace=0.3 if rows > 1 else None,
    )
    return fig, axes


#: Columns a decimated line keeps: more than the pixels of a 110-dpi, 7-inch axis.
DECIMATE_COLUMNS = 2000


def decimate(x: np.ndarray, y: np.ndarray, columns: int = DECIMATE_COLUMNS) -> tuple[np.ndarray, np.ndarray]:
    """The points of a line that a plot ``columns`` pixels wide can show: per column
    of samples its minimum and maximum, in time order (every sample if there are few)."""
    n = len(x)
    if n <= 4 * columns:
        return x, y
    per = n // columns
    m = per * columns
    xb, yb = x[:m].reshape(columns, per), y[:m].reshape(columns, per)
    lo, hi = yb.argmin(axis=1), yb.argmax(axis=1)
    first, second = np.minimum(lo, hi), np.maximum(lo, hi)
    rows = np.arange(columns)
    xs = np.column_stack([xb[rows, first], xb[rows, second]]).ravel()
    ys = np.column_stack([yb[rows, first], yb[rows, second]]).ravel()
    return np.concatenate([xs, x[m:]]), np.concatenate([ys, y[m:]])


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
    fig, ax = _figure(6, 4)
    ax.plot(zeta, adhesion_ratio(zeta, law, op.rolling_speed_m_s), lw=1.5)
    ax.axvline(op.creepage, color="C3", ls="--", lw=1, label=f"quasi-static creepage {op.creepage:.4f}")
    for s in (-sat, sat):
        ax.axvline(s, color="0.5", ls=":", lw=1)
    ax.set_xlabel("lateral creepage zeta (-)")
    ax.set_ylabel("adhesion ratio mu = -Q/W (-)")
    ax.set_title(f"Creep curve (Eq. 3), V0 = {op.rolling_speed_m_s:.2f} m/s; saturation at {sat:.4f}")
    ax.legend(loc="lower right")
    ax.grid(alpha=0.3)
    return _save(fig, directory / "creep_curve.png")


def _velocity_history(history: TimeHistory, directory: Path) -> Path:
    """Fig. 6: the contact velocity from rest."""
    op = history.operating_point
    fig, ax = _figure(7, 4)
    ax.plot(*decimate(history.t, history.v), lw=0.4)
    for s in (1, -1):
        ax.axhline(s * op.crabbing_velocity_m_s, color="C3", ls="--", lw=1)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("lateral vibration velocity y' (m/s)")
    ax.set_title(f"Velocity from rest; Vc = {op.crabbing_velocity_m_s:.3f} m/s (dashed: +/- Vc)")
    ax.grid(alpha=0.3)
    return _save(fig, directory / "velocity_history.png")


def _force_velocity(history: TimeHistory, directory: Path, t0: float) -> Path:
    """Fig. 7 / 9: velocity and lateral force over a few cycles around ``t0``."""
    sel, centre = _window(history, t0)
    t = history.t[sel]
    fig, (a1, a2) = _figure(7, 5, 2, 1, sharex=True)
    a1.plot(t, history.v[sel], lw=1)
    a1.set_ylabel("y' (m/s)")
    a1.set_title(f"Velocity and lateral force around {centre:.3f} s (Fig. 7/9)")
    a2.plot(t, history.Q[sel], color="C1", lw=1)
    a2.set_ylabel("Q (N)")
    a2.set_xlabel("time (s)")
    for a in (a1, a2):
        a.grid(alpha=0.3)
    return _save(fig, directory / f"force_velocity_{centre:.2f}s.png")


def _power(history: TimeHistory, directory: Path, t0: float) -> Path:
    """Fig. 8 / 10: the power input over a few cycles around ``t0``."""
    sel, centre = _window(history, t0)
    fig, ax = _figure(7, 3.5)
    ax.plot(history.t[sel], history.P[sel], color="C2", lw=1)
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("P = Q y' - c y'^2 (W)")
    ax.set_title(f"Power input around {centre:.3f} s (Fig. 8/10); window mean {history.P[sel].mean():.3g} W")
    ax.grid(alpha=0.3)
    return _save(fig, directory / f"power_{centre:.2f}s.png")


def _save(fig: Any, path: Path) -> Path:
    fig.savefig(path, dpi=PLOT_DPI)
    return path
