"""The PNG figures of every command (drawn in the plot process:
:mod:`wheel_squeal.plotting`), from the records."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..outputs import NONE
from ..sweeps import VerdictGrid
from .canvas import PLOT_DPI

if TYPE_CHECKING:
    from acoustics.measured import Measured

    from ..envelope import Envelope
    from ..simulation import Simulation
    from ..verdict import ModeOutcome

__all__ = [
    "curve",
    "plot_times",
    "write_compare_plot",
    "write_envelope_plot",
    "write_mode_growth_plot",
    "write_shares_plot",
    "write_sweep_plot",
]


def plot_times(sim: Simulation) -> tuple[float, float]:
    """Windows [s] for the paper's Fig. 7-10: while growing (0.2 s, or halfway to
    saturation) and at the limit cycle: the record's last periods."""
    lc = sim.limit_cycle
    end = float(sim.history.t[-1])
    if not (lc.saturated and math.isfinite(lc.time_to_saturation_s)):
        return (min(0.2, end / 3), round(end, 2))
    period = 1.0 / lc.frequency_hz
    growing = min(0.2, 0.5 * lc.time_to_saturation_s)
    return (round(growing, 2), round(max(end - 4 * period, 0.0), 2))


def write_compare_plot(path: Path, rows: Sequence[dict], analyses: Sequence) -> Path:
    """Each design's growth to its limit cycle (the verdict's mode), its tone with the
    verdict mode named, and its sound power level and the level 7.5 m from the wheel
    centre (common to every design, unlike a microphone near each rim)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(14, 4.4))
    axes = fig.subplots(1, 3)
    fig.subplots_adjust(left=0.06, right=0.98, bottom=0.28, top=0.9, wspace=0.3)
    top = 0.0
    for r, a in zip(rows, analyses):
        o = a.outcome
        if o is None:
            continue
        cyc = o.simulation.limit_cycle.cycles
        style = "-" if o.saturated else "--"
        axes[0].plot(cyc.start_s, cyc.amplitude_m_s, style, label=f"{r['design']}: {o.label}")
        top = max(top, float(np.max(cyc.amplitude_m_s, initial=0)))
    vc = abs(analyses[0].operating_point.crabbing_velocity_m_s)
    axes[0].axhline(vc, color="k", ls=":", lw=1, label="Vc")
    axes[0].set_ylim(0, 1.1 * max(vc, top))
    axes[0].set(
        xlabel="time (s)", ylabel="contact velocity amplitude (m/s)", title="growth (dashed: still growing)"
    )
    axes[0].legend(fontsize=7)
    x = np.arange(len(rows))
    names = [r["design"] for r in rows]
    tones = [r["tone_hz"] or 0.0 for r in rows]
    bars = axes[1].bar(x, tones, color="tab:blue")
    for b, r in zip(bars, rows):
        axes[1].annotate(
            r["verdict_mode"] or "no squeal",
            (b.get_x() + b.get_width() / 2, b.get_height()),
            ha="center",
            va="bottom",
            fontsize=7,
        )
    axes[1].set(xticks=x, ylabel="squeal tone (Hz)", title="tone and the mode that squeals")
    axes[1].set_xticklabels(names, rotation=30, ha="right")
    power = [r["sound_power_level_db"] if r["sound_power_level_db"] is not None else np.nan for r in rows]
    far = [r["spl_7_5m_db"] if r["spl_7_5m_db"] is not None else np.nan for r in rows]
    hollow = ["tab:orange" if r["saturated"] else "none" for r in rows]
    axes[2].bar(x - 0.2, power, 0.4, color=hollow, edgecolor="tab:orange", label="L_W (dB re 1 pW)")
    axes[2].bar(
        x + 0.2,
        far,
        0.4,
        color=["tab:green" if r["saturated"] else "none" for r in rows],
        edgecolor="tab:green",
        label="SPL 7.5 m (dB re 20 uPa)",
    )
    for xi, r in zip(x, rows):
        if r["sound_power_level_db"] is not None:
            axes[2].annotate(
                f"{r['sound_power_level_db']:.1f}",
                (xi - 0.2, r["sound_power_level_db"]),
                ha="center",
                va="bottom",
                fontsize=7,
            )
    finite = [v for v in power + far if np.isfinite(v)]
    if finite:
        axes[2].set_ylim(min(finite) - 20, max(finite) + 10)
    axes[2].legend(fontsize=7, loc="upper right")
    axes[2].set(
        xticks=x, ylabel="level (dB)", title="sound power, and level at 7.5 m\n(hollow: not a limit cycle)"
    )
    axes[2].set_xticklabels(names, rotation=30, ha="right")
    fig.savefig(path, dpi=PLOT_DPI)
    return path


#: Marker and colour of each mechanism in the growth-rate plot (None: decays)
_MECHANISM_STYLE = {
    "falling friction": ("o", "C3"),
    "mode coupling": ("s", "C0"),
    "both": ("D", "C4"),
    None: ("o", "0.6"),
}


def write_mode_growth_plot(path: Path, rows: Sequence, chosen: int | None = None) -> Path:
    """growth.png: every mode's linear growth rate [1/s] against its frequency [Hz],
    marked by the mechanism that makes it grow (grey: it decays), each mode labelled,
    the verdict's mode (``chosen``, a mode index) circled."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8, 4.2))
    ax = fig.subplots()
    fig.subplots_adjust(left=0.1, right=0.97, bottom=0.13, top=0.9)
    seen = set()
    for row in rows:
        m, st = row.mode, row.stability
        marker, colour = _MECHANISM_STYLE.get(st.mechanism, ("o", "k"))
        label = st.mechanism or "decays"
        ax.plot(
            [st.damped_frequency_hz],
            [st.growth_rate_1_s],
            marker,
            color=colour,
            ms=7,
            label=None if label in seen else label,
        )
        seen.add(label)
        ax.annotate(
            m.label(),
            (st.damped_frequency_hz, st.growth_rate_1_s),
            fontsize=7,
            xytext=(4, 4),
            textcoords="offset points",
        )
        if chosen is not None and m.index == chosen:
            ax.plot(
                [st.damped_frequency_hz],
                [st.growth_rate_1_s],
                "o",
                mfc="none",
                mec="k",
                ms=15,
                label="the verdict's mode",
            )
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set(
        xlabel="frequency at the contact (Hz)",
        ylabel="linear growth rate (1/s)",
        title="every mode at the operating point: above 0 it grows (can squeal)",
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.savefig(path, dpi=PLOT_DPI)
    return Path(path)


def write_envelope_plot(path: Path, env: Envelope, mitigation: dict[str, Any] | None = None) -> Path:
    """stability.png: the largest growth rate against the crabbing velocity, one curve
    per speed (its marker in the legend), each point coloured by the mode that grows
    fastest there; with ``mitigation`` (summary.json's), a second panel: each mode's
    damping ratio now and the one that keeps it stable over the envelope (rotation off
    and on), and the friction slope required."""
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    fig = Figure(figsize=(13 if mitigation else 8, 5))
    axes = fig.subplots(1, 2 if mitigation else 1, squeeze=False)[0]
    ax = axes[0]
    fig.subplots_adjust(left=0.07, right=0.97 if mitigation else 0.7, bottom=0.3, top=0.9, wspace=0.55)
    labels = {
        int(i): f"{env.modes[i].label()}, {env.modes[i].frequency_hz:.0f} Hz" for i in np.unique(env.winner)
    }
    colours = {i: f"C{k % 10}" for k, i in enumerate(labels)}
    markers = "osD^v<>"
    for j in range(len(env.rpm)):
        ax.plot(env.crabbing_velocities_m_s, env.growth_rate_1_s[:, j], "-", color="0.6", lw=0.8)
        for i in labels:
            sel = env.winner[:, j] == i
            ax.plot(
                env.crabbing_velocities_m_s[sel],
                env.growth_rate_1_s[sel, j],
                markers[j % 7],
                ms=4,
                color=colours[i],
            )
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set(
        xlabel="crabbing velocity Vc (m/s)",
        ylabel="largest growth rate (1/s)",
        title="growth rate and the fastest mode (> 0: squeal grows)",
    )
    handles = [
        Line2D([], [], ls="", marker="s", color=colours[i], label=label) for i, label in labels.items()
    ]
    handles += [
        Line2D([], [], ls="-", marker=markers[j % 7], color="0.5", label=f"{rpm:.0f} RPM")
        for j, rpm in enumerate(env.rpm)
    ]
    ax.legend(
        handles=handles, title="fastest mode; speed", fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0)
    )
    ax.grid(alpha=0.3)
    if mitigation:
        _mitigation_panel(axes[1], mitigation)
    fig.savefig(path, dpi=PLOT_DPI)
    return path


