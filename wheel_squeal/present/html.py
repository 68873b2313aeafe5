"""``report.html``: one self-contained page per result folder (``run``, ``compare``,
``study``) to send to a colleague: the inputs, the verdict and its reason, the tables
and the figures, the squeal to listen to, the assumptions and the files.

The page needs nothing but itself: its images and its sound are embedded as data URIs,
its style is inline, and it loads nothing from the network, so it opens from a mail
attachment. It is written last, from the files already in the folder.
"""

from __future__ import annotations

import base64
import datetime as _dt
import html
import importlib.metadata
import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from geometry.files import write_atomic

from ..outputs import NONE
from ..provenance import CODE_PACKAGES, code_version
from .summary import operating_point_summary
from .text import verdict_lines

if TYPE_CHECKING:
    from ..chain import Analysis

__all__ = [
    "ASSUMPTIONS", "REPORT_NAME", "audio", "compare_report", "image",
    "listing_report", "run_report", "study_report", "table",
]  # fmt: skip

REPORT_NAME = "report.html"

#: What every prediction rests on, said on every report
ASSUMPTIONS = (
    "The wheel is axisymmetric and linear-elastic, clamped at the bore; its modes come from "
    "the finite-element model of the chosen preset.",
    "The contact is one Hertz ellipse on the tread (or a flange root) with lateral creep only "
    "(no spin, no longitudinal creep); the normal force follows the Hertz spring about the load.",
    "Each mode is damped by its modal damping ratio (the design's, or a measured one).",
    "Linear stability is a linearisation about steady sliding; the level is the time domain's "
    "limit cycle from rest.",
    "Sound: the wheel alone in free field (no roller, axle, ground or enclosure), the mode's "
    "shape radiating at each harmonic of the contact velocity; levels at the microphone, at 1 m "
    "and 7.5 m from the wheel centre.",
)

_STYLE = """
body { font-family: -apple-system, Segoe UI, Helvetica, Arial, sans-serif; margin: 2em auto;
       max-width: 1100px; color: #222; line-height: 1.4; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; } h2 { font-size: 1.2em; margin-top: 1.8em;
       border-bottom: 1px solid #ccc; }
.verdict { font-size: 1.15em; padding: 0.8em 1em; border-left: 6px solid #b22; background: #fbeaea; }
.verdict.quiet { border-color: #282; background: #eaf6ea; }
table { border-collapse: collapse; margin: 0.6em 0; font-size: 0.9em; }
td, th { border: 1px solid #ccc; padding: 0.2em 0.6em; text-align: right; }
th { background: #f3f3f3; } td.text, th.text { text-align: left; }
img { max-width: 100%; border: 1px solid #eee; margin: 0.4em 0; }
.muted { color: #666; font-size: 0.9em; }
"""


# -- pieces ----------------------------------------------------------------------------------
def _e(x: object) -> str:
    return html.escape(str(x))


def image(path: Path, alt: str) -> str:
    """An embedded PNG (empty where the file is not there)."""
    if not path.is_file():
        return ""
    data = base64.b64encode(path.read_bytes()).decode()
    return f'<img src="data:image/png;base64,{data}" alt="{_e(alt)}">'


def audio(path: Path) -> str:
    """An embedded WAV player (empty where the file is not there)."""
    if not path.is_file():
        return ""
    data = base64.b64encode(path.read_bytes()).decode()
    return f'<audio controls preload="auto" src="data:audio/wav;base64,{data}"></audio>'


def _cell(x: object) -> str:
    if x is None:
        return "-"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, float):
        return f"{x:.4g}"
    return _e(x)


def table(rows: Sequence[dict], columns: Sequence[tuple[str, str]]) -> str:
    """An HTML table of ``rows`` with ``columns`` as (key, heading)."""
    head = "".join(f'<th class="text">{_e(h)}</th>' if i == 0 else f"<th>{_e(h)}</th>"
                   for i, (_, h) in enumerate(columns))  # fmt: skip
    body = "".join(
        "<tr>"
        + "".join(
            f'<td class="text">{_cell(r.get(k))}</td>'
            if i == 0 or isinstance(r.get(k), str)
            else f"<td>{_cell(r.get(k))}</td>"
            for i, (k, _) in enumerate(columns)
        )
        + "</tr>"
        for r in rows
    )
    return f"<table><tr>{head}</tr>{body}</table>"


def _pairs(items: Sequence[tuple[str, object]]) -> str:
    return table([{"k": k, "v": v} for k, v in items], [("k", "quantity"), ("v", "value")])


