"""A railway line at scale: curves of radius 100-3000 m (log-uniform, seeded) at 40 km/h
without cant, the shipped railway wheel, the default traffic and friction (four states),
the modes cached; the time per curve and how many squeal by radius class; with
``--compare``, the same curves at their own radii and on the radius grid of
``--radius-step``, and what the grid changes (probability, L_Aeq,day, the day's emission).

    .venv/bin/python benchmarks/bench_line.py [--curves 500] [--radius-step 0.1] [--compare]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import wheel_squeal as ws  # noqa: E402
from wheel_squeal.line import LineSpec, line, load_line  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--curves", type=int, default=500)
    ap.add_argument("--radius-step", type=float, default=0.0)
    ap.add_argument("--compare", action="store_true", help="also at the curves' own radii, and the changes")
    args = ap.parse_args()
    rng = np.random.default_rng(1)
    radii = np.exp(rng.uniform(np.log(100.0), np.log(3000.0), args.curves)).round(0)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "line.csv"
        rows = [f"c{i},{r:g},200,0,40" for i, r in enumerate(radii)]
        path.write_text("id,radius_m,length_m,cant_mm,train_speed_km_h\n" + "\n".join(rows) + "\n")
        curves = load_line(path)
    design = ws.load_design("railway_920_track")
    ctx = ws.RunContext.of("balanced")
    ws.curve(design, [150.0], [40.0], context=ctx)  # warm: the modes, the rail's fits
    t0 = time.perf_counter()
    results = line(design, curves, LineSpec(radius_step=args.radius_step), context=ctx)
    seconds = time.perf_counter() - t0
    if args.compare:
        exact = line(design, curves, LineSpec(), context=ctx)
        dp = max(abs(a.emission.probability - b.emission.probability) for a, b in zip(results, exact))
        both = [
            (a, b)
            for a, b in zip(results, exact)
            if a.emission.laeq_dba["day"] is not None and b.emission.laeq_dba["day"] is not None
        ]
        dl = max(
            (abs(a.emission.laeq_dba["day"] - b.emission.laeq_dba["day"]) for a, b in both),
            default=float("nan"),
        )
        where = f"grid {args.radius_step:g} against own radii"
        print(f"{where}: probability by up to {dp:.2f}; L_Aeq,day by up to {dl:.1f} dB ({len(both)} heard)")
    radii_count = len({c.radius_m for c in curves})
    per_curve = seconds / len(curves)
    head = f"{len(curves)} curves ({radii_count} radii) in 4 friction states"
    print(f"{head}: {seconds:.1f} s, {per_curve:.2f} s each")
    for lo, hi in ((100, 200), (200, 300), (300, 500), (500, 1000), (1000, 3001)):
        mine = [r for r in results if lo <= r.curve.radius_m < hi]
        squeal = [r for r in mine if r.emission.probability > 0]
        mean = np.mean([r.emission.probability for r in mine]) if mine else float("nan")
        print(f"R {lo}-{hi} m: {len(squeal)} of {len(mine)} curves squeal some of the time (mean {mean:.2f})")


if __name__ == "__main__":
    main()
