"""The ``render`` command: mode-shape PNGs (and GIFs), off-screen."""

from __future__ import annotations

import argparse

from ..runtime.request_errors import RequestError
from ..runtime.result_folders import result_folder
from .common import context_of, design_of, modes_of, out_of
from .options import add_common, add_fe
from .stops import uninterrupted

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The command\'s flags."""
    p = sub.add_parser("render", help="mode-shape PNGs (and GIFs), off-screen")
    add_common(p)
    add_fe(p, mode=False)
    p.add_argument("--modes", help="comma list of mode indices (default: all)")
    p.add_argument("--gif", action="store_true", help="also an animated GIF per mode")


def run(args: argparse.Namespace) -> int:
    from fem.render import render_modes

    design = design_of(args)
    out = out_of(args, design.name)
    progress = context_of(args).progress
    with result_folder(out, "render") as tmp:
        ms = modes_of(args, design)
        indices = None
        if args.modes:
            try:
                indices = [int(i) for i in args.modes.split(",")]
            except ValueError:
                raise RequestError(f"--modes takes indices like 0,3,4, got {args.modes!r}") from None
            bad = [i for i in indices if not 0 <= i < len(ms.modes)]
            if bad:
                raise RequestError(f"mode index {bad[0]} out of range 0..{len(ms.modes) - 1}")
        with progress.stage("render"):
            with uninterrupted():
                paths = render_modes(ms, tmp, indices=indices, gif=args.gif)
    print(f"{len(paths)} files -> {out}")
    return 0
