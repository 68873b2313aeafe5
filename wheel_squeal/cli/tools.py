"""Commands around the model: calibrate, converge, cache."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from geometry.files import write_atomic

from ..cache import ENV_SIZE, StageCache, parse_size
from ..errors import RequestError
from ..folders import result_folder
from ..progress import Progress
from .common import design_of, out_of

__all__ = ["cmd_cache", "cmd_calibrate", "cmd_converge", "cmd_designs"]


def cmd_calibrate(args: argparse.Namespace) -> int:
    from ..calibration import CALIBRATED_MARK, calibrate, calibrated_design_path, check_request

    design = design_of(args)
    free = [f for part in args.free for f in part.split(",") if f]
    check_request(free, args.target_frequency, args.target_modal_mass)
    name = f"{design.name}_calibrated"
    design.replace(name=name)  # a valid name, checked before the work
    path = calibrated_design_path(Path(args.out), name) if args.out else None
    cal = calibrate(
        design,
        free,
        args.target_frequency,
        args.target_modal_mass,
        fidelity=args.fidelity,
        mode=args.mode,
        frequency_uncertainty=args.frequency_uncertainty,
        modal_mass_uncertainty=args.modal_mass_uncertainty,
        progress=Progress(args.quiet),
    )
    cal_design = cal.design.replace(
        name=name,
        description=(
            f"{design.name} with {', '.join(free)}{CALIBRATED_MARK}"
            f"{args.target_frequency} Hz, m = {args.target_modal_mass} kg "
            f"({args.fidelity}); residual {cal.residual}"
        ),
    )
    for k, v in cal.free.items():
        print(f"{k} = {v:.6g} (was {design.get(k):.6g})")
    print(
        f"selected mode: f = {cal.frequency_hz:.1f} Hz, m = {cal.modal_mass_kg:.3f} kg; residual "
        + ", ".join(f"{k} {v:+.2%}" for k, v in cal.residual.items() if k != "weighted_rms")
        + f", weighted rms {cal.residual['weighted_rms']:.3g} ({cal.evaluations} evaluations)"
    )
    if path is not None:
        write_atomic(path, cal_design.to_toml())
        print(f"-> {path}")
    return 0


def cmd_converge(args: argparse.Namespace) -> int:
    from ..convergence import run_convergence

    design = design_of(args)
    out = out_of(args, design.name)
    with result_folder(out, "converge") as tmp:
        rows = run_convergence(design, tmp, quick=args.quick, progress=Progress(args.quiet).say)
    print(f"{len(rows)} rungs -> {out}/convergence.csv (and plots)")
    return 0


def cmd_designs(args: argparse.Namespace) -> int:
    from ..api import shipped_designs

    for name, description in shipped_designs().items():
        first = description.split(". ")[0].split(": ")[0]
        print(f"{name:<16} {first if len(first) <= 90 else first[:89] + '...'}")
    print("give one by name from any folder: --design NAME")
    return 0


def cmd_cache(args: argparse.Namespace) -> int:
    cache = StageCache(args.cache_dir)
    if args.action == "clear":
        print(f"removed {cache.clear()} cache entries from {cache.root}")
        return 0
    if args.action == "limit":
        if args.size is None:
            raise RequestError("cache limit takes a size, like 500M or 5G")
        cache.set_limit(parse_size(args.size))
    elif args.size is not None:
        raise RequestError(f"cache {args.action} takes no size")
    n, size = cache.info()
    limit = cache.max_bytes
    source = f" (from ${ENV_SIZE})" if os.environ.get(ENV_SIZE, "").strip() else ""
    print(
        f"{cache.root}: {n} entries, {size / 1e6:.1f} MB of {limit / 1e6:.0f} MB{source}; "
        "the least recently used go beyond it"
    )
    return 0
