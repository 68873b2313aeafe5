"""Safety on a shared, busy machine: names that never become paths, a time budget that
holds for the whole request, stop signals that are one line whenever they land, a full
disk, implausible numbers, silence reported as silence, and oscillations never called
quiet. Each class of the probe that found them has a test here; the ones that start the
command line in a subprocess are marked slow."""

from __future__ import annotations

import errno
import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from conftest import PIPELINE, ROOT, one_line_error, run_cli

from wheel_squeal.cli import main


def _write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


# --------------------------------------------------------------------------------------
# a name is never a path; a result is never inside another
# --------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["", "..", "../../etc/x", "/tmp/abs", "a/b", ".hidden", "-x", "é"])
def test_a_study_name_that_is_not_a_label_is_refused(tmp_path, name):
    from wheel_squeal.runtime.request_errors import RequestError
    from wheel_squeal.study.spec import load_spec

    spec = (ROOT / "studies" / "smoke.toml").read_text()
    spec = spec.replace('name = "smoke"', f"name = {json.dumps(name)}")
    spec = spec.replace('base = "../designs/table1.toml"', f'base = "{ROOT / "designs" / "table1.toml"}"')
    with pytest.raises(RequestError, match="not a usable name"):
        load_spec(_write(tmp_path / "s.toml", spec))


def test_no_result_folder_is_made_inside_another(tmp_path):
    from wheel_squeal.runtime.request_errors import RequestError
    from wheel_squeal.runtime.result_folders import ResultFolder, result_folder

    with result_folder(tmp_path / "outer", "run") as staging:
        (staging / "a.txt").write_text("x")
    with pytest.raises(RequestError, match="inside another result"):
        ResultFolder(tmp_path / "outer" / "inner").check()
    # a result that holds another (made by hand) is never replaced: it would go with it
    (tmp_path / "outer2" / "inner").mkdir(parents=True)
    for folder in (tmp_path / "outer2", tmp_path / "outer2" / "inner"):
        (folder / ".wheel-squeal-result").write_text("{}")
    with pytest.raises(RequestError, match="holds another result"):
        ResultFolder(tmp_path / "outer2").check()


# --------------------------------------------------------------------------------------
# the time budget: the whole request, estimated first, enforced while running
# --------------------------------------------------------------------------------------
def test_the_budget_counts_the_whole_request_and_stops_it_past_its_time():
    from wheel_squeal.runtime.budget import Budget
    from wheel_squeal.runtime.request_errors import BudgetError, BudgetExhausted

    spent = Budget(max_seconds=10.0, started_s=time.monotonic() - 8.0)
    spent.checkpoint("nothing")  # 2 s left: goes on
    with pytest.raises(BudgetError, match="2 s of it left|1.9 s of it left|2.0 s of it left"):
        spent.check_work("the next stage", 5.0, "ask for less")  # fits alone, not in what is left
    over = Budget(max_seconds=1.0, started_s=time.monotonic() - 1.5)
    with pytest.raises(BudgetExhausted, match="ran past its time budget"):
        over.checkpoint("the squeal model")


def test_small_dense_solves_run_on_one_blas_thread():
    """The stability's eigen-solves do not spread over the cores (several processes on
    a shared machine would fight for them); the model's estimate assumes one thread."""
    from threadpoolctl import threadpool_info

    from reduced._numerics import one_blas_thread

    with one_blas_thread():
        blas = [p for p in threadpool_info() if p["user_api"] == "blas"]
        assert blas and all(p["num_threads"] == 1 for p in blas)


