"""The verdict over a grid of crabbing velocities x wheel speeds (the paper's Fig. 5): the
chain (:func:`wheel_squeal.chain.analyse`) at every point, stopped after the limit cycle
(or the sound), so that a point of a sweep says what ``run`` says there.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from .chain import ChainOptions, analyse
from .context import RunContext
from .design import Design
from .presets import rpm_to_speed
from .runtime.request_errors import RequestError

if TYPE_CHECKING:
    from fem.modes import ModeSet

__all__ = ["VerdictGrid", "sweep_verdicts"]


@dataclass(frozen=True, eq=False)
class VerdictGrid:
    """The verdict at every point of crabbing velocities (n_vc,) [m/s] x wheel speeds
    (n_rpm,) [rev/min]; the 2-D arrays have shape (n_vc, n_rpm).

    Attributes
    ----------
    crabbing_velocities_m_s, rpm, rolling_speeds_m_s : numpy.ndarray
        The axes [m/s, rev/min, m/s].
    mode, mechanism : numpy.ndarray of str
        The mode that squeals and what makes it grow ("" where none).
    squeals, saturated : numpy.ndarray of bool
        Whether it squeals; whether its record ended in a limit cycle.
    amplitude_m_s, tone_hz, time_to_saturation_s : numpy.ndarray
        Of the verdict's run [m/s, Hz, s] (NaN where no squeal).
    growth_rate_1_s : numpy.ndarray
        Its linear growth rate [1/s] (the largest of all where none squeals).
    spl_db, spl_dba, sound_power_level_db : numpy.ndarray
        Its levels [dB, dB(A) re 20 uPa; dB re 1 pW] (NaN without sound).
    named : str
        The mode named by the design or the request ("" if none).
    duration_s : float or None
        Each run's fixed length [s] (None: until its outcome is known).

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> g = ws.sweep_verdicts(ws.load_design(), [0.39], [400, 800], modeset=ws.explicit_modes(3.1, 1.6e8, 42))
    >>> g.amplitude_m_s.shape, bool(g.squeals.all())
    ((1, 2), True)
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
    spl_dba: np.ndarray
    sound_power_level_db: np.ndarray
    mechanism: np.ndarray
    named: str
    duration_s: float | None


#: The numbers of a grid point, from the verdict's record (:meth:`Verdict.to_dict`).
_NUMBERS = ("amplitude_m_s", "tone_hz", "growth_rate_1_s", "spl_db", "spl_dba", "sound_power_level_db")


def sweep_verdicts(
    design: Design,
    crab_velocities: Any,
    rpms: Any,
    duration: float | None = None,
    *,
    modeset: ModeSet | None = None,
    options: ChainOptions | None = None,
    context: RunContext | None = None,
    sound: bool = False,
) -> VerdictGrid:
    """The verdict of the chain at every point of the grid.

    Parameters
    ----------
    design : Design
    crab_velocities : array_like
        Crabbing velocities [m/s].
    rpms : array_like
        Wheel speeds [rev/min].
    duration : float, optional
        Each run's length [s] (None: until its outcome is known, as ``run``).
    modeset : fem.ModeSet, optional
        The design's modes when solved already (a modal model's, one given mode's).
    options : ChainOptions, optional
        As for :func:`~wheel_squeal.chain.analyse` (the mode named, rotation, ...).
    context : RunContext, optional
        How it computes; its memo keeps each mode's radiation between points.
    sound : bool
        The levels too (the chain's last stage).

    Returns
    -------
    VerdictGrid

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> g = ws.sweep_verdicts(ws.load_design(), [0.0, 0.39], [800], modeset=ws.explicit_modes(3.1, 1.6e8, 42))
    >>> g.squeals[:, 0].tolist()
    [False, True]
    """
    from reduced import OperatingPoint

    vcs = np.atleast_1d(np.asarray(crab_velocities, float))
    rpms = np.atleast_1d(np.asarray(rpms, float))
    if not (np.all(np.isfinite(vcs)) and np.all(np.isfinite(rpms)) and np.all(rpms > 0)):
        raise RequestError("crabbing velocities must be finite and wheel speeds positive")
    if duration is not None and not (math.isfinite(duration) and duration > 0):
        raise RequestError(f"duration must be positive, got {duration:g}")
    ctx = context or RunContext()
    opts = replace(
        options or ChainOptions(),
        duration=duration,
        remedy=False,
        beside=False,
        stop_after="sound" if sound else "limit_cycle",
    )
    speeds = np.array([rpm_to_speed(r, design.rolling_radius) for r in rpms])
    shape = (len(vcs), len(rpms))
    numbers = {k: np.full(shape, np.nan) for k in (*_NUMBERS, "time_to_saturation_s")}
    labels = {k: np.full(shape, "", dtype=object) for k in ("mode", "mechanism")}
    flags = {k: np.zeros(shape, dtype=bool) for k in ("squeals", "saturated")}
    named = ""
    report = ctx.progress.counter("sweep", "points") if vcs.size * rpms.size > 4 else None
    for (i, j), _ in np.ndenumerate(flags["squeals"]):
        if i or j:  # between points: the first is priced by its own plan
            ctx.budget.checkpoint(f"the sweep's point {i * len(rpms) + j + 1} of {vcs.size * rpms.size}")
        started = time.perf_counter()
        a = analyse(
            design,
            op=OperatingPoint(float(speeds[j]), float(vcs[i])),
            options=opts,
            context=ctx,
            modes=modeset,
        )
        if i == j == 0 and vcs.size * rpms.size > 1:  # the first point prices the others
            ctx.budget.check_work(
                f"the sweep's other {vcs.size * rpms.size - 1:,} points",
                (vcs.size * rpms.size - 1) * (time.perf_counter() - started - a.timings_s.get("modes", 0.0)),
                "use fewer points",
            )
        modeset = a.modeset
        v, o = a.verdict.to_dict(), a.verdict.outcome
        for k in _NUMBERS:
            numbers[k][i, j] = np.nan if v.get(k) is None else v[k]
        if not v["squeals"]:
            numbers["growth_rate_1_s"][i, j] = a.stability.growth_rate_1_s
        if o is not None and o.simulation is not None:
            numbers["time_to_saturation_s"][i, j] = o.simulation.limit_cycle.time_to_saturation_s
        labels["mode"][i, j], labels["mechanism"][i, j] = v["mode"] or "", v["mechanism"] or ""
        flags["squeals"][i, j], flags["saturated"][i, j] = v["squeals"], v["saturated"]
        named = a.decision.named.label() if a.decision.named is not None else ""
        if report is not None:
            report(i * len(rpms) + j + 1, vcs.size * rpms.size)
    return VerdictGrid(
        vcs,
        rpms,
        speeds,
        labels["mode"],
        flags["squeals"],
        flags["saturated"],
        numbers["amplitude_m_s"],
        numbers["tone_hz"],
        numbers["growth_rate_1_s"],
        numbers["time_to_saturation_s"],
        numbers["spl_db"],
        numbers["spl_dba"],
        numbers["sound_power_level_db"],
        labels["mechanism"],
        named,
        duration,
    )
