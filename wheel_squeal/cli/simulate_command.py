"""The ``simulate`` command: time-domain squeal model at one operating point."""

from __future__ import annotations

import argparse

from ..outputs import write_json
from ..plotting import PlotWorkers
from ..present.results import write_simulation_files
from ..present.summary import analysis_summary
from ..present.text import analysis_text
from ..runtime.result_folders import result_folder
from .common import analysis_of, context_of, design_of, out_of, record_bytes_of
from .options import add_common, add_fe, add_modal, add_modal_model, add_operating, add_record, add_rotation

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The command\'s flags."""
    p = sub.add_parser("simulate", help="time-domain squeal model at one operating point")
    add_common(p)
    add_fe(p)
    add_modal(p)
    add_modal_model(p)
    add_operating(p)
    add_rotation(p)
    p.add_argument(
        "--nodal-diameters", type=int, default=0, help="the --mass mode's nodal diameters (for --rotation)"
    )
    add_record(p)


def run(args: argparse.Namespace, plots: PlotWorkers) -> int:
    design = design_of(args)
    out = out_of(args, design.name)
    with result_folder(out, "simulate") as tmp:
        a = analysis_of(args, design, stop_after="limit_cycle", remedy=False)
        o = a.outcome
        if o is not None and o.simulation is not None:
            write_simulation_files(tmp, o.simulation, plots, record_bytes_of(args))
        write_json(
            tmp / "summary.json",
            {**analysis_summary(a, record_bytes_of(args)), "timings_s": context_of(args).progress.timings},
        )
        with context_of(args).progress.stage("plots"):
            plots.draw()
    print(analysis_text(a))
    print(f"-> {out}")
    return 0
