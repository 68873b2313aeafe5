"""Shared fixtures: the repository's paths, a command-line runner, a sandbox folder, and
the paper's contact (Table 1) and Fig. 6 operating point."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from wheel_squeal.runtime.library_folders import LIBRARY_FOLDERS  # noqa: E402

# The libraries' own files (numba's machine code, matplotlib's font list, Mesa's shaders) in
# one folder for the whole session, the tool's default stage cache's, unless the user set
# one: else the first test's sandbox cache would take them, cold, and each worker compile the
# kernels anew (six seconds in its first test of the time domain); and a command run in this
# process would point them into a sandbox that is removed after its test.
from wheel_squeal.runtime.stage_cache import LIBRARIES_FOLDER, default_cache_root  # noqa: E402

for _module, _variable, _name in LIBRARY_FOLDERS.values():
    if not os.environ.get(_variable, "").strip():
        os.environ[_variable] = str(default_cache_root() / LIBRARIES_FOLDER / _name)

if "PYTEST_XDIST_WORKER" in os.environ:  # the workers share the cores: one thread each
    for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
        os.environ.setdefault(_var, "1")

import pytest  # noqa: E402
from hypothesis import settings  # noqa: E402

# Property tests draw the same examples on every run ("ci", the default), so that a test
# that passes in CI passes again; ``--hypothesis-profile explore`` draws new ones on each
# run (a run that looks for what the fixed draw missed).
settings.register_profile("ci", derandomize=True, deadline=None, print_blob=True)
settings.register_profile("explore", derandomize=False, deadline=None, print_blob=True)
settings.load_profile("ci")

ROOT = Path(__file__).resolve().parents[1]
DESIGNS = ROOT / "designs"
PIPELINE = ROOT / "pipeline.py"

#: A two-mode modal model that squeals by mode coupling: 1000 and 960 Hz, lateral 0.5/0.1,
#: normal -0.05/0.15 [1/sqrt(kg)], damping ratio 0.001 each (on a constant friction law
#: it grows at 109 1/s at 800 RPM, Vc = 0.39 m/s, with no falling friction).
COUPLED_PAIR_TOML = """
[[mode]]
frequency_hz = 1000.0
damping_ratio = 0.001
lateral = 0.5
normal = -0.05
label = "m1"

[[mode]]
frequency_hz = 960.0
damping_ratio = 0.001
lateral = 0.1
normal = 0.15
label = "m2"
"""
#: Table 1's mode given directly on the command line (no FE).
TABLE1_MODE_ARGS = ("--mass", "3.1", "--stiffness", "1.6e8", "--damping", "42")


def run_cli(
    *args: str, cwd: Path | None = None, env: dict | None = None, timeout: float = 600, preexec_fn=None
) -> subprocess.CompletedProcess:
    """``python pipeline.py ARGS`` in a fresh process; ``env`` entries are added to (or,
    with value None, removed from) the current environment."""
    full = dict(os.environ)
    for k, v in (env or {}).items():
        if v is None:
            full.pop(k, None)
        else:
            full[k] = v
    return subprocess.run(
        [sys.executable, str(PIPELINE), *map(str, args)],
        capture_output=True,
        text=True,
        cwd=cwd or ROOT,
        env=full,
        timeout=timeout,
        preexec_fn=preexec_fn,
    )


def run_here(
    *args: str, cwd: Path | None = None, env: dict | None = None, **_: object
) -> subprocess.CompletedProcess:
    """The command line in this process (``wheel_squeal.cli.main``, the function the
    entry point calls, without its stop handlers), for requests refused or answered in
    well under a second: the same exit status, stdout and stderr as :func:`run_cli` in a
    fraction of its time (no interpreter and imports per call). A bug raises here."""
    import contextlib
    import io

    from wheel_squeal.cli import main

    out, err = io.StringIO(), io.StringIO()
    saved_env, saved_cwd = dict(os.environ), os.getcwd()
    try:
        for k, v in (env or {}).items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
        os.chdir(cwd or ROOT)
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                status = main([str(a) for a in args], prog="pipeline.py")
            except SystemExit as exc:  # argparse's refusals
                status = exc.code if isinstance(exc.code, int) else 2
    finally:
        os.chdir(saved_cwd)
        os.environ.clear()
        os.environ.update(saved_env)
    return subprocess.CompletedProcess(
        ["pipeline.py", *map(str, args)], status, out.getvalue(), err.getvalue()
    )


def load_wheel(path):
    """The wheel (``geometry.WheelDesign``) of a design file."""
    import wheel_squeal as ws

    return ws.load_design(path).wheel


def one_line_error(r: subprocess.CompletedProcess) -> str:
    """The single stderr line of a refused request (asserts there is exactly one and no
    traceback); warnings (``warning: ...``) may precede it."""
    lines = [ln for ln in r.stderr.splitlines() if ln.strip() and not ln.startswith("warning:")]
    assert "Traceback" not in r.stderr, r.stderr
    assert len(lines) == 1, r.stderr
    return lines[0]


@pytest.fixture
def cli():
    return run_cli


@pytest.fixture
def sandbox(tmp_path: Path) -> Path:
    """A working folder with things a user keeps: earlier results, designs, own files."""
    box = tmp_path / "box"
    (box / "results" / "keep").mkdir(parents=True)
    (box / "results" / "keep" / "notes.txt").write_text("mine")
    (box / "designs").mkdir()
    (box / "designs" / "mine.toml").write_text((DESIGNS / "thin_web.toml").read_text())
    (box / "data.npz").write_bytes(b"not a cache entry")
    (box / "report.tmp").write_text("also mine")
    return box


def snapshot(folder: Path) -> dict[str, bytes | None]:
    """Every path below ``folder`` with its content (None for folders)."""
    out: dict[str, bytes | None] = {}
    for p in sorted(folder.rglob("*")):
        out[str(p.relative_to(folder))] = None if p.is_dir() else p.read_bytes()
    return out


def table1_law(normal_load_n: float = 1000.0):
    """The creep law of Table 1's wheel on its roller (optionally another normal load)."""
    import reduced as r

    h = r.hertz_contact(0.213, 0.300, 0.085, 0.040, 175e9, 0.28, normal_load_n)
    return r.ContactLaw.from_hertz(h, friction_coefficient=0.3)


@pytest.fixture(scope="module")
def law():
    return table1_law()


@pytest.fixture(scope="module")
def op_fig6():
    """The paper's Fig. 6 point: 800 RPM, Vc = 0.39 m/s."""
    import reduced as r

    return r.OperatingPoint.from_rpm(800, 0.213, 0.39)
