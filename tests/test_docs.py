"""The documentation cannot drift: every command is in the command table, every field a
command writes is in ``wheel_squeal.fields`` (which the reference is generated from), the
repository carries its own theory, and the README stays a README."""

from __future__ import annotations

import argparse
import csv
import json
import re
import subprocess
from pathlib import Path

import pytest
from conftest import ROOT, run_cli

from wheel_squeal.cli.parser import build_parser
from wheel_squeal.fields import FIELDS, FREE_GROUPS, GROUPS
from wheel_squeal.output_files import FILES

#: the README's size limit [characters]: a README, not a manual
README_MAX_CHARS = 10_000


def _tracked_files() -> list[Path]:
    out = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True).stdout
    return [ROOT / p for p in out.splitlines() if p]


def test_nothing_points_outside_the_repository():
    """The theory and the reference values live in docs/: no file names the folder the
    project was started from."""
    outside = "../" + "shared"  # spelled in two parts so that this file does not match itself
    hits = []
    for p in _tracked_files():
        if p.suffix in {".py", ".md", ".toml", ".txt", ".cfg", ".csv", ""} and p.is_file():
            text = p.read_text(errors="replace")
            if outside in text or "MODEL" + ".md" in text:
                hits.append(str(p.relative_to(ROOT)))
    assert not hits, hits


def test_the_readme_is_short_and_links_into_the_docs():
    text = (ROOT / "README.md").read_text()
    assert len(text) <= README_MAX_CHARS, len(text)
    for page in (
        "docs/getting-started.md",
        "docs/theory.md",
        "docs/guide/which-mode.md",
        "docs/validation.md",
    ):
        assert f"({page})" in text, page
        assert (ROOT / page).is_file(), page


def test_every_command_is_in_the_command_table():
    """The README's table (which docs/commands.md includes) has a row per command, and
    nothing else; the command-line reference is generated from the same parser."""
    table = re.findall(r"^\| `([a-z-]+)` \|", (ROOT / "README.md").read_text(), re.M)
    assert sorted(table) == sorted(build_parser().subcommands)


def test_every_page_is_in_the_table_of_contents():
    docs = ROOT / "docs"
    pages = {str(p.relative_to(docs).with_suffix("")) for p in docs.rglob("*.md") if "_build" not in p.parts}
    listed = set()
    for index in docs.rglob("index.md"):
        if "_build" in index.parts:
            continue
        base = index.parent.relative_to(docs)
        for entry in re.findall(r"```\{toctree\}(.*?)```", index.read_text(), re.S):
            for line in entry.splitlines():
                line = line.strip()
                if line and not line.startswith(":"):
                    listed.add(str(base / line) if str(base) != "." else line)
    generated = {"reference/cli", "reference/outputs"}
    assert pages - {"index"} - generated <= listed, sorted(pages - {"index"} - generated - listed)


# -- the output fields ------------------------------------------------------------------------
def _json_keys(x, parent: str, leaves: set[str], groups: set[str], listed: bool = False) -> None:
    if isinstance(x, dict):
        if parent in FREE_GROUPS and not listed:  # keyed by names (a list of records is a group)
            keyed = {"verdicts": "verdict", "operating_points": "operating_point"}
            if parent in keyed:  # keyed by design: each a verdict or an operating point
                for v in x.values():
                    _json_keys(v, keyed[parent], leaves, groups)
            return
        for k, v in x.items():
            records = isinstance(v, list) and (bool(v) and isinstance(v[0], dict) or (not v and k in GROUPS))
            if isinstance(v, dict) or records:
                groups.add(k)
            _json_keys(v, k, leaves, groups)
    elif isinstance(x, list) and x and isinstance(x[0], dict):
        for item in x:
            _json_keys(item, parent, leaves, groups, listed=True)
    elif not (isinstance(x, list) and not x and parent in GROUPS):  # an empty list of records: a group
        leaves.add(parent)


