"""Studies: the spec, one task per design, the same numbers on a local pool, a dask
LocalCluster and a scheduler with worker processes, worker deaths, resuming, faults."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import distributed  # noqa: F401  (the test extra installs it: a missing one must fail, not skip)
import numpy as np
import pytest
import xarray as xr
from conftest import ROOT, one_line_error, run_cli

#: every test here starts a worker pool, a cluster or the command line
pytestmark = pytest.mark.slow

from wheel_squeal.runtime.request_errors import RequestError  # noqa: E402
from wheel_squeal.study import load_spec  # noqa: E402

SMOKE = ROOT / "studies" / "smoke.toml"


def write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


def same_numbers(a, b) -> None:
    """Two study datasets hold the same results (floats to 1e-9: a mode solved afresh
    or read from a cache; strings exactly)."""
    assert set(a.data_vars) == set(b.data_vars)
    failed = b["status"].values != "ok"
    assert not failed.any(), f"cases not computed: {sorted(set(b['reason'].values[failed]))}"
    differ = {}
    for v in a.data_vars:
        x, y = a[v].values, b[v].values
        if x.dtype.kind in "fi":
            same = np.isclose(x, y, rtol=1e-9, atol=0, equal_nan=True)
        else:
            same = x == y
        if not np.all(same):  # every differing variable, where and how: a failure says why
            at = np.argwhere(~np.asarray(same))[:3]
            differ[v] = [(tuple(int(i) for i in k), x[tuple(k)], y[tuple(k)]) for k in at]
    assert differ == {}, differ
    for c in a.coords:
        np.testing.assert_array_equal(a[c].values, b[c].values)


#: What a case that failed for its environment, not its design, says (never stored: a rerun
#: computes it)
TRANSIENT = ("refused by the budget", "its dask workers died", "its worker process died")


def completed(out: Path, cache: Path):
    """The study in ``out``, its cases refused for their environment (a worker killed by
    the test, a budget under a busy CI machine) computed by a rerun, as a user would; any
    other failure fails the test. The rerun is said as a warning."""
    import warnings

    ds = xr.load_dataset(out / "study.nc")
    failed = ds["status"].values != "ok"
    if failed.any():
        reasons = sorted(set(ds["reason"].values[failed]))
        assert all(r.startswith(TRANSIENT) for r in reasons), reasons
        warnings.warn(f"{int(failed.sum())} case(s) rerun: {reasons}", stacklevel=2)
        r = run_study(out, cache, "--quiet")
        assert r.returncode == 0, r.stderr
        ds = xr.load_dataset(out / "study.nc")
    return ds


def run_study(out: Path, cache: Path, *extra, env=None, **kw):
    return run_cli("study", SMOKE, "--out", out, "--cache-dir", cache, *extra, env=env, **kw)


# -- the spec ---------------------------------------------------------------------------------
def test_smoke_spec_cases():
    spec = load_spec(SMOKE)
    cases = spec.cases()
    assert len(cases) == 8 and spec.kind == "grid"
    assert cases[0].changes == (("rim_depth", 0.03), ("web_thickness", 0.013))
    assert cases[-1].index == (3, 1)
    assert len(spec.crabbing_velocities_m_s) * len(spec.rpm) == 6


def test_wear_and_samples_specs(tmp_path):
    wear = load_spec(ROOT / "studies" / "wear.toml")
    base = wear.base
    for case in wear.cases():
        (w,) = case.values
        changes = dict(case.changes)
        assert changes["rolling_radius"] == pytest.approx(base.wheel.rolling_radius - w)
        assert changes["rim_depth"] == pytest.approx(base.wheel.rim_depth - w)
    tol = load_spec(ROOT / "studies" / "tolerance.toml")
    a, b = tol.cases(), load_spec(ROOT / "studies" / "tolerance.toml").cases()
    assert a == b and len(a) == tol.samples  # a seed: the same draws every time
    rd = np.array([dict(c.changes)["rim_depth"] for c in a])
    assert abs(rd.mean() - 0.0335) < 3 * 0.0005 / np.sqrt(len(rd))


@pytest.mark.parametrize(
    "text, phrase",
    [
        ("typo = 1\n[grid]\nrim_depth = [0.03]\n", "unknown key"),
        ("[grid]\nrim_dept = [0.03]\n", "not a design parameter"),
        ("[grid]\nrim_depth = []\n", "empty"),
        ("[samples]\nn = 10\nrim_depth = { gauss = [1, 2] }\n", "normal"),
        ("[grid]\nrim_depth = [0.03]\n[samples]\nn = 2\n", r"either \[grid\] or \[samples\]"),
        ('fidelity = "best"\n[grid]\nrim_depth = [0.03]\n', "fidelity"),
        ("[grid]\nsqueal_mode = [1.0]\n", "a name the results use"),
        ("[grid]\nnormal_load_n = [1.0]\n", "not a design parameter"),
        ("base = 5\n[grid]\nrim_depth = [0.03]\n", "a string"),
        ("[grid]\nrpm = { values = [0, 1], add = { rim_depth = 1.0 } }\n", "a name the results use"),
        ("[grid]\ndesign_x = { values = [0, 1], add = { rim_depth = 1.0 } }\n", "a name the results use"),
        ('[grid]\n"" = { values = [0, 1], add = { rim_depth = 1.0 } }\n', "letters, digits"),
        ("[grid]\nrim_depth = { start = 0.03, stop = 0.04, num = 3, step = 1 }\n", "unknown key"),
        ("[grid]\nx = { values = [0, 1], add = { web_thickness_rim = 1.0 } }\n", "does not set"),
        (
            "[grid]\na = { start = 0, stop = 1, num = 100000, add = { rim_depth = 1e-9 } }\n"
            "b = { start = 0, stop = 1, num = 100000, add = { web_thickness = 1e-9 } }\n",
            "more than a study takes",
        ),
        (
            "[grid]\nrim_depth = [0.03]\n[operating]\ncrab_velocity = { start = 0, stop = 1, num = 100000 }\n"
            "rpm = { start = 100, stop = 1000, num = 100000 }\n",
            "more than a study takes",
        ),
        (f'base = "{ROOT / "designs" / "curved_web.toml"}"\n[grid]\nrim_depth = [0.03]\n', "is an outline"),
    ],
)
def test_bad_specs_are_refused(tmp_path, text, phrase):
    with pytest.raises(RequestError, match=phrase):
        load_spec(write(tmp_path / "s.toml", text))


# -- one dataset, three ways of running --------------------------------------------------------
@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The smoke study on the local process pool (the default)."""
    tmp = tmp_path_factory.mktemp("ref")
    r = run_study(tmp / "out", tmp / "cache", "--quiet")
    assert r.returncode == 0, r.stderr
    ds = xr.load_dataset(tmp / "out" / "study.nc")
    assert (ds["status"] == "ok").all()
    assert set(np.unique(ds["verdict_mode"].values)) - {""}  # something squeals
    assert ds.attrs["named_mode"] == "n=3,c=0"  # the base design names its squeal mode
    assert ds.attrs["spec"] == SMOKE.read_text() and ds.attrs["code_version"]
    for name in ("study.csv", "study.toml", "study_tone_level.png", "report.html"):
        assert (tmp / "out" / name).is_file()
    return ds