def _num(x: float | None) -> str:
    return NONE if x is None else f"{x:.3g}"


def _mitigation_panel(ax: Any, mitigation: dict[str, Any]) -> None:
    """Each mode's damping ratio now and required over the envelope (log scale)."""
    off, on = mitigation["rotation_off"], mitigation["rotation_on"]
    names = [d["label"] for d in off["damping"]]
    x = np.arange(len(names))
    now = [d["damping_ratio"] for d in off["damping"]]
    ax.bar(x - 0.27, now, 0.27, color="0.6", label="now")

    def needed(rows: list[dict]) -> list[float]:  # none needed (null): no bar
        return [d["required_damping_ratio"] or np.nan for d in rows]

    ax.bar(x, needed(off["damping"]), 0.27, color="C3", label="required")
    ax.bar(x + 0.27, needed(on["damping"]), 0.27, color="C1", label="required, rotation on")
    ax.set_yscale("log")
    positive = [z for z in now if z > 0]
    if positive:  # a mode stable without damping needs none: its bar is below the axis
        ax.set_ylim(bottom=0.1 * min(positive))
    ax.set_xticks(x, names, rotation=90, ha="center", fontsize=7)
    ax.set(
        ylabel="modal damping ratio",
        title=f"what stops squeal for Vc {mitigation['crabbing_velocity_m_s'][0]:g}-"
        f"{mitigation['crabbing_velocity_m_s'][1]:g} m/s: damping per mode,\n"
        f"or a creep curve no steeper than dmu/dzeta = {_num(off['required_friction_slope'])} "
        f"(rotation on: {_num(on['required_friction_slope'])})",
    )
    ax.title.set_fontsize(9)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3, axis="y")


