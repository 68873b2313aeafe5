"""The ``compare`` command: several designs at the same operating point."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..output_files import columns_of
from ..outputs import write_csv, write_json
from ..present.figures import write_compare_plot
from ..present.run_report import compare_report
from ..present.summary import operating_point_summary
from ..present.tables import by_loudness
from ..present.text import compare_table, verdict_lines
from ..runtime.request_errors import RequestError
from ..runtime.result_folders import result_folder
from .common import analysis_of, context_of, design_of, out_of
from .options import add_budget, add_cache, add_fe, add_operating, add_out, add_remedy, add_rotation

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The command\'s flags."""
    p = sub.add_parser("compare", help="several designs at the same operating point")
    p.add_argument("designs", nargs="+", type=Path, help="design TOML files")
    add_out(p)
    p.add_argument("--quiet", action="store_true")
    add_cache(p)
    add_budget(p)
    add_fe(p)
    add_operating(p)
    add_rotation(p)
    add_remedy(p)


def run(args: argparse.Namespace) -> int:
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
