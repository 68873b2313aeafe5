"""The benchmark suite in one command: one table, medians of several runs, ratios
against baselines measured in the same run.

    .venv/bin/python benchmarks/run_all.py [--quick] [--design FILE] [--output FILE]

Rows (Table 1 wheel unless ``--design``):

* meshing: the 2-D profile (balanced preset's mesh), the cyclic 3-D wheel (1 element
  across the web, curved second order, revolved in N = 48 sectors: the mesh the 3-D P2
  rows use) and the gmsh 3-D wheel (curved tetra10, 1 element across the web: the
  unstructured check);
* modes: the axisymmetric solver through ``wheel_squeal.compute_modes`` for the fast,
  balanced and accurate presets (no cache: mesh + modes), and the 3-D P2 modes (all
  modes <= 5 kHz) on the cyclic mesh: the chosen path ``fem.cyclic.solve_cyclic``
  (cyclic symmetry, one small problem per harmonic; mesh given) vs the baseline on the
  same mesh, scikit-fem form assembly of the full matrices + plain
  ``scipy.sparse.linalg.eigsh(K, k, M, sigma=0)`` (SuperLU with SciPy's default COLAMD
  ordering, default threads; k = the eigenvalues in the band padded by
  ``fem.solid.PAIR_RTOL``, a pair counting twice): eigen-solve alone and whole path
  (baseline: assembly + eigsh; chosen: ``solve_cyclic`` total with labels), runs
  interleaved; plus ``fem.solid.solve_solid`` on the gmsh mesh (the unstructured check);
* one simulation (Fig. 6 operating point, balanced preset's mode): the production
  ``ws.simulate`` (compiled RK4, duration extended while growing) and RK4 over the
  same final duration, vs ``solve_ivp`` (DOP853, rtol 1e-8) over that duration; the
  interpreted against the compiled RK4 kernel on 0.6 s of it, with the compiled form's
  load in a fresh process (where the two break even);
* one sweep (50 crabbing velocities x 3 speeds, 0.6 s each): ``reduced.sweep``
  (numba, parallel) vs the 150 cases run one after another with ``reduced.simulate``
  + ``limit_cycle`` (RK4, one core); the first call (compile/cache load) is reported
  apart;
* which mode squeals: the linear stability of 14 modes (``stability_table``), the
  envelope map of 50 crabbing velocities x 3 speeds (rotation off and on) and the
  mitigation over it, against a 0.6 s multi-mode time-domain run of the same modes;
* sound: the radiation of the (3,0) mode (air mesh, assembly, solve, far field) against
  the mesh and modes it comes from;
* the command line as a user meets it (subprocesses, interleaved with their
  baselines): ``pipeline.py simulate`` of the Fig. 6 case (no FE) against
  ``benchmarks/baselines/fig6_solve_ivp.py`` (the same case as a plain solve_ivp +
  pyplot script), ``pipeline.py run`` with a warm cache against the bare import of
  ``scipy.sparse.linalg`` and ``matplotlib.pyplot``, and ``run`` with a cold cache.

Each figure is the median of ``n`` runs (the column ``n``); slow baselines run fewer
times. ``--quick`` runs everything once or twice (a smoke test of the suite, not
figures to quote).
"""

from __future__ import annotations

import argparse
import datetime as _dt
import math
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))  # bench_modes: the shared 3-D baseline

import numpy as np  # noqa: E402

import wheel_squeal as ws  # noqa: E402
from wheel_squeal.runtime.provenance import CODE_PACKAGES  # noqa: E402


# --------------------------------------------------------------------------------------
# machine and timing helpers
# --------------------------------------------------------------------------------------
def machine_info() -> dict:
    cpu = "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem_gb = float("nan")
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal"):
                mem_gb = int(line.split()[1]) / 1024**2
                break
    except OSError:
        pass
    try:
        affinity = len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover
        affinity = os.cpu_count()
    try:
        commit = (
            subprocess.run(
                ["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True, timeout=10
            ).stdout.strip()
            or "unknown"
        )
    except (OSError, subprocess.SubprocessError):
        commit = "unknown"
    import scipy

    return {
        "date": _dt.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z"),
        "nproc": affinity,
        "cpu": cpu,
        "memory_gb": mem_gb,
        "loadavg": os.getloadavg() if hasattr(os, "getloadavg") else (float("nan"),) * 3,
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "commit": commit,
    }


def timed(fn: Callable[[], Any], n: int) -> tuple[float, Any, list[float]]:
    """Median wall time of ``n`` calls, the last result and all times."""
    times, out = [], None
    for _ in range(max(1, n)):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), out, times


