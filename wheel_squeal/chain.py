"""The chain at one operating point, as one function: design and operating point in, one
result out. Every command that reports a squeal takes its answer from it, stopping after
the stage it needs (:data:`wheel_squeal.types.Stage`):

    modes -> stability of every mode (once) -> the decision (``wheel_squeal.decision``)
    -> "stability": the linear verdict
    -> the time domain of what the decision integrates -> "limit_cycle": the verdict
    -> the sound of the verdict's mode -> "sound": the verdict with its levels

    import wheel_squeal as ws
    a = ws.analyse(ws.load_design(), rpm=800, crabbing_velocity_m_s=0.39)
    print(a.verdict.squeals, a.verdict.get("mode"))
"""

from __future__ import annotations

import time
from dataclasses import fields, replace
from typing import TYPE_CHECKING, Any, get_args

from .analysis import STAGES, Analysis, ChainOptions
from .api import contact_law, operating_point
from .context import RunContext
from .decision import modes_of_eigenvalue
from .design import Design
from .fe_stages import context_modes
from .mode_stability import StabilityTable, body_of, excitable, mode_dofs, stability_table
from .outcomes import Outcomes
from .plan import NO_REMEDY_HINT, stability_plan, verdict_plan
from .presets import Fidelity, fidelity_for
from .runtime.request_errors import RequestError
from .simulation import simulate
from .types import AmplitudeMethod
from .verdict import LOWEST_SQUEAL_HZ, ModeOutcome, Verdict
from .verdict_remedy import margin_of, remedy_design, remedy_of

if TYPE_CHECKING:
    from fem.modes import ModeSet
    from reduced import OperatingPoint


__all__ = ["AMPLITUDE_METHODS", "Analysis", "ChainOptions", "analyse"]  # the record and options: .analysis

#: The amplitude methods, the faster last
AMPLITUDE_METHODS: tuple[AmplitudeMethod, ...] = get_args(AmplitudeMethod)
#: The keywords of :func:`analyse` that make its operating point
_OPERATING_POINT_KEYS = ("rpm", "rolling_speed_m_s", "crabbing_velocity_m_s", "angle_of_attack_rad")
#: The keywords of :func:`analyse` that make its context
_CONTEXT_KEYS = ("fidelity", "solver", "fmax_hz", "cache", "budget", "progress")


