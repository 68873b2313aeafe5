"""The verdict over a grid of crabbing velocities x wheel speeds (the paper's Fig. 5):
at every point the rule of :mod:`wheel_squeal.verdict` (the named mode as asked where it
squeals, else the fastest-growing mode), each mode's points run together in the
compiled sweep kernel, and the levels of the mode that squeals there.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .budget import Budget
from .design import Design
from .errors import RequestError
from .presets import rpm_to_speed
from .progress import Progress

if TYPE_CHECKING:
    from fem.modes import Mode, ModeSet
    from reduced import ContactLaw, ModalDOF

    from .sound import Listener

__all__ = ["VerdictGrid", "sweep_verdicts"]


@dataclass(frozen=True, eq=False)
class VerdictGrid:
    """The verdict at every point of crabbing velocities (n_vc,) [m/s] x wheel speeds
    (n_rpm,) [rev/min]; the 2-D arrays have shape (n_vc, n_rpm).

    mode : the label of the mode that squeals ("" where none); squeals, saturated : bool
    (saturated False: still growing at the end of the run, its amplitude and level are
    not a limit cycle's); amplitude_m_s, tone_hz, time_to_saturation_s : of that mode's
    run (NaN where no squeal); growth_rate_1_s : its linear growth rate (the largest of
    all modes where none squeals); spl_db, sound_power_level_db : its levels (NaN without
    sound or squeal). named : the mode named by the design or ``--mode`` ("" if none).
    rolling_speeds_m_s : the speeds at the contact; duration_s : each run's length.
    """

    crabbing_velocities_m_s: np.ndarray
    rpm: np.ndarray
    rolling_speeds_m_s: np.ndarray
    mode: np.ndarray
    squeals: np.ndarray
    saturated: np.ndarray
    amplitude_m_s: np.ndarray
    tone_hz: np.ndarray
    growth_rate_1_s: np.ndarray
    time_to_saturation_s: np.ndarray
    spl_db: np.ndarray
    sound_power_level_db: np.ndarray
    named: str
    duration_s: float


def sweep_verdicts(
    design: Design,
    crab_velocities,
    rpms,
    duration: float,
    *,
    modeset: ModeSet | None = None,
    dof: ModalDOF | None = None,
    contact: ContactLaw,
    mode: str = "auto",
    sound: bool = False,
    listener: Listener | None = None,
    fidelity: str = "balanced",
    fmax_hz: float = 5000.0,
    cache=None,
    budget: Budget | None = None,
    progress: Progress | None = None,
) -> VerdictGrid:
    """The verdict over the grid, each point run ``duration`` [s] from rest: from the FE
    modes (``modeset``, with the design's damping), or from one mode given directly
    (``dof``: then it is the only candidate). ``sound`` adds the levels heard by
    ``listener`` (the mode's radiation is computed once, at 1 m/s)."""
    from reduced import OperatingPoint
    from reduced.sweep import squeal_points

    from .stability import contact_dofs, excitable, named_mode

    progress = progress or Progress(quiet=True)
    budget = budget or Budget.from_environment()
    vcs = np.atleast_1d(np.asarray(crab_velocities, float))
    rpms = np.atleast_1d(np.asarray(rpms, float))
    if not (np.all(np.isfinite(vcs)) and np.all(np.isfinite(rpms)) and np.all(rpms > 0)):
        raise RequestError("crabbing velocities must be finite and wheel speeds positive")
    if not (math.isfinite(duration) and duration > 0):
        raise RequestError(f"duration must be positive, got {duration:g}")
    speeds = np.array([rpm_to_speed(r, design.rolling_radius) for r in rpms])
    shape = (len(vcs), len(rpms))
    n_points = shape[0] * shape[1]
    modes: list[Mode] = []
    named_i: int | None
    if dof is not None:
        dofs, named_i, named = [dof], 0, "the given mode"
    else:
        if modeset is None:
            raise TypeError("sweep_verdicts needs the FE modes (modeset) or one mode (dof)")
        modes = excitable(modeset, contact)
        if not modes:
            raise RequestError("no mode below fmax is seen at the contact: nothing can squeal there")
        dofs = contact_dofs(modes, design)
        first = named_mode(design, modeset, mode).mode
        named_i = next((k for k, m in enumerate(modes) if first and m.index == first.index), None)
        named = first.label() if first is not None else ""
    runs = n_points * (2 if named_i is not None and dof is None else 1)
    seconds = _check_cost(dofs, contact, vcs, speeds, duration, runs, budget)
    report = progress.counter("sweep", "cases") if seconds > 2.0 else None
    ops = [OperatingPoint(float(v0), float(vc)) for vc in vcs for v0 in speeds]
    pts = squeal_points(
        dofs, contact, ops, duration, first=named_i, fastest=dof is None, candidates=len(modes) or None,
        progress=report,
    )  # fmt: skip
    chosen = pts.mode
    if dof is None:
        label = np.array([modes[k].label() if k >= 0 else "" for k in chosen], dtype=object)
    else:
        label = np.where(chosen >= 0, named, "").astype(object)
    amplitude = pts.amplitude_m_s
    spl, power = np.full(len(ops), np.nan), np.full(len(ops), np.nan)
    if sound and pts.squeals.any():
        if dof is not None or modeset is None:
            raise RequestError("--sound needs the FE mode (its shape radiates): not with --mass")
        from .sound import mode_sound

        for i_mode in np.unique(chosen[chosen >= 0]):
            m = modes[int(i_mode)]
            with progress.stage(f"sound of {m.label()}"):
                unit = mode_sound(
                    design, modeset, m, m.frequency_hz, 1.0, listener=listener, fidelity=fidelity,
                    fmax_hz=fmax_hz, cache=cache, budget=budget,
                )  # fmt: skip
            at = chosen == i_mode
            spl[at], power[at] = unit.levels_at(amplitude[at])
    return VerdictGrid(
        vcs, rpms, speeds, label.reshape(shape), pts.squeals.reshape(shape), pts.saturated.reshape(shape),
        amplitude.reshape(shape), pts.frequency_hz.reshape(shape), pts.growth_rate_1_s.reshape(shape),
        pts.time_to_saturation_s.reshape(shape), spl.reshape(shape), power.reshape(shape), named,
        float(duration),
    )  # fmt: skip


def _check_cost(
    dofs: list[ModalDOF],
    contact: ContactLaw,
    crab_velocities_m_s: np.ndarray,
    speeds_m_s: np.ndarray,
    duration: float,
    runs: int,
    budget: Budget,
) -> float:
    """The estimated seconds of the sweep's runs and eigen-solves, refused beyond the
    budget; from the axes alone (the slowest points are the lowest speeds)."""
    from reduced import OperatingPoint
    from reduced.stability import eigen_solve_seconds
    from reduced.sweep import MAX_SWEEP_STEPS, numba_threads, sweep_steps

    v0 = float(speeds_m_s.min())
    corners = [OperatingPoint(v0, float(vc)) for vc in (crab_velocities_m_s.min(), crab_velocities_m_s.max())]
    steps = max(sweep_steps(dofs, contact, op, duration) for op in corners)
    if steps > MAX_SWEEP_STEPS:
        raise RequestError(
            f"a sweep case needs {steps:,} RK4 steps (limit {MAX_SWEEP_STEPS:,}): a very stiff or light "
            "mode or a very low rolling speed; shorten the duration"
        )
    n_points = len(crab_velocities_m_s) * len(speeds_m_s)
    remedy = "use fewer points or a shorter duration"
    seconds = budget.check_sweep(runs, steps, 1, numba_threads(), remedy)
    return seconds + budget.check_work(
        f"the stability of {len(dofs)} modes at {n_points:,} points",
        n_points * eigen_solve_seconds(dofs),
        remedy,
    )
