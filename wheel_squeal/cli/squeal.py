"""The squeal commands: run (design to report), simulate, sweep, compare and stability."""

from __future__ import annotations

import time

import numpy as np

from .. import api, compare_files, stability_files, writers
from ..envelope import envelope, envelope_seconds, mitigation_summary
from ..errors import RequestError
from ..fields import columns_of
from ..modal_model import MODAL_MODEL_SOLVER
from ..outputs import result_folder, write_csv, write_json
from ..plotting import PlotWorkers
from ..presets import DEFAULT_ENVELOPE_CRAB_VELOCITIES, DEFAULT_SPEEDS_RPM
from ..progress import Progress
from ..report import compare_report, run_report
from ..sound_files import sound_text
from ..stability import (
    check_stability_budget,
    eigenvalue_list,
    excitable,
    stability_table,
    wheel_speed_rad_s,
)
from .arguments import grid_axis
from .common import (
    analysis_of,
    budget_of,
    cache_of,
    design_of,
    modes_of,
    operating_point_of,
    out_of,
    speeds_or_rpm,
    squeal_mode,
    write_files,
)
from .sound import listener_of, write_sound_files
from .stops import uninterrupted


def files_in(folder) -> str:
    """The result folder's files, the PNGs as one pattern."""
    names = sorted(p.name for p in folder.iterdir() if p.is_file() and not p.name.startswith("."))
    pngs = [n for n in names if n.endswith(".png")]
    return ", ".join([n for n in names if not n.endswith(".png")] + (["*.png"] if pngs else []))


__all__ = ["cmd_compare", "cmd_run", "cmd_simulate", "cmd_stability", "cmd_sweep"]


def cmd_run(args, plots: PlotWorkers) -> int:
    design = design_of(args)
    out = out_of(args, design.name)
    progress = Progress(args.quiet)
    t0 = time.perf_counter()
    listener = listener_of(args, design)
    with result_folder(out, "run") as tmp:
        cache = cache_of(args)
        a = analysis_of(args, design, progress, cache, listener)
        o = a.outcome
        if o is not None:
            with progress.stage("report"):
                writers.write_simulation_files(tmp, o.simulation, plots)
        if a.verdict.outcome is not None and a.verdict.outcome.sound is not None:
            write_sound_files(tmp, a.verdict.outcome.sound, plots, a.verdict.outcome.simulation)
        if a.multimode is not None:
            plots.submit(stability_files.write_multimode_plot, tmp / "multimode.png", a.multimode)
        ms = a.modeset
        shown = [o.mode.index] if o is not None else []
        indices = {"selected": shown, "none": [], "all": list(range(len(ms.modes)))}[args.render]
        if ms.solver != MODAL_MODEL_SOLVER:  # a modal model has no shapes to draw
            with progress.stage("mode views"):
                with uninterrupted():
                    views = api.mode_views(design, a.fidelity, args.fmax, ms, indices, cache)
                write_files(tmp, views)
        plots.submit(stability_files.write_mode_growth_plot, tmp / "growth.png", a.rows,
                     o.mode.index if o is not None else None)  # fmt: skip
        with progress.stage("plots"):
            plots.draw()
        summary = {
            **a.to_dict(),
            "timings_s": {**progress.timings, "total": time.perf_counter() - t0},
            "cache": {"hits": cache.hits, "misses": cache.misses},
        }
        write_json(tmp / "summary.json", summary)
        run_report(tmp, a)
    print(writers.analysis_header(a))
    if o is not None:
        print(writers.squeal_report(o.simulation, api.modal_dof(o.mode, design), o.label))
    if a.verdict.outcome is not None and a.verdict.outcome.sound is not None:
        print(sound_text(a.verdict.outcome.sound.summary()))
    if a.multimode is not None:
        print(stability_files.multimode_text(a.multimode))
    print("\n".join(a.verdict.lines()))
    seconds = time.perf_counter() - t0
    print(f"files: {out}/ ({files_in(out)})  [{seconds:.1f} s]")
    return 0


def cmd_simulate(args, plots: PlotWorkers) -> int:
    progress = Progress(args.quiet)
    design = design_of(args)
    out = out_of(args, design.name)
    with result_folder(out, "simulate") as tmp:
        contact = api.contact_law(design, args.c22, args.friction_law)
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
    print(f"-> {out}")
    return 0


