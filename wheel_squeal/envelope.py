"""The operating envelope: the linear stability of every FE mode over a grid of
crabbing velocities x wheel speeds, and what would keep every mode stable over it (the
damping per mode and the friction slope: ``reduced.stability_map``,
``reduced.mitigation``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .design import Design
from .mode_stability import body_of, excitable, mode_dofs
from .outputs import bound_or_none, needed_or_none
from .presets import rpm_to_speed

if TYPE_CHECKING:
    from fem.modes import Mode, ModeSet
    from reduced import ContactLaw, Mitigation as MitigationResult, ModalDOF

__all__ = ["Envelope", "Mitigation", "envelope", "envelope_seconds", "mitigation", "mitigation_summary"]


def _map_inputs(
    design: Design, modeset: ModeSet, contact: ContactLaw, rpms: Sequence[float] | np.ndarray, rotation: bool
) -> tuple[list[Mode], list[ModalDOF], np.ndarray, float | None]:
    """What ``reduced``'s maps take: the excitable modes, their degrees of freedom at the
    contact, the rolling speeds [m/s] of ``rpms``, and the rolling radius when rotation
    is modelled (the counter-body: :func:`~wheel_squeal.mode_stability.body_of`)."""
    modes = excitable(modeset, contact)
    speeds = np.array([rpm_to_speed(float(r), design.rolling_radius) for r in rpms])
    return modes, mode_dofs(modes, design), speeds, design.rolling_radius if rotation else None


@dataclass(frozen=True)
class Envelope:
    """The linear stability over a grid of crabbing velocities x wheel speeds.

    crabbing_velocities_m_s (n_vc,), rpm (n_speeds,); growth_rate_1_s (n_vc, n_speeds): the
    largest growth rate; winner (n_vc, n_speeds): index into ``modes`` of the
    fastest-growing mode; damped_frequency_hz: its frequency at the contact; modes: the
    excitable FE modes.
    """

    crabbing_velocities_m_s: np.ndarray
    rpm: np.ndarray
    growth_rate_1_s: np.ndarray
    winner: np.ndarray
    damped_frequency_hz: np.ndarray
    modes: list[Mode]


def envelope(
    design: Design,
    modeset: ModeSet,
    contact: ContactLaw,
    crab_velocities: Sequence[float] | np.ndarray,
    rpms: Sequence[float] | np.ndarray,
    rotation: bool = False,
) -> Envelope:
    """Growth rate and winning mode over crabbing velocities x wheel speeds
    (``reduced.stability_map``).

    Parameters
    ----------
    design : Design
    modeset : fem.ModeSet
    contact : reduced.ContactLaw
    crab_velocities : array_like
        Crabbing velocities [m/s].
    rpms : array_like
        Wheel speeds [rev/min].
    rotation : bool
        Model the wheel's rotation.

    Returns
    -------
    Envelope
        Growth rate [1/s], winning mode and its frequency [Hz] per point.

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> d = ws.load_design()
    >>> env = ws.envelope(d, ws.explicit_modes(3.1, 1.6e8, 42), ws.contact_law(d), [0.0, 0.39], [800])
    >>> (env.growth_rate_1_s[:, 0] > 0).tolist()
    [False, True]
    """
    from reduced import stability_map

    modes, dofs, speeds, radius = _map_inputs(design, modeset, contact, rpms, rotation)
    m = stability_map(
        dofs, contact, crab_velocities, speeds, radius, candidates=len(modes), body=body_of(design)
    )
    rpms = np.asarray(rpms, float)
    return Envelope(
        m.crabbing_velocities_m_s, rpms, m.growth_rate_1_s, m.winner, m.damped_frequency_hz, modes
    )


@dataclass(frozen=True)
class Mitigation:
    """What would keep every mode stable over an envelope (``reduced.Mitigation`` with
    the FE modes and wheel speeds): see :meth:`to_dict`."""

    modes: list[Mode]
    result: MitigationResult
    rpm: np.ndarray

    def to_dict(self, design: Design) -> dict:
        """JSON-ready: per mode its present and required damping ratio (and where it
        binds), the friction slope required, and whether the bounds settled."""
        r = self.result
        to_rpm = rpm_to_speed(1.0, design.rolling_radius)
        return {
            "damping": [
                {
                    "mode": m.index,
                    "label": m.label(),
                    "frequency_hz": m.frequency_hz,
                    "damping_ratio": design.damping_ratio_of(m),
                    "required_damping_ratio": needed_or_none(z),
                    "at_crabbing_velocity_m_s": float(p[0]),
                    "at_rpm": float(p[1]) / to_rpm,
                }
                for m, z, p in zip(self.modes, r.damping_ratio, r.damping_worst_point)
            ],
            "required_friction_slope": bound_or_none(r.friction_slope),
            "friction_slope_at_rpm": r.friction_worst_speed_m_s / to_rpm,
            "settled": r.settled,
            "reason": r.reason,
        }


def mitigation(
    design: Design,
    modeset: ModeSet,
    contact: ContactLaw,
    crab_velocities: Sequence[float] | np.ndarray,
    rpms: Sequence[float] | np.ndarray,
    rotation: bool = False,
) -> Mitigation:
    """The damping per mode and the friction slope that stop squeal over the envelope
    (``reduced.mitigation``).

    Parameters
    ----------
    design, modeset, contact, crab_velocities, rpms, rotation
        The envelope's, as :func:`envelope` takes them.

    Returns
    -------
    Mitigation
        Per mode the damping ratio it needs, and the creep-curve slope dmu/dzeta the
        friction must not fall below.

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> d = ws.load_design()
    >>> mit = ws.mitigation(d, ws.explicit_modes(3.1, 1.6e8, 42), ws.contact_law(d), [0.1, 0.39], [800])
    >>> bool(mit.result.settled), float(mit.result.damping_ratio[0]) > 0.00094
    (True, True)
    """
    from reduced import mitigation as find

    modes, dofs, speeds, radius = _map_inputs(design, modeset, contact, rpms, rotation)
    result = find(dofs, contact, crab_velocities, speeds, radius, body=body_of(design))
    return Mitigation(modes, result, np.asarray(rpms, float))


def mitigation_summary(
    design: Design,
    modeset: ModeSet,
    contact: ContactLaw,
    crab_velocities: Sequence[float] | np.ndarray,
    rpms: Sequence[float] | np.ndarray,
) -> dict:
    """summary.json's ``mitigation``: what stops squeal over the envelope with the
    wheel's rotation left out and taken in (:meth:`Mitigation.to_dict` each)."""
    off = mitigation(design, modeset, contact, crab_velocities, rpms, rotation=False)
    on = mitigation(design, modeset, contact, crab_velocities, rpms, rotation=True)
    return {
        "crabbing_velocity_m_s": [float(crab_velocities[0]), float(crab_velocities[-1])],
        "rpm": list(rpms),
        "rotation_off": off.to_dict(design),
        "rotation_on": on.to_dict(design),
    }


def envelope_seconds(
    design: Design, modeset: ModeSet, contact: ContactLaw, n_crab_velocities: int, n_speeds: int
) -> float:
    """The estimated time of the map and both mitigations (rotation off and on) [s]."""
    from reduced.stability import eigen_solve_seconds, mitigation_seconds

    dofs = mode_dofs(excitable(modeset, contact), design)
    points = n_crab_velocities * n_speeds
    body = design.counter_body.states()
    return sum(
        points * eigen_solve_seconds(dofs, rot, body)
        + mitigation_seconds(dofs, n_crab_velocities, n_speeds, rot, body)
        for rot in (False, True)
    )
