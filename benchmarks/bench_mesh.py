"""Meshing benchmark: median-of-3 wall time, nodes, elements and volume error of the
2-D profile and 3-D wheel meshes, P1 and P2, at the default and a fine size.

    .venv/bin/python benchmarks/bench_mesh.py [--design designs/table1.toml] [--repeat 3]
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from geometry import (  # noqa: E402
    mesh_profile,
    mesh_size,
    mesh_wheel,
    profile_area,
    revolved_volume,
)
from wheel_squeal import load_design  # noqa: E402


def run(design, dim: int, order: int, elements_through_web: int | None, repeat: int) -> dict:
    fn = mesh_profile if dim == 2 else mesh_wheel
    times, mesh = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        mesh = fn(design, elements_through_web=elements_through_web, order=order)
        times.append(time.perf_counter() - t0)
    if dim == 2:
        err = mesh.area() / profile_area(design) - 1
    else:
        err = mesh.volume() / revolved_volume(design) - 1
    return {
        "dim": dim,
        "order": order,
        "size_m": mesh_size(design, elements_through_web=elements_through_web, dim=dim),
        "label": "default" if elements_through_web is None else f"web/{elements_through_web}",
        "seconds": statistics.median(times),
        "nodes": mesh.n_nodes,
        "elements": mesh.n_elements,
        "rel_error": err,
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--design", default=None, help="design TOML (default: Table 1)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--json", action="store_true", help="print JSON instead of a table")
    args = ap.parse_args(argv)
    design = load_design(args.design).wheel
    rows = []
    for dim, fine in ((2, 8), (3, 2)):
        for order in (1, 2):
            for n in (None, fine):
                rows.append(run(design, dim, order, n, args.repeat))
    if args.json:
        print(json.dumps({"design": design.name, "results": rows}, indent=2))
        return 0
    print(f"design {design.name}: median of {args.repeat}")
    print(
        f"{'dim':>3} {'P':>2} {'size':>12} {'mm':>6} {'seconds':>8} {'nodes':>8} {'elements':>9} "
        f"{'rel.err':>9}"
    )
    for r in rows:
        print(
            f"{r['dim']:>3} {r['order']:>2} {r['label']:>12} {1e3 * r['size_m']:6.2f} "
            f"{r['seconds']:8.3f} {r['nodes']:8d} {r['elements']:9d} {r['rel_error']:+9.1e}"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
