"""The stability command's and the multi-mode run's files and text: the table of every
mode, the envelope map (CSV, PNG), the mitigation, the multi-mode envelopes."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from reduced.report import PLOT_DPI

from .fields import columns_of
from .outputs import write_csv

__all__ = [
    "write_mode_growth_plot",
    "mitigation_text",
    "multimode_text",
    "stability_text",
    "write_envelope_csv",
    "write_envelope_plot",
    "write_multimode_plot",
]


def _cell(value: float, width: int) -> str:
    """A number in a text table, '-' where it was not computed (NaN)."""
    return f"{value:{width}.3g}" if math.isfinite(value) else f"{'-':>{width}}"


def stability_text(rows: Sequence, winner: int) -> str:
    """The stability of every excitable mode as text, the fastest-growing one marked."""
    lines = [
        f"{'#':>3} {'f [Hz]':>9} {'n':>2} {'c':>2} {'family':<15} {'sigma [1/s]':>11} "
        f"{'zeta_crit':>10} {'dmu/dz crit':>11}"
    ]
    for i, row in enumerate(rows):
        m, s = row.mode, row.stability
        mark = " <- fastest" if i == winner else (" unstable" if s.unstable else "")
        lines.append(
            f"{m.index:>3} {s.damped_frequency_hz:9.1f} {m.nodal_diameters:>2} {m.nodal_circles:>2} "
            f"{m.family:<15} {s.growth_rate_1_s:11.3g} {_cell(s.critical_damping_ratio, 10)} "
            f"{_cell(s.critical_friction_slope, 11)}{mark}"
        )
    return "\n".join(lines)


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
            [st.damped_frequency_hz], [st.growth_rate_1_s], marker, color=colour, ms=7,
            label=None if label in seen else label,
        )  # fmt: skip
        seen.add(label)
        ax.annotate(m.label(), (st.damped_frequency_hz, st.growth_rate_1_s), fontsize=7,
                    xytext=(4, 4), textcoords="offset points")  # fmt: skip
        if chosen is not None and m.index == chosen:
            ax.plot([st.damped_frequency_hz], [st.growth_rate_1_s], "o", mfc="none", mec="k", ms=15,
                    label="the verdict's mode")  # fmt: skip
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


def write_envelope_csv(path: Path, env) -> Path:
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


def write_envelope_plot(path: Path, env, mitigation: dict | None = None) -> Path:
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
    fig.subplots_adjust(left=0.07, right=0.97 if mitigation else 0.7, bottom=0.2, top=0.9, wspace=0.55)
    labels = {
        int(i): f"{env.modes[i].label()}, {env.modes[i].frequency_hz:.0f} Hz" for i in np.unique(env.winner)
    }
    colours = {i: f"C{k % 10}" for k, i in enumerate(labels)}
    markers = "osD^v<>"
    for j in range(len(env.rpm)):
        ax.plot(env.crabbing_velocities_m_s, env.growth_rate_1_s[:, j], "-", color="0.6", lw=0.8)
        for i in labels:
            sel = env.winner[:, j] == i
            ax.plot(env.crabbing_velocities_m_s[sel], env.growth_rate_1_s[sel, j], markers[j % 7], ms=4,
                    color=colours[i])  # fmt: skip
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set(
        xlabel="crabbing velocity Vc (m/s)",
        ylabel="largest growth rate (1/s)",
        title="growth rate and the fastest mode (> 0: squeal grows)",
    )
    handles = [
        Line2D([], [], ls="", marker="s", color=colours[i], label=label) for i, label in labels.items()
    ]
    handles += [Line2D([], [], ls="-", marker=markers[j % 7], color="0.5", label=f"{rpm:.0f} RPM")
                for j, rpm in enumerate(env.rpm)]  # fmt: skip
    ax.legend(
        handles=handles, title="fastest mode; speed", fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0)
    )
    ax.grid(alpha=0.3)
    if mitigation:
        _mitigation_panel(axes[1], mitigation)
    fig.savefig(path, dpi=PLOT_DPI)
    return path


def _mitigation_panel(ax, mitigation: dict) -> None:
    """Each mode's damping ratio now and required over the envelope (log scale)."""
    off, on = mitigation["rotation_off"], mitigation["rotation_on"]
    names = [d["label"] for d in off["damping"]]
    x = np.arange(len(names))
    now = [d["damping_ratio"] for d in off["damping"]]
    ax.bar(x - 0.27, now, 0.27, color="0.6", label="now")
    ax.bar(x, [d["required_damping_ratio"] for d in off["damping"]], 0.27, color="C3", label="required")
    ax.bar(x + 0.27, [d["required_damping_ratio"] for d in on["damping"]], 0.27, color="C1",
           label="required, rotation on")  # fmt: skip
    ax.set_yscale("log")
    positive = [z for z in now if z > 0]
    if positive:  # a mode stable without damping needs none: its bar is below the axis
        ax.set_ylim(bottom=0.1 * min(positive))
    ax.set_xticks(x, names, rotation=60, ha="right", fontsize=7)
    ax.set(
        ylabel="modal damping ratio",
        title=f"what stops squeal for Vc {mitigation['crabbing_velocity_m_s'][0]:g}-"
        f"{mitigation['crabbing_velocity_m_s'][1]:g} m/s: damping per mode,\n"
        f"or a creep curve no steeper than dmu/dzeta = {off['required_friction_slope']:.3g} "
        f"(rotation on: {on['required_friction_slope']:.3g})",
    )
    ax.title.set_fontsize(9)
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3, axis="y")