def versions() -> list[tuple[str, object]]:
    """The tool's and its libraries' versions and the code's hash."""
    out: list[tuple[str, object]] = []
    for name in ("wheel-squeal", "numpy", "scipy", "scikit-fem", "gmsh", "numba"):
        try:
            out.append((name, importlib.metadata.version(name)))
        except importlib.metadata.PackageNotFoundError:
            out.append((name, "absent"))
    out.append(("code", code_version(*CODE_PACKAGES)))
    return out


def _files(folder: Path) -> str:
    names = sorted(p.name for p in folder.iterdir() if p.is_file() and not p.name.startswith("."))
    return "<ul>" + "".join(f"<li><code>{_e(n)}</code></li>" for n in names + [REPORT_NAME]) + "</ul>"


def _page(title: str, subtitle: str, body: list[str]) -> str:
    when = _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC")
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        f"<title>{_e(title)}</title><style>{_STYLE}</style></head><body>"
        f'<h1>{_e(title)}</h1><p class="muted">{_e(subtitle)}; written {when}</p>'
        + "".join(body)
        + "</body></html>\n"
    )


def _section(title: str, *parts: str) -> str:
    return f"<h2>{_e(title)}</h2>" + "".join(p for p in parts if p)


def _verdict_block(lines: Sequence[str], squeals: bool) -> str:
    return (
        f'<div id="verdict" class="verdict{"" if squeals else " quiet"}">'
        + "<br>".join(_e(x) for x in lines)
        + "</div>"
    )


def _assumptions(assumptions: Sequence[str] = ASSUMPTIONS) -> str:
    return "<ul>" + "".join(f"<li>{_e(a)}</li>" for a in assumptions) + "</ul>"


def _write(folder: Path, text: str) -> Path:
    return write_atomic(folder / REPORT_NAME, text)


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
                f'<p class="muted">{_e(what)} {when}, about t = {_e(t)}</p>' + image(path, f"{what} {when}")
            )
    return _section("The limit cycle", *parts) if any(parts) else ""


def _together(folder: Path, a: Analysis) -> str:
    """The modes integrated together: which carries the limit cycle, each one's share."""
    o = next((x for x in (a.verdict.pick, a.verdict.named) if x is not None and x.shares), None)
    if o is None or o.shares is None:
        return ""
    rows = [{"dof": k, "share": f"{v:.1%}"} for k, v in sorted(o.shares.items(), key=lambda kv: -kv[1])]
    carried = (
        f" ({o.energy_share:.1%} of the energy with its eigenvalue's partners)" if o.energy_share else ""
    )
    return _section(
        "The modes that grow together",
        f"<p>{_e(o.label)} carries the limit cycle{_e(carried)}, at {o.tone_hz:.1f} Hz.</p>",
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
        (f"friction coefficient (now {r['friction_coefficient_now']:.2g})",
         f"below {mu:.2g}" if mu is not None else f"{NONE} stops it"),
        (f"creep-curve slope dmu/dzeta (now {r['friction_slope_now']:.3g})",
         f"above {slope:.3g}" if slope is not None else f"{NONE} stops it"),
        *((f"{s['mode']} (now {s['frequency_hz_now']:.1f} Hz)", f"above {s['frequency_hz']:.1f} Hz")
          for s in r["separations"] if s["frequency_hz"] is not None),
    ]  # fmt: skip
    toml = folder / "remedy.toml"
    return _section(
        "What would stop it",
        f"<p>{_e(r['words'])}</p>",
        table(
            rows, [("mode", "mode"), ("now", "damping ratio now (-)"), ("needed", "damping ratio needed (-)")]
        ),
        _pairs(levers),
        f'<p class="muted">remedy.toml, to paste into the design:</p><pre>{_e(toml.read_text())}</pre>'
        if toml.is_file()
        else "",
    )


