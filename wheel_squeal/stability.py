"""Which mode squeals: the linear stability of every FE mode at the contact, the mode a
run simulates (the operating envelope and what stops the squeal over it:
:mod:`wheel_squeal.envelope`).

Every mode below ``fmax`` that the contact can excite (lateral motion at the contact,
or normal motion where the Hertz spring makes the normal force follow it) enters the
coupled linear model of ``reduced.stability`` with its own damping (the design's
``[squeal.damping]`` where it gives one), beside the roller's own modes when [roller]
gives them. On a turning wheel (``rotation``) each pair with n nodal diameters becomes
two travelling waves at f0 -/+ n Omega / 2 pi, Omega = V0 / R. Every growing
eigenvalue is named by its mechanism (falling friction or mode coupling) and its
participating modes.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from .design import Design
from .errors import RequestError
from .presets import MAX_MULTIMODE

if TYPE_CHECKING:
    from fem.modes import Mode, ModeSet
    from reduced import (
        ContactLaw,
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
    "contact_dofs",
    "eigenvalue_list",
    "StabilityTable",
    "stability_seconds",
    "check_stability_budget",
    "MultiMode",
    "ModeStabilityRow",
    "choose_mode",
    "excitable",
    "mode_dofs",
    "multimode",
    "named_mode",
    "NamedMode",
    "stability_table",
    "wheel_speed_rad_s",
]


def wheel_speed_rad_s(design: Design, op: OperatingPoint, rotation: bool) -> float:
    """Omega = V0 / R1 [rad/s] when the wheel's rotation is modelled, else 0."""
    return op.wheel_speed_rad_s(design.rolling_radius) if rotation else 0.0


def excitable(modeset: ModeSet, contact: ContactLaw) -> list[Mode]:
    """The modes the contact can excite, in frequency order: those that move it
    laterally, and with the Hertz spring on (``contact.normal_stiffness_n_m`` > 0) those
    that move it normally too."""
    normal = contact.normal_stiffness_n_m > 0.0
    return [
        m
        for m in modeset.modes
        if m.contact_components[0] != 0.0 or (normal and m.contact_components[1] != 0.0)
    ]


def mode_dofs(modes: Sequence[Mode], design: Design) -> list[ModalDOF]:
    """Each FE mode as a ``reduced.ModalDOF`` (:func:`wheel_squeal.api.modal_dof`)."""
    from .api import modal_dof

    return [modal_dof(m, design) for m in modes]


def contact_dofs(modes: Sequence[Mode], design: Design) -> list[ModalDOF]:
    """Every degree of freedom the contact sees: the FE modes (first, in order), then
    the roller's modes ([roller]; none for a rigid roller)."""
    from .api import counter_body_dofs

    return mode_dofs(modes, design) + counter_body_dofs(design)


def _dof_label(modes: Sequence[Mode], dofs: Sequence[ModalDOF], i: int) -> str:
    """An FE mode's label, or the roller's degree of freedom (after the modes) by its gains."""
    if i < len(modes):
        return modes[i].label()
    return "roller normal" if dofs[i].normal != 0.0 else "roller lateral"


@dataclass(frozen=True)
class ModeStabilityRow:
    """One FE mode and its linear stability (``reduced.ModeStability``); partners: the
    labels of the modes that take part in its fastest eigenvalue."""

    mode: Mode
    stability: ModeStability
    partners: tuple[str, ...] = ()

    def to_dict(self, design: Design) -> dict:
        m, s = self.mode, self.stability
        phi_t, phi_n = m.contact_components
        return {
            **m.to_dict(design.damping_ratio_of(m)),
            "lateral_component": phi_t,
            "normal_component": phi_n,
            "growth_rate_1_s": s.growth_rate_1_s,
            "damped_frequency_hz": s.damped_frequency_hz,
            "critical_damping_ratio": s.critical_damping_ratio,
            "critical_friction_slope": s.critical_friction_slope,
            "unstable": bool(s.unstable),
            "mechanism": s.mechanism,
            "partners": list(self.partners),
        }