def cmd_sweep(args) -> int:
    from ..sweep_files import sweep_table, write_sweep_csv, write_sweep_plot, write_sweep_spl
    from ..sweeps import sweep_verdicts

    progress = Progress(args.quiet)
    design = design_of(args)
    listener = listener_of(args, design) if args.sound else None
    measured = None
    if args.measured is not None:
        from ..measured import load_measured

        if not args.sound:
            raise RequestError("--measured compares levels: give --sound too")
        measured = load_measured(args.measured)
    vcs, rpms = args.crab_velocity, speeds_or_rpm(args, design)
    if measured is not None:
        from ..measured import check_speeds

        check_speeds(measured, rpms)  # before any work
    explicit = (args.mass, args.stiffness, args.damping)
    out = out_of(args, design.name)
    with result_folder(out, "sweep") as tmp:
        contact = api.contact_law(design, args.c22, args.friction_law)
        cache = cache_of(args)
        dof = ms = None
        if any(v is not None for v in explicit):
            if any(v is None for v in explicit):
                raise RequestError("--mass, --stiffness and --damping go together: give all three")
            dof = api.explicit_dof(*explicit)
        else:
            _, ms = modes_of(args, design, progress, cache)
        with progress.stage(f"sweep {len(vcs)} x {len(rpms)} points, {args.duration:g} s each"):
            grid = sweep_verdicts(
                design, vcs, rpms, args.duration, modeset=ms, dof=dof, contact=contact, mode=args.mode,
                sound=args.sound, listener=listener, fidelity=args.fidelity, fmax_hz=args.fmax, cache=cache,
                budget=budget_of(args), progress=progress,
            )  # fmt: skip
        write_sweep_csv(tmp / "sweep.csv", grid)
        write_sweep_plot(tmp / "sweep.png", grid, measured)
        if args.sound:
            write_sweep_spl(tmp / "sweep_spl.csv", grid)
        comparison = None
        if measured is not None:
            from ..measured import compare_measured
            from ..sweep_files import write_measured_csv

            comparison = compare_measured(grid, measured)
            write_measured_csv(tmp / "measured.csv", comparison)
        write_json(
            tmp / "summary.json",
            {
                "design": design.name,
                "named_mode": grid.named or None,
                "duration_s": args.duration,
                "points": len(vcs) * len(rpms),
                "squealing_points": int(grid.squeals.sum()),
                "still_growing_points": int((grid.squeals & ~grid.saturated).sum()),
                "timings_s": progress.timings,
            },
        )
    print(sweep_table(grid))
    if comparison is not None:
        from ..sweep_files import measured_table

        print(measured_table(comparison))
    print(f"-> {out} ({files_in(out)})")
    return 0


def cmd_compare(args) -> int:
    progress = Progress(args.quiet)
    designs = []
    for path in args.designs:
        try:
            designs.append(design_of(args, path))
        except RequestError as exc:
            raise RequestError(f"design {path}: {exc}") from None
    if len({d.name for d in designs}) != len(designs):
        raise RequestError("two designs have the same name; give each a distinct name")
    out = out_of(args, "+".join(d.name for d in designs)[:64])
    with result_folder(out, "compare") as tmp:
        cache = cache_of(args)
        analyses = []
        for d in designs:
            progress.say(f"design {d.name}")
            try:
                analyses.append(analysis_of(args, d, progress, cache))
            except RequestError as exc:
                raise RequestError(f"design {d.name}: {exc}") from None
        rows = [compare_files.compare_row(a) for a in analyses]
        write_csv(tmp / "compare.csv", rows, columns_of("compare.csv"))
        compare_files.write_compare_plot(tmp / "compare.png", rows, analyses)
        write_json(
            tmp / "summary.json",
            {
                "designs": rows,
                "verdicts": {a.design.name: a.verdict.to_dict() for a in analyses},
                "fidelity": analyses[0].fidelity.name,
                "operating_point": writers.operating_point_summary(analyses[0].operating_point, designs[0]),
            },
        )
        compare_report(tmp, rows, analyses)
    print(compare_files.compare_table(rows))
    for a in analyses:
        print(f"{a.design.name}: " + "\n  ".join(a.verdict.lines()))
    print(f"-> {out}")
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
    out = out_of(args, design.name)
    with result_folder(out, "stability") as tmp:
        op = operating_point_of(args, design)
        contact = api.contact_law(design, args.c22, args.friction_law)
        budget = budget_of(args)
        cache = cache_of(args)
        fid, ms = modes_of(args, design, progress, cache)
        n = len(excitable(ms, contact))
        bounds = None if args.no_bounds else "all"
        seconds = check_stability_budget(
            design, ms, contact, args.rotation, budget, 0 if bounds is None else n
        )
        if axes is not None:
            budget.check_work(
                f"the stability envelope ({len(axes[0])} x {len(axes[1])} points, {n} modes) and its "
                "mitigation",
                envelope_seconds(design, ms, contact, len(axes[0]), len(axes[1])),
                "use fewer --envelope-crab-velocity points or a lower --fmax",
            )
        with progress.stage(
            f"linear stability of {n} modes" + (f" (about {seconds:.2g} s)" if seconds > 2 else "")
        ):
            stab = stability_table(design, ms, contact, op, args.rotation, bounds=bounds)
        rows, result = stab
        table = [r.to_dict(design) for r in rows]
        with progress.stage("verdict"):
            # the table solved once; the verdict stops before the time domain
            a = analysis_of(args, design, progress, cache, modes=ms, table=stab, simulate=False)
        summary = {
            "verdict": a.verdict.to_dict(),
            "design": design.name,
            "fidelity": fid.name,
            "solver": ms.solver,
            "rotation": bool(args.rotation),
            "operating_point": writers.operating_point_summary(op, design),
            "contact": writers.contact_summary(design, contact, op),
            "friction_damping_ns_m": result.friction_damping_ns_m,
            "modes": table,
            "winner": table[stab.fastest],
            "eigenvalues": eigenvalue_list(stab, design),
        }
        if axes is not None:
            vcs, rpms = axes
            with progress.stage(f"envelope {len(vcs)} x {len(rpms)} points"):
                env = envelope(design, ms, contact, vcs, rpms, args.rotation)
            with progress.stage("mitigation (rotation off and on)"):
                summary["mitigation"] = mitigation_summary(design, ms, contact, vcs, rpms)
            stability_files.write_envelope_csv(tmp / "stability.csv", env)
            stability_files.write_envelope_plot(tmp / "stability.png", env, summary["mitigation"])
        write_json(tmp / "summary.json", summary)
    print(stability_files.stability_text(rows, stab.fastest))
    print(stability_files.eigenvalues_text(summary["eigenvalues"], summary["contact"]))
    if axes is not None:
        print(stability_files.mitigation_text(summary["mitigation"]))
    print("\n".join(a.verdict.lines()))
    print(f"-> {out}")
    return 0
