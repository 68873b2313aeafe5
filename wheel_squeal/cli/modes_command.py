"""The ``modes`` command: eigenmodes, labels and contact modal parameters."""

from __future__ import annotations

import argparse

from .. import api
from ..outputs import write_json
from ..present.summary import modes_summary
from ..present.text import modes_table
from ..runtime.request_errors import RequestError
from ..runtime.result_folders import result_folder
from .common import analysis_of, context_of, design_of, modes_of, out_of, write_files
from .options import add_common, add_fe
from .stops import uninterrupted

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The command\'s flags."""
    p = sub.add_parser("modes", help="eigenmodes, labels and contact modal parameters")
    add_common(p)
    add_fe(p)


def run(args: argparse.Namespace) -> int:
    design = design_of(args)
    out = out_of(args, design.name)
    ctx = context_of(args)
    with result_folder(out, "modes") as tmp:
        ms = modes_of(args, design)
        if not ms.modes:
            raise RequestError(f"no modes below {ctx.fmax_hz:g} Hz for {design.name}")
        a = analysis_of(args, design, stop_after="stability", remedy=False, modes=ms)
        chosen = a.verdict.outcome or a.verdict.named or a.verdict.pick
        selected, why = (chosen.mode, a.verdict.reason) if chosen is not None else (None, a.verdict.reason)
        with uninterrupted():
            views = api.mode_views(
                design, ctx.fidelity, ctx.fmax_hz, ms, [], ctx.cache, ctx.budget.max_file_bytes
            )
        write_files(tmp, views)
        write_json(tmp / "summary.json", modes_summary(design, ms, selected, ctx.fidelity, why))
    print(modes_table(ms.modes, design, selected))
    if selected is not None:
        print(
            f"selected: mode {selected.index} ({why}), {selected.frequency_hz:.1f} Hz, "
            f"m = {selected.modal_mass:.3f} kg"
        )
    print(f"{ms.solver}, {ms.dofs} DOFs, {ctx.fidelity.name} -> {out}")
    return 0
