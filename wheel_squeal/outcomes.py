"""How the chain finds one outcome at an operating point, once the stability is solved
and the decision made: a mode's linear answer (the eigenvalue that speaks for it), its
limit cycle by the request's amplitude method (the time domain of the modes integrated
together with the counter-body, or the harmonic balance of the mode named for them), the
mode that carries it, and its sound. :mod:`wheel_squeal.chain` turns outcomes into the
verdict."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from acoustics.harmonics import radiation_frequency_hz

from .analysis import ChainOptions
from .context import RunContext
from .decision import decide, eigenvalue_of, group_label, modes_of_eigenvalue
from .design import Design
from .mode_stability import (
    StabilityTable,
    body_of,
    dof_labels,
    mode_dofs,
    named_mode,
    wheel_speed_rad_s,
)
from .outputs import finite_or_none
from .runtime.request_errors import RequestError
from .simulation import simulate
from .squeal_sound import squeal_sound
from .verdict import COUPLING_ONLY, Balance, ModeOutcome, wave_of

if TYPE_CHECKING:
    from collections.abc import Sequence

    from fem.modes import Mode, ModeSet
    from reduced import BodyModel, ContactLaw, ModalDOF, OperatingPoint

    from .simulation import Simulation

__all__ = ["Outcomes"]


@dataclass
class Outcomes:
    """One analysis in progress after the stability: its decision and the outcomes the
    verdict is made of (module docstring)."""

    design: Design
    opts: ChainOptions
    ctx: RunContext
    modeset: ModeSet
    contact: ContactLaw
    op: OperatingPoint
    table: StabilityTable
    #: the table's rows' modes as ``reduced.ModalDOF`` (None: found where needed)
    dofs: Sequence[ModalDOF] | None = None

    def __post_init__(self) -> None:
        self.omega = wheel_speed_rad_s(self.design, self.op, self.opts.rotation)
        self.rows = self.table.rows
        self.by_index = {r.mode.index: r for r in self.rows}
        self.row_of = {r.mode.index: k for k, r in enumerate(self.rows)}
        named = named_mode(self.design, self.modeset, self.opts.mode)
        if named.mode is not None and named.mode.index not in self.by_index:
            raise RequestError(f"mode {named.mode.index} ({named.mode.label()}) is not seen at the contact")
        self.decision = decide(self.table, named, self.opts.max_modes)

    # -- the outcomes ---------------------------------------------------------------------
    def linear(self, m: Mode) -> ModeOutcome:
        """A mode's linear answer: of the eigenvalue that speaks for it (the fastest-growing
        one it takes part in: a coupled pair's eigenvalue for both its modes)."""
        j = eigenvalue_of(self.table, self.row_of[m.index])
        lam = self.table.result.eigenvalues[j]
        f = abs(float(lam.imag)) / (2 * math.pi)
        mechanism = self.table.result.mechanisms[j] if self.table.result.mechanisms else None
        return ModeOutcome(m, float(lam.real), f, wave_of(m, f, self.omega), mechanism=mechanism)

    def run(self, group: tuple[Mode, ...]) -> ModeOutcome:
        """The limit cycle of ``group`` (its first mode the one named for it) by the
        request's amplitude method: the time domain (:meth:`integrate`) or the harmonic
        balance (:meth:`balance`)."""
        if self.opts.amplitude == "harmonic balance":
            return self.balance(group)
        return self.integrate(group)

    def balance(self, group: tuple[Mode, ...]) -> ModeOutcome:
        """The harmonic balance of the mode named for ``group`` (the named mode, or the
        model's linear pick): its damping changed so that its growth rate alone is the one
        the whole linear model gives it with the counter-body and the other modes
        (``reduced.equivalent_mode``), then the energy balance over one harmonic cycle
        (``reduced.predict_limit_cycle``). Mode coupling alone has no falling branch to
        balance: its amplitude is left to the time domain, and said so."""
        import warnings

        from reduced import equivalent_mode, harmonic_distortion, predict_limit_cycle

        from .api import modal_dof

        head = group[0] if self.decision.named is not None and group[0] == self.decision.named else None
        carrier, competed = head or self.decision.fastest or group[0], ""
        if head is None and len(group) > 1:
            carrier, competed = self.competition(group, carrier)
        base = replace(self.linear(carrier), group=tuple(group))
        if not base.grows:
            return base
        if base.mechanism == "mode coupling":
            return replace(base, balance=Balance(None, note=COUPLING_ONLY))
        eq, clipped = equivalent_mode(
            modal_dof(carrier, self.design), self.contact, self.op, base.growth_rate_1_s
        )
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # the distortion is reported instead
            amplitude = predict_limit_cycle(eq, self.contact, self.op).velocity_amplitude_m_s
        if not (math.isfinite(amplitude) and amplitude > 0):
            return replace(base, balance=Balance(None, note="no stable limit cycle in the harmonic balance"))
        clipped_note = (
            "the rest of the system adds more than the mode's damping: a lower bound" if clipped else ""
        )
        note = "; ".join(n for n in (competed, clipped_note) if n)
        distortion = harmonic_distortion(amplitude, eq, self.contact, self.op)
        return replace(base, balance=Balance(float(amplitude), float(distortion), note))

    def competition(self, group: tuple[Mode, ...], fastest: Mode) -> tuple[Mode, str]:
        """The mode whose harmonic-balance cycle the others cannot grow on, followed from
        the one that reaches its cycle first from rest
        (``reduced.competition.surviving_cycle``), and what the row says of it (empty: the
        fastest-growing mode's own cycle holds)."""
        from reduced.competition import surviving_cycle

        dofs = mode_dofs(group, self.design)
        eigenvalues = [eigenvalue_of(self.table, self.row_of[m.index]) for m in group]
        body = body_of(self.design)
        cycle, visited = surviving_cycle(dofs, eigenvalues, self.contact, self.op, self.omega, body)
        if cycle is None:
            return (
                fastest,
                "no single mode's cycle holds against the others' growth on it: the time domain decides",
            )
        carrier = group[cycle.index]
        if carrier == fastest:
            return fastest, ""
        path = " -> ".join(group[c.index].label() for c in visited)
        return carrier, f"the cycle reached from rest is not the fastest-growing mode's ({path})"

    def integrate(self, group: tuple[Mode, ...]) -> ModeOutcome:
        """The time-domain answer of ``group`` integrated together (with the counter-body)
        from rest: the mode that carries its limit cycle, with every share."""
        from reduced import modal_content

        dofs = mode_dofs(group, self.design)
        body = body_of(self.design)
        self.ctx.budget.checkpoint(f"the squeal model of {group_label(group)}")
        with self.ctx.progress.stage(f"squeal model of {group_label(group)}"):
            sim = self.simulate(dofs, body)
        labels = dof_labels(group, self.design)
        shares: dict[str, float] | None = None
        carrier, carried, tone = group[0], None, None
        if len(dofs) > 1 or body is not None:
            content = modal_content(sim.history)
            shares = {lab: float(x) for lab, x in zip(labels, content.energy_share)}
            carrier, carried = self.carrier(group, content.energy_share)
            tone = finite_or_none(float(content.mode_frequency_hz[group.index(carrier)]))
        base = self.linear(carrier)
        f = float(sim.limit_cycle.frequency_hz)
        wave = wave_of(carrier, f if math.isfinite(f) else base.damped_frequency_hz, self.omega)
        return replace(
            base,
            wave=wave,
            simulation=sim,
            group=tuple(group),
            shares=shares,
            energy_share=carried,
            carrier_tone_hz=tone,
        )

    def simulate(self, dofs: list[ModalDOF], body: BodyModel | None) -> Simulation:
        """The time domain of ``dofs`` with the counter-body ``body`` from rest (a
        track's in its static deflection under the steady creep force: loaded long
        before the squeal starts)."""
        return simulate(
            dofs,
            self.contact,
            self.op,
            self.opts.duration,
            self.omega,
            self.ctx.budget,
            body,
            self.design.counter_body.PRELOADED,
            self.ctx.cache,
        )

    def carrier(self, group: tuple[Mode, ...], energy_share: np.ndarray) -> tuple[Mode, float]:
        """The mode that carries a limit cycle of ``group``, and its share of the energy:
        the eigenvalue whose modes hold most of the energy carries it, and it is named by
        its mode of the largest share (so that a coupled pair is named as its linear
        eigenvalue is, in every command); the share is its modes' together."""
        by_eigenvalue: dict[int, float] = {}
        for k, m in enumerate(group):
            j = eigenvalue_of(self.table, self.row_of[m.index])
            by_eigenvalue[j] = by_eigenvalue.get(j, 0.0) + float(energy_share[k])
        j = max(by_eigenvalue, key=lambda jj: by_eigenvalue[jj])
        members = {m.index for m in group}
        named = [
            self.rows[r].mode
            for r in modes_of_eigenvalue(self.table, j)
            if self.rows[r].mode.index in members
        ]
        return (named[0] if named else group[0]), by_eigenvalue[j]

    def heard(self, o: ModeOutcome) -> ModeOutcome:
        """The outcome with its sound (where it squeals with an amplitude and the request
        goes so far)."""
        if not (self.opts.reaches("sound") and o.squeals and o.amplitude_m_s is not None):
            return o
        if self.modeset.solver == "modal-model":  # no shapes: nothing radiates
            return o
        shape = self.radiating(o)
        self.ctx.budget.checkpoint(f"the sound of {o.label}")
        if o.simulation is None:
            return replace(o, sound=self.balanced_sound(o))
        with self.ctx.progress.stage(f"sound of {o.label}"):
            s = squeal_sound(
                self.design,
                self.modeset,
                shape,
                radiation_frequency_hz(o.tone_hz, shape.frequency_hz),
                o.simulation,
                o.tone_hz,
                **self.radiation(o),
            )
        return replace(o, sound=s)

    def radiation(self, o: ModeOutcome) -> dict[str, Any]:
        """The keywords of a radiation (``sound.mode_sound``): who listens, how the wave
        travels, the FE preset and band, the cache, the budget and the process's memo."""
        return dict(
            listener=self.opts.listener,
            travelling=o.wave != "standing",
            fidelity=self.ctx.fidelity.name,
            fmax_hz=self.ctx.fmax_hz,
            cache=self.ctx.cache,
            budget=self.ctx.budget,
            memo=self.ctx.memo,
        )

    def balanced_sound(self, o: ModeOutcome) -> Any:
        """The sound of a harmonic balance's limit cycle: the contact velocity's harmonics
        (``reduced.harmonic_contact_velocities``: the contact force's distortion through the
        decision's group of modes, as a time domain of those modes would show them), each
        the mode's radiation at k times its frequency (``acoustics.harmonics.radiation_frequency_hz``;
        kept for the process: ``ctx.memo``), as the time domain's are; the harmonics kept
        as ``acoustics.harmonics.kept_harmonics`` keeps a record's."""
        from acoustics.harmonics import kept_harmonics, max_harmonic_order
        from reduced import harmonic_contact_velocities

        from .sound import mode_sound
        from .squeal_sound import SquealSound

        assert o.amplitude_m_s is not None
        f_rad = radiation_frequency_hz(o.tone_hz, o.mode.frequency_hz)
        group = mode_dofs(self.decision.growing or (o.mode,), self.design)
        velocities = harmonic_contact_velocities(
            o.amplitude_m_s, o.tone_hz, group, self.contact, self.op, max_harmonic_order(o.mode.frequency_hz)
        )
        orders, share = kept_harmonics(velocities, 0.5 * float(np.sum(np.abs(velocities) ** 2)))
        sounds = tuple(
            mode_sound(
                self.design,
                self.modeset,
                o.mode,
                k * f_rad,
                float(abs(velocities[k - 1])),
                **self.radiation(o),
            )
            for k in orders
        )
        return SquealSound(sounds, orders, share, o.tone_hz)

    def radiating(self, o: ModeOutcome) -> Mode:
        """The shape that radiates a limit cycle: the mode holding the largest share of
        its vibration energy (of several integrated together), else the outcome's own."""
        if not (o.shares and o.group):
            return o.mode
        by_label = {m.label(): m for m in o.group}
        held = [(share, by_label[lab]) for lab, share in o.shares.items() if lab in by_label]
        return max(held, key=lambda sm: sm[0])[1] if held else o.mode
