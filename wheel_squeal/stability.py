"""Which mode squeals: the linear stability of every FE mode at the contact, the mode a
run simulates (the operating envelope and what stops the squeal over it:
:mod:`wheel_squeal.envelope`).

Every mode below ``fmax`` that the contact can excite (a finite contact modal mass)
enters the coupled linear model of ``reduced.stability`` with its own damping (the
design's ``[squeal.damping]`` where it gives one). On a turning wheel (``rotation``)
each pair with n nodal diameters becomes two travelling waves at f0 -/+ n Omega / 2 pi,
Omega = V0 / R1.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

from .design import Design
from .errors import RequestError
from .presets import MAX_MULTIMODE

if TYPE_CHECKING:
    from fem.modes import Mode, ModeSet
    from reduced import (
        ContactLaw,
        ContactMode,
        ModalContent,
        ModalDOF,
        ModeStability,
        OperatingPoint,
        StabilityResult,
    )

    from .api import Simulation
    from .budget import Budget

__all__ = [
    "ModeChoice",
    "contact_modes",
    "StabilityTable",
    "stability_seconds",
    "MultiMode",
    "ModeStabilityRow",
    "choose_mode",
    "excitable",
    "mode_dofs",
    "multimode",
    "named_mode",
    "NamedMode",
    "stability_table",
    "two_directions",
    "wheel_speed_rad_s",
]


def wheel_speed_rad_s(design: Design, op: OperatingPoint, rotation: bool) -> float:
    """Omega = V0 / R1 [rad/s] when the wheel's rotation is modelled, else 0."""
    return op.wheel_speed_rad_s(design.wheel.rolling_radius) if rotation else 0.0


def excitable(modeset: ModeSet) -> list[Mode]:
    """The modes the contact can excite (finite contact modal mass), in frequency order."""
    return [m for m in modeset.modes if math.isfinite(m.modal_mass)]


def mode_dofs(modes: Sequence[Mode], design: Design) -> list[ModalDOF]:
    """Each FE mode as a ``reduced.ModalDOF`` (:func:`wheel_squeal.api.modal_dof`)."""
    from .api import modal_dof

    return [modal_dof(m, design) for m in modes]


@dataclass(frozen=True)
class ModeStabilityRow:
    """One FE mode and its linear stability (``reduced.ModeStability``)."""

    mode: Mode
    stability: ModeStability

    def to_dict(self, design: Design) -> dict:
        m, s = self.mode, self.stability
        return {
            **m.to_dict(design.damping.ratio(m.nodal_diameters, m.nodal_circles)),
            "growth_rate_1_s": s.growth_rate_1_s,
            "damped_frequency_hz": s.damped_frequency_hz,
            "critical_damping_ratio": s.critical_damping_ratio,
            "critical_friction_slope": s.critical_friction_slope,
            "unstable": bool(s.unstable),
        }


class StabilityTable(NamedTuple):
    """Every excitable mode's linear stability: ``rows`` (a :class:`ModeStabilityRow`
    each, in frequency order) and ``result`` (the ``reduced.StabilityResult``, whose
    ``winner`` is the row that grows fastest)."""

    rows: list[ModeStabilityRow]
    result: StabilityResult


def stability_table(
    design: Design,
    modeset: ModeSet,
    contact: ContactLaw,
    op: OperatingPoint,
    rotation: bool = False,
    bounds: str | Sequence[int] | None = None,
) -> StabilityTable:
    """The linear stability of every mode the contact can excite at ``op``.

    ``bounds``: the rows whose critical damping and friction slope are found ("all",
    indices, or None: growth rates only, one eigen-solve; see
    ``reduced.linear_stability``)."""
    from reduced import linear_stability

    modes = excitable(modeset)
    if not modes:
        raise RequestError("no mode below fmax is seen at the contact: nothing can squeal there")
    omega = wheel_speed_rad_s(design, op, rotation)
    result = linear_stability(mode_dofs(modes, design), contact, op, omega, bounds=bounds)
    return StabilityTable([ModeStabilityRow(m, s) for m, s in zip(modes, result.modes)], result)


def stability_seconds(design: Design, modeset: ModeSet, rotation: bool = False, bounds: int = 0) -> float:
    """The estimated time of :func:`stability_table` with ``bounds`` modes' bounds [s]."""
    from reduced.stability import stability_seconds as seconds

    return seconds(mode_dofs(excitable(modeset), design), rotation, bounds)


