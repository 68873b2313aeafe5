"""Designs per second of a study: the serial loop against the local process pool.

The 200-design fast-fidelity tolerance study (``studies/tolerance.toml``: mesh, modes,
stability, limit cycle and sound of every design), without any cache so every task
does its whole work, run serially in this process and on the local pool in the same
run, alternately, medians of several runs. Task overhead: the pool's wall time times
its workers against the serial time, (W T_pool - T_serial) / T_serial.

    .venv/bin/python benchmarks/bench_study.py [--runs 3] [--samples 200] [--workers 2]
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from wheel_squeal.study import load_spec  # noqa: E402
from wheel_squeal.study.runner import case_results  # noqa: E402


def _spin(n: int) -> int:
    """Pure-CPU work: what two processes can gain on this machine right now."""
    total = 0
    for i in range(n):
        total += i * i
    return total


def _noop(_: object) -> None:
    return None


def machine_scaling(workers: int, n: int = 20_000_000) -> float:
    """Speed-up of ``workers`` processes over one on a pure-CPU job (the ceiling a busy
    shared machine allows at this moment)."""
    t = time.perf_counter()
    for _ in range(workers):
        _spin(n)
    serial = time.perf_counter() - t
    with ProcessPoolExecutor(workers) as pool:
        t = time.perf_counter()
        list(pool.map(_spin, [n] * workers))
        return serial / (time.perf_counter() - t)


def dispatch_seconds(workers: int, tasks: int) -> float:
    """Wall time per task of the pool on tasks that do nothing (submission, pickling,
    result) [s]."""
    with ProcessPoolExecutor(workers) as pool:
        list(pool.map(_noop, range(workers)))  # started
        t = time.perf_counter()
        list(pool.map(_noop, range(tasks)))
        return (time.perf_counter() - t) / tasks


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--samples", type=int, default=200)
    p.add_argument("--workers", type=int, default=2)
    args = p.parse_args()
    spec = dataclasses.replace(load_spec(ROOT / "studies" / "tolerance.toml"), samples=args.samples)
    # warm up: imports and numba's compiled kernels, inherited by the forked workers
    warm = dataclasses.replace(spec, samples=1)
    case_results(warm, workers=1)
    serial, pool, ceiling = [], [], []
    for _ in range(args.runs):
        ceiling.append(machine_scaling(args.workers))
        t = time.perf_counter()
        a = case_results(spec, workers=1)
        serial.append(time.perf_counter() - t)
        t = time.perf_counter()
        b = case_results(spec, workers=args.workers)
        pool.append(time.perf_counter() - t)
    dispatch = dispatch_seconds(args.workers, spec.samples)
    assert [r["status"] for r in a] == [r["status"] for r in b]
    ts, tp = statistics.median(serial), statistics.median(pool)
    ok = sum(r["status"] == "ok" for r in a)
    print(
        f"study: {spec.name}, {spec.samples} designs ({ok} ok), fidelity {spec.fidelity}, "
        f"compute {', '.join(spec.compute)}, no cache"
    )
    n = spec.samples
    task = ts / n
    runs = f"median of {args.runs}"
    print(f"serial loop: {ts:.1f} s ({runs}), {n / ts:.2f} designs/s, {task * 1e3:.0f} ms per design")
    print(f"local pool, {args.workers} workers: {tp:.1f} s ({runs}), {n / tp:.2f} designs/s")
    each = ", ".join(f"{c:.2f}" for c in ceiling)
    print(
        f"speed-up {ts / tp:.2f}x (target >= 1.8); this machine's ceiling in the same run "
        f"(pure-CPU job): {statistics.median(ceiling):.2f}x (runs: {each})"
    )
    loss = (args.workers * tp - ts) / ts * 100
    print(
        f"task overhead: dispatch {dispatch * 1e3:.2f} ms per task = {100 * dispatch / task:.2f} % of the "
        f"task time (target < 5 %); wall-time loss ({args.workers} x pool - serial) / serial {loss:.1f} %"
    )


if __name__ == "__main__":
    main()
