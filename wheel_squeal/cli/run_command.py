"""The ``run`` command: design -> modes -> squeal limit cycle -> report (default: Table 1)."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from fem.modal_model import MODAL_MODEL_SOLVER

from .. import api
from ..design import Design
from ..outputs import write_json
from ..plotting import PlotWorkers
from ..present.results import write_run_files
from ..present.run_report import run_report
from ..present.summary import analysis_summary
from ..present.text import analysis_text
from ..presets import MAX_MULTIMODE
from ..result_cache import restore_result, result_key, store_result
from ..runtime.result_folders import result_folder
from .arguments import count
from .common import (
    analysis_of,
    cache_of,
    context_of,
    design_of,
    files_in,
    out_of,
    record_bytes_of,
    write_files,
)
from .options import (
    add_common,
    add_fe,
    add_microphone,
    add_modal_model,
    add_operating,
    add_record,
    add_remedy,
    add_rotation,
)
from .stops import uninterrupted

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The command\'s flags."""
    p = sub.add_parser("run", help="design -> modes -> squeal limit cycle -> report (default: Table 1)")
    add_common(p)
    add_fe(p)
    add_modal_model(p)
    add_operating(p)
    p.add_argument(
        "--render",
        choices=["selected", "all", "none"],
        default="selected",
        help="mode-shape PNGs to draw (default: the squeal mode)",
    )
    add_rotation(p)
    add_remedy(p)
    add_microphone(p)
    add_record(p)
    p.add_argument(
        "--multimode",
        type=count,
        nargs="?",
        const=MAX_MULTIMODE,
        metavar="K",
        help="the verdict is the model's own outcome (the design's named mode set aside; --mode still "
        "overrides): the modes of every growing eigenvalue integrated together, at most K of them "
        f"(default {MAX_MULTIMODE})",
    )


def run(args: argparse.Namespace, plots: PlotWorkers) -> int:
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
