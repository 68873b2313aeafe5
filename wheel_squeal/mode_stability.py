"""The linear stability of every mode the contact sees, and every degree of freedom
named (the modes, then the counter-body's); which of them the verdict integrates is
:mod:`wheel_squeal.decision`'s (the operating envelope and what stops the squeal over it:
:mod:`wheel_squeal.envelope`).

Every mode below ``fmax`` that the contact can excite (lateral motion at the contact,
or normal motion where the Hertz spring makes the normal force follow it) enters the
coupled linear model of ``reduced.stability`` with its own damping (the design's
``[squeal.damping]`` where it gives one), beside the counter-body's degrees of freedom
([counter_body]). On a turning wheel (``rotation``) each pair with n nodal diameters becomes
two travelling waves at f0 -/+ n Omega / 2 pi, Omega = V0 / R. Every growing
eigenvalue is named by its mechanism (falling friction or mode coupling) and its
participating modes.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from .design import Design
from .outputs import bound_or_none
from .runtime.request_errors import RequestError

if TYPE_CHECKING:
    from fem.modes import Mode, ModeSet
    from reduced import BodyModel, ContactLaw, ModalDOF, ModeStability, OperatingPoint, StabilityResult


__all__ = [
    "ModeStabilityRow",
    "NamedMode",
    "StabilityTable",
    "body_of",
    "dof_labels",
    "eigenvalue_list",
    "excitable",
    "mode_dofs",
    "named_mode",
    "stability_seconds",
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


def body_of(design: Design) -> BodyModel | None:
    """The counter-body in series with the contact (``reduced.BodyModel``), None where it
    is rigid and fixed."""
    body = design.counter_body.model()
    return body if body.terms else None


def dof_labels(modes: Sequence[Mode], design: Design) -> list[str]:
    """The label of every participant of an eigenvalue or a limit cycle: the modes', then
    the counter-body's where it moves (its name, "the rail")."""
    body = body_of(design)
    return [m.label() for m in modes] + ([body.name] if body is not None else [])


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
            "critical_damping_ratio": bound_or_none(s.critical_damping_ratio),
            "critical_friction_slope": bound_or_none(s.critical_friction_slope),
            "unstable": bool(s.unstable),
            "mechanism": s.mechanism,
            "partners": list(self.partners),
        }


@dataclass(frozen=True)
class StabilityTable:
    """Every excitable mode's linear stability at one operating point.

    Attributes
    ----------
    rows : list of ModeStabilityRow
        One per mode the contact sees, in frequency order.
    result : reduced.StabilityResult
        The coupled system's: the modes, then the counter-body's degrees of freedom
        (eigenvalues [1/s], each mode's growth rate [1/s] and mechanism).
    labels : tuple of str
        Every degree of freedom's label, in the order of ``result``.
    wheel_speed_rad_s : float
        Omega, the wheel's rotation modelled (0: off) [rad/s].

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> d = ws.load_design()
    >>> modes = ws.explicit_modes(3.1, 1.6e8, 42)
    >>> t = ws.stability_table(d, modes, ws.contact_law(d), ws.operating_point(d))
    >>> t.labels, round(t.rows[0].stability.growth_rate_1_s, 2)
    (('the given mode (1143.4 Hz)',), 8.63)
    """

    rows: list[ModeStabilityRow]
    result: StabilityResult
    labels: tuple[str, ...]
    wheel_speed_rad_s: float = 0.0

    def __iter__(self) -> Iterator[Any]:  # (rows, result) = table
        return iter((self.rows, self.result))

    @property
    def fastest(self) -> int:
        """The index of the leading row (``reduced.stability.leading_mode`` among the
        wheel's modes: the one holding most of the fastest-growing eigenvalue a mode of
        the wheel takes part in); where nothing grows, the row that decays slowest. The
        decision's pick (``decision.fastest_mode``)."""
        from reduced.stability import leading_mode

        growth = [r.stability.growth_rate_1_s for r in self.rows]
        return leading_mode(self.result.eigenvalues, self.result.shares, growth, len(self.rows))

    @property
    def grows(self) -> bool:
        """Whether an eigenvalue a mode of the wheel takes part in grows."""
        return any(r.stability.unstable for r in self.rows)

    @property
    def growing(self) -> list[ModeStabilityRow]:
        """The rows whose mode grows."""
        return [r for r in self.rows if r.stability.unstable]


