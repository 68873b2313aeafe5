"""The ``line`` command: every curve of a railway line, its squeal's probability over the
friction's distribution and its emission for the noise-mapping tools."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..errors import RequestError
from ..folders import result_folder
from .common import context_of, design_of, out_of

__all__ = ["cmd_line"]


def cmd_line(args: argparse.Namespace) -> int:
    """line.csv, line.geojson (with coordinates), line.nc, line.png, summary.json and
    report.html of every curve of ``--line``."""
    from track.line import count_rows

    from ..line import line, load_line, read_line_spec
    from ..plan import line_plan
    from ..present.line import write_line_files
    from ..study.runner import local_workers, scheduler_of

    path = Path(args.line)
    if not path.is_file():
        raise RequestError(f"--line {path}: no such file")
    design = design_of(args)
    spec = read_line_spec(Path(args.traffic) if args.traffic else None)
    ctx = context_of(args)
    scheduler = scheduler_of(args.scheduler)
    workers = None if scheduler else local_workers(args.workers, ctx.progress)
    plan = line_plan(count_rows(path), len(spec.states()), workers)
    plan.check(ctx.budget, "the line", "")  # before reading it: a line too long is refused at once
    curves = load_line(path)
    out = out_of(args, design.name)
    with result_folder(out, "line") as tmp:
        results = line(design, curves, spec, context=ctx, workers=workers or 1, scheduler=scheduler)
        rows = write_line_files(tmp, design.name, results, spec, args.crs)
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
