"""A railway line at scale: curves of radius 100-3000 m (log-uniform, seeded) at 40 km/h
without cant, the shipped railway wheel, the default traffic and friction (four states), on
``--workers`` local processes with a new stage cache: the first line with everything to
compute (the modes, the squeals' radiation), then a second line of other radii with the
modes and the radiation solved so far in the cache (what a second line on the same wheel
costs); the time per curve beside the line's estimate (``wheel_squeal.plan.line_plan``)
and how many squeal by radius class; with ``--compare``, the
same curves at their own radii and on the radius grid of ``--radius-step``, and what the
grid changes (probability, L_Aeq,day, the day's emission).

    .venv/bin/python benchmarks/bench_line.py [--curves 500] [--workers 2] [--radius-step 0.1] [--compare]
"""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import wheel_squeal as ws  # noqa: E402
from wheel_squeal.line import LineSpec, line, load_line  # noqa: E402
from wheel_squeal.plan import line_plan  # noqa: E402
from wheel_squeal.runtime.stage_cache import StageCache  # noqa: E402


def _line(count: int, seed: int, folder: Path) -> list:
    rng = np.random.default_rng(seed)
    radii = np.exp(rng.uniform(np.log(100.0), np.log(3000.0), count)).round(0)
    path = folder / f"line{seed}.csv"
    rows = [f"c{i},{r:g},200,0,40" for i, r in enumerate(radii)]
    path.write_text("id,radius_m,length_m,cant_mm,train_speed_km_h\n" + "\n".join(rows) + "\n")
    return load_line(path)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--curves", type=int, default=500)
    ap.add_argument("--radius-step", type=float, default=0.0)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--compare", action="store_true", help="also at the curves' own radii, and the changes")
    args = ap.parse_args()
    design = ws.load_design("railway_920_track")
    spec = LineSpec(radius_step=args.radius_step)
    tmp = Path(tempfile.mkdtemp())
    ctx = ws.RunContext.of("balanced", cache=StageCache(tmp / "cache"))
    for seed, what in ((1, "first line, new cache"), (2, "second line, modes and radiation cached")):
        curves = _line(args.curves, seed, tmp)
        t0 = time.perf_counter()
        results = line(design, curves, spec, context=ctx, workers=args.workers)
        seconds = time.perf_counter() - t0
        estimate = line_plan(len(curves), len(spec.states()), args.workers).seconds
        print(
            f"{what}: {len(curves)} curves x 4 friction states on {args.workers} processes: "
            f"{seconds:.1f} s, {seconds / len(curves):.2f} s a curve (estimated {estimate:.0f} s, "
            f"{estimate / seconds:.2f}x)"
        )
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
    for lo, hi in ((100, 200), (200, 300), (300, 500), (500, 1000), (1000, 3001)):
        mine = [r for r in results if lo <= r.curve.radius_m < hi]
        squeal = [r for r in mine if r.emission.probability > 0]
        mean = np.mean([r.emission.probability for r in mine]) if mine else float("nan")
        print(f"R {lo}-{hi} m: {len(squeal)} of {len(mine)} curves squeal some of the time (mean {mean:.2f})")
    shutil.rmtree(tmp)


if __name__ == "__main__":
    main()
