"""The whole chain at one operating point, as one function: design and operating point
in, one result out (modes, the stability of every mode, the verdict, the limit cycle
and its sound). ``run``, ``stability``, ``compare``, ``sweep`` and every study case
take their answer from it; :meth:`Analysis.to_dict` is ``summary.json``.

    import wheel_squeal as ws
    a = ws.analyse(ws.load_design(), rpm=800, crab_velocity=0.39)
    print(a.verdict.lines()[0])
"""

from __future__ import annotations

import contextlib
import math
import time
from dataclasses import dataclass, field, fields, replace
from typing import TYPE_CHECKING, Any

from .api import contact_law, modal_dof, operating_point, simulate
from .budget import Budget
from .design import Design
from .errors import RequestError
from .levels import squeal_sound
from .modes import compute_modes
from .plan import NO_REMEDY_HINT, stability_plan, verdict_plan
from .presets import DEFAULT_FIDELITY, DEFAULT_FMAX_HZ, Fidelity, fidelity_for
from .progress import Progress
from .remedy import margin_of, remedy_of
from .sound import Listener
from .stability import (
    ModeStabilityRow,
    StabilityTable,
    contact_dofs,
    excitable,
    multimode,
    named_mode,
    stability_table,
    wheel_speed_rad_s,
)
from .verdict import ModeOutcome, Verdict, wave_frequency_hz, wave_of

if TYPE_CHECKING:
    from fem.modes import Mode, ModeSet
    from reduced import ContactLaw, OperatingPoint, StabilityResult

    from .cache import StageCache
    from .stability import MultiMode

__all__ = ["Analysis", "ChainOptions", "analyse"]


@dataclass
class Analysis:
    """The chain's result at one operating point.

    design, fidelity, modeset (``fem.ModeSet``), operating_point and contact
    (``reduced``), rotation (whether the wheel's rotation is modelled) and its speed
    [rad/s]; rows: every excitable mode with its linear stability
    (:class:`~wheel_squeal.stability.ModeStabilityRow`), stability: the
    ``reduced.StabilityResult``; verdict: the answer
    (:class:`~wheel_squeal.verdict.Verdict`); multimode: the multi-mode run when asked
    for; timings_s: seconds per stage.
    """

    design: Design
    fidelity: Fidelity
    modeset: ModeSet
    operating_point: OperatingPoint
    contact: ContactLaw
    rotation: bool
    wheel_speed_rad_s: float
    rows: list[ModeStabilityRow]
    stability: StabilityResult
    verdict: Verdict
    multimode: MultiMode | None = None
    timings_s: dict[str, float] = field(default_factory=dict)

    @property
    def outcome(self) -> ModeOutcome | None:
        """The simulated mode the verdict rests on: the squealing one, else the named
        one, else the model's pick (None when nothing was simulated)."""
        v = self.verdict
        for o in (v.outcome, v.named, v.pick):
            if o is not None and o.simulation is not None:
                return o
        return None

    def to_dict(self) -> dict:
        """``summary.json``: the verdict first, then what it rests on."""
        from . import writers

        o = self.outcome
        rows = [r.to_dict(self.design) for r in self.rows]
        winner = max(range(len(rows)), key=lambda i: rows[i]["growth_rate_1_s"])
        out = {
            "verdict": self.verdict.to_dict(),
            **writers.modes_summary(self.design, self.modeset, o.mode if o else None, self.fidelity),
            "stability": rows,
            "winner": rows[winner],
            "rotation": self.rotation,
            "operating_point": writers.operating_point_summary(self.operating_point, self.design),
        }
        if o is not None and o.simulation is not None:
            out |= {k: v for k, v in o.simulation.summary().items() if k != "operating_point"}
            out["modal_parameters"] = writers.dof_summary(modal_dof(o.mode, self.design))
            out["sound"] = o.sound.summary() if o.sound is not None else None
        if self.multimode is not None:
            out["multimode"] = self.multimode.summary()
        return out


