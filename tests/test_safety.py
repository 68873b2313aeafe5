"""A user's files are never destroyed and nothing runs away.

Every case below was found by probing the command line with bad and extreme input; each
is checked through the CLI where it is a CLI behaviour. The invariants: nothing outside
``--out`` and the cache is modified by a bad run (a snapshot of a sandbox before and
after); an earlier result survives a kill at any point of a rerun; a read-only cache
still gives results; runaway requests are refused in one line within 2 s.
"""

from __future__ import annotations

import errno
import json
import math
import multiprocessing as mp
import os
import resource
import signal
import time
from pathlib import Path

import numpy as np
import pytest
from conftest import DESIGNS, ROOT, TABLE1_MODE_ARGS, one_line_error, run_cli, snapshot
from hypothesis import HealthCheck, example, given, settings, strategies as st

import wheel_squeal as ws
import wheel_squeal.runtime.result_folders as folders
from geometry import WheelDesign
from geometry.wheel_design import SECTIONS
from wheel_squeal.design import FIELDS
from wheel_squeal.fe_stages import check_modes_budget
from wheel_squeal.runtime.budget import Budget
from wheel_squeal.runtime.request_errors import BudgetError, RequestError
from wheel_squeal.runtime.result_folders import MARKER, ResultFolder, result_folder
from wheel_squeal.runtime.stage_cache import LIBRARIES_FOLDER, MARKER as CACHE_MARKER, StageCache

FORK = mp.get_context("fork")


def write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


# --------------------------------------------------------------------------------------
# a bad run changes nothing outside --out and the cache
# --------------------------------------------------------------------------------------
def _bad_runs(box: Path) -> list[tuple[list[str], dict, str]]:
    """(arguments, environment, a word of the expected message)."""
    d = box / "designs"
    return [
        (["run", "--design", write(d / "e.toml", 'name = ""\n')], {}, "name"),
        (["run", "--design", write(d / "up.toml", 'name = "../designs"\n')], {}, "name"),
        (["run", "--design", write(d / "out.toml", 'name = "../../x"\n')], {}, "name"),
        (["run", "--design", write(d / "dots.toml", 'name = ".."\n')], {}, "name"),
        (["modes", "--fidelity", "fast", "--out", "results"], {}, "not a result"),
        (["modes", "--fidelity", "fast", "--out", "."], {}, "current folder"),
        (["modes", "--fidelity", "fast", "--out", "designs"], {}, "not a result"),
        (["cache", "clear", "--cache-dir", "."], {}, "not a wheel-squeal cache"),
        (["cache", "clear"], {"WHEEL_SQUEAL_CACHE": str(box)}, "not a wheel-squeal cache"),
        (["modes", "--out", "r", "--cache-dir", "designs/mine.toml"], {}, "not a folder"),
        (["modes", "--out", "r", "--cache-dir", "designs"], {}, "not a wheel-squeal cache"),
        (["modes", "--out", "/proc/x"], {}, "cannot be written"),
        (
            ["sweep", *TABLE1_MODE_ARGS, "--out", "/sys/x"],
            {},
            "cannot be written",
        ),
        (
            ["calibrate", "--free", "rim_depth", "--target-frequency", "1143", "--out", "/proc/x.toml"],
            {},
            "cannot be written",
        ),
        (
            ["calibrate", "--free", "rim_depth", "--target-frequency", "1143", "--out", "designs/mine.toml"],
            {},
            "not a design written by calibrate",
        ),
        (["run", "--mode", "f=inf", "--out", "r"], {}, "positive frequency"),
        (["run", "--mode", "f=nan", "--out", "r"], {}, "positive frequency"),
        (["run", "--mode", "f=-5", "--out", "r"], {}, "positive frequency"),
        (
            [
                "simulate",
                *TABLE1_MODE_ARGS,
                "--duration",
                "1000",
                "--out",
                "r",
            ],
            {},
            "at most",
        ),
    ]


