"""What the commands write and print: summaries (JSON-ready dicts), tables and plots.

Functions here take the plain objects of the stages (:mod:`wheel_squeal.api`) and either
return text / dicts or write files into a folder they are given (the caller makes the
folder atomic, :mod:`wheel_squeal.outputs`).
"""

from __future__ import annotations

import math
from pathlib import Path

from .design import Design
from .outputs import finite_or_none
from .plotting import PlotWorkers
from .presets import Fidelity, rpm_to_speed

#: The resolution of every figure the commands draw [dots per inch].

__all__ = [
    "analysis_header",
    "dof_summary",
    "modes_summary",
    "modes_table",
    "operating_point_summary",
    "plot_times",
    "squeal_report",
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


def modes_summary(design: Design, modeset, selected, fid: Fidelity, why: str | None = None) -> dict:
    """``summary.json``'s modal part: every mode with its labels and contact m, k, c, the
    selected mode (and why; None when no mode was selected), the solver, DOFs and timings."""

    def zeta(m) -> float:
        return design.damping_ratio_of(m)

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


def operating_point_summary(op, design: Design) -> dict:
    """The operating point (SI units, and the wheel speed in rev/min)."""
    return {
        "rolling_speed_m_s": op.rolling_speed_m_s,
        "rpm": op.rolling_speed_m_s / rpm_to_speed(1.0, design.rolling_radius),
        "crabbing_velocity_m_s": op.crabbing_velocity_m_s,
        "creepage": op.creepage,
        "wheel_speed_rad_s": op.wheel_speed_rad_s(design.rolling_radius),
    }


def contact_summary(design: Design, contact, op) -> dict:
    """The contact as the stability sees it: its point and angle, the friction law, the
    normal spring, transient creep and the roller's modes (SI units)."""
    frame = design.contact_frame
    return {
        **frame.to_dict(),
        "friction_law": contact.friction_law,
        "normal_contact": design.contact.normal_contact,
        "normal_stiffness_n_m": contact.normal_stiffness_n_m,
        "hertz_approach_m": finite_or_none(contact.hertz_approach_m),
        "relaxation_length_m": contact.relaxation_length_m,
        "relaxation_time_s": contact.relaxation_time_s(op.rolling_speed_m_s),
        "roller_normal": design.roller.modal("normal"),
        "roller_lateral": design.roller.modal("lateral"),
    }


def modes_table(modes, design: Design, selected=None) -> str:
    """The modes as a text table (damping c from each mode's ratio), the selected one marked."""
    lines = [
        f"{'#':>3} {'f [Hz]':>9} {'n':>2} {'c':>2} {'family':<15} {'m [kg]':>10} "
        f"{'k [N/m]':>10} {'c [Ns/m]':>9}"
    ]
    for m in modes:
        d = m.to_dict(design.damping_ratio_of(m))
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
        f"mu = {ct['friction_coefficient']:.3g}"
        + ("" if ct["friction_law"] == "falling" else f" ({ct['friction_law']} friction)"),
        f"operating point: V0 = {op['rolling_speed_m_s']:.2f} m/s, "
        f"Vc = {op['crabbing_velocity_m_s']:.4g} m/s, creepage = {op['creepage']:.4g}",
    ]
    if lc["squeal"]:
        state = {
            "limit cycle": "limit cycle",
            "still growing": "still growing at the end of the run",
            "not settled": "not settled: a sustained oscillation, not a clean limit cycle",
        }[sim.limit_cycle.state]
        tsat = lc["time_to_saturation_s"]
        lines.append(
            f"limit cycle{of}: velocity amplitude {lc['velocity_amplitude_m_s']:.4g} m/s ({state}), "
            f"{lc['frequency_hz']:.1f} Hz, growth rate {lc['growth_rate_1_s']:.3g} 1/s"
            + (f", saturated after {tsat:.3f} s" if tsat is not None and math.isfinite(tsat) else "")
            + (
                f"; wheel and roller apart over {lc['contact_lost_fraction']:.0%} of the last quarter"
                if lc["contact_lost_fraction"] > 0
                else ""
            )
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