def test_a_modal_model_too_large_for_the_budget_is_refused_before_any_eigen_solve(tmp_path, monkeypatch):
    """2,000 modes: the remedy's bounds alone would take hours; refused at once, naming
    them, without the 1-minute eigen-solve first; with --no-remedy the estimate fits."""
    import reduced.stability

    def boom(*a, **k):
        raise AssertionError("solved before refusing")

    monkeypatch.setattr(reduced.stability, "_eigen", boom)
    mode = "[[mode]]\nfrequency_hz = {}\ndamping_ratio = 0.001\nlateral = 0.5\nnormal = 0.0\nlabel = 'm{}'\n"
    text = "".join(mode.format(300 + 2 * i, i) for i in range(2000))
    model = _write(tmp_path / "mm.toml", text)
    import wheel_squeal as ws
    from fem.modal_model import load_modal_model
    from wheel_squeal.plan import stability_plan
    from wheel_squeal.runtime.budget import Budget
    from wheel_squeal.runtime.request_errors import BudgetError

    design = ws.load_design()
    modes = load_modal_model(model)
    contact = ws.contact_law(design)
    with pytest.raises(BudgetError, match="remedy or margin"):
        stability_plan(design, modes, contact, False, True).check(Budget(), "the request", "less")
    assert stability_plan(design, modes, contact, False, False).seconds < Budget().max_seconds


def test_a_modal_model_of_more_modes_than_it_takes_is_refused_on_reading(tmp_path):
    from fem.modal_model import MAX_MODES, load_modal_model
    from geometry import DesignError

    one = "[[mode]]\nfrequency_hz = 1000.0\ndamping_ratio = 0.001\nlateral = 0.5\nnormal = 0.0\n"
    with pytest.raises(DesignError, match="more than a modal model takes"):
        load_modal_model(_write(tmp_path / "m.toml", one * (MAX_MODES + 1)))


def test_a_modal_model_keeps_the_band(tmp_path):
    from fem.modal_model import load_modal_model
    from geometry import DesignError

    text = "".join(
        f"[[mode]]\nfrequency_hz = {f}\ndamping_ratio = 0.001\nlateral = 0.5\nnormal = 0.0\n"
        for f in (500.0, 1500.0, 6000.0)
    )
    path = _write(tmp_path / "m.toml", text)
    with pytest.warns(UserWarning, match="1 of 3 modes lie above fmax"):
        assert [m.frequency_hz for m in load_modal_model(path, 5000.0).modes] == [500.0, 1500.0]
    with pytest.raises(DesignError, match="no mode up to fmax"):
        load_modal_model(path, 100.0)


def test_a_never_started_study_over_budget_is_refused_before_its_cases_are_made(tmp_path, monkeypatch):
    from wheel_squeal.runtime.budget import Budget
    from wheel_squeal.runtime.request_errors import BudgetError
    from wheel_squeal.runtime.stage_cache import StageCache
    from wheel_squeal.study import runner
    from wheel_squeal.study.spec import StudySpec, load_spec

    spec_text = (ROOT / "studies" / "tolerance.toml").read_text()
    spec_text = spec_text.replace("n = 200", "n = 1000000")
    spec_text = spec_text.replace("../designs/table1.toml", str(ROOT / "designs" / "table1.toml"))
    spec = load_spec(_write(tmp_path / "big.toml", spec_text))

    def boom(self):
        raise AssertionError("made a million cases before refusing")

    monkeypatch.setattr(StudySpec, "cases", boom)
    with pytest.raises(BudgetError, match="1,000,000 designs"):
        runner.case_results(spec, workers=1, cache=StageCache(tmp_path / "c"), budget=Budget())


def test_a_cache_size_that_is_not_a_size_is_refused_before_any_work(tmp_path, monkeypatch, capsys):
    import wheel_squeal.fe_stages

    def boom(*a, **k):
        raise AssertionError("worked before checking the environment")

    monkeypatch.setattr(wheel_squeal.fe_stages, "compute_modes", boom)
    monkeypatch.setenv("WHEEL_SQUEAL_CACHE_SIZE", "abc")
    rc = main(["modes", "--cache-dir", str(tmp_path / "c"), "--out", str(tmp_path / "o"), "--quiet"])
    err = capsys.readouterr().err
    assert rc == 2 and "WHEEL_SQUEAL_CACHE_SIZE" in err and not (tmp_path / "o").exists()


