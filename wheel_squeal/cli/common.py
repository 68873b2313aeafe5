"""What the commands share: reading their common flags into the request's design,
context (:class:`~wheel_squeal.context.RunContext`), chain options and modes."""

from __future__ import annotations

import argparse
import math
from dataclasses import replace
from pathlib import Path
from typing import Any

from geometry.files import check_label

from .. import api
from ..chain import Analysis, ChainOptions, analyse
from ..context import RunContext
from ..design import Design
from ..fe_stages import context_modes
from ..listener import Listener, air_for, microphone_for
from ..presets import DEFAULT_SPEEDS_RPM, MAX_MULTIMODE, fidelity_for, rpm_to_speed
from ..runtime.budget import Budget
from ..runtime.progress import Progress
from ..runtime.request_errors import RequestError
from ..runtime.stage_cache import StageCache
from ..types import Stage

__all__ = [
    "analysis_of",
    "budget_of",
    "cache_of",
    "context_of",
    "design_of",
    "given_modes",
    "listener_of",
    "modes_of",
    "operating_point_of",
    "options_of",
    "out_of",
    "settings_of",
    "speeds_or_rpm",
    "write_files",
]


def design_of(args: argparse.Namespace, path: Path | str | None = None) -> Design:
    """The design of ``--design`` (or ``path``) with the command's [contact] overrides
    (``--contact-angle`` in degrees, ``--normal-contact``, ``--transient-creep``)."""
    design = api.load_design(args.design if path is None else path)
    changes: dict[str, Any] = {}
    if getattr(args, "contact_angle", None) is not None:
        changes["contact_angle"] = math.radians(args.contact_angle)
    if getattr(args, "normal_contact", None) is not None:
        changes["normal_contact"] = args.normal_contact
    if getattr(args, "transient_creep", False):
        changes["transient_creep"] = True
    if getattr(args, "friction", None) is not None:
        changes["friction_coefficient"] = args.friction
    if given_modes(args) is not None:  # the design's [squeal] mode and (n, c) keys name FE modes
        by_label = tuple((k, z) for k, z in design.damping.by_mode if "=" not in k)
        changes |= {"squeal_mode": "", "mode_damping": by_label}
    return design.replace(**changes) if changes else design


def given_modes(args: argparse.Namespace) -> Any:
    """The modes the command line gives instead of the FE (a ``fem.ModeSet``): the
    ``--modal-model`` file's, or the one mode of ``--mass/--stiffness/--damping``; None
    without."""
    cached = vars(args).get("_given")
    if cached is not None:
        return cached or None
    path = getattr(args, "modal_model", None)
    explicit = [getattr(args, k, None) for k in ("mass", "stiffness", "damping")]
    given = None
    if path is not None:
        from fem.modal_model import load_modal_model

        given = load_modal_model(path, getattr(args, "fmax", None))
    elif any(v is not None for v in explicit):
        if any(v is None for v in explicit):
            raise RequestError("--mass, --stiffness and --damping go together: give all three")
        n = getattr(args, "nodal_diameters", 0)
        if getattr(args, "rotation", False) and n < 1:
            raise RequestError("--rotation needs the mode's --nodal-diameters (1 or more) with --mass")
        from fem.modal_model import explicit_modes

        mass, stiffness, damping = (float(v) for v in explicit if v is not None)
        given = explicit_modes(mass, stiffness, damping, nodal_diameters=n)
    args._given = given if given is not None else False
    return given


def cache_of(args: argparse.Namespace) -> StageCache:
    """The request's stage cache (one per command: its hits and misses are the run's)."""
    cache = vars(args).get("_cache")
    if cache is None:
        cache = args._cache = StageCache(args.cache_dir, enabled=not getattr(args, "no_cache", False))
    return cache


def budget_of(args: argparse.Namespace) -> Budget:
    """The request's one budget, its time counted from the process's start."""
    budget = vars(args).get("_budget")
    if budget is None:
        budget = Budget.from_environment(getattr(args, "max_dofs", None), getattr(args, "max_seconds", None))
        started = vars(args).get("_started_s")
        if started is not None:  # the process's own start: its imports count too
            budget = replace(budget, started_s=started)
        args._budget = budget
    return budget


def settings_of(args: argparse.Namespace) -> Budget:
    """The request's budget and, for a command that has one, its cache: every limit and
    folder from the flags and the environment, checked before any work (a bad
    ``WHEEL_SQUEAL_CACHE_SIZE`` is one line at once, not after the modes)."""
    budget = budget_of(args)
    if hasattr(args, "cache_dir"):
        cache_of(args)
    return budget


def context_of(args: argparse.Namespace) -> RunContext:
    """The request's context: ``--fidelity``, ``--solver``, ``--fmax``, the cache, the
    budget and progress (``--quiet``)."""
    ctx = vars(args).get("_context")
    if ctx is None:
        fid = fidelity_for(getattr(args, "fidelity", "balanced"), getattr(args, "solver", None))
        cache = cache_of(args) if hasattr(args, "cache_dir") else None
        ctx = args._context = RunContext(
            fid,
            getattr(args, "fmax", 5000.0),
            cache,
            budget_of(args),
            Progress(getattr(args, "quiet", False)),
        )
    return ctx


