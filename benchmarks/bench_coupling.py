"""The linear stability with the contact in both directions (the Hertz spring, the
friction's stiffness coupling, each eigenvalue's mechanism) of 30 FE modes at a moved
contact, against the same modes with a constant normal load (the lateral model): one
point, and an envelope of 50 crabbing velocities x 3 speeds. Medians of repeated runs,
measured in the same process.

    .venv/bin/python benchmarks/bench_coupling.py [--design NAME] [--angle DEG] [--repeat 7]
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

import reduced as r  # noqa: E402
import wheel_squeal as ws  # noqa: E402
from wheel_squeal.mode_stability import body_of, excitable, mode_dofs  # noqa: E402

#: the modes the benchmark takes (the issue's size)
MODES = 30


def median_seconds(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--design", default="table1_crowned")
    ap.add_argument("--angle", type=float, default=15.0, help="contact angle [deg]")
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args()
    design = ws.load_design(args.design).replace(contact_angle=math.radians(args.angle))
    law = ws.contact_law(design)
    modes = ws.compute_modes(design, "balanced", fmax_hz=12000.0)
    dofs = mode_dofs(excitable(modes, law)[:MODES], design)
    body = body_of(design)
    normal = sum(d.normal != 0.0 for d in dofs)
    constant = dataclasses.replace(law, hertz_approach_m=math.inf)
    op = ws.operating_point(design)
    both = median_seconds(lambda: r.linear_stability(dofs, law, op, body=body), args.repeat)
    lateral = median_seconds(lambda: r.linear_stability(dofs, constant, op, body=body), args.repeat)
    points = [
        r.OperatingPoint.from_rpm(rpm, design.rolling_radius, vc)
        for vc in np.linspace(0.0, 0.6, 50)
        for rpm in (400.0, 600.0, 800.0)
    ]
    envelope = median_seconds(lambda: [r.linear_stability(dofs, law, p, body=body) for p in points], 3)
    grid = median_seconds(
        lambda: r.stability_map(
            dofs, law, np.linspace(0.0, 0.6, 50), [p.rolling_speed_m_s for p in points[:3]]
        ),
        3,
    )
    res = r.linear_stability(dofs, law, op, body=body)
    mechanisms = sorted({m for m in res.mechanisms if m})
    print(
        f"design {design.name} at {args.angle:g} deg: {len(dofs)} modes, {normal} move the contact normally"
    )
    print(f"growing eigenvalues: {sum(m is not None for m in res.mechanisms)} ({', '.join(mechanisms)})")
    print(
        f"linear_stability, both directions, one point: {1e3 * both:.2f} ms (median of {args.repeat}); ",
        end="",
    )
    print("target < 50 ms")
    print(
        f"linear_stability, constant normal load, one point: {1e3 * lateral:.2f} ms (median of {args.repeat})"
    )
    print(
        f"linear_stability over 50 x 3 points (mechanisms too): {envelope:.2f} s (median of 3); target < 1 s"
    )
    print(f"stability_map over 50 x 3 points: {grid:.2f} s (median of 3)")


if __name__ == "__main__":
    main()
