"""A railway line: every curve of it, under the friction the rail head has over the year,
as the noise-mapping tools take it: the squeal's occurrence probability, the bogie's
pass-by levels, the traffic's equivalent level per period and the line source's sound
power per metre per band (``acoustics.emission``).

A line is a CSV of curve sections (``id``, ``radius_m``, ``length_m``, ``cant_mm``,
``train_speed_km_h``; optionally ``x0``, ``y0``, ``x1``, ``y1`` in a projected coordinate
system, or a ``wkt`` LINESTRING). Its ``[line]`` spec (:class:`LineSpec`) gives the traffic
per period and the friction's distribution. Each curve is the curve map of its radius, speed
and cant (:func:`wheel_squeal.curve.curve`) at each friction state; the curves that share a
speed and a cant are one map. A friction state is a friction coefficient with its share of
the time, on a falling creep curve or, for the share of time a top-of-rail friction modifier
acts, a flat one. The squeal probability is the share of time some wheel of the bogie
squeals; the levels are those while it squeals (their energy mean over the squealing
states); the emission is the expected one (the squealing states' power times their share).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from acoustics.emission import PERIODS
from track.alignment import LineCurve

from .runtime.request_errors import RequestError
from .traffic import (
    LineSpec,
    load_line_spec,
    read_line_spec,
)

if TYPE_CHECKING:
    from acoustics.emission import CurveEmission, SquealState

    from .context import RunContext
    from .design import Design
    from .presets import Fidelity

__all__ = [
    "PERIODS",
    "LineCurve",
    "LineJob",
    "LineResult",
    "LineSpec",
    "line",
    "load_line",
    "load_line_spec",
    "read_line_spec",
    "run_line_job",
]


def load_line(path: Path) -> list[LineCurve]:
    """The curves of a line's CSV (``track.alignment.read_line``), with one-line errors."""
    from track.alignment import LineFileError, read_line

    try:
        return read_line(path)
    except LineFileError as exc:
        raise RequestError(str(exc)) from None


@dataclass(frozen=True)
class LineResult:
    """One curve of a line (module docstring): its squeal's occurrence, levels and emission
    (``acoustics.emission.CurveEmission``) and CNOSSOS-EU's flat correction for it [dB]."""

    curve: LineCurve
    emission: CurveEmission
    cnossos_correction_db: float


def _result(curve: LineCurve, states: list[SquealState], spec: LineSpec) -> LineResult:
    """One curve's result from its bogie's state in each friction state."""
    from acoustics.emission import cnossos_curve_correction_db, intermittent_emission

    per_hour = {p: spec.bogies_per_hour(p) for p, _ in PERIODS}
    emission = intermittent_emission(states, curve.train_speed_km_h / 3.6, _passby_distance_m(), per_hour)
    return LineResult(curve, emission, cnossos_curve_correction_db(curve.radius_m))


def _passby_distance_m() -> float:
    """From CNOSSOS-EU's wheel/rail source to the ISO 3095 microphone [m]."""
    from acoustics.emission import CNOSSOS_SOURCE_HEIGHT_M
    from acoustics.passby import MICROPHONE_DISTANCE_M, MICROPHONE_HEIGHT_M

    return math.hypot(MICROPHONE_DISTANCE_M, MICROPHONE_HEIGHT_M - CNOSSOS_SOURCE_HEIGHT_M)


#: The curves of one speed, cant and friction state one task takes (each curve's steady
#: curving starts from the last one's equilibrium; more tasks spread over more workers)
CURVES_PER_TASK = 25


@dataclass(frozen=True)
class LineJob:
    """One task of a line: the curve map of ``radii_m`` at one speed and cant, of the design
    in one friction state; the worker's cache folder (None: none; "": its default) and the
    limit of its modal solve."""

    design: Design
    radii_m: tuple[float, ...]
    train_speed_km_h: float
    cant_mm: float
    fidelity: Fidelity
    fmax_hz: float
    cache_dir: str | None
    max_dofs: float | None