def analyse(
    design: Design,
    *,
    op: OperatingPoint | None = None,
    options: ChainOptions | None = None,
    context: RunContext | None = None,
    modes: ModeSet | None = None,
    table: StabilityTable | None = None,
    **settings: Any,
) -> Analysis:
    """The chain at one operating point (see the module docstring).

    Parameters
    ----------
    design : Design
        The wheel and its counter-body, contact and damping.
    op : reduced.OperatingPoint, optional
        The operating point; or, among ``settings``, those of
        :func:`~wheel_squeal.api.operating_point` (``rpm`` or ``rolling_speed_m_s``,
        ``crabbing_velocity_m_s`` or ``angle_of_attack_rad``); defaults 800 RPM and
        0.39 m/s.
    options : ChainOptions, optional
        What it computes; the other ``settings`` replace its fields, as in
        ``analyse(d, rpm=600, stop_after="limit_cycle")``.
    context : RunContext, optional
        How it computes and what it may spend; ``settings`` may give its ``fidelity``,
        ``solver``, ``fmax_hz``, ``cache``, ``budget`` and ``progress`` instead.
    modes : fem.ModeSet, optional
        The design's modes when already solved (a modal model's, or the context's band).
    table : StabilityTable, optional
        The stability at ``op`` when already solved (with bounds or not).

    Returns
    -------
    Analysis
        The verdict and what it rests on.

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> a = ws.analyse(ws.load_design(), fidelity="fast", fmax_hz=3000.0, stop_after="stability")
    >>> a.verdict.squeals, a.verdict.get("mode")
    (True, '(3,0) axial')
    """
    at = {k: settings.pop(k) for k in _OPERATING_POINT_KEYS if k in settings}
    ctx_settings = {k: settings.pop(k) for k in _CONTEXT_KEYS if k in settings}
    try:
        opts = replace(options or ChainOptions(), **settings)
    except TypeError:
        unknown = sorted(set(settings) - {f.name for f in fields(ChainOptions)})
        raise TypeError(f"analyse() got unknown settings {unknown}") from None
    if opts.stop_after not in STAGES:
        raise RequestError(f"stop_after must be one of {', '.join(STAGES)}, got {opts.stop_after!r}")
    if opts.amplitude not in AMPLITUDE_METHODS:
        raise RequestError(f"amplitude must be one of {', '.join(AMPLITUDE_METHODS)}, got {opts.amplitude!r}")
    ctx = _context(context, ctx_settings)
    op = op or operating_point(design, **at)
    timings: dict[str, float] = {}
    t0 = time.perf_counter()
    if modes is None:
        modes = context_modes(design, ctx)
    timings["modes"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    contact = contact_law(design, opts.c22, opts.friction_law)
    seen = excitable(modes, contact)
    dofs = mode_dofs(seen, design) if seen else None  # none: stability_table says so
    if table is None:
        plan = stability_plan(design, modes, contact, opts.rotation, opts.remedy, dofs)
        plan.check(ctx.budget, "the linear stability", NO_REMEDY_HINT)
        with ctx.progress.stage(f"linear stability of {len(seen)} modes") if len(seen) > 200 else _nothing():
            rows = opts.stable_rows or opts.remedy or opts.mode != "model"  # who reads them
            table = stability_table(design, modes, contact, op, opts.rotation, dofs=dofs, stable_rows=rows)
    timings["stability"] = time.perf_counter() - t0
    ctx.budget.checkpoint("the linear stability")
    chain = _Chain(design, opts, ctx, modes, contact, op, table, dofs)
    verdict = chain.verdict()
    timings["total"] = sum(timings.values())
    return Analysis(
        design, opts, ctx.fidelity, modes, op, contact, table, chain.decision, verdict, chain.omega, timings
    )


def _context(context: RunContext | None, settings: dict[str, Any]) -> RunContext:
    if context is not None:
        return replace(context, **{k: v for k, v in settings.items() if k in ("cache", "budget", "progress")})
    fidelity: Any = settings.get("fidelity") or "balanced"
    fid = fidelity if isinstance(fidelity, Fidelity) else fidelity_for(fidelity, settings.get("solver"))
    ctx = RunContext.of(
        fid, cache=settings.get("cache"), budget=settings.get("budget"), progress=settings.get("progress")
    )
    if settings.get("fmax_hz") is not None:
        ctx = replace(ctx, fmax_hz=float(settings["fmax_hz"]))
    return ctx


class _nothing:
    def __enter__(self) -> None:
        return None

    def __exit__(self, *exc: object) -> None:
        return None


class _Chain(Outcomes):
    """One analysis in progress: the steps of :func:`analyse` after the stability, from
    the outcomes (:class:`~wheel_squeal.outcomes.Outcomes`) to the verdict."""

    # -- the verdict ----------------------------------------------------------------------
    def verdict(self) -> Verdict:
        """The one answer (:meth:`decide_verdict`), with what a counter-body's own degrees of
        freedom (a rail's, a roller's modes) add to it."""
        v = self.decide_verdict()
        if v.outcome is not None:
            v = replace(v, damping=self.design.damping_source(v.outcome.mode))
        body = body_of(self.design)
        if body is None or not self.opts.counter_body_effect:
            return v
        rigid = self.rigid_growth_rate()
        fastest = float(self.table.result.eigenvalues.real.max())
        effect = fastest - rigid
        noun = body.name.removeprefix("the ")
        words = (
            f"; {body.name} {'adds' if effect >= 0 else 'removes'} {abs(effect):.3g} 1/s at the fastest "
            f"eigenvalue ({fastest:.3g} 1/s; {rigid:.3g} 1/s on a rigid {noun})"
        )
        return replace(v, reason=v.reason + words, counter_body_effect_1_s=effect)

    def rigid_growth_rate(self) -> float:
        """The fastest growth rate [1/s] with the counter-body rigid (its degrees of
        freedom left out, the contact as it is)."""
        from reduced import largest_growth_rate

        dofs = self.dofs if self.dofs is not None else mode_dofs([r.mode for r in self.rows], self.design)
        return largest_growth_rate(dofs, self.contact, self.op, self.omega)

    def decide_verdict(self) -> Verdict:
        """The one answer: the named mode as asked where it squeals, else the model's own
        outcome; never "no squeal" while a mode grows and sustains."""
        d = self.decision
        simulated = [(d.named, d.named_group)] if d.named is not None else []
        if d.growing:
            simulated.append((d.fastest or d.growing[0], d.growing))
        if self.opts.reaches("limit_cycle"):
            plan = verdict_plan(
                self.design,
                self.modeset,
                self.contact,
                self.op,
                self.opts,
                [r.mode for r in self.rows],
                simulated,
                bool(d.growing),
                self.opts.reaches("sound"),
            )
            plan.check(self.ctx.budget, "the verdict", NO_REMEDY_HINT)
            if self.opts.beside and len(d.growing) > 1:
                # the model's several modes run compiled: load that first, and the named
                # mode runs compiled too instead of being interpreted (the same bits)
                from reduced import load_compiled_kernels

                load_compiled_kernels()
        named = self.named_outcome()
        model = self.model_outcome(integrate=not (named is not None and named.squeals) or self.opts.beside)
        if named is not None and named.squeals:
            beside = f"; the model alone: {self.model_words(model)}" if model is not None else ""
            how = (
                "integrated" if named.simulation is not None else "balanced" if named.balance else "reported"
            )
            return self.loud(named, f"{d.named_by} {named.label}, {how} as asked{beside}", named, model)
        if model is None:
            stable = f"{d.named_by} {named.label}; " if named is not None else ""
            return self.quiet(f"{stable}no mode grows here", named=named)
        words = self.model_words(model)
        if named is not None:
            rate = f"{named.growth_rate_1_s:.3g} 1/s"
            words = f"{d.named_by} {named.label}, which does not squeal here ({rate}); {words}"
        if model.squeals:
            return self.loud(model, words, named, model)
        # whether it squeals is the decision's (it grows at steady sliding), whatever the
        # amplitude method; the time domain's record that dies out from rest is said beside
        beside = f"{words}; its time domain from rest does not sustain: no amplitude from it"
        return self.loud(model, beside, named, model)

    def model_outcome(self, integrate: bool = True) -> ModeOutcome | None:
        """The model's own outcome (None: nothing grows); its linear pick where the
        request stops before the time domain or ``integrate`` is False."""
        d = self.decision
        if not d.growing:
            return None
        if not (integrate and self.opts.reaches("limit_cycle")):
            return self.linear(d.fastest or d.growing[0])
        return self.run(d.growing)

    def named_outcome(self) -> ModeOutcome | None:
        """The override's outcome (None: nothing named)."""
        d = self.decision
        if d.named is None:
            return None
        out = self.linear(d.named)
        if not self.opts.reaches("limit_cycle") or (not out.grows and not self.opts.simulate_stable):
            return out
        return self.run(d.named_group)

    def model_words(self, o: ModeOutcome) -> str:
        n_grow = f"{len(self.table.growing)} of {len(self.rows)} modes grow"
        if o.shares is not None and o.group and len(o.group) > 1 and o.simulation is not None:
            together = len(o.group)
            left = f", {self.decision.left_out} more left out" if self.decision.left_out else ""
            share = f"{o.energy_share:.1%}" if o.energy_share is not None else "most"
            return (
                f"{o.label} carries the limit cycle of the {together} modes that grow together ({share} of "
                f"its energy; {n_grow}{left}), {o.growth_rate_1_s:.3g} 1/s, {o.mechanism}"
            )
        rate = f"{o.growth_rate_1_s:.3g} 1/s at {o.damped_frequency_hz:.1f} Hz"
        partners = o.group[1:] if o.group else ()
        coupled = f" with {', '.join(x.label() for x in partners)}" if partners else ""
        return f"{o.label}{coupled} grows fastest ({rate}, {o.mechanism}; {n_grow})"

    def loud(
        self, outcome: ModeOutcome, reason: str, named: ModeOutcome | None, pick: ModeOutcome | None
    ) -> Verdict:
        """It squeals in ``outcome``: with its sound, and (``remedy`` asked for) what
        would stop it."""
        if outcome.tone_hz < LOWEST_SQUEAL_HZ:
            low = (
                f"{reason}; its oscillation is at {outcome.tone_hz:.3g} Hz, below {LOWEST_SQUEAL_HZ:g} Hz: "
                "an instability of the wheel, not a squeal one hears"
            )
            return Verdict(False, None, low, named, pick)
        remedy = self.remedy(outcome) if self.opts.remedy else None
        return Verdict(True, self.heard(outcome), reason, named, pick, remedy=remedy)

    def remedy(self, outcome: ModeOutcome) -> dict[str, Any]:
        """What stops every growing mode (``remedy_of``), its damping checked once more by
        integrating the verdict's modes with it from rest: the record must decay."""
        result = self.table.result
        growing = [j for j in result.ranked() if result.eigenvalues[j].real > 0.0]
        mechanisms = [
            (result.mechanisms[j] if result.mechanisms else None, modes_of_eigenvalue(self.table, j))
            for j in growing
        ]
        with self.ctx.progress.stage("remedy"):
            r = remedy_of(self.design, self.rows, self.contact, self.op, self.opts.rotation, mechanisms)
        if r["settled"] and self.opts.reaches("limit_cycle") and outcome.simulation is not None:
            group = outcome.group or (outcome.mode,)
            damped = remedy_design(self.design, r["paste"])
            with self.ctx.progress.stage("the remedy checked in the time domain"):
                sim = simulate(
                    mode_dofs(group, damped),
                    self.contact,
                    self.op,
                    self.opts.duration,
                    self.omega,
                    self.ctx.budget,
                    body_of(damped),
                    damped.counter_body.PRELOADED,
                )
            r["time_domain"] = sim.limit_cycle.state
            if sim.limit_cycle.squeal:
                r["settled"] = False
                r["words"] = (
                    f"{r['words']} (but integrated with them the record still {sim.limit_cycle.state})"
                )
        return r

    def quiet(self, reason: str, **extra: Any) -> Verdict:
        """No squeal, with how far the least stable mode is from growing."""
        far = None
        if self.opts.remedy:
            far = margin_of(self.design, self.rows, self.contact, self.op, self.opts.rotation)
            reason = f"{reason}; {far['words']}"
        return Verdict(False, None, reason, margin=far, **extra)