def contact_modes(design: Design, modeset: ModeSet) -> tuple[list[Mode], list[ContactMode]]:
    """The modes that move the contact in either direction, and each as the contact sees
    it (``reduced.ContactMode``: frequency, the design's damping ratio, (phi_t, phi_n))."""
    from reduced import ContactMode

    modes = [m for m in modeset.modes if any(abs(x) > 0 for x in m.contact_components)]
    ratios = [design.damping.ratio(m.nodal_diameters, m.nodal_circles) for m in modes]
    return modes, [ContactMode(m.frequency_hz, z, *m.contact_components) for m, z in zip(modes, ratios)]


def two_directions(design: Design, modeset: ModeSet, contact: ContactLaw, op: OperatingPoint) -> dict:
    """The linear stability with the contact's normal direction (``reduced.coupling``):
    every mode seen at the contact in either direction, with its damping ratio and
    (phi_t, phi_n) at the tread apex, on the Hertz spring of the design's contact. The
    JSON-ready summary: k_H, and every growing eigenvalue with its tone, the nearest
    mode and the mechanism that makes it grow."""
    from reduced import coupled_stability

    from .api import hertz_of

    modes, cms = contact_modes(design, modeset)
    k_h = hertz_of(design).normal_stiffness_n_m
    cs = coupled_stability(cms, contact, op, k_h)
    growing = []
    for lam, mech, f in zip(cs.eigenvalues, cs.mechanisms, cs.frequency_hz):
        if mech is None:
            continue
        near = min(modes, key=lambda m: abs(m.frequency_hz - f))
        growing.append({"mode": near.label(), "frequency_hz": float(f), "growth_rate_1_s": float(lam.real),
                        "mechanism": mech})  # fmt: skip
    return {
        "normal_stiffness_n_m": k_h,
        "friction_law": contact.friction_law,
        "modes_with_normal_motion": sum(_moves_normally(m) for m in modes),
        "growing": growing,
    }


#: a mode moves the contact normally when phi_n is above this fraction of its larger
#: component (below it: a symmetric wheel's meshing noise, about 2e-6)
NORMAL_MOTION_RTOL = 1e-3


def _moves_normally(mode: Mode) -> bool:
    t, n = mode.contact_components
    return abs(n) > NORMAL_MOTION_RTOL * max(abs(t), abs(n))


def margin_of(
    design: Design,
    rows: Sequence[ModeStabilityRow],
    contact: ContactLaw,
    op: OperatingPoint,
    rotation: bool = False,
) -> dict:
    """How far from squeal a point where no mode grows is: the least stable mode, its
    growth rate [1/s], and the damping ratio below which (or the friction slope
    dmu/dzeta below which) it would grow, with the values now; ``words`` says it."""
    from reduced import linear_stability

    i = max(range(len(rows)), key=lambda k: rows[k].stability.growth_rate_1_s)
    m = rows[i].mode
    omega = wheel_speed_rad_s(design, op, rotation)
    dofs = mode_dofs([r.mode for r in rows], design)
    result = linear_stability(dofs, contact, op, omega, bounds=[i])
    s = result.modes[i]
    zeta_now = design.damping.ratio(m.nodal_diameters, m.nodal_circles)
    slope_now = result.friction_damping_ns_m * op.rolling_speed_m_s / contact.normal_load_n
    damping = (
        f"a damping ratio below {s.critical_damping_ratio:.3g} (it has {zeta_now:.3g})"
        if s.critical_damping_ratio > 0
        else "no damping at all"
    )
    words = (
        f"the least stable, {m.label()} at {s.damped_frequency_hz:.1f} Hz, decays at "
        f"{s.growth_rate_1_s:.3g} 1/s; "
        f"it would grow with {damping} or a creep curve falling more steeply than dmu/dzeta = "
        f"{s.critical_friction_slope:.3g} (now {slope_now:.3g})"
    )
    return {
        "mode": m.label(),
        "mode_index": m.index,
        "growth_rate_1_s": s.growth_rate_1_s,
        "damping_ratio": zeta_now,
        "grows_below_damping_ratio": s.critical_damping_ratio,
        "friction_slope": slope_now,
        "grows_below_friction_slope": s.critical_friction_slope,
        "words": words,
    }


class NamedMode(NamedTuple):
    """The mode the user (``--mode``) or the design (``[squeal] mode``) names: ``mode``
    (None: neither names one), ``source`` (who names it, in words) and ``reason`` (how it
    was found among the modes)."""

    mode: Mode | None
    source: str
    reason: str


