"""The ``track`` command: the rail's point receptances (a design on a track).

receptance.csv, receptance.png and summary.json of the rail the design rolls on.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from ..outputs import write_json
from ..plan import track_plan
from ..runtime.result_folders import result_folder
from .common import context_of, design_of, out_of

if TYPE_CHECKING:
    pass
from .arguments import count, positive
from .options import add_common

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The command\'s flags."""
    p = sub.add_parser("track", help="the rail's point receptances (a design on a track)")
    add_common(p, cache=False)
    p.add_argument("--fmin", type=positive, default=20.0, help="lowest frequency [Hz] (default %(default)g)")
    p.add_argument(
        "--fmax", type=positive, default=5000.0, help="highest frequency [Hz] (default %(default)g)"
    )
    p.add_argument("--points", type=count, default=300, help="frequencies, log-spaced (default %(default)d)")


def run(args: argparse.Namespace) -> int:
    """receptance.csv, receptance.png and summary.json of the rail the design rolls on."""
    from ..present.receptance_files import track_text, write_receptance_csv, write_receptance_plot
    from ..rail_receptances import track_receptances

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
