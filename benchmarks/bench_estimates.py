"""The budget's estimates against what the work then takes, on every shipped design
and study spec: the stability bounds of every mode, the envelope map with its
mitigation (rotation off and on, as ``stability --envelope`` runs them), the sound of
the squeal mode (air unknowns and time), the dense eigen-solve of large modal models,
the track command and curve maps (harmonic balance and time domain), and whole studies
on one worker.

    .venv/bin/python benchmarks/bench_estimates.py [--fidelity balanced] [--quick]

A refusal is only as good as its estimate: each must be within a factor 2 of the
measurement (the last column). ``--quick`` skips the studies, the railway wheels'
envelopes and the time-domain curve map (about 4 minutes of the run's 12).
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import replace
from functools import partial
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

import wheel_squeal as ws  # noqa: E402
from wheel_squeal.presets import DEFAULT_ENVELOPE_CRAB_VELOCITIES, DEFAULT_SPEEDS_RPM  # noqa: E402


def timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def row(kind: str, what: str, estimate: float, measured: float, unit: str = "s") -> bool:
    """One estimate beside its measurement; a time's estimate as the budget takes it, times
    the machine's load now (``wheel_squeal.runtime.budget.machine_slowdown``)."""
    from wheel_squeal.runtime.budget import machine_slowdown

    if unit == "s":
        estimate *= machine_slowdown()
    ratio = estimate / measured if measured > 0 else float("inf")
    ok = 0.5 <= ratio <= 2.0
    print(
        f"| {kind} | {what} | {estimate:.3g} {unit} | {measured:.3g} {unit} | {ratio:.2f} | "
        f"{'yes' if ok else 'NO'} |",
        flush=True,
    )
    return ok


def designs(fidelity: str, quick: bool) -> list[bool]:
    from acoustics import forget_air_meshes, radiate, radiation_cost
    from wheel_squeal.envelope import envelope, envelope_seconds, mitigation
    from wheel_squeal.mode_stability import excitable, stability_seconds, stability_table
    from wheel_squeal.sound import mode_surface

    start, stop, num = DEFAULT_ENVELOPE_CRAB_VELOCITIES
    vcs, rpms = np.linspace(start, stop, num), list(DEFAULT_SPEEDS_RPM)
    oks = []
    radiate(mode_surface(*_warm_modes(fidelity)), 500.0)  # imports and first calls, not counted
    for path in sorted((ROOT / "designs").glob("*.toml")):
        d = ws.load_design(path)
        ms = ws.compute_modes(d, fidelity, cache=ws.StageCache())
        contact, op = ws.contact_law(d), ws.operating_point(d)
        d.counter_body.model()  # a track's fits: made once per process, priced on their own
        n = len(excitable(ms, contact))
        for rotation in (False, True):
            t, _ = timed(partial(stability_table, d, ms, contact, op, rotation, bounds="all"))
            label = f"{d.name}, {n} modes" + (", rotation" if rotation else "")
            oks.append(row("stability bounds", label, stability_seconds(d, ms, contact, rotation, n), t))
        if not (quick and d.name.startswith("railway_920")):
            t = sum(
                timed(partial(fn, d, ms, contact, vcs, rpms, rotation))[0]
                for rotation in (False, True)
                for fn in (envelope, mitigation)
            )
            oks.append(
                row(
                    "envelope + mitigation",
                    f"{d.name}, {n} modes",
                    envelope_seconds(d, ms, contact, num, 3),
                    t,
                )
            )
        a = ws.analyse(d, op=op, modes=ms, stop_after="stability", remedy=False)  # the mode it decides
        mode = a.outcome.mode if a.outcome is not None else a.rows[a.table.fastest].mode
        surface = mode_surface(ms, mode, mode.frequency_hz)
        cost = radiation_cost(surface, mode.frequency_hz)
        forget_air_meshes()  # a design of the same outline would have left its air meshed
        t, field = timed(partial(radiate, surface, mode.frequency_hz))
        what = f"{d.name} {mode.label()} {mode.frequency_hz:.0f} Hz"
        oks.append(row("sound: air unknowns", what, cost.dofs, len(field.pressure), "DOFs"))
        oks.append(row("sound: time", what, cost.seconds, t))
    return oks


