"""Which mode squeals: the linear stability of every FE mode at the contact, the mode a
run simulates, the operating envelope and what would stop the squeal.

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

import numpy as np

from geometry import WheelDesign

from .errors import RequestError
from .presets import MAX_MULTIMODE, rpm_to_speed

__all__ = [
    "Envelope",
    "Mitigation",
    "MultiMode",
    "ModeStabilityRow",
    "choose_mode",
    "envelope",
    "excitable",
    "mitigation",
    "mode_dofs",
    "multimode",
    "stability_table",
    "wheel_speed_rad_s",
]


def wheel_speed_rad_s(design: WheelDesign, op, rotation: bool) -> float:
    """Omega = V0 / R1 [rad/s] when the wheel's rotation is modelled, else 0."""
    return op.rolling_speed_m_s / design.rolling_radius if rotation else 0.0


def excitable(modeset) -> list:
    """The modes the contact can excite (finite contact modal mass), in frequency order."""
    return [m for m in modeset.modes if math.isfinite(m.modal_mass)]


def mode_dofs(modes: Sequence, design: WheelDesign) -> list:
    """Each FE mode as a ``reduced.ModalDOF`` with its damping ratio and nodal diameters."""
    from reduced import ModalDOF

    return [
        ModalDOF.from_damping_ratio(
            m.modal_mass,
            m.modal_stiffness,
            design.damping_ratio(m.nodal_diameters, m.nodal_circles),
            m.nodal_diameters,
        )
        for m in modes
    ]


@dataclass(frozen=True)
class ModeStabilityRow:
    """One FE mode and its linear stability (``reduced.ModeStability``)."""

    mode: object
    stability: object

    def to_dict(self, design: WheelDesign) -> dict:
        m, s = self.mode, self.stability
        return {
            **m.to_dict(design.damping_ratio(m.nodal_diameters, m.nodal_circles)),
            "growth_rate_1_s": s.growth_rate_1_s,
            "damped_frequency_hz": s.damped_frequency_hz,
            "critical_damping_ratio": s.critical_damping_ratio,
            "critical_friction_slope": s.critical_friction_slope,
            "unstable": bool(s.unstable),
        }


def stability_table(design: WheelDesign, modeset, contact, op, rotation: bool = False):
    """(rows, result): a :class:`ModeStabilityRow` per excitable mode, fastest first
    is ``result.winner``; ``result`` the ``reduced.StabilityResult``."""
    from reduced import linear_stability

    modes = excitable(modeset)
    if not modes:
        raise RequestError("no mode below fmax is seen at the contact: nothing can squeal there")
    result = linear_stability(mode_dofs(modes, design), contact, op, wheel_speed_rad_s(design, op, rotation))
    return [ModeStabilityRow(m, s) for m, s in zip(modes, result.modes)], result


def choose_mode(design: WheelDesign, modeset, mode: str, contact, op, rotation: bool = False):
    """The mode a run simulates, why, and the stability table.

    ``mode``: "auto" takes the mode the design names (``[squeal] mode``), else the one
    with the largest linear growth rate at ``op``; anything else selects as
    :func:`wheel_squeal.api.pick_mode` does.
    """
    from .api import pick_mode

    rows, result = stability_table(design, modeset, contact, op, rotation)
    if mode != "auto":
        chosen, why = pick_mode(modeset, mode)
    elif design.squeal_mode:
        chosen, why = pick_mode(modeset, design.squeal_mode)
        why = f"the mode {design.name} names as its squeal mode ({design.squeal_mode}): {why}"
    else:
        row = rows[result.winner]
        chosen = row.mode
        why = (
            f"largest linear growth rate at this operating point, {row.stability.growth_rate_1_s:.3g} 1/s"
            + (" (wheel rotation on)" if rotation else "")
        )
    return chosen, why, rows


