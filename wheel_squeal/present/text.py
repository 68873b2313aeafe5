"""What a command prints: the verdict's lines, tables of modes, eigenvalues, sweeps,
comparisons and levels, from the records."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..design import Design
from ..outputs import NONE, bound_or_none
from ..presets import rpm_to_speed
from ..sweeps import VerdictGrid

if TYPE_CHECKING:
    from fem.modes import Mode
    from reduced import ModalDOF

    from ..chain import Analysis
    from ..simulation import Simulation
    from ..verdict import ModeOutcome, Verdict

__all__ = [
    "analysis_text",
    "analysis_header",
    "compare_table",
    "eigenvalues_text",
    "measured_table",
    "mitigation_text",
    "modes_table",
    "num_cell",
    "shares_text",
    "verdict_lines",
    "sound_text",
    "squeal_report",
    "stability_text",
    "sweep_table",
]


def modes_table(modes: Sequence[Mode], design: Design, selected: Mode | None = None) -> str:
    """The modes as a text table (damping c from each mode's ratio), the selected one marked."""
    lines = [
        f"{'#':>3} {'f [Hz]':>9} {'n':>2} {'c':>2} {'family':<15} {'m [kg]':>10} "
        f"{'k [N/m]':>10} {'c [Ns/m]':>9}"
    ]
    for m in modes:
        d = m.to_dict(design.damping_ratio_of(m))
        mass = f"{d['modal_mass_kg']:10.3f}" if d["modal_mass_kg"] is not None else f"{NONE:>10}"
        k = f"{d['modal_stiffness_n_m']:10.3e}" if d["modal_stiffness_n_m"] is not None else f"{NONE:>10}"
        c = f"{d['modal_damping_ns_m']:9.2f}" if d["modal_damping_ns_m"] is not None else f"{NONE:>9}"
        mark = " <- selected" if selected is not None and m.index == selected.index else ""
        lines.append(
            f"{m.index:>3} {m.frequency_hz:9.1f} {m.nodal_diameters:>2} "
            f"{m.nodal_circles:>2} {m.family:<15} {mass} {k} {c}{mark}"
        )
    return "\n".join(lines)


def analysis_header(a: Analysis) -> str:
    """One line: the design, the preset, how many modes grow at the operating point."""
    op = a.operating_point
    rpm = op.rolling_speed_m_s / rpm_to_speed(1.0, a.design.rolling_radius)
    grow = sum(r.stability.unstable for r in a.rows)
    preset = f"{a.fidelity.name} preset{', rotating' if a.rotation else ''}"
    return (
        f"{a.design.name} ({preset}): {grow} of {len(a.rows)} modes seen at the contact grow at "
        f"{rpm:.0f} RPM, Vc = {op.crabbing_velocity_m_s:.4g} m/s"
    )


def squeal_report(sim: Simulation, dof: ModalDOF, label: str | None = None) -> str:
    """The simulated mode's modal parameters, the contact ellipse, the operating point and
    its limit cycle, as text (the verdict is :func:`verdict_lines`)."""
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
        tsat, grew = lc["time_to_saturation_s"], lc["envelope_growth_rate_1_s"]
        lines.append(
            f"limit cycle{of}: velocity amplitude {lc['velocity_amplitude_m_s']:.4g} m/s ({state}), "
            f"{lc['frequency_hz']:.1f} Hz"
            + (f", its envelope grew at {grew:.3g} 1/s" if grew is not None and math.isfinite(grew) else "")
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


def num_cell(v: Any, fmt: str, width: int) -> str:
    """A fixed-width number, or the word for none."""
    return f"{v:{width}{fmt}}" if v is not None else f"{NONE:>{width}}"


def compare_table(rows: Sequence[dict]) -> str:
    """The designs side by side, as text, in the rows' order (loudest sound power first),
    each at its own operating point, with levels at the common distances."""

    lines = [
        f"{'design':<16} {'V0 [m/s]':>8} {'[RPM]':>6} {'Vc [m/s]':>8} {'verdict':<16} {'tone [Hz]':>9} "
        f"{'growth [1/s]':>12} {'amp [m/s]':>9} {'L_W [dB]':>8} {'L_W [dB(A)]':>11} {'1 m [dB]':>8} "
        f"{'7.5 m [dB]':>10}"
    ]
    for r in rows:
        verdict = r["verdict_mode"] or "no squeal"
        amp = num_cell(r["amplitude_m_s"], ".4f", 9) + ("" if r["saturated"] or not r["squeals"] else "*")
        tone, growth = num_cell(r["tone_hz"], ".1f", 9), num_cell(r["growth_rate_1_s"], ".3g", 12)
        power, power_a = (
            num_cell(r["sound_power_level_db"], ".1f", 8),
            num_cell(r["sound_power_level_dba"], ".1f", 11),
        )
        near, far = num_cell(r["spl_1m_db"], ".1f", 8), num_cell(r["spl_7_5m_db"], ".1f", 10)
        lines.append(
            f"{r['design']:<16} {r['rolling_speed_m_s']:8.2f} {r['rpm']:6.0f} "
            f"{r['crabbing_velocity_m_s']:8.3g} {verdict:<16} {tone} {growth} {amp} "
            f"{power} {power_a} {near} {far}"
        )
    lines.append("loudest sound power first; levels 1 m and 7.5 m from the wheel centre, loudest direction")
    if any(r["squeals"] and not r["saturated"] for r in rows):
        lines.append("* still growing at the end of the run: not a limit cycle")
    return "\n".join(lines)


def _cell(value: float | None, width: int, computed: bool = True) -> str:
    """A number in a text table: :data:`NONE` where it has no value (the contact cannot
    excite the mode, or no bound exists), '-' where it was not computed."""
    if not computed:
        return f"{'-':>{width}}"
    v = bound_or_none(value)
    return f"{v:{width}.3g}" if v is not None else f"{NONE:>{width}}"


def stability_text(rows: Sequence, winner: int, bounds: bool = True) -> str:
    """The stability of every excitable mode as text, the leading one (the decision's)
    marked (``bounds``: the critical damping and slope were computed)."""
    lines = [
        f"{'#':>3} {'f [Hz]':>9} {'n':>2} {'c':>2} {'family':<15} {'sigma [1/s]':>11} "
        f"{'zeta_crit':>10} {'dmu/dz crit':>11}"
    ]
    for i, row in enumerate(rows):
        m, s = row.mode, row.stability
        mark = " <- leads" if i == winner else (" unstable" if s.unstable else "")
        lines.append(
            f"{m.index:>3} {s.damped_frequency_hz:9.1f} {m.nodal_diameters:>2} {m.nodal_circles:>2} "
            f"{m.family:<15} {s.growth_rate_1_s:11.3g} {_cell(s.critical_damping_ratio, 10, bounds)} "
            f"{_cell(s.critical_friction_slope, 11, bounds)}{mark}"
        )
    return "\n".join(lines)


def shares_text(o: ModeOutcome) -> str:
    """Which mode carries the limit cycle of the modes integrated together, with every
    degree of freedom's share of its vibration energy."""
    assert o.shares is not None and o.simulation is not None
    wheel = {m.label() for m in o.group}
    parts = [f"{label} {s:.1%}" for label, s in o.shares.items() if label in wheel]
    # the counter-body's share, its terms together under its name ("the rail")
    parts += [f"{label} {s:.1%}" for label, s in o.shares.items() if label not in wheel]
    share = ", ".join(parts)
    return (
        f"the {len(o.group)} modes that grow together: {o.label} carries the limit cycle at "
        f"{o.tone_hz:.1f} Hz; energy shares: {share}"
    )


def verdict_lines(v: Verdict) -> list[str]:
    """The verdict as the last lines a command prints: the answer, why, and what would
    stop it (or how far it is from squealing).

    Parameters
    ----------
    v : Verdict

    Returns
    -------
    list of str

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> a = ws.analyse(ws.load_design(), modes=ws.explicit_modes(3.1, 1.6e8, 42), stop_after="limit_cycle")
    >>> print(ws.verdict_lines(a.verdict)[0][:62])
    VERDICT: squeals in the given mode (1143.4 Hz) by falling fric
    """
    o = v.outcome
    if not v.squeals or o is None:
        return [f"VERDICT: no squeal. {v.reason}"]
    levels = o.levels()
    spl, dba, power = levels["spl_db"], levels["spl_dba"], levels["sound_power_level_db"]
    level = (
        f", SPL {spl:.1f} dB ({dba:.1f} dB(A)) at the microphone, sound power {power:.1f} dB"
        if spl is not None
        else f", silent at the microphone, sound power {power:.1f} dB"
        if power is not None
        else ""
    )
    amplitude = (
        f", {o.amplitude_m_s:.4g} m/s at the contact ({o.state_words})" if o.amplitude_m_s is not None else ""
    )
    wave = f", its {o.wave} wave" if o.wave != "standing" else ""
    by = f" by {o.mechanism}" if o.mechanism else ""
    # the common ratio goes without saying on the terminal (summary.json always has it)
    own = v.damping is not None and v.damping[1] != "modal_damping_ratio"
    damping = (
        [f"  damping: {o.label}'s ratio {v.damping[0]:.2g}, from {v.damping[1]}"] if own and v.damping else []
    )
    return [
        f"VERDICT: squeals in {o.label}{by} at {o.tone_hz:.1f} Hz{wave}{amplitude}{level}",
        f"  why: {v.reason}",
        *damping,
        *([f"  remedy: {v.remedy['words']}"] if v.remedy is not None else []),
    ]


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


def _need(value: float | None, width: int) -> str:
    return f"{value:{width}.2e}" if value is not None else f"{NONE:>{width}}"


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
            f"{_need(a['required_damping_ratio'], 12)} {_need(b['required_damping_ratio'], 13)}"
        )
    lines.append(
        f"or a creep curve no steeper than dmu/dzeta = {_cell(off['required_friction_slope'], 0).strip()} "
        f"(rotation on: {_cell(on['required_friction_slope'], 0).strip()}) at the quasi-static creepage"
    )
    return "\n".join(lines)


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


def measured_table(comparison: list[dict]) -> str:
    """The comparison as text: prediction minus measurement per point, and its mean and
    spread over the points with a prediction."""

    def num_cell(x: Any, fmt: str) -> str:
        return "-" if x is None else format(x, fmt)

    lines = [f"{'Vc [m/s]':>9} {'rpm':>6} {'measured':>9} {'predicted':>9} {'pred-meas':>9}  dB"]
    for c in comparison:
        lines.append(
            f"{c['crabbing_velocity_m_s']:9.4f} {c['rpm']:6.0f} {c['measured_spl_db']:9.1f} "
            f"{num_cell(c['predicted_spl_db'], '9.1f'):>9} {num_cell(c['spl_difference_db'], '+9.1f'):>9}"
        )
    d = np.array([c["spl_difference_db"] for c in comparison if c["spl_difference_db"] is not None])
    if len(d):
        lines.append(
            f"prediction minus measurement over {len(d)} of {len(comparison)} points: "
            f"mean {d.mean():+.1f} dB, rms {np.sqrt(np.mean(d**2)):.1f} dB "
            "('-': no limit cycle predicted there)"
        )
    return "\n".join(lines)


def sound_text(summary: dict) -> str:
    """The levels, at which contact velocity and where they were taken (two lines)."""
    r, z, theta = summary["microphone_m"]
    where = f"at the microphone (r {r:g} m, z {z:g} m, theta {theta:g})"
    v = summary["velocity_amplitude_m_s"]
    if summary["sound_power_level_db"] is None:
        return f"sound: none (contact velocity amplitude {v:g} m/s)"
    spl = (
        f"SPL {summary['spl_db']:.1f} dB ({summary['spl_dba']:.1f} dB(A)) re 20 uPa {where}"
        if summary["spl_db"] is not None
        else f"silent {where} (below -20 dB: a node of the radiation, on the axis or on a nodal diameter)"
    )
    harmonics = len(summary["harmonics"])
    far = (
        f"{summary['spl_1m_db']:.1f} dB at 1 m and {summary['spl_7_5m_db']:.1f} dB at 7.5 m from the wheel "
        f"centre, {summary['loudest_angle_deg']:.0f} deg from its axis (the loudest direction)"
    )
    return (
        f"sound: sound power level {summary['sound_power_level_db']:.1f} dB re 1 pW "
        f"({summary['sound_power_level_dba']:.1f} dB(A)), {spl}, radiation efficiency "
        f"{summary['radiation_efficiency']:.3g}, {summary['frequency_hz']:.1f} Hz"
        + (f" and {harmonics - 1} harmonics" if harmonics > 1 else "")
        + f", contact velocity {v:.4g} m/s (wheel alone, free field)\n       {far}"
    )


def analysis_text(a: Analysis) -> str:
    """What ``run`` and ``simulate`` print.

    The header, the simulated outcome's modal parameters and limit cycle, the modes that
    grew together, the sound and the verdict.

    Parameters
    ----------
    a : Analysis

    Returns
    -------
    str
        Lines of text (no trailing newline).

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> a = ws.analyse(ws.load_design(), modes=ws.explicit_modes(3.1, 1.6e8, 42), stop_after="limit_cycle")
    >>> print(ws.analysis_text(a).splitlines()[0])
    table1 (balanced preset): 1 of 1 modes seen at the contact grow at 800 RPM, Vc = 0.39 m/s
    """
    from ..api import modal_dof

    lines = [analysis_header(a)]
    o = a.outcome
    if o is not None and o.simulation is not None:
        lines.append(squeal_report(o.simulation, modal_dof(o.mode, a.design), o.label))
    for outcome in (a.verdict.pick, a.verdict.named):
        if outcome is not None and outcome.shares is not None and outcome.simulation is not None:
            lines.append(shares_text(outcome))
            break
    if o is not None and o.simulation is not None and o.simulation.history.v_body is not None:
        from reduced.summaries import counter_body_motion

        m = counter_body_motion(o.simulation.history)
        body = a.design.counter_body.model().name
        lines.append(
            f"{body} at the end of the record: {m['counter_body_velocity_share']:.1%} of the slip velocity "
            f"(rms {m['counter_body_velocity_rms_m_s']:.3g} m/s), {m['counter_body_power_w']:.3g} W into it"
        )
    heard = a.verdict.outcome
    if heard is not None and heard.sound is not None:
        lines.append(sound_text(heard.sound.summary()))
    return "\n".join(lines + verdict_lines(a.verdict))