def large_models(sizes=(50, 200, 600, 1200)) -> list[bool]:
    """The dense eigen-solve of modal models of many modes (with a normal component, so
    the mechanisms' two limits are solved too), growth rates only, against the model's
    single-thread estimate."""
    from reduced import ModalDOF, linear_stability
    from reduced.stability import stability_seconds

    d = ws.load_design()
    contact, op = ws.contact_law(d), ws.operating_point(d)
    rng = np.random.default_rng(1)
    oks = []
    for n in sizes:
        dofs = [ModalDOF.from_components(f, 1e-3, 0.5, 0.1, 0) for f in rng.uniform(200.0, 5000.0, n)]
        t, _ = timed(partial(linear_stability, dofs, contact, op))
        oks.append(row("stability of a modal model", f"{n} modes", stability_seconds(dofs), t))
    return oks


def _warm_modes(fidelity: str):
    ms = ws.compute_modes(ws.load_design(), fidelity, cache=ws.StageCache())
    mode, _ = ws.pick_mode(ms, "n=3,c=0")
    return ms, mode, 500.0


def studies() -> list[bool]:
    from reduced import load_compiled_kernels
    from wheel_squeal.plan import estimate_study
    from wheel_squeal.study import load_spec
    from wheel_squeal.study.runner import case_results

    load_compiled_kernels()  # as a worker does before its first case
    oks = []
    for path in sorted((ROOT / "studies").glob("*.toml")):
        spec = load_spec(path)
        cost = estimate_study(spec)
        t, _ = timed(partial(case_results, spec, workers=1))
        what = f"{spec.name}: {spec.n_cases} designs x {spec.n_points} points, one worker"
        oks.append(row("study", what, cost.seconds(spec.n_cases, 1), t))
    return oks


def field(fidelity: str, quick: bool) -> list[bool]:
    """The track command's receptances and fits, and curve maps of the test track's
    wheel by the harmonic balance and in the time domain, each priced by its whole plan
    (``wheel_squeal.curve.curve_estimate``: the modes cached, every sliding axle's
    stability solved) before it runs."""
    from track.design_sections import TRACK_FIT_SECONDS
    from wheel_squeal.curve import CurveRequest, curve, curve_estimate
    from wheel_squeal.plan import track_plan
    from wheel_squeal.rail_receptances import track_receptances

    d = ws.load_design("railway_920_track")
    oks = []
    # a track this process has not fitted yet (the fits are kept per track in a process)
    track = replace(d.counter_body, sleeper_mass=d.counter_body.sleeper_mass + 1e-6)
    unfitted = replace(d, counter_body=track)
    t, _ = timed(partial(track_receptances, unfitted, 20.0, 5000.0, 400))
    estimate = track_plan(400, TRACK_FIT_SECONDS).seconds  # a track not fitted yet
    oks.append(row("track", "railway_920_track, 400 frequencies and the fits", estimate, t))
    ctx = ws.RunContext.of(fidelity)
    maps = [("harmonic balance", [100.0, 150.0, 200.0, 300.0, 600.0, 1000.0], [20.0, 40.0, 60.0])]
    if not quick:
        maps.append(("time domain", [100.0, 150.0, 200.0, 300.0], [20.0, 40.0, 60.0]))
    for method, radii, speeds in maps:
        plan = curve_estimate(d, CurveRequest(radii, speeds, method=method), context=ctx)  # type: ignore[arg-type]
        t, _ = timed(partial(curve, d, radii, speeds, method=method, context=ctx))
        what = f"railway_920_track, {len(radii)} radii x {len(speeds)} speeds, {method}"
        oks.append(row("curve map", what, plan.seconds, t))
    return oks


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--fidelity", default="balanced")
    p.add_argument("--quick", action="store_true")
    args = p.parse_args()
    print("| work | case | estimate | measured | ratio | within 2x |")
    print("|---|---|---|---|---|---|")
    oks = designs(args.fidelity, args.quick)
    oks += large_models((50, 200, 600) if args.quick else (50, 200, 600, 1200))
    oks += field(args.fidelity, args.quick)
    if not args.quick:
        oks += studies()
    print(f"\n{sum(oks)} of {len(oks)} estimates within a factor 2 of the measurement")
    return 0 if all(oks) else 1


if __name__ == "__main__":
    sys.exit(main())
