"""Benchmark of the wheel modal solvers on the Table 1 wheel (one run, one table).

1. Wall time and DOFs, all modes <= 5 kHz, on the same curved P2 mesh (41k DOFs;
   ``--full`` adds the 85k-DOF mesh), medians of ``--reps`` runs with the baseline and
   the chosen path interleaved (the machine is shared: same load for both):
   - axisymmetric-harmonic solver (``fem.axisym.solve_axisymmetric``, default mesh);
   - baseline: scikit-fem assembly (``linear_elasticity``) + plain
     ``scipy.sparse.linalg.eigsh(K, k, M, sigma=0)`` (SuperLU, SciPy's default COLAMD
     ordering, default threads), given the number of modes in the band so it runs once;
     the same eigsh on one BLAS thread once, for reference;
   - chosen path: ``fem.solid.solve_solid`` (vectorised assembly, ``solve_eigen`` with
     ``factorization="auto"``, labels), with its assembly and eigen times;
   - ``fem.eigen.solve_eigen`` with each available factorisation on the same matrices.
   Ratios: eigen-solve alone, assembly + eigen-solve, and the whole path (baseline
   total = its assembly + eigsh + the same mesh and labelling time as the chosen path).
2. Convergence (skip with ``--no-convergence``): 3-D P2 (curved) at several mesh sizes
   vs the converged axisymmetric solution (curved P2, 8 elements across the web):
   relative difference of every mode below 3 kHz, and of the (3,0) axial contact modal
   mass.

Run: ``python benchmarks/bench_modes.py [--full] [--reps 3] [--no-convergence]
[--quick]``. ``--quick``: one repetition, no per-factorisation rows, coarse
convergence only.
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
from threadpoolctl import threadpool_limits  # noqa: E402

from fem.eigen import auto_factorization, available_factorizations, solve_eigen  # noqa: E402
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
    tag = f"[{h * 1e3:g} mm]"
    band = fmax * (1 + PAIR_RTOL)  # exactly what solve_solid does: band padded by PAIR_RTOL

    def baseline(threads=None):
        t = time.perf_counter()
        model = assemble(d, mesh.points, mesh.tetra, order=2, fast=False)
        K = model.K[model.free][:, model.free].tocsr()
        M = model.M[model.free][:, model.free].tocsr()
        t_asm = time.perf_counter() - t
        nd = K.shape[0]
        t = time.perf_counter()
        v0 = np.ones(nd) / math.sqrt(nd)
        if threads is None:
            vals, _ = spla.eigsh(K, k=nev, M=M, sigma=0.0, which="LM", v0=v0)
        else:
            with threadpool_limits(limits=threads):
                vals, _ = spla.eigsh(K, k=nev, M=M, sigma=0.0, which="LM", v0=v0)
        return t_asm, time.perf_counter() - t, np.sort(vals), K, M

    # the chosen path once first: number of eigenpairs in the padded band (for eigsh)
    first = solve_solid(d, mesh, order=2, fmax_hz=fmax)
    model = assemble(d, mesh.points, mesh.tetra, order=2)
    K = model.K[model.free][:, model.free].tocsr()
    M = model.M[model.free][:, model.free].tocsr()
    ref = solve_eigen(K, M, fmax_hz=band, factorization="auto", guess=eigen_guess(band))
    nev = len(ref.eigenvalues)
    nd = K.shape[0]

    base, chosen = [], []
    for _ in range(reps):  # interleaved: same load for both
        base.append(baseline()[:3])
        t = time.perf_counter()
        ms = solve_solid(d, mesh, order=2, fmax_hz=fmax)
        chosen.append((ms.timings_s["assemble"], ms.timings_s["eigen"], ms.timings_s["label"],
                       ms.timings_s["mesh"], time.perf_counter() - t))
    med = statistics.median
    b_asm, b_eig = med(b[0] for b in base), med(b[1] for b in base)
    c_asm, c_eig = med(c[0] for c in chosen), med(c[1] for c in chosen)
    c_lab, c_tot = med(c[2] for c in chosen), med(c[4] for c in chosen)
    dev = max(np.max(np.abs(b[2] - ref.eigenvalues) / ref.eigenvalues) for b in base)
    fa = auto_factorization(nd, definite=True)
    rows.append((f"3-D P2 {tag} baseline: skfem assembly", nd, b_asm, reps, nev))
    rows.append((f"3-D P2 {tag} baseline: eigsh + SuperLU/COLAMD (plain)", nd, b_eig, reps, nev))
    _, t1, _, _, _ = baseline(threads=1)
    rows.append((f"3-D P2 {tag} (eigsh + SuperLU/COLAMD, 1 BLAS thread)", nd, t1, 1, nev))
    rows.append((f"3-D P2 {tag} chosen: vectorised assembly", nd, c_asm, reps, nev))
    rows.append((f"3-D P2 {tag} chosen: solve_eigen auto (= {fa})", nd, c_eig, reps, nev))
    rows.append((f"3-D P2 {tag} chosen: solve_solid total (mesh given)", nd, c_tot, reps, len(first.modes)))
    if not quick:
        for name in available_factorizations():
            t_e, res, n = timed(
                lambda: solve_eigen(K, M, fmax_hz=band, factorization=name, guess=eigen_guess(band)), 1
            )
            rows.append((f"3-D P2 {tag} solve_eigen {name}", nd, t_e, n, len(res.eigenvalues)))
    b_tot = b_asm + b_eig + (c_tot - c_asm - c_eig)
    line = (f"{tag} {nd} DOFs, {nev} eigenpairs: chosen path vs plain eigsh+SuperLU: eigen-solve "
            f"{b_eig / c_eig:.1f}x ({b_eig:.1f} s -> {c_eig:.1f} s; vs 1-thread eigsh {t1 / c_eig:.1f}x), "
            f"assembly {b_asm / c_asm:.1f}x, assembly + eigen {(b_asm + b_eig) / (c_asm + c_eig):.1f}x, "
            f"whole solve_solid {b_tot / c_tot:.1f}x ({b_tot:.1f} s -> {c_tot:.1f} s); eigenvalues "
            f"agree to {dev:.1e}")
    return rows, line


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="one repetition, fewer rows and meshes")
    ap.add_argument("--full", action="store_true", help="add the 85k-DOF mesh (size 10 mm)")
    ap.add_argument("--no-convergence", action="store_true", help="timing section only")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--fmax", type=float, default=5000.0)
    ap.add_argument("--sizes", type=float, nargs="*", default=None,
                    help="3-D mesh sizes for the timing [m] (default 0.015; --full: 0.015 0.01)")
    args = ap.parse_args(argv)
    reps = 1 if args.quick else args.reps
    d = WheelDesign()
    print(f"factorisations available: {', '.join(available_factorizations())}")

    # ---------------------------------------------------------------- 1. timing
    rows = []
    if solve_axisymmetric is not None:
        t_ax, ax, n = timed(lambda: solve_axisymmetric(d, fmax_hz=args.fmax), max(reps, 3))
        rows.append(("axisymmetric (default mesh, all n, incl. meshing)", ax.dofs, t_ax, n, len(ax.modes)))

    sizes_t = args.sizes or ([0.015, 0.01] if args.full else [0.015])
    summary = []
    for h in sizes_t:
        rows_h, line = time_3d(d, h, args.fmax, reps, args.quick)
        rows += rows_h
        summary.append(line)

    print(f"\n## Wall time, all modes <= {args.fmax:g} Hz (median of n runs)")
    print(f"{'solver':<62} {'DOFs':>8} {'time s':>8} {'n':>2} {'modes':>5}")
    for label, dofs, t_s, n, nm in rows:
        print(f"{label:<62} {dofs:8d} {t_s:8.2f} {n:2d} {nm:5d}")
    for line in summary:
        print(line)
    if args.no_convergence:
        return 0

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


if __name__ == "__main__":
    raise SystemExit(main())