class Table:
    def __init__(self) -> None:
        self.rows: list[tuple] = []

    def add(
        self,
        section: str,
        what: str,
        n: int,
        seconds: float,
        baseline: str = "",
        baseline_s: float | None = None,
        baseline_n: int | None = None,
        note: str = "",
    ) -> None:
        self.rows.append((section, what, n, seconds, baseline, baseline_s, baseline_n, note))
        ratio = f", {baseline_s / seconds:.1f}x faster than {baseline}" if baseline_s else ""
        print(f"  {section}: {what}: {_fmt_s(seconds)} (median of {n}){ratio}", file=sys.stderr, flush=True)

    def render(self) -> str:
        head = (
            f"{'section':<10} {'benchmark':<46} {'n':>2} {'median':>9} "
            f"{'baseline (same run)':<34} {'n':>2} {'median':>9} {'ratio':>7}  notes"
        )
        lines = [head, "-" * len(head)]
        for sec, what, n, s, base, bs, bn, note in self.rows:
            ratio = f"{bs / s:6.1f}x" if bs else ""
            lines.append(
                f"{sec:<10} {what:<46} {n:>2} {_fmt_s(s):>9} {base:<34} "
                f"{bn if bn else '':>2} {_fmt_s(bs) if bs else '':>9} {ratio:>7}  {note}"
            )
        lines.append("ratio = baseline median / median (how many times faster than the baseline)")
        return "\n".join(lines)


def _fmt_s(s: float | None) -> str:
    if s is None or not math.isfinite(s):
        return "-"
    if s < 0.1:
        return f"{s * 1e3:.1f} ms"
    return f"{s:.2f} s"


# --------------------------------------------------------------------------------------
# the benchmarks
# --------------------------------------------------------------------------------------
#: sectors of the cyclic 3-D mesh (the default for 1 element across the Table 1 web)
CYCLIC_SECTORS = 48


def bench_mesh(design, table: Table, quick: bool) -> None:
    from geometry import mesh_profile, mesh_wheel, revolve_profile

    bal = ws.FIDELITIES["balanced"]
    wheel = design.wheel
    s, m, _ = timed(
        lambda: mesh_profile(wheel, elements_through_web=bal.elements_through_web, order=bal.mesh_order),
        3 if quick else 5,
    )
    table.add(
        "mesh",
        f"2-D profile ({bal.elements_through_web}/web, order {bal.mesh_order})",
        3 if quick else 5,
        s,
        note=f"{m.n_nodes} nodes, {m.n_elements} triangles",
    )
    n = 3 if quick else 5
    s, m, _ = timed(
        lambda: revolve_profile(mesh_profile(wheel, elements_through_web=1, order=2), CYCLIC_SECTORS), n
    )
    table.add(
        "mesh",
        f"3-D cyclic wheel (1/web, tetra10, N={CYCLIC_SECTORS})",
        n,
        s,
        note=f"profile + revolve_profile: {m.n_nodes} nodes, {m.n_elements} tetrahedra",
    )
    n = 1 if quick else 3
    s, m, _ = timed(lambda: mesh_wheel(design.wheel, elements_through_web=1, order=2), n)
    table.add(
        "mesh",
        "3-D gmsh wheel (1/web, curved tetra10)",
        n,
        s,
        note=f"{m.n_nodes} nodes, {m.n_elements} tetrahedra",
    )