@pytest.mark.slow
def test_modes_vtu_holds_the_drawn_modes_only_beyond_the_file_limit(tmp_path):
    import meshio

    import wheel_squeal as ws

    design = ws.load_design()
    fid = ws.fidelity_for("fast")
    modeset = ws.compute_modes(design, fid, fmax_hz=2000.0)
    from fem.render import modes_vtu_bytes

    limit = 0.5 * (modes_vtu_bytes(modeset) + modes_vtu_bytes(modeset, [2]))  # between one and all
    with pytest.warns(UserWarning, match="holds the modes drawn only"):
        files = ws.mode_views(design, fid, 2000.0, modeset, [2], None, max_file_bytes=limit)
    (tmp_path / "modes.vtu").write_bytes(files["modes.vtu"])
    names = set(meshio.read(tmp_path / "modes.vtu").point_data)
    assert names and all("mode_02" in n for n in names)


@pytest.mark.slow
def test_a_request_past_its_time_budget_ends_within_a_tenth_of_it(tmp_path):
    """The default run (no cache: mesh, modes, squeal model, sound, views) cannot finish
    in 2.5 s on this machine: it is refused up front (exit 2) or stopped when the budget
    runs out (exit 1), in one line, within 10 % of the budget, nothing written."""
    budget = 2.5
    t0 = time.perf_counter()
    r = run_cli(
        "run", "--no-cache", "--out", tmp_path / "o", "--quiet", env={"WHEEL_SQUEAL_MAX_SECONDS": str(budget)}
    )
    elapsed = time.perf_counter() - t0
    line = one_line_error(r)
    assert r.returncode in (1, 2) and ("budget" in line.lower() or "limit" in line.lower()), line
    assert elapsed < 1.1 * budget + 0.3, elapsed  # 0.3 s: starting the interpreter before the clock
    assert not (tmp_path / "o").exists() and not list(tmp_path.glob(".o.*"))


def test_a_stop_inside_a_long_native_computation_ends_within_the_grace(tmp_path):
    """SIGALRM (the budget) while LAPACK works for seconds: the watcher ends the process
    with the budget's line and exit 1, its staging folder removed."""
    code = f"""
import signal, sys, numpy as np
sys.path.insert(0, {str(ROOT)!r})
from wheel_squeal.cli.stops import install_stop_handlers, STATE, stop_line
from wheel_squeal.runtime.result_folders import ResultFolder
install_stop_handlers()
a = np.random.default_rng(0).standard_normal((3000, 3000))  # made before the clock starts
STATE.budget_s = 0.5
ResultFolder({str(tmp_path / "o")!r}).open()
signal.setitimer(signal.ITIMER_REAL, 0.5)
try:
    np.linalg.eig(a)  # seconds in LAPACK: the alarm lands there
except KeyboardInterrupt:  # (on a loaded machine it may land just before: main's path)
    print(stop_line(signal.SIGALRM, 0.5), file=sys.stderr)
    ResultFolder.discard_all()
    sys.exit(1)
print("finished")
"""
    t0 = time.perf_counter()
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    elapsed = time.perf_counter() - t0
    assert r.returncode == 1 and "finished" not in r.stdout, (r.returncode, r.stderr)
    assert one_line_error(r).startswith("error: the request ran past its time budget")
    assert elapsed < 5.0 and list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------------------
