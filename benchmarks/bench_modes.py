"""Benchmark of the wheel modal solvers on the Table 1 wheel (one run, one table).

1. Wall time and DOFs, all modes <= 5 kHz (``--fmax``), medians of ``n`` runs:
   - axisymmetric-harmonic solver (``fem.axisym.solve_axisymmetric``, default mesh,
     meshing included);
   - on ONE cyclic curved P2 (tetra10) mesh of the whole wheel
     (``geometry.revolve.revolve_profile`` of ``mesh_profile(elements_through_web=1,
     order=2)`` in N = 48 sectors, ~45k DOFs; ``--full`` adds N = 96, ~90k DOFs), the
     mesh given to every solver (its meshing time is printed apart):
     * baseline: scikit-fem form assembly of the full mesh (``fem.solid.assemble(...,
       fast=False)``) + plain ``scipy.sparse.linalg.eigsh(K, k=nev, M=M, sigma=0,
       which="LM", v0=fixed)`` (SuperLU, SciPy's default COLAMD ordering, default
       threads), with nev = the number of eigenvalues in the band padded by
       ``fem.solid.PAIR_RTOL`` (a pair counts twice; taken from the chosen path's
       result, so eigsh runs once);
     * chosen path: ``fem.cyclic.solve_cyclic`` (cyclic symmetry: one small problem per
       harmonic), total and its assemble / eigen / label split;
     * middle reference: ``fem.solid.solve_solid`` on the same mesh (full matrices,
       vectorised assembly, ``solve_eigen`` with the fastest factorisation);
     baseline, chosen path and solve_solid runs are interleaved (same machine load);
     the slow baseline and solve_solid run fewer times (``--base-reps``; the ``n``
     column says how many). Summary: eigen-solve ratio, whole-path ratio (baseline
     whole = skfem assembly + eigsh, no labels; chosen = solve_cyclic total with
     labels) and the largest relative difference between eigsh's eigenvalues and the
     cyclic ones (each cyclic pair counted twice): the same problem, so ~1e-10.
   - unstructured check: ``solve_solid`` on the gmsh tetra10 mesh
     (``mesh_wheel(size=0.015, order=2)``, ~41k DOFs), one or two runs, no ratio.
2. Convergence (skip with ``--no-convergence``), vs the converged axisymmetric
   solution (curved P2, 8 elements across the web): a cyclic 3-D P2 ladder
   (elements across the web 1, 2, 4 with N = ``fem.cyclic.default_sectors`` and,
   for 1 and 2, N doubled): mesh and solve time, DOFs, max and mean relative
   difference of every mode below 3 kHz (and max below 5 kHz), the (3,0) axial
   contact modal mass, whether the labels agree, a per-mode table; then the
   axisymmetric solver as timed in 1 vs the finest 3-D rung over all modes <= 5 kHz
   (the "within 0.5 % of the converged 3-D frequencies" target). ``--tet`` adds the
   gmsh unstructured tetra10 ladder (15, 10, 7.5 mm; slow: minutes).

Run: ``python benchmarks/bench_modes.py [--quick] [--full] [--reps 3] [--base-reps N]
[--no-convergence] [--tet] [--design FILE]`` (default design ``WheelDesign()``: Table 1
values with the 30 mm rim depth; ``designs/table1.toml``, what ``run_all.py`` uses, has
the calibrated 33.5 mm rim and ~6 % more DOFs on the same mesh settings). ``--quick``: one repetition,
convergence ladder
elements-across-web 1 and 2 only (and the 15 mm tet mesh with ``--tet``): a smoke
test, not figures to quote.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402
import scipy.sparse.linalg as spla  # noqa: E402

from fem.cyclic import default_sectors, solve_cyclic  # noqa: E402
from fem.eigen import available_factorizations  # noqa: E402
from fem.solid import PAIR_RTOL, assemble, solve_solid  # noqa: E402
from geometry import mesh_profile, mesh_wheel, revolve_profile  # noqa: E402
from wheel_squeal import load_design  # noqa: E402

try:
    from fem.axisym import solve_axisymmetric  # noqa: E402
except ImportError:  # pragma: no cover - lands separately
    solve_axisymmetric = None

K30 = (3, 0, "axial")
med = statistics.median


def key(m):
    return (m.nodal_diameters, m.nodal_circles, m.family)


def timed(fn, reps):
    times, out = [], None
    for _ in range(reps):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return med(times), out, len(times)


def cyclic_mesh(d, etw, n_sectors=None):
    """Curved P2 cyclic mesh (profile with ``etw`` elements across the web, revolved in
    ``n_sectors``, default :func:`default_sectors`) and its meshing time."""
    t = time.perf_counter()
    prof = mesh_profile(d, elements_through_web=etw, order=2)
    n = n_sectors or default_sectors(d, prof.size)
    mesh = revolve_profile(prof, n)
    return mesh, time.perf_counter() - t


def eigenvalue_list(ms, n_sectors):
    """Sorted eigenvalues (2 pi f)^2 of the full problem from cyclic modes: a pair
    (0 < n < N/2) counts twice."""
    lam = []
    for m in ms.modes:
        real = m.nodal_diameters == 0 or 2 * m.nodal_diameters == n_sectors
        lam += [(2 * math.pi * m.frequency_hz) ** 2] * (1 if real else 2)
    return np.sort(np.array(lam))


# ---------------------------------------------------------------------------- timing
def eigsh_baseline(design, mesh, nev: int):
    """The baseline on ``mesh``: scikit-fem form assembly of the whole wheel and a plain
    ``eigsh(K, nev, M, sigma=0)`` (SciPy's SuperLU with COLAMD, fixed start vector).
    Returns (assembly s, eigen-solve s, sorted eigenvalues, free DOFs)."""
    t = time.perf_counter()
    model = assemble(design, mesh.points, mesh.tetra, order=2, fast=False)
    K = model.K[model.free][:, model.free].tocsr()
    M = model.M[model.free][:, model.free].tocsr()
    t_asm = time.perf_counter() - t
    n = K.shape[0]
    t = time.perf_counter()
    vals, _ = spla.eigsh(K, k=nev, M=M, sigma=0.0, which="LM", v0=np.ones(n) / math.sqrt(n))
    return t_asm, time.perf_counter() - t, np.sort(vals), n


def time_cyclic(d, etw, n_sectors, fmax, reps, base_reps):
    """Timing rows on one cyclic mesh: baseline (skfem + plain eigsh), chosen
    (solve_cyclic), solve_solid, all on the same mesh."""
    mesh, t_mesh = cyclic_mesh(d, etw, n_sectors)
    N = mesh.n_sectors
    tag = f"[{etw}/web, N={N}]"
    band = fmax * (1 + PAIR_RTOL)  # padded like solve_solid's band
    # the chosen path on the padded band, untimed: the eigenvalues eigsh must find
    ref = solve_cyclic(d, mesh, fmax_hz=band)
    lam_c = eigenvalue_list(ref, N)
    nev = len(lam_c)
    nd = ref.dofs
    n_base = base_reps if base_reps is not None else (reps if nd < 60_000 else 1)
    n_base = max(1, min(reps, n_base))

    def baseline():
        return eigsh_baseline(d, mesh, nev)

    def chosen():
        t = time.perf_counter()
        ms = solve_cyclic(d, mesh, fmax_hz=fmax)
        wall = time.perf_counter() - t
        ts = ms.timings_s
        return (ts["assemble"], ts["eigen"], ts["label"], wall), ms

    base, cyc, sol = [], [], []
    ms_c = ms_s = None
    for i in range(reps):  # interleaved: the same load for all
        if i < n_base:
            base.append(baseline())
        c, ms_c = chosen()
        cyc.append(c)
        if i < n_base:
            t = time.perf_counter()
            ms_s = solve_solid(d, mesh, order=2, fmax_hz=fmax)
            ts = ms_s.timings_s
            sol.append((ts["assemble"], ts["eigen"], ts["label"], time.perf_counter() - t))
        c, ms_c = chosen()
        cyc.append(c)
    if base[0][3] != nd:
        raise RuntimeError(f"DOF mismatch: eigsh {base[0][3]} vs cyclic {nd}")
    b_asm, b_eig = med(b[0] for b in base), med(b[1] for b in base)
    c_asm, c_eig, c_lab, c_tot = (med(c[j] for c in cyc) for j in range(4))
    s_asm, s_eig, s_lab, s_tot = (med(s[j] for s in sol) for j in range(4))
    dev = max(float(np.max(np.abs(b[2] - lam_c) / lam_c)) for b in base)
    fc = np.sort([m.frequency_hz for m in ms_c.modes])
    fs = np.sort([m.frequency_hz for m in ms_s.modes])
    dev_s = float(np.max(np.abs(fs / fc - 1))) if len(fs) == len(fc) else float("nan")
    nm, ns, nc = len(ms_c.modes), len(sol), len(cyc)
    rows = [
        (f"3-D P2 {tag} meshing (profile + revolve), not in the rows below", nd, t_mesh, 1, nm),
        (f"3-D P2 {tag} baseline: skfem form assembly", nd, b_asm, n_base, nev),
        (f"3-D P2 {tag} baseline: eigsh + SuperLU/COLAMD (plain)", nd, b_eig, n_base, nev),
        (f"3-D P2 {tag} baseline: whole (assembly + eigsh)", nd, b_asm + b_eig, n_base, nev),
        (f"3-D P2 {tag} solve_solid: vectorised assembly", nd, s_asm, ns, len(ms_s.modes)),
        (f"3-D P2 {tag} solve_solid: solve_eigen auto", nd, s_eig, ns, len(ms_s.modes)),
        (f"3-D P2 {tag} solve_solid total (mesh given)", nd, s_tot, ns, len(ms_s.modes)),
        (f"3-D P2 {tag} chosen: solve_cyclic sector assembly", nd, c_asm, nc, nm),
        (f"3-D P2 {tag} chosen: solve_cyclic eigen (all harmonics)", nd, c_eig, nc, nm),
        (f"3-D P2 {tag} chosen: solve_cyclic labels", nd, c_lab, nc, nm),
        (f"3-D P2 {tag} chosen: solve_cyclic total (mesh given)", nd, c_tot, nc, nm),
    ]
    b_tot = b_asm + b_eig
    line = (
        f"{tag} {nd} DOFs, {nev} eigenvalues <= {band:g} Hz ({nm} modes <= {fmax:g} Hz): "
        f"solve_cyclic vs plain eigsh+SuperLU/COLAMD on the same mesh: eigen-solve "
        f"{b_eig / c_eig:.0f}x ({b_eig:.1f} s -> {c_eig:.2f} s), whole path {b_tot / c_tot:.0f}x "
        f"({b_tot:.1f} s skfem assembly + eigsh -> {c_tot:.2f} s solve_cyclic incl. labels); "
        f"vs solve_solid {s_tot / c_tot:.0f}x ({s_tot:.1f} s); eigsh eigenvalues = cyclic to "
        f"{dev:.1e} (max rel.), solve_solid frequencies to {dev_s:.1e}; baseline and "
        f"solve_solid: median of {n_base} run(s) (slow), solve_cyclic of {nc}"
    )
    return rows, line


def time_tet(d, h, fmax, n):
    """The unstructured check: solve_solid on a gmsh tetra10 mesh."""
    t = time.perf_counter()
    mesh = mesh_wheel(d, size=h, order=2)
    t_mesh = time.perf_counter() - t
    runs = []
    for _ in range(n):
        t = time.perf_counter()
        ms = solve_solid(d, mesh, order=2, fmax_hz=fmax)
        runs.append((ms.timings_s["assemble"], ms.timings_s["eigen"], time.perf_counter() - t))
    tag = f"[gmsh {h * 1e3:g} mm]"
    a, e, tot = (med(r[j] for r in runs) for j in range(3))
    return [
        (f"3-D P2 {tag} unstructured check: gmsh meshing", ms.dofs, t_mesh, 1, len(ms.modes)),
        (f"3-D P2 {tag} unstructured check: solve_solid assembly", ms.dofs, a, n, len(ms.modes)),
        (f"3-D P2 {tag} unstructured check: solve_solid eigen", ms.dofs, e, n, len(ms.modes)),
        (f"3-D P2 {tag} unstructured check: solve_solid total (mesh given)", ms.dofs, tot, n, len(ms.modes)),
    ]


# ----------------------------------------------------------------------- convergence
def compare(ms, fref, fcut):
    """Relative differences to the reference (modes below fcut by key) and whether the
    labels of the lowest modes agree."""
    got = {key(m): m for m in ms.modes}
    rel = {k: got[k].frequency_hz / f - 1 for k, f in fref.items() if k in got}
    ref_keys = [k for k, f in sorted(fref.items(), key=lambda kv: kv[1]) if f < fcut]
    low = [key(m) for m in sorted(ms.modes, key=lambda m: m.frequency_hz)][: len(ref_keys)]
    same = Counter(low) == Counter(ref_keys) and len(got) == len(ms.modes)
    return got, rel, same


def convergence(d, args, ax):
    etw_ref = 8
    fcut = 3000.0
    band = args.fmax * (1 + PAIR_RTOL)
    t = time.perf_counter()
    axr = solve_axisymmetric(
        d, mesh_profile(d, elements_through_web=etw_ref, order=2), curved=True, fmax_hz=band, n_theta=8
    )
    print(
        f"\n## Convergence vs axisymmetric reference (curved P2, {etw_ref} elements across "
        f"the web, {axr.dofs} DOFs, {time.perf_counter() - t:.1f} s)"
    )
    fref = {key(m): m.frequency_hz for m in axr.modes}
    if len(fref) != len(axr.modes):
        print("  (reference has modes with identical labels: per-mode comparison by label is partial)")
    m30 = next(m for m in axr.modes if key(m) == K30).modal_mass
    low = {k: f for k, f in fref.items() if f < fcut}
    top = {k: f for k, f in fref.items() if f <= args.fmax}

    head = (
        f"{'mesh':<22} {'DOFs':>8} {'mesh s':>6} {'solve s':>7} {'modes':>5} {'max<3k':>7} "
        f"{'mean<3k':>7} {'max<5k':>7} {'f(3,0) Hz':>9} {'dm(3,0)':>8} labels"
    )
    rungs = [(1, 1), (2, 1)] if args.quick else [(1, 1), (1, 2), (2, 1), (2, 2), (4, 1)]
    per_mode, names, finest = {}, [], None

    def report(name, ms, t_mesh, t_solve):
        got, rel, same = compare(ms, fref, fcut)
        r3 = [v for k, v in rel.items() if k in low]
        r5 = [v for k, v in rel.items() if k in top]
        s30 = got[K30]
        print(
            f"{name:<22} {ms.dofs:8d} {t_mesh:6.2f} {t_solve:7.2f} {len(r3):5d} "
            f"{max(map(abs, r3)):7.3%} {np.mean(r3):+7.3%} {max(map(abs, r5)):7.3%} "
            f"{s30.frequency_hz:9.2f} {s30.modal_mass / m30 - 1:+8.3%} {'same' if same else 'DIFFER'}"
        )
        per_mode[name] = rel
        names.append(name)

    print(
        f"\n3-D P2 cyclic (solve_cyclic, mesh_profile(etw, order=2) revolved in N sectors), "
        f"modes <= {band:g} Hz solved; max/mean |df/f| vs the reference:"
    )
    print(head)
    for etw, mult in rungs:
        mesh, t_mesh = cyclic_mesh(d, etw)
        if mult > 1:
            mesh, t_mesh = cyclic_mesh(d, etw, mult * mesh.n_sectors)
        t = time.perf_counter()
        ms = solve_cyclic(d, mesh, fmax_hz=band)
        t_solve = time.perf_counter() - t
        report(f"cyclic {etw}/web N={mesh.n_sectors}", ms, t_mesh, t_solve)
        finest = (f"cyclic {etw}/web N={mesh.n_sectors}", ms)

    if args.tet:
        sizes = [0.015] if args.quick else [0.015, 0.01, 0.0075]
        print("\n3-D P2 gmsh unstructured tetra10 (solve_solid, mesh_wheel(size, order=2)):")
        print(head)
        for h in sizes:
            t = time.perf_counter()
            mesh = mesh_wheel(d, size=h, order=2)
            t_mesh = time.perf_counter() - t
            t = time.perf_counter()
            ms = solve_solid(d, mesh, order=2, fmax_hz=band)
            report(f"gmsh tet {h * 1e3:g} mm", ms, t_mesh, time.perf_counter() - t)

    print(f"\nper mode (relative difference 3-D - axisym reference; * = above {fcut:g} Hz):")
    cw = max(len(n) for n in names)
    print(f"{'mode':<24} {'axisym Hz':>9} " + " ".join(f"{n:>{cw}}" for n in names))
    for k, f in sorted(top.items(), key=lambda kv: kv[1]):
        cells = " ".join(f"{per_mode[n].get(k, float('nan')):+{cw}.3%}" for n in names)
        mark = "*" if f >= fcut else " "
        print(f"({k[0]},{k[1]}) {k[2]:<18}{mark} {f:9.1f} {cells}")
    print(f"(3,0) axial contact modal mass, axisym reference: {m30:.4f} kg")

    if ax is not None and finest is not None:
        name, ms = finest
        got = {key(m): m.frequency_hz for m in ms.modes}
        fax = {key(m): m.frequency_hz for m in ax.modes}
        rel = [f / got[k] - 1 for k, f in fax.items() if k in got]
        missing = sorted(set(fax) - set(got))
        print(
            f"\naxisymmetric as timed above ({ax.dofs} DOFs, {len(ax.modes)} modes <= {args.fmax:g} Hz) "
            f"vs the finest 3-D ({name}, {ms.dofs} DOFs): max |df/f| {max(map(abs, rel)):.3%}, "
            f"mean {np.mean(rel):+.3%} over {len(rel)} modes"
            + (f"; not matched by label: {missing}" if missing else "")
            + " (target: within 0.5 %)"
        )


# ------------------------------------------------------------------------------ main
def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="one repetition, short convergence ladder")
    ap.add_argument("--full", action="store_true", help="add the N=96 cyclic mesh (~90k DOFs) to the timing")
    ap.add_argument("--no-convergence", action="store_true", help="timing section only")
    ap.add_argument("--tet", action="store_true", help="add the (slow) gmsh tetra10 convergence ladder")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument(
        "--base-reps",
        type=int,
        default=None,
        help="runs of the slow baseline and solve_solid (default: --reps below 60k DOFs, else 1)",
    )
    ap.add_argument("--fmax", type=float, default=5000.0)
    ap.add_argument(
        "--design",
        type=Path,
        default=None,
        help="design TOML (default: WheelDesign(), rim depth 30 mm; designs/table1.toml is the "
        "calibrated 33.5 mm rim run_all.py and the pipeline use)",
    )
    ap.add_argument(
        "--sectors",
        type=int,
        nargs="*",
        default=None,
        help="N of the 1/web cyclic timing meshes (default 48; --full: 48 96)",
    )
    args = ap.parse_args(argv)
    reps = 1 if args.quick else args.reps
    d = load_design(args.design).wheel
    print(
        f"design: {args.design or 'WheelDesign() (Table 1 values, rim depth 30 mm)'}; "
        f"factorisations available: {', '.join(available_factorizations())}"
    )

    # ---------------------------------------------------------------- 1. timing
    rows, summary, ax = [], [], None
    if solve_axisymmetric is not None:
        t_ax, ax, n = timed(
            lambda: solve_axisymmetric(d, mesh_profile(d, order=1), fmax_hz=args.fmax), max(reps, 5)
        )
        rows.append(("axisymmetric (default mesh, all n, incl. meshing)", ax.dofs, t_ax, n, len(ax.modes)))
    for N in args.sectors or ([48, 96] if args.full else [48]):
        rows_n, line = time_cyclic(d, 1, N, args.fmax, reps, args.base_reps)
        rows += rows_n
        summary.append(line)
    rows += time_tet(d, 0.015, args.fmax, 1 if args.quick else min(reps, 2))

    print(
        f"\n## Wall time, all modes <= {args.fmax:g} Hz (median of n runs; modes: a pair counts once, "
        f"except eigsh rows: eigenvalues)"
    )
    w = max(len(r[0]) for r in rows)
    print(f"{'solver':<{w}} {'DOFs':>8} {'time s':>8} {'n':>2} {'modes':>5}")
    for label, dofs, t_s, n, nm in rows:
        print(f"{label:<{w}} {dofs:8d} {t_s:8.2f} {n:2d} {nm:5d}")
    for line in summary:
        print(line)
    if args.no_convergence:
        return 0
    if solve_axisymmetric is None:
        print("\n(fem.axisym not available: convergence section skipped)")
        return 0
    convergence(d, args, ax)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
