"""The whole chain at one operating point, as one function: design and operating point
in, one result out (modes, the stability of every mode, the verdict, the limit cycle
and its sound). ``run``, ``stability``, ``compare``, ``sweep`` and every study case
take their answer from it; :meth:`Analysis.to_dict` is ``summary.json``.

    import wheel_squeal as ws
    a = ws.analyse(ws.load_design(), rpm=800, crab_velocity=0.39)
    print(a.verdict.lines()[0])
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from .api import contact_law, modal_dof, operating_point, simulate
from .design import Design
from .errors import RequestError
from .modes import compute_modes, pick_mode
from .presets import DEFAULT_FIDELITY, DEFAULT_FMAX_HZ, Fidelity, fidelity_for
from .progress import Progress
from .sound import Listener, mode_sound
from .stability import ModeStabilityRow, margin_of, multimode, stability_table, wheel_speed_rad_s
from .verdict import ModeOutcome, Verdict, wave_frequency_hz, wave_of

if TYPE_CHECKING:
    from fem.modes import Mode, ModeSet
    from reduced import ContactLaw, OperatingPoint, StabilityResult

    from .budget import Budget
    from .cache import StageCache
    from .stability import MultiMode

__all__ = ["Analysis", "analyse"]


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


def analyse(
    design: Design,
    *,
    rpm: float | None = None,
    speed: float | None = None,
    crab_velocity: float | None = None,
    angle_of_attack: float | None = None,
    op: OperatingPoint | None = None,
    fidelity: str | Fidelity = DEFAULT_FIDELITY,
    solver: str | None = None,
    fmax_hz: float = DEFAULT_FMAX_HZ,
    mode: str = "auto",
    rotation: bool = False,
    multimode_count: int | None = None,
    duration: float | None = None,
    simulate_modes: bool = True,
    sound: bool = True,
    listener: Listener | None = None,
    c22: float | str | None = None,
    modes: ModeSet | None = None,
    cache: StageCache | None = None,
    budget: Budget | None = None,
    progress: Progress | None = None,
    memo: dict | None = None,
    margin: bool = True,
    simulate_stable: bool = True,
) -> Analysis:
    """The chain at one operating point: modes, stability of every mode, the verdict
    (:mod:`wheel_squeal.verdict`), the limit cycle of the verdict's mode and its sound.

    Parameters
    ----------
    design : the wheel.
    rpm, speed, crab_velocity, angle_of_attack : the operating point (wheel speed in
        rev/min or rolling speed in m/s; crabbing velocity in m/s or angle of attack in
        rad; defaults 800 RPM and 0.39 m/s), or ``op`` (``reduced.OperatingPoint``).
    fidelity, solver, fmax_hz : the FE preset, another solver for it, the band [Hz].
    mode : "auto" (the design's named mode, else the model's pick) or a mode the user
        names (an index, ``n=3[,c=0]``, ``f=HZ``): an override, simulated as asked.
    rotation : model the wheel's rotation (travelling waves).
    multimode_count : integrate this many most unstable modes together (None: each mode
        alone); the mode that carries their limit cycle is the model's pick.
    duration : simulated time [s] (None: until the outcome is known).
    simulate_modes, sound : run the time domain and the radiation (False: the linear
        verdict alone, or no levels).
    listener : microphone and air (default: 0.05 m off the rim face, air at 20 degC).
    c22 : the creep coefficient (None: the design's; a number; "kalker").
    modes : the design's modes when already solved (with ``fidelity`` and ``fmax_hz``).
    cache, budget, progress : the stage cache, the resource budget, progress on stderr.
    memo : a dict kept between calls of one process (a study's operating points): the
        radiation of each mode is computed once.
    margin : with no squeal, find how far the least stable mode is from growing (one
        root find, some 20 eigen-solves); False leaves it out (studies).
    simulate_stable : simulate a named mode even where it is linearly stable (from rest
        it decays: the run shows how); False takes the linear answer (studies).

    Returns
    -------
    Analysis
    """
    progress = progress or Progress(quiet=True)
    fid = fidelity if isinstance(fidelity, Fidelity) else fidelity_for(fidelity, solver)
    op = op or operating_point(
        design, rpm=rpm, speed=speed, crab_velocity=crab_velocity, angle_of_attack=angle_of_attack
    )
    contact = contact_law(design, c22)
    timings: dict[str, float] = {}
    t0 = time.perf_counter()
    ms = (
        modes
        if modes is not None
        else compute_modes(design, fid, fmax_hz=fmax_hz, cache=cache, progress=progress, budget=budget)
    )
    timings["modes"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    rows, result = stability_table(design, ms, contact, op, rotation)
    timings["stability"] = time.perf_counter() - t0
    omega = wheel_speed_rad_s(design, op, rotation)
    by_index = {r.mode.index: r for r in rows}

    named, source = None, ""
    if mode != "auto":
        named, _ = pick_mode(ms, mode)
        source = f"--mode {mode} asks for"
    elif design.squeal.mode:
        named, _ = pick_mode(ms, design.squeal.mode)
        source = f"the design {design.name} names"
    if named is not None and named.index not in by_index:
        modal_dof(named, design)  # its one-line refusal: a node at the contact
        raise RequestError(f"mode {named.index} ({named.label()}) is not seen at the contact")

    def linear(m: Mode) -> ModeOutcome:
        s = by_index[m.index].stability
        return ModeOutcome(
            m, s.growth_rate_1_s, s.damped_frequency_hz, wave_of(m, s.damped_frequency_hz, omega)
        )

    def run(m: Mode) -> ModeOutcome:
        o = linear(m)
        if not simulate_modes or (not o.grows and not simulate_stable):
            return o
        with progress.stage(f"squeal model of {m.label()}"):
            sim = simulate(modal_dof(m, design), contact, op, duration, omega, budget)
        f = float(sim.limit_cycle.frequency_hz)
        wave = wave_of(m, f if math.isfinite(f) else o.damped_frequency_hz, omega)
        return ModeOutcome(m, o.growth_rate_1_s, o.damped_frequency_hz, wave, sim)

    def heard(o: ModeOutcome) -> ModeOutcome:
        if not (sound and o.simulation is not None and o.squeals):
            return o
        with progress.stage(f"sound of {o.label}"):
            s = mode_sound(
                design, ms, o.mode, wave_frequency_hz(o.mode, o.wave, omega), o.amplitude_m_s or 0.0,
                listener=listener, travelling=o.wave != "standing", fidelity=fid.name, fmax_hz=fmax_hz,
                cache=cache, budget=budget, memo=memo,
            )  # fmt: skip
        return ModeOutcome(
            o.mode, o.growth_rate_1_s, o.damped_frequency_hz, o.wave, o.simulation, s, o.energy_share
        )

    growing = [r for r in rows if r.stability.unstable]
    fastest = max(rows, key=lambda r: r.stability.growth_rate_1_s)
    multi = None
    pick: ModeOutcome | None = None
    if growing and multimode_count is not None:
        with progress.stage("multi-mode squeal model"):
            multi = multimode(design, rows, contact, op, rotation, multimode_count, duration, budget)
        carrier = multi.carrier
        share = float(multi.content.energy_share[multi.modes.index(carrier)])
        f = multi.content.peak_frequency_hz
        base = linear(carrier)
        wave = wave_of(carrier, f, omega)
        pick = ModeOutcome(
            carrier, base.growth_rate_1_s, base.damped_frequency_hz, wave, multi.simulation, None, share
        )
    elif growing:
        pick = linear(fastest.mode)
    n_grow = f"{len(growing)} of {len(rows)} modes grow"

    def pick_words(p: ModeOutcome) -> str:
        if p.energy_share is not None:
            return (
                f"{p.label} carries the multi-mode limit cycle ({p.energy_share:.0%} of its energy; {n_grow})"
            )
        rate = f"{p.growth_rate_1_s:.3g} 1/s at {p.damped_frequency_hz:.1f} Hz"
        return f"{p.label} grows fastest ({rate}; {n_grow})"

    def quiet(reason: str, **extra) -> Verdict:
        far = margin_of(design, rows, contact, op, rotation) if margin else None
        return Verdict(False, None, reason, margin=far, **extra)

    if named is not None:
        n_out = run(named)
        if n_out.squeals:
            beside = ""
            if pick is not None and pick.mode.index != named.index:
                rate = f"{pick.tone_hz:.1f} Hz ({pick.growth_rate_1_s:.3g} 1/s)"
                beside = f"; the model alone picks {pick.label} at {rate}"
            verdict = Verdict(
                True, heard(n_out), f"{source} {named.label()}, simulated as asked{beside}", n_out, pick
            )
        elif pick is not None:
            p_out = pick if pick.simulation is not None else run(pick.mode)
            stable = f"{source} {named.label()}, which does not squeal here ({n_out.growth_rate_1_s:.3g} 1/s)"
            if p_out.squeals:
                verdict = Verdict(True, heard(p_out), f"{stable}; {pick_words(p_out)}", n_out, p_out)
            else:
                verdict = quiet(
                    f"{stable}; {pick_words(p_out)} but does not sustain from rest", named=n_out, pick=p_out
                )
        else:
            verdict = quiet(f"{source} {named.label()}; no mode grows here", named=n_out)
    elif pick is not None:
        p_out = pick if pick.simulation is not None else run(pick.mode)
        if p_out.squeals:
            verdict = Verdict(True, heard(p_out), pick_words(p_out), None, p_out)
        else:
            verdict = quiet(f"{pick_words(p_out)} but its oscillation does not sustain from rest", pick=p_out)
    else:
        verdict = quiet("no mode grows here")
    if not verdict.squeals and verdict.margin is not None:
        verdict = Verdict(
            False,
            None,
            f"{verdict.reason}; {verdict.margin['words']}",
            verdict.named,
            verdict.pick,
            verdict.margin,
        )
    timings["total"] = sum(timings.values())
    return Analysis(design, fid, ms, op, contact, rotation, omega, rows, result, verdict, multi, timings)