@pytest.mark.slow
def test_bad_runs_change_nothing_outside_out_and_cache(sandbox, tmp_path):
    cache = tmp_path / "cache"
    for args, env, needle in _bad_runs(sandbox):
        args = [str(a) for a in args]
        if args[0] != "cache":
            args.append("--quiet")
        if args[0] in ("run", "modes", "simulate", "sweep") and "--cache-dir" not in args:
            args += ["--cache-dir", str(cache)]
        before = snapshot(sandbox)
        r = run_cli(*args, cwd=sandbox, env=env)
        msg = f"{args}: rc={r.returncode} stderr={r.stderr!r}"
        assert r.returncode == 2, msg
        assert needle.lower() in one_line_error(r).lower(), msg
        assert snapshot(sandbox) == before, f"{args} changed the sandbox"
        assert not (tmp_path / "x").exists(), msg


@pytest.mark.slow
def test_empty_cache_variable_is_unset_and_never_the_working_folder(sandbox):
    r = run_cli(
        "cache",
        "info",
        cwd=sandbox,
        env={"WHEEL_SQUEAL_CACHE": "", "XDG_CACHE_HOME": str(sandbox.parent / "xdg")},
    )
    assert r.returncode == 0, r.stderr
    assert str(sandbox.parent / "xdg" / "wheel-squeal") in r.stdout
    before = snapshot(sandbox)
    r = run_cli(
        "cache",
        "clear",
        cwd=sandbox,
        env={"WHEEL_SQUEAL_CACHE": "", "XDG_CACHE_HOME": str(sandbox.parent / "xdg")},
    )
    assert r.returncode == 0 and snapshot(sandbox) == before


def test_result_folders_are_replaced_only_when_they_are_results(tmp_path):
    out = tmp_path / "res"
    with result_folder(out, "test") as tmp:
        (tmp / "a.txt").write_text("first")
    assert (out / MARKER).is_file() and (out / "a.txt").read_text() == "first"
    with result_folder(out, "test") as tmp:
        (tmp / "b.txt").write_text("second")
    assert not (out / "a.txt").exists() and (out / "b.txt").read_text() == "second"
    # an empty folder may take a result; a folder with other files may not
    empty = tmp_path / "empty"
    empty.mkdir()
    with result_folder(empty, "test") as tmp:
        (tmp / "c.txt").write_text("x")
    assert (empty / "c.txt").exists()
    theirs = tmp_path / "theirs"
    theirs.mkdir()
    (theirs / "thesis.tex").write_text("years of work")
    with pytest.raises(RequestError, match="not a result"):
        with result_folder(theirs, "test"):
            pass
    assert (theirs / "thesis.tex").read_text() == "years of work"
    # the folder's mode follows the user's umask (not mkdtemp's 0700)
    old = os.umask(0o022)
    try:
        with result_folder(tmp_path / "umask", "test"):
            pass
    finally:
        os.umask(old)
    assert (tmp_path / "umask").stat().st_mode & 0o777 == 0o755
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []


# --------------------------------------------------------------------------------------
# kills and concurrent writers
# --------------------------------------------------------------------------------------
_STEPS = ("_rename_new", "_exchange", "_remove")


def _write_killed(out: Path, kill_at: int, exchange: bool) -> None:
    """Child: write a new result to ``out``, SIGKILLing itself at the ``kill_at``-th step
    (before and after each rename / exchange / removal); exit 0 if it got through."""
    if not exchange:
        folders._RENAMEAT2 = None
    events = [0]
    for name in _STEPS:
        real = getattr(folders, name)

        def step(*a, _real=real):
            if events[0] == kill_at:
                os.kill(os.getpid(), signal.SIGKILL)
            events[0] += 1
            result = _real(*a)
            if events[0] == kill_at:
                os.kill(os.getpid(), signal.SIGKILL)
            events[0] += 1
            return result

        setattr(folders, name, step)
    folder = ResultFolder(out)
    folder.open()
    for i in range(20):
        (folder.staging / f"part{i}.txt").write_text("new")
    if kill_at == -1:
        os.kill(os.getpid(), signal.SIGKILL)  # killed while computing
    folder.publish("test")
    os._exit(0)