@dataclass(frozen=True)
class Envelope:
    """The linear stability over a grid of crabbing velocities x wheel speeds.

    crab_velocities_m_s (n_vc,), rpm (n_speeds,); growth_rate_1_s (n_vc, n_speeds): the
    largest growth rate; winner (n_vc, n_speeds): index into ``modes`` of the
    fastest-growing mode; modes: the excitable FE modes.
    """

    crab_velocities_m_s: np.ndarray
    rpm: np.ndarray
    growth_rate_1_s: np.ndarray
    winner: np.ndarray
    modes: list


def envelope(
    design: WheelDesign, modeset, contact, crab_velocities, rpms, rotation: bool = False
) -> Envelope:
    """Growth rate and winning mode over crabbing velocities [m/s] x wheel speeds [rpm]."""
    from reduced import OperatingPoint
    from reduced.stability import friction_damping_ns_m, growth_rates

    modes = excitable(modeset)
    dofs = mode_dofs(modes, design)
    damping = [d.damping_ns_m for d in dofs]
    vcs, rpms = np.asarray(crab_velocities, float), np.asarray(rpms, float)
    growth = np.empty((len(vcs), len(rpms)))
    winner = np.empty((len(vcs), len(rpms)), dtype=np.int64)
    for j, rpm in enumerate(rpms):
        v0 = rpm_to_speed(rpm, design.rolling_radius)
        omega = v0 / design.rolling_radius if rotation else 0.0
        for i, vc in enumerate(vcs):
            g = friction_damping_ns_m(contact, OperatingPoint(v0, vc))
            sigma = growth_rates(dofs, damping, g, omega)
            winner[i, j] = int(np.argmax(sigma))
            growth[i, j] = sigma[winner[i, j]]
    return Envelope(vcs, rpms, growth, winner, modes)


#: The damping bounds are raised by this fraction above the exact critical values, so
#: that the coupling between modes (each bound moves the others' by about 1e-5) cannot
#: leave a point marginally growing.
MITIGATION_MARGIN = 1e-3


@dataclass(frozen=True)
class Mitigation:
    """What would keep every mode stable over an envelope.

    damping_ratio : per excitable mode, the smallest modal damping ratio (to
        ``MITIGATION_MARGIN``) that keeps it stable at every point, the others at theirs:
        what a wheel damper must give;
    friction_slope : the dmu/dzeta (at the quasi-static creepage) the creep curve must
        not fall below anywhere, with the design's damping: what a friction modifier
        must achieve; worst_point : (crab velocity m/s, rpm) where each bound binds.
    """

    modes: list
    damping_ratio: np.ndarray
    damping_worst_point: list[tuple[float, float]]
    friction_slope: float
    friction_worst_rpm: float

    def to_dict(self, design: WheelDesign) -> dict:
        """JSON-ready: per mode its present and required damping ratio (and where it
        binds), and the friction slope required."""
        return {
            "damping": [
                {
                    "mode": m.index,
                    "label": m.label(),
                    "frequency_hz": m.frequency_hz,
                    "damping_ratio": design.damping_ratio(m.nodal_diameters, m.nodal_circles),
                    "required_damping_ratio": float(z),
                    "at_crab_velocity_m_s": float(p[0]),
                    "at_rpm": float(p[1]),
                }
                for m, z, p in zip(self.modes, self.damping_ratio, self.damping_worst_point)
            ],
            "required_friction_slope": self.friction_slope,
            "friction_slope_at_rpm": self.friction_worst_rpm,
        }


