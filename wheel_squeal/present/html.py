"""``report.html``: one self-contained page per result folder to send to a colleague: the
inputs, the verdict and its reason, the tables and the figures, the squeal to listen to,
the assumptions and the files. Here: the page's parts and the reports that list a folder's
summary and plots (``study``, ``curve``, ``line``); ``run``'s and ``compare``'s are
:mod:`.run_report`'s.

The page needs nothing but itself: its images and its sound are embedded as data URIs,
its style is inline, and it loads nothing from the network, so it opens from a mail
attachment. It is written last, from the files already in the folder.
"""

from __future__ import annotations

import base64
import datetime as _dt
import html
import importlib.metadata
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from geometry.files import write_atomic

from ..runtime.provenance import CODE_PACKAGES, code_version

if TYPE_CHECKING:
    pass

__all__ = [
    "ASSUMPTIONS",
    "REPORT_NAME",
    "assumption_list",
    "audio",
    "escape",
    "file_list",
    "image",
    "listing_report",
    "page",
    "pairs",
    "section",
    "study_report",
    "table",
    "verdict_block",
    "versions",
    "write_report",
]

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
def escape(x: object) -> str:
    return html.escape(str(x))


def image(path: Path, alt: str) -> str:
    """An embedded PNG (empty where the file is not there)."""
    if not path.is_file():
        return ""
    data = base64.b64encode(path.read_bytes()).decode()
    return f'<img src="data:image/png;base64,{data}" alt="{escape(alt)}">'


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
    return escape(x)


def table(rows: Sequence[dict], columns: Sequence[tuple[str, str]]) -> str:
    """An HTML table of ``rows`` with ``columns`` as (key, heading)."""
    head = "".join(
        f'<th class="text">{escape(h)}</th>' if i == 0 else f"<th>{escape(h)}</th>"
        for i, (_, h) in enumerate(columns)
    )
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


def pairs(items: Sequence[tuple[str, object]]) -> str:
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


def file_list(folder: Path) -> str:
    names = sorted(p.name for p in folder.iterdir() if p.is_file() and not p.name.startswith("."))
    return "<ul>" + "".join(f"<li><code>{escape(n)}</code></li>" for n in names + [REPORT_NAME]) + "</ul>"


def page(title: str, subtitle: str, body: list[str]) -> str:
    when = _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC")
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        f"<title>{escape(title)}</title><style>{_STYLE}</style></head><body>"
        f'<h1>{escape(title)}</h1><p class="muted">{escape(subtitle)}; written {when}</p>'
        + "".join(body)
        + "</body></html>\n"
    )


def section(title: str, *parts: str) -> str:
    return f"<h2>{escape(title)}</h2>" + "".join(p for p in parts if p)


def verdict_block(lines: Sequence[str], squeals: bool) -> str:
    return (
        f'<div id="verdict" class="verdict{"" if squeals else " quiet"}">'
        + "<br>".join(escape(x) for x in lines)
        + "</div>"
    )


def assumption_list(assumptions: Sequence[str] = ASSUMPTIONS) -> str:
    return "<ul>" + "".join(f"<li>{escape(a)}</li>" for a in assumptions) + "</ul>"


def write_report(folder: Path, text: str) -> Path:
    return write_atomic(folder / REPORT_NAME, text)


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
        section("Summary", "<ul>" + "".join(f"<li>{escape(x)}</li>" for x in summary_lines) + "</ul>"),
        *(section(t, part) for t, part in sections),
        section("Plots", *(image(p, p.stem) for p in sorted(folder.glob("*.png")))),
        section("Inputs", pairs(list(inputs)), pairs(versions())),
        section("Assumptions and limits", assumption_list(assumptions)),
        section("Files", file_list(folder)),
    ]
    return write_report(folder, page(title, subtitle, body))


def study_report(
    folder: Path, name: str, summary_lines: Sequence[str], inputs: Sequence[tuple[str, object]]
) -> Path:
    """The report of ``study``: its summary and every plot in ``folder``."""
    return listing_report(folder, f"Study {name}", "wheel-squeal study", summary_lines, inputs)
