"""The ``curve`` command: each wheel of a bogie in curves of radius R at train speed V.

curve.csv, curve.nc, summary.json, the maps, the loudest pass-by's WAV and
report.html: each wheel of the bogie at each radius and speed.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from ..runtime.request_errors import RequestError
from ..runtime.result_folders import result_folder
from .common import context_of, design_of, out_of

if TYPE_CHECKING:
    from ..types import AmplitudeMethod
from .arguments import c22_value, finite, grid_axis, non_negative, positive
from .options import add_common, add_fe, add_friction_law

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The command\'s flags."""
    p = sub.add_parser("curve", help="each wheel of a bogie in curves of radius R at train speed V")
    add_common(p)
    add_fe(p, mode=False)
    p.add_argument(
        "--radius", type=grid_axis, required=True, help="curve radii [m]: a comma list or START:STOP:N"
    )
    p.add_argument(
        "--train-speed", type=grid_axis, required=True, help="train speeds [km/h]: a list or START:STOP:N"
    )
    p.add_argument(
        "--wheelbase", type=positive, help="the bogie's wheelbase 2a [m] (default: the design's [vehicle])"
    )
    p.add_argument(
        "--cant", type=finite, default=0.0, help="the curves' installed cant [mm] (default %(default)g)"
    )
    p.add_argument("--bogie", help=argparse.SUPPRESS)  # replaced by the steady curving: refused with why
    add_friction_law(p)
    p.add_argument(
        "--no-remedy",
        action="store_true",
        help="leave out what would stop the squeal: each treatment (friction modifier, lower friction, "
        "flange lubrication, both, wheel dampers, steering bogie, lower speed) is checked by running the "
        "map again with it",
    )
    p.add_argument(
        "--c22",
        type=c22_value,
        help="creep coefficient C22 of every contact: a number or 'kalker' (default: Kalker's of each "
        "contact's own ellipse)",
    )
    p.add_argument(
        "--time-domain",
        action="store_true",
        help="amplitudes and sound from the time domain (minutes per squealing axle; default: "
        "harmonic balance of the squeal mode)",
    )
    p.add_argument(
        "--ground-reflection",
        type=non_negative,
        help="also the pass-by over a ground 0.5 m below the rail head with this reflection "
        "factor (0 to 1; default: free field only)",
    )


def run(args: argparse.Namespace) -> int:
    """curve.csv, curve.nc, summary.json, the maps, the loudest pass-by's WAV and
    report.html: each wheel of the bogie at each radius and speed."""
    from ..curve import CurveRequest, curve_map
    from ..present.curve_files import curve_table, write_curve_files

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
            request = CurveRequest(args.radius, args.train_speed, None, args.cant, c22, method, q)
            result = curve_map(design, request, context=ctx, remedy=not args.no_remedy)
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
