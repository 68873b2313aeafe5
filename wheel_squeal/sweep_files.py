"""The sweep's files: ``sweep.csv`` (the verdict at every point), ``sweep_spl.csv`` (its
levels, with ``--sound``) and ``sweep.png`` (the paper's Fig. 5: amplitude, and level
in dB, against the crabbing velocity, one curve per speed). A point still growing at the
end of its run is drawn hollow and never joined by a line to a limit cycle."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from reduced.report import PLOT_DPI

from .fields import columns_of
from .outputs import write_csv
from .sweeps import VerdictGrid

__all__ = [
    "curve",
    "measured_table",
    "sweep_table",
    "write_measured_csv",
    "write_sweep_csv",
    "write_sweep_plot",
    "write_sweep_spl",
]


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


def curve(grid: VerdictGrid, values: np.ndarray, j: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The drawing of ``values`` (n_vc, n_rpm) at speed ``j``: the line through the limit
    cycles (NaN breaks it at every point that is not one, so that it joins only
    neighbouring limit cycles), and the hollow markers of the points still growing, as
    (x, line_y, hollow_mask)."""
    x = grid.crabbing_velocities_m_s
    y = np.asarray(values[:, j], float)
    cycle = grid.squeals[:, j] & grid.saturated[:, j]
    hollow = grid.squeals[:, j] & ~grid.saturated[:, j]
    return x, np.where(cycle, y, np.nan), hollow


def write_sweep_plot(path: Path, grid: VerdictGrid, measured=None) -> Path:
    """sweep.png: the amplitude (top) and the SPL (bottom, with sound; else the velocity
    level re 5e-8 m/s) against the crabbing velocity, one curve per speed; hollow: still
    growing at the end of the run; each filled point labelled by nothing, the modes in
    the legend; ``measured`` (``wheel_squeal.measured.Measured``): the measured levels
    as crosses in their speed's colour."""
    from matplotlib.figure import Figure

    from reduced.report import VELOCITY_REFERENCE_M_S

    fig = Figure(figsize=(7.5, 7))
    top, bottom = fig.subplots(2, 1, sharex=True)
    fig.subplots_adjust(left=0.12, right=0.97, bottom=0.08, top=0.93, hspace=0.12)
    with np.errstate(divide="ignore", invalid="ignore"):
        level = (
            grid.spl_db
            if np.isfinite(grid.spl_db).any()
            else 20 * np.log10(grid.amplitude_m_s / VELOCITY_REFERENCE_M_S)
        )
    for j, rpm in enumerate(grid.rpm):
        x, y, hollow = curve(grid, grid.amplitude_m_s, j)
        (line,) = top.plot(x, y, "-o", ms=3, label=f"{rpm:g} RPM")
        top.plot(x[hollow], grid.amplitude_m_s[hollow, j], "o", mfc="white", mec=line.get_color(), ms=6)
        _, yl, _ = curve(grid, level, j)
        bottom.plot(x, yl, "-o", ms=3, color=line.get_color(), label=f"{rpm:g} RPM, predicted")
        bottom.plot(x[hollow], level[hollow, j], "o", mfc="white", mec=line.get_color(), ms=6)
        if measured is not None:
            at = np.isclose(measured.rpm, rpm, rtol=0.01)
            if at.any():
                bottom.plot(
                    measured.crab_velocity[at], measured.spl_db[at], "x", ms=8, mew=2,
                    color=line.get_color(), label=f"{rpm:g} RPM, measured",
                )  # fmt: skip
    if measured is not None:
        bottom.legend(fontsize=8)
    if (grid.squeals & ~grid.saturated).any():
        top.plot([], [], "o", mfc="white", mec="0.4", ms=6, label="still growing: not a limit cycle")
    top.plot(grid.crabbing_velocities_m_s, np.abs(grid.crabbing_velocities_m_s), "k--", lw=0.8, label="|Vc|")
    modes = ", ".join(sorted({m for m in grid.mode.ravel() if m})) or "none"
    top.set(ylabel="contact velocity amplitude (m/s)", title=f"Squeal over the sweep (modes: {modes})")
    top.legend(fontsize=8)
    sound = np.isfinite(grid.spl_db).any()
    bottom.set(
        xlabel="crabbing velocity Vc (m/s)",
        ylabel="SPL at the microphone (dB re 20 uPa)" if sound else "velocity level (dB re 5e-8 m/s)",
    )
    for a in (top, bottom):
        a.grid(alpha=0.3)
    fig.savefig(path, dpi=PLOT_DPI)
    return Path(path)


def sweep_table(grid: VerdictGrid) -> str:
    """The amplitude over the grid as text ('-' no squeal, '*' still growing), and the
    modes that squeal."""
    lines = [f"{'Vc [m/s]':>9} " + " ".join(f"{r:>9.0f}rpm" for r in grid.rpm)]
    for i, vc in enumerate(grid.crabbing_velocities_m_s):
        cells = []
        for j in range(len(grid.rpm)):
            if not grid.squeals[i, j]:
                cells.append(f"{'-':>12}")
            else:
                star = " " if grid.saturated[i, j] else "*"
                cells.append(f"{grid.amplitude_m_s[i, j]:11.4f}{star}")
        lines.append(f"{vc:9.4f} " + " ".join(cells))
    modes = sorted({m for m in grid.mode.ravel() if m})
    lines.append(
        "contact velocity amplitude [m/s]; - no squeal, * still growing at the end of the run; "
        f"squealing modes: {', '.join(modes) or 'none'}"
    )
    return "\n".join(lines)


def write_measured_csv(path: Path, comparison: list[dict]) -> Path:
    """measured.csv: per measured point its values, the prediction there and the
    prediction minus the measurement (``wheel_squeal.measured.compare_measured``)."""
    return write_csv(path, comparison, columns_of("measured.csv"))


def measured_table(comparison: list[dict]) -> str:
    """The comparison as text: prediction minus measurement per point, and its mean and
    spread over the points with a prediction."""

    def num(x, fmt: str) -> str:
        return "-" if x is None else format(x, fmt)

    lines = [f"{'Vc [m/s]':>9} {'rpm':>6} {'measured':>9} {'predicted':>9} {'pred-meas':>9}  dB"]
    for c in comparison:
        lines.append(
            f"{c['crabbing_velocity_m_s']:9.4f} {c['rpm']:6.0f} {c['measured_spl_db']:9.1f} "
            f"{num(c['predicted_spl_db'], '9.1f'):>9} {num(c['spl_difference_db'], '+9.1f'):>9}"
        )
    d = np.array([c["spl_difference_db"] for c in comparison if c["spl_difference_db"] is not None])
    if len(d):
        lines.append(
            f"prediction minus measurement over {len(d)} of {len(comparison)} points: "
            f"mean {d.mean():+.1f} dB, rms {np.sqrt(np.mean(d**2)):.1f} dB "
            "('-': no limit cycle predicted there)"
        )
    return "\n".join(lines)