def named_mode(design: Design, modeset: ModeSet, mode: str = "auto") -> NamedMode:
    """The named mode: ``mode`` unless "auto", else the design's ``[squeal] mode``. A
    named mode with a node at the contact is refused in one line."""
    from .api import modal_dof, pick_mode

    if mode != "auto":
        found, source = pick_mode(modeset, mode), f"--mode {mode} asks for"
    elif design.squeal.mode:
        found, source = pick_mode(modeset, design.squeal.mode), f"the design {design.name} names"
    else:
        return NamedMode(None, "", "")
    modal_dof(found.mode, design)  # a node at the contact: its one-line refusal
    return NamedMode(found.mode, source, found.reason)


class ModeChoice(NamedTuple):
    """The mode a run simulates, the sentence that says why, and the stability rows."""

    mode: Mode
    reason: str
    rows: list[ModeStabilityRow]


def choose_mode(
    design: Design,
    modeset: ModeSet,
    mode: str,
    contact: ContactLaw,
    op: OperatingPoint,
    rotation: bool = False,
) -> ModeChoice:
    """The mode a run simulates, why, and the stability table.

    ``mode``: "auto" takes the mode the design names (``[squeal] mode``), else the one
    with the largest linear growth rate at ``op``; anything else selects as
    :func:`wheel_squeal.api.pick_mode` does.
    """
    rows, result = stability_table(design, modeset, contact, op, rotation)
    named = named_mode(design, modeset, mode)
    if named.mode is not None and mode != "auto":
        chosen, why = named.mode, named.reason
    elif named.mode is not None:
        chosen = named.mode
        why = f"the mode {design.name} names as its squeal mode ({design.squeal.mode}): {named.reason}"
    else:
        row = rows[result.winner]
        chosen = row.mode
        why = (
            f"largest linear growth rate at this operating point, {row.stability.growth_rate_1_s:.3g} 1/s"
            + (" (wheel rotation on)" if rotation else "")
        )
    return ModeChoice(chosen, why, rows)


@dataclass(frozen=True)
class MultiMode:
    """Several modes integrated together from rest (``reduced.simulate`` with N modes).

    modes : the FE modes integrated (the most unstable first); simulation : the
    ``api.Simulation``; content : ``reduced.ModalContent`` (energy share per mode, the
    carrier, the contact velocity's peak frequency); linear_winner : the FE mode with the
    largest linear growth rate."""

    modes: list[Mode]
    simulation: Simulation
    content: ModalContent
    linear_winner: Mode

    @property
    def carrier(self) -> Mode:
        """The FE mode that carries the limit cycle (most of the vibration energy)."""
        return self.modes[self.content.carrier]

    @property
    def agrees(self) -> bool:
        """Whether the nonlinear winner (the carrier) is the linear winner."""
        return self.carrier.index == self.linear_winner.index

    def summary(self) -> dict:
        c = self.content
        return {
            "mode_indices": [m.index for m in self.modes],
            "energy_share": {m.label(): float(s) for m, s in zip(self.modes, c.energy_share)},
            "carrier_mode": self.carrier.index,
            "carrier": self.carrier.label(),
            "peak_frequency_hz": c.peak_frequency_hz,
            "window_s": list(c.window_s),
            "linear_winner_mode": self.linear_winner.index,
            "agrees_with_linear_winner": self.agrees,
            **self.simulation.summary(),
        }


def multimode(
    design: Design,
    rows: Sequence[ModeStabilityRow],
    contact: ContactLaw,
    op: OperatingPoint,
    rotation: bool = False,
    count: int = MAX_MULTIMODE,
    duration: float | None = None,
    budget: Budget | None = None,
) -> MultiMode:
    """The ``count`` most unstable modes of ``rows`` (:func:`stability_table`) integrated
    together from rest; with none unstable, the least stable one alone."""
    from reduced import modal_content

    from .api import simulate

    if count < 1:
        raise RequestError(f"--multimode takes 1 or more modes, got {count}")
    ranked = sorted(rows, key=lambda r: -r.stability.growth_rate_1_s)
    chosen = [r.mode for r in ranked if r.stability.unstable][:count] or [ranked[0].mode]
    sim = simulate(
        mode_dofs(chosen, design), contact, op, duration, wheel_speed_rad_s(design, op, rotation), budget
    )
    return MultiMode(chosen, sim, modal_content(sim.history), ranked[0].mode)
