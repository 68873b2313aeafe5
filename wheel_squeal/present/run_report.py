"""The ``report.html`` of ``run`` (one analysis: the verdict, the modes, the limit cycle,
the sound, what would stop it) and of ``compare`` (one verdict per design), from the parts
of :mod:`.html`."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from ..outputs import NONE
from .html import (
    assumption_list,
    audio,
    escape,
    file_list,
    image,
    page,
    pairs,
    section,
    table,
    verdict_block,
    versions,
    write_report,
)
from .summary import operating_point_summary
from .text import verdict_lines

if TYPE_CHECKING:
    from ..chain import Analysis

__all__ = ["compare_report", "run_report"]


def _times(folder: Path, stem: str) -> list[Path]:
    """``stem_<t>s.png`` in ``folder``, by time."""
    return sorted(folder.glob(f"{stem}_*s.png"), key=lambda p: float(p.stem.rsplit("_", 1)[1][:-1]))


def _limit_cycle(folder: Path) -> str:
    """The counterparts of the paper's Figs. 4 and 6-10: the creep curve with the
    operating point, the contact velocity over the run, and force, velocity and power
    while growing and over the last periods (the limit cycle)."""
    parts = [
        image(folder / "velocity_history.png", "contact velocity over the run"),
        image(folder / "creep_curve.png", "creep curve and the operating point"),
    ]
    for stem, what in (("force_velocity", "creep force and contact velocity"), ("power", "power")):
        paths = _times(folder, stem)
        for k, path in enumerate(paths):
            when = "over the last periods (the limit cycle)" if k == len(paths) - 1 else "while growing"
            t = path.stem.rsplit("_", 1)[1]
            parts.append(
                f'<p class="muted">{escape(what)} {when}, about t = {escape(t)}</p>'
                + image(path, f"{what} {when}")
            )
    return section("The limit cycle", *parts) if any(parts) else ""


def _together(folder: Path, a: Analysis) -> str:
    """The modes integrated together: which carries the limit cycle, each one's share."""
    o = next((x for x in (a.verdict.pick, a.verdict.named) if x is not None and x.shares), None)
    if o is None or o.shares is None:
        return ""
    rows = [{"dof": k, "share": f"{v:.1%}"} for k, v in sorted(o.shares.items(), key=lambda kv: -kv[1])]
    carried = (
        f" ({o.energy_share:.1%} of the energy with its eigenvalue's partners)" if o.energy_share else ""
    )
    return section(
        "The modes that grow together",
        f"<p>{escape(o.label)} carries the limit cycle{escape(carried)}, at {o.tone_hz:.1f} Hz.</p>",
        table(rows, [("dof", "mode"), ("share", "share of the vibration energy")]),
        image(folder / "multimode.png", "energy shares of the modes integrated together"),
    )


def _remedy(folder: Path, a: Analysis) -> str:
    """What stops the squeal: the damping per mode, the friction levers, remedy.toml."""
    r = a.verdict.remedy
    if r is None:
        return ""
    rows = [{"mode": k, "now": r["damping_now"][k], "needed": v} for k, v in r["damping"].items()]
    mu, slope = r["friction_coefficient"], r["friction_slope"]
    levers = [
        (
            f"friction coefficient (now {r['friction_coefficient_now']:.2g})",
            f"below {mu:.2g}" if mu is not None else f"{NONE} stops it",
        ),
        (
            f"creep-curve slope dmu/dzeta (now {r['friction_slope_now']:.3g})",
            f"above {slope:.3g}" if slope is not None else f"{NONE} stops it",
        ),
        *(
            (f"{s['mode']} (now {s['frequency_hz_now']:.1f} Hz)", f"above {s['frequency_hz']:.1f} Hz")
            for s in r["separations"]
            if s["frequency_hz"] is not None
        ),
    ]
    toml = folder / "remedy.toml"
    return section(
        "What would stop it",
        f"<p>{escape(r['words'])}</p>",
        table(
            rows, [("mode", "mode"), ("now", "damping ratio now (-)"), ("needed", "damping ratio needed (-)")]
        ),
        pairs(levers),
        f'<p class="muted">remedy.toml, to paste into the design:</p><pre>{escape(toml.read_text())}</pre>'
        if toml.is_file()
        else "",
    )


