"""The squeal commands: run (design to report), simulate, sweep, compare and stability."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from geometry import DesignError

from .. import api, writers
from ..errors import RequestError
from ..outputs import result_folder, write_csv, write_json
from ..plotting import PlotWorkers
from ..presets import DEFAULT_ENVELOPE_CRAB_VELOCITIES, DEFAULT_SPEEDS_RPM, fidelity_for, rpm_to_speed
from ..progress import Progress
from ..sound_files import sound_text, write_sweep_spl
from ..stability import (
    choose_mode,
    envelope,
    envelope_seconds,
    excitable,
    mitigation,
    multimode,
    stability_seconds,
    stability_table,
    wheel_speed_rad_s,
)
from .common import budget_of, cache_of, design_of, modes_of, operating_point_of, squeal_mode, write_files
from .parser import grid_axis
from .sound import listener_of, mode_sound, write_sound_files

__all__ = ["cmd_compare", "cmd_run", "cmd_simulate", "cmd_stability", "cmd_sweep"]


def _stability_summary(design, sq) -> dict:
    rows = [r.to_dict(design) for r in sq.stability]
    winner = max(range(len(rows)), key=lambda i: rows[i]["growth_rate_1_s"])
    return {"stability": rows, "winner": rows[winner]}


def cmd_run(args, plots: PlotWorkers) -> int:
    design = design_of(args)
    out = args.out or Path("results") / design.name
    progress = Progress(args.quiet)
    t0 = time.perf_counter()
    listener = listener_of(args, design)
    with result_folder(out, "run") as tmp:
        cache = cache_of(args)
        op = operating_point_of(args, design)
        contact = api.contact_law(design, args.c22)
        sq = squeal_mode(args, design, progress, cache, contact, op)
        omega = wheel_speed_rad_s(design, op, args.rotation)
        with progress.stage("squeal model"):
            sim = api.simulate(sq.dof, contact, op, args.duration, omega, budget_of(args))
        multi = None
        if args.multimode is not None:
            with progress.stage("multi-mode squeal model"):
                multi = multimode(
                    design, sq.stability, contact, op, args.rotation, args.multimode, args.duration
                )
        sound = None
        if sim.limit_cycle.squeal:
            with progress.stage("sound"):
                # The tone: the mode's frequency, or its backward wave's on a turning wheel
                # (the limit cycle's fitted frequency differs by a few 1e-4: not worth a
                # new radiation solve per operating point).
                travelling = bool(args.rotation) and sq.mode.nodal_diameters >= 1
                tone = sq.mode.frequency_hz - sq.mode.nodal_diameters * omega / (2 * np.pi) * travelling
                amplitude = sim.limit_cycle.velocity_amplitude_m_s
                sound = mode_sound(
                    args, design, sq.modeset, sq.mode, tone, amplitude, cache, listener, travelling
                )
                write_sound_files(tmp, sound, plots)
        with progress.stage("report"):
            writers.write_simulation_files(tmp, sim, plots)
        mode, ms = sq.mode, sq.modeset
        indices = {"selected": [mode.index], "none": [], "all": list(range(len(ms.modes)))}[args.render]
        with progress.stage("mode views"):
            fid = fidelity_for(args.fidelity, args.solver)
            write_files(tmp, api.mode_views(design, fid, args.fmax, ms, indices, cache))
        with progress.stage("plots"):
            plots.draw()
        write_json(
            tmp / "summary.json",
            {
                **sq.summary,
                **_stability_summary(design, sq),
                **sim.summary(),
                "rotation": bool(args.rotation),
                "sound": sound.summary() if sound is not None else None,
                **({"multimode": multi.summary()} if multi is not None else {}),
                "modal_parameters": writers.dof_summary(sq.dof),
                "timings_s": {**progress.timings, "total": time.perf_counter() - t0},
                "cache": {"hits": cache.hits, "misses": cache.misses},
            },
        )
    print(
        f"{design.name}: squeal mode {mode.index}: {mode.label()} "
        f"({sq.summary['selected_mode']['why']}), {mode.frequency_hz:.1f} Hz"
    )
    print(writers.stability_line(sq.stability, mode))
    print(writers.squeal_report(sim, sq.dof))
    print(sound_text(sound.summary()) if sound is not None else "no sound: no squeal")
    if multi is not None:
        print(writers.multimode_text(multi))
    print(
        f"files: {out}/ (summary.json, timeseries.csv, *.png, modes.vtu, pressure.vtu)  "
        f"[{time.perf_counter() - t0:.1f} s]"
    )
    return 0


def cmd_simulate(args, plots: PlotWorkers) -> int:
    progress = Progress(args.quiet)
    with result_folder(args.out, "simulate") as tmp:
        design = design_of(args)
        contact = api.contact_law(design, args.c22)
        op = operating_point_of(args, design)
        sq = squeal_mode(args, design, progress, cache_of(args), contact, op)
        with progress.stage("squeal model"):
            omega = wheel_speed_rad_s(design, op, args.rotation)
            sim = api.simulate(sq.dof, contact, op, args.duration, omega, budget_of(args))
        summary = {
            "design": design.name,
            "modal_parameters": writers.dof_summary(sq.dof),
            **sim.summary(),
            "rotation": bool(args.rotation),
            "timings_s": progress.timings,
        }
        if sq.summary is not None:
            summary["selected_mode"] = sq.summary["selected_mode"]
        writers.write_simulation_files(tmp, sim, plots)
        write_json(tmp / "summary.json", summary)
        with progress.stage("plots"):
            plots.draw()
    print(writers.squeal_report(sim, sq.dof))
    print(f"-> {args.out}")
    return 0


def cmd_sweep(args) -> int:
    from reduced import write_sweep_csv, write_sweep_plot

    progress = Progress(args.quiet)
    design = design_of(args)
    listener = listener_of(args, design) if args.sound else None
    with result_folder(args.out, "sweep") as tmp:
        contact = api.contact_law(design, args.c22)
        cache = cache_of(args)
        sq = squeal_mode(args, design, progress, cache, contact, api.operating_point(design))
        speeds = [rpm_to_speed(r, design.rolling_radius) for r in args.rpm]
        vcs = args.crab_velocity
        with progress.stage(f"sweep {len(vcs)} x {len(speeds)} cases, {args.duration:g} s each"):
            result = api.sweep(
                sq.dof, contact, vcs, speeds, args.duration, budget=budget_of(args), progress=progress
            )
        write_sweep_csv(result, tmp, wheel_radius_m=design.rolling_radius)
        write_sweep_plot(result, tmp, wheel_radius_m=design.rolling_radius)
        sound = None
        if args.sound:
            if sq.mode is None:
                raise RequestError("--sound needs the FE mode (its shape radiates): not with --mass")
            with progress.stage("sound"):
                sound = mode_sound(
                    args, design, sq.modeset, sq.mode, sq.mode.frequency_hz, 1.0, cache, listener
                )
                write_sweep_spl(tmp, vcs, args.rpm, result, sound)
        write_json(
            tmp / "summary.json",
            {
                "design": design.name,
                "modal_parameters": writers.dof_summary(sq.dof),
                "duration_s": args.duration,
                "sound_per_unit_velocity": sound.summary() if sound is not None else None,
                "timings_s": progress.timings,
            },
        )
    print(writers.sweep_table(vcs, args.rpm, result))
    if sound is not None:
        print(f"per 1 m/s: {sound_text(sound.summary())}")
        print("SPL at the microphone per case: sweep_spl.csv, sweep_spl.png")
    print(f"velocity amplitude [m/s] ('-' = no squeal) -> {args.out}")
    return 0


def cmd_compare(args) -> int:
    progress = Progress(args.quiet)
    with result_folder(args.out, "compare") as tmp:
        cache = cache_of(args)
        designs = []
        for path in args.designs:
            try:
                designs.append(api.load_design(path))
            except DesignError as exc:
                raise RequestError(f"design {path}: {exc}") from None
        if len({d.name for d in designs}) != len(designs):
            raise RequestError("two designs have the same name; give each a distinct name")
        rows, sims = [], []
        for d in designs:
            progress.say(f"design {d.name}")
            try:
                op, contact = operating_point_of(args, d), api.contact_law(d, args.c22)
                fid, ms = modes_of(args, d, progress, cache)
                mode, _, _ = choose_mode(d, ms, args.mode, contact, op, args.rotation)
                dof = api.modal_dof(mode, d)
                sim = api.simulate(
                    dof, contact, op, args.duration, wheel_speed_rad_s(d, op, args.rotation), budget_of(args)
                )
            except (RequestError, DesignError) as exc:
                raise RequestError(f"design {d.name}: {exc}") from None
            rows.append(writers.compare_row(d, mode, dof, sim))
            sims.append(sim)
        write_csv(tmp / "compare.csv", rows)
        writers.write_compare_plot(tmp / "compare.png", rows, sims)
        write_json(
            tmp / "summary.json",
            {"designs": rows, "fidelity": fid.name, "operating_point": sims[0].summary()["operating_point"]},
        )
    print(writers.compare_table(rows))
    print(f"-> {args.out}")
    return 0


def _envelope_axes(args) -> tuple[np.ndarray, list[float]] | None:
    """The envelope's axes, or None without --envelope (whose axes flags then refuse)."""
    given = [f for f, v in (("--envelope-crab-velocity", args.envelope_crab_velocity),
                            ("--envelope-rpm", args.envelope_rpm)) if v is not None]  # fmt: skip
    if not args.envelope:
        if given:
            raise RequestError(f"{given[0]} shapes the envelope: give it with --envelope")
        return None
    vcs = args.envelope_crab_velocity or grid_axis(
        ":".join(f"{x:g}" for x in DEFAULT_ENVELOPE_CRAB_VELOCITIES)
    )
    rpms = args.envelope_rpm or list(DEFAULT_SPEEDS_RPM)
    if min(rpms) <= 0:
        raise RequestError("--envelope-rpm: wheel speeds must be positive")
    return np.asarray(vcs, float), rpms


