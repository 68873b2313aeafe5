"""What would stop a squeal, or start one: the critical damping ratio and friction
slope of the verdict's mode (:func:`remedy_of`), or of the least stable mode where none
grows (:func:`margin_of`), found by root finding on the coupled eigenvalues
(``reduced.linear_stability`` with bounds)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

from .design import Design
from .stability import ModeStabilityRow, contact_dofs, wheel_speed_rad_s

if TYPE_CHECKING:
    from fem.modes import Mode
    from reduced import ContactLaw, ModalDOF, ModeStability, OperatingPoint

__all__ = ["bounds_seconds", "margin_of", "remedy_of"]


def bounds_seconds(dofs: Sequence[ModalDOF], rotation: bool = False) -> float:
    """The estimated time of one mode's critical damping and friction slope among
    ``dofs`` [s] (the remedy of a squeal, the margin of a quiet point)."""
    from reduced.stability import bound_solves, eigen_solve_seconds

    return bound_solves(len(dofs)) * eigen_solve_seconds(dofs, rotation)


def _bounds(
    design: Design,
    rows: Sequence[ModeStabilityRow],
    contact: ContactLaw,
    op: OperatingPoint,
    rotation: bool,
    i: int,
) -> tuple[ModeStability, float, float]:
    """(its stability with bounds, damping ratio now, friction slope now) of row ``i``
    (the row's own bounds where the table has them)."""
    from reduced import friction_damping_ns_m, linear_stability

    slope_now = friction_damping_ns_m(contact, op) * op.rolling_speed_m_s / contact.normal_load_n
    known = rows[i].stability
    if not (math.isnan(known.critical_damping_ratio) or math.isnan(known.critical_friction_slope)):
        return known, design.damping_ratio_of(rows[i].mode), slope_now
    omega = wheel_speed_rad_s(design, op, rotation)
    dofs = contact_dofs([r.mode for r in rows], design)
    result = linear_stability(dofs, contact, op, omega, bounds=[i])
    return result.modes[i], design.damping_ratio_of(rows[i].mode), slope_now


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
    i = max(range(len(rows)), key=lambda k: rows[k].stability.growth_rate_1_s)
    m = rows[i].mode
    s, zeta_now, slope_now = _bounds(design, rows, contact, op, rotation, i)
    damping = (
        f"a damping ratio below {s.critical_damping_ratio:.3g} (it has {zeta_now:.3g})"
        if s.critical_damping_ratio > 0
        else "no damping at all"
    )
    rate = s.growth_rate_1_s
    how = (
        f"decays at {-rate:.3g} 1/s" if rate < 0 else f"grows at {rate:.3g} 1/s" if rate > 0 else "is neutral"
    )
    words = (
        f"the least stable, {m.label()} at {s.damped_frequency_hz:.1f} Hz, {how}; "
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


def remedy_of(
    design: Design,
    rows: Sequence[ModeStabilityRow],
    contact: ContactLaw,
    op: OperatingPoint,
    mode: Mode,
    rotation: bool = False,
) -> dict:
    """What would stop the squealing ``mode`` here: the damping ratio above which it
    stops growing (the other modes as they are) and the creep-curve slope dmu/dzeta
    above which it stops, with the values now; ``words`` says it. (The mitigation of
    ``stability --envelope`` makes every mode stable over a whole envelope.)"""
    i = next(k for k, r in enumerate(rows) if r.mode.index == mode.index)
    s, zeta_now, slope_now = _bounds(design, rows, contact, op, rotation, i)
    damping = (
        f"a damping ratio of {mode.label()} above {s.critical_damping_ratio:.3g} (now {zeta_now:.3g})"
        if math.isfinite(s.critical_damping_ratio) and s.critical_damping_ratio > zeta_now
        else f"no damping of {mode.label()} alone"
    )
    slope = (
        f"a creep curve falling less steeply than dmu/dzeta = {s.critical_friction_slope:.3g} at the "
        f"quasi-static creepage (now {slope_now:.3g})"
        if math.isfinite(s.critical_friction_slope)
        else "no friction slope alone"
    )
    return {
        "mode": mode.label(),
        "mode_index": mode.index,
        "damping_ratio": zeta_now,
        "stops_above_damping_ratio": s.critical_damping_ratio,
        "friction_slope": slope_now,
        "stops_above_friction_slope": s.critical_friction_slope,
        "words": f"it stops with {damping}, or with {slope}",
    }
