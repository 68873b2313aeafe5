"""The field's commands held to the promises of the others: a curve map priced as a whole
and refused at once when it cannot fit, curves and track values that mean nothing refused
before any work, and what a run writes outside its result folder."""

from __future__ import annotations

import os

import pytest
from conftest import DESIGNS, TABLE1_MODE_ARGS, one_line_error, run_here

TRACK = (DESIGNS / "railway_920_track.toml").read_text()
CURVE = ["curve", "--design", "railway_920_track", "--quiet"]


def _refused(args, tmp_path, word: str) -> str:
    """One line naming ``word``, exit 2, nothing written (how fast: benchmarks/bench_safety.py;
    a refusal that enumerated the 1e12 cases would not come back at all)."""
    out = tmp_path / "out"
    r = run_here(*args, "--out", out)
    assert r.returncode == 2, (r.returncode, r.stderr)
    line = one_line_error(r)
    assert word.lower() in line.lower(), line
    assert not out.exists()
    return line


@pytest.mark.parametrize(
    ("radii", "speeds"),
    [("100:2000:1000", "10:120:100"), ("100:1000000:1000000", "10:120:1000000")],
    ids=["1e5 curves", "1e12 curves"],
)
def test_a_curve_map_far_beyond_the_budget_is_refused_at_once_with_its_estimate(tmp_path, radii, speeds):
    line = _refused([*CURVE, "--radius", radii, "--train-speed", speeds], tmp_path, "would take")
    assert "contacts' stability" in line and "fewer radii or train speeds" in line
    assert "--no-remedy" not in line  # a flag the curve command does not have


@pytest.mark.parametrize(
    ("radius", "speed", "word"),
    [
        ("1", "40", "angle of attack"),
        ("1e-9", "40", "angle of attack"),
        ("5", "40", "R >= 50 m"),
        ("300", "1000", "400 km/h"),
        ("100", "80", "unbalanced lateral acceleration"),
    ],
)
def test_curves_that_mean_nothing_are_refused_before_any_work(tmp_path, radius, speed, word):
    _refused([*CURVE, "--radius", radius, "--train-speed", speed], tmp_path, word)


@pytest.mark.parametrize(
    ("old", "new", "word"),
    [
        ('rail = "UIC60"', 'rail = "UIC99"', "UIC99"),
        ("sleeper_spacing = 0.6", "sleeper_spacing = 100", "sleeper_spacing"),
        ("sleeper_spacing = 0.6", "sleeper_spacing = 1e-6", "sleeper_spacing"),
        ("pad_stiffness_vertical = 300.0e6", "pad_stiffness_vertical = 3e20", "pad_stiffness_vertical"),
    ],
)
def test_absurd_track_values_are_refused_by_name(tmp_path, old, new, word):
    assert old in TRACK
    design = tmp_path / "track.toml"
    design.write_text(TRACK.replace(old, new))
    _refused(["track", "--design", design], tmp_path, word)


@pytest.mark.parametrize("value", ["10", "1e300", "0", "-0.3", "nan"])
def test_a_friction_coefficient_outside_its_range_is_refused(tmp_path, value):
    _refused(["run", "--design", "table1", "--friction", value], tmp_path, "friction")


def test_a_damping_key_unknown_lists_the_keys_it_takes(tmp_path):
    design = tmp_path / "d.toml"
    design.write_text('name = "x"\n[squeal.damping]\nbogus = 0.01\n')
    # refused once the modes are known (the keys name them)
    line = _refused(["run", "--design", design, "--quiet"], tmp_path, "bogus")
    assert '"n=N,c=C"' in line and '"n>=2"' in line


@pytest.mark.slow  # two runs of the squeal model in this process (about 2 s)
def test_an_out_naming_a_link_keeps_the_link_and_replaces_its_target(tmp_path):
    target = tmp_path / "target"
    link = tmp_path / "link"
    args = ["simulate", *TABLE1_MODE_ARGS, "--rpm", "800", "--crab-velocity", "0.39", "--duration", "0.1"]
    args.append("--quiet")
    assert run_here(*args, "--out", target).returncode == 0
    (target / "summary.json").write_text("{}")  # changed, to see it replaced
    link.symlink_to(target)
    r = run_here(*args, "--out", link)
    assert r.returncode == 0, r.stderr
    assert link.is_symlink() and os.readlink(link) == str(target)
    assert (target / "summary.json").read_text() != "{}"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link", "target"]


def test_numba_keeps_its_compiled_code_in_the_cache(tmp_path, monkeypatch):
    """Set before numba is imported (a fresh process), unless the user set it."""
    import subprocess
    import sys

    from conftest import ROOT

    code = (
        f"import sys, os; sys.path.insert(0, {str(ROOT)!r})\n"
        "from wheel_squeal.runtime.stage_cache import StageCache\n"
        "from wheel_squeal.runtime.library_folders import keep_library_files\n"
        f"keep_library_files(StageCache({str(tmp_path / 'cache')!r}))\n"
        "import numba; print(os.environ.get('NUMBA_CACHE_DIR'), numba.config.CACHE_DIR)\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=60)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == [str(tmp_path / "cache" / "libraries" / "numba")] * 2
    env["NUMBA_CACHE_DIR"] = str(tmp_path / "mine")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=60)
    assert out.stdout.split() == [str(tmp_path / "mine")] * 2