def _failures() -> tuple[type[Exception], ...]:
    """The failures a line's task reports as its result (bad input or an anticipated
    failure of the computation), raised again in the caller's process by their name."""
    from fem.eigen import EigenError
    from geometry import MeshError
    from reduced.model import IntegrationError
    from track.bogie_curving import CurvingError

    return (RequestError, CurvingError, MeshError, EigenError, IntegrationError)


def _failure_type(name: str | None) -> type[Exception]:
    """The exception a task's failure named ``name`` is raised as in the caller's process:
    its own (:func:`_failures`, a budget's refusal), or, unnamed, an exhausted budget."""
    from .runtime.request_errors import BudgetError, BudgetExhausted

    named = {e.__name__: e for e in (*_failures(), BudgetError)}
    return named.get(name or "", BudgetExhausted)


def run_line_job(job: LineJob, context: RunContext | None = None) -> dict:
    """A :class:`LineJob` as a JSON-ready dict: ``status``, ``reason`` and per radius the
    bogie's ``squeals`` and what its pass-by leaves (``acoustics.emission.HeardPassby``);
    in ``context`` (this process's) or in a context of the job's own."""
    from acoustics.emission import HeardPassby

    from .context import RunContext
    from .curve import curve
    from .runtime.budget import Budget
    from .runtime.request_errors import BudgetError
    from .runtime.stage_cache import StageCache
    from .study.runner import transient

    if context is None:
        cache = None if job.cache_dir is None else StageCache(job.cache_dir or None)
        context = RunContext(job.fidelity, job.fmax_hz, cache, Budget.from_environment(job.max_dofs))
    try:
        cases = curve(
            job.design,
            list(job.radii_m),
            [job.train_speed_km_h],
            cant_mm=job.cant_mm,
            context=context,
            priced=True,
            counter_body_effect=False,
        )
    except BudgetError as exc:  # this run's limit, not the line's: computed again next time
        return {**transient(str(exc)), "error": "BudgetError"}
    except _failures() as exc:
        return {"status": "failed", "error": type(exc).__name__, "reason": str(exc)}
    speed, distance = job.train_speed_km_h / 3.6, _passby_distance_m()
    states = []
    for i in range(len(job.radii_m)):
        bogie = cases[4 * i : 4 * i + 4]
        passby = next((c.passby.free for c in bogie if c.passby is not None), None)
        heard = None if passby is None else HeardPassby.of(passby, speed, distance).to_dict()
        states.append({"squeals": any(c.analysis.verdict.squeals for c in bogie), "heard": heard})
    return {"status": "ok", "reason": "", "curves": states}


def check_line_result(result: dict, radii: int) -> None:
    """A stored line task's ``result`` (:func:`run_line_job`) as the line reads it: one
    state per radius of its job, each a flag and a pass-by (``ValueError``, ``KeyError``
    or ``TypeError`` where it is not)."""
    from acoustics.emission import HeardPassby

    curves = result["curves"]
    if not isinstance(curves, list) or len(curves) != radii:
        raise ValueError("a stored line task does not hold one state per radius")
    for state in curves:
        if not isinstance(state["squeals"], bool):
            raise ValueError("a stored line task's flag is not one")
        if state["heard"] is not None:
            HeardPassby.from_dict(state["heard"])