@pytest.fixture(scope="module")
def written(tmp_path_factory) -> dict[str, Path]:
    """One folder per command, each run as a user would (fast preset, no pictures)."""
    root = tmp_path_factory.mktemp("fields")
    cache = ("--cache-dir", str(root / "cache"))
    fast = ("--fidelity", "fast", "--quiet", *cache)
    measured = root / "measured.csv"
    measured.write_text("crab_velocity,rpm,spl_db,frequency_hz\n0.35,800,126.0,1140\n")
    runs = {
        "run": ("run", *fast, "--render", "none", "--multimode", "2"),
        "stability": (
            "stability",
            *fast,
            "--envelope",
            "--envelope-crab-velocity",
            "0.2,0.4",
            "--envelope-rpm",
            "400,800",
        ),
        "sweep": (
            "sweep",
            *fast,
            "--sound",
            "--crab-velocity",
            "0.3,0.4",
            "--rpm",
            "800",
            "--measured",
            str(measured),
        ),
        "compare": ("compare", "table1", "thin_web", *fast),
        "sound": ("sound", *fast),
        "modes": ("modes", *fast),
        "mesh": ("mesh", "--quiet"),
        "simulate": ("simulate", "--quiet", "--mass", "3.1", "--stiffness", "1.6e8", "--damping", "42"),
        "study": ("study", str(ROOT / "studies" / "smoke.toml"), "--quiet", *cache),
        "track": ("track", "--design", "railway_920_track", "--points", "20", "--quiet"),
        "curve": ("curve", "--design", "railway_920_track", "--radius", "150", "--train-speed", "40", *fast),
    }
    out = {}
    for name, args in runs.items():
        folder = root / name
        r = run_cli(*args, "--out", folder)
        assert r.returncode == 0, (name, r.stderr)
        out[name] = folder
    return out


@pytest.mark.slow
def test_every_field_written_is_documented_and_every_documented_field_is_written(written):
    leaves: set[str] = set()
    groups: set[str] = set()
    for folder in written.values():
        summary = folder / "summary.json"
        if summary.is_file():
            _json_keys(json.loads(summary.read_text()), "", leaves, groups)
    columns: set[str] = set()
    for name, spec in FILES.items():
        if not spec.fields:
            continue
        paths = sorted(p for folder in written.values() for p in folder.glob(name))
        assert paths, f"no command of the test wrote {name}"
        for p in paths:
            with open(p, newline="") as f:
                rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
            header = rows[0]
            if name == "study.csv":  # design axes first and design_<field> last: named by the study
                header = [h for h in header if h in spec.fields]
            assert header == list(spec.fields), (name, header)
            columns |= set(header)
    assert leaves <= set(FIELDS), sorted(leaves - set(FIELDS))
    assert groups <= set(GROUPS) | set(FREE_GROUPS), sorted(groups - set(GROUPS) - set(FREE_GROUPS))
    # written only where the fixture's runs do not go: a verdict on a track (the rail's
    # effect and motion), a remedy of a mode-coupled pair (its separation): test_track and
    # test_remedy write and check them
    motion = {"contact_velocity_rms_m_s", "counter_body_energy_share", "counter_body_power_w"}
    motion |= {"counter_body_velocity_rms_m_s", "counter_body_velocity_share"}
    elsewhere = {"counter_body_effect_1_s", "frequency_hz_now", "partner"} | motion
    documented_unwritten = set(FIELDS) - leaves - columns - {"rim_depth", "web_thickness"} - elsewhere
    assert not documented_unwritten, sorted(documented_unwritten)
    assert not set(GROUPS) - groups - {"counter_body_motion"}, sorted(set(GROUPS) - groups)


def test_the_generated_references_cover_every_command_and_field():
    import importlib.util

    spec = importlib.util.spec_from_file_location("docs_conf", ROOT / "docs" / "conf.py")
    assert spec and spec.loader
    conf = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(conf)
    cli = conf._cli_reference()
    parser = build_parser()
    for name, sub in parser.subcommands.items():
        assert f"## {name}" in cli
        for action in sub._actions:
            if action.help == argparse.SUPPRESS:  # a retired flag, refused with its reason
                continue
            for flag in action.option_strings:
                assert flag in cli, (name, flag)
    outputs = conf._outputs_reference()
    for key in FIELDS:
        assert f"`{key}`" in outputs, key