def run_report(folder: Path, a: Analysis) -> Path:
    """The report of ``run``: the analysis ``a`` and the files in ``folder``."""

    d, op = a.design, operating_point_summary(a.operating_point, a.design)
    frame = d.contact_frame
    inputs = [
        ("design", f"{d.name}: {d.description}"),
        (
            "rolling radius at the contact",
            f"{frame.r_m:.4g} m (contact angle {frame.to_dict()['contact_angle_deg']:.3g} deg)",
        ),
        ("wheel speed", f"{op['rpm']:.4g} rev/min (V0 = {op['rolling_speed_m_s']:.4g} m/s)"),
        ("crabbing velocity", f"{op['crabbing_velocity_m_s']:.4g} m/s (creepage {op['creepage']:.4g})"),
        (
            "normal load, friction",
            f"{d.contact.normal_load:g} N, mu = {d.contact.friction_coefficient:g}, "
            f"{a.contact.friction_law} law, normal contact {d.contact.normal_contact}",
        ),
        (
            "damping ratio",
            f"{d.damping.modal_damping_ratio:g} (measured by mode: {dict(d.damping.by_mode) or 'none'})",
        ),
        ("rotation", "modelled (travelling waves)" if a.rotation else "left out (the paper's model)"),
        ("fidelity", f"{a.fidelity.name} preset, {a.modeset.solver} solver, {a.modeset.dofs} DOFs"),
    ]
    rows = []
    for r in a.rows:
        m, st = r.mode, r.stability
        mass = m.modal_mass
        rows.append(
            {
                "mode": m.label(),
                "f": m.frequency_hz,
                "mass": mass if mass != float("inf") else None,
                "sigma": st.growth_rate_1_s,
                "fd": st.damped_frequency_hz,
                "mech": st.mechanism or "decays",
            }
        )
    mode_table = table(
        rows,
        [
            ("mode", "mode"),
            ("f", "f (Hz)"),
            ("mass", "lateral modal mass (kg)"),
            ("fd", "frequency with contact (Hz)"),
            ("sigma", "growth rate (1/s)"),
            ("mech", "mechanism"),
        ],
    )
    o = a.verdict.outcome
    sound = o.sound.summary() if o is not None and o.sound is not None else None
    levels = ""
    if sound is not None:
        levels = pairs(
            [
                (
                    "SPL at the microphone",
                    f"{sound['spl_db']:.1f} dB, {sound['spl_dba']:.1f} dB(A) re 20 uPa"
                    if sound["spl_db"] is not None
                    else "silent (below -20 dB re 20 uPa)",
                ),
                (
                    "microphone (r, z, theta)",
                    "{:g} m, {:g} m, {:g} deg".format(
                        *sound["microphone_m"][:2], math.degrees(sound["microphone_m"][2])
                    ),
                ),
                (
                    "sound power level",
                    f"{sound['sound_power_level_db']:.1f} dB, "
                    f"{sound['sound_power_level_dba']:.1f} dB(A) re 1 pW",
                ),
                (
                    "SPL 1 m / 7.5 m from the centre",
                    f"{sound['spl_1m_db']:.1f} / {sound['spl_7_5m_db']:.1f} dB "
                    f"(loudest direction, {sound['loudest_angle_deg']:.0f} deg from the axis)",
                ),
                (
                    "harmonics radiated",
                    f"{len(sound['harmonics'])}, holding {sound['velocity_energy_share']:.2%} "
                    "of the contact velocity's energy",
                ),
                ("radiation efficiency", f"{sound['radiation_efficiency']:.3g}"),
            ]
        )
    listen = (
        section(
            "Listen",
            audio(folder / "squeal.wav"),
            '<p class="muted">the microphone\'s pressure over the simulated run (growth and limit cycle), '
            "peak-normalised: its true level is above</p>",
        )
        if (folder / "squeal.wav").is_file()
        else ""
    )
    body = [
        verdict_block(verdict_lines(a.verdict), a.verdict.squeals),
        section("How loud", levels) if levels else "",
        listen,
        section("Which mode squeals", mode_table, image(folder / "growth.png", "growth rate of every mode")),
        _together(folder, a),
        _remedy(folder, a),
        _limit_cycle(folder),
        section(
            "Spectra and band levels", image(folder / "spectrum.png", "spectra and one-third-octave bands")
        ),
        section("Sound field and directivity", image(folder / "sound_field.png", "near field and far field")),
        section("The squeal mode", *(image(p, p.stem) for p in sorted(folder.glob("mode_*.png")))),
        section("Inputs", pairs(inputs), '<p class="muted">versions</p>', pairs(versions())),
        section("Assumptions and limits", assumption_list()),
        section("Files", file_list(folder)),
    ]
    return write_report(folder, page(f"Squeal of {d.name}", "wheel-squeal run", body))


def compare_report(folder: Path, rows: Sequence[dict], analyses: Sequence[Analysis]) -> Path:
    """The report of ``compare``: one verdict per design."""
    verdicts = "".join(
        f"<h3>{escape(a.design.name)}</h3>" + verdict_block(verdict_lines(a.verdict), a.verdict.squeals)
        for a in analyses
    )
    columns = [
        ("design", "design"),
        ("rolling_speed_m_s", "V0 (m/s)"),
        ("rpm", "speed (rev/min)"),
        ("crabbing_velocity_m_s", "Vc (m/s)"),
        ("verdict_mode", "verdict"),
        ("tone_hz", "tone (Hz)"),
        ("growth_rate_1_s", "growth (1/s)"),
        ("amplitude_m_s", "amplitude (m/s)"),
        ("sound_power_level_db", "L_W (dB re 1 pW)"),
        ("sound_power_level_dba", "L_W (dB(A))"),
        ("spl_1m_db", "SPL 1 m (dB re 20 uPa)"),
        ("spl_7_5m_db", "SPL 7.5 m (dB re 20 uPa)"),
    ]
    a0 = analyses[0]
    body = [
        section("Verdicts", verdicts),
        section("Side by side", table(rows, columns), image(folder / "compare.png", "designs compared")),
        section(
            "Inputs",
            pairs(
                [
                    ("designs", ", ".join(a.design.name for a in analyses)),
                    ("fidelity", f"{a0.fidelity.name} preset"),
                    *(
                        (
                            f"operating point of {a.design.name}",
                            f"V0 = {a.operating_point.rolling_speed_m_s:.4g} m/s "
                            f"({a.operating_point.rpm(a.design.rolling_radius):.0f} rev/min), "
                            f"Vc = {a.operating_point.crabbing_velocity_m_s:.4g} m/s",
                        )
                        for a in analyses
                    ),
                ]
            ),
            pairs(versions()),
        ),
        section("Assumptions and limits", assumption_list()),
        section("Files", file_list(folder)),
    ]
    return write_report(folder, page("Designs compared", "wheel-squeal compare", body))
