"""The track a design rolls on and the curves it runs through: the ``track`` command
(the rail's receptances) and the ``curve`` command (each wheel of a bogie per curve
radius and train speed)."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from ..errors import RequestError
from ..folders import result_folder
from ..outputs import write_json
from ..plan import track_plan
from .common import context_of, design_of, out_of

if TYPE_CHECKING:
    from ..types import AmplitudeMethod

__all__ = ["cmd_curve", "cmd_track"]


def cmd_track(args: argparse.Namespace) -> int:
    """receptance.csv, receptance.png and summary.json of the rail the design rolls on."""
    from ..present.track import track_text, write_receptance_csv, write_receptance_plot
    from ..track import track_receptances

    design = design_of(args)
    out = out_of(args, design.name)
    ctx = context_of(args)
    track_plan(args.points, design.counter_body.model_seconds()).check(ctx.budget, "the track", "")
    with result_folder(out, "track") as tmp:
        with ctx.progress.stage(f"the rail's receptances at {args.points} frequencies"):
            t = track_receptances(design, args.fmin, args.fmax, args.points)
        write_receptance_csv(tmp / "receptance.csv", t)
        write_receptance_plot(tmp / "receptance.png", t)
        write_json(tmp / "summary.json", {"design": design.name, **t.summary()})
    print(track_text(t))
    print(f"-> {out}")
    return 0


def cmd_curve(args: argparse.Namespace) -> int:
    """curve.csv, curve.nc, summary.json, the maps, the loudest pass-by's WAV and
    report.html: each wheel of the bogie at each radius and speed."""
    from ..curve import curve_map
    from ..present.curve import curve_table, write_curve_files

    design = design_of(args)
    if args.bogie is not None:
        raise RequestError(
            "--bogie is replaced by the steady curving: each axle's angle of attack follows from the bogie's "
            "primary yaw stiffness ([vehicle] primary_yaw_stiffness in the design; --wheelbase stays)"
        )
    if args.wheelbase is not None:
        design = design.replace(wheelbase=args.wheelbase)
    if args.friction_law is not None:
        design = design.replace(friction_law=args.friction_law)
    c22 = args.c22 if isinstance(args.c22, float) else None  # 'kalker': each contact's own
    vehicle = design.vehicle.vehicle()
    q = args.ground_reflection
    method: AmplitudeMethod = "time domain" if args.time_domain else "harmonic balance"
    out = out_of(args, design.name)
    ctx = context_of(args)
    with result_folder(out, "curve") as tmp:
        n = len(args.radius) * len(args.train_speed)
        remedies = "" if args.no_remedy else ", then again under each treatment of the remedy"
        with ctx.progress.stage(f"{n} curves x 4 wheels ({method}){remedies}"):
            result = curve_map(
                design,
                args.radius,
                args.train_speed,
                cant_mm=args.cant,
                c22=c22,
                method=method,
                context=ctx,
                ground_reflection=q,
                remedy=not args.no_remedy,
            )
        rows, summary = write_curve_files(
            tmp, design, vehicle, args.cant, result.cases, method, q, result.remedy, result.loudest
        )
    if result.remedy is not None:
        print(result.remedy.words())
    print(curve_table(rows))
    for line in summary["findings"]:
        print(line)
    print(f"-> {out}")
    return 0
