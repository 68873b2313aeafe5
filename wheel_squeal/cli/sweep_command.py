"""The ``sweep`` command: limit cycles over crabbing velocity x speed (Fig. 5)."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..outputs import write_json
from ..present.figures import write_sweep_plot
from ..present.tables import write_measured_csv, write_sweep_csv, write_sweep_spl
from ..present.text import measured_table, sweep_table
from ..presets import DEFAULT_SPEEDS_RPM, DEFAULT_SWEEP_CRAB_VELOCITIES
from ..runtime.request_errors import RequestError
from ..runtime.result_folders import result_folder
from ..sweeps import sweep_verdicts
from .arguments import c22_value, grid_axis, positive
from .common import context_of, design_of, files_in, modes_of, options_of, out_of, speeds_or_rpm
from .options import add_axis, add_common, add_contact, add_fe, add_friction_law, add_microphone, add_modal

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The command\'s flags."""
    p = sub.add_parser("sweep", help="limit cycles over crabbing velocity x speed (Fig. 5)")
    add_common(p)
    add_fe(p)
    add_modal(p)
    add_axis(p, "--crab-velocity", DEFAULT_SWEEP_CRAB_VELOCITIES, "crabbing velocities [m/s]", span=True)
    add_axis(p, "--rpm", DEFAULT_SPEEDS_RPM, "wheel speeds [rev/min]", filled=False)
    p.add_argument("--speed", type=grid_axis, help="rolling speeds at the contact [m/s], instead of --rpm")
    p.add_argument(
        "--duration",
        type=positive,
        help="simulated time per point [s] (default: each until its outcome is known, as run)",
    )
    p.add_argument("--c22", type=c22_value, help="C22 or 'kalker'")
    add_friction_law(p)
    add_contact(p)
    p.add_argument("--sound", action="store_true", help="also the SPL at the microphone (Fig. 5 in dB)")
    p.add_argument(
        "--measured",
        type=Path,
        metavar="FILE.csv",
        help="measured levels to draw over the --sound curves and compare (columns crab_velocity, rpm, "
        "spl_db, optional frequency_hz): measured.csv holds prediction minus measurement",
    )
    add_microphone(p)


def run(args: argparse.Namespace) -> int:
    design = design_of(args)
    measured = None
    if args.measured is not None:
        from ..measured_comparison import check_speeds, load_measured

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
            from ..measured_comparison import compare_measured

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