@dataclass(frozen=True)
class ChainOptions:
    """How :func:`analyse` computes (every field a keyword of :func:`analyse` too).

    Attributes
    ----------
    fidelity, solver, fmax_hz
        The FE preset, another solver for it, the band [Hz].
    mode
        "auto" (the design's named mode, else the model's pick) or a mode the user
        names (an index, ``n=3[,c=0]``, ``f=HZ``): an override, simulated as asked.
    rotation
        Model the wheel's rotation (travelling waves).
    multimode_count
        Integrate this many most unstable modes together (None: each mode alone); the
        mode that carries their limit cycle is the model's pick.
    duration
        Simulated time [s] (None: until the outcome is known).
    simulate_modes, sound
        Run the time domain and the radiation (False: the linear verdict alone, or no
        levels).
    listener
        Microphone and air (default: 0.05 m off the rim face, air at 20 degC).
    c22
        The creep coefficient (None: the design's; a number; "kalker").
    friction_law
        A name of ``reduced.FRICTION_LAWS`` (None: the design's).
    margin
        With no squeal, find how far the least stable mode is from growing (one root
        find, some 20 eigen-solves); False leaves it out (studies).
    simulate_stable
        Simulate a named mode even where it is linearly stable (from rest it decays:
        the run shows how); False takes the linear answer (studies).
    """

    fidelity: str | Fidelity = DEFAULT_FIDELITY
    solver: str | None = None
    fmax_hz: float = DEFAULT_FMAX_HZ
    mode: str = "auto"
    rotation: bool = False
    multimode_count: int | None = None
    duration: float | None = None
    simulate_modes: bool = True
    sound: bool = True
    listener: Listener | None = None
    c22: float | str | None = None
    friction_law: str | None = None
    margin: bool = True
    simulate_stable: bool = True


#: the keywords of :func:`analyse` that make its operating point
_OPERATING_POINT_KEYS = ("rpm", "speed", "crab_velocity", "angle_of_attack")