@pytest.mark.slow
def test_the_python_guide_runs(tmp_path, monkeypatch):
    """Every ``python`` block of the Python API guide runs as written (one namespace, in
    order, in a scratch folder), so that the guide cannot drift from the API."""
    text = (ROOT / "docs" / "guide" / "python-api.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert len(blocks) >= 2
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("HOME", str(tmp_path))  # the guide's cache folder lands here
    namespace: dict = {}
    for block in blocks:
        exec(compile(block, "python-api.md", "exec"), namespace)  # noqa: S102
    assert namespace["grid"].squeals.shape == (3, 2)


def _documented_files() -> dict[str, tuple[set[str], set[str]]]:
    """Per command of the README's table: (every file its "writes" cell names, those it
    names outside parentheses: written every time)."""
    out = {}
    for command, cell in re.findall(
        r"^\| `([a-z-]+)` \|[^|]*\| ([^|]*) \|$", (ROOT / "README.md").read_text(), re.M
    ):
        always = re.sub(r"\([^)]*\)", "", cell)
        out[command] = (set(re.findall(r"`([^`]+)`", cell)), set(re.findall(r"`([^`]+)`", always)))
    return out


@pytest.mark.slow
def test_every_command_writes_the_files_the_table_lists(written):
    """The files each command wrote (in the fixture's runs: a squeal, --envelope, --sound,
    --measured) are named by the README's table (patterns like ``*.png`` allowed), and
    each file the table names outside parentheses was written."""
    import fnmatch

    documented = _documented_files()
    for command, folder in written.items():
        names = {p.name for p in folder.iterdir() if p.is_file() and not p.name.startswith(".")}
        every, always = documented[command]
        unlisted = {n for n in names if not any(fnmatch.fnmatch(n, pattern) for pattern in every)}
        assert not unlisted, (command, sorted(unlisted))
        missing = {pattern for pattern in always if not any(fnmatch.fnmatch(n, pattern) for n in names)}
        assert not missing, (command, sorted(missing))


def test_the_docs_render_math_without_the_network():
    """The site bundles MathJax (the extension that copies it into _static), listed in the
    docs extra; .ci/run checks the built pages load no script from the network."""
    conf = (ROOT / "docs" / "conf.py").read_text()
    assert '"sphinx-mathjax-offline"' in conf and "mathjax_path" not in conf
    assert "sphinx-mathjax-offline" in (ROOT / "pyproject.toml").read_text()
    assert 'src="(https?:)?//' in (ROOT / ".ci" / "run").read_text()


def test_the_benchmark_results_are_tables_the_scripts_wrote():
    """benchmarks/RESULTS.md is headings, each section's command and the tables it printed
    (benchmarks/record.py writes them): no prose, whose history belongs to git; and the
    recorder puts a script's output in its own section and nowhere else."""
    import sys

    sys.path.insert(0, str(ROOT / "benchmarks"))
    from record import replaced_section

    text = (ROOT / "benchmarks" / "RESULTS.md").read_text()
    fenced = False
    for number, line in enumerate(text.splitlines()[7:], start=8):  # past the page's opening
        if line.startswith("```"):
            fenced = not fenced
        elif not fenced:
            assert line == "" or line.startswith(("#", "Run: `", "|")), (number, line)
    page = (
        "# R\n\n## A (`benchmarks/a.py`)\n\nRun: `x`\n\n```\nold\n```\n\n## B (`benchmarks/b.py`)\n\nkept\n"
    )
    new = replaced_section(page, "a.py", "python benchmarks/a.py", "new table\n")
    assert (
        "new table" in new
        and "old" not in new
        and "in a block" not in new
        and new.endswith("## B (`benchmarks/b.py`)\n\nkept\n")
    )