# stop signals to the process group, at any moment
# --------------------------------------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_a_stop_signal_to_the_group_is_one_line_whenever_it_lands(tmp_path, sig):
    """``timeout``, batch schedulers and Ctrl-C signal the whole process group (the plot
    process too), and the signal may land during the imports, gmsh, the eigen-solve, the
    squeal model or the drawing: each time one line, exit 143 or 130, the staging folder
    gone and the earlier result as it was."""
    cache = tmp_path / "cache"
    out = tmp_path / "out"
    base = [
        sys.executable,
        str(PIPELINE),
        "run",
        "--fidelity",
        "fast",
        "--quiet",
        "--out",
        str(out),
        "--cache-dir",
        str(cache),
    ]
    first = subprocess.run(base, capture_output=True, text=True, cwd=tmp_path, timeout=300)
    assert first.returncode == 0, first.stderr
    before = (out / "summary.json").read_bytes()
    expected = {signal.SIGTERM: (143, "terminated"), signal.SIGINT: (130, "interrupted")}[sig]
    for k, delay in enumerate((0.05, 0.4, 0.9, 1.4, 2.0)):
        cold = ["--no-cache"] if k % 2 else []  # gmsh and the FE run in every other one
        p = subprocess.Popen(
            base + cold,
            cwd=tmp_path,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            start_new_session=True,
        )
        time.sleep(delay)
        os.killpg(p.pid, sig)
        _, err = p.communicate(timeout=60)
        assert "Traceback" not in err, f"a stop {delay} s in printed (in full):\n{err}"
        if p.returncode == 0:  # done before the signal (a warm run reads its result from the cache)
            before = (out / "summary.json").read_bytes()
            continue
        lines = [ln for ln in err.splitlines() if ln.strip() and not ln.startswith("warning:")]
        assert (p.returncode, lines) == (expected[0], [expected[1]]), (delay, err)
        assert not list(tmp_path.glob(".out.*")), delay
        assert (out / "summary.json").read_bytes() == before, delay


# --------------------------------------------------------------------------------------
# a full disk
# --------------------------------------------------------------------------------------
def _small_filesystem(path: Path) -> bool:
    """A 2 MB tmpfs at ``path`` where this process may mount one (root on Linux)."""
    path.mkdir()
    if os.geteuid() != 0:
        return False
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=2m", "tmpfs", str(path)], capture_output=True)
    return r.returncode == 0


@pytest.mark.slow
def test_a_full_disk_is_one_line_and_the_earlier_result_stays(tmp_path):
    """On a real full file system where this machine lets the test mount one; elsewhere
    :func:`test_enospc_anywhere_is_one_line` injects the error instead."""
    disk = tmp_path / "disk"
    if not _small_filesystem(disk):
        pytest.skip("no tmpfs can be mounted here: the injected ENOSPC test covers the path")
    try:
        model = _one_mode(tmp_path)
        first = run_cli("stability", "--modal-model", model, "--out", disk / "r", "--quiet", cwd=disk)
        assert first.returncode == 0, first.stderr
        earlier = {p.name: p.read_bytes() for p in (disk / "r").iterdir()}
        stat = os.statvfs(disk)
        (disk / "filler").write_bytes(b"\0" * (stat.f_bavail * stat.f_frsize - 8192))  # 8 kB left
        for command in (["run"], ["stability"], ["sweep", "--crab-velocity", "0.1,0.3", "--rpm", "800"]):
            r = run_cli(*command, "--fidelity", "fast", "--out", disk / "r", "--quiet", cwd=disk)
            assert r.returncode == 1, (command, r.stderr)
            assert "No space left on device" in one_line_error(r)
            assert sorted(p.name for p in disk.iterdir()) == ["filler", "r"]
            assert {p.name: p.read_bytes() for p in (disk / "r").iterdir()} == earlier
    finally:
        subprocess.run(["umount", str(disk)], check=False)


def test_enospc_anywhere_is_one_line(tmp_path, monkeypatch, capsys):
    import wheel_squeal.cli.commands  # noqa: F401 (every command's module bound to the real
    import wheel_squeal.outputs as outputs  # writer first: one imported under the patch keeps the fake)

    (tmp_path / "o").mkdir()
    (tmp_path / "o" / ".wheel-squeal-result").write_text("{}")
    (tmp_path / "o" / "summary.json").write_text("earlier")

    def full(path, data):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))

    monkeypatch.setattr(outputs, "write_json", full)
    monkeypatch.setattr("wheel_squeal.cli.stability_command.write_json", full)
    rc = main(
        ["stability", "--modal-model", str(_one_mode(tmp_path)), "--out", str(tmp_path / "o"), "--quiet"]
    )
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 1 and len(err) == 1 and "No space left on device" in err[0]
    assert (tmp_path / "o" / "summary.json").read_text() == "earlier"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mm.toml", "o"]


