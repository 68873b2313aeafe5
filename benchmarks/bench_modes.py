"""Benchmark of the wheel modal solvers on the Table 1 wheel (one run, one table).

1. Wall time and DOFs, all modes <= 5 kHz:
   - axisymmetric-harmonic solver (``fem.axisym.solve_axisymmetric``, default mesh);
   - 3-D P2 eigen-solve with plain ``scipy.sparse.linalg.eigsh(K, k, M, sigma=0)``
     (SuperLU, SciPy's default COLAMD ordering, default threads), given the number of
     modes in the band so it runs once;
   - 3-D P2 with ``fem.eigen.solve_eigen`` and each factorisation (``auto`` is the
     chosen path), on the same matrices; and the whole ``solve_solid`` (mesh, assembly,
     eigen, labels).
2. Convergence: 3-D P2 (curved) at several mesh sizes vs the converged axisymmetric
   solution (curved P2, 8 elements across the web): relative difference of every mode
   below 3 kHz, and of the (3,0) axial contact modal mass.

Run: ``python benchmarks/bench_modes.py [--quick] [--reps 3]``. ``--quick`` does one
repetition, skips the slow baselines on larger meshes and the finest 3-D meshes.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402
import scipy.sparse.linalg as spla  # noqa: E402

from fem.eigen import available_factorizations, solve_eigen  # noqa: E402
from fem.solid import PAIR_RTOL, assemble, eigen_guess, solve_solid  # noqa: E402
from geometry.design import WheelDesign  # noqa: E402
from geometry.mesh import mesh_profile, mesh_wheel  # noqa: E402

try:
    from fem.axisym import solve_axisymmetric  # noqa: E402
except ImportError:  # pragma: no cover - lands separately
    solve_axisymmetric = None


def key(m):
    return (m.nodal_diameters, m.nodal_circles, m.family)


def timed(fn, reps):
    times, out = [], None
    for _ in range(reps):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), out, len(times)


def time_3d(d, h, fmax, reps, quick):
    """Timing rows of the 3-D solvers on one curved P2 mesh of size h."""
    rows = []
    mesh = mesh_wheel(d, size=h, order=2)
    t = time.perf_counter()
    model = assemble(d, mesh.points, mesh.tetra, order=2)
    t_asm = time.perf_counter() - t
    K = model.K[model.free][:, model.free].tocsr()
    M = model.M[model.free][:, model.free].tocsr()
    nd = K.shape[0]
    tag = f"[{h * 1e3:g} mm]"
    results = {}
    for name in ["auto"] + available_factorizations():
        r = reps if name == "auto" else 1
        # exactly what solve_solid does: band padded by PAIR_RTOL, first-run guess
        band = fmax * (1 + PAIR_RTOL)
        t_e, res, n = timed(
            lambda: solve_eigen(K, M, fmax_hz=band, factorization=name, guess=eigen_guess(band)), r
        )
        results[name] = (t_e, res, n)
    t_auto, ref, _ = results["auto"]
    nev = len(ref.eigenvalues)  # eigenpairs in the (padded) band

    def plain():
        v0 = np.ones(nd) / math.sqrt(nd)
        return spla.eigsh(K, k=nev, M=M, sigma=0.0, which="LM", v0=v0)

    t_plain, (vals, _), n_plain = timed(plain, 1 if quick else min(reps, 2))
    dev = np.max(np.abs(np.sort(vals) - ref.eigenvalues) / ref.eigenvalues)
    rows.append((f"3-D P2 {tag} eigsh + SuperLU/COLAMD (plain)", nd, t_plain, n_plain, nev))
    for name, (t_e, res, n) in results.items():
        label = f"3-D P2 {tag} solve_eigen " + (f"auto (= {_auto_name()})" if name == "auto" else name)
        rows.append((label, nd, t_e, n, len(res.eigenvalues)))
    t_full, full, n_full = timed(lambda: solve_solid(d, mesh, order=2, fmax_hz=fmax), reps)
    rows.append((f"3-D P2 {tag} solve_solid (assembly {t_asm:.1f} s + eigen + labels)", full.dofs,
                 t_full, n_full, len(full.modes)))
    line = (f"{tag} {nd} DOFs: chosen path {t_plain / t_auto:.1f}x faster than plain "
            f"eigsh+SuperLU (eigen-solve), {(t_plain + t_asm) / t_full:.1f}x incl. assembly and "
            f"labels; eigenvalues agree to {dev:.1e}")
    return rows, line


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="one repetition, fewer meshes")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--fmax", type=float, default=5000.0)
    ap.add_argument("--sizes", type=float, nargs="*", default=None,
                    help="3-D mesh sizes for the timing [m] (default 0.015 0.01; quick: 0.015)")
    args = ap.parse_args(argv)
    reps = 1 if args.quick else args.reps
    d = WheelDesign()
    print(f"factorisations available: {', '.join(available_factorizations())}")

    # ---------------------------------------------------------------- 1. timing
    rows = []
    if solve_axisymmetric is not None:
        t_ax, ax, n = timed(lambda: solve_axisymmetric(d, fmax_hz=args.fmax), max(reps, 3))
        rows.append(("axisymmetric (default mesh, all n)", ax.dofs, t_ax, n, len(ax.modes)))

    sizes_t = [0.015] if args.quick else (args.sizes or [0.015, 0.01])
    summary = []
    for h in sizes_t:
        rows_h, line = time_3d(d, h, args.fmax, reps, args.quick)
        rows += rows_h
        summary.append(line)

    print(f"\n## Wall time, all modes <= {args.fmax:g} Hz (median of n runs; eigen-solve only "
          "unless stated)")
    print(f"{'solver':<58} {'DOFs':>8} {'time s':>8} {'n':>2} {'modes':>5}")
    for label, dofs, t_s, n, nm in rows:
        print(f"{label:<58} {dofs:8d} {t_s:8.2f} {n:2d} {nm:5d}")
    for line in summary:
        print(line)

    # ---------------------------------------------------------- 2. convergence
    if solve_axisymmetric is None:
        print("\n(fem.axisym not available: convergence section skipped)")
        return 0
    etw_ref = 8
    t = time.perf_counter()
    axr = solve_axisymmetric(d, mesh_profile(d, elements_through_web=etw_ref, order=2), curved=True,
                             fmax_hz=3100.0, n_theta=8)
    print(f"\n## Convergence vs axisymmetric reference (curved P2, {etw_ref} elements across "
          f"the web, {axr.dofs} DOFs, {time.perf_counter() - t:.1f} s), modes < 3 kHz")
    fref = {key(m): m.frequency_hz for m in axr.modes if m.frequency_hz < 3000}
    k30 = (3, 0, "axial")
    m30 = next(m for m in axr.modes if key(m) == k30).modal_mass
    sizes = [0.015] if args.quick else [0.015, 0.01, 0.0075]
    per_mode = {}
    print(f"{'size mm':>7} {'DOFs':>7} {'time s':>7} {'modes':>5} {'max |df/f|':>10} "
          f"{'mean df/f':>9} {'f(3,0) Hz':>9} {'dm(3,0)':>8} labels")
    for h in sizes:
        t = time.perf_counter()
        ms = solve_solid(d, mesh_wheel(d, size=h, order=2), order=2, fmax_hz=3000.0)
        tt = time.perf_counter() - t
        got = {key(m): m for m in ms.modes}
        same = sorted(got) == sorted(fref)
        rel = {k: got[k].frequency_hz / f - 1 for k, f in fref.items() if k in got}
        per_mode[h] = rel
        s30 = got[k30]
        print(f"{h * 1e3:7.1f} {ms.dofs:7d} {tt:7.1f} {len(ms.modes):5d} "
              f"{max(abs(v) for v in rel.values()):10.3%} {np.mean(list(rel.values())):9.3%} "
              f"{s30.frequency_hz:9.2f} {s30.modal_mass / m30 - 1:+8.3%} "
              f"{'same' if same else 'DIFFER'}")
    print("\nper mode (relative difference 3-D - axisym):")
    print(f"{'mode':<24} {'axisym Hz':>9} " + " ".join(f"{h * 1e3:>7.1f}mm" for h in sizes))
    for k, f in sorted(fref.items(), key=lambda kv: kv[1]):
        cells = " ".join(f"{per_mode[h].get(k, float('nan')):+9.3%}" for h in sizes)
        print(f"({k[0]},{k[1]}) {k[2]:<18} {f:9.1f} {cells}")
    print(f"(3,0) axial contact modal mass, axisym reference: {m30:.4f} kg")
    return 0


def _auto_name() -> str:
    from fem.eigen import AUTO_ORDER

    avail = available_factorizations()
    return next(n for n in AUTO_ORDER if n in avail)


if __name__ == "__main__":
    raise SystemExit(main())