def record_bytes_of(args: argparse.Namespace) -> float:
    """What timeseries.csv may hold: every sample (``--full-record``) up to the size any
    file may take, else ``present.time_history.TIMESERIES_BYTES``."""
    from ..present.time_history import TIMESERIES_BYTES

    most = context_of(args).budget.max_file_bytes
    return most if getattr(args, "full_record", False) else min(TIMESERIES_BYTES, most)


def listener_of(args: argparse.Namespace, design: Design) -> Listener:
    """The command's ``--microphone``, ``--air-density`` and ``--sound-speed``, checked
    before any work (:func:`wheel_squeal.listener.microphone_for`, ``air_for``)."""
    return Listener(microphone_for(design, args.microphone), air_for(args.air_density, args.sound_speed))


def options_of(
    args: argparse.Namespace, design: Design, stop_after: Stage = "sound", **changes: Any
) -> ChainOptions:
    """The chain's options from the command's flags (``changes`` replace them)."""
    listener = listener_of(args, design) if stop_after == "sound" and hasattr(args, "microphone") else None
    mode = getattr(args, "mode", "auto") or "auto"
    if mode == "auto" and getattr(args, "multimode", None):
        mode = "model"  # --multimode asks for the model's own outcome as the verdict
    options = ChainOptions(
        mode=mode,
        rotation=getattr(args, "rotation", False),
        max_modes=getattr(args, "multimode", None) or MAX_MULTIMODE,
        duration=getattr(args, "duration", None),
        stop_after=stop_after,
        listener=listener,
        c22=getattr(args, "c22", None),
        friction_law=getattr(args, "friction_law", None),
        remedy=not getattr(args, "no_remedy", False),
    )
    return replace(options, **changes)


def modes_of(args: argparse.Namespace, design: Design) -> Any:
    """The design's modes: the command line's own (:func:`given_modes`), else the FE's
    through the request's context."""
    given = given_modes(args)
    ctx = context_of(args)
    if given is not None:
        ctx.progress.say(f"modes: {len(given.modes)} given (no FE)")
        return given
    return context_modes(design, ctx)


def operating_point_of(args: argparse.Namespace, design: Design) -> Any:
    return api.operating_point(
        design,
        rpm=getattr(args, "rpm", None),
        rolling_speed_m_s=getattr(args, "speed", None),
        crabbing_velocity_m_s=getattr(args, "crab_velocity", None),
        angle_of_attack_rad=getattr(args, "angle_of_attack", None),
    )


def analysis_of(
    args: argparse.Namespace, design: Design, stop_after: Stage = "sound", **changes: Any
) -> Analysis:
    """The chain (:func:`wheel_squeal.chain.analyse`) with the command's flags, stopping
    after ``stop_after``; ``changes``: its options or ``modes``/``table`` when known."""
    known = {k: changes.pop(k) for k in ("modes", "table") if k in changes}
    op = operating_point_of(args, design)
    options = options_of(args, design, stop_after, **changes)  # a bad microphone: before any work
    modes = known.get("modes")
    if modes is None:
        modes = modes_of(args, design)
    return analyse(
        design, op=op, options=options, context=context_of(args), modes=modes, table=known.get("table")
    )


def out_of(args: argparse.Namespace, name: str) -> Path:
    """The command's result folder: ``--out``, else ``results/COMMAND/NAME`` below the
    working folder (NAME: the design's, the study's, or the compared designs'; a label,
    never a path: ``geometry.files.check_label``)."""
    out = (
        Path(args.out)
        if args.out is not None
        else Path("results") / args.command / check_label(name, "a result's name", RequestError)
    )
    cache = vars(args).get("_cache")
    if cache is not None and cache.enabled:
        check_apart(out, cache.root)
    return out


def check_apart(out: Path, cache_root: Path) -> None:
    """Refuse, before any work, a result folder that is the cache, lies inside it or holds
    it: publishing the result would replace the cache, and clearing the cache or evicting
    its entries would remove results."""
    a, b = out.expanduser().resolve(), cache_root.expanduser().resolve()
    if a == b or b in a.parents or a in b.parents:
        relation = "is" if a == b else "lies inside" if b in a.parents else "holds"
        raise RequestError(
            f"result folder {out} {relation} the cache folder {cache_root}: give --out and --cache-dir "
            "folders apart"
        )


def write_files(directory: Path, files: dict[str, bytes]) -> None:
    for name, data in files.items():
        (directory / name).write_bytes(data)


def speeds_or_rpm(args: argparse.Namespace, design: Design) -> list[float]:
    """A sweep's wheel speeds [rev/min]: ``--rpm``, or ``--speed`` (m/s at the contact)
    converted with the design's rolling radius."""
    if args.speed is not None:
        if args.rpm is not None:
            raise RequestError("give --rpm or --speed, not both")
        if min(args.speed) <= 0:
            raise RequestError("--speed: rolling speeds must be positive")
        return [v / rpm_to_speed(1.0, design.rolling_radius) for v in args.speed]
    return list(args.rpm) if args.rpm is not None else list(DEFAULT_SPEEDS_RPM)


def files_in(folder: Path) -> str:
    """The result folder's files, the PNGs as one pattern."""
    names = sorted(p.name for p in folder.iterdir() if p.is_file() and not p.name.startswith("."))
    pngs = [n for n in names if n.endswith(".png")]
    return ", ".join([n for n in names if not n.endswith(".png")] + (["*.png"] if pngs else []))