def analyse(
    design: Design,
    *,
    op: OperatingPoint | None = None,
    options: ChainOptions | None = None,
    modes: ModeSet | None = None,
    cache: StageCache | None = None,
    budget: Budget | None = None,
    progress: Progress | None = None,
    memo: dict | None = None,
    table: StabilityTable | None = None,
    **settings: Any,
) -> Analysis:
    """The chain at one operating point: modes, stability of every mode, the verdict
    (:mod:`wheel_squeal.verdict`), the limit cycle of the verdict's mode and its sound.

    Parameters
    ----------
    design : the wheel.
    op : the operating point (``reduced.OperatingPoint``), or, among ``settings``,
        ``rpm`` or ``speed`` (wheel speed in rev/min or rolling speed in m/s) and
        ``crab_velocity`` or ``angle_of_attack`` (m/s or rad); defaults 800 RPM and
        0.39 m/s.
    options : how it computes (:class:`ChainOptions`); the other ``settings`` replace
        its fields, as in ``analyse(d, rpm=600, fidelity="fast", sound=False)``.
    modes : the design's modes when already solved (with the options' fidelity and band).
    cache, budget, progress : the stage cache, the resource budget, progress on stderr.
    memo : a dict kept between calls of one process (a study's operating points): the
        radiation of each mode is computed once.
    table : the stability table at ``op`` when already solved (with bounds or not).

    Returns
    -------
    Analysis
    """
    at = {k: settings.pop(k) for k in _OPERATING_POINT_KEYS if k in settings}
    try:
        opts = replace(options or ChainOptions(), **settings)
    except TypeError:
        unknown = sorted(set(settings) - {f.name for f in fields(ChainOptions)})
        raise TypeError(f"analyse() got unknown settings {unknown}") from None
    progress = progress or Progress(quiet=True)
    fid = opts.fidelity if isinstance(opts.fidelity, Fidelity) else fidelity_for(opts.fidelity, opts.solver)
    op = op or operating_point(design, **at)
    timings: dict[str, float] = {}
    t0 = time.perf_counter()
    if modes is None:
        modes = compute_modes(
            design, fid, fmax_hz=opts.fmax_hz, cache=cache, progress=progress, budget=budget
        )
    timings["modes"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    contact = contact_law(design, opts.c22, opts.friction_law)
    budget = budget or Budget.from_environment()
    if table is None:
        stability_plan(design, modes, contact, opts.rotation, opts.margin).check(
            budget, "the linear stability", NO_REMEDY_HINT
        )
        n = len(excitable(modes, contact))
        with progress.stage(f"linear stability of {n} modes") if n > 200 else contextlib.nullcontext():
            table = stability_table(design, modes, contact, op, opts.rotation)
    rows, result = table
    timings["stability"] = time.perf_counter() - t0
    chain = _Chain(design, opts, fid, modes, contact, op, rows, progress, cache, budget, memo)
    chain.check_plan()
    multi, pick = chain.model_pick()
    verdict = chain.verdict(pick)
    timings["total"] = sum(timings.values())
    return Analysis(
        design, fid, modes, op, contact, opts.rotation, chain.omega, rows, result, verdict, multi, timings
    )


@dataclass
class _Chain:
    """One analysis in progress: what the verdict's rules need (the steps of
    :func:`analyse`)."""

    design: Design
    opts: ChainOptions
    fid: Fidelity
    modeset: ModeSet
    contact: ContactLaw
    op: OperatingPoint
    rows: list[ModeStabilityRow]
    progress: Progress
    cache: StageCache | None
    budget: Budget
    memo: dict | None

    def __post_init__(self) -> None:
        self.omega = wheel_speed_rad_s(self.design, self.op, self.opts.rotation)
        self.by_index = {r.mode.index: r for r in self.rows}
        self.growing = [r for r in self.rows if r.stability.unstable]

    def check_plan(self) -> None:
        """The rest of the request estimated before any of it runs
        (:func:`~wheel_squeal.plan.verdict_plan`), refused in one line beyond the budget."""
        named, _ = self.named()
        candidates = [m for m in (named,) if m is not None]
        if self.growing:
            fastest = max(self.rows, key=lambda r: r.stability.growth_rate_1_s).mode
            if fastest not in candidates:
                candidates.append(fastest)
        plan = verdict_plan(
            self.design, self.modeset, self.contact, self.op, self.opts, [r.mode for r in self.rows],
            [(m, self.together(m)) for m in candidates], bool(self.growing),
        )  # fmt: skip
        plan.check(self.budget, "the verdict", NO_REMEDY_HINT)

    def linear(self, m: Mode) -> ModeOutcome:
        """A mode's linear answer."""
        s = self.by_index[m.index].stability
        wave = wave_of(m, s.damped_frequency_hz, self.omega)
        return ModeOutcome(m, s.growth_rate_1_s, s.damped_frequency_hz, wave, mechanism=s.mechanism)

    def together(self, m: Mode) -> list[Mode]:
        """The modes that take part in ``m``'s fastest eigenvalue, ``m`` first: ``m``
        alone for an isolated mode, a coupled pair for mode coupling."""
        partners = self.by_index[m.index].stability.partners
        return [self.rows[k].mode for k in partners if k < len(self.rows)] or [m]

    def run(self, m: Mode) -> ModeOutcome:
        """A mode's time-domain answer from rest (its linear one where not simulated),
        integrated with the modes that share its fastest eigenvalue and the roller's."""
        o = self.linear(m)
        if not self.opts.simulate_modes or (not o.grows and not self.opts.simulate_stable):
            return o
        modes = self.together(m)
        dofs = contact_dofs(modes, self.design)
        which = m.label() + (f" with {', '.join(x.label() for x in modes[1:])}" if len(modes) > 1 else "")
        with self.progress.stage(f"squeal model of {which}"):
            sim = simulate(dofs, self.contact, self.op, self.opts.duration, self.omega, self.budget)
        f = float(sim.limit_cycle.frequency_hz)
        wave = wave_of(m, f if math.isfinite(f) else o.damped_frequency_hz, self.omega)
        return ModeOutcome(m, o.growth_rate_1_s, o.damped_frequency_hz, wave, sim, mechanism=o.mechanism)

    def heard(self, o: ModeOutcome) -> ModeOutcome:
        """The outcome with its sound (where it squeals and sound is asked for)."""
        if not (self.opts.sound and o.simulation is not None and o.squeals):
            return o
        with self.progress.stage(f"sound of {o.label}"):
            s = squeal_sound(
                self.design, self.modeset, o.mode, wave_frequency_hz(o.mode, o.wave, self.omega),
                o.simulation, o.tone_hz, listener=self.opts.listener, travelling=o.wave != "standing",
                fidelity=self.fid.name, fmax_hz=self.opts.fmax_hz, cache=self.cache, budget=self.budget,
                memo=self.memo,
            )  # fmt: skip
        return replace(o, sound=s)

    def named(self) -> tuple[Mode | None, str]:
        """The mode the user or the design names, and who names it."""
        named, source, _ = named_mode(self.design, self.modeset, self.opts.mode)
        if named is not None and named.index not in self.by_index:
            raise RequestError(f"mode {named.index} ({named.label()}) is not seen at the contact")
        return named, source

    def model_pick(self) -> tuple[MultiMode | None, ModeOutcome | None]:
        """The model's own pick: the carrier of the multi-mode limit cycle when asked
        for, else the fastest-growing mode (None: no mode grows)."""
        if not self.growing:
            return None, None
        if self.opts.multimode_count is None:
            fastest = max(self.rows, key=lambda r: r.stability.growth_rate_1_s)
            return None, self.linear(fastest.mode)
        with self.progress.stage("multi-mode squeal model"):
            multi = multimode(
                self.design, self.rows, self.contact, self.op, self.opts.rotation,
                self.opts.multimode_count, self.opts.duration, self.budget,
            )  # fmt: skip
        carrier = multi.carrier
        share = float(multi.content.energy_share[multi.modes.index(carrier)])
        base = self.linear(carrier)
        wave = wave_of(carrier, multi.content.peak_frequency_hz, self.omega)
        pick = ModeOutcome(
            carrier, base.growth_rate_1_s, base.damped_frequency_hz, wave, multi.simulation, None, share,
            base.mechanism,
        )  # fmt: skip
        return multi, pick

    def pick_words(self, p: ModeOutcome) -> str:
        n_grow = f"{len(self.growing)} of {len(self.rows)} modes grow"
        if p.energy_share is not None:
            return (
                f"{p.label} carries the multi-mode limit cycle ({p.energy_share:.0%} of its energy; {n_grow})"
            )
        rate = f"{p.growth_rate_1_s:.3g} 1/s at {p.damped_frequency_hz:.1f} Hz"
        partners = self.together(p.mode)[1:]
        coupled = f" with {', '.join(x.label() for x in partners)}" if partners else ""
        return f"{p.label}{coupled} grows fastest ({rate}, {p.mechanism}; {n_grow})"

    def loud(self, outcome: ModeOutcome, reason: str, named=None, pick=None) -> Verdict:
        """It squeals in ``outcome``: with its sound, and (``margin`` asked for) what
        would stop it."""
        remedy = None
        if self.opts.margin:
            remedy = remedy_of(
                self.design, self.rows, self.contact, self.op, outcome.mode, self.opts.rotation
            )
        return Verdict(True, self.heard(outcome), reason, named, pick, remedy=remedy)

    def quiet(self, reason: str, **extra: Any) -> Verdict:
        """No squeal, with how far the least stable mode is from growing."""
        far = None
        if self.opts.margin:
            far = margin_of(self.design, self.rows, self.contact, self.op, self.opts.rotation)
            reason = f"{reason}; {far['words']}"
        return Verdict(False, None, reason, margin=far, **extra)

    def verdict(self, pick: ModeOutcome | None) -> Verdict:
        """The one answer: a named mode first (simulated as asked), else the model's pick."""
        named, source = self.named()
        if named is not None:
            n_out = self.run(named)
            if n_out.squeals:
                beside = ""
                if pick is not None and pick.mode.index != named.index:
                    rate = f"{pick.tone_hz:.1f} Hz ({pick.growth_rate_1_s:.3g} 1/s)"
                    beside = f"; the model alone picks {pick.label} at {rate}"
                reason = f"{source} {named.label()}, simulated as asked{beside}"
                return self.loud(n_out, reason, n_out, pick)
            if pick is None:
                return self.quiet(f"{source} {named.label()}; no mode grows here", named=n_out)
            p_out = pick if pick.simulation is not None else self.run(pick.mode)
            stable = f"{source} {named.label()}, which does not squeal here ({n_out.growth_rate_1_s:.3g} 1/s)"
            if p_out.squeals:
                return self.loud(p_out, f"{stable}; {self.pick_words(p_out)}", n_out, p_out)
            return self.quiet(
                f"{stable}; {self.pick_words(p_out)} but does not sustain from rest", named=n_out, pick=p_out
            )
        if pick is None:
            return self.quiet("no mode grows here")
        p_out = pick if pick.simulation is not None else self.run(pick.mode)
        if p_out.squeals:
            return self.loud(p_out, self.pick_words(p_out), None, p_out)
        return self.quiet(
            f"{self.pick_words(p_out)} but its oscillation does not sustain from rest", pick=p_out
        )
