"""What the commands share: reading their common flags, and choosing the squeal mode."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

from geometry.files import check_label

from .. import api, writers
from ..budget import Budget
from ..cache import StageCache
from ..design import Design
from ..errors import RequestError
from ..modal_model import MODAL_MODEL_SOLVER
from ..presets import DEFAULT_SPEEDS_RPM, fidelity_for, rpm_to_speed
from ..progress import Progress
from ..stability import choose_mode

__all__ = [
    "Squeal",
    "speeds_or_rpm",
    "analysis_of",
    "out_of",
    "budget_of",
    "cache_of",
    "design_of",
    "modal_model_of",
    "modes_of",
    "operating_point_of",
    "squeal_mode",
    "write_files",
]


def design_of(args, path=None) -> Design:
    """The design of ``--design`` (or ``path``) with the command's [contact] overrides
    (``--contact-angle`` in degrees, ``--normal-contact``, ``--transient-creep``)."""
    design = api.load_design(args.design if path is None else path)
    changes: dict = {}
    if getattr(args, "contact_angle", None) is not None:
        changes["contact_angle"] = math.radians(args.contact_angle)
    if getattr(args, "normal_contact", None) is not None:
        changes["normal_contact"] = args.normal_contact
    if getattr(args, "transient_creep", False):
        changes["transient_creep"] = True
    if modal_model_of(args) is not None:  # the design's [squeal] names FE modes
        changes |= {"squeal_mode": "", "mode_damping": ()}
    return design.replace(**changes) if changes else design


def modal_model_of(args):
    """The ``--modal-model`` file's modes (``fem.ModeSet``), None without one."""
    path = getattr(args, "modal_model", None)
    if path is None:
        return None
    from ..modal_model import load_modal_model

    return load_modal_model(path, getattr(args, "fmax", None))


def cache_of(args) -> StageCache:
    """The request's stage cache (one per command: its hits and misses are the run's)."""
    cache = vars(args).get("_cache")
    if cache is None:
        cache = args._cache = StageCache(args.cache_dir, enabled=not getattr(args, "no_cache", False))
    return cache


def budget_of(args) -> Budget:
    """The request's one budget, its time counted from the first call."""
    budget = vars(args).get("_budget")
    if budget is None:
        budget = Budget.from_environment(getattr(args, "max_dofs", None), getattr(args, "max_seconds", None))
        started = vars(args).get("_started_s")
        if started is not None:  # the process's own start: its imports count too
            budget = replace(budget, started_s=started)
        args._budget = budget
    return budget


def settings_of(args) -> Budget:
    """The request's budget and, for a command that has one, its cache: every limit and
    folder from the flags and the environment, checked before any work (a bad
    ``WHEEL_SQUEAL_CACHE_SIZE`` is one line at once, not after the modes)."""
    budget = budget_of(args)
    if hasattr(args, "cache_dir"):
        cache_of(args)
    return budget


def write_files(directory: Path, files: dict[str, bytes]) -> None:
    for name, data in files.items():
        (directory / name).write_bytes(data)


def modes_of(args, design: Design, progress: Progress, cache: StageCache | None = None):
    """(fidelity, mode set): the design's FE modes with the command's ``--fidelity``,
    ``--solver``, ``--fmax``, cache and budget flags."""
    fid = fidelity_for(args.fidelity, args.solver)
    measured = modal_model_of(args)
    if measured is not None:
        progress.say(f"modes: {len(measured.modes)} from the modal model {args.modal_model} (no FE)")
        return fid, measured
    cache = cache_of(args) if cache is None else cache
    budget = budget_of(args)
    return fid, api.compute_modes(
        design, fid, fmax_hz=args.fmax, cache=cache, progress=progress, budget=budget
    )


def operating_point_of(args, design: Design):
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


def squeal_mode(args, design: Design, progress: Progress, cache: StageCache, contact, op) -> Squeal:
    """From ``--mass/--stiffness/--damping`` when given (no FE at all), else the design's
    FE modes and ``--mode`` (auto: the design's named mode, else the fastest-growing)."""
    mass, stiffness, damping = (getattr(args, k, None) for k in ("mass", "stiffness", "damping"))
    rotation = getattr(args, "rotation", False)
    if mass is not None or stiffness is not None or damping is not None:
        if mass is None or stiffness is None or damping is None:
            raise RequestError("--mass, --stiffness and --damping go together: give all three")
        n = getattr(args, "nodal_diameters", 0)
        if rotation and n < 1:
            raise RequestError("--rotation needs the mode's --nodal-diameters (1 or more) with --mass")
        progress.say("modal parameters given: no mesh, no FE")
        return Squeal(api.explicit_dof(mass, stiffness, damping, nodal_diameters=n))
    fid, ms = modes_of(args, design, progress, cache)
    mode, why, rows = choose_mode(design, ms, args.mode, contact, op, rotation)
    progress.say(f"squeal mode: {mode.index} ({why}), {mode.frequency_hz:.1f} Hz")
    summary = writers.modes_summary(design, ms, mode, fid, why)
    return Squeal(api.modal_dof(mode, design), ms, mode, summary, rows)


def out_of(args, name: str) -> Path:
    """The command's result folder: ``--out``, else ``results/COMMAND/NAME`` below the
    working folder (NAME: the design's, the study's, or the compared designs'; a label,
    never a path: ``geometry.files.check_label``)."""
    if args.out is not None:
        return args.out
    return Path("results") / args.command / check_label(name, "a result's name", RequestError)


def analysis_of(
    args,
    design: Design,
    progress: Progress,
    cache: StageCache,
    listener=None,
    modes=None,
    table=None,
    simulate: bool = True,
):
    """:func:`wheel_squeal.chain.analyse` with the command's flags (a modal model's modes
    have no shape: nothing is radiated); ``table``: the stability table when solved
    already; ``simulate=False`` stops before the time domain (the linear verdict)."""
    from ..chain import analyse

    measured = modal_model_of(args) if modes is None else None
    modes = measured if measured is not None else modes

    return analyse(
        design,
        rpm=args.rpm,
        speed=getattr(args, "speed", None),
        crab_velocity=args.crab_velocity,
        angle_of_attack=args.angle_of_attack,
        fidelity=args.fidelity,
        solver=args.solver,
        fmax_hz=args.fmax,
        mode=getattr(args, "mode", "auto") or "auto",
        rotation=getattr(args, "rotation", False),
        multimode_count=getattr(args, "multimode", None),
        duration=getattr(args, "duration", None),
        listener=listener,
        sound=simulate and (modes is None or modes.solver != MODAL_MODEL_SOLVER),
        simulate_modes=simulate,
        table=table,
        c22=args.c22,
        friction_law=getattr(args, "friction_law", None),
        margin=not getattr(args, "no_remedy", False),
        modes=modes,
        cache=cache,
        budget=budget_of(args),
        progress=progress,
    )


def speeds_or_rpm(args, design: Design) -> list[float]:
    """A sweep's wheel speeds [rev/min]: ``--rpm``, or ``--speed`` (m/s at the contact)
    converted with the design's rolling radius."""
    if args.speed is not None:
        if args.rpm is not None:
            raise RequestError("give --rpm or --speed, not both")
        if min(args.speed) <= 0:
            raise RequestError("--speed: rolling speeds must be positive")
        return [v / rpm_to_speed(1.0, design.rolling_radius) for v in args.speed]
    return list(args.rpm) if args.rpm is not None else list(DEFAULT_SPEEDS_RPM)
