"""The curve command's speed: railway_920 on the test track, 20 curve radii x 5 train
speeds x the 4 wheels of its bogie (the steady curving, each contact's verdict,
harmonic-balance amplitude, sound and pass-by level of every wheel) with a warm cache (the
FE modes on disk, the squeal modes' radiation kept in the run), target under 30 s; against
the same 400 wheel cases run one by one (each its own curving, analyses, amplitude and
pass-by). Medians of repeated runs in the same process.

    .venv/bin/python benchmarks/bench_curve.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from bench_coupling import median_seconds  # noqa: E402  (the same medians, a script beside this one)

import wheel_squeal as ws  # noqa: E402
from acoustics.passby import passby  # noqa: E402
from track.bogie_curving import steady_curving  # noqa: E402
from wheel_squeal.curve import CurveCase, axle_sound, bogie_sources, contact_geometry, wheel_sites  # noqa: E402

RADII_M = tuple(float(r) for r in np.round(np.geomspace(100.0, 2000.0, 20)))
SPEEDS_KM_H = (20.0, 30.0, 40.0, 50.0, 60.0)  # within 3 m/s^2 unbalanced at 100 m


def one_by_one(design: ws.Design, ctx: ws.RunContext) -> int:
    """Every wheel case as its own request; returns how many squeal."""
    options = ws.ChainOptions(mode="model", stop_after="sound", remedy=False, amplitude="harmonic balance")
    vehicle = design.vehicle.vehicle()
    geometry = contact_geometry(design)  # the wheel on its rail once: a profile's table, not a request's
    squealing = 0
    for radius in RADII_M:
        for speed in SPEEDS_KM_H:
            for index in range(4):
                wheel = steady_curving(
                    geometry,
                    vehicle,
                    radius,
                    speed,
                    wheel_load_n=design.contact.normal_load,
                    friction_coefficient=design.contact.friction_coefficient,
                )[index]
                sites = wheel_sites(design, wheel, speed)
                analyses = tuple(ws.analyse(s.design, op=s.op, options=options, context=ctx) for s in sites)
                states = tuple(s.state for s in sites)
                case = CurveCase(radius, speed, wheel, analyses, states=states)
                sound = axle_sound(case.analysis)
                if sound is not None:
                    case = CurveCase(radius, speed, wheel, analyses, sound, states=states)
                sources, _ = bogie_sources([case], vehicle.wheelbase_m, design.rolling_radius)
                if sources:
                    passby(sources, speed / 3.6)
                    squealing += 1
    return squealing


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    design = ws.load_design("railway_920_track")
    ctx = ws.RunContext.of("balanced")
    ws.curve(design, RADII_M[:1], SPEEDS_KM_H[:1], context=ctx)  # warm: modes, fits, radiation
    cases: list = []

    def row() -> None:
        cases[:] = ws.curve(design, RADII_M, SPEEDS_KM_H, context=ctx)

    t_row = median_seconds(row, args.repeat)
    n = len(cases)
    heard = sum(c.analysis.verdict.squeals for c in cases)
    t_one = median_seconds(lambda: one_by_one(design, ctx), args.repeat)
    print(
        f"railway_920 on the test track: {len(RADII_M)} radii x {len(SPEEDS_KM_H)} speeds x 4 wheels "
        f"= {n} cases, {heard} squeal"
    )
    print(f"curve, warm cache: {t_row:.1f} s (median of {args.repeat}); target < 30 s")
    print(f"the same cases one by one: {t_one:.1f} s; ratio {t_one / t_row:.1f}")


if __name__ == "__main__":
    main()