def bench_modes(design, table: Table, quick: bool) -> tuple:
    n = 3 if quick else 5
    results = {}
    for name in ("fast", "balanced", "accurate"):
        s, ms, _ = timed(lambda name=name: ws.compute_modes(design, name), n)
        mode, _ = ws.pick_mode(ms)
        results[name] = (s, ms, mode)
        fid = ws.FIDELITIES[name]
        table.add(
            "modes",
            f"{fid.solver} P{fid.order} {name} ({fid.elements_through_web}/web), mesh+modes",
            n,
            s,
            note=f"{ms.dofs} DOFs, {len(ms.modes)} modes <= 5 kHz, (3,0) {mode.frequency_hz:.2f} Hz",
        )

    from bench_modes import eigenvalue_list, eigsh_baseline

    from fem.cyclic import solve_cyclic
    from fem.solid import PAIR_RTOL, solve_solid
    from geometry import mesh_profile, mesh_wheel, revolve_profile

    t = time.perf_counter()
    mesh = revolve_profile(mesh_profile(design.wheel, elements_through_web=1, order=2), CYCLIC_SECTORS)
    t_mesh = time.perf_counter() - t
    N = mesh.n_sectors
    # the eigenvalues in the padded band (untimed): a pair (0 < n < N/2) counts twice;
    # eigsh is given exactly that many, so it runs once
    ref = solve_cyclic(design.wheel, mesh, fmax_hz=5000.0 * (1 + PAIR_RTOL))
    lam = eigenvalue_list(ref, N)
    nev = len(lam)

    def baseline():
        return eigsh_baseline(design.wheel, mesh, nev)[:3]

    n_fast = 3 if quick else 5
    n_base = 1 if quick else 2
    base, cyc = [], []
    for i in range(n_fast):  # interleaved: the same machine load for both
        if i < n_base:
            base.append(baseline())
        ms = solve_cyclic(design.wheel, mesh, fmax_hz=5000.0)
        cyc.append((ms.timings_s["eigen"], ms.timings_s["total"]))
    med = statistics.median
    b_eig, b_tot = med(b[1] for b in base), med(b[0] + b[1] for b in base)
    c_eig, c_tot = med(c[0] for c in cyc), med(c[1] for c in cyc)
    dev = max(float(np.max(np.abs(b[2] - lam) / lam)) for b in base)
    tag = f"3-D P2 cyclic 1/web N={N}:"
    table.add(
        "modes",
        f"{tag} eigen-solve (cyclic)",
        n_fast,
        c_eig,
        "eigsh + SuperLU/COLAMD (plain)",
        b_eig,
        n_base,
        note=f"{ms.dofs} DOFs (same mesh), {nev} eigenvalues <= {5000 * (1 + PAIR_RTOL):g} Hz; "
        f"eigenvalues agree to {dev:.0e}",
    )
    s_bal = results["balanced"][0]
    table.add(
        "modes",
        f"{tag} whole solve_cyclic",
        n_fast,
        c_tot,
        "skfem assembly + eigsh (plain)",
        b_tot,
        n_base,
        note=f"mesh given; {len(ms.modes)} modes <= 5 kHz, labelled; with meshing {_fmt_s(t_mesh + c_tot)}, "
        f"axisym balanced (mesh + modes) {_fmt_s(s_bal)} is {(t_mesh + c_tot) / s_bal:.1f}x faster",
    )

    gm = mesh_wheel(design.wheel, elements_through_web=1, order=2)
    n_tet = 1 if quick else 2
    s_full, full, _ = timed(lambda: solve_solid(design.wheel, gm, order=2, fmax_hz=5000.0), n_tet)
    table.add(
        "modes",
        "3-D P2 gmsh tet (1/web) solve_solid",
        n_tet,
        s_full,
        note=f"unstructured check (full matrices): {full.dofs} DOFs; solve_cyclic on "
        f"{ms.dofs} DOFs is {s_full / c_tot:.0f}x faster",
    )
    return results


def bench_simulation(design, mode, table: Table, quick: bool):
    import reduced

    dof = ws.modal_dof(mode, design)
    contact = ws.contact_law(design)
    op = ws.operating_point(design)
    reduced.load_compiled_kernels()  # the compiled RK4 throughout (its load: bench_engine)
    n = 3 if quick else 5
    s_prod, sim, _ = timed(lambda: ws.simulate(dof, contact, op), n)
    duration = float(sim.history.t[-1])
    s_rk4, hist, _ = timed(lambda: reduced.simulate(dof, contact, op, duration), n)
    n_ivp = 1 if quick else 3
    s_ivp, ref, _ = timed(
        lambda: reduced.simulate_reference(dof, contact, op, duration, method="DOP853", rtol=1e-8), n_ivp
    )
    a_ref = reduced.limit_cycle(ref).velocity_amplitude_m_s
    a_rk4 = reduced.limit_cycle(hist).velocity_amplitude_m_s
    base = "solve_ivp DOP853 rtol 1e-8"
    table.add(
        "simulate",
        "ws.simulate (RK4 48/period, auto length)",
        n,
        s_prod,
        base,
        s_ivp,
        n_ivp,
        note=f"length from the harmonic-balance growth estimate: {duration:g} s "
        f"(baseline: {duration:g} s once)",
    )
    table.add(
        "simulate",
        f"RK4 48/period, same {duration:g} s",
        n,
        s_rk4,
        base,
        s_ivp,
        n_ivp,
        note=f"amplitude {a_rk4:.5f} vs {a_ref:.5f} m/s ({a_rk4 / a_ref - 1:+.1e})",
    )
    return dof, contact


