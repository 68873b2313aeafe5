"""The squeal commands: run (design to report), simulate, sweep, compare and stability;
each parses its flags, asks the one chain (:func:`wheel_squeal.chain.analyse`, stopped
where it needs) and presents the records (:mod:`wheel_squeal.present`)."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from fem.modal_model import MODAL_MODEL_SOLVER

from .. import api
from ..design import Design
from ..envelope import envelope, mitigation_summary
from ..errors import RequestError
from ..folders import result_folder
from ..output_files import columns_of
from ..outputs import write_csv, write_json
from ..plan import stability_request_plan
from ..plotting import PlotWorkers
from ..present.figures import write_compare_plot, write_envelope_plot, write_sweep_plot
from ..present.results import write_remedy_toml, write_run_files, write_simulation_files
from ..present.run_report import compare_report, run_report
from ..present.summary import analysis_summary, contact_summary, operating_point_summary
from ..present.tables import (
    by_loudness,
    write_envelope_csv,
    write_measured_csv,
    write_sweep_csv,
    write_sweep_spl,
)
from ..present.text import (
    analysis_text,
    compare_table,
    eigenvalues_text,
    measured_table,
    mitigation_text,
    stability_text,
    sweep_table,
    verdict_lines,
)
from ..presets import DEFAULT_ENVELOPE_CRAB_VELOCITIES, DEFAULT_SPEEDS_RPM
from ..result_cache import restore_result, result_key, store_result
from ..stability import eigenvalue_list, excitable, stability_table
from ..sweeps import sweep_verdicts
from .arguments import grid_axis
from .common import (
    analysis_of,
    cache_of,
    context_of,
    design_of,
    modes_of,
    operating_point_of,
    options_of,
    out_of,
    record_bytes_of,
    speeds_or_rpm,
    write_files,
)
from .stops import uninterrupted

__all__ = ["cmd_compare", "cmd_run", "cmd_simulate", "cmd_stability", "cmd_sweep"]


def files_in(folder: Path) -> str:
    """The result folder's files, the PNGs as one pattern."""
    names = sorted(p.name for p in folder.iterdir() if p.is_file() and not p.name.startswith("."))
    pngs = [n for n in names if n.endswith(".png")]
    return ", ".join([n for n in names if not n.endswith(".png")] + (["*.png"] if pngs else []))


def cmd_run(args: argparse.Namespace, plots: PlotWorkers) -> int:
    design = design_of(args)
    out = out_of(args, design.name)
    t0 = time.perf_counter()
    key = result_key("run", vars(args), design.content_hash())
    with result_folder(out, "run") as tmp:
        text = restore_result(cache_of(args), key, tmp, {"total": time.perf_counter() - t0})
        if text is None:
            text = _run(args, design, tmp, plots, t0)
            store_result(cache_of(args), key, tmp, text)
    print(text)
    print(f"files: {out}/ ({files_in(out)})  [{time.perf_counter() - t0:.1f} s]")
    return 0


def _run(args: argparse.Namespace, design: Design, tmp: Path, plots: PlotWorkers, t0: float) -> str:
    """``run``'s files in ``tmp``; returns what it says (the verdict and its reasons)."""
    a = analysis_of(args, design)
    ctx = context_of(args)
    with ctx.progress.stage("report"):
        write_run_files(tmp, a, plots, record_bytes_of(args))
    o = a.outcome
    if a.modeset.solver != MODAL_MODEL_SOLVER:  # a modal model has no shapes to draw
        shown = [o.mode.index] if o is not None else []
        indices = {"selected": shown, "none": [], "all": list(range(len(a.modeset.modes)))}[args.render]
        with ctx.progress.stage("mode views"), uninterrupted():
            views = api.mode_views(
                design, a.fidelity, ctx.fmax_hz, a.modeset, indices, ctx.cache, ctx.budget.max_file_bytes
            )
        write_files(tmp, views)
    with ctx.progress.stage("plots"):
        plots.draw()
    summary = {
        **analysis_summary(a, record_bytes_of(args)),
        "timings_s": {**ctx.progress.timings, "total": time.perf_counter() - t0},
        "cache": {"hits": ctx.cache.hits, "misses": ctx.cache.misses} if ctx.cache else None,
    }
    write_json(tmp / "summary.json", summary)
    run_report(tmp, a)
    return analysis_text(a)


def cmd_simulate(args: argparse.Namespace, plots: PlotWorkers) -> int:
    design = design_of(args)
    out = out_of(args, design.name)
    with result_folder(out, "simulate") as tmp:
        a = analysis_of(args, design, stop_after="limit_cycle", remedy=False)
        o = a.outcome
        if o is not None and o.simulation is not None:
            write_simulation_files(tmp, o.simulation, plots, record_bytes_of(args))
        write_json(
            tmp / "summary.json",
            {
                **analysis_summary(a, record_bytes_of(args)),
                "timings_s": context_of(args).progress.timings,
            },
        )
        with context_of(args).progress.stage("plots"):
            plots.draw()
    print(analysis_text(a))
    print(f"-> {out}")
    return 0