@pytest.mark.parametrize("exchange", [True, False], ids=["renameat2", "two-renames"])
def test_previous_result_survives_a_kill_at_any_point(tmp_path, exchange):
    out = tmp_path / "res"
    kill_at, completed = -1, False
    while not completed:
        with result_folder(out, "test") as tmp:
            (tmp / "old.txt").write_text("old")
        p = FORK.Process(target=_write_killed, args=(out, kill_at, exchange))
        p.start()
        p.join(60)
        completed = p.exitcode == 0
        assert completed or p.exitcode == -signal.SIGKILL
        # the next run tidies up (and, without renameat2, puts the old result back) ...
        folder = ResultFolder(out)
        folder.open()
        folder.discard()
        # ... and then the result is complete: the old one, or the new one whole
        names = sorted(f.name for f in out.iterdir())
        if completed:
            assert names == sorted([MARKER] + [f"part{i}.txt" for i in range(20)])
        else:
            assert names in ([MARKER, "old.txt"], sorted([MARKER] + [f"part{i}.txt" for i in range(20)]))
        hidden = [p.name for p in tmp_path.iterdir() if p.name.startswith(".")]
        assert hidden == [], (kill_at, hidden)
        kill_at += 1
    assert kill_at >= 3


@pytest.mark.slow
def test_a_killed_command_leaves_no_process_behind(tmp_path):
    # the plot process (and its drawing children) end with the command: an orphan would
    # hold the caller's pipes open and a script reading them would wait forever
    import subprocess
    import sys

    pipe = [sys.executable, str(ROOT / "pipeline.py"), "simulate", *TABLE1_MODE_ARGS]
    for delay in (0.2, 0.6):  # while the plot process imports; while it draws
        p = subprocess.Popen(
            [*pipe, "--out", str(tmp_path / f"sim{delay}")], stdout=subprocess.PIPE, stderr=subprocess.PIPE
        )
        time.sleep(delay)
        p.send_signal(signal.SIGKILL)
        p.communicate(timeout=20)  # EOF: every holder of the pipes has gone (else TimeoutExpired)
    # a refused request does not wait for the plot process, which then ends by itself
    refused = [*pipe[:2], "run", "--design", str(tmp_path / "missing.toml"), "--out", str(tmp_path / "r")]
    p = subprocess.Popen(refused, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    _, err = p.communicate(timeout=20)
    assert p.returncode == 2 and "not found" in err


def _publish_together(out: Path, barrier, tag: str) -> None:
    folder = ResultFolder(out)
    folder.open()
    for i in range(50):
        (folder.staging / f"{tag}{i}.txt").write_text(tag)
    barrier.wait()
    folder.publish("test")
    os._exit(0)


def test_two_writers_to_one_out_both_finish(tmp_path):
    for round_ in range(5):
        out = tmp_path / f"res{round_}"
        if round_ % 2:  # with and without an earlier result in place
            with result_folder(out, "test") as tmp:
                (tmp / "old.txt").write_text("old")
        barrier = FORK.Barrier(2)
        procs = [FORK.Process(target=_publish_together, args=(out, barrier, t)) for t in "ab"]
        for p in procs:
            p.start()
        for p in procs:
            p.join(60)
        assert [p.exitcode for p in procs] == [0, 0]
        names = {f.name for f in out.iterdir()} - {MARKER}
        assert names in ({f"a{i}.txt" for i in range(50)}, {f"b{i}.txt" for i in range(50)})
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []


# --------------------------------------------------------------------------------------
# the cache
# --------------------------------------------------------------------------------------
@pytest.mark.slow
def test_cache_touches_only_its_own_entries(tmp_path):
    root = tmp_path / "cache"
    cache = StageCache(root)
    cache.store("modes", {"k": 1}, {"a": np.arange(3.0)})
    assert (root / CACHE_MARKER).is_file()
    # user files inside the cache folder, even one named like an entry, stay
    (root / "notes.txt").write_text("mine")
    (root / "modes" / ("0" * 32 + ".npz")).write_bytes(_plain_npz())
    assert StageCache(root).clear() == 1
    assert (root / "notes.txt").exists() and (root / "modes" / ("0" * 32 + ".npz")).exists()
    # a folder that is not a cache is refused, for use and for clearing
    user = tmp_path / "user"
    user.mkdir()
    (user / "x.npz").write_bytes(_plain_npz())
    with pytest.raises(RequestError, match="not a wheel-squeal cache"):
        StageCache(user)
    r = run_cli("cache", "clear", "--cache-dir", user)
    assert r.returncode == 2 and (user / "x.npz").exists()


def test_cache_of_a_concurrent_run_before_its_first_store_is_accepted(tmp_path):
    """Two workers sharing a new cache: the first's numba writes its machine code into
    ``compiled`` before its first store writes the marker; the second must not take the
    folder for a user's."""
    root = tmp_path / "cache"
    (root / LIBRARIES_FOLDER / "numba").mkdir(parents=True)
    StageCache(root).store("modes", {"k": 1}, {"a": np.arange(3.0)})
    assert (root / CACHE_MARKER).is_file()


def _plain_npz() -> bytes:
    import io

    buf = io.BytesIO()
    np.savez(buf, a=np.ones(2))
    return buf.getvalue()


def test_read_only_cache_still_gives_results(tmp_path, monkeypatch, capsys):
    root = tmp_path / "cache"
    design = WheelDesign()
    warm = StageCache(root)
    ws.compute_modes(design, "fast", cache=warm)  # fills mesh and modes
    import geometry.files

    def read_only(*a, **k):
        raise OSError(errno.EROFS, "Read-only file system")

    monkeypatch.setattr(geometry.files.tempfile, "mkstemp", read_only)
    cache = StageCache(root)
    ms = ws.compute_modes(design, "fast", cache=cache)  # a hit
    assert cache.hits == ["modes"]
    other = ws.compute_modes(design, "balanced", cache=cache)  # misses: warn once, go on
    assert other.modes and ms.modes
    err = capsys.readouterr().err
    assert err.count("cannot be written") == 1
    assert not cache.writable


def test_cache_entry_taken_by_a_folder_is_recomputed(tmp_path, capsys):
    cache = StageCache(tmp_path / "cache")
    key = {"k": 2}
    cache.path("modes", key).mkdir(parents=True)
    with pytest.raises(ws.CacheMiss):
        cache.load("modes", key)
    cache.store("modes", key, {"a": np.zeros(1)})  # cannot replace a folder: warned, not raised
    err = capsys.readouterr().err
    assert "corrupt" in err and "cannot be written" in err


# --------------------------------------------------------------------------------------
# runaway requests
# --------------------------------------------------------------------------------------
RUNAWAY = [
    ("[wheel]\nbore_radius = 1e-6\n", "shorter than any part"),
    ("[wheel]\nweb_thickness = 1e-4\n", "memory"),
    ("[wheel]\nweb_thickness = 5e-4\n", "DOFs"),
    ("[wheel]\nrolling_radius = 213\nrim_depth = 33.5\n", "millimetres"),
    ("[material]\nyoungs_modulus = 175\n", "GPa"),
    ("[material]\nyoungs_modulus = 175e3\n", "MPa"),
    ("[material]\nyoungs_modulus = 1e300\n", "youngs_modulus"),
    ("[material]\nyoungs_modulus = 1e-300\n", "youngs_modulus"),
    ("[material]\ndensity = 7.8\n", "g/cm^3"),
]


@pytest.mark.slow
@pytest.mark.parametrize("text,needle", RUNAWAY, ids=[t.split("\n")[1] for t, _ in RUNAWAY])
def test_runaway_designs_are_refused_at_once(tmp_path, text, needle):
    design = write(tmp_path / "d.toml", text)
    t = time.perf_counter()
    r = run_cli(
        "run", "--design", design, "--out", tmp_path / "out", "--quiet", "--cache-dir", tmp_path / "c"
    )
    elapsed = time.perf_counter() - t
    assert r.returncode == 2, r.stderr
    assert needle in one_line_error(r)
    assert elapsed < 2.0 + _startup_allowance()
    assert not (tmp_path / "out").exists() and not (tmp_path / "c").exists()


def _startup_allowance() -> float:
    """A loaded CI machine starts Python slowly: allow what an empty run costs here."""
    t = time.perf_counter()
    run_cli("--help")
    return max(0.0, time.perf_counter() - t - 0.5)


@pytest.mark.slow
def test_unbounded_sweeps_are_refused(tmp_path):
    base = ["sweep", *TABLE1_MODE_ARGS, "--quiet"]
    r = run_cli(*base, "--crab-velocity", "0:1:1000000000", "--out", tmp_path / "a")
    assert r.returncode == 2 and "points" in one_line_error(r)
    r = run_cli(*base, "--crab-velocity", "0:1:1000000", "--out", tmp_path / "b")
    assert r.returncode == 2 and "--max-seconds" in one_line_error(r)
    # the limit can be lifted (here lowered: the same sweep that runs by default is refused)
    r = run_cli(
        *base,
        *"--crab-velocity 0:0.4:3 --rpm 800 --duration 0.5 --max-seconds 0.001".split(),
        "--out",
        tmp_path / "c",
    )
    assert r.returncode == 2 and "limit" in one_line_error(r)
    assert not any((tmp_path / x).exists() for x in "abc")


@pytest.mark.slow
def test_the_dof_limit_is_a_setting(tmp_path):
    r = run_cli(
        *"modes --fidelity fast --max-dofs 100 --quiet".split(),
        "--out",
        tmp_path / "m",
        "--cache-dir",
        tmp_path / "c",
    )
    assert r.returncode == 2 and "--max-dofs" in one_line_error(r)
    r = run_cli(
        "modes",
        "--fidelity",
        "fast",
        "--out",
        tmp_path / "m",
        "--quiet",
        "--cache-dir",
        tmp_path / "c",
        env={"WHEEL_SQUEAL_MAX_DOFS": "100"},
    )
    assert r.returncode == 2 and "limit 100 DOFs" in one_line_error(r)
    with pytest.raises(BudgetError):
        ws.compute_modes(WheelDesign(), "fast", budget=Budget(max_dofs=100))


_MEASURE = """
import json, sys
import fem.axisym, fem.cyclic
import wheel_squeal as ws

def peak():  # VmHWM: the peak resident set of this process (ru_maxrss survives exec)
    for line in open("/proc/self/status"):
        if line.startswith("VmHWM:"):
            return float(line.split()[1]) * 1024

fidelity, solver = sys.argv[1], (sys.argv[2] or None)
r0 = peak()
ms = ws.compute_modes(ws.load_design(), fidelity, solver=solver)
print(json.dumps([ms.dofs, peak() - r0]))
"""


@pytest.mark.slow
@pytest.mark.parametrize(
    "fidelity,solver",
    [("fast", None), ("balanced", None), ("accurate", None), ("fast", "3d"), ("balanced", "3d")],
)
def test_estimate_is_within_2x_of_measured_dofs_and_memory(fidelity, solver):
    """The budget's estimate against the solve measured in a fresh process (its peak
    resident memory above what the imports took)."""
    import subprocess
    import sys

    fid = ws.fidelity_for(fidelity, solver)
    cost = check_modes_budget(WheelDesign(), fid, 5000.0, Budget())
    r = subprocess.run(
        [sys.executable, "-c", _MEASURE, fidelity, solver or ""],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=ROOT,
    )
    assert r.returncode == 0, r.stderr
    dofs, memory = json.loads(r.stdout.splitlines()[-1])
    assert 0.5 <= cost.dofs / dofs <= 2.0, (cost.dofs, dofs)
    assert 0.5 <= cost.memory_bytes / memory <= 2.0, (cost.memory_bytes / 1e6, memory / 1e6)


# --------------------------------------------------------------------------------------
# messages a user can act on
# --------------------------------------------------------------------------------------
@pytest.mark.slow
def test_compare_names_the_design_that_failed(tmp_path):
    bad = write(
        tmp_path / "nothree.toml",
        (DESIGNS / "thin_web.toml").read_text().replace('name = "thin_web"', 'name = "nothree"'),
    )
    r = run_cli(
        "compare",
        DESIGNS / "table1.toml",
        bad,
        "--fidelity",
        "fast",
        "--fmax",
        "600",
        "--out",
        tmp_path / "cmp",
        "--quiet",
        "--cache-dir",
        tmp_path / "c",
    )
    assert r.returncode == 2 and one_line_error(r).startswith("error: design ")


@pytest.mark.slow
def test_plot_windows_stay_inside_the_record(tmp_path):
    """A very soft mode (0.0036 Hz): the Fig. 7-10 windows are clamped to the record."""
    out = tmp_path / "soft"
    r = run_cli(
        *"simulate --mass 3.1 --stiffness 1e-3 --damping 0 --duration 0.5 --quiet".split(), "--out", out
    )
    assert r.returncode == 0, r.stderr
    names = [p.name for p in out.glob("force_velocity_*.png")]
    times = [float(n.removeprefix("force_velocity_").removesuffix("s.png")) for n in names]
    assert times and all(0.0 <= t <= 0.5 for t in times)


@pytest.mark.slow
def test_empty_design_file_says_it_is_the_default(tmp_path):
    empty = tmp_path / "empty.toml"
    empty.write_text("")
    r = run_cli(
        "modes",
        "--design",
        empty,
        "--fidelity",
        "fast",
        "--out",
        tmp_path / "m",
        "--cache-dir",
        tmp_path / "c",
        "--quiet",
    )
    assert r.returncode == 0, r.stderr
    assert "default Table 1 wheel" in r.stderr
    s = json.loads((tmp_path / "m" / "summary.json").read_text())
    ref = ws.compute_modes(WheelDesign(), "fast")
    assert [m["frequency_hz"] for m in s["modes"]] == pytest.approx([m.frequency_hz for m in ref.modes])


# --------------------------------------------------------------------------------------
# any design near Table 1: a result or one line, never a traceback, under a memory cap
# --------------------------------------------------------------------------------------
_DEFAULT = ws.Design()
_NUMERIC = {
    k: _DEFAULT.get(k)
    for k in FIELDS
    if _DEFAULT.get(k) not in (0.0, None)  # the optional shape keys are absent
}
_MEMORY_CAP = 4 << 30


def _cap_memory() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (_MEMORY_CAP, _MEMORY_CAP))