def _one_mode(tmp_path: Path) -> Path:
    return _write(
        tmp_path / "mm.toml",
        "[[mode]]\nfrequency_hz = 1143.0\ndamping_ratio = 0.00094\nlateral = 0.568\nnormal = 0.0\n",
    )


# --------------------------------------------------------------------------------------
# finite but absurd numbers, control characters, measured files
# --------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("mode", "word"),
    [
        ("frequency_hz = 1e300\nlateral = 0.5", "outside the range of a wheel's modes"),
        ("frequency_hz = 1e-300\nlateral = 0.5", "outside the range of a wheel's modes"),
        ("frequency_hz = 1000.0\nlateral = 1e200", "modal mass"),
        ("frequency_hz = 1000.0\nlateral = 1e-300", "modal mass"),
        ('frequency_hz = 1000.0\nlateral = 0.5\nlabel = "\\u001b[2J"', "control characters"),
    ],
)
def test_absurd_modal_models_are_refused_on_reading(tmp_path, mode, word):
    from fem.modal_model import load_modal_model
    from geometry import DesignError

    text = f"[[mode]]\n{mode}\ndamping_ratio = 0.001\nnormal = 0.0\n"
    with pytest.raises(DesignError, match=word):
        load_modal_model(_write(tmp_path / "m.toml", text))


@pytest.mark.parametrize(
    ("table", "word"),
    [
        (
            {
                "roller": {
                    "lateral_frequency_hz": 3e3,
                    "lateral_damping_ratio": 0.01,
                    "lateral_modal_mass_kg": 1e300,
                }
            },
            "plausible range",
        ),
        ({"wheel": {"bore_radius": 5e-324}}, "shorter than any part of a wheel"),
        ({"contact": {"c22": 1e12}}, "Kalker"),
        ({"contact": {"transient_creep": True, "relaxation_length": 1e6}}, "contact length"),
        ({"description": "a\u001b[2Jb"}, "control characters"),
    ],
)
def test_absurd_design_values_are_refused_on_reading(table, word):
    from geometry import DesignError
    from wheel_squeal.design import Design
    from wheel_squeal.runtime.request_errors import RequestError

    with pytest.raises((RequestError, DesignError), match=word):
        Design.from_mapping({"name": "x", **table})


def test_cli_angles_are_degrees_and_f_hz_must_be_near_a_mode(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["run", "--contact-angle", "100", "--quiet"])
    assert stop.value.code == 2 and "angle in degrees from -90 to 90" in capsys.readouterr().err
    import wheel_squeal as ws
    from wheel_squeal.runtime.request_errors import RequestError

    modes = ws.compute_modes(ws.load_design(), ws.fidelity_for("fast"), fmax_hz=3000.0)
    with pytest.raises(RequestError, match="no mode near 1e\\+09 Hz"):
        ws.pick_mode(modes, "f=1e9")
    assert ws.pick_mode(modes, "f=1100").mode.nodal_diameters == 3


@pytest.mark.parametrize(
    ("text", "word"),
    [
        ("crab_velocity,rpm,spl_db,spl_db\n0.3,800,120,1\n", "given twice"),
        ("crab_velocity,rpm,spl_db\n0.3,800," + "1" * 140_000 + "\n", "not a readable CSV"),
        ("crab_velocity,rpm,spl_db\n# a note\n\n0.3,800,1e300\n", "line 4, spl_db"),
        ("crab_velocity,rpm,spl_db,frequency_hz\n0.3,800,120,-5\n", "frequency_hz"),
        ("crab_velocity,rpm,spl_db\n" + "0.3,800,120\n" * 100_001, "more than 100,000"),
    ],
)
def test_measured_files_are_checked_on_reading(tmp_path, text, word):
    from wheel_squeal.measured_comparison import load_measured
    from wheel_squeal.runtime.request_errors import RequestError

    with pytest.raises(RequestError, match=word):
        load_measured(_write(tmp_path / "m.csv", text))


