"""Benchmark of the axisymmetric-harmonic solver on the Table 1 wheel.

For a few profile meshes (P2 elements across the web): median-of-5 wall time of
``solve_axisymmetric`` for all modes <= 5 kHz (meshing included), DOFs summed over
the harmonics, the (3,0) axial frequency and contact modal mass, and the largest
deviation of any mode <= 5 kHz from a fine reference (curved P2, 10 elements across the
web). Run: ``python benchmarks/bench_axisym.py [--reps 5] [--fmax 5000]``.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fem.axisym import solve_axisymmetric  # noqa: E402
from geometry.gmsh_mesh import mesh_profile  # noqa: E402
from wheel_squeal import load_design  # noqa: E402


def key(m):
    return (m.nodal_diameters, m.nodal_circles, m.family)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--fmax", type=float, default=5000.0)
    ap.add_argument("--ref-etw", type=int, default=10)
    ap.add_argument(
        "--design", type=Path, default=Path(__file__).resolve().parents[1] / "designs" / "table1.toml"
    )
    args = ap.parse_args(argv)
    d = load_design(args.design).wheel

    t = time.perf_counter()
    ref = solve_axisymmetric(
        d,
        mesh_profile(d, elements_through_web=args.ref_etw, order=2),
        curved=True,
        fmax_hz=args.fmax * 1.05,
        n_theta=8,
    )
    print(
        f"reference: curved P2, {args.ref_etw} elements across the web, {ref.dofs} DOFs, "
        f"{time.perf_counter() - t:.1f} s"
    )
    fref = {key(m): m.frequency_hz for m in ref.modes}
    mref = {key(m): m.modal_mass for m in ref.modes}
    k30 = (3, 0, "axial")

    print(
        f"\n{'etw':>3} {'curved':>6} {'DOFs':>7} {'modes':>5} {'median s':>9} {'min s':>7} "
        f"{'f(3,0) Hz':>10} {'m(3,0) kg':>9} {'max |df|/f':>10} {'dm(3,0)':>8}"
    )
    for etw in (1, 2, 3, 4, 6):
        for curved in (False, True):
            times = []
            for _ in range(args.reps):
                t = time.perf_counter()
                ms = solve_axisymmetric(
                    d, mesh_profile(d, elements_through_web=etw, order=2), curved=curved, fmax_hz=args.fmax
                )
                times.append(time.perf_counter() - t)
            errs = [abs(m.frequency_hz / fref[key(m)] - 1) for m in ms.modes]
            m3 = next(m for m in ms.modes if key(m) == k30)
            print(
                f"{etw:3d} {str(curved):>6} {ms.dofs:7d} {len(ms.modes):5d} "
                f"{statistics.median(times):9.3f} {min(times):7.3f} {m3.frequency_hz:10.2f} "
                f"{m3.modal_mass:9.4f} {100 * max(errs):9.3f}% "
                f"{100 * (m3.modal_mass / mref[k30] - 1):+7.3f}%"
            )

    ms = solve_axisymmetric(d, mesh_profile(d, order=1), fmax_hz=args.fmax)
    print(
        f"\nTable 1 modes (default mesh, {ms.dofs} DOFs, timings "
        + ", ".join(f"{k} {v:.3f} s" for k, v in ms.timings_s.items())
        + ")"
    )
    print(f"{'f [Hz]':>9} {'n':>3} {'c':>3} {'family':<16} {'m [kg]':>10} {'k [N/m]':>10}")
    for m in ms.modes:
        print(
            f"{m.frequency_hz:9.1f} {m.nodal_diameters:3d} {m.nodal_circles:3d} "
            f"{m.family:<16} {m.modal_mass:10.4g} {m.modal_stiffness:10.4g}"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