def test_serial_loop_gives_the_same_numbers(reference, tmp_path):
    r = run_study(tmp_path / "out", tmp_path / "cache", "--workers", "1", "--quiet")
    assert r.returncode == 0, r.stderr
    same_numbers(reference, xr.load_dataset(tmp_path / "out" / "study.nc"))


def test_physics_of_the_smoke_study(reference):
    """What the study reports is the single-design pipeline's: the (3,0) growth and
    amplitude at a point re-computed with the API; growth and squeal agree in sign."""
    g, a = reference["growth_rate_1_s"].values, reference["amplitude_m_s"].values
    assert np.all(np.isfinite(g))
    squeal = np.isfinite(a) & (a > 0)
    assert np.all(g[squeal] > 0)  # a limit cycle only where a mode grows
    spl = reference["spl_db"].values[squeal]
    assert np.all((spl > 80) & (spl < 150))
    # heavier rims carry more mass
    m = reference["mass_kg"].values
    assert np.all(np.diff(m, axis=0) > 0) and np.all(np.diff(m, axis=1) > 0)


def test_dask_local_cluster_gives_the_same_numbers(reference, tmp_path):
    from distributed import LocalCluster

    env = {"WHEEL_SQUEAL_CACHE": str(tmp_path / "worker-cache")}
    old = {k: os.environ.get(k) for k in env}
    os.environ.update(env)  # the cluster's worker processes inherit it
    try:
        with LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster:
            r = run_study(tmp_path / "out", tmp_path / "cache", "--scheduler", cluster.scheduler_address)
    finally:
        for k, v in old.items():
            os.environ.pop(k) if v is None else os.environ.__setitem__(k, v)
    assert r.returncode == 0, r.stderr
    assert "dask scheduler" in r.stderr
    same_numbers(reference, completed(tmp_path / "out", tmp_path / "cache"))
    # the workers kept the FE in their own (default) cache
    assert any(p.name.endswith(".npz") for p in (tmp_path / "worker-cache").rglob("*")), "no worker cache"


