"""The track a design rolls on and the curves it runs through: the ``track`` command
(the rail's receptances) and the ``curve`` command (each wheel of a bogie per curve
radius and train speed)."""

from __future__ import annotations

import argparse

from ..errors import RequestError
from ..outputs import result_folder, write_json
from .common import context_of, design_of, out_of

__all__ = ["cmd_curve", "cmd_track"]


def cmd_track(args: argparse.Namespace) -> int:
    """receptance.csv, receptance.png and summary.json of the rail the design rolls on."""
    from ..present.track import track_text, write_receptance_csv, write_receptance_plot
    from ..track import track_receptances

    design = design_of(args)
    out = out_of(args, design.name)
    ctx = context_of(args)
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
    """curve.csv and summary.json: each wheel of the bogie at each radius and speed."""
    from track.curving import Bogie

    from ..curve import curve
    from ..fields import columns_of
    from ..outputs import write_csv
    from ..present.text import curve_table

    design = design_of(args)
    try:
        bogie = Bogie(args.wheelbase, args.bogie)
    except ValueError as exc:
        raise RequestError(str(exc)) from None
    if min(args.radius) <= 0 or min(args.train_speed) <= 0:
        raise RequestError("--radius and --train-speed take positive values")
    out = out_of(args, design.name)
    ctx = context_of(args)
    with result_folder(out, "curve") as tmp:
        n = len(args.radius) * len(args.train_speed)
        with ctx.progress.stage(f"{n} curves x 4 wheels"):
            cases = curve(
                design, args.radius, args.train_speed, bogie,
                stop_after="sound" if args.sound else "stability",
                context=ctx, ground_reflection=args.ground_reflection,
            )  # fmt: skip
        rows = [c.to_record() for c in cases]
        write_csv(tmp / "curve.csv", rows, columns_of("curve.csv"))
        write_json(
            tmp / "summary.json",
            {"design": design.name, "wheelbase_m": args.wheelbase, "bogie": args.bogie,
             "cases": [{**r, "verdict": c.analysis.verdict.to_dict()} for r, c in zip(rows, cases)]},
        )  # fmt: skip
    print(curve_table(rows))
    print(f"-> {out}")
    return 0
