"""The two-direction linear stability (reduced.coupled_stability) of the FE modes of a
design, against the lateral one (reduced.linear_stability) on the same modes: one point,
and an envelope of 50 crabbing velocities x 3 speeds. Medians of repeated runs.

    .venv/bin/python benchmarks/bench_coupling.py [--design NAME] [--repeat 7]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

import reduced as r  # noqa: E402
import wheel_squeal as ws  # noqa: E402
from wheel_squeal.api import hertz_of  # noqa: E402
from wheel_squeal.stability import contact_modes as seen_by_contact  # noqa: E402
from wheel_squeal.stability import excitable, mode_dofs  # noqa: E402


def median_seconds(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--design", default="dished_web")
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args()
    design = ws.load_design(args.design)
    modes = ws.compute_modes(design, "balanced", fmax_hz=10000.0)
    contact_modes = seen_by_contact(design, modes)[1][:30]
    dofs = mode_dofs(excitable(modes), design)[:30]
    law = ws.contact_law(design)
    k_h = hertz_of(design).normal_stiffness_n_m
    op = ws.operating_point(design)
    one = median_seconds(lambda: r.coupled_stability(contact_modes, law, op, k_h), args.repeat)
    lateral = median_seconds(lambda: r.linear_stability(dofs, law, op), args.repeat)
    points = [
        r.OperatingPoint.from_rpm(rpm, design.wheel.rolling_radius, vc)
        for vc in np.linspace(0.0, 0.6, 50)
        for rpm in (400.0, 600.0, 800.0)
    ]
    envelope = median_seconds(lambda: [r.coupled_stability(contact_modes, law, p, k_h) for p in points], 3)
    print(f"design {design.name}: {len(contact_modes)} modes (two directions), {len(dofs)} modes (lateral)")
    print(f"coupled_stability, one point: {1e3 * one:.2f} ms (median of {args.repeat}); target < 50 ms")
    print(f"linear_stability (lateral), one point: {1e3 * lateral:.2f} ms (median of {args.repeat})")
    print(f"coupled_stability over 50 x 3 points: {envelope:.2f} s (median of 3); target < 1 s")


if __name__ == "__main__":
    main()