def test_a_measured_file_with_a_byte_order_mark_reads_and_its_speeds_are_checked_first(tmp_path):
    from wheel_squeal.measured_comparison import check_speeds, load_measured
    from wheel_squeal.runtime.request_errors import RequestError

    path = tmp_path / "m.csv"
    path.write_bytes("\ufeffcrab_velocity,rpm,spl_db\n0.3,800,120\n0.3,500,110\n".encode())
    measured = load_measured(path)
    assert list(measured.rpm) == [800.0, 500.0]
    with pytest.raises(RequestError, match="500 RPM is not among"):
        check_speeds(measured, [400.0, 600.0, 800.0])


# --------------------------------------------------------------------------------------
# honest levels and words
# --------------------------------------------------------------------------------------
@pytest.mark.slow  # a whole chain with its FE modes and radiation: 1.6-10.6 s measured
def test_a_microphone_on_a_silent_axis_hears_silence():
    import wheel_squeal as ws
    from wheel_squeal.listener import Listener, air_for

    design = ws.load_design()
    a = ws.analyse(
        design,
        fidelity="fast",
        fmax_hz=3000.0,
        remedy=False,
        listener=Listener((0.0, 0.1, 0.0), air_for(1.21, 343.0)),
    )
    sound = a.verdict.outcome.sound
    assert a.verdict.squeals and not sound.audible
    s = sound.summary()
    assert s["spl_db"] is None and s["spl_dba"] is None and s["wav_full_scale_pa"] is None
    assert s["sound_power_level_db"] > 100  # it radiates, away from the axis
    assert "silent at the microphone" in ws.verdict_lines(a.verdict)[0]


def test_an_oscillation_that_never_settles_is_a_squeal_not_quiet():
    """Irregular cycles (no clean limit cycle) of a record whose steady sliding is
    linearly unstable: the motion cannot come back to rest, so it squeals, "not
    settled"; its level and tone are the record's."""
    from reduced.limit_cycle import Cycles, metrics_from_cycles

    rng = np.random.default_rng(3)
    n = 400
    start = np.cumsum(np.full(n, 1 / 261.0))
    amp = 0.4 * (1 + 0.3 * rng.standard_normal(n))  # chattering: 30 % spread cycle to cycle
    cyc = Cycles(start, amp, np.full(n, 1 / 261.0), np.zeros(n), np.ones(n))
    grows = metrics_from_cycles(cyc, 0.39, 8.3, record_end_s=float(start[-1] + 1 / 261.0))
    assert grows.squeal and grows.state == "not settled" and not grows.saturated
    fading = Cycles(start, 0.4 * np.exp(-8.3 * start), np.full(n, 1 / 261.0), np.zeros(n), np.ones(n))
    decays = metrics_from_cycles(fading, 0.39, -8.3, record_end_s=float(start[-1] + 1 / 261.0))
    assert not decays.squeal and decays.state == "quiet"  # a decay of a stable equilibrium


def test_a_record_that_has_not_settled_is_measured_over_its_tail():
    from types import SimpleNamespace

    from reduced.limit_cycle import record_tail_level

    t = np.arange(0, 1.0, 1 / 20000.0)
    v = 0.38 * np.sin(2 * np.pi * 261.0 * t) + 0.1 * np.sin(2 * np.pi * 3130.0 * t)
    amplitude, frequency = record_tail_level(SimpleNamespace(t=t, v=v))
    assert amplitude == pytest.approx(math.sqrt(0.38**2 + 0.1**2), rel=0.01)  # rms of both tones
    assert frequency == pytest.approx(261.0, abs=1.0)  # the larger line, within a bin's fraction


