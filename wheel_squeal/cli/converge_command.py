"""The ``converge`` command: speed/accuracy study: mesh ladders, solvers, integrator."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..runtime.progress import Progress
from ..runtime.result_folders import result_folder
from .common import design_of, out_of
from .options import add_out

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The command\'s flags."""
    p = sub.add_parser("converge", help="speed/accuracy study: mesh ladders, solvers, integrator")
    p.add_argument(
        "--design", type=Path, help="wheel design TOML or shipped name (default: the Table 1 wheel)"
    )
    add_out(p)
    p.add_argument("--quick", action="store_true", help="only the cheapest rungs")
    p.add_argument("--quiet", action="store_true")


def run(args: argparse.Namespace) -> int:
    from ..convergence import run_convergence

    design = design_of(args)
    out = out_of(args, design.name)
    with result_folder(out, "converge") as tmp:
        rows = run_convergence(design, tmp, quick=args.quick, progress=Progress(args.quiet).say)
    print(f"{len(rows)} rungs -> {out}/convergence.csv (and plots)")
    return 0
