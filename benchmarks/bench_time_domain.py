"""The time domain at the field's scale: railway_920_track at 150 m / 40 km/h (the rigid
bogie's leading axle: V0 = 11.109568 m/s, Vc = 0.185177 m/s) as a user runs it, and what
the chain's reductions leave out.

    .venv/bin/python benchmarks/bench_time_domain.py [--repeat 3]

Commands (fresh processes; wall time as a ratio to ``import scipy.sparse.linalg,
matplotlib.pyplot`` timed in the same run, peak memory from ``/usr/bin/time``):

* ``run`` of the track design at that point, the FE modes cached, the record and the
  sound not (a cache of its own, its modes copied in);
* ``curve --time-domain`` at 150 and 300 m, 40 km/h, the same way;
* the rig wheel's ``run`` warm (everything cached) against the imports.

Reductions (in this process), each against the full model at the same point:

* the decision's group (at most ``presets.MAX_MULTIMODE`` modes of the growing
  eigenvalues) against every mode the contact sees, both with the rail's states;
* the exponential integrator's step (64 per period of the highest mode) against half of it.
"""

from __future__ import annotations

import argparse
import json
import math
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

POINT = ("--speed", "11.109568", "--crab-velocity", "0.185177")
PIPELINE = [sys.executable, str(ROOT / "pipeline.py")]


def imports_s(repeat: int) -> float:
    code = "import scipy.sparse.linalg, matplotlib.pyplot"
    walls = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-c", code], check=True)
        walls.append(time.perf_counter() - t0)
    return statistics.median(walls)


def command(args: list[str], cache: Path) -> tuple[float, float]:
    """(wall [s], peak memory [GB]) of ``pipeline.py ARGS`` with its own cache."""
    with tempfile.NamedTemporaryFile("r", suffix=".txt") as stats:
        t0 = time.perf_counter()
        timed = ["/usr/bin/time", "-o", stats.name, "-f", "%M", *PIPELINE, *args]
        r = subprocess.run([*timed, "--quiet", "--cache-dir", str(cache)], capture_output=True, text=True)
        wall = time.perf_counter() - t0
        if r.returncode != 0:
            raise SystemExit(f"{' '.join(args)}: {r.stderr.strip()}")
        return wall, int(Path(stats.name).read_text().split()[-1]) / 1e6


def with_modes(cache: Path, design: str) -> None:
    """A cache holding the design's FE modes and their views only."""
    subprocess.run(
        [
            *PIPELINE,
            "modes",
            "--design",
            design,
            "--quiet",
            "--cache-dir",
            str(cache),
            "--out",
            str(cache.parent / "modes"),
        ],
        check=True,
        capture_output=True,
    )
    for stage in cache.iterdir():
        if stage.is_dir() and stage.name not in ("modes", "mesh2d", "views"):
            shutil.rmtree(stage)


