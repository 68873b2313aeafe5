"""The rail in the squeal model: the linear stability of 30 FE modes of railway_920 on the
test track (the rail's fitted terms in series at the contact) against the same modes on
a rigid rail with the same contact, one point each (target: under 50 ms with the rail);
and what the track costs once per design: the receptances and their fits. Medians of
repeated runs, measured in the same process.

    .venv/bin/python benchmarks/bench_track.py [--repeat 7]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from bench_coupling import median_seconds  # noqa: E402  (the same medians, a script beside this one)

import reduced as r  # noqa: E402
import wheel_squeal as ws  # noqa: E402
from wheel_squeal.mode_stability import body_of, excitable, mode_dofs  # noqa: E402

#: the modes the benchmark takes (the issue's size)
MODES = 30


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args()
    design = ws.load_design("railway_920_track")
    law = ws.contact_law(design)
    modes = excitable(ws.compute_modes(design, "balanced", fmax_hz=6000.0), law)[:MODES]
    op = ws.operating_point(design, rolling_speed_m_s=11.1, crabbing_velocity_m_s=0.111)
    t0 = time.perf_counter()
    fits = design.counter_body.fits()  # the first call fits (then it is kept in the process)
    first = time.perf_counter() - t0
    dofs = mode_dofs(modes, design)
    body = body_of(design)
    on_rail = median_seconds(lambda: r.linear_stability(dofs, law, op, body=body), args.repeat)
    on_rigid = median_seconds(lambda: r.linear_stability(dofs, law, op), args.repeat)
    states = body.states if body is not None else 0
    print(
        f"railway_920 on the test track: {len(modes)} modes, the rail's state space of {states} states "
        f"({len(fits[0].poles)} vertical, {len(fits[1].poles)} lateral poles; weighted errors "
        f"{fits[0].weighted_error:.2%} and {fits[1].weighted_error:.2%})"
    )
    print(f"the track's receptances and fits, once per design: {first:.2f} s")
    print(
        f"linear_stability, one point, with the rail: {on_rail * 1e3:.1f} ms (median of {args.repeat}); "
        "target < 50 ms"
    )
    print(f"linear_stability, one point, rigid rail: {on_rigid * 1e3:.1f} ms; ratio {on_rail / on_rigid:.1f}")


if __name__ == "__main__":
    main()