# -- the reports -------------------------------------------------------------------------------
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
        ),  # fmt: skip
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
        rows.append({
            "mode": m.label(), "f": m.frequency_hz, "mass": mass if mass != float("inf") else None,
            "sigma": st.growth_rate_1_s, "fd": st.damped_frequency_hz, "mech": st.mechanism or "decays",
        })  # fmt: skip
    mode_table = table(
        rows,
        [
            ("mode", "mode"),
            ("f", "f (Hz)"),
            ("mass", "lateral modal mass (kg)"),
            ("fd", "frequency with contact (Hz)"),
            ("sigma", "growth rate (1/s)"),
            ("mech", "mechanism"),
        ],  # fmt: skip
    )
    o = a.verdict.outcome
    sound = o.sound.summary() if o is not None and o.sound is not None else None
    levels = ""
    if sound is not None:
        levels = _pairs(
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
                ),  # fmt: skip
                (
                    "harmonics radiated",
                    f"{len(sound['harmonics'])}, holding {sound['velocity_energy_share']:.2%} "
                    "of the contact velocity's energy",
                ),  # fmt: skip
                ("radiation efficiency", f"{sound['radiation_efficiency']:.3g}"),
            ]
        )
    listen = (
        _section(
            "Listen",
            audio(folder / "squeal.wav"),
            '<p class="muted">the microphone\'s pressure over the simulated run (growth and limit cycle), '
            "peak-normalised: its true level is above</p>",
        )
        if (folder / "squeal.wav").is_file()
        else ""
    )
    body = [
        _verdict_block(verdict_lines(a.verdict), a.verdict.squeals),
        _section("How loud", levels) if levels else "",
        listen,
        _section("Which mode squeals", mode_table, image(folder / "growth.png", "growth rate of every mode")),
        _together(folder, a),
        _remedy(folder, a),
        _limit_cycle(folder),
        _section(
            "Spectra and band levels", image(folder / "spectrum.png", "spectra and one-third-octave bands")
        ),
        _section(
            "Sound field and directivity", image(folder / "sound_field.png", "near field and far field")
        ),
        _section("The squeal mode", *(image(p, p.stem) for p in sorted(folder.glob("mode_*.png")))),
        _section("Inputs", _pairs(inputs), '<p class="muted">versions</p>', _pairs(versions())),
        _section("Assumptions and limits", _assumptions()),
        _section("Files", _files(folder)),
    ]
    return _write(folder, _page(f"Squeal of {d.name}", "wheel-squeal run", body))


def compare_report(folder: Path, rows: Sequence[dict], analyses: Sequence[Analysis]) -> Path:
    """The report of ``compare``: one verdict per design."""
    verdicts = "".join(
        f"<h3>{_e(a.design.name)}</h3>" + _verdict_block(verdict_lines(a.verdict), a.verdict.squeals)
        for a in analyses
    )
    columns = [("design", "design"), ("rolling_speed_m_s", "V0 (m/s)"), ("rpm", "speed (rev/min)"),
               ("crabbing_velocity_m_s", "Vc (m/s)"), ("verdict_mode", "verdict"), ("tone_hz", "tone (Hz)"),
               ("growth_rate_1_s", "growth (1/s)"), ("amplitude_m_s", "amplitude (m/s)"),
               ("sound_power_level_db", "L_W (dB re 1 pW)"), ("sound_power_level_dba", "L_W (dB(A))"),
               ("spl_1m_db", "SPL 1 m (dB re 20 uPa)"),
               ("spl_7_5m_db", "SPL 7.5 m (dB re 20 uPa)")]  # fmt: skip
    a0 = analyses[0]
    body = [
        _section("Verdicts", verdicts),
        _section("Side by side", table(rows, columns), image(folder / "compare.png", "designs compared")),
        _section(
            "Inputs",
            _pairs(
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
            _pairs(versions()),
        ),  # fmt: skip
        _section("Assumptions and limits", _assumptions()),
        _section("Files", _files(folder)),
    ]
    return _write(folder, _page("Designs compared", "wheel-squeal compare", body))


def listing_report(
    folder: Path,
    title: str,
    subtitle: str,
    summary_lines: Sequence[str],
    inputs: Sequence[tuple[str, object]],
    sections: Sequence[tuple[str, str]] = (),
    assumptions: Sequence[str] = ASSUMPTIONS,
) -> Path:
    """A report of summary lines, further sections (title, HTML), every plot in
    ``folder``, the inputs, the ``assumptions`` it rests on and the files."""
    body = [
        _section("Summary", "<ul>" + "".join(f"<li>{_e(x)}</li>" for x in summary_lines) + "</ul>"),
        *(_section(t, part) for t, part in sections),
        _section("Plots", *(image(p, p.stem) for p in sorted(folder.glob("*.png")))),
        _section("Inputs", _pairs(list(inputs)), _pairs(versions())),
        _section("Assumptions and limits", _assumptions(assumptions)),
        _section("Files", _files(folder)),
    ]
    return _write(folder, _page(title, subtitle, body))


def study_report(
    folder: Path, name: str, summary_lines: Sequence[str], inputs: Sequence[tuple[str, object]]
) -> Path:
    """The report of ``study``: its summary and every plot in ``folder``."""
    return listing_report(folder, f"Study {name}", "wheel-squeal study", summary_lines, inputs)