def line(
    design: Design,
    curves: Sequence[LineCurve],
    spec: LineSpec,
    *,
    context: RunContext | None = None,
    workers: int | None = 1,
    scheduler: str | None = None,
) -> list[LineResult]:
    """Every curve of a line under the friction of ``spec`` (module docstring), in the
    line's order. The curves that share a speed and a cant are one map per friction state,
    run as tasks of :data:`CURVES_PER_TASK` curves (:class:`LineJob`) as a study's cases
    are: in this process (``workers`` 1), on local processes (None: the cores) or on the
    dask scheduler at ``scheduler``; each finished task is kept in the context's cache, so
    that a line stopped and started again computes only what is missing."""
    import dataclasses
    import functools

    from acoustics.emission import HeardPassby, SquealState
    from track.curving import check_curve

    from .context import RunContext
    from .runtime.progress import Progress
    from .study.runner import code_key, local_workers, run_tasks, scheduler_of, store_result, stored_results

    ctx = context or RunContext.of("balanced")
    scheduler = scheduler_of(scheduler)
    vehicle = design.vehicle.vehicle()
    for c in curves:
        try:
            check_curve(c.radius_m, c.train_speed_km_h, vehicle.wheelbase_m, c.cant_mm)
        except ValueError as exc:
            raise RequestError(f"curve {c.id}: {exc}") from None
    groups: dict[tuple[float, float], list[LineCurve]] = {}
    for c in curves:
        groups.setdefault((c.train_speed_km_h, c.cant_mm), []).append(c)
    states = spec.states()
    n_local = 1 if scheduler else local_workers(workers, ctx.progress)
    cache_dir = (
        None if ctx.cache is None or not ctx.cache.enabled else "" if scheduler else str(ctx.cache.root)
    )
    jobs: list[tuple[LineJob, int]] = []  # and the index of its friction state
    for (speed, cant), members in groups.items():
        radii = sorted({spec.grid_radius_m(c.radius_m) for c in members}, reverse=True)
        for k, (mu, law, _) in enumerate(states):
            treated = design.replace(friction_coefficient=mu, friction_law=law)
            for i in range(0, len(radii), CURVES_PER_TASK):
                chunk = tuple(radii[i : i + CURVES_PER_TASK])
                job = LineJob(
                    treated, chunk, speed, cant, ctx.fidelity, ctx.fmax_hz, cache_dir, ctx.budget.max_dofs
                )
                jobs.append((job, k))
    base = {"stage": "line-task", **code_key(), "fmax_hz": ctx.fmax_hz}
    keys = [
        {
            **base,
            "fidelity": repr(j.fidelity),
            "design": j.design.content_hash(),
            "radii": list(j.radii_m),
            "speed": j.train_speed_km_h,
            "cant": j.cant_mm,
        }
        for j, _ in jobs
    ]
    results = stored_results(keys, ctx.cache, lambda i, r: check_line_result(r, len(jobs[i][0].radii_m)))
    # the tightest curves first (their squeals' balance and sound cost most), so that no
    # worker is left alone with one at the end
    missing = sorted((i for i, r in enumerate(results) if r is None), key=lambda i: min(jobs[i][0].radii_m))
    todo = {i: jobs[i][0] for i in missing}
    report = ctx.progress.counter(f"{len(curves):,} curves x {len(states)} friction states", "tasks")
    ctx.progress.say(f"line: {len(jobs)} tasks, {len(jobs) - len(todo)} from an earlier run")

    def done(i: int, result: dict) -> None:
        ctx.budget.checkpoint(f"the line's task {i}")
        results[i] = result
        store_result(ctx.cache, keys[i], result)
        report(sum(r is not None for r in results), len(results))

    # the tasks quiet, the line's counter the one progress line; the memo (modes, radiation) shared
    here = functools.partial(run_line_job, context=dataclasses.replace(ctx, progress=Progress(quiet=True)))
    if todo and not scheduler and n_local > 1:
        # one curve of the cheapest task here first: the workers inherit its modes, the
        # rail's fits and the contact tables instead of each making them
        first = todo[missing[-1]]
        here(dataclasses.replace(first, radii_m=first.radii_m[-1:]))
    run_tasks(
        todo, run_line_job if scheduler else here, done, n_local, scheduler, ctx.progress, lambda n: None
    )
    failed = next((r for r in results if r is not None and r["status"] != "ok"), None)
    if failed is not None:
        # a task that failed without a name of its own lost its worker process (memory)
        raise _failure_type(failed.get("error"))(f"the line: {failed['reason']}")
    by_curve: dict[str, list[SquealState]] = {c.id: [] for c in curves}
    for (job, k), result in zip(jobs, results):
        assert result is not None  # every task has run
        at = dict(zip(job.radii_m, result["curves"]))
        (speed, cant), share = (job.train_speed_km_h, job.cant_mm), states[k][2]
        for c in groups[(speed, cant)]:
            state = at.get(spec.grid_radius_m(c.radius_m))
            if state is not None:
                heard = None if state["heard"] is None else HeardPassby.from_dict(state["heard"])
                by_curve[c.id].append(SquealState(share, state["squeals"], heard))
    return [_result(c, by_curve[c.id], spec) for c in curves]
