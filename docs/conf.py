"""Sphinx configuration. The command-line and output-field references are generated
here, at build time, from the argparse parser and from ``wheel_squeal.fields``: they
cannot drift from the code."""

from __future__ import annotations

import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))

project = "wheel-squeal"
author = "the wheel-squeal developers"
copyright = "2026, the wheel-squeal developers"

extensions = [
    "myst_nb",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    # MathJax 3 copied into the site (_static/mathjax): the math renders offline, with no
    # script fetched from a CDN
    "sphinx-mathjax-offline",
]
myst_enable_extensions = ["dollarmath", "amsmath"]
myst_heading_anchors = 3
source_suffix = {".md": "myst-nb"}
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store", "jupyter_execute"]
html_theme = "alabaster"
html_static_path: list[str] = []
html_theme_options = {"description": "railway wheel squeal, from design to dB"}
nb_execution_mode = "force"
nb_execution_timeout = 600
nb_execution_raise_on_error = True
autodoc_typehints = "description"
autodoc_member_order = "bysource"
napoleon_numpy_docstring = True
suppress_warnings = ["myst.header"]


def _cli_reference() -> str:
    from wheel_squeal.cli.parser import build_parser

    parser = build_parser("wheel-squeal")
    out = [
        "# Command line",
        "",
        "Generated from the argparse parser at build time. `python pipeline.py COMMAND` in the",
        "repository and `wheel-squeal COMMAND` anywhere are the same program.",
        "",
        "```text",
        parser.format_help().rstrip(),
        "```",
        "",
    ]
    for name, sub in parser.subcommands.items():
        out += [f"## {name}", "", "```text", sub.format_help().rstrip(), "```", ""]
    return "\n".join(out)


def _outputs_reference() -> str:
    from wheel_squeal.fields import FIELDS, FREE_GROUPS, GROUPS
    from wheel_squeal.output_files import FILES

    def row(key: str) -> str:
        f = FIELDS[key]
        return f"| `{key}` | {f.unit or '(none)'} | {f.description} |"

    out = [
        "# Output files and fields",
        "",
        "Generated from `wheel_squeal/fields.py` at build time; a test fails when a command",
        'writes a field that is not documented there. A unit "-" marks labels, flags and',
        "text; an empty cell or `null` means no value (a NaN).",
        "",
    ]
    for name, spec in FILES.items():
        out += [
            f"## {name}",
            "",
            f"Written by: {', '.join(f'`{c}`' for c in spec.commands)}. {spec.description}.",
            "",
        ]
        if spec.fields:
            out += ["| column | unit | meaning |", "|---|---|---|", *(row(k) for k in spec.fields), ""]
    out += [
        "## summary.json",
        "",
        "Every command's `summary.json` holds these objects (each command the ones it computes):",
        "",
        "| object | holds |",
        "|---|---|",
        *(f"| `{k}` | {v} |" for k, v in {**GROUPS, **FREE_GROUPS}.items()),
        "",
        "and these fields, in any of them:",
        "",
        "| field | unit | meaning |",
        "|---|---|---|",
        *(row(k) for k in FIELDS),
        "",
    ]
    return "\n".join(out)


def _generate(app) -> None:
    for name, text in (("cli.md", _cli_reference()), ("outputs.md", _outputs_reference())):
        path = DOCS / "reference" / name
        if not path.exists() or path.read_text() != text:
            path.write_text(text)


def setup(app):
    app.connect("builder-inited", _generate)