class StabilityTable(NamedTuple):
    """Every excitable mode's linear stability: ``rows`` (a :class:`ModeStabilityRow`
    each, in frequency order) and ``result`` (the ``reduced.StabilityResult`` of the
    modes and, after them, the roller's degrees of freedom)."""

    rows: list[ModeStabilityRow]
    result: StabilityResult

    @property
    def fastest(self) -> int:
        """The index of the row that grows fastest."""
        return max(range(len(self.rows)), key=lambda i: self.rows[i].stability.growth_rate_1_s)


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

    modes = excitable(modeset, contact)
    if not modes:
        raise RequestError("no mode below fmax is seen at the contact: nothing can squeal there")
    omega = wheel_speed_rad_s(design, op, rotation)
    dofs = contact_dofs(modes, design)
    if bounds == "all":
        bounds = range(len(modes))
    result = linear_stability(dofs, contact, op, omega, bounds=bounds)
    rows = [
        ModeStabilityRow(m, s, tuple(_dof_label(modes, dofs, k) for k in s.partners))
        for m, s in zip(modes, result.modes)
    ]
    return StabilityTable(rows, result)


def eigenvalue_list(table: StabilityTable, design: Design) -> list[dict]:
    """Every eigenvalue of the table's system, fastest-growing first: its growth rate
    [1/s], damped frequency [Hz], mechanism (None: it decays) and participating modes
    with their shares of its vibration energy (those of at least
    ``reduced.stability.PARTNER_SHARE``)."""
    from reduced.stability import PARTNER_SHARE

    rows, result = table
    assert result.shares is not None  # linear_stability gives them
    modes = [r.mode for r in rows]
    dofs = contact_dofs(modes, design)
    out = []
    for j in result.ranked():
        lam, share = result.eigenvalues[j], result.shares[:, j]
        order = [int(k) for k in np.argsort(-share) if share[k] >= PARTNER_SHARE]
        out.append(
            {
                "growth_rate_1_s": float(lam.real),
                "damped_frequency_hz": float(abs(lam.imag)) / (2 * math.pi),
                "mechanism": result.mechanisms[j],
                "participants": [
                    {"mode": _dof_label(modes, dofs, k), "share": float(share[k])} for k in order
                ],
            }
        )
    return out


def stability_seconds(
    design: Design, modeset: ModeSet, contact: ContactLaw, rotation: bool = False, bounds: int = 0
) -> float:
    """The estimated time of :func:`stability_table` with ``bounds`` modes' bounds [s]."""
    from reduced.stability import stability_seconds as seconds

    dofs = contact_dofs(excitable(modeset, contact), design)
    coupled = contact.normal_stiffness_n_m > 0 and any(d.normal != 0.0 for d in dofs)
    return seconds(dofs, rotation, bounds, coupled)


def check_stability_budget(
    design: Design,
    modeset: ModeSet,
    contact: ContactLaw,
    rotation: bool,
    budget: Budget,
    bounds: int = 0,
) -> float:
    """Refuse :func:`stability_table` (with ``bounds`` modes' bounds) beyond ``budget``
    in time or memory, before it starts; returns its estimated time [s]."""
    from reduced.stability import eigen_solve_bytes

    dofs = contact_dofs(excitable(modeset, contact), design)
    what = f"the linear stability of {len(dofs)} degrees of freedom" + (
        f" with the critical damping and friction slope of {bounds}" if bounds else ""
    )
    return budget.check_work(
        what,
        stability_seconds(design, modeset, contact, rotation, bounds),
        "lower fmax" + (", or leave the bounds out" if bounds else ""),
        eigen_solve_bytes(dofs, rotation),
    )


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
    table = stability_table(design, modeset, contact, op, rotation)
    rows = table.rows
    named = named_mode(design, modeset, mode)
    if named.mode is not None and mode != "auto":
        chosen, why = named.mode, named.reason
    elif named.mode is not None:
        chosen = named.mode
        why = f"the mode {design.name} names as its squeal mode ({design.squeal.mode}): {named.reason}"
    else:
        row = rows[table.fastest]
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
        """The FE mode that carries the limit cycle (most of the vibration energy; the
        roller's degrees of freedom, after the modes, are not candidates)."""
        return self.modes[int(np.argmax(self.content.energy_share[: len(self.modes)]))]

    @property
    def agrees(self) -> bool:
        """Whether the nonlinear winner (the carrier) is the linear winner."""
        return self.carrier.index == self.linear_winner.index

    def summary(self) -> dict:
        c = self.content
        return {
            "mode_indices": [m.index for m in self.modes],
            "energy_share": {m.label(): float(s) for m, s in zip(self.modes, c.energy_share)}
            | {f"roller {i}": float(s) for i, s in enumerate(c.energy_share[len(self.modes) :])},
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
        contact_dofs(chosen, design), contact, op, duration, wheel_speed_rad_s(design, op, rotation), budget
    )
    return MultiMode(chosen, sim, modal_content(sim.history), ranked[0].mode)