def cmd_stability(args) -> int:
    design = design_of(args)
    progress = Progress(args.quiet)
    axes = _envelope_axes(args)
    with result_folder(args.out, "stability") as tmp:
        op = operating_point_of(args, design)
        contact = api.contact_law(design, args.c22)
        budget = budget_of(args)
        fid, ms = modes_of(args, design, progress)
        n = len(excitable(ms))
        bounds = None if args.no_bounds else "all"
        seconds = budget.check_work(
            f"the critical damping and friction slope of {n} modes",
            stability_seconds(design, ms, args.rotation, 0 if bounds is None else n),
            "lower --fmax, or give --no-bounds for the growth rates alone",
        )
        if axes is not None:
            budget.check_work(
                f"the stability envelope ({len(axes[0])} x {len(axes[1])} points, {n} modes) and its "
                "mitigation",
                envelope_seconds(design, ms, len(axes[0]), len(axes[1])),
                "use fewer --envelope-crab-velocity points or a lower --fmax",
            )
        with progress.stage(
            f"linear stability of {n} modes" + (f" (about {seconds:.2g} s)" if seconds > 2 else "")
        ):
            rows, result = stability_table(design, ms, contact, op, args.rotation, bounds=bounds)
        table = [r.to_dict(design) for r in rows]
        summary = {
            "design": design.name,
            "fidelity": fid.name,
            "solver": ms.solver,
            "rotation": bool(args.rotation),
            "operating_point": {
                "rolling_speed_m_s": op.rolling_speed_m_s,
                "rpm": op.rolling_speed_m_s / rpm_to_speed(1.0, design.rolling_radius),
                "crabbing_velocity_m_s": op.crabbing_velocity_m_s,
                "creepage": op.creepage,
                "wheel_speed_rad_s": wheel_speed_rad_s(design, op, True),
            },
            "friction_damping_ns_m": result.friction_damping_ns_m,
            "modes": table,
            "winner": table[result.winner],
        }
        if axes is not None:
            vcs, rpms = axes
            with progress.stage(f"envelope {len(vcs)} x {len(rpms)} points"):
                env = envelope(design, ms, contact, vcs, rpms, args.rotation)
            with progress.stage("mitigation (rotation off and on)"):
                summary["mitigation"] = {
                    "crab_velocity_m_s": [float(vcs[0]), float(vcs[-1])],
                    "rpm": list(rpms),
                    **{
                        key: mitigation(design, ms, contact, vcs, rpms, rot).to_dict(design)
                        for key, rot in (("rotation_off", False), ("rotation_on", True))
                    },
                }
            writers.write_envelope_csv(tmp / "stability.csv", env)
            writers.write_envelope_plot(tmp / "stability.png", env)
        write_json(tmp / "summary.json", summary)
    print(writers.stability_text(rows, result.winner))
    if axes is not None:
        print(writers.mitigation_text(summary["mitigation"]))
    print(f"-> {args.out}")
    return 0