def _dask(*args, env) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-m", "distributed.cli." + args[0], *args[1:]],
        env={**os.environ, **env},
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )


def _wait_for(path: Path, seconds: float = 60) -> None:
    end = time.time() + seconds
    while not path.exists():
        if time.time() > end:
            raise TimeoutError(path)
        time.sleep(0.2)


def test_scheduler_and_worker_processes_survive_a_killed_worker(reference, tmp_path):
    """A scheduler and two workers as separate processes on 127.0.0.1, reached with
    --scheduler; one worker is killed once the study is under way: the scheduler gives
    its tasks to the other and the numbers are the same."""
    env = {"WHEEL_SQUEAL_CACHE": str(tmp_path / "worker-cache")}  # cold: tasks take a while
    sched_file = tmp_path / "scheduler.json"
    procs = [
        _dask(
            "dask_scheduler",
            "--host",
            "127.0.0.1",
            "--port",
            "0",
            "--no-dashboard",
            "--scheduler-file",
            str(sched_file),
            env=env,
        )
    ]
    try:
        _wait_for(sched_file)
        import json

        address = json.loads(sched_file.read_text())["address"]
        for _ in range(2):
            procs.append(
                _dask("dask_worker", address, "--nworkers", "1", "--nthreads", "1", "--no-dashboard", env=env)
            )
        from distributed import Client

        with Client(address, timeout="30s") as c:
            c.wait_for_workers(2, timeout=60)
        study = subprocess.Popen(
            [
                sys.executable,
                str(ROOT / "pipeline.py"),
                "study",
                str(SMOKE),
                "--out",
                str(tmp_path / "out"),
                "--cache-dir",
                str(tmp_path / "cache"),
                "--scheduler",
                address,
            ],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        time.sleep(2.0)  # the workers have their first tasks
        assert study.poll() is None  # mid-study
        os.killpg(procs[1].pid, signal.SIGKILL)
        out, err = study.communicate(timeout=300)
        assert study.returncode == 0, err
        assert study.poll() == 0 and procs[1].wait(5) == -signal.SIGKILL
        same_numbers(reference, completed(tmp_path / "out", tmp_path / "cache"))
    finally:
        for p in procs:
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGKILL)
                p.wait(10)


def _children(pid: int) -> set[int]:
    path = Path(f"/proc/{pid}/task/{pid}/children")
    try:
        return {int(x) for x in path.read_text().split()}
    except OSError:
        return set()


def _kill_a_pool_worker(pid: int, workers: int) -> bool:
    """SIGKILL one of the study's pool workers, mid-study: the first child that has lived
    through two looks 0.5 s apart while the study had ``workers`` children (a process
    forked for a moment, such as a mesher's, is not one of them). False after 60 s."""
    end = time.time() + 60
    seen: set[int] = set()
    while time.time() < end:
        now = _children(pid)
        steady = sorted(seen & now)
        if len(now) >= workers and steady:
            try:
                os.kill(steady[0], signal.SIGKILL)
                return True
            except ProcessLookupError:  # it ended between the look and the kill
                pass
        seen = now
        time.sleep(0.5)
    return False