def cmd_sweep(args: argparse.Namespace) -> int:
    design = design_of(args)
    measured = None
    if args.measured is not None:
        from ..measured import check_speeds, load_measured

        if not args.sound:
            raise RequestError("--measured compares levels: give --sound too")
        measured = load_measured(args.measured)
    vcs, rpms = args.crab_velocity, speeds_or_rpm(args, design)
    if measured is not None:
        check_speeds(measured, rpms)  # before any work
    out = out_of(args, design.name)
    ctx = context_of(args)
    with result_folder(out, "sweep") as tmp:
        modes = modes_of(args, design)
        options = options_of(args, design, "sound" if args.sound else "limit_cycle")
        how = f"{args.duration:g} s each" if args.duration else "each until its outcome is known"
        with ctx.progress.stage(f"sweep {len(vcs)} x {len(rpms)} points, {how}"):
            grid = sweep_verdicts(
                design,
                vcs,
                rpms,
                args.duration,
                modeset=modes,
                options=options,
                context=ctx,
                sound=args.sound,
            )
        write_sweep_csv(tmp / "sweep.csv", grid)
        write_sweep_plot(tmp / "sweep.png", grid, measured)
        if args.sound:
            write_sweep_spl(tmp / "sweep_spl.csv", grid)
        comparison = None
        if measured is not None:
            from ..measured import compare_measured

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
                "timings_s": ctx.progress.timings,
            },
        )
    print(sweep_table(grid))
    if comparison is not None:
        print(measured_table(comparison))
    print(f"-> {out} ({files_in(out)})")
    return 0


def cmd_compare(args: argparse.Namespace) -> int:
    designs = []
    for path in args.designs:
        try:
            designs.append(design_of(args, path))
        except RequestError as exc:
            raise RequestError(f"design {path}: {exc}") from None
    if len({d.name for d in designs}) != len(designs):
        raise RequestError("two designs have the same name; give each a distinct name")
    out = out_of(args, "+".join(d.name for d in designs)[:64])
    ctx = context_of(args)
    with result_folder(out, "compare") as tmp:
        analyses = []
        for d in designs:
            ctx.progress.say(f"design {d.name}")
            try:
                analyses.append(analysis_of(args, d))
            except RequestError as exc:
                raise RequestError(f"design {d.name}: {exc}") from None
        analyses = by_loudness(analyses)
        rows = [{k: a.to_record()[k] for k in columns_of("compare.csv")} for a in analyses]
        write_csv(tmp / "compare.csv", rows, columns_of("compare.csv"))
        write_compare_plot(tmp / "compare.png", rows, analyses)
        write_json(
            tmp / "summary.json",
            {
                "designs": rows,
                "verdicts": {a.design.name: a.verdict.to_dict() for a in analyses},
                "fidelity": analyses[0].fidelity.name,
                "operating_points": {
                    a.design.name: operating_point_summary(a.operating_point, a.design) for a in analyses
                },
            },
        )
        compare_report(tmp, rows, analyses)
    print(compare_table(rows))
    for a in analyses:
        print(f"{a.design.name}: " + "\n  ".join(verdict_lines(a.verdict)))
    print(f"-> {out}")
    return 0


def _envelope_axes(args: argparse.Namespace) -> tuple[np.ndarray, list[float]] | None:
    """The envelope's axes, or None without --envelope (whose axes flags then refuse)."""
    given = [
        f
        for f, v in (
            ("--envelope-crab-velocity", args.envelope_crab_velocity),
            ("--envelope-rpm", args.envelope_rpm),
        )
        if v is not None
    ]
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


def cmd_stability(args: argparse.Namespace) -> int:
    design = design_of(args)
    axes = _envelope_axes(args)
    out = out_of(args, design.name)
    ctx = context_of(args)
    with result_folder(out, "stability") as tmp:
        op = operating_point_of(args, design)
        contact = api.contact_law(design, args.c22, args.friction_law)
        ms = modes_of(args, design)
        n = len(excitable(ms, contact))
        bounds = None if args.no_bounds else "all"
        sizes = None if axes is None else (len(axes[0]), len(axes[1]))
        plan = stability_request_plan(design, ms, contact, args.rotation, bounds is not None, sizes)
        seconds = plan.check(ctx.budget, "the stability", "ask for less")
        with ctx.progress.stage(
            f"linear stability of {n} modes" + (f" (about {seconds:.2g} s)" if seconds > 2 else "")
        ):
            table = stability_table(design, ms, contact, op, args.rotation, bounds=bounds)
        with ctx.progress.stage("verdict"):
            a = analysis_of(args, design, stop_after="stability", modes=ms, table=table)
        rows = [r.to_dict(design) for r in table.rows]
        summary = {
            "verdict": a.verdict.to_dict(),
            "design": design.name,
            "fidelity": ctx.fidelity.name,
            "solver": ms.solver,
            "rotation": bool(args.rotation),
            "operating_point": operating_point_summary(op, design),
            "contact": contact_summary(design, contact, op),
            "friction_damping_ns_m": table.result.friction_damping_ns_m,
            "modes": rows,
            "winner": rows[table.fastest],
            "eigenvalues": eigenvalue_list(table),
        }
        if axes is not None:
            vcs, rpms = axes
            with ctx.progress.stage(f"envelope {len(vcs)} x {len(rpms)} points"):
                env = envelope(design, ms, contact, vcs, rpms, args.rotation)
            with ctx.progress.stage("mitigation (rotation off and on)"):
                summary["mitigation"] = mitigation_summary(design, ms, contact, vcs, rpms)
            write_envelope_csv(tmp / "stability.csv", env)
            write_envelope_plot(tmp / "stability.png", env, summary["mitigation"])
        write_remedy_toml(tmp, a)
        write_json(tmp / "summary.json", summary)
    print(stability_text(table.rows, table.fastest, bounds is not None))
    print(eigenvalues_text(summary["eigenvalues"], summary["contact"]))
    if axes is not None:
        print(mitigation_text(summary["mitigation"]))
    print("\n".join(verdict_lines(a.verdict)))
    print(f"-> {out}")
    return 0
