"""One answer to "which mode squeals, at what tone, how loud": the same verdict from
every command and the Python API, for a design that names its squeal mode (table1), one
that names none (thin_web) and one where nothing grows (table1 heavily damped); rotation
naming the stable override; "still growing" marked everywhere; one command grammar."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest
from conftest import DESIGNS, ROOT, run_cli

import wheel_squeal as ws
from geometry import DesignError

#: The Fig. 6 point, the fast preset (every command below runs with these).
POINT = ("--rpm", "800", "--crab-velocity", "0.39")
FAST = ("--fidelity", "fast")


def _damped(folder: Path) -> Path:
    """Table 1 with 5 % damping in every mode: nothing grows at the Fig. 6 point."""
    path = folder / "damped.toml"
    path.write_text('name = "damped"\n[damping]\nmodal_damping_ratio = 0.05\n')
    return path


def _csv(path: Path) -> list[dict]:
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def _num(text: str) -> float | None:
    return float(text) if text not in ("", None) else None


def _outcome(row: dict, tone: str | None = None) -> dict:
    """The verdict's mode, tone, level and state from a CSV row (``tone``: from another file)."""
    return {
        "mode": row["verdict_mode"] or None,
        "tone_hz": _num(row["tone_hz"] if tone is None else tone),
        "spl_db": _num(row["spl_db"]),
        "saturated": row["saturated"] == "True",
    }