def test_local_pool_survives_a_killed_worker(reference, tmp_path):
    """A local pool process killed mid-study: the pool is rebuilt, the unfinished cases
    run again, the numbers are the same."""
    study = subprocess.Popen(
        [
            sys.executable,
            str(ROOT / "pipeline.py"),
            "study",
            str(SMOKE),
            "--out",
            str(tmp_path / "out"),
            "--cache-dir",
            str(tmp_path / "cache"),
            "--workers",
            "2",
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert _kill_a_pool_worker(study.pid, workers=2)
    out, err = study.communicate(timeout=300)
    assert study.returncode == 0, err
    assert "a worker process died" in err
    same_numbers(reference, xr.load_dataset(tmp_path / "out" / "study.nc"))


def test_an_interrupted_study_resumes_with_only_the_missing_cases(reference, tmp_path):
    cmd = [
        sys.executable,
        str(ROOT / "pipeline.py"),
        "study",
        str(SMOKE),
        "--out",
        str(tmp_path / "out"),
        "--cache-dir",
        str(tmp_path / "cache"),
        "--workers",
        "1",
    ]
    study = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    lines = []
    for line in study.stderr:  # stop it once some cases are done (progress: "k/8 cases")
        lines.append(line)
        done = [int(w.split("/")[0]) for w in line.split() if w.endswith("/8")]
        if done and 2 <= done[0] < 8:
            study.send_signal(signal.SIGKILL)
            break
    study.wait(30)
    assert not (tmp_path / "out").exists()  # no half-written result
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    earlier = int(r.stderr.split(" from an earlier run")[0].rsplit(", ", 1)[1])
    assert 2 <= earlier < 8, "".join(lines) + r.stderr
    same_numbers(reference, xr.load_dataset(tmp_path / "out" / "study.nc"))


def test_invalid_sampled_designs_are_reported_not_fatal(tmp_path):
    spec = write(
        tmp_path / "tol.toml",
        f'base = "{ROOT / "designs" / "table1.toml"}"\ncompute = ["stability"]\n'
        "[samples]\nn = 6\nseed = 3\nweb_thickness = { uniform = [0.010, 0.040] }\n"
        "[operating]\ncrab_velocity = [0.3]\nrpm = [800]\n",
    )
    r = run_cli("study", spec, "--out", tmp_path / "out", "--cache-dir", tmp_path / "c", "--quiet")
    assert r.returncode == 0, r.stderr
    ds = xr.load_dataset(tmp_path / "out" / "study.nc")
    status = ds["status"].values
    assert "invalid" in status and "ok" in status
    bad = ds["reason"].values[status == "invalid"]
    assert all("web_thickness" in x for x in bad)
    assert np.isnan(ds["growth_rate_1_s"].values[status == "invalid"]).all()
    assert np.isfinite(ds["growth_rate_1_s"].values[status == "ok"]).all()
    # the stability alone: the summary counts the designs study.nc says squeal
    squeal = ds["squeals"].where(ds["status"] == "ok").max(["crab_velocity", "rpm"]).values > 0.5
    ok = int((status == "ok").sum())
    assert f"{int(squeal.sum())} of {ok} valid designs squeal" in r.stdout + r.stderr


def test_without_the_study_extra_one_line_says_what_to_install(tmp_path):
    fake = tmp_path / "fake"
    (fake / "xarray").mkdir(parents=True)
    (fake / "xarray" / "__init__.py").write_text("raise ImportError('no xarray here')\n")
    r = run_cli("study", SMOKE, "--out", tmp_path / "out", env={"PYTHONPATH": str(fake)})
    assert r.returncode == 2
    assert "pip install" in one_line_error(r)
    assert not (tmp_path / "out").exists()


def test_a_youngs_modulus_grid_scales_the_tone_as_its_square_root(tmp_path):
    """Invariant: E changes no mesh, so every frequency scales as sqrt(E) (an outline
    base: the study varies what an outline design may vary), with a constant normal
    load: the Hertz spring stiffens as E^(2/3), not as E, and moves the tones of the
    modes that move the contact normally (this outline's do: its web is curved)."""
    from wheel_squeal.study.runner import case_results

    base = (
        (ROOT / "designs" / "curved_web.toml")
        .read_text()
        .replace("[contact]\n", '[contact]\nnormal_contact = "constant"\n')
    )
    spec = load_spec(
        write(
            tmp_path / "e.toml",
            f'base = "{write(tmp_path / "curved_web.toml", base)}"\ncompute = ["stability"]\n'
            "[grid]\nyoungs_modulus = [170e9, 210e9]\n[operating]\ncrab_velocity = [0.3]\nrpm = [800]\n",
        )
    )
    a, b = case_results(spec, workers=1)
    assert a["verdict_mode"] == b["verdict_mode"] == [["(1,0) axial"]]
    ratio = b["tone_hz"][0][0] / a["tone_hz"][0][0]
    # the tone is the damped frequency: the friction's damping does not scale with E,
    # which moves it by about (sigma / omega)^2 = (10 / 2300)^2 = 2e-5
    assert ratio == pytest.approx(np.sqrt(210 / 170), rel=1e-4)
