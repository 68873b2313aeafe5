"""``compare``'s files and text: one row per design (its verdict, the named mode and
the model's pick, the verdict mode's contact modal parameters), the table, the plot."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from reduced.report import PLOT_DPI

__all__ = ["compare_row", "compare_table", "modal_dof_summary", "write_compare_plot"]


def compare_row(a) -> dict:
    """One design's line of ``compare.csv``: its verdict (mode, tone, growth, amplitude,
    saturated, levels, reason), the named mode's and the model's own pick beside it, and
    the contact modal parameters of the verdict's mode (``a``: a
    :class:`~wheel_squeal.chain.Analysis`)."""
    v = a.verdict
    d = v.to_dict()
    o = v.outcome or v.named or v.pick
    dof = modal_dof_summary(a, o)
    return {
        "design": a.design.name,
        "squeals": v.squeals,
        "verdict_mode": d["mode"] or "",
        "tone_hz": d["tone_hz"],
        "growth_rate_1_s": d["growth_rate_1_s"],
        "amplitude_m_s": d["amplitude_m_s"],
        "saturated": d["saturated"],
        "spl_db": d["spl_db"],
        "spl_dba": d["spl_dba"],
        "sound_power_level_db": d["sound_power_level_db"],
        "override_mode": v.named.label if v.named else "",
        "override_growth_rate_1_s": v.named.growth_rate_1_s if v.named else None,
        "model_pick": v.pick.label if v.pick else "",
        "model_pick_growth_rate_1_s": v.pick.growth_rate_1_s if v.pick else None,
        "mode_frequency_hz": o.mode.frequency_hz if o else None,
        **dof,
        "reason": v.reason,
    }


def modal_dof_summary(a, outcome) -> dict:
    """The contact modal mass, stiffness and damping of ``outcome``'s mode (None without)."""
    from .api import modal_dof

    if outcome is None:
        return {"modal_mass_kg": None, "modal_stiffness_n_m": None, "modal_damping_ns_m": None}
    dof = modal_dof(outcome.mode, a.design)
    return {
        "modal_mass_kg": dof.mass_kg,
        "modal_stiffness_n_m": dof.stiffness_n_m,
        "modal_damping_ns_m": dof.damping_ns_m,
    }


def compare_table(rows: Sequence[dict]) -> str:
    """The designs side by side, as text."""

    def num(v, fmt: str, width: int) -> str:
        return f"{v:{width}{fmt}}" if v is not None else f"{'-':>{width}}"

    lines = [
        f"{'design':<16} {'verdict':<16} {'tone [Hz]':>9} {'growth [1/s]':>12} {'amp [m/s]':>9} "
        f"{'SPL [dB]':>8} {'L_W [dB]':>8} {'model pick':<14}"
    ]
    for r in rows:
        verdict = r["verdict_mode"] or "no squeal"
        amp = num(r["amplitude_m_s"], ".4f", 9) + ("" if r["saturated"] or not r["squeals"] else "*")
        tone, growth = num(r["tone_hz"], ".1f", 9), num(r["growth_rate_1_s"], ".3g", 12)
        spl, power = num(r["spl_db"], ".1f", 8), num(r["sound_power_level_db"], ".1f", 8)
        lines.append(
            f"{r['design']:<16} {verdict:<16} {tone} {growth} {amp} {spl} {power} {r['model_pick']:<14}"
        )
    if any(r["squeals"] and not r["saturated"] for r in rows):
        lines.append("* still growing at the end of the run: not a limit cycle")
    return "\n".join(lines)


def write_compare_plot(path: Path, rows: Sequence[dict], analyses: Sequence) -> Path:
    """Each design's growth to its limit cycle (the verdict's mode), its tone with the
    verdict mode named, and its level at the microphone."""
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
        axes[1].annotate(r["verdict_mode"] or "no squeal", (b.get_x() + b.get_width() / 2, b.get_height()),
                         ha="center", va="bottom", fontsize=7)  # fmt: skip
    axes[1].set(xticks=x, ylabel="squeal tone (Hz)", title="tone and the mode that squeals")
    axes[1].set_xticklabels(names, rotation=30, ha="right")
    spl = [r["spl_db"] if r["spl_db"] is not None else np.nan for r in rows]
    axes[2].bar(
        x, spl, color=["tab:orange" if r["saturated"] else "none" for r in rows], edgecolor="tab:orange"
    )
    for xi, r in zip(x, rows):
        if r["spl_db"] is not None:
            axes[2].annotate(f"{r['spl_db']:.1f} dB\n{r['spl_dba']:.1f} dB(A)", (xi, r["spl_db"]),
                             ha="center", va="bottom", fontsize=7)  # fmt: skip
    finite = [v for v in spl if np.isfinite(v)]
    if finite:
        axes[2].set_ylim(min(finite) - 20, max(finite) + 8)
    axes[2].set(
        xticks=x, ylabel="SPL at the microphone (dB re 20 uPa)", title="level (hollow: not a limit cycle)"
    )
    axes[2].set_xticklabels(names, rotation=30, ha="right")
    fig.savefig(path, dpi=PLOT_DPI)
    return path