def stability_table(
    design: Design,
    modeset: ModeSet,
    contact: ContactLaw,
    op: OperatingPoint,
    rotation: bool = False,
    bounds: str | Sequence[int] | None = None,
    dofs: Sequence[ModalDOF] | None = None,
    stable_rows: bool = True,
) -> StabilityTable:
    """The linear stability of every mode the contact can excite at ``op``.

    Parameters
    ----------
    design : Design
    modeset : fem.ModeSet
    contact : reduced.ContactLaw
    op : reduced.OperatingPoint
    rotation : bool
        Model the wheel's rotation (travelling waves).
    bounds : "all", sequence of int or None
        The rows whose critical damping ratio and friction slope are found (None: growth
        rates only, one eigen-solve; see ``reduced.linear_stability``).
    dofs : sequence of reduced.ModalDOF, optional
        The excitable modes' :func:`mode_dofs`, when the caller has them.
    stable_rows : bool
        False: where no eigenvalue grows, no rows, the eigenvalues alone saying so
        (``ChainOptions.stable_rows``; ``reduced.linear_stability``'s ``stable_modes``).

    Returns
    -------
    StabilityTable

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> d = ws.load_design()
    >>> modes, contact, op = ws.explicit_modes(3.1, 1.6e8, 42), ws.contact_law(d), ws.operating_point(d)
    >>> t = ws.stability_table(d, modes, contact, op, bounds="all")
    >>> round(t.rows[0].stability.critical_damping_ratio, 5)
    0.00214
    """
    from reduced import linear_stability

    modes = excitable(modeset, contact)
    if not modes:
        raise RequestError("no mode below fmax is seen at the contact: nothing can squeal there")
    omega = wheel_speed_rad_s(design, op, rotation)
    dofs = mode_dofs(modes, design) if dofs is None else dofs
    if bounds == "all":
        bounds = range(len(modes))
    result = linear_stability(
        dofs, contact, op, omega, bounds=bounds, body=body_of(design), stable_modes=stable_rows
    )
    labels = tuple(dof_labels(modes, design))
    rows = [ModeStabilityRow(m, s, tuple(labels[k] for k in s.partners)) for m, s in zip(modes, result.modes)]
    return StabilityTable(rows, result, labels, omega)


def eigenvalue_list(table: StabilityTable) -> list[dict]:
    """Every eigenvalue of the table's system, fastest-growing first: its growth rate
    [1/s], damped frequency [Hz], mechanism (None: it decays) and participating modes
    with their shares of its vibration energy (those of at least
    ``reduced.stability.PARTNER_SHARE``)."""
    from reduced.stability import PARTNER_SHARE

    result = table.result
    assert result.shares is not None  # linear_stability gives them
    out = []
    for j in result.ranked():
        lam, share = result.eigenvalues[j], result.shares[:, j]
        order = [int(k) for k in np.argsort(-share) if share[k] >= PARTNER_SHARE]
        out.append(
            {
                "growth_rate_1_s": float(lam.real),
                "damped_frequency_hz": float(abs(lam.imag)) / (2 * math.pi),
                "mechanism": result.mechanisms[j],
                "participants": [{"mode": table.labels[k], "share": float(share[k])} for k in order],
            }
        )
    return out


def stability_seconds(
    design: Design,
    modeset: ModeSet,
    contact: ContactLaw,
    rotation: bool = False,
    bounds: int = 0,
    dofs: Sequence[ModalDOF] | None = None,
) -> float:
    """The estimated time of :func:`stability_table` with ``bounds`` modes' bounds [s]
    (``dofs``: the excitable modes' :func:`mode_dofs`, when the caller has them)."""
    from reduced.stability import stability_seconds as seconds

    if dofs is None:
        dofs = mode_dofs(excitable(modeset, contact), design)
    coupled = contact.normal_stiffness_n_m > 0 and any(d.normal != 0.0 for d in dofs)
    return seconds(dofs, rotation, bounds, coupled, design.counter_body.states())


class NamedMode(NamedTuple):
    """The mode the user (``--mode``) or the design (``[squeal] mode``) names: ``mode``
    (None: neither names one), ``source`` (who names it, in words) and ``reason`` (how it
    was found among the modes)."""

    mode: Mode | None
    source: str
    reason: str


def named_mode(design: Design, modeset: ModeSet, mode: str = "auto") -> NamedMode:
    """The named mode: ``mode`` unless "auto" or "model", else (with "auto") the design's
    ``[squeal] mode`` (which names one of its FE modes: not among a modal model's);
    "model" names none (the model's own outcome is the verdict). A named mode with a
    node at the contact is refused in one line."""
    from fem.modal_model import MODAL_MODEL_SOLVER

    from .api import modal_dof, pick_mode

    if mode == "model":
        return NamedMode(None, "", "")
    if mode != "auto":
        found, source = pick_mode(modeset, mode), f"the request ({mode}) names"
    elif design.squeal.mode and modeset.solver != MODAL_MODEL_SOLVER:  # it names an FE mode
        found, source = pick_mode(modeset, design.squeal.mode), f"the design {design.name} names"
    else:
        return NamedMode(None, "", "")
    modal_dof(found.mode, design)  # a node at the contact: its one-line refusal
    return NamedMode(found.mode, source, found.reason)