@pytest.fixture(scope="module")
def cases(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("verdicts")
    return {
        "table1": DESIGNS / "table1.toml",
        "thin_web": DESIGNS / "thin_web.toml",
        "damped": _damped(tmp),
    }, tmp


@pytest.mark.slow
@pytest.mark.parametrize("name", ["table1", "thin_web", "damped"])
def test_every_command_gives_the_same_verdict(cases, name):
    """run, stability, compare, sweep (at that point), a one-design study and the API:
    the same mode, tone (0.1 Hz) and level (0.05 dB: the sweep's fixed 1.5 s run against
    the run's own length changes the amplitude's last digits)."""
    paths, tmp = cases
    design = paths[name]
    cache = ("--cache-dir", tmp / "cache")
    base = tmp / name
    api = ws.analyse(
        ws.load_design(design),
        rpm=800,
        crabbing_velocity_m_s=0.39,
        fidelity="fast",
        cache=ws.StageCache(tmp / "cache"),
    )
    want = api.verdict.to_dict()
    expected_mode = {"table1": "(3,0) axial", "thin_web": "(1,0) axial", "damped": None}[name]
    assert want["mode"] == expected_mode and want["squeals"] == (expected_mode is not None)

    got = {}
    r = run_cli(
        "run", "--design", design, *FAST, *POINT, "--render", "none", "--out", base / "run", "--quiet", *cache
    )
    assert r.returncode == 0, r.stderr
    got["run"] = json.loads((base / "run" / "summary.json").read_text())["verdict"]
    r = run_cli(
        "stability", "--design", design, *FAST, *POINT, "--no-bounds", "--out", base / "st", "--quiet", *cache
    )
    assert r.returncode == 0, r.stderr
    got["stability"] = json.loads((base / "st" / "summary.json").read_text())["verdict"]
    last = r.stdout.splitlines()[-4:-1]  # the verdict, why and what would stop it, before the folder
    assert (
        last[0].startswith("VERDICT:") and last[1].startswith("  why:") and last[2].startswith("  remedy:")
    ) or ("no squeal" in r.stdout.splitlines()[-2])
    r = run_cli("compare", design, *FAST, *POINT, "--out", base / "cmp", "--quiet", *cache)
    assert r.returncode == 0, r.stderr
    row = _csv(base / "cmp" / "compare.csv")[0]
    got["compare"] = _outcome(row)
    r = run_cli(
        "sweep",
        "--design",
        design,
        *FAST,
        "--sound",
        "--crab-velocity",
        "0.39",
        "--rpm",
        "800",
        "--out",
        base / "sw",
        "--quiet",
        *cache,
    )
    assert r.returncode == 0, r.stderr
    row = _csv(base / "sw" / "sweep_spl.csv")[0]
    tone = _csv(base / "sw" / "sweep.csv")[0]["tone_hz"]
    got["sweep"] = _outcome(row, tone)
    spec = base / "one.toml"
    field = "web_thickness"
    value = ws.load_design(design).wheel.web_thickness
    spec.write_text(
        f'base = "{design}"\nfidelity = "fast"\n[grid]\n{field} = [{value!r}]\n'
        "[operating]\ncrab_velocity = [0.39]\nrpm = [800]\n"
    )
    r = run_cli("study", spec, "--workers", "1", "--out", base / "study", "--quiet", *cache)
    assert r.returncode == 0, r.stderr
    row = _csv(base / "study" / "study.csv")[0]
    got["study"] = _outcome(row)
    for where, v in got.items():
        assert v["mode"] == want["mode"], where
        if where == "stability":  # it stops before the time domain: the linear verdict
            continue
        assert v["saturated"] == want["saturated"], where
        if want["mode"] is None:
            # no squeal, no level; a tone, where a command gives one, the run's
            assert v["spl_db"] is None, where
            assert (
                v["tone_hz"] is None
                or want["tone_hz"] is None
                or (v["tone_hz"] == pytest.approx(want["tone_hz"], abs=0.1))
            ), where
            continue
        assert v["tone_hz"] == pytest.approx(want["tone_hz"], abs=0.1), where
        assert v["spl_db"] == pytest.approx(want["spl_db"], abs=0.05), where


def test_no_squeal_says_how_far_it_is(cases):
    paths, tmp = cases
    a = ws.analyse(ws.load_design(paths["damped"]), fidelity="fast", cache=ws.StageCache(tmp / "cache"))
    v = a.verdict
    assert not v.squeals and v.margin is not None
    m = v.margin
    assert m["growth_rate_1_s"] < 0 and 0 < m["grows_below_damping_ratio"] < m["damping_ratio"]
    # the margin is true: just below the damping bound that mode grows (the others at 5 %)
    design = ws.load_design(paths["damped"])
    least = a.modeset.modes[m["mode_index"]]
    key = f"n={least.nodal_diameters},c={least.nodal_circles}"
    lower = design.replace(mode_damping=((key, 0.97 * m["grows_below_damping_ratio"]),))
    assert ws.analyse(lower, fidelity="fast", stop_after="stability", modes=a.modeset).verdict.squeals
    assert "least stable" in v.reason and "would grow" in v.reason


@pytest.mark.slow
def test_rotation_squeals_in_a_growing_mode_and_names_the_stable_override(tmp_path):
    """On a turning wheel the named (3,0) mode is stable at the Fig. 6 point; the
    verdict is the model's pick, with its tone (the wave a fixed microphone hears) and
    level, and (3,0) beside it as the stable override: never "no squeal"."""
    r = run_cli(
        "run",
        "--rotation",
        *FAST,
        "--render",
        "none",
        "--out",
        tmp_path / "o",
        "--quiet",
        "--cache-dir",
        tmp_path / "c",
    )
    assert r.returncode == 0, r.stderr
    v = json.loads((tmp_path / "o" / "summary.json").read_text())["verdict"]
    assert v["squeals"] and v["mode"] != "(3,0) axial" and v["growth_rate_1_s"] > 0
    assert v["spl_db"] > 80 and v["wave"] in ("backward", "forward") and v["tone_hz"] > 0
    assert v["override"]["mode"] == "(3,0) axial" and v["override"]["growth_rate_1_s"] < 0
    assert "does not squeal here" in v["reason"]
    assert "VERDICT: squeals in" in r.stdout and "no sound" not in r.stdout


@pytest.mark.slow
def test_unsaturated_sweep_points_are_marked_and_drawn_hollow_unjoined(tmp_path):
    """Near the stability boundary 0.2 s runs do not saturate: each such point says
    saturated=False in sweep.csv and sweep_spl.csv, and the drawing joins only limit
    cycles (the plotted data, not the pixels)."""
    from wheel_squeal.present.figures import curve

    r = run_cli(
        "sweep",
        *FAST,
        "--sound",
        "--crab-velocity",
        "0.1,0.3,0.45,0.5",
        "--rpm",
        "400,800",
        "--duration",
        "0.25",
        "--out",
        tmp_path / "sw",
        "--quiet",
        "--cache-dir",
        tmp_path / "c",
    )
    assert r.returncode == 0, r.stderr
    for name in ("sweep.csv", "sweep_spl.csv"):
        rows = _csv(tmp_path / "sw" / name)
        growing = [row for row in rows if row["squeals"] == "True" and row["saturated"] == "False"]
        assert growing and all("saturated" in row for row in rows), name
    assert "* still growing" in r.stdout
    design = ws.load_design()
    grid = ws.sweep_verdicts(
        design,
        [0.1, 0.3, 0.45, 0.5],
        [400, 800],
        0.25,
        modeset=ws.compute_modes(design, "fast"),
    )
    assert (grid.squeals & ~grid.saturated).any()
    for j in range(2):
        x, line, hollow = curve(grid, grid.amplitude_m_s, j)
        assert np.all(np.isnan(line[hollow]))  # never on the line
        assert np.all(np.isnan(line[~grid.saturated[:, j]]))
        assert np.all(np.isfinite(line[grid.saturated[:, j] & grid.squeals[:, j]]))


@pytest.mark.slow
def test_sound_states_its_velocity_and_compare_its_levels(tmp_path):
    r = run_cli("sound", *FAST, "--out", tmp_path / "s", "--quiet", "--cache-dir", tmp_path / "c")
    assert r.returncode == 0 and "contact velocity 1 m/s" in r.stdout
    r = run_cli(
        "compare",
        DESIGNS / "table1.toml",
        DESIGNS / "thin_web.toml",
        *FAST,
        "--out",
        tmp_path / "cmp",
        "--quiet",
        "--cache-dir",
        tmp_path / "c",
    )
    assert r.returncode == 0, r.stderr
    rows = _csv(tmp_path / "cmp" / "compare.csv")
    assert {
        "verdict_mode",
        "tone_hz",
        "spl_db",
        "sound_power_level_db",
        "saturated",
        "reason",
        "model_pick",
        "override_mode",
    } <= set(rows[0])
    assert all(_num(row["spl_db"]) > 80 for row in rows)
    assert "why:" in r.stdout


@pytest.mark.slow
def test_a_shipped_design_by_name_from_any_folder(tmp_path):
    r = run_cli(
        "modes",
        "--design",
        "thin_web",
        *FAST,
        "--out",
        tmp_path / "m",
        "--quiet",
        cwd=tmp_path,
        env={"WHEEL_SQUEAL_CACHE": str(tmp_path / "c")},
    )
    assert r.returncode == 0, r.stderr
    assert json.loads((tmp_path / "m" / "summary.json").read_text())["design"] == "thin_web"
    r = run_cli("designs", cwd=tmp_path)
    assert r.returncode == 0 and "thin_web" in r.stdout and "railway_920" in r.stdout
    r = run_cli("modes", "--design", "no_such_wheel", "--out", tmp_path / "x", cwd=tmp_path)
    assert r.returncode == 2 and "shipped design" in r.stderr


@pytest.mark.slow
def test_one_grammar(tmp_path):
    """--out optional everywhere (results/COMMAND/NAME), --speed wherever --rpm is, an
    unknown option points to the subcommand's help, the API's own error for bad designs."""
    r = run_cli(
        "stability",
        *FAST,
        "--no-bounds",
        "--speed",
        "17.84",
        "--quiet",
        cwd=tmp_path,
        env={"WHEEL_SQUEAL_CACHE": str(tmp_path / "c")},
    )
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "results" / "stability" / "table1" / "summary.json").is_file()
    r = run_cli(
        "sweep",
        "--mass",
        "3.1",
        "--stiffness",
        "1.6e8",
        "--damping",
        "42",
        "--speed",
        "8.9,17.8",
        "--crab-velocity",
        "0.3",
        "--duration",
        "0.6",
        "--quiet",
        cwd=tmp_path,
    )
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "results" / "sweep" / "table1" / "sweep.csv").is_file()
    r = run_cli("run", "--bogus")
    assert r.returncode == 2 and "run --help" in r.stderr
    with pytest.raises(DesignError):  # one error type for a design file's every mistake
        ws.load_design(ROOT / "tests" / "conftest.py")