_LOAD_COMPILED = """
import time
import numpy as np
t = time.perf_counter()
from reduced import _engine
kernels = _engine.compiled()
y, u = np.empty(2), np.empty(2)
law = (1e3, 0.3, 5.0, 0.138, 6.9, 17.8, 0.39)
kernels.integrate_store_1(0.0, 0.0, 3.1, 42.0, 1.6e8, law, 1e-5, 1, 1, y, u)
print(time.perf_counter() - t)
"""


def bench_engine(dof, contact, op, table: Table, quick: bool) -> None:
    """The interpreted and compiled forms of the scalar RK4 kernel on the Fig. 6 run, and
    the compiled form's one-off load in a fresh process (numba's import and the first call
    from its cache): where they break even sets ``reduced._engine.INTERPRETED_MAX_STEPS``."""
    from reduced import _engine, _kernels
    from reduced.model import choose_time_step, law_vector

    h = choose_time_step(dof, contact, op)
    steps = int(0.6 / h)
    law = tuple(law_vector(contact, op).tolist())
    y, u = np.empty(steps + 1), np.empty(steps + 1)
    args = (0.0, 0.0, dof.mass_kg, dof.damping_ns_m, dof.stiffness_n_m, law, h, steps, 1, y, u)
    compiled = _engine.compiled()
    n = 2 if quick else 5
    s_interp, _, _ = timed(lambda: _kernels.integrate_store_1(*args), n)
    s_comp, _, _ = timed(lambda: compiled.integrate_store_1(*args), n)
    loads = [
        float(
            subprocess.run(
                [sys.executable, "-c", _LOAD_COMPILED], capture_output=True, text=True, check=True, cwd=ROOT
            ).stdout
        )
        for _ in range(n)
    ]
    s_load = statistics.median(loads)
    per_step = (s_interp - s_comp) / steps
    table.add(
        "simulate",
        f"RK4 kernel interpreted, {steps} steps (0.6 s)",
        n,
        s_interp,
        "compiled (numba)",
        s_comp,
        n,
        note=f"compiled load in a fresh process {s_load:.2f} s (median of {n}): break-even at "
        f"{s_load / per_step:,.0f} steps; interpreted up to {_engine.INTERPRETED_MAX_STEPS:,}",
    )


def bench_sweep(design, dof, contact, table: Table, quick: bool) -> None:
    import reduced

    vcs = np.linspace(0.0, 0.5, 50)
    rpms = np.array([400.0, 600.0, 800.0])
    speeds = rpms * 2 * math.pi / 60 * design.wheel.rolling_radius
    t = time.perf_counter()
    reduced.sweep(dof, contact, [0.39], [speeds[-1]], 0.01)
    t_first = time.perf_counter() - t
    n = 3 if quick else 5
    s, res, _ = timed(lambda: reduced.sweep(dof, contact, vcs, speeds, 0.6), n)

    def serial():
        out = []
        for vc in vcs:
            for v0 in speeds:
                op = reduced.OperatingPoint(v0, vc)
                out.append(reduced.limit_cycle(reduced.simulate(dof, contact, op, 0.6)))
        return out

    s_ser, _, _ = timed(serial, 1)
    table.add(
        "sweep",
        "reduced.sweep 50 x 3, 0.6 s (numba prange)",
        n,
        s,
        "150 x simulate+limit_cycle, serial",
        s_ser,
        1,
        note=f"{int(res.squeal.sum())}/150 squeal; first call {t_first:.2f} s (compile/cache load)",
    )


def _command_seconds(args: list[str], cwd: Path = ROOT) -> float:
    t = time.perf_counter()
    p = subprocess.run(args, capture_output=True, text=True, cwd=cwd, timeout=1800)
    dt = time.perf_counter() - t
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(args[1:3])} failed ({p.returncode}): {p.stderr.strip()[-300:]}")
    return dt