def mitigation(
    design: WheelDesign, modeset, contact, crab_velocities, rpms, rotation: bool = False
) -> Mitigation:
    """The damping per mode and the friction slope that stop squeal over the envelope.

    Each bound is found where it binds (the point of the most negative friction damping
    for the damping, the lowest wheel speed for the slope) by root finding on the coupled
    eigenvalues, then checked at every point of the envelope with all modes at their
    new damping (and raised where a point still grows)."""
    from reduced import OperatingPoint, linear_stability
    from reduced.stability import friction_damping_ns_m, growth_rates

    modes = excitable(modeset)
    dofs = mode_dofs(modes, design)
    vcs, rpms = np.asarray(crab_velocities, float), np.asarray(rpms, float)
    points = [(vc, rpm) for vc in vcs for rpm in rpms]

    def op_at(vc, rpm):
        return OperatingPoint(rpm_to_speed(rpm, design.rolling_radius), vc)

    def omega(rpm):
        return rpm_to_speed(rpm, design.rolling_radius) / design.rolling_radius if rotation else 0.0

    g_at = {p: friction_damping_ns_m(contact, op_at(*p)) for p in points}
    worst = min(points, key=lambda p: g_at[p])
    zeta = np.array(
        [
            s.critical_damping_ratio
            for s in linear_stability(dofs, contact, op_at(*worst), omega(worst[1])).modes
        ]
    )
    where = [worst] * len(modes)
    for _ in range(4 * len(modes) + 4):  # raise a mode's bound where a point still grows
        damped = [d.with_damping_ratio(z * (1 + MITIGATION_MARGIN)) for d, z in zip(dofs, zeta)]
        sig = {
            p: growth_rates(damped, [d.damping_ns_m for d in damped], g_at[p], omega(p[1])) for p in points
        }
        p, i = max(((p, int(np.argmax(s))) for p, s in sig.items()), key=lambda pi: sig[pi[0]][pi[1]])
        if sig[p][i] <= 0.0:
            break
        zeta[i] = linear_stability(damped, contact, op_at(*p), omega(p[1])).modes[i].critical_damping_ratio
        where[i] = p
    else:
        raise RuntimeError("the damping bounds did not settle over the envelope")
    zeta = zeta * (1 + MITIGATION_MARGIN)
    slopes = {
        rpm: max(
            s.critical_friction_slope
            for s in linear_stability(dofs, contact, op_at(float(vcs[-1]), rpm), omega(rpm)).modes
        )
        for rpm in rpms
    }
    rpm_bind = max(slopes, key=slopes.get)
    return Mitigation(modes, zeta, where, float(slopes[rpm_bind]), float(rpm_bind))


@dataclass(frozen=True)
class MultiMode:
    """Several modes integrated together from rest (``reduced.simulate`` with N modes).

    modes : the FE modes integrated (the most unstable first); simulation : the
    ``api.Simulation``; content : ``reduced.ModalContent`` (energy share per mode, the
    carrier, the contact velocity's peak frequency); linear_winner : the FE mode with the
    largest linear growth rate."""

    modes: list
    simulation: object
    content: object
    linear_winner: object

    @property
    def carrier(self):
        """The FE mode that carries the limit cycle (most of the vibration energy)."""
        return self.modes[self.content.carrier]

    @property
    def agrees(self) -> bool:
        """Whether the nonlinear winner (the carrier) is the linear winner."""
        return self.carrier.index == self.linear_winner.index

    def summary(self) -> dict:
        c = self.content
        return {
            "modes": [m.index for m in self.modes],
            "energy_share": {str(m.index): float(s) for m, s in zip(self.modes, c.energy_share)},
            "carrier_mode": self.carrier.index,
            "carrier": self.carrier.label(),
            "peak_frequency_hz": c.peak_frequency_hz,
            "window_s": list(c.window_s),
            "linear_winner_mode": self.linear_winner.index,
            "agrees_with_linear_winner": self.agrees,
            **self.simulation.summary(),
        }


def multimode(
    design: WheelDesign,
    rows: Sequence[ModeStabilityRow],
    contact,
    op,
    rotation: bool = False,
    count: int = MAX_MULTIMODE,
    duration: float | None = None,
) -> MultiMode:
    """The ``count`` most unstable modes of ``rows`` (:func:`stability_table`) integrated
    together from rest; with none unstable, the least stable one alone."""
    from reduced import modal_content

    from .api import simulate

    if count < 1:
        raise RequestError(f"--multimode takes 1 or more modes, got {count}")
    ranked = sorted(rows, key=lambda r: -r.stability.growth_rate_1_s)
    chosen = [r.mode for r in ranked if r.stability.unstable][:count] or [ranked[0].mode]
    sim = simulate(mode_dofs(chosen, design), contact, op, duration, wheel_speed_rad_s(design, op, rotation))
    return MultiMode(chosen, sim, modal_content(sim.history), ranked[0].mode)