def write_multimode_plot(path: Path, multi) -> Path:
    """multimode.png: each mode's velocity envelope over time (log scale): which mode
    takes the contact, and when."""
    from matplotlib.figure import Figure

    h = multi.simulation.history
    coords = h.coordinates
    f_low = min(m.frequency_hz for m in multi.modes)
    block = max(1, int(round(1.0 / (f_low * float(h.t[1] - h.t[0])))))  # one lowest period
    n = len(h.t) // block * block
    fig = Figure(figsize=(8, 4.5))
    ax = fig.subplots()
    fig.subplots_adjust(left=0.1, right=0.72, bottom=0.12, top=0.9)
    t = h.t[:n].reshape(-1, block).mean(axis=1)
    for i, (m, share) in enumerate(zip(multi.modes, multi.content.energy_share)):
        cols = np.flatnonzero(coords.mode == i) if coords is not None else np.array([i])
        speed = np.sqrt((h.v_modes[:n, cols] ** 2).sum(axis=1))
        envelope = speed.reshape(-1, block).max(axis=1)
        ax.semilogy(
            t, np.maximum(envelope, 1e-12), lw=1.2, label=f"{m.label()}, {m.frequency_hz:.0f} Hz: {share:.1%}"
        )
    ax.set(
        xlabel="time (s)",
        ylabel="modal velocity envelope (m/s)",
        title=f"Multi-mode run: {multi.carrier.label()} carries the limit cycle",
    )
    ax.legend(
        title="mode: share of the final energy", fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0)
    )
    ax.grid(alpha=0.3, which="both")
    fig.savefig(path, dpi=PLOT_DPI)
    return path


def multimode_text(multi) -> str:
    """Which mode carries the multi-mode limit cycle, and whether the linear winner does."""
    share = ", ".join(
        f"{m.index} {m.label()} {s:.1%}" for m, s in zip(multi.modes, multi.content.energy_share)
    )
    verdict = (
        "the linear winner"
        if multi.agrees
        else f"not the linear winner (mode {multi.linear_winner.index} {multi.linear_winner.label()})"
    )
    return (
        f"multi-mode ({len(multi.modes)} modes): mode {multi.carrier.index} {multi.carrier.label()} carries "
        f"the limit cycle, {verdict}; contact velocity peak {multi.content.peak_frequency_hz:.1f} Hz; "
        f"energy shares: {share}"
    )


def eigenvalues_text(eigenvalues: list[dict], contact: dict) -> str:
    """The growing eigenvalues: tone, growth rate, mechanism and the modes that take part."""
    k_h = contact["normal_stiffness_n_m"]
    normal = f"Hertz normal spring {k_h:.3g} N/m" if k_h else "constant normal load"
    angle = contact["contact_angle_deg"]
    head = f"with {contact['friction_law']} friction, {normal}, contact angle {angle:.3g} deg: "
    growing = [e for e in eigenvalues if e["mechanism"] is not None]
    if not growing:
        return head + "no eigenvalue grows"
    lines = [head + f"{len(growing)} eigenvalue(s) grow"]
    for e in growing[:6]:
        who = " + ".join(f"{p['mode']} {p['share']:.0%}" for p in e["participants"][:3])
        f, sigma = e["damped_frequency_hz"], e["growth_rate_1_s"]
        lines.append(f"  {f:8.1f} Hz  {sigma:9.3g} 1/s  {e['mechanism']:<16}  {who}")
    if len(growing) > 6:
        lines.append(f"  and {len(growing) - 6} more")
    return "\n".join(lines)


def mitigation_text(mitigation: dict) -> str:
    """The damping per mode and the friction slope that stop squeal over the envelope."""
    vc, rpm = mitigation["crabbing_velocity_m_s"], mitigation["rpm"]
    lines = [
        f"to stop squeal for Vc {vc[0]:g}-{vc[1]:g} m/s at {', '.join(f'{r:g}' for r in rpm)} RPM:",
        f"{'#':>3} {'mode':<20} {'f [Hz]':>8} {'zeta now':>9} {'zeta needed':>12} {'(rotation on)':>13}",
    ]
    off, on = mitigation["rotation_off"], mitigation["rotation_on"]
    for a, b in zip(off["damping"], on["damping"]):
        lines.append(
            f"{a['mode']:>3} {a['label']:<20} {a['frequency_hz']:8.1f} {a['damping_ratio']:9.2e} "
            f"{a['required_damping_ratio']:12.2e} {b['required_damping_ratio']:13.2e}"
        )
    lines.append(
        f"or a creep curve no steeper than dmu/dzeta = {off['required_friction_slope']:.3g} "
        f"(rotation on: {on['required_friction_slope']:.3g}) at the quasi-static creepage"
    )
    return "\n".join(lines)
