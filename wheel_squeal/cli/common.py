"""What the commands share: reading their common flags, and choosing the squeal mode."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from geometry import WheelDesign

from .. import api, writers
from ..budget import Budget
from ..cache import StageCache
from ..errors import RequestError
from ..presets import fidelity_for
from ..progress import Progress
from ..stability import choose_mode

__all__ = [
    "Squeal",
    "budget_of",
    "cache_of",
    "design_of",
    "modes_of",
    "operating_point_of",
    "squeal_mode",
    "write_files",
]


def design_of(args) -> WheelDesign:
    return api.load_design(args.design)


def cache_of(args) -> StageCache:
    return StageCache(args.cache_dir, enabled=not getattr(args, "no_cache", False))


def budget_of(args) -> Budget:
    return Budget.from_environment(getattr(args, "max_dofs", None), getattr(args, "max_seconds", None))


def write_files(directory: Path, files: dict[str, bytes]) -> None:
    for name, data in files.items():
        (directory / name).write_bytes(data)


def modes_of(args, design: WheelDesign, progress: Progress, cache: StageCache | None = None):
    """(fidelity, mode set): the design's FE modes with the command's ``--fidelity``,
    ``--solver``, ``--fmax``, cache and budget flags."""
    fid = fidelity_for(args.fidelity, args.solver)
    cache = cache_of(args) if cache is None else cache
    budget = budget_of(args)
    return fid, api.compute_modes(
        design, fid, fmax_hz=args.fmax, cache=cache, progress=progress, budget=budget
    )


def operating_point_of(args, design: WheelDesign):
    return api.operating_point(
        design,
        rpm=args.rpm,
        speed=getattr(args, "speed", None),
        crab_velocity=args.crab_velocity,
        angle_of_attack=args.angle_of_attack,
    )


@dataclass
class Squeal:
    """The mode a command simulates: its (m, k, c), and, from the FE, the mode set, the
    mode, the modes' summary (with why it was chosen) and every mode's stability."""

    dof: object
    modeset: object = None
    mode: object = None
    summary: dict | None = None
    stability: list | None = None


def squeal_mode(args, design: WheelDesign, progress: Progress, cache: StageCache, contact, op) -> Squeal:
    """From ``--mass/--stiffness/--damping`` when given (no FE at all), else the design's
    FE modes and ``--mode`` (auto: the design's named mode, else the fastest-growing)."""
    explicit = (args.mass, args.stiffness, args.damping) if hasattr(args, "mass") else (None,) * 3
    rotation = getattr(args, "rotation", False)
    if any(v is not None for v in explicit):
        if any(v is None for v in explicit):
            raise RequestError("--mass, --stiffness and --damping go together: give all three")
        n = getattr(args, "nodal_diameters", 0)
        if rotation and n < 1:
            raise RequestError("--rotation needs the mode's --nodal-diameters (1 or more) with --mass")
        progress.say("modal parameters given: no mesh, no FE")
        return Squeal(api.explicit_dof(*explicit, nodal_diameters=n))
    fid, ms = modes_of(args, design, progress, cache)
    mode, why, rows = choose_mode(design, ms, args.mode, contact, op, rotation)
    progress.say(f"squeal mode: {mode.index} ({why}), {mode.frequency_hz:.1f} Hz")
    summary = writers.modes_summary(design, ms, mode, fid, why)
    return Squeal(api.modal_dof(mode, design), ms, mode, summary, rows)