def bench_run(design_path: Path | None, table: Table, quick: bool) -> None:
    """The command line as a user meets it (subprocesses, interleaved with baselines)."""
    py = sys.executable
    pipe = [py, str(ROOT / "pipeline.py")]
    # an installed package has its bytecode compiled at install time; an editable one
    # only once it is imported with bytecode writing on: compile it, as pip would
    subprocess.run(
        [
            py,
            "-m",
            "compileall",
            "-q",
            *(str(ROOT / p) for p in (*CODE_PACKAGES, "designs", "pipeline.py")),
        ],
        check=True,
    )
    run_args = pipe + ["run", "--quiet"] + (["--design", str(design_path)] if design_path else [])
    n = 2 if quick else 5
    tmp = Path(tempfile.mkdtemp(prefix="bench-run-"))
    try:
        sim = pipe + ["simulate", "--mass", "3.1", "--stiffness", "1.6e8", "--damping", "42", "--quiet"]
        ivp = [py, str(ROOT / "benchmarks" / "baselines" / "fig6_solve_ivp.py"), str(tmp / "fig6.png")]
        imports = [py, "-c", "import scipy.sparse.linalg, matplotlib.pyplot"]
        run = partial(_command_seconds, cwd=tmp)
        cold, warm, sims, ivps, imps = [], [], [], [], []
        run(run_args + ["--cache-dir", str(tmp / "warm-cache"), "--out", str(tmp / "first")])
        for i in range(n):  # interleaved: the same machine load for each command and its baseline
            sims.append(run(sim + ["--out", str(tmp / f"sim-{i}")]))
            ivps.append(run(ivp))
            warm_cache = ["--cache-dir", str(tmp / "warm-cache")]
            warm.append(run(run_args + warm_cache + ["--out", str(tmp / f"w-{i}")]))
            imps.append(run(imports))
            if i < (1 if quick else 3):
                cold_cache = ["--cache-dir", str(tmp / f"cold-{i}")]
                cold.append(run(run_args + cold_cache + ["--out", str(tmp / f"c-{i}")]))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    med = statistics.median
    s_sim, s_ivp, s_warm, s_imp, s_cold = med(sims), med(ivps), med(warm), med(imps), med(cold)
    table.add(
        "latency",
        "pipeline.py simulate, Fig. 6 case (no FE)",
        n,
        s_sim,
        "fig6_solve_ivp.py (solve_ivp + pyplot)",
        s_ivp,
        n,
        note=f"simulate / baseline = {s_sim / s_ivp:.2f} (target <= 0.5): record, CSV, 6 PNGs, JSON",
    )
    table.add(
        "latency",
        "pipeline.py run, warm cache",
        n,
        s_warm,
        "import scipy.sparse.linalg, matplotlib.pyplot",
        s_imp,
        n,
        note=f"warm run / imports = {s_warm / s_imp:.2f} (target <= 1.5): modes from the cache",
    )
    table.add(
        "run",
        "pipeline.py run, cold cache",
        len(cold),
        s_cold,
        "warm cache",
        s_warm,
        n,
        note="fresh empty cache each time: mesh + modes (balanced) + squeal + report + render "
        "(target < 10 s)",
    )