def write_shares_plot(path: Path, o: ModeOutcome) -> Path:
    """multimode.png: the velocity envelope of each mode integrated together, over time
    (log scale): which mode takes the contact, and when."""
    from matplotlib.figure import Figure

    assert o.simulation is not None and o.shares is not None
    h = o.simulation.history
    coords = h.coordinates
    tm = h.modes_time  # the exponential integrator keeps the coordinates over the tail
    f_low = min(m.frequency_hz for m in o.group)
    block = max(1, int(round(1.0 / (f_low * float(tm[1] - tm[0])))))  # one lowest period
    n = len(tm) // block * block
    fig = Figure(figsize=(8.5, 4.5))
    ax = fig.subplots()
    fig.subplots_adjust(left=0.1, right=0.66, bottom=0.12, top=0.9)
    t = tm[:n].reshape(-1, block).mean(axis=1)
    for i, (label, share) in enumerate(o.shares.items()):
        cols = np.flatnonzero(coords.mode == i) if coords is not None else np.array([i])
        speed = np.sqrt((h.v_modes[:n, cols] ** 2).sum(axis=1))
        envelope = speed.reshape(-1, block).max(axis=1)
        ax.semilogy(t, np.maximum(envelope, 1e-12), lw=1.2, label=f"{label}: {share:.1%}")
    span = "" if h.t_modes is None else f" (the record's last {tm[-1] - tm[0]:.2g} s)"
    ax.set(
        xlabel="time (s)",
        ylabel="modal velocity envelope (m/s)",
        title=f"{o.label} carries the limit cycle{span}",
    )
    ax.legend(title="share of the final energy", fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.grid(alpha=0.3, which="both")
    fig.savefig(path, dpi=PLOT_DPI)
    return path


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


def write_sweep_plot(path: Path, grid: VerdictGrid, measured: Measured | None = None) -> Path:
    """sweep.png: the amplitude (top) and the SPL (bottom, with sound; else the velocity
    level re 5e-8 m/s) against the crabbing velocity, one curve per speed; hollow: still
    growing at the end of the run; each filled point labelled by nothing, the modes in
    the legend; ``measured`` (``acoustics.measured.Measured``): the measured levels
    as crosses in their speed's colour."""
    from matplotlib.figure import Figure

    from reduced.summaries import VELOCITY_REFERENCE_M_S

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
                    measured.crab_velocity[at],
                    measured.spl_db[at],
                    "x",
                    ms=8,
                    mew=2,
                    color=line.get_color(),
                    label=f"{rpm:g} RPM, measured",
                )
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