def test_a_growing_least_stable_mode_is_never_said_to_decay():
    import wheel_squeal as ws
    from wheel_squeal.mode_stability import stability_table
    from wheel_squeal.verdict_remedy import margin_of

    design = ws.load_design()
    modes = ws.compute_modes(design, ws.fidelity_for("fast"), fmax_hz=3000.0)
    contact = ws.contact_law(design)
    op = ws.operating_point(design)
    rows, _ = stability_table(design, modes, contact, op)
    words = margin_of(design, rows, contact, op)["words"]
    assert "grows at" in words and "decays at" not in words


def _c_level_disposition(signum: int) -> str:
    """What the kernel will do with ``signum`` in this process (Linux /proc)."""
    status = Path("/proc/self/status").read_text()
    fields = dict(line.split(":", 1) for line in status.splitlines() if ":" in line)
    bit = 1 << (signum - 1)
    if int(fields["SigIgn"], 16) & bit:
        return "ignore"
    return "handler" if int(fields["SigCgt"], 16) & bit else "default"


def test_gmsh_leaves_the_process_its_signal_dispositions():
    """gmsh resets SIGPIPE to its default (a write to a dead worker's pipe would then kill
    the command silently) and SIGINT too; every session gives them back."""
    from geometry.gmsh_mesh import gmsh_session

    before = {s: _c_level_disposition(s) for s in (signal.SIGPIPE, signal.SIGINT, signal.SIGTERM)}
    with gmsh_session(False):
        during = _c_level_disposition(signal.SIGPIPE)
    after = {s: _c_level_disposition(s) for s in before}
    assert before[signal.SIGPIPE] == "ignore" and during == "ignore" and after == before


STOP_IN_A_CALLBACK = """
import ctypes, os, signal, sys, time
from wheel_squeal.cli.stops import install_stop_handlers

install_stop_handlers()
code = "def notify():\\n    os.kill(os.getpid(), signal.SIGINT)\\n    for _ in range(10000): pass\\n"
ns = {}
where = "/site-packages/llvmlite/binding/executionengine.py"
exec(compile(code, where, "exec"), {"os": os, "signal": signal}, ns)
callback = ctypes.CFUNCTYPE(None)(ns["notify"])  # Python called from native code, as numba's cache is
try:
    callback()
    time.sleep(3)
    print("not stopped", file=sys.stderr)
except KeyboardInterrupt:
    print("stopped", file=sys.stderr)
"""


def test_a_stop_that_lands_in_a_native_callback_is_raised_after_it():
    """A stop signal that lands while numba's machine-code cache calls back into Python
    (through ctypes, which prints and swallows an exception raised there) is sent again
    once the callback has returned: the command stops with its one line, no traceback."""
    r = subprocess.run(
        [sys.executable, "-c", STOP_IN_A_CALLBACK], capture_output=True, text=True, cwd=ROOT, timeout=60
    )
    assert r.stderr.strip() == "stopped", r.stderr


def test_a_stop_inside_logging_s_fork_hooks_is_sent_again_not_swallowed():
    """A stop that lands while logging takes or releases its lock around a fork (a library
    running a subprocess during the imports) is swallowed there, printed as "Exception
    ignored" with a traceback: the handler knows those hooks (this Python's among them) and
    sends the signal again a moment later instead; outside them it raises at once."""
    import logging

    from wheel_squeal.cli.stops import NATIVE_CALLBACKS, in_native_callback

    names = [name for where, name in NATIVE_CALLBACKS if where == "logging/__init__.py"]
    assert sum(hasattr(logging, name) for name in names) >= 2, names
    for name in names:
        space = {"sys": sys}
        source = f"def {name}(probe):\n    return probe(sys._getframe())\n"
        exec(compile(source, logging.__file__, "exec"), space)
        assert space[name](in_native_callback), name
    assert not in_native_callback(sys._getframe())
