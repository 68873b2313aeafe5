"""The ``calibrate`` command: fit design parameters to measured modal data."""

from __future__ import annotations

import argparse
from pathlib import Path

from geometry.files import write_atomic

from ..presets import FIDELITIES
from ..runtime.progress import Progress
from .arguments import positive
from .common import design_of

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The command\'s flags."""
    p = sub.add_parser("calibrate", help="fit design parameters to measured modal data")
    p.add_argument("--design", type=Path)
    p.add_argument(
        "--free",
        action="append",
        required=True,
        help="design parameter(s) to fit, e.g. rim_depth (repeat or comma list)",
    )
    p.add_argument("--target-frequency", type=positive, help="measured frequency [Hz]")
    p.add_argument("--target-modal-mass", type=positive, help="measured contact modal mass [kg]")
    p.add_argument(
        "--frequency-uncertainty",
        type=positive,
        default=0.01,
        help="relative standard uncertainty of the measured frequency (default 0.01)",
    )
    p.add_argument(
        "--modal-mass-uncertainty",
        type=positive,
        default=0.10,
        help="relative standard uncertainty of the measured modal mass (default 0.10)",
    )
    p.add_argument("--fidelity", default="fast", choices=list(FIDELITIES))
    p.add_argument(
        "--mode",
        help="the measured mode: INDEX, n=3[,c=0] or f=HZ (default: the design's squeal mode, else n=3,c=0)",
    )
    p.add_argument("--out", type=Path, help="folder or .toml path for the calibrated design")
    p.add_argument("--quiet", action="store_true")


def run(args: argparse.Namespace) -> int:
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
