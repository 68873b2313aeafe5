"""The ``line`` command: every curve of a railway line: squeal probability and emission.

line.csv, line.geojson (with coordinates), line.nc, line.png, summary.json and
report.html of every curve of ``--line``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from geometry.files import printable

from ..runtime.request_errors import RequestError
from ..runtime.result_folders import result_folder
from .common import context_of, design_of, out_of
from .options import add_common, add_fe, add_workers

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The command\'s flags."""
    p = sub.add_parser("line", help="every curve of a railway line: squeal probability and emission")
    add_common(p)
    add_fe(p, mode=False)
    p.add_argument(
        "--line",
        required=True,
        help="LINE.csv: id, radius_m, length_m, cant_mm, train_speed_km_h (x0, y0, x1, y1 or wkt optional)",
    )
    p.add_argument("--traffic", help="a TOML file with a [line] table: traffic per period and friction")
    p.add_argument("--crs", help="the coordinates' projected system, as line.geojson names it (EPSG:25832)")
    add_workers(p)


def run(args: argparse.Namespace) -> int:
    """line.csv, line.geojson (with coordinates), line.nc, line.png, summary.json and
    report.html of every curve of ``--line``."""
    from track.alignment import LineFileError, count_rows

    from ..line import line, load_line, read_line_spec
    from ..plan import line_plan
    from ..present.line_files import check_geojson_size, write_line_files
    from ..study.runner import local_workers, scheduler_of

    path = Path(args.line)
    try:
        n_rows = count_rows(path)  # the file checked first: regular, within the size read
    except LineFileError as exc:
        raise RequestError(f"--line: {exc}") from None
    crs = None if args.crs is None else projected_crs(args.crs)
    design = design_of(args)
    spec = read_line_spec(Path(args.traffic) if args.traffic else None)
    ctx = context_of(args)
    scheduler = scheduler_of(args.scheduler)
    workers = None if scheduler else local_workers(args.workers, ctx.progress)
    plan = line_plan(n_rows, len(spec.states()), workers)
    plan.check(ctx.budget, "the line", "")  # before reading it: a line too long is refused at once
    curves = load_line(path)
    check_geojson_size(curves)  # its coordinates, priced before the work
    out = out_of(args, design.name)
    with result_folder(out, "line") as tmp:
        results = line(design, curves, spec, context=ctx, workers=workers or 1, scheduler=scheduler)
        rows = write_line_files(tmp, design.name, results, spec, crs)
    squealing = sum(r["squeal_probability"] > 0 for r in rows)
    print(f"{design.name}: {squealing} of {len(rows)} curves squeal some of the time")
    for r in rows:
        if r["squeal_probability"] > 0:
            print(
                f"  {r['id']}: R = {r['radius_m']:g} m, {r['train_speed_km_h']:g} km/h, probability "
                f"{r['squeal_probability']:.2f}, L_pAmax {r['bogie_lpamax_dba']} dB(A), "
                f"L_Aeq,day {r['laeq_day_dba']} dB(A) (CNOSSOS-EU: +{r['cnossos_correction_db']:g} dB)"
            )
    print(f"-> {out}")
    return 0


def projected_crs(text: str) -> str:
    """``--crs``: a projected coordinate system pyproj knows, as its authority names it
    (``EPSG:25832``); ``RequestError`` for anything else (a geographic system, whose
    degrees are not the metres of the curves, included)."""
    from pyproj import CRS
    from pyproj.exceptions import CRSError

    if not printable(text) or len(text) > 200:
        raise RequestError(f"--crs {ascii(text[:40])}: a coordinate system's name, like EPSG:25832")
    try:
        crs = CRS.from_user_input(text)
    except CRSError:
        raise RequestError(
            f"--crs {text[:60]!r}: not a coordinate system pyproj knows (give EPSG:CODE)"
        ) from None
    if not crs.is_projected:
        raise RequestError(
            f"--crs {text[:60]!r} ({crs.name}) is not projected: give a projected system in metres"
        )
    authority = crs.to_authority()
    return f"{authority[0]}:{authority[1]}" if authority else crs.to_string()