def _toml(values: dict) -> str:
    """A design file of every numeric field, ``values`` replacing the defaults."""
    sections: dict[str, list[str]] = {}
    for k, v in {**_NUMERIC, **values}.items():
        part, attr = FIELDS[k]
        section = next(s for s, keys in SECTIONS.items() if k in keys) if part == "wheel" else part
        sections.setdefault(section, []).append(f"{attr} = {v!r}")
    return 'name = "probe"\n' + "".join(f"[{s}]\n" + "\n".join(lines) + "\n" for s, lines in sections.items())


_DECADE = st.dictionaries(st.sampled_from(sorted(_NUMERIC)), st.floats(-1.0, 1.0), min_size=1, max_size=6)


def _design_error(path: Path) -> str | None:
    """The one-line refusal of a design file in-process (None: a valid design)."""
    import wheel_squeal as ws
    from geometry import DesignError

    try:
        ws.load_design(path)
    except DesignError as exc:
        return str(exc)
    return None


@settings(
    max_examples=200,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(_DECADE)
def test_designs_within_a_decade_of_table1_load_or_name_their_problem(tmp_path, exponents):
    values = {k: _NUMERIC[k] * 10.0**e for k, e in exponents.items()}
    problem = _design_error(write(tmp_path / "probe.toml", _toml(values)))
    if problem is not None:
        assert "\n" not in problem and any(FIELDS[k][1] in problem for k in _NUMERIC), problem


@pytest.mark.slow
@settings(
    max_examples=6,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)
@given(_DECADE)
@example({"poissons_ratio": 1.0})  # invalid: the refusal is the in-process one
def test_designs_within_a_decade_of_table1_end_in_a_result_or_one_line(tmp_path, exponents):
    """A valid design within a decade of Table 1 gives a verdict (exit 0), or, when none
    of its modes is below fmax or its estimate is beyond the test's 30 s, says so in one
    line (exit 2); an invalid one is refused with the
    in-process message (exit 2). A refusal writes nothing; no run fails (exit 1)."""
    values = {k: _NUMERIC[k] * 10.0**e for k, e in exponents.items()}
    design = write(tmp_path / "probe.toml", _toml(values))
    problem = _design_error(design)
    out = tmp_path / "out"
    r = run_cli(
        "run",
        "--design",
        design,
        "--fidelity",
        "fast",
        "--render",
        "none",
        "--fmax",
        "3000",
        "--out",
        out,
        "--quiet",
        "--no-cache",
        preexec_fn=_cap_memory,
        env={"WHEEL_SQUEAL_MAX_SECONDS": "30"},
        timeout=300,
    )
    msg = f"{values}: rc={r.returncode} {r.stderr[-2000:]}"
    if problem is None and r.returncode == 2 and "would take about" in r.stderr:
        # valid, but beyond the 30 s this test allows (a large wheel has hundreds of modes)
        assert "--max-seconds" in one_line_error(r) and not out.exists(), msg
    elif problem is None and r.returncode == 2:  # valid, but its first mode is above fmax
        assert one_line_error(r).startswith("error: no mode below fmax"), msg
        assert "the lowest is" in r.stderr and not out.exists(), msg
    elif problem is None:
        assert r.returncode == 0, msg
        verdict = json.loads((out / "summary.json").read_text())["verdict"]
        assert isinstance(verdict["squeals"], bool) and verdict["reason"], msg
    else:
        assert r.returncode == 2, msg
        assert one_line_error(r) == f"error: {problem}", msg
        assert not out.exists(), msg
    if out.exists():
        import shutil

        shutil.rmtree(out)


@pytest.mark.slow
def test_default_run_writes_into_results_of_the_working_folder(sandbox, tmp_path):
    before = snapshot(sandbox / "results" / "keep")
    r = run_cli(
        "run", "--fidelity", "fast", "--render", "none", "--quiet", "--cache-dir", tmp_path / "c", cwd=sandbox
    )
    assert r.returncode == 0, r.stderr
    assert (sandbox / "results" / "run" / "table1" / "summary.json").is_file()  # results/COMMAND/NAME
    assert snapshot(sandbox / "results" / "keep") == before
    assert math.isfinite(
        json.loads((sandbox / "results" / "run" / "table1" / "summary.json").read_text())["limit_cycle"][
            "velocity_amplitude_m_s"
        ]
    )


# --------------------------------------------------------------------------------------
# a stop signal at the commit and at the WAV's write
# --------------------------------------------------------------------------------------
def _run_stopped_at(target: str, args: list[str]) -> tuple[int, str]:
    """The command line in a fresh process whose ``target`` (module:function) sends it
    SIGTERM as it is entered: (exit status, stderr)."""
    import subprocess
    import sys

    module, name = target.split(":")
    code = (
        f"import os, signal, sys; sys.path.insert(0, {str(ROOT)!r}); import {module} as m\n"
        f"real = m.{name}\n"
        f"def stopped(*a, **k):\n"
        f"    os.kill(os.getpid(), signal.SIGTERM)\n"
        f"    return real(*a, **k)\n"
        f"m.{name} = stopped\n"
        f"sys.argv = ['pipeline.py', *{[str(a) for a in args]!r}]\n"
        f"import pipeline; pipeline.run(prog='pipeline.py')\n"
    )
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    return p.returncode, p.stderr


@pytest.mark.slow  # two commands (about 2 s each)
def test_a_stop_at_the_commit_ends_nothing(tmp_path):
    """A SIGTERM as the earlier result is being removed (the new one already in place):
    the command completes, exit 0, the new result whole and nothing left beside --out."""
    out = tmp_path / "sim"
    args = ["simulate", *TABLE1_MODE_ARGS, "--rpm", "800", "--crab-velocity", "0.39", "--duration", "0.2"]
    first = run_cli(*args, "--quiet", "--out", out)
    assert first.returncode == 0, first.stderr
    before = json.loads((out / "summary.json").read_text())
    status, err = _run_stopped_at(
        "wheel_squeal.runtime.result_folders:_remove", [*args, "--quiet", "--out", out]
    )
    assert status == 0 and "Traceback" not in err, err
    after = json.loads((out / "summary.json").read_text())
    assert after.keys() == before.keys() and (out / "timeseries.csv").stat().st_size > 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sim"]


@pytest.mark.slow  # one run of the Table 1 wheel from the cache (about 8 s)
def test_a_stop_at_the_wav_write_is_one_line_and_keeps_the_earlier_result(tmp_path):
    out = tmp_path / "run"
    with result_folder(out, "test") as tmp:
        (tmp / "old.txt").write_text("old")
    status, err = _run_stopped_at(
        "wheel_squeal.present.vtu_and_wav:write_wav", ["run", "--design", "table1", "--quiet", "--out", out]
    )
    lines = [ln for ln in err.splitlines() if ln.strip() and not ln.startswith("warning:")]
    assert status == 143 and lines == ["terminated"], err
    assert sorted(p.name for p in out.iterdir()) == sorted([MARKER, "old.txt"])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run"]