def bench_stability(design, table: Table, quick: bool) -> None:
    """Linear stability of 14 modes (the Table 1 wheel's lowest 14 the contact sees)
    and the 50 x 3 envelope map, against the multi-mode time domain (0.6 s of the same
    modes from rest) that would otherwise tell which mode grows."""
    import dataclasses

    from wheel_squeal.envelope import envelope, mitigation
    from wheel_squeal.mode_stability import excitable, mode_dofs, stability_table

    ms = ws.compute_modes(design, "balanced", fmax_hz=8000.0)
    contact, op = ws.contact_law(design), ws.operating_point(design)
    ms = dataclasses.replace(ms, modes=excitable(ms, contact)[:14])
    dofs = mode_dofs(ms.modes, design)
    ws.simulate(dofs, contact, op, 0.01)  # compile / cache load, not timed
    n = 3 if quick else 7
    s_base, _, _ = timed(lambda: ws.simulate(dofs, contact, op, 0.6), 1 if quick else 3)
    s, table14, _ = timed(lambda: stability_table(design, ms, contact, op), n)
    base = f"time domain, {len(ms.modes)} modes, 0.6 s"
    table.add(
        "stability",
        f"stability_table, {len(ms.modes)} modes",
        n,
        s,
        base,
        s_base,
        1 if quick else 3,
        note=f"target < 0.2 s; winner {table14.rows[table14.fastest].mode.label()}",
    )
    vcs, rpms = np.linspace(0.0, 0.6, 50), [400.0, 600.0, 800.0]
    for rotation in (False, True):
        s, _, _ = timed(lambda rotation=rotation: envelope(design, ms, contact, vcs, rpms, rotation), n)
        table.add(
            "stability",
            f"envelope 50 x 3, rotation {'on' if rotation else 'off'}",
            n,
            s,
            base,
            s_base,
            1 if quick else 3,
            note="target < 1 s",
        )
    s, _, _ = timed(lambda: mitigation(design, ms, contact, vcs, rpms), 1 if quick else 3)
    table.add("stability", "mitigation over 50 x 3", 1 if quick else 3, s, note="damping per mode + slope")


def bench_sound(design, table: Table, quick: bool) -> None:
    """The radiation of the (3,0) mode (balanced preset, no cache: air mesh, assembly,
    solve, far field) against the modes it comes from (mesh + modes, same preset)."""
    from wheel_squeal.listener import default_microphone
    from wheel_squeal.sound import mode_radiation

    ms = ws.compute_modes(design, "balanced")
    mode, _ = ws.pick_mode(ms, "n=3,c=0")
    mic = default_microphone(design)
    n = 3 if quick else 5
    s_modes, _, _ = timed(lambda: ws.compute_modes(design, "balanced"), n)
    s, radiation, _ = timed(lambda: mode_radiation(design, ms, mode, mode.frequency_hz, mic), n)
    field = radiation.field
    table.add(
        "sound",
        "radiation of the (3,0) mode (balanced)",
        n,
        s,
        "mesh + modes (balanced)",
        s_modes,
        n,
        note=f"target < 1 s; {len(field.pressure)} DOFs, "
        f"L_W {10 * math.log10(field.sound_power_w / 1e-12):.2f} dB per 1 m/s",
    )


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repetitions (smoke test)")
    ap.add_argument("--design", type=Path, default=None, help="design TOML (default Table 1)")
    ap.add_argument("--output", type=Path, default=None, help="also write the report here")
    args = ap.parse_args(argv)
    info = machine_info()
    t0 = time.perf_counter()
    design = ws.load_design(args.design)
    table = Table()
    print(
        f"benchmarks/run_all.py{' --quick' if args.quick else ''}: design {design.name} ...",
        file=sys.stderr,
        flush=True,
    )
    bench_mesh(design, table, args.quick)
    results = bench_modes(design, table, args.quick)
    dof, contact = bench_simulation(design, results["balanced"][2], table, args.quick)
    bench_engine(dof, contact, ws.operating_point(design), table, args.quick)
    bench_sweep(design, dof, contact, table, args.quick)
    bench_stability(design, table, args.quick)
    bench_sound(design, table, args.quick)
    bench_run(args.design, table, args.quick)
    load_end = os.getloadavg() if hasattr(os, "getloadavg") else (float("nan"),) * 3
    la = info["loadavg"]
    header = [
        f"date: {info['date']}   commit: {info['commit']}   design: {design.name}",
        f"machine: {info['nproc']} CPUs ({info['cpu']}), {info['memory_gb']:.1f} GB RAM; "
        f"python {info['python']}, numpy {info['numpy']}, scipy {info['scipy']}",
        f"load average at start: {la[0]:.2f} {la[1]:.2f} {la[2]:.2f}; at end: "
        f"{load_end[0]:.2f} {load_end[1]:.2f} {load_end[2]:.2f}"
        + (
            f"   (shared/busy machine: load at start above {0.5 * info['nproc']:g}; expect noisy times)"
            if la[0] > 0.5 * info["nproc"]
            else ""
        ),
        f"command: .venv/bin/python benchmarks/run_all.py{' --quick' if args.quick else ''}"
        + (f" --design {args.design}" if args.design else ""),
        f"total wall time: {time.perf_counter() - t0:.0f} s",
        "",
    ]
    text = "\n".join(header) + table.render()
    print(text)
    if args.output:
        args.output.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
