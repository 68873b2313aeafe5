"""What the commands write and print: summaries (JSON-ready dicts), tables and plots.

Functions here take the plain objects of the stages (:mod:`wheel_squeal.api`) and either
return text / dicts or write files into a folder they are given (the caller makes the
folder atomic, :mod:`wheel_squeal.outputs`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from geometry import WheelDesign

from .outputs import write_csv
from .plotting import PlotWorkers
from .presets import Fidelity, rpm_to_speed

#: The resolution of every figure the commands draw [dots per inch].
PLOT_DPI = 110

__all__ = [
    "compare_row",
    "modal_dof_summary",
    "compare_table",
    "dof_summary",
    "modes_summary",
    "operating_point_summary",
    "mitigation_text",
    "modes_table",
    "multimode_text",
    "analysis_header",
    "write_multimode_plot",
    "plot_times",
    "squeal_report",
    "stability_line",
    "stability_text",
    "sweep_table",
    "write_compare_plot",
    "write_envelope_csv",
    "write_envelope_plot",
    "write_simulation_files",
]


def dof_summary(dof) -> dict:
    """The modal parameters of a ``reduced.ModalDOF`` (SI units)."""
    return {
        "mass_kg": dof.mass_kg,
        "stiffness_n_m": dof.stiffness_n_m,
        "damping_ns_m": dof.damping_ns_m,
        "frequency_hz": dof.frequency_hz,
    }


def modes_summary(design: WheelDesign, modeset, selected, fid: Fidelity, why: str | None = None) -> dict:
    """``summary.json``'s modal part: every mode with its labels and contact m, k, c, the
    selected mode (and why; None when no mode was selected), the solver, DOFs and timings."""

    def zeta(m) -> float:
        return design.damping_ratio(m.nodal_diameters, m.nodal_circles)

    sel = selected.to_dict(zeta(selected)) if selected is not None else None
    if why is not None and sel is not None:
        sel["why"] = why
    return {
        "design": design.name,
        "fidelity": fid.name,
        "solver": modeset.solver,
        "dofs": int(modeset.dofs),
        "modes": [m.to_dict(zeta(m)) for m in modeset.modes],
        "selected_mode": sel,
        "timings_s": dict(modeset.timings_s),
    }


def operating_point_summary(op, design: WheelDesign) -> dict:
    """The operating point (SI units, and the wheel speed in rev/min)."""
    return {
        "rolling_speed_m_s": op.rolling_speed_m_s,
        "rpm": op.rolling_speed_m_s / rpm_to_speed(1.0, design.rolling_radius),
        "crabbing_velocity_m_s": op.crabbing_velocity_m_s,
        "creepage": op.creepage,
        "wheel_speed_rad_s": op.wheel_speed_rad_s(design.rolling_radius),
    }


def modes_table(modes, design: WheelDesign, selected=None) -> str:
    """The modes as a text table (damping c from each mode's ratio), the selected one marked."""
    lines = [
        f"{'#':>3} {'f [Hz]':>9} {'n':>2} {'c':>2} {'family':<15} {'m [kg]':>10} "
        f"{'k [N/m]':>10} {'c [Ns/m]':>9}"
    ]
    for m in modes:
        d = m.to_dict(design.damping_ratio(m.nodal_diameters, m.nodal_circles))
        mass = f"{d['modal_mass_kg']:10.3f}" if d["modal_mass_kg"] is not None else f"{'node':>10}"
        k = f"{d['modal_stiffness_n_m']:10.3e}" if d["modal_stiffness_n_m"] is not None else f"{'-':>10}"
        c = f"{d['modal_damping_ns_m']:9.2f}" if d["modal_damping_ns_m"] is not None else f"{'-':>9}"
        mark = " <- selected" if selected is not None and m.index == selected.index else ""
        lines.append(
            f"{m.index:>3} {m.frequency_hz:9.1f} {m.nodal_diameters:>2} "
            f"{m.nodal_circles:>2} {m.family:<15} {mass} {k} {c}{mark}"
        )
    return "\n".join(lines)


def analysis_header(a) -> str:
    """One line: the design, the preset, how many modes grow at the operating point."""
    op = a.operating_point
    rpm = op.rolling_speed_m_s / rpm_to_speed(1.0, a.design.rolling_radius)
    grow = sum(r.stability.unstable for r in a.rows)
    preset = f"{a.fidelity.name} preset{', rotating' if a.rotation else ''}"
    return (
        f"{a.design.name} ({preset}): {grow} of {len(a.rows)} modes seen at the contact grow at "
        f"{rpm:.0f} RPM, Vc = {op.crabbing_velocity_m_s:.4g} m/s"
    )


def squeal_report(sim, dof, label: str | None = None) -> str:
    """The simulated mode's modal parameters, the contact ellipse, the operating point and
    its limit cycle, as text (the verdict is :meth:`wheel_squeal.verdict.Verdict.lines`)."""
    s = sim.summary()
    lc, op, ct = s["limit_cycle"], s["operating_point"], s["contact"]
    of = f" of {label}" if label else ""
    lines = [
        f"modal parameters{of}: f = {dof.frequency_hz:.1f} Hz, m = {dof.mass_kg:.3f} kg, "
        f"k = {dof.stiffness_n_m:.4g} N/m, c = {dof.damping_ns_m:.2f} N s/m",
        f"contact ellipse: a = {ct['semi_axis_a_m'] * 1e3:.3f} mm (rolling), "
        f"b = {ct['semi_axis_b_m'] * 1e3:.3f} mm, C22 = {ct['c22']:.3g}, "
        f"mu = {ct['friction_coefficient']:.3g}",
        f"operating point: V0 = {op['rolling_speed_m_s']:.2f} m/s, "
        f"Vc = {op['crabbing_velocity_m_s']:.4g} m/s, creepage = {op['creepage']:.4g}",
    ]
    if lc["squeal"]:
        state = "limit cycle" if sim.limit_cycle.saturated else "still growing at the end of the run"
        tsat = lc["time_to_saturation_s"]
        lines.append(
            f"limit cycle{of}: velocity amplitude {lc['velocity_amplitude_m_s']:.4g} m/s ({state}), "
            f"{lc['frequency_hz']:.1f} Hz, growth rate {lc['growth_rate_1_s']:.3g} 1/s"
            + (f", saturated after {tsat:.3f} s" if tsat is not None else "")
        )
    else:
        rate = sim.limit_cycle.growth_rate_analytic_1_s
        lines.append(
            f"limit cycle{of}: none, the oscillation does not sustain (linear growth rate {rate:.3g} 1/s)"
        )
    return "\n".join(lines)


def plot_times(sim) -> tuple[float, float]:
    """Windows [s] for the paper's Fig. 7-10: while growing (0.2 s) and at the limit
    cycle (0.4 s in the paper; later when this mode saturates later), inside the record."""
    lc = sim.limit_cycle
    end = float(sim.history.t[-1])
    if not (lc.saturated and math.isfinite(lc.time_to_saturation_s)):
        return (min(0.2, end / 3), min(0.4, end))
    period = 1.0 / lc.frequency_hz
    t_lc = max(0.4, lc.time_to_saturation_s + 20 * period)
    growing = min(0.2, 0.5 * lc.time_to_saturation_s)
    return (round(growing, 2), round(max(min(t_lc, end - 5 * period), 0.0), 2))


def write_simulation_files(directory: Path, sim, plots: PlotWorkers) -> None:
    """``timeseries.csv`` and the Fig. 4, 6-10 counterparts (PNG) of a simulation, queued
    on ``plots``, one job per file."""
    from reduced import write_time_history_plots, write_timeseries_csv
    from reduced.report import TIME_HISTORY_FIGURES

    plots.submit(write_timeseries_csv, sim.history, directory)
    for figure in TIME_HISTORY_FIGURES:
        plots.submit(write_time_history_plots, sim.history, directory, plot_times(sim), (figure,))


def sweep_table(crab_velocities: np.ndarray, rpms: np.ndarray, result) -> str:
    """The limit-cycle amplitude over the sweep grid as text ('-' = no squeal)."""
    lines = [f"{'Vc [m/s]':>9} " + " ".join(f"{r:>9.0f}rpm" for r in rpms)]
    for i, vc in enumerate(crab_velocities):
        cells = [
            f"{result.velocity_amplitude_m_s[i, j]:12.4f}" if result.squeal[i, j] else f"{'-':>12}"
            for j in range(len(rpms))
        ]
        lines.append(f"{vc:9.4f} " + " ".join(cells))
    return "\n".join(lines)


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
    finite = [v for v in spl if np.isfinite(v)]
    if finite:
        axes[2].set_ylim(min(finite) - 20, max(finite) + 5)
    axes[2].set(
        xticks=x, ylabel="SPL at the microphone (dB re 20 uPa)", title="level (hollow: not a limit cycle)"
    )
    axes[2].set_xticklabels(names, rotation=30, ha="right")
    fig.savefig(path, dpi=PLOT_DPI)
    return path


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


def stability_line(rows: Sequence, chosen) -> str:
    """One line: how many modes are unstable, the fastest, and the chosen one's growth."""
    unstable = [r for r in rows if r.stability.unstable]
    fastest = max(rows, key=lambda r: r.stability.growth_rate_1_s)
    own = next((r for r in rows if r.mode.index == chosen.index), None)
    text = (
        f"linear stability: {len(unstable)} of {len(rows)} modes unstable here; fastest "
        f"{fastest.mode.label()} at {fastest.stability.damped_frequency_hz:.1f} Hz, "
        f"{fastest.stability.growth_rate_1_s:.3g} 1/s"
    )
    if own is not None and own is not fastest:
        text += f"; the simulated mode {own.stability.growth_rate_1_s:.3g} 1/s (see the stability command)"
    return text


def write_envelope_csv(path: Path, env) -> Path:
    """stability.csv: one row per (crabbing velocity, speed) with the fastest mode."""
    rows = []
    for i, vc in enumerate(env.crab_velocities_m_s):
        for j, rpm in enumerate(env.rpm):
            m = env.modes[env.winner[i, j]]
            rows.append(
                {
                    "crab_velocity_m_s": float(vc),
                    "rpm": float(rpm),
                    "growth_rate_1_s": float(env.growth_rate_1_s[i, j]),
                    "unstable": bool(env.growth_rate_1_s[i, j] > 0),
                    "fastest_mode_index": m.index,
                    "fastest_mode": m.label(),
                    "fastest_mode_frequency_hz": m.frequency_hz,
                }
            )
    return write_csv(path, rows)


def write_envelope_plot(path: Path, env) -> Path:
    """stability.png: the largest growth rate against the crabbing velocity, one curve
    per speed, each point coloured by the mode that grows fastest there."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8, 5))
    ax = fig.subplots()
    fig.subplots_adjust(left=0.1, right=0.7, bottom=0.11, top=0.92)
    labels = {
        int(i): f"{env.modes[i].label()}, {env.modes[i].frequency_hz:.0f} Hz" for i in np.unique(env.winner)
    }
    colours = {i: f"C{k % 10}" for k, i in enumerate(labels)}
    markers = "osD^v<>"
    for j, rpm in enumerate(env.rpm):
        ax.plot(env.crab_velocities_m_s, env.growth_rate_1_s[:, j], "-", color="0.6", lw=0.8)
        for i, label in labels.items():
            sel = env.winner[:, j] == i
            ax.plot(
                env.crab_velocities_m_s[sel],
                env.growth_rate_1_s[sel, j],
                markers[j % 7],
                ms=4,
                color=colours[i],
                label=label if j == 0 else None,
            )
        ax.annotate(f"{rpm:.0f} RPM", (env.crab_velocities_m_s[-1], env.growth_rate_1_s[-1, j]), fontsize=8)
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set(
        xlabel="crabbing velocity Vc (m/s)",
        ylabel="largest growth rate (1/s)",
        title="Linear stability: growth rate and the fastest mode (> 0: squeal grows)",
    )
    ax.legend(title="fastest mode", fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.grid(alpha=0.3)
    fig.savefig(path, dpi=110)
    return path


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


def mitigation_text(mitigation: dict) -> str:
    """The damping per mode and the friction slope that stop squeal over the envelope."""
    vc, rpm = mitigation["crab_velocity_m_s"], mitigation["rpm"]
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