def commands(repeat: int) -> None:
    base = imports_s(repeat)
    print(f"import scipy.sparse.linalg, matplotlib.pyplot: {base:.2f} s (median of {repeat})\n")
    print("| command | wall | x imports | peak memory | result |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        cache = work / "cache"
        with_modes(cache, "railway_920_track")
        out = work / "run"
        wall, gb = command(["run", "--design", "railway_920_track", *POINT, "--out", str(out)], cache)
        s = json.loads((out / "summary.json").read_text())
        v = s["verdict"]
        csv_mb = (out / "timeseries.csv").stat().st_size / 1e6
        plots = s["timings_s"].get("plots", math.nan)
        print(
            f"| run railway_920_track, 150 m / 40 km/h | {wall:.1f} s | {wall / base:.1f} | {gb:.2f} GB | "
            f"{v['mode']} at {v['tone_hz']:.1f} Hz, {v['amplitude_m_s']:.3f} m/s, {v['spl_dba']:.1f} dB(A); "
            f"timeseries.csv {csv_mb:.1f} MB; plots {plots:.2f} s |"
        )
        shutil.rmtree(cache)
        with_modes(cache, "railway_920_track")
        curve = ["curve", "--design", "railway_920_track", "--radius", "150,300", "--train-speed", "40"]
        wall, gb = command([*curve, "--time-domain", "--out", str(work / "curve")], cache)
        rows = json.loads((work / "curve" / "summary.json").read_text())["cases"]
        said = "; ".join(
            f"{c['radius_m']:g} m {c['axle']}: {c['verdict_mode'] or 'no squeal'}"
            + (f", {c['passby_lpamax_dba']:.1f} dB(A)" if c["passby_lpamax_dba"] else "")
            for c in rows[::2]
        )
        what = "curve --time-domain 150, 300 m, 40 km/h"
        print(f"| {what} | {wall:.1f} s | {wall / base:.1f} | {gb:.2f} GB | {said} |")
        rig = work / "rig"
        command(["run", "--out", str(rig)], rig.with_name("rig_cache"))
        walls = [command(["run", "--out", str(rig)], rig.with_name("rig_cache"))[0] for _ in range(repeat)]
        warm = statistics.median(walls)
        print(f"| run table1, warm (median of {repeat}) | {warm:.2f} s | {warm / base:.2f} | | |")


def reductions() -> None:
    import numpy as np

    import reduced as r
    import wheel_squeal as ws
    from reduced.stepping import STEPS_PER_PERIOD, ExponentialRun
    from wheel_squeal.mode_stability import body_of, excitable, mode_dofs
    from wheel_squeal.simulation import simulate

    design = ws.load_design("railway_920_track")
    op = r.OperatingPoint(11.109568, 0.185177)
    a = ws.analyse(design, op=op, stop_after="limit_cycle", remedy=False, mode="model")
    o = a.outcome
    assert o is not None and o.simulation is not None
    body = body_of(design)
    group = mode_dofs(list(o.group), design)
    every = mode_dofs(excitable(a.modeset, a.contact), design)
    seconds = float(o.simulation.history.t[-1])
    print(f"\nreductions at 150 m / 40 km/h ({o.label} leads; the record {seconds:.2f} s):\n")
    print("| model | modes | amplitude [m/s] | tone [Hz] | level vs full [dB] | wall [s] |")
    print("|---|---|---|---|---|---|")
    results = {}
    for name, dofs in (("full: every mode the contact sees", every), ("the decision's group", group)):
        t0 = time.perf_counter()
        sim = simulate(dofs, a.contact, op, seconds, body=body, preload_body=True)
        content = r.modal_content(sim.history)  # the verdict's tone: the carrier's own frequency
        tone = float(content.mode_frequency_hz[content.carrier])
        results[name] = (len(dofs), sim.limit_cycle.velocity_amplitude_m_s, tone, time.perf_counter() - t0)
    full = results["full: every mode the contact sees"][1]
    for name, (n, amp, tone, wall) in results.items():
        print(f"| {name} | {n} | {amp:.4f} | {tone:.1f} | {20 * np.log10(amp / full):+.2f} | {wall:.1f} |")
    print("\n| step | amplitude [m/s] | tone [Hz] | wall [s] |")
    print("|---|---|---|---|")
    for per in (STEPS_PER_PERIOD, 2 * STEPS_PER_PERIOD):
        t0 = time.perf_counter()
        run = ExponentialRun(tuple(group), a.contact, op, 0.0, body, None, True, seconds, per)
        run.advance(seconds)
        history = run.history()
        lc, content = r.limit_cycle(history), r.modal_content(history)
        wall = time.perf_counter() - t0
        tone = float(content.mode_frequency_hz[content.carrier])
        print(f"| {per} per period | {lc.velocity_amplitude_m_s:.4f} | {tone:.2f} | {wall:.1f} |")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--reductions-only", action="store_true")
    args = p.parse_args()
    if not args.reductions_only:
        commands(args.repeat)
    reductions()


if __name__ == "__main__":
    main()
